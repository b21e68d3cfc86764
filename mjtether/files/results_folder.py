"""The one writer of a run's results folder, for every system (a scenario's single tether, a
network of lines): the same files in the same layout, each system giving only what is its own
(its columns, rows, arrays, summary and plots).

Files (SI units):

* ``timeseries.csv``: a header of column names (``name_unit``), then one row per output sample,
  every value with 9 significant figures (``.9g``: a float64 read back to 1e-9);
* ``lines.npz`` (``np.savez_compressed``): ``time_s`` and, per line NAME, the arrays named by
  ``line_arrays`` (``lineNAME``, ``lineNAME_nodes``, ...), and the MuJoCo state a replay sets
  again (``qpos``, ...); ``mjtether.io.lines_npz`` says what each array holds;
* ``summary.json``: the system's summary, with ``"kind"`` (``"scenario"`` or ``"network"``) and,
  where plots were drawn, ``"plots"`` (their file names); a non-finite float as its text
  (``"inf"``), NumPy scalars as numbers (``jsonable``);
* the plots the system draws and any extra files (e.g. a video rendered during the run).

It writes into a folder that is staged (``outdir.Staging``: renamed into place only when
complete, removed on any failure), so nothing that looks like results is left by a failure. This
module imports nothing of the package (the target check and the staging are the callers', from
``mjtether.files.outdir``), so that any part may use it.
"""

from __future__ import annotations

import csv
import json
import math
import shutil
from pathlib import Path

import numpy as np

TIMESERIES = "timeseries.csv"
LINES = "lines.npz"
SUMMARY = "summary.json"


def line_arrays(name: str, final_nodes, per_sample: dict) -> dict:
    """``lines.npz``'s arrays of the line ``name``: ``line<name>`` (its deployed nodes at the end
    of the run, m) and ``line<name>_<key>`` for each array of ``per_sample`` (one entry per
    sample: ``nodes``, ``tension``, ``compression``, ...), every one from end A to end B."""
    out = {f"line{name}": np.asarray(final_nodes, dtype=float)}
    for key, values in per_sample.items():
        out[f"line{name}_{key}"] = np.asarray(values)
    return out


def jsonable(x):
    """``x`` with every non-finite float as its text (JSON has no inf nor NaN) and NumPy scalars as
    Python numbers, through dicts, lists and tuples."""
    if isinstance(x, dict):
        return {k: jsonable(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [jsonable(v) for v in x]
    if isinstance(x, (np.floating, np.integer)):
        x = x.item()
    if isinstance(x, float) and not math.isfinite(x):
        return str(x)
    return x


def write_folder(stage, columns, rows, arrays: dict, summary: dict, *, plots=None, extra_files=None) -> Path:
    """Write the results into ``stage`` and commit it; returns the folder's path. ``stage``: an
    ``outdir.Staging`` (anything with ``path`` and ``commit()``), or a folder (written into as it
    is, nothing committed). ``columns``: the CSV's header, one name per column of ``rows``
    (samples, columns). ``arrays``: ``lines.npz``'s. ``summary``: ``summary.json``'s (the
    ``"plots"`` key added where ``plots`` is given). ``plots(folder)`` draws the system's plots
    into ``folder`` and returns the names of the files it wrote; ``extra_files`` {name: path}
    are moved in. Raises ValueError where a row's length is not the header's."""
    folder = Path(getattr(stage, "path", stage))
    rows = np.asarray(rows, dtype=float)
    if rows.ndim != 2 or rows.shape[1] != len(columns):
        raise ValueError(f"{TIMESERIES}: rows of shape {rows.shape} under a header of {len(columns)} columns")
    with open(folder / TIMESERIES, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(list(columns))
        for r in rows:
            w.writerow([f"{v:.9g}" for v in r])
    np.savez_compressed(folder / LINES, **arrays)
    summary = dict(summary)
    if plots is not None:
        summary["plots"] = list(plots(folder))
    (folder / SUMMARY).write_text(json.dumps(jsonable(summary), indent=2))
    for name, path in (extra_files or {}).items():
        shutil.move(str(path), folder / name)
    return stage.commit() if hasattr(stage, "commit") else folder
