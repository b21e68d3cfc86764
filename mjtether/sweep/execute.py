"""Running the cases: one case (``run_case``), on this process and a pool of worker processes
(``run_local``), or as Ray tasks (``run_ray``)."""

from __future__ import annotations

import concurrent.futures as cf
import contextlib
import datetime
import multiprocessing
import os
import re
import signal
import threading
import time

from ..network import Network
from ..scenario import Scenario
from .outputs import COLUMNS
from .plan import Case, SweepError, network_columns

# ------------------------------------------------------------------ one case


class _RunProbe:
    """``runner.run``'s ``on_start``/``on_end`` callbacks: the start's touchdown and, at the
    end, the touchdown of the final shape (figures the recorded rows do not hold)."""

    def __init__(self):
        self.touchdown_start = None
        self.touchdown_end = None
        self.runner = None

    @property
    def time(self) -> float:
        """The simulated time reached (s)."""
        return 0.0 if self.runner is None else float(self.runner.sim.time)

    def start(self, runner) -> None:
        self.runner = runner
        ss = runner.initial
        self.touchdown_start = None if ss is None or ss.touchdown is None else float(ss.touchdown)

    def end(self, runner) -> None:
        touchdown = runner.named.touchdown_arc_length()
        if touchdown is not None:
            self.touchdown_end = touchdown


def run_case(sc: Scenario | Network, folder=None) -> dict:
    """Run one case (in whichever process): its figures (``COLUMNS``; a network's:
    ``run_network_case``), ``status`` and ``error``. Never raises for a failing case;
    KeyboardInterrupt and SystemExit pass through. ``folder`` (``--keep-cases``): where a case
    that ran ok also writes its whole results folder, as ``mjtether run --out`` does
    (``io.results.write``: staged beside it, renamed into place complete, with its manifest; an
    earlier one there is replaced), from the same run as the figures; a failed case writes none.
    An error writing it (``OutputError``: a full disk) is not the case's: it is raised."""
    if isinstance(sc, Network):
        return run_network_case(sc, folder)
    from mjtether.io.results import summary
    from mjtether.scenario.runner import RECORD_FIELDS, RunFailed, run

    from ..simulation import SimulationDiverged

    started = time.time()
    t0 = time.perf_counter()
    rec = {name: None for name, _ in COLUMNS}
    rec.update(status="ok", error="", started_at=_iso(started))
    probe = _RunProbe()
    history = None
    try:
        rows, history, info = run(sc, keep_nodes=folder is not None, on_start=probe.start, on_end=probe.end)
    except (RunFailed, SimulationDiverged, ValueError, RuntimeError) as exc:
        rec.update(status="failed", error=str(exc) or type(exc).__name__)
        _failed_figures(rec, exc, probe, SimulationDiverged)
    except Exception as exc:  # noqa: BLE001 - one bad case must not stop a long sweep
        rec.update(status="failed", error=f"{type(exc).__name__}: {exc}")
        _failed_figures(rec, exc, probe, SimulationDiverged)
    else:
        s = summary(sc, rows, info, None)
        col = {name: i for i, (name, _, _) in enumerate(RECORD_FIELDS)}
        rec.update(initial_state=info["initial_state"])
        if info.get("tethered", True):  # (a vehicle without a tether has no tension figures: left empty)
            rec.update(peak_ship_tension_N=s["peak"]["ship_tension_N"], peak_tow_tension_N=s["peak"]["tow_tension_N"],
                       final_ship_tension_N=s["final"]["ship_tension_N"],
                       final_tow_tension_N=s["final"]["tow_tension_N"],
                       final_deployed_length_m=s["final"]["deployed_length_m"],
                       final_length_on_seabed_m=float(rows[-1, col["length_on_seabed"]]),
                       touchdown_start_m=probe.touchdown_start, touchdown_end_m=probe.touchdown_end,
                       min_node_z_m=float(rows[:, col["tether_lowest_z"]].min()))
    rec["wall_s"] = time.perf_counter() - t0
    if folder is not None and rec["status"] == "ok":
        from mjtether.io.results import write

        write(folder, sc, rows, history, info, overwrite=True)
    return rec


