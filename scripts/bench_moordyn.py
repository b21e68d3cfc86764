"""Benchmark: mjtether against MoorDyn-C on MoorDyn's own files, wall time per simulated second.

Cases (``tests/data/moordyn``, MoorDyn v2.7.1): MoorDyn's ``WD0200_Chain.txt`` (one 700 m chain
from a vessel to an anchor in 200 m of water) with its NumSegs set to 20, 40 and 100,
``lines.txt`` (three lines of 20 segments, the OC3-Hywind spread mooring), ``WD0600_Chain.txt``
(one 1700 m chain in 600 m of water) at 200 segments, and ``RodHanging.txt`` (a free rod, a
rigid body, hung on two 450 m ropes of 45 segments, released from the file's positions). Each
is run for ``DURATION`` s by both, in one process, one after the other:

* MoorDyn-C (the ``moordyn`` package): ``Create``, ``Init`` (its initial-condition solver) and
  its steps at the file's dtM (or the step its CFL gives);
* mjtether: what ``mjtether run FILE`` runs (a scenario for one line, a network for several),
  from its steady state, at its own stable step, without writing results.

Reported per case: seconds of wall time per simulated second for each, the stepping alone for
each, and their ratio (mjtether over MoorDyn; below 1: mjtether faster). The goal is a ratio
below 1 on every case.

**At equal accuracy** (``equal_accuracy``, the ``*_eq_*`` keys): each program is run again at its
own step times ``FACTORS`` (MoorDyn-C's from its file's dtM or CFL, set by ``SetDt`` after its
initial-condition solve; mjtether's from its own stable step, by ``simulation.timestep``); its
fairlead tension at the end (line 1's, end B) at the finest step is its converged value, and the
largest step whose tension is within ``EQUAL_ACCURACY`` of it (a run that fails or diverges does
not count) is the one it is timed at. Reported: the step found and the wall time per simulated
second of each, and their ratio. The runs start from each program's own steady state and hold
the fairlead still, so the steps found are those at which each settles to its own equilibrium;
a moving fairlead (a heaving ship) would ask more of each.

    python scripts/bench_moordyn.py [--json]
"""

from __future__ import annotations

import argparse
import json
import math
import os
import re
import shutil
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np

DATA = Path(__file__).resolve().parents[1] / "tests" / "data" / "moordyn" / "tests" / "Mooring"
DURATION = 20.0
CASES = {"single_N20": ("WD0200_Chain.txt", 20), "single_N40": ("WD0200_Chain.txt", 40),
         "single_N100": ("WD0200_Chain.txt", 100), "network_3_lines": ("lines.txt", None),
         "single_N200_1700m": ("WD0600_Chain.txt", 200), "body_rod_hanging": ("RodHanging.txt", None)}


def _case_file(folder: Path, name: str, segments: int | None) -> Path:
    """The case's file in ``folder`` (MoorDyn writes its outputs beside it), NumSegs replaced."""
    text = (DATA / name).read_text()
    if segments is not None:  # the LINES row: ID LineType AttachA AttachB UnstrLen NumSegs ...
        head, sep, rest = text.partition(re.search(r"^-+ *LINES *-+.*$", text, flags=re.M).group(0))
        rest = re.sub(r"^(1\s+\S+\s+\S+\s+\S+\s+\S+\s+)\d+", rf"\g<1>{segments}", rest, count=1, flags=re.M)
        text = head + sep + rest
        text = re.sub(r"^.*fileIC.*$\n", "", text, flags=re.M)  # (its saved start is for 170 segments)
    elif (DATA / f"{name}.ic").exists():  # (the file's saved start for MoorDyn's IC solver)
        shutil.copy(DATA / f"{name}.ic", folder)
    path = folder / name
    path.write_text(text)
    return path


def _moordyn_start(path: Path):
    """MoorDyn-C's system for ``path`` (in its folder), initialised with its coupled points where
    the file puts them, at rest: (system, their positions, their velocities)."""
    import moordyn
    s = moordyn.Create(str(path))
    x = []
    for i in range(moordyn.GetNumberPoints(s)):
        p = moordyn.GetPoint(s, i + 1)
        if moordyn.GetPointType(p) == moordyn.POINT_TYPE_COUPLED:
            x += list(moordyn.GetPointPos(p))
    x = np.array(x, float)
    v = np.zeros_like(x)
    moordyn.Init(s, x, v)
    return s, x, v


