"""Replaying a results folder (``mjtether run SCENARIO --out DIR``) to a video without simulating
again: ``mjtether render DIR``.

The scene is rebuilt from the scenario saved in ``summary.json`` (``ScenarioRun(sc,
replay=True)``: nothing is stepped or solved), and each frame sets the state the run saved at
the sample on or after the frame's time (as a live video takes the first step on or after it):
the bodies' ``qpos`` and mocap poses and the tether's nodes from ``lines.npz``; the overlay's
time, tensions, deployed length and speed are the run's own (``timeseries.csv``), and the
tether is coloured by its saved tensions. Between two samples the picture holds still: a smooth
replay needs ``simulation.output_interval`` at or below 1 / fps.

A network's results folder (``summary.json`` kind "network") is replayed the same way
(``SavedNetwork``, ``NetworkReplay``): the network is rebuilt once from ``summary.json``'s
"network" (``network.run.build``: its statics are solved once, nothing is stepped), and each frame
sets the saved ``qpos`` and every line's nodes from ``lines.npz``; the lines are coloured by their
saved element tensions and the overlay's end tensions are those of ``timeseries.csv``.

A folder that is not a complete results folder is refused (``ReplayError``) with one line saying
what is missing.
"""

from __future__ import annotations

import csv
import json
from pathlib import Path

import mujoco
import numpy as np

from mjtether.files.outdir import MANIFEST
from mjtether.scenario import ScenarioError, load_scenario
from mjtether.scenario.runner import RECORD_FIELDS, STATE_FIELDS, ScenarioRun

from . import lines_npz
from .network_view import NetworkView
from .results import written

COLUMN = {name: i for i, (name, _, _) in enumerate(RECORD_FIELDS)}


class ReplayError(ValueError):
    """The folder cannot be replayed (the message says why, in one line)."""


def restore(x):
    """``summary.json``'s scenario or network back to what ``load_scenario(data=...)`` and
    ``network.from_dict`` take: the non-finite numbers it stores as text ("inf", as
    ``files.results_folder.jsonable`` writes them) as numbers, keys without a value left out."""
    if isinstance(x, dict):
        return {k: restore(v) for k, v in x.items() if v is not None}
    if isinstance(x, list):
        return [restore(v) for v in x]
    if isinstance(x, str) and x in ("inf", "-inf", "nan"):
        return float(x)
    return x


def _summary(folder) -> dict:
    """``summary.json`` of the results folder ``folder``, after checking that it is one (a
    ``ReplayError`` says what is missing)."""
    d, where = Path(folder), str(folder)
    if not d.is_dir():
        raise ReplayError(f"{where}: no such results folder")
    if not (d / "summary.json").is_file():
        raise ReplayError(f"{where}: not a results folder: no summary.json (give a folder that `mjtether run "
                          "SCENARIO --out DIR` wrote, or a scenario file)")
    if not (d / MANIFEST).is_file():
        raise ReplayError(f"{where}: an incomplete results folder: no {MANIFEST} (the run did not finish; run "
                          "the scenario again)")
    try:
        summary = json.loads((d / "summary.json").read_text())
    except (OSError, ValueError) as exc:
        raise ReplayError(f"{where}/summary.json: unreadable ({exc.__class__.__name__}: {exc})") from None
    if not isinstance(summary, dict):
        raise ReplayError(f"{where}/summary.json: unreadable (not a table of keys)")
    return summary


def is_network(folder) -> bool:
    """Whether the results folder ``folder`` is a network's (``summary.json`` kind "network")."""
    return _summary(folder).get("kind") == "network"


