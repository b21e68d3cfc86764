"""A scenario's run: ``run`` steps a ``ScenarioRun`` to its end by the run loop every system
shares (``simulation.drive``), recording a row of ``RECORD_FIELDS`` and every element at each
output sample, with the watches it checks there (``TangleMonitor``, ``SurfaceWatch``) and the
video's frames as they fall due."""

from __future__ import annotations

import math
import time
from typing import NamedTuple

import numpy as np

from mjtether.cable import snap
from mjtether.simulation import drive

from . import Scenario
from .runner import RECORD_FIELDS, STATE_FIELDS, ScenarioRun


class TangleMonitor:
    """The tangle monitor's thresholds (``tangle`` in the scenario) checked at each recorded
    sample: an event when the cable comes within ``clearance_m`` of a vehicle, or within
    ``self_clearance_m`` of itself or crosses itself in plan view (logged once each time it goes
    in, with the time and the place); with ``stop``, the first event ends the run."""

    def __init__(self, cfg):
        self.cfg = cfg
        self.events = []
        self.stopped = ""
        self._inside = {"vehicle": False, "self": False}

    def check(self, run) -> bool:
        """Check the state just recorded (``run.named.last_tangle``); True to stop the run."""
        t = run.named.last_tangle
        if t is None:
            return False
        now = {"vehicle": self.cfg.clearance_m > 0 and t["clearance"] < self.cfg.clearance_m,
               "self": self.cfg.self_clearance_m > 0 and (t["self_clearance"] < self.cfg.self_clearance_m
                                                          or t["plan_crossings"] > 0)}
        new = False
        for kind, inside in now.items():
            if inside and not self._inside[kind]:
                key, limit = ("clearance", self.cfg.clearance_m) if kind == "vehicle" else \
                    ("self_clearance", self.cfg.self_clearance_m)
                where = "a vehicle" if kind == "vehicle" else "itself"
                self.events.append({"time_s": float(run.sim.time), "kind": kind, "clearance_m": float(t[key]),
                                    "place_m": [float(v) for v in t[f"{key}_at"]],
                                    "plan_crossings": int(t["plan_crossings"]),
                                    "what": (f"the cable within {t[key]:.2f} m of {where}" if t[key] >= 0.0 else
                                             f"the cable through {where} ({t[key]:.2f} m)")
                                    + f" (threshold {limit:g} m)"
                                    + (f", {t['plan_crossings']} crossing(s) in plan view"
                                       if kind == "self" and t["plan_crossings"] else "")})
                new = True
            self._inside[kind] = inside
        if new and self.cfg.stop and not self.stopped:
            e = self.events[-1]
            self.stopped = f"tangle.stop: {e['what']} at t = {e['time_s']:.2f} s"
            return True
        return False


class SurfaceWatch:
    """A submerged vehicle robot breaking the surface (part of its hull out of the water:
    ``BoundVehicle.wet_fraction`` below 1), checked at each recorded sample: an event logged once
    each time it goes out, with the time and how much of it is out; with ``robot.stop_at_surface``
    the first ends the run."""

    def __init__(self, vehicle, stop: bool):
        self.vehicle, self.stop = vehicle, stop
        self.events = []
        self.stopped = ""
        self._out = False

    def check(self, run) -> bool:
        d = run.sim.data
        wet = self.vehicle.wet_fraction(d)
        out = wet < 1.0
        if out and not self._out:
            self.events.append({"time_s": float(run.sim.time), "kind": "breach",
                                "position_m": [float(v) for v in d.xpos[self.vehicle.id]],
                                "what": f"the vehicle broke the surface ({100 * (1 - wet):.0f} % of its hull out of "
                                        "the water)"})
            if self.stop and not self.stopped:
                self.stopped = f"robot.stop_at_surface: {self.events[-1]['what']} at t = {run.sim.time:.2f} s"
                self._out = out
                return True
        self._out = out
        return False


class ScenarioResult(NamedTuple):
    """What ``run`` returns (``rows, history, info = run(sc)`` still unpacks it): ``rows``
    (samples, len(RECORD_FIELDS)), ``history`` (the elements and the MuJoCo state at the samples)
    and ``info`` (how the run went)."""

    rows: np.ndarray
    history: dict
    info: dict


