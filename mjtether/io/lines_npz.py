"""``lines.npz``: every line of a run at every sample, in one layout for a single tether and for a
network of lines.

Keys (arrays; SI units; world frame, z up; a line's arrays named by ``files.results_folder.line_arrays``
for every system):

* ``time_s`` (n,): the samples' times (s);
* per line NAME (a single tether's line is named ``tether``), every array from end A to end B
  (MoorDyn's ends: A at the anchor or robot, B at the fairlead or the ship's winch):
  ``lineNAME`` (its deployed nodes at the end of the run, m), ``lineNAME_nodes`` (n, e+1, 3; m),
  ``lineNAME_tension`` (n, e; N, >= 0: each element's pull, 0 when slack),
  ``lineNAME_compression`` (n, e; N, >= 0: the largest push of each element's constraint since the
  previous sample, which a cable cannot make and the tension leaves out), ``lineNAME_peak_tension``
  (n, e; N: the largest tension of each element since the previous sample, over every time
  step) and, for a single tether, ``lineNAME_element_length`` (n, e; m, stretched). A line on a winch keeps its full
  capacity: cable still on the drum is at end B, with element length and tension 0, so element j
  is the same piece of cable all run;
* ``qpos`` (n, nq) and, where the model has mocap bodies (a ship, a held robot),
  ``mocap_pos`` (n, nmocap, 3; m) and ``mocap_quat`` (n, nmocap, 4): the MuJoCo state that
  places every body at each sample, which ``mjtether render DIR`` sets again to replay the run.

Folders written before this layout hold a single tether's arrays in ``tether.npz`` instead
(``time``, ``nodes``, ... from the ship's drum to the robot); ``read_tether`` reads either.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from mjtether.files.results_folder import LINES as FILE
from mjtether.files.results_folder import line_arrays

OLD_FILE = "tether.npz"
TETHER = "tether"
"""The name of a single tether's line."""
STATE = ("qpos", "mocap_pos", "mocap_quat")


def tether_arrays(time: np.ndarray, history: dict, tethered: bool = True) -> dict:
    """``lines.npz``'s arrays of a single-tether run from ``scenario.runner.run``'s ``history``
    (its arrays from the drum's core to the robot, reversed here to run from end A, the robot)."""
    out = {"time_s": np.asarray(time, float)}
    if tethered:
        nodes = history["nodes"][:, ::-1]
        length = history["element_length"][-1, ::-1]
        on = np.flatnonzero(length > 0.0)
        last = int(on[-1]) + 1 if on.size else 0  # (the deployed nodes: those of the elements with a length)
        out.update(line_arrays(TETHER, nodes[-1, :last + 1], {
            "nodes": nodes, **{key: history[key][:, ::-1] for key in ("tension", "compression", "element_length",
                                                                        "peak_tension") if key in history}}))
    for key in STATE:
        if key in history:
            out[key] = history[key]
    return out


def read_tether(folder) -> dict:
    """A single-tether run's saved arrays in ``scenario.runner.run``'s order (from the drum's core
    to the robot): {"time", "nodes", "tension", "element_length", "compression" (where saved),
    and the ``STATE`` arrays}; from ``lines.npz``, or ``tether.npz`` in a folder written before
    it. Raises KeyError naming a missing array, FileNotFoundError where neither file is there."""
    d = Path(folder)
    if (d / FILE).is_file():
        with np.load(d / FILE) as z:
            out = {"time": z["time_s"]}
            for key in ("nodes", "tension", "element_length", "compression", "peak_tension"):
                name = f"line{TETHER}_{key}"
                if name in z.files:
                    out[key] = z[name][:, ::-1]
            out.update({k: z[k] for k in STATE if k in z.files})
        return out
    if (d / OLD_FILE).is_file():
        with np.load(d / OLD_FILE) as z:
            return {k: z[k] for k in z.files}
    raise FileNotFoundError(f"no {FILE}")