def moordyn_c(path: Path) -> tuple[float, float]:
    """(wall s of the whole run, wall s of its steps) per simulated second."""
    import moordyn
    old = os.getcwd()
    os.chdir(path.parent)
    try:
        t0 = time.perf_counter()
        s, x, v = _moordyn_start(path)
        t1 = time.perf_counter()
        t, dt = 0.0, 0.1
        while t < DURATION - 1e-9:
            moordyn.Step(s, x, v, t, dt)
            t += dt
        t2 = time.perf_counter()
        moordyn.Close(s)
    finally:
        os.chdir(old)
    return (t2 - t0) / DURATION, (t2 - t1) / DURATION


def moordyn_c_at(path: Path, factor: float) -> tuple[float, float, float]:
    """MoorDyn-C on ``path`` at ``factor`` times its own step: (the step, s; line 1's fairlead
    tension at the end, N, NaN if the run failed; wall s of the whole run per simulated second)."""
    import moordyn
    old = os.getcwd()
    os.chdir(path.parent)
    try:
        t0 = time.perf_counter()
        s, x, v = _moordyn_start(path)
        import cmoordyn  # (moordyn.GetDt of MoorDyn 2.7 drops the value it reads: its module's own call)
        dt = cmoordyn.get_dt(s) * factor
        moordyn.SetDt(s, dt)
        t, tension = 0.0, math.nan
        try:
            while t < DURATION - 1e-9:
                moordyn.Step(s, x, v, t, 0.1)
                t += 0.1
            tension = float(moordyn.GetLineFairTen(moordyn.GetLine(s, 1)))
        except (RuntimeError, ValueError):  # (MoorDyn-C's NaN check)
            pass
        wall = time.perf_counter() - t0
        moordyn.Close(s)
    finally:
        os.chdir(old)
    return dt, tension, wall / DURATION


def mjtether_at(path: Path, factor: float) -> tuple[float, float, float]:
    """mjtether on ``path`` at ``factor`` times its own stable step, as ``mjtether``: (the step,
    s; line 1's fairlead tension at the end, N, NaN if the run failed; wall s of the whole run per
    simulated second)."""
    from mjtether.io import moordyn as md
    from mjtether.network import Network
    from mjtether.network import run as nrun
    from mjtether.scenario.runner import run
    from mjtether.simulation import SimulationDiverged

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        base = md.read(path, overrides=[f"simulation.duration={DURATION}"])
        if isinstance(base, Network):  # (its own step: built once to find it, not timed)
            probe = nrun.build(base)
            probe.sim.close()
            dt = probe.timestep * factor
        else:
            dt = base.simulation.timestep * factor
        t0 = time.perf_counter()
        try:
            sc = md.read(path, overrides=[f"simulation.duration={DURATION}", f"simulation.timestep={dt!r}"])
            if isinstance(sc, Network):
                r = nrun.build(sc)
                if sc.settle > 0:
                    nrun.settle(r, sc.settle)
                r.sim.step(round(DURATION / r.timestep))
                tension = float(np.linalg.norm(r.line_forces(sc.lines[0].name)[1]))
                r.sim.close()
            else:
                rows, _, _ = run(sc, keep_nodes=False)
                tension = float(rows[-1, 1])  # (ship_tension, RECORD_FIELDS' first after time)
        except (SimulationDiverged, ValueError, RuntimeError):
            tension = math.nan
    return dt, tension, (time.perf_counter() - t0) / DURATION


FACTORS = (4.0, 2.0, 1.0, 0.5, 0.25, 0.125)
"""Each program's steps tried, as multiples of its own (the last: its converged answer)."""
EQUAL_ACCURACY = 1e-3
"""The fairlead tension's distance from the converged value at which a step counts (0.1 %)."""


def equal_accuracy(path: Path, program) -> dict:
    """``program`` (``moordyn_c_at`` or ``mjtether_at``) on ``path`` at each of ``FACTORS``: the
    largest step within ``EQUAL_ACCURACY`` of the finest's tension, and its cost."""
    runs = [program(path, f) for f in FACTORS]
    ref = runs[-1][1]
    for dt, tension, cost in runs:
        if math.isfinite(tension) and abs(tension / ref - 1.0) <= EQUAL_ACCURACY:
            return {"step_s": dt, "tension_N": round(tension, 2), "s_per_s": cost, "converged_N": round(ref, 2)}
    raise RuntimeError(f"{path.name}: no step of {program.__name__} converged")