def run_network_case(net: Network, folder=None) -> dict:
    """Run one network case (``mjtether.network.run.simulate``, ``r.sim`` closed after): its
    figures (``plan.network_columns``: each line's peak and final end tensions, N, from the
    time series), ``status`` and ``error``, as ``run_case``; with ``folder``, a case that ran
    ok writes its results folder there as ``mjtether run --out`` does (``network.run.write``,
    staged, with its manifest)."""
    from mjtether.network.run import columns, simulate, write

    from ..simulation import SimulationDiverged

    started = time.time()
    t0 = time.perf_counter()
    rec = {name: None for name, _ in network_columns(net)}
    rec.update(status="ok", error="", started_at=_iso(started))
    try:
        r, rows = simulate(net)
    except Exception as exc:  # noqa: BLE001 - one bad case must not stop a long sweep
        known = isinstance(exc, (SimulationDiverged, ValueError, RuntimeError))
        rec.update(status="failed", error=(str(exc) or type(exc).__name__) if known else f"{type(exc).__name__}: {exc}")
        if isinstance(exc, SimulationDiverged):
            m = re.search(r"diverged at t = ([-+0-9.eE]+) s", str(exc))
            rec["diverged_at_s"] = float(m.group(1)) if m else None
    else:
        try:
            col = {name: j for j, name in enumerate(columns(net))}
            peaks = []
            for ln in net.lines:
                a, b = (rows[:, col[f"line{ln.name}_{end}_tension_N"]] for end in "AB")
                peaks.append(float(max(a.max(), b.max())))
                rec[f"line{ln.name}_peak_tension_N"] = peaks[-1]
                rec[f"line{ln.name}_final_A_tension_N"] = float(a[-1])
                rec[f"line{ln.name}_final_B_tension_N"] = float(b[-1])
            rec.update(peak_tension_N=max(peaks) if peaks else None, timestep_s=float(r.timestep),
                       initial_state=r.note)
            rec["wall_s"] = time.perf_counter() - t0
            if folder is not None:
                from mjtether.files.outdir import Staging, check_target

                with Staging(check_target(folder, overwrite=True), overwrite=True) as stage:
                    write(r, rows, stage, wall_time=rec["wall_s"])
        finally:
            r.sim.close()
        return rec
    rec["wall_s"] = time.perf_counter() - t0
    return rec


def _failed_figures(rec, exc, probe, diverged_type) -> None:
    rec["touchdown_start_m"] = probe.touchdown_start
    if probe.runner is not None:
        rec["initial_state"] = probe.runner.initial_note
    if isinstance(exc, diverged_type):
        m = re.search(r"diverged at t = ([-+0-9.eE]+) s", str(exc))
        rec["diverged_at_s"] = float(m.group(1)) if m else probe.time


def _iso(t: float) -> str:
    return datetime.datetime.fromtimestamp(t, datetime.timezone.utc).isoformat(timespec="microseconds")


_CLAIMS = None
"""In a worker process: the shared claim flags of the cases (see ``run_local``)."""


def _worker_init(claims) -> None:
    """Workers leave Ctrl-C to the main process, which stops them (no traceback per worker)."""
    global _CLAIMS
    _CLAIMS = claims
    signal.signal(signal.SIGINT, signal.SIG_IGN)


def _claim(claims, i: int) -> bool:
    """Take case ``i`` if no process has taken it yet."""
    with claims.get_lock():
        if claims[i]:
            return False
        claims[i] = 1
        return True


def _claim_and_run(i: int, sc: Scenario | Network, folder=None) -> dict | None:
    """In a worker: run case ``i`` unless the main process took it (then None); ``folder``: as
    ``run_case``'s (the worker writes the case's results folder itself)."""
    return _run_one(sc, folder) if _claim(_CLAIMS, i) else None


def _run_one(sc, folder):
    """``run_case``, looked up at call time (tests replace it), given ``folder`` only where there is one."""
    return run_case(sc) if folder is None else run_case(sc, folder)


# ------------------------------------------------------------------ running them


