"""Writing a scenario's results: a folder that is either complete or absent, written by the
writer every system shares (``files.results_folder.write_folder``); what is the scenario's own
is here: its columns, its summary and its plots.

Files (all SI units; ``docs/scenarios.md`` lists the CSV columns):

* ``timeseries.csv``: one row per output sample, columns ``runner.RECORD_FIELDS`` named
  ``<name>_<unit>`` (without the tether's, ``readouts.TETHER_FIELDS``, for a vehicle run
  without one, ``tether.attached = false``: then ``lines.npz`` has no line, and there is no ``tension.png``,
  ``line_tension.png`` nor ``profile.png`` either; without the tangle monitor's about a vehicle,
  ``readouts.VEHICLE_FIELDS``, for a run without a vehicle);
* ``lines.npz`` (``io.lines_npz``, the layout every run writes, a network's too): the line
  ``tether`` from end A (the robot) to end B (the ship's drum): ``linetether_nodes`` (n, e+1, 3)
  m, ``linetether_tension`` (n, e) N (never negative: elements carry tension only; 0 when slack),
  ``linetether_element_length`` (n, e) m, ``linetether_compression`` (n, e) N (the largest push of
  each element's constraint since the previous sample, over every time step, >= 0: a cable cannot
  push, so any is the model's error, kept out of the tension and shown here and in
  ``max_compression``), ``linetether`` (its deployed nodes at the end); all e elements allocated,
  so element j is the same piece of cable all run, those still on the drum with length and
  tension 0 and their nodes at the fairlead; and the MuJoCo state that places every body (ship,
  robot, nodes) at each sample, ``qpos`` (n, nq), ``mocap_pos`` (n, nmocap, 3) m and
  ``mocap_quat`` (n, nmocap, 4), which ``mjtether render DIR`` sets again to replay the run
  (``mjtether.io.replay``; a run without a tether saves these only);
* ``summary.json``: the scenario as read (defaults filled in), final and peak tensions, wall time,
  real-time factor, how the run was started, the snap loads (``snap_loads``: every slack-to-taut
  event, the worst ten, and DNV-RP-H103's slack criterion; ``scenario.recording.snap_report``)
  and (where drawn) ``plots``, the plots' file names;
* ``tension.png`` (tensions at the ship end and the tow point, the snap loads, deployed length,
  and in a sea state the wave elevation, the fairlead's heave and the compensator's),
  ``line_tension.png`` (the tension along the tether: each element's least, mean and largest
  over the run against its arc length from end A, the robot, with ``tether.rated_load`` where it
  is finite), ``profile.png`` (side view x-z of six snapshots coloured by time, to scale: equal
  axes, or an inset to scale where the x extent is under 1 % of the z extent; the water surface,
  the seabed as defined, sloped or not, the ship and the robot; top view x-y with their tracks);
  a run without a tether ``track.png`` instead (plan view of the ship's and the robot's tracks:
  with a tether the profile's top view draws the same tracks); see ``tension_figure``,
  ``line_tension_figure``, ``profile_figure``, ``track_figure``;
* ``mjtether-manifest.json``: the files above with sizes and SHA-256, written last: it marks the
  folder as an mjtether result, the only kind ``overwrite`` replaces.

Everything is written to a temporary folder beside ``out`` and renamed into place at the end
(``outdir.Staging``), so a failed or interrupted run leaves nothing that looks like results, and
an existing folder is never replaced unless it is purely an earlier mjtether result
(``outdir.check_target``).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from mjtether.cable.builder import seabed_height
from mjtether.network.plots import draw_tension_along, tension_along
from mjtether.files.outdir import Staging, check_target
from mjtether.files.results_folder import jsonable as _jsonable
from mjtether.files.results_folder import write_folder
from mjtether.physics.water import WaterColumn
from mjtether.scenario.readouts import TETHER_FIELDS, VEHICLE_FIELDS
from mjtether.scenario.runner import RECORD_FIELDS

from . import lines_npz


def written(tethered: bool = True, vehicle: bool = True) -> list[int]:
    """Indices of the ``RECORD_FIELDS`` a run writes: all but the tether's
    (``readouts.TETHER_FIELDS``) for a run without one, and but the tangle monitor's about a
    vehicle (``readouts.VEHICLE_FIELDS``) for a run without a vehicle."""
    return [i for i, (name, _, _) in enumerate(RECORD_FIELDS)
            if (tethered or name not in TETHER_FIELDS) and (vehicle or name not in VEHICLE_FIELDS)]


def column_names(tethered: bool = True, vehicle: bool = True) -> list[str]:
    """The CSV's column names (``name_unit``) of the fields ``written`` writes."""
    names = [f"{name}_{unit.replace(' ', '').replace('/', 'per')}" if unit else name
             for name, unit, _ in RECORD_FIELDS]
    return [names[i] for i in written(tethered, vehicle)]