def run(sc: Scenario, progress=None, keep_nodes: bool = True, video=None, on_start=None,
        on_end=None) -> ScenarioResult:
    """Simulate ``sc`` (``simulation.drive``, every system's run loop, stepping it); returns
    ``ScenarioResult(rows, history, info)``: ``rows`` (n, len(RECORD_FIELDS)), one per
    ``simulation.output_interval`` from the start and at the end (a duration that is not a whole
    number of intervals ends with a shorter one). ``history`` has
    ``nodes`` (n, e+1, 3) m, ``tension`` (n, e) N, ``element_length`` (n, e) m and
    ``compression`` (n, e) N (the largest push since the previous sample) and
    ``peak_tension`` (n, e) N (the largest tension since then) for every one
    of the e elements allocated (numbered from the drum's core; see ``element_record``), each
    sample (only the first with ``keep_nodes=False``), and ``qpos``, ``mocap_pos`` and ``mocap_quat``
    (``ScenarioRun.state``) at the same samples. At each sample the tangle monitor
    (``TangleMonitor``, with a tether) and the surface watch (``SurfaceWatch``, a submerged
    vehicle) are checked, and either may stop the run (``info["stopped"]`` says why).
    ``progress(k, n)`` is called as it goes. ``video(runner)`` makes a ``render.VideoRecorder``
    for the built run; frames are then taken as they fall due and the file is finished, or
    deleted if the run fails. ``on_start(runner)`` is called once the run is built and started,
    ``on_end(runner)`` after its last step (not if it fails), e.g. to read what the records do
    not hold. ``info`` times the run in wall seconds: ``wall_time_s`` all of it (``realtime_factor``
    its simulated seconds per wall second), ``start_s`` the building and starting (the force
    kernels' compile on a first run too) and ``stepping_s`` the stepping and recording
    (``stepping_realtime_factor``), apart. Raises ``RunFailed`` or ``SimulationDiverged`` (a
    record that became non-finite too)."""
    dt = sc.simulation.timestep
    n_steps = int(round(sc.simulation.duration / dt))
    every = max(1, int(round(sc.simulation.output_interval / dt)))
    hist, states = [], []
    t0 = time.perf_counter()
    runner = ScenarioRun(sc)
    rec = None
    try:
        if on_start is not None:
            on_start(runner)
        rec = video(runner) if video is not None else None
        watches = []
        monitor = TangleMonitor(sc.tangle) if runner.tethered else None
        if monitor is not None:
            watches.append(lambda: monitor.check(runner))
        surface = None
        if runner.vehicle is not None and runner.vehicle.hydro.surface is None:
            surface = SurfaceWatch(runner.vehicle, sc.robot.stop_at_surface)
            watches.append(lambda: surface.check(runner))

        def sample():
            row = runner.record()
            if keep_nodes or not hist:
                hist.append(runner.element_record())
                states.append(runner.state())
            return row

        def advance(k):
            runner.advance(k)

        t1 = time.perf_counter()  # (built, started, and compiled on a first run: the stepping starts)
        rows, n_steps = drive(advance, n_steps, every, sample, clock=lambda: runner.sim.time, watches=watches,
                              video=rec, progress=progress, names=[name for name, _, _ in RECORD_FIELDS])
        t2 = time.perf_counter()
        wall = t2 - t0
        if on_end is not None:
            on_end(runner)
        if rec is not None:
            rec.finish()
    except BaseException:
        if rec is not None:
            rec.abort()
        raise
    finally:
        runner.close()
    info = {"initial_state": runner.initial_note, "tethered": runner.tethered, "vehicle": bool(runner.named.hulls),
            "effective_EA": runner.effective_EA,
            "wall_time_s": wall, "simulated_s": n_steps * dt,
            "realtime_factor": n_steps * dt / wall if wall > 0 else math.inf, "steps": n_steps,
            "start_s": t1 - t0, "stepping_s": t2 - t1,
            "stepping_realtime_factor": n_steps * dt / (t2 - t1) if t2 > t1 else math.inf}
    if monitor is not None:
        info["tangle_events"] = monitor.events
        if monitor.stopped:
            info["stopped"] = monitor.stopped
    if runner.bt is not None and runner.bt.snaps is not None:
        info["snap_loads"] = snap.snap_report(runner.bt)
    if surface is not None:
        info["surface_events"] = surface.events
        if surface.stopped:
            info["stopped"] = surface.stopped
    if rec is not None:
        info["video"] = {"file": str(rec.path), "frames": rec.frames, "fps": rec.s.fps, "camera": rec.s.camera,
                         "tension_scale_N": rec.scale}
    history = {"nodes": np.array([h[0] for h in hist]), "tension": np.array([h[1] for h in hist]),
               "element_length": np.array([h[2] for h in hist]), "compression": np.array([h[3] for h in hist]),
               "peak_tension": np.array([h[4] for h in hist])}
    for k, key in enumerate(STATE_FIELDS):
        history[key] = np.array([st[k] for st in states])
    return ScenarioResult(rows, history, info)