def mjtether(path: Path) -> tuple[float, float]:
    """(wall s of the whole run, wall s of its steps) per simulated second."""
    from mjtether.io import moordyn as md
    from mjtether.network import Network
    from mjtether.network import run as nrun
    from mjtether.scenario.runner import run

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", md.MoorDynWarning)
        t0 = time.perf_counter()
        sc = md.read(path, overrides=[f"simulation.duration={DURATION}"])
    if isinstance(sc, Network):
        r = nrun.build(sc)
        if sc.settle > 0:
            nrun.settle(r, sc.settle)
        t1 = time.perf_counter()
        r.sim.step(round(DURATION / r.timestep))
        t2 = time.perf_counter()
        r.sim.close()
        return (t2 - t0) / DURATION, (t2 - t1) / DURATION
    _, _, info = run(sc, keep_nodes=False)
    t2 = time.perf_counter()
    return (t2 - t0) / DURATION, info["stepping_s"] / DURATION  # (wall_time_s, before 2026-12-02: the whole run)


def measure() -> dict:
    out = {"duration_s": DURATION}
    with tempfile.TemporaryDirectory(prefix="bench-moordyn-") as tmp:
        mjtether(_case_file(Path(tmp), "lines.txt", None))  # (first use: kernels and imports, of a network
        warm = Path(tmp) / "warm"  # and of a scenario)
        warm.mkdir()
        mjtether(_case_file(warm, "WD0050_Chain.txt", 10))
        shutil.rmtree(warm)
        for key, (name, n) in CASES.items():
            folder = Path(tmp) / key
            folder.mkdir()
            path = _case_file(folder, name, n)
            md_total, md_steps = moordyn_c(path)
            mj_total, mj_steps = mjtether(path)
            md_eq, mj_eq = equal_accuracy(path, moordyn_c_at), equal_accuracy(path, mjtether_at)
            shutil.rmtree(folder)
            for who, eq in (("moordyn", md_eq), ("mjtether", mj_eq)):
                out[f"{key}_eq_{who}_step_s"] = float(f"{eq['step_s']:.4g}")
                out[f"{key}_eq_{who}_s_per_s"] = round(eq["s_per_s"], 4)
                out[f"{key}_eq_{who}_tension_N"] = eq["tension_N"]
            out[f"{key}_eq_ratio"] = round(mj_eq["s_per_s"] / md_eq["s_per_s"], 3)
            out[f"{key}_moordyn_s_per_s"] = round(md_total, 4)
            out[f"{key}_mjtether_s_per_s"] = round(mj_total, 4)
            out[f"{key}_moordyn_steps_s_per_s"] = round(md_steps, 4)
            out[f"{key}_mjtether_steps_s_per_s"] = round(mj_steps, 4)
            out[f"{key}_ratio"] = round(mj_total / md_total, 3)
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--json", action="store_true", help="print one JSON object")
    args = ap.parse_args(argv)
    out = measure()
    if args.json:
        print(json.dumps(out))
        return
    for key in CASES:
        print(f"{key}: mjtether {out[f'{key}_mjtether_s_per_s']:.3f} s/s (steps {out[f'{key}_mjtether_steps_s_per_s']:.3f}), "
              f"MoorDyn-C {out[f'{key}_moordyn_s_per_s']:.3f} s/s (steps {out[f'{key}_moordyn_steps_s_per_s']:.3f}); "
              f"ratio {out[f'{key}_ratio']:.2f}; at equal accuracy (0.1 %): mjtether at "
              f"{out[f'{key}_eq_mjtether_step_s']:g} s, {out[f'{key}_eq_mjtether_s_per_s']:.4f} s/s, MoorDyn-C at "
              f"{out[f'{key}_eq_moordyn_step_s']:g} s, {out[f'{key}_eq_moordyn_s_per_s']:.4f} s/s: ratio "
              f"{out[f'{key}_eq_ratio']:.2f}")


if __name__ == "__main__":
    main()