def summary(sc, rows: np.ndarray, info: dict, scenario_path) -> dict:
    col = {name: i for i, (name, _, _) in enumerate(RECORD_FIELDS)}
    out = {
        "scenario_file": None if scenario_path is None else str(scenario_path),
        "scenario": _jsonable(sc.to_dict()),
        "samples": int(len(rows)),
        "final": {"time_s": float(rows[-1, col["time"]]),
                  "ship_tension_N": float(rows[-1, col["ship_tension"]]),
                  "tow_tension_N": float(rows[-1, col["tow_tension"]]),
                  "deployed_length_m": float(rows[-1, col["deployed_length"]])},
        "peak": {"ship_tension_N": float(rows[:, col["ship_tension"]].max()),
                 "tow_tension_N": float(rows[:, col["tow_tension"]].max())},
        "run": _jsonable(info),
    }
    out = {"kind": "scenario", **out}
    if not info.get("tethered", True):  # no tether: no tensions to report
        out["final"] = {"time_s": out["final"]["time_s"]}
        del out["peak"]
        out["lines"] = {}
    else:  # (the single tether as a network's line: end A at the robot, B at the ship)
        out["lines"] = {lines_npz.TETHER: {
            "A": "robot", "B": "ship", "length_m": float(sc.tether.length), "segments": int(sc.tether.segments),
            "final_A_tension_N": out["final"]["tow_tension_N"], "final_B_tension_N": out["final"]["ship_tension_N"],
            "peak_tension_N": max(out["peak"]["tow_tension_N"], out["peak"]["ship_tension_N"]),
            "effective_EA": _jsonable(info.get("effective_EA"))}}
        # the tangle monitor's worst moments, and its events
        t = rows[:, col["time"]]
        tg = {}
        keys = [("cable_self_clearance", "min_cable_self_clearance", "_m", np.argmin),
                ("cable_plan_crossings", "max_cable_plan_crossings", "", np.argmax)]
        if info.get("vehicle", True):
            keys = [("cable_clearance", "min_cable_clearance", "_m", np.argmin), *keys,
                    ("cable_wrap", "max_cable_wrap", "_deg", np.argmax)]
        for name, label, unit, pick in keys:
            k = int(pick(rows[:, col[name]]))
            tg[label + unit] = float(rows[k, col[name]])
            tg[label + "_time_s"] = float(t[k])
        tg["events"] = info.get("tangle_events", [])
        out["tangle"] = tg
        if "snap_loads" in info:  # (from the run's info to the top: the sea state's first question)
            out["snap_loads"] = out["run"].pop("snap_loads")
            out["lines"][lines_npz.TETHER]["snap_count"] = out["snap_loads"]["count"]
            out["peak"]["element_tension_N"] = float(rows[:, col["peak_tension"]].max())
    return out


def write(out, sc: dict, rows: np.ndarray, history: dict, info: dict, scenario_path=None,
          plots: bool = True, extra_files: dict | None = None, *, overwrite: bool = False) -> Path:
    """Write the results folder ``out`` atomically; returns its absolute path.
    ``history`` is ``runner.run``'s (nodes, tension, element_length per sample);
    ``extra_files`` {name: path} are moved into it (e.g. a video rendered during the run).
    ``out`` may be absent or an empty folder; with ``overwrite`` also an earlier mjtether result
    (nothing else: raises ``outdir.OutputError``, as for a full disk, and writes nothing). The cli
    checks ``out`` before simulating; it is checked again here for callers from Python."""
    target = check_target(out, overwrite=overwrite, protect=[scenario_path] if scenario_path else ())
    tethered, vehicle = info.get("tethered", True), info.get("vehicle", True)
    arrays = lines_npz.tether_arrays(rows[:, 0], history, tethered)
    with Staging(target, overwrite=overwrite) as stage:
        return write_folder(stage, column_names(tethered, vehicle), rows[:, written(tethered, vehicle)], arrays,
                            summary(sc, rows, info, scenario_path),
                            plots=(lambda folder: _plots(folder, rows, history["nodes"], sc, tethered,
                                                         info.get("snap_loads", {}).get("worst"), arrays)) if plots
                            else None, extra_files=extra_files)


