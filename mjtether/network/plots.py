"""Plots of a network run, written beside its time series: ``tension.png`` (every line's end
tensions against time) and ``profile.png`` (every line at the start and the end of the run, side
view x-z and top view x-y, each to scale, with the water surface and the seabed). Units SI, world
frame, z up; tensions in kN where they pass 10 kN."""

from __future__ import annotations

from pathlib import Path

import numpy as np



def _pyplot():
    import matplotlib

    matplotlib.use("Agg")  # (headless: files only)
    import matplotlib.pyplot as plt

    return plt


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


def write(folder: Path, r, rows: np.ndarray, cols: list[str]) -> list[str]:
    """Write the two plots of run ``r`` into ``folder``; returns their file names."""
    plt = _pyplot()
    made = []
    for name, make in (("tension.png", lambda: tension_figure(r.net, cols, rows)),
                       ("profile.png", lambda: profile_figure(r.net, r.history))):
        if name == "profile.png" and not r.net.lines:
            continue
        fig = make()
        try:
            fig.savefig(Path(folder) / name, dpi=110)
        finally:
            plt.close(fig)
        made.append(name)
    return made
