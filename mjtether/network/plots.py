"""Plots of a network run, written beside its time series: ``tension.png`` (every line's end
tensions against time), ``profile.png`` (every line at the start and the end of the run, side
view x-z and top view x-y, each to scale, with the water surface and the seabed) and
``line_tension.png`` (the tension along every line: each element's least, mean and largest over
the run against its arc length from end A; a network's line types carry no rating, so no rated
load is drawn). Units SI, world frame, z up; tensions in kN where they pass 10 kN.

``tension_along`` and ``draw_tension_along`` are shared with a scenario's ``line_tension.png``
(``mjtether.io.results``): a single tether is the line ``tether`` of the same layout."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

RATED_SHOWN = 2.0
"""The rated load is drawn as a line where it is at most this many times the largest tension
plotted (above, the curves would be squashed flat at the bottom: a note gives it instead)."""
PEAK_SHOWN = 0.01
"""Each element's largest tension at any time step is drawn where it passes the samples' largest
by more than this fraction of the largest tension plotted (a snap load between samples)."""


def _pyplot():
    import matplotlib

    matplotlib.use("Agg")  # (headless: files only)
    import matplotlib.pyplot as plt

    return plt


def tension_along(tension: np.ndarray, element_length: np.ndarray) -> dict:
    """Each element's tension over the run, from ``lines.npz``'s arrays of one line (from end A
    to end B): ``tension`` (samples, e) N and ``element_length`` (samples, e) m. An element counts
    at the samples it is deployed (length > 0: cable on a drum has length 0) and elements never
    deployed are left out. Returns {"arc_length" (k,) m: the element's centre from end A, each
    element taken at its median length over the samples it is deployed (the element at a
    paying-out drum grows past its share before the next is let go: the median is nearer it); "min", "mean", "max" (k,) N: its least,
    mean and largest tension over the samples it is deployed; "element" (k,): the elements'
    indices from end A}."""
    t, length = np.asarray(tension, float), np.asarray(element_length, float)
    on = length > 0.0
    used = np.flatnonzero(on.any(axis=0))
    typical = np.nan_to_num(np.nanmedian(np.where(on, length, np.nan)[:, used], axis=0))
    each = np.zeros(length.shape[1])
    each[used] = typical
    arc = np.cumsum(each) - 0.5 * each
    t, on = t[:, used], on[:, used]
    mean = np.where(on, t, 0.0).sum(axis=0) / on.sum(axis=0)
    return {"arc_length": arc[used], "min": np.where(on, t, np.inf).min(axis=0, initial=np.inf),
            "mean": mean, "max": np.where(on, t, -np.inf).max(axis=0, initial=-np.inf), "element": used}


def draw_tension_along(ax, along: dict, rated: float = math.inf, peak: np.ndarray | None = None,
                       kilo: bool | None = None) -> None:
    """Draw ``tension_along``'s least, mean and largest tension (gids "tension_min",
    "tension_mean", "tension_max"; the band between shaded) against arc length on ``ax``, and the
    rated load ``rated`` (N; gid "rated_load": a line where it is at most ``RATED_SHOWN`` times the
    largest tension plotted, else a note saying how far above it is; nothing where it is
    infinite). ``peak`` (k,) N: each element's largest tension at any time step, drawn (gid
    "tension_peak") where it passes the samples' largest by ``PEAK_SHOWN`` of the largest. ``kilo``: tensions in kN (default: where they pass 10 kN)."""
    s, top = along["arc_length"], float(np.max(along["max"], initial=0.0))
    if kilo is None:
        kilo = max(top, 0.0 if math.isinf(rated) else min(rated, RATED_SHOWN * top)) > 1e4
    k, unit = (1e-3, "kN") if kilo else (1.0, "N")
    ax.fill_between(s, k * along["min"], k * along["max"], color="tab:blue", alpha=0.15, lw=0)
    ax.plot(s, k * along["max"], color="tab:red", lw=1.2, gid="tension_max", label="largest over the run")
    ax.plot(s, k * along["mean"], color="k", lw=1.2, gid="tension_mean", label="mean over the run")
    ax.plot(s, k * along["min"], color="tab:blue", lw=1.2, gid="tension_min", label="least over the run")
    if peak is not None and np.max(peak - along["max"], initial=0.0) > PEAK_SHOWN * top:
        ax.plot(s, k * peak, ":", color="0.4", lw=1.0, gid="tension_peak", label="largest at any time step")
        top = max(top, float(np.max(peak)))
    if math.isfinite(rated):
        text = f"rated load {rated / 1e3:.4g} kN" if rated > 1e4 else f"rated load {rated:.4g} N"
        if rated <= RATED_SHOWN * top:
            ax.axhline(k * rated, color="crimson", ls="--", lw=1.2, gid="rated_load", label=text)
        else:
            ax.text(0.02, 0.96, f"{text}: {rated / top:.3g}x the largest tension here, off the scale"
                    if top > 0 else f"{text}: off the scale", transform=ax.transAxes, va="top", fontsize=7,
                    color="crimson", gid="rated_load")
    ax.set_xlabel("arc length from end A (m)")
    ax.set_ylabel(f"tension ({unit})")
    ax.set_ylim(bottom=0.0)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, loc="best")