# ------------------------------------------------------------------------------ plots
# World frame throughout: x, y horizontal (m), z up (m), water surface at z = 0; headings from +x
# towards +y, in degrees on every label. Each ``*_figure`` returns its matplotlib Figure (Agg
# backend, nothing shown) so that it can be inspected; ``_plots`` saves and closes them. Artists a
# test may look for carry a gid: "seabed", "surface", "ship", "robot", "ship_track",
# "robot_track", "ship_start", "robot_start", "upslope", "snapshot" (each snapshot, side and top
# view), "to_scale" (the side view's inset), "tension_min", "tension_mean", "tension_max",
# "tension_peak", "rated_load" (``network.plots.draw_tension_along``).

SNAPSHOT_COLOURS = "viridis"
"""The colour map of the profile's snapshots over time (its first 90 %: its top is a pale yellow)."""
INSET_BELOW = 0.01
"""The side view is drawn to scale (equal axes) unless its x extent is below this fraction of its
z extent; then it is stretched to fill its panel and an inset beside it draws it to scale."""

_SHIP_MARKER = [(-1.0, 0.35), (1.0, 0.35), (0.65, -0.35), (-0.65, -0.35), (-1.0, 0.35)]
"""A hull in side view (deck wider than keel), centred on the fairlead; marker units."""


def _pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _columns(rows: np.ndarray) -> dict:
    """{field name: column of ``rows``} (``runner.RECORD_FIELDS``)."""
    return {name: rows[:, i] for i, (name, _, _) in enumerate(RECORD_FIELDS)}


def _snapshot_indices(nodes: np.ndarray, count: int = 6) -> np.ndarray:
    """Up to ``count`` samples of ``nodes`` spread evenly over the run, first and last included."""
    return np.unique(np.linspace(0, len(nodes) - 1, count).round().astype(int))


def _snapshot_times(rows: np.ndarray, nodes: np.ndarray) -> np.ndarray:
    """Time (s) of each sample of ``nodes``: the rows' times when every sample was kept,
    otherwise (``runner.run(keep_nodes=False)``) those of the first samples only."""
    t = rows[:, 0]
    return t if len(nodes) == len(t) else t[:len(nodes)]


def _time(t: float) -> str:
    """A time (s) for a label: to 0.01 s, no trailing zeros."""
    return f"{round(float(t), 2):g}"


def _frame(ax, x0: float, x1: float, z0: float, z1: float) -> None:
    """Autoscale ``ax`` to the box [x0, x1] x [z0, z1] (m, with matplotlib's margins) and not to
    every artist on it (a seabed far below the cable stays out of view); an equal aspect
    (``adjustable="datalim"``) may then widen either range to fill the panel."""
    ax.dataLim.set_points(np.array([[x0, z0], [x1, z1]], dtype=float))
    ax.autoscale_view()


def _upslope(ax, sc) -> None:
    """An arrow in the top-right corner of the top-view ``ax`` pointing up the seabed slope
    (heading ``sc.water.seabed_slope_heading_deg`` from +x towards +y); nothing on a level seabed.
    Drawn in points from its tip, so its direction is true on an equal-aspect x-y plot."""
    w = sc.water
    if w.seabed_slope_deg == 0.0:
        return
    h = math.radians(w.seabed_slope_heading_deg)
    length = 40.0  # points
    ax.annotate(f"upslope ({w.seabed_slope_deg:g}\N{DEGREE SIGN})", xy=(0.88, 0.88), xycoords="axes fraction",
                xytext=(-length * math.cos(h), -length * math.sin(h)), textcoords="offset points",
                ha="center", va="center", fontsize=8, color="saddlebrown", gid="upslope",
                arrowprops=dict(arrowstyle="-|>", color="saddlebrown", lw=1.5))


def _tracks(ax, cols: dict) -> None:
    """Ship (fairlead) and robot (tow point) tracks in plan, x-y (m), with start markers."""
    ax.plot(cols["ship_x"], cols["ship_y"], "--", color="0.35", label="ship track", gid="ship_track")
    ax.plot(cols["ship_x"][0], cols["ship_y"][0], "s", color="0.35", mfc="none", label="ship start",
            gid="ship_start")
    ax.plot(cols["robot_x"], cols["robot_y"], "-", color="darkorange", label="robot track", gid="robot_track")
    ax.plot(cols["robot_x"][0], cols["robot_y"][0], "o", color="darkorange", mfc="none", label="robot start",
            gid="robot_start")