class Saved:
    """A results folder, read and checked: ``sc`` (the scenario as the run read it), ``rows``
    (the record, ``RECORD_FIELDS`` columns; those a run does not write are NaN), ``time``,
    ``nodes``, ``tension``, ``element_length`` and the state (``STATE_FIELDS``) per sample, and
    ``simulated_s``."""

    def __init__(self, folder):
        self.folder = d = Path(folder)
        where = str(folder)
        summary = _summary(folder)
        if summary.get("kind") == "network":
            raise ReplayError(f"{where}: a network's results folder (summary.json kind = network): read it with "
                              "SavedNetwork")
        try:
            run = summary["run"]
            raw = summary["scenario"]
            self.simulated_s = float(run["simulated_s"])
        except (ValueError, KeyError, TypeError) as exc:
            raise ReplayError(f"{where}/summary.json: unreadable ({exc.__class__.__name__}: {exc})") from None
        self.tethered, self.vehicle = bool(run.get("tethered", True)), bool(run.get("vehicle", True))
        try:
            self.sc = load_scenario(data=restore(raw), name=f"{where}/summary.json")
        except ScenarioError as exc:
            raise ReplayError(f"cannot rebuild the scenario: {exc}") from None
        npz = lines_npz.FILE if (d / lines_npz.FILE).is_file() or not (d / lines_npz.OLD_FILE).is_file() \
            else lines_npz.OLD_FILE  # (the file of a folder written before lines.npz)
        for name in ("timeseries.csv", npz):
            if not (d / name).is_file():
                raise ReplayError(f"{where}: an incomplete results folder: no {name}")
        try:
            z = lines_npz.read_tether(d)
            need = ("time", *(("nodes", "tension", "element_length") if self.tethered else ()), *STATE_FIELDS)
            missing = [k for k in need if k not in z]
            if missing:
                raise ReplayError(f"{where}/{npz}: holds no {', '.join(missing)} (written by an mjtether "
                                  "that did not save the states a replay sets): run the scenario again")
            for k in need:
                setattr(self, k, z[k])
            self.rows = self._read_rows(d / "timeseries.csv")
        except (OSError, ValueError, KeyError) as exc:
            if isinstance(exc, ReplayError):
                raise
            raise ReplayError(f"{where}: unreadable results ({exc.__class__.__name__}: {exc})") from None
        n = len(self.time)
        if n == 0 or len(self.rows) != n or any(len(getattr(self, k)) != n for k in need[1:]):
            raise ReplayError(f"{where}: {npz} and timeseries.csv disagree on the samples ({n} and "
                              f"{len(self.rows)}; a run with every sample kept has one per "
                              "simulation.output_interval in both)")

    def _read_rows(self, path: Path) -> np.ndarray:
        with open(path, newline="") as fh:
            table = [r for r in csv.reader(fh)][1:]
        keep = written(self.tethered, self.vehicle)
        rows = np.full((len(table), len(RECORD_FIELDS)), np.nan)
        if table and len(table[0]) != len(keep):
            raise ValueError(f"timeseries.csv has {len(table[0])} columns, not {len(keep)}")
        for i, r in enumerate(table):
            rows[i, keep] = [float(v) for v in r]
        return rows

    def sample_at(self, t: float) -> int:
        """The first sample on or after time ``t`` (s), the last if none."""
        return min(int(np.searchsorted(self.time, t - 1e-9)), len(self.time) - 1)


class _SavedReadouts:
    """The named readouts the renderer reads, from the saved sample ``k`` where the run saved
    them; the rest (the robot's place and heading, the vehicles' hulls) from the state set."""

    def __init__(self, live, saved: Saved):
        self._live, self._saved, self.k = live, saved, 0

    def __getattr__(self, name):
        return getattr(self._live, name)

    def _row(self, name: str) -> float:
        return float(self._saved.rows[self.k, COLUMN[name]])

    @property
    def time(self) -> float:
        return float(self._saved.time[self.k])

    @property
    def ship_tension(self) -> float:
        return self._row("ship_tension")

    @property
    def tow_tension(self) -> float:
        return self._row("tow_tension")

    @property
    def deployed_length(self) -> float:
        return self._row("deployed_length")

    @property
    def robot_speed(self) -> float:
        return self._row("robot_speed")

    def _first(self) -> int:
        """The first deployed element: those on the drum have length 0."""
        on = self._saved.element_length[self.k] > 0.0
        return int(np.argmax(on)) if on.any() else 0

    @property
    def tether_nodes(self) -> np.ndarray:
        return self._saved.nodes[self.k, self._first():].copy()

    @property
    def tether_tension(self) -> np.ndarray:
        return self._saved.tension[self.k, self._first():].copy()

    def tangle(self, x=None) -> dict:
        return self._live.tangle(self.tether_nodes if x is None else x)


