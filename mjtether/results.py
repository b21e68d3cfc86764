"""Writing a run's results: a folder that is either complete or absent.

Files (all SI units; ``docs/scenarios.md`` lists the CSV columns):

* ``timeseries.csv``: one row per output sample, columns ``runner.RECORD_FIELDS`` named
  ``<name>_<unit>``;
* ``tether.npz``: ``time`` (n,) s; ``nodes`` (n, e+1, 3), node positions in m; ``tension``
  (n, e), element tensions in N (never negative: elements carry tension only; 0 when slack);
  ``element_length`` (n, e), stretched element lengths in m. The e elements allocated are
  numbered from the drum's core to the robot end, so element j is the same piece of cable all
  run; those still on the drum have length and tension 0, their nodes sit at the fairlead;
* ``summary.json``: the scenario as read (defaults filled in), final and peak tensions, wall time,
  real-time factor, how the run was started;
* ``tension.png``, ``profile.png`` (side and top views of tether snapshots), ``track.png``;
* ``mjtether-manifest.json``: the files above with sizes and SHA-256, written last: it marks the
  folder as an mjtether result, the only kind ``overwrite`` replaces.

Everything is written to a temporary folder beside ``out`` and renamed into place at the end
(``outdir.Staging``), so a failed or interrupted run leaves nothing that looks like results, and
an existing folder is never replaced unless it is purely an earlier mjtether result
(``outdir.check_target``).
"""

from __future__ import annotations

import csv
import json
import math
import shutil
from pathlib import Path

import numpy as np

from .outdir import Staging, check_target
from .runner import RECORD_FIELDS


def column_names() -> list[str]:
    return [f"{name}_{unit.replace(' ', '').replace('/', 'per')}" if unit else name
            for name, unit, _ in RECORD_FIELDS]


def _jsonable(x):
    if isinstance(x, dict):
        return {k: _jsonable(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_jsonable(v) for v in x]
    if isinstance(x, float) and not math.isfinite(x):
        return str(x)
    if isinstance(x, (np.floating, np.integer)):
        return x.item()
    return x


def summary(sc, rows: np.ndarray, info: dict, scenario_path) -> dict:
    col = {name: i for i, (name, _, _) in enumerate(RECORD_FIELDS)}
    return {
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


def write(out, sc: dict, rows: np.ndarray, history: dict, info: dict, scenario_path=None,
          plots: bool = True, extra_files: dict | None = None, *, overwrite: bool = False) -> Path:
    """Write the results folder ``out`` atomically; returns its absolute path.
    ``history`` is ``runner.run``'s (nodes, tension, element_length per sample);
    ``extra_files`` {name: path} are moved into it (e.g. a video rendered during the run).
    ``out`` may be absent or an empty folder; with ``overwrite`` also an earlier mjtether result
    (nothing else: raises ``outdir.OutputError``, as for a full disk, and writes nothing). The cli
    checks ``out`` before simulating; it is checked again here for callers from Python."""
    target = check_target(out, overwrite=overwrite, protect=[scenario_path] if scenario_path else ())
    nodes = history["nodes"]
    with Staging(target, overwrite=overwrite) as stage:
        tmp = stage.path
        with open(tmp / "timeseries.csv", "w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(column_names())
            for r in rows:
                w.writerow([f"{v:.9g}" for v in r])
        np.savez_compressed(tmp / "tether.npz", time=rows[:, 0], nodes=nodes, tension=history["tension"],
                            element_length=history["element_length"])
        (tmp / "summary.json").write_text(json.dumps(summary(sc, rows, info, scenario_path), indent=2))
        if plots:
            _plots(tmp, rows, nodes, sc)
        for name, path in (extra_files or {}).items():
            shutil.move(str(path), tmp / name)
        return stage.commit()


def _plots(folder: Path, rows: np.ndarray, nodes: np.ndarray, sc) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    col = {name: i for i, (name, _, _) in enumerate(RECORD_FIELDS)}
    t = rows[:, col["time"]]
    fig, ax = plt.subplots(2, 1, figsize=(8, 6), sharex=True)
    ax[0].plot(t, rows[:, col["ship_tension"]], label="ship end")
    ax[0].plot(t, rows[:, col["tow_tension"]], label="tow point")
    ax[0].set_ylabel("tension (N)")
    ax[0].legend()
    ax[0].grid(alpha=0.3)
    ax[1].plot(t, rows[:, col["deployed_length"]], color="k")
    ax[1].set_ylabel("deployed length (m)")
    ax[1].set_xlabel("time (s)")
    ax[1].grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(folder / "tension.png", dpi=110)
    plt.close(fig)

    fig, ax = plt.subplots(1, 2, figsize=(11, 4.5))
    k = np.unique(np.linspace(0, len(nodes) - 1, 6).round().astype(int))
    depth = sc.water.depth
    for i in k:
        ax[0].plot(nodes[i, :, 0], nodes[i, :, 2], label=f"t = {t[i]:.0f} s")
        ax[1].plot(nodes[i, :, 0], nodes[i, :, 1])
    ax[0].axhline(-depth, color="saddlebrown", lw=2)
    ax[0].axhline(0.0, color="steelblue", lw=1)
    ax[0].set_xlabel("x (m)")
    ax[0].set_ylabel("z (m)")
    ax[0].set_title("side view")
    ax[0].legend(fontsize=8)
    ax[1].set_xlabel("x (m)")
    ax[1].set_ylabel("y (m)")
    ax[1].set_title("top view")
    ax[1].set_aspect("equal", adjustable="datalim")
    for a in ax:
        a.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(folder / "profile.png", dpi=110)
    plt.close(fig)

    fig, ax = plt.subplots(figsize=(6, 6))
    ax.plot(rows[:, col["robot_x"]], rows[:, col["robot_y"]], label="robot")
    ax.plot(rows[:, col["ship_x"]], rows[:, col["ship_y"]], "--", label="ship")
    ax.plot(rows[0, col["robot_x"]], rows[0, col["robot_y"]], "o", color="C0")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_aspect("equal", adjustable="datalim")
    ax.legend()
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(folder / "track.png", dpi=110)
    plt.close(fig)