def tension_figure(rows: np.ndarray, snaps: list | None = None):
    """Tension (N) at the ship end (fairlead) and at the robot's tow point, the largest of any
    element between samples and the snap loads (``snaps``: ``summary.json``'s
    ``snap_loads["worst"]`` events, their peaks marked), and the unstretched deployed length
    (m), against simulated time (s); in a sea state (the fairlead moving, or waves) a third
    panel: the wave elevation at the ship, the fairlead's heave, the heave compensator's payout
    and the residual heave the line sees (m). ``rows``: ``runner.run``'s records."""
    plt = _pyplot()
    c = _columns(rows)
    heave = c["fairlead_z"] - c["fairlead_z"][0]
    sea = bool(np.any(c["wave_elevation"] != 0.0) or np.ptp(heave) > 1e-9 or np.any(c["heave_compensation"] != 0))
    fig, ax = plt.subplots(3 if sea else 2, 1, figsize=(8, 9 if sea else 6.5), sharex=True)
    fig.suptitle("Tether tension and deployed length")
    ax[0].plot(c["time"], c["ship_tension"], label="ship end")
    ax[0].plot(c["time"], c["tow_tension"], label="tow point")
    if np.any(c["peak_tension"] > np.maximum(c["ship_tension"], c["tow_tension"]) * (1 + 1e-9)):
        ax[0].plot(c["time"], c["peak_tension"], lw=0.8, color="0.5", label="largest of any element since the last "
                   "sample")
    if snaps:
        ax[0].plot([e["time_s"] for e in snaps], [e["peak_tension_N"] for e in snaps], "v", color="crimson",
                   ms=6, ls="none", gid="snaps", label=f"snap loads (peaks; {len(snaps)} worst)")
    ax[0].set_title("Tension at the ship end and at the robot's tow point")
    ax[0].set_ylabel("tension (N)")
    ax[0].legend(fontsize=8)
    ax[1].plot(c["time"], c["deployed_length"], color="k")
    ax[1].set_title("Deployed (unstretched) cable length")
    ax[1].set_ylabel("deployed length (m)")
    if sea:
        ax[2].plot(c["time"], c["wave_elevation"], color="steelblue", label="wave elevation at the ship")
        ax[2].plot(c["time"], heave, color="0.3", label="fairlead heave")
        if np.any(c["heave_compensation"] != 0):
            ax[2].plot(c["time"], c["heave_compensation"], "--", color="seagreen", label="heave compensator's payout")
            ax[2].plot(c["time"], heave - c["heave_compensation"], color="darkorange", label="residual heave")
        ax[2].set_title("The sea and the fairlead")
        ax[2].set_ylabel("height (m)")
        ax[2].legend(fontsize=8)
    for a in ax:
        a.set_xlabel("time (s)")
        a.grid(alpha=0.3)
    fig.tight_layout()
    return fig