class Replay:
    """What ``render.VideoRecorder`` draws (the parts of a ``ScenarioRun`` it reads), showing a
    results folder's saved samples: ``show(k)`` sets sample ``k``. ``close()`` frees the model."""

    def __init__(self, saved: Saved):
        self.saved = saved
        self.run = run = ScenarioRun(saved.sc, replay=True)
        try:
            m = run.sim.model
            if saved.qpos.shape[1] != m.nq or saved.mocap_pos.shape[1] != m.nmocap:
                raise ReplayError(f"{saved.folder}: the saved states do not fit the scene rebuilt from its scenario "
                                  f"({saved.qpos.shape[1]} positions saved, {m.nq} in the model): written by another "
                                  "version of mjtether? run the scenario again")
            self.sc, self.sim, self.water, self.walker = run.sc, run.sim, run.water, run.walker
            self.tethered, self.is_vehicle, self.scene = run.tethered, run.is_vehicle, run.scene
            self.named = _SavedReadouts(run.named, saved)
            # the tether's node bodies (three world slide joints each): their qpos is a displacement
            # from the body's place in this model, set from the saved world positions of the nodes
            self._node_qpos = None  # (a vehicle alone: no tether's nodes to set)
            if run.tethered:
                bodies = [int(b) for b in run.bt.layout.bids]
                self._node_qpos = np.array([[m.jnt_qposadr[m.body_jntadr[b] + a] for a in range(3)] for b in bodies])
                d = run.sim.data
                d.qpos[self._node_qpos.ravel()] = 0.0
                mujoco.mj_kinematics(m, d)
                self._node_ref = d.xpos[bodies].copy()
        except BaseException:
            run.close()
            raise
        self.show(0)

    @property
    def contact_diameter(self) -> float:
        return self.run.contact_diameter

    def seabed_z(self, x, y):
        return self.run.seabed_z(x, y)

    def show(self, k: int) -> None:
        """Set the saved sample ``k``: the bodies' state, the tether's nodes, the readouts."""
        s, m, d = self.saved, self.sim.model, self.sim.data
        d.qpos[:] = s.qpos[k]
        d.mocap_pos[:] = s.mocap_pos[k]
        d.mocap_quat[:] = s.mocap_quat[k]
        if self._node_qpos is not None:
            d.qpos[self._node_qpos] = s.nodes[k] - self._node_ref
        d.qvel[:] = 0.0
        d.time = float(s.time[k])
        mujoco.mj_forward(m, d)
        self.named.k = k

    def close(self) -> None:
        self.run.close()