def run_local(cases: list[Case], jobs: int, on_result, folder_of=None) -> None:
    """Run ``cases``, ``jobs`` at a time, calling ``on_result(case, record)`` in this process as
    each finishes; ``folder_of(case)``, where given, the folder each case's results go to
    (``run_case``'s ``folder``: written by whichever process runs it, a worker or this one).
    ``jobs`` > 1: every case is submitted to a pool of ``jobs - 1`` worker
    processes, which take them from the front, while this process takes them from the back;
    a shared flag per case says who took it (a worker handed a case already taken skips it).
    (Cancelling queued futures instead would be simpler, but Python 3.11's executor then fails
    on them when its workers are stopped after a Ctrl-C.)"""
    def folder(c):
        return None if folder_of is None else folder_of(c)

    if jobs <= 1 or len(cases) <= 1:
        for c in cases:
            on_result(c, _run_one(c.sc, folder(c)))
        return
    ctx = multiprocessing.get_context("spawn")
    claims = ctx.Array("b", len(cases))
    ex = cf.ProcessPoolExecutor(max_workers=min(jobs - 1, len(cases) - 1), mp_context=ctx,
                                initializer=_worker_init, initargs=(claims,))
    futures = {}
    clean = False
    try:
        with _worker_start():  # the worker processes start during these submits
            for i, c in enumerate(cases):
                futures[ex.submit(_claim_and_run, i, c.sc, folder(c))] = c
        back = len(cases) - 1
        while futures or back >= 0:
            for f in [f for f in futures if f.done()]:
                c = futures.pop(f)
                rec = _result(f)
                if rec is not None:
                    on_result(c, rec)
            mine = None
            if back >= 0:
                if _claim(claims, back):
                    mine = cases[back]
                    back -= 1
                else:  # a worker has it, so it has taken every case before it too
                    back = -1
            if mine is not None:
                on_result(mine, _run_one(mine.sc, folder(mine)))
            elif futures:
                cf.wait(list(futures), return_when=cf.FIRST_COMPLETED)
        clean = True
    finally:
        if not clean:  # keep what the workers finished, then stop them
            for f, c in list(futures.items()):
                if f.done() and not f.cancelled() and f.exception() is None and f.result() is not None:
                    with contextlib.suppress(BaseException):
                        on_result(c, f.result())
            _stop_workers(ex)
        ex.shutdown(wait=clean, cancel_futures=True)


@contextlib.contextmanager
def _worker_start():
    """What worker processes started inside inherit: SIGINT ignored (a Ctrl-C while they import
    prints no traceback; the main process stops them), and ``MUJOCO_GL=disable`` (they never
    render: MuJoCo then skips loading GLFW, whose library probe runs a child process of its own)."""
    main = threading.current_thread() is threading.main_thread()
    old = signal.signal(signal.SIGINT, signal.SIG_IGN) if main else None
    gl = os.environ.get("MUJOCO_GL")
    os.environ["MUJOCO_GL"] = "disable"
    try:
        yield
    finally:
        if gl is None:
            os.environ.pop("MUJOCO_GL", None)
        else:
            os.environ["MUJOCO_GL"] = gl
        if main:
            signal.signal(signal.SIGINT, old)


def _result(f) -> dict:
    try:
        return f.result()
    except cf.BrokenExecutor as exc:
        raise SweepError(f"a worker process died ({exc}); the cases finished so far are kept: rerun the same "
                         "command to resume", code=1) from None


def _stop_workers(ex) -> None:
    procs = list((getattr(ex, "_processes", None) or {}).values())
    for p in procs:
        with contextlib.suppress(Exception):
            p.terminate()
    for p in procs:
        with contextlib.suppress(Exception):
            p.join(timeout=5)


def _import_ray():
    try:
        import ray
    except ImportError:
        raise SweepError("--ray needs Ray, which is not installed: pip install mjtether[ray]") from None
    return ray


def run_ray(cases: list[Case], address: str | None, jobs: int | None, on_result) -> None:
    """Run ``cases`` as Ray tasks (one ``@ray.remote`` around ``run_case``), calling
    ``on_result(case, record)`` here as each finishes. Uses a Ray already initialised in this
    process, else ``ray.init(address=address or None)`` (shut down again at the end)."""
    ray = _import_ray()
    started = False
    if not ray.is_initialized():
        kw = {"num_cpus": jobs} if not address and jobs else {}
        ray.init(address=address or None, **kw)
        started = True
    refs = {}
    try:
        remote = ray.remote(num_cpus=1)(run_case)
        refs = {remote.remote(c.sc): c for c in cases}
        pending = list(refs)
        while pending:
            done, pending = ray.wait(pending, num_returns=1)
            if pending:  # and whatever else is ready
                more, pending = ray.wait(pending, num_returns=len(pending), timeout=0)
                done += more
            for r in done:
                c = refs.pop(r)
                try:
                    rec = ray.get(r)
                except ray.exceptions.RayError as exc:
                    first = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
                    raise SweepError(f"Ray task of case {c.index} failed ({first}); the cases finished so far "
                                     "are kept: rerun the same command to resume", code=1) from None
                on_result(c, rec)
    except BaseException:
        for r in refs:
            with contextlib.suppress(Exception):
                ray.cancel(r, force=True)
        raise
    finally:
        if started:
            ray.shutdown()