def profile_figure(rows: np.ndarray, nodes: np.ndarray, sc):
    """Snapshots of the tether: side view (x-z, m) and top view (x-y, m), world frame, z up,
    water surface at z = 0. ``nodes`` (samples, nodes, 3) m, from the ship end (first node: the
    fairlead) to the robot end. Up to six snapshots, coloured by their time (``SNAPSHOT_COLOURS``,
    the times in s in the legend). The side view shows the water surface, the seabed as the
    scenario defines it (sloped or not), and the ship and the robot at the last snapshot; it is
    to scale (equal axes), or, where its x extent is under ``INSET_BELOW`` of its z extent (a
    cable hanging nearly straight down), stretched along x with an inset to scale. The top view
    (equal axes) shows the ship's and the robot's tracks and, on a sloped seabed, which way is
    upslope."""
    plt = _pyplot()
    from matplotlib import colormaps

    c = _columns(rows)
    nodes = np.asarray(nodes, dtype=float)
    times = _snapshot_times(rows, nodes)
    fig, (side, top) = plt.subplots(1, 2, figsize=(12, 5))
    fig.suptitle("Tether profile")
    shots = _snapshot_indices(nodes)
    colours = colormaps[SNAPSHOT_COLOURS](np.linspace(0.0, 0.9, len(shots)))
    for i, colour in zip(shots, colours):
        side.plot(nodes[i, :, 0], nodes[i, :, 2], color=colour, gid="snapshot", label=f"t = {_time(times[i])} s")
        top.plot(nodes[i, :, 0], nodes[i, :, 1], color=colour, gid="snapshot")
    last = nodes[-1]
    ship, robot = last[0], last[-1]

    # The seabed in the x-z view. The seabed plane's height depends on y as well as x when the
    # slope heading is not along x; the line drawn is its section at the y of the cable's robot
    # end in the last snapshot (where the cable meets the seabed), over the plotted x range. When
    # the plotted cables span a range of y over which the seabed height differs, the band of
    # seabed heights over that range is shaded as well.
    w = sc.water
    slope, heading = math.radians(w.seabed_slope_deg), math.radians(w.seabed_slope_heading_deg)
    water = WaterColumn(depth=w.depth)  # only its seabed height is used: z = -depth at x = y = 0
    grid = w.grid

    def height(x, y):  # (the bathymetry grid's, or the plane's)
        return grid.height(x, y) if grid is not None else seabed_height(water, x, y, slope, heading)
    x_all = np.concatenate([nodes[..., 0].ravel(), [ship[0], robot[0]]])
    x0, x1 = float(x_all.min()), float(x_all.max())
    pad = 0.05 * max(x1 - x0, 1.0)
    xs = np.linspace(x0 - pad, x1 + pad, 101)
    y_ref = float(robot[1])
    seabed = height(xs, np.full_like(xs, y_ref))
    y_lo, y_hi = float(nodes[..., 1].min()), float(nodes[..., 1].max())
    lo = height(xs, np.full_like(xs, y_lo))
    hi = height(xs, np.full_like(xs, y_hi))
    if np.max(np.abs(hi - lo)) > 1e-3:
        side.fill_between(xs, np.minimum(lo, hi), np.maximum(lo, hi), color="saddlebrown", alpha=0.2, lw=0,
                          label=f"seabed for y in [{y_lo:.0f}, {y_hi:.0f}] m")
    # The frame: the cable (every snapshot, the ship and the robot), and the water surface and the
    # seabed where they are within the cable's own size of it (a vehicle at 50 m in 1000 m of
    # water is drawn, to scale, without the 950 m of water below it; the legend says so).
    xz = np.vstack([nodes[..., [0, 2]].reshape(-1, 2), ship[[0, 2]], robot[[0, 2]]])
    z_lo, z_hi = float(xz[:, 1].min()), float(xz[:, 1].max())
    reach = max(x1 - x0, z_hi - z_lo, 1.0)
    bed_lo = float(min(np.min(seabed), np.min(lo), np.min(hi)))
    bed_hi = float(max(np.max(seabed), np.max(lo), np.max(hi)))
    bed_shown = bed_hi >= z_lo - reach
    if bed_shown:
        z_lo = min(z_lo, bed_lo)
    if z_hi >= -reach:
        z_hi = max(z_hi, 0.0)
    seabed_label = f"seabed at y = {y_ref:.1f} m" + (f" (slope {w.seabed_slope_deg:g}\N{DEGREE SIGN})"
                                                      if w.seabed_slope_deg else " (bathymetry grid)" if grid
                                                      else "")
    if not bed_shown:
        seabed_label += f", z = {bed_hi:.4g} m and below: out of view"
    side.plot(xs, seabed, color="saddlebrown", lw=2, gid="seabed", label=seabed_label)
    side.axhline(0.0, color="steelblue", lw=1, gid="surface", label="water surface" +
                 ("" if z_hi >= 0.0 else ", z = 0: out of view"))
    side.plot([ship[0]], [ship[2]], marker=_SHIP_MARKER, ms=16, ls="none", color="0.3", gid="ship",
              label=f"ship (fairlead, t = {_time(times[-1])} s)")
    side.plot([robot[0]], [robot[2]], marker="D", ms=8, ls="none", color="darkorange", gid="robot",
              label=f"robot (tow point, t = {_time(times[-1])} s)")
    side.set_xlabel("x (m)")
    side.set_ylabel("z, height above the water surface (m)")
    if x1 - x0 < INSET_BELOW * (z_hi - z_lo):
        # stretched along x (room kept on the right for the inset), and an inset to scale
        side.set_title(f"Side view (x-z): x stretched (x extent {x1 - x0:.3g} m, z {z_hi - z_lo:.3g} m); "
                       "inset to scale", fontsize=9)
        _frame(side, x0, x1 + 0.45 * (x1 - x0 + 2 * pad), z_lo, z_hi)
        inset = side.inset_axes([0.74, 0.06, 0.24, 0.86])
        inset.set_gid("to_scale")
        for i, colour in zip(shots, colours):
            inset.plot(nodes[i, :, 0], nodes[i, :, 2], color=colour, lw=1)
        inset.plot(xs, seabed, color="saddlebrown", lw=1.5)
        inset.axhline(0.0, color="steelblue", lw=1)
        _frame(inset, x0, x1, z_lo, z_hi)
        inset.set_aspect("equal", adjustable="datalim")
        inset.set_title("to scale", fontsize=7)
        inset.tick_params(labelsize=6)
        side.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.12), ncol=3)  # (clear of the inset)
    else:
        side.set_title("Side view (x-z), to scale")
        _frame(side, x0, x1, z_lo, z_hi)
        side.set_aspect("equal", adjustable="datalim")
        side.legend(fontsize=7, loc="best")

    _tracks(top, c)
    _upslope(top, sc)
    top.set_title("Top view (x-y) with ship and robot tracks")
    top.set_xlabel("x (m)")
    top.set_ylabel("y (m)")
    top.set_aspect("equal", adjustable="datalim")
    top.legend(fontsize=7, loc="best")
    for a in (side, top):
        a.grid(alpha=0.3)
    fig.tight_layout()
    return fig