class SavedNetwork:
    """A network's results folder, read and checked: ``net`` (the network as the run read it, from
    ``summary.json``'s "network"), ``simulated_s``, and per sample ``time`` (s), ``qpos`` (the
    model's positions) and, per line NAME, ``nodes[NAME]`` (samples, n+1, 3; m, world),
    ``tension[NAME]`` (samples, n; N) from end A to end B, and ``ends[NAME]`` (samples, 2: the
    tension at ends A and B, N, from ``timeseries.csv``)."""

    def __init__(self, folder):
        from mjtether.network import NetworkError, from_dict

        self.folder = d = Path(folder)
        where = str(folder)
        summary = _summary(folder)
        lacks = [k for k in ("network", "simulated_s") if k not in summary]
        if lacks:
            raise ReplayError(f"{where}/summary.json: holds no {lacks[0]} (written by an older mjtether, which did not "
                              "save what a replay rebuilds): run the network again")
        if not isinstance(summary["network"], dict):
            raise ReplayError(f"{where}/summary.json: network must be a table (the network's TOML tree)")
        try:
            self.net = from_dict(restore(summary["network"]), name=f"{where}/summary.json")
            self.simulated_s = float(summary["simulated_s"])
        except (NetworkError, ValueError, TypeError, KeyError, AttributeError) as exc:
            raise ReplayError(f"cannot rebuild the network from {where}/summary.json: {exc}") from None
        for name in ("timeseries.csv", "lines.npz"):
            if not (d / name).is_file():
                raise ReplayError(f"{where}: an incomplete results folder: no {name}")
        names = [ln.name for ln in self.net.lines]
        try:
            with np.load(d / "lines.npz") as z:
                if "qpos" not in z.files:
                    raise ReplayError(f"{where}/lines.npz: holds no qpos (written by an older mjtether, which did not "
                                      "save the states a replay sets): run the network again")
                need = ["time_s"] + [f"line{n}_{k}" for n in names for k in ("nodes", "tension")]
                missing = [k for k in need if k not in z.files]
                if missing:
                    raise ReplayError(f"{where}/lines.npz: holds no {', '.join(missing)}: run the network again")
                self.time, self.qpos = z["time_s"], z["qpos"]
                self.nodes = {n: z[f"line{n}_nodes"] for n in names}
                self.tension = {n: z[f"line{n}_tension"] for n in names}
            self.ends = self._read_ends(d / "timeseries.csv", names)
        except (OSError, ValueError, KeyError, IndexError) as exc:
            if isinstance(exc, ReplayError):
                raise
            raise ReplayError(f"{where}: unreadable results ({exc.__class__.__name__}: {exc})") from None
        n = len(self.time)
        per_line = (*self.nodes.values(), *self.tension.values(), *self.ends.values())
        counts = [len(self.qpos)] + [len(a) for a in per_line]
        if n == 0 or any(c != n for c in counts):
            raise ReplayError(f"{where}: lines.npz and timeseries.csv disagree on the samples ({n} times, "
                              f"{min(counts)} to {max(counts)} states)")
        for name in names:
            x, t = self.nodes[name], self.tension[name]
            if x.ndim != 3 or x.shape[2] != 3 or t.shape != (n, x.shape[1] - 1):
                raise ReplayError(f"{where}/lines.npz: line{name}_nodes {x.shape} and line{name}_tension {t.shape} "
                                  "are not (samples, n+1, 3) and (samples, n): run the network again")

    @staticmethod
    def _read_ends(path: Path, names: list) -> dict:
        with open(path, newline="") as fh:
            table = list(csv.reader(fh))
        if len(table) < 2:
            raise ReplayError(f"{path}: no samples: run the network again")
        header, rows = table[0], np.array([[float(v) for v in r] for r in table[1:]]).reshape(-1, len(table[0]))
        out = {}
        for n in names:
            cols = [f"line{n}_{e}_tension_N" for e in "AB"]
            missing = [c for c in cols if c not in header]
            if missing:
                raise ReplayError(f"{path}: no column {missing[0]}: run the network again")
            out[n] = rows[:, [header.index(c) for c in cols]]
        return out

    def sample_at(self, t: float) -> int:
        """The first sample on or after time ``t`` (s), the last if none."""
        return min(int(np.searchsorted(self.time, t - 1e-9)), len(self.time) - 1)