def tension_figure(net, cols: list[str], rows: np.ndarray):
    """End A (solid) and end B (dashed) tension of every line against time."""
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(8, 4.5))
    ends = [[cols.index(f"line{ln.name}_{e}_tension_N") for e in "AB"] for ln in net.lines]
    kilo = bool(ends) and float(np.max(rows[:, np.ravel(ends)])) > 1e4
    scale, unit = (1e-3, "kN") if kilo else (1.0, "N")
    for ln, (a, b) in zip(net.lines, ends):
        line, = ax.plot(rows[:, 0], scale * rows[:, a], label=f"line {ln.name}, end A ({ln.a})")
        ax.plot(rows[:, 0], scale * rows[:, b], "--", color=line.get_color(), label=f"line {ln.name}, end B ({ln.b})")
    ax.set_title("End tensions of every line")
    ax.set_xlabel("time (s)")
    ax.set_ylabel(f"tension ({unit})")
    ax.grid(alpha=0.3)
    if net.lines:
        ax.legend(fontsize=7, ncol=2 if len(net.lines) > 3 else 1)
    fig.tight_layout()
    return fig


def profile_figure(net, history: dict):
    """Every line at the first and last sample (``history``: ``NetworkRun.history``), side view
    x-z and top view x-y, equal axes (a short line beside a deep column is drawn to scale)."""
    plt = _pyplot()
    fig, (side, top) = plt.subplots(1, 2, figsize=(11, 4.8))
    for ln in net.lines:
        nodes = np.asarray(history[ln.name]["nodes"])
        first, = side.plot(nodes[0, :, 0], nodes[0, :, 2], ":", alpha=0.6)
        colour = first.get_color()
        side.plot(nodes[-1, :, 0], nodes[-1, :, 2], "-", color=colour, label=f"line {ln.name}")
        top.plot(nodes[0, :, 0], nodes[0, :, 1], ":", color=colour, alpha=0.6)
        top.plot(nodes[-1, :, 0], nodes[-1, :, 1], "-", color=colour)
    side.axhline(0.0, color="tab:blue", lw=0.8, label="water surface")
    if net.grid is None:
        side.axhline(-net.depth, color="saddlebrown", lw=1.0, label="seabed")
    side.set_title("Side view (dotted: start, solid: end)")
    side.set_xlabel("x (m)")
    side.set_ylabel("z (m)")
    top.set_title("Top view")
    top.set_xlabel("x (m)")
    top.set_ylabel("y (m)")
    for a in (side, top):
        a.set_aspect("equal", adjustable="datalim")
        a.grid(alpha=0.3)
    if net.lines:
        side.legend(fontsize=7)
    fig.tight_layout()
    return fig


def line_tension_figure(net, history: dict):
    """The tension along every line (one panel each, ``draw_tension_along``): each element's
    least, mean and largest tension over the run against its arc length from end A (m), from
    ``history`` (``NetworkRun.history``: per line ``nodes`` (samples, n+1, 3) m and ``tension``
    (samples, n) N, from end A; an element's length is the distance between its nodes, 0 for
    cable still on a drum, which is left out). No rated load: a network's line types have none."""
    plt = _pyplot()
    n = len(net.lines)
    cols = 1 if n == 1 else 2
    rows = math.ceil(n / cols)
    fig, axes = plt.subplots(rows, cols, figsize=(8 if cols == 1 else 11, 1.0 + 2.8 * rows), squeeze=False)
    fig.suptitle("Tension along each line over the run")
    for ln, ax in zip(net.lines, axes.ravel()):
        h = history[ln.name]
        nodes = np.asarray(h["nodes"], float)
        length = np.linalg.norm(np.diff(nodes, axis=1), axis=2)
        along = tension_along(h["tension"], length)
        peak = h.get("peak_tension")
        draw_tension_along(ax, along, peak=None if peak is None or not len(peak) else
                           np.asarray(peak, float)[:, along["element"]].max(axis=0))
        ax.set_title(f"line {ln.name}: end A ({ln.a}) to end B ({ln.b})", fontsize=9)
    for ax in axes.ravel()[n:]:
        ax.set_visible(False)
    fig.tight_layout()
    return fig


def write(folder: Path, r, rows: np.ndarray, cols: list[str]) -> list[str]:
    """Write the plots of run ``r`` into ``folder`` (``tension.png``; where it has lines
    ``profile.png`` and ``line_tension.png``); returns their file names."""
    plt = _pyplot()
    made = []
    for name, make in (("tension.png", lambda: tension_figure(r.net, cols, rows)),
                       ("profile.png", lambda: profile_figure(r.net, r.history)),
                       ("line_tension.png", lambda: line_tension_figure(r.net, r.history))):
        if name != "tension.png" and not r.net.lines:
            continue
        fig = make()
        try:
            fig.savefig(Path(folder) / name, dpi=110)
        finally:
            plt.close(fig)
        made.append(name)
    return made