def line_tension_figure(arrays: dict, sc):
    """The tension along the tether (``network.plots.draw_tension_along``): each element's least,
    mean and largest tension over the run (N) against the arc length of its centre from end A,
    the robot (m), from the writer's ``lines.npz`` arrays (``arrays``: ``linetether_tension``
    and ``linetether_element_length`` (samples, e), from end A; cable still on the drum, length 0,
    is left out), with ``tether.rated_load`` where it is finite and, dotted, each element's
    largest tension at any time step where that passes the samples' largest
    (``linetether_peak_tension``)."""
    plt = _pyplot()
    key = f"line{lines_npz.TETHER}_"
    along = tension_along(arrays[key + "tension"], arrays[key + "element_length"])
    peak = arrays.get(key + "peak_tension")
    fig, ax = plt.subplots(figsize=(8, 4.5))
    fig.suptitle("Tension along the tether over the run")
    draw_tension_along(ax, along, sc.tether.rated_load,
                       None if peak is None else np.asarray(peak, float)[:, along["element"]].max(axis=0))
    ax.set_title("Each element's least, mean and largest tension (end A: the robot; end B: the ship)", fontsize=9)
    ax.set_xlabel("arc length from end A, the robot (m)")
    fig.tight_layout()
    return fig


def track_figure(rows: np.ndarray, sc):
    """Plan view (x-y, m, world frame) of the ship's (fairlead's) and the robot's (tow point's)
    tracks with their start markers and, on a sloped seabed, an arrow pointing upslope."""
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(6.5, 6.5))
    fig.suptitle("Ship and robot tracks")
    _tracks(ax, _columns(rows))
    _upslope(ax, sc)
    ax.set_title("Plan view (x-y)")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_aspect("equal", adjustable="datalim")
    ax.legend(fontsize=8, loc="best")
    ax.grid(alpha=0.3)
    fig.tight_layout()
    return fig


def _plots(folder: Path, rows: np.ndarray, nodes: np.ndarray, sc, tethered: bool = True,
           snaps: list | None = None, arrays: dict | None = None) -> list[str]:
    """Write the plots into ``folder``: with a tether tension.png (``snaps``: the snap loads it
    marks), line_tension.png (from ``arrays``, the writer's ``lines.npz`` arrays) and profile.png;
    without one track.png only (with one, profile.png's top view draws the same tracks). Returns
    the names of the files written."""
    plt = _pyplot()
    figures = (("tension.png", lambda: tension_figure(rows, snaps)),
               ("line_tension.png", lambda: line_tension_figure(arrays, sc)),
               ("profile.png", lambda: profile_figure(rows, nodes, sc))) if tethered else \
        (("track.png", lambda: track_figure(rows, sc)),)
    names = []
    for name, make in figures:
        fig = make()
        try:
            fig.savefig(folder / name, dpi=110)
        finally:
            plt.close(fig)
        names.append(name)
    return names