class NetworkReplay(NetworkView):
    """A network's results folder as ``render.FrameRenderer`` draws it: the network built once
    (``network.run.build``, its EA warnings silenced: the run gave them), ``show(k)`` setting the
    saved sample ``k``: ``qpos``, and every line's node bodies (three world slide joints each,
    their ``qpos`` a displacement from the body's place in this model) at the saved nodes; the
    lines' tensions and the overlay's from the folder. ``close()`` frees the model."""

    def __init__(self, saved: SavedNetwork):
        import warnings

        from mjtether.network.run import build

        self.saved = saved
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            r = build(saved.net)
        try:
            m, d = r.sim.model, r.sim.data
            if saved.qpos.shape[1] != m.nq:
                raise ReplayError(f"{saved.folder}: the saved states do not fit the network rebuilt from its summary "
                                  f"({saved.qpos.shape[1]} positions saved, {m.nq} in the model): written by another "
                                  "version of mjtether? run the network again")
            self._node_qpos, bodies = {}, {}
            for name, bt in r.sim.tethers.items():  # (builder order: from end B to end A)
                if saved.nodes[name].shape[1] != bt.n + 1:
                    raise ReplayError(f"{saved.folder}/lines.npz: line{name}_nodes holds "
                                      f"{saved.nodes[name].shape[1] - 1} elements, the line rebuilt from its summary "
                                      f"{bt.n}: written by another version of mjtether? run the network again")
                bodies[name] = [int(b) for b in bt.layout.bids]
                self._node_qpos[name] = np.array([[m.jnt_qposadr[m.body_jntadr[b] + a] for a in range(3)]
                                                  for b in bodies[name]])
                d.qpos[self._node_qpos[name].ravel()] = 0.0
            mujoco.mj_kinematics(m, d)
            self._node_ref = {name: d.xpos[b].copy() for name, b in bodies.items()}
            super().__init__(r)
        except BaseException:
            r.sim.close()
            raise
        self.show(0)

    @property
    def time(self) -> float:
        return float(self.saved.time[self.k])

    def line_state(self, name: str) -> tuple[np.ndarray, np.ndarray]:
        return self.saved.nodes[name][self.k], self.saved.tension[name][self.k]

    def end_tensions(self) -> dict:
        return {name: tuple(float(v) for v in e[self.k]) for name, e in self.saved.ends.items()}

    def show(self, k: int) -> None:
        """Set the saved sample ``k``."""
        s, m, d = self.saved, self.r.sim.model, self.r.sim.data
        d.qpos[:] = s.qpos[k]
        for name, adr in self._node_qpos.items():
            d.qpos[adr] = s.nodes[name][k][::-1] - self._node_ref[name]
        d.qvel[:] = 0.0
        d.time = float(s.time[k])
        mujoco.mj_forward(m, d)
        self.k = k

    def close(self) -> None:
        self.r.sim.close()


def replay(folder, path, settings, duration: float | None = None, overwrite: bool = True) -> dict:
    """Render the results folder ``folder`` (a scenario's or a network's) to the video ``path``
    (``render.VideoSettings`` ``settings``) for ``duration`` s (default: all the run simulated);
    returns what ``run``'s info["video"] holds, with ``simulated_s``, ``samples``,
    ``output_interval_s``, ``smooth`` and ``wall_time_s``. Raises ``ReplayError`` (or ValueError
    for a bad video path)."""
    import time

    from .render import VideoRecorder, check_output_path

    t0 = time.perf_counter()
    check_output_path(path, overwrite=overwrite)
    network = is_network(folder)
    saved = SavedNetwork(folder) if network else Saved(folder)
    if duration is not None and not (0.0 < duration <= saved.simulated_s + 1e-9):
        raise ReplayError(f"--duration {duration:g}: must be in (0, {saved.simulated_s:g}] s, the time the saved "
                          "run simulated")
    shown = saved.simulated_s if duration is None else duration
    rep = NetworkReplay(saved) if network else Replay(saved)
    try:
        with VideoRecorder(rep, path, settings, duration=shown) as rec:
            for t in rec.times:
                rep.show(saved.sample_at(t))
                rec.capture()
        scale = rec.scale
    finally:
        rep.close()
    samples = int(np.searchsorted(saved.time, shown + 1e-9))
    interval = saved.net.output_interval if network else saved.sc.simulation.output_interval
    return {"file": str(rec.path), "frames": rec.frames, "fps": settings.fps, "camera": settings.camera,
            "tension_scale_N": scale, "simulated_s": shown, "samples": samples,
            "tethered": bool(network or saved.tethered),
            "wall_time_s": time.perf_counter() - t0, "output_interval_s": interval,
            "smooth": interval <= (1.0 + 1e-9) / settings.fps}
