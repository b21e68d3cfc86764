"""Parameter sweeps: one scenario run over a grid (or a random sample) of key values.

    mjtether sweep SCENARIO.toml --vary KEY=SPEC [--vary ...] [--samples K [--seed S]]
                   [--set KEY=VALUE ...] [--jobs N | --ray [ADDRESS]] --out DIR [--overwrite] [--restart]

``--vary tether.length=200:1000:9`` is START:STOP:COUNT (inclusive, as ``numpy.linspace``; numbers
and integers only); ``--vary water.current.surface_speed_kn=0,1,2`` is a list (any kind of key;
items in TOML syntax, a bare word is a string, ``[40.0, 0.0, -90.0]`` a point). Keys are scenario
key paths as in the file (``_kn`` knots aliases allowed, ``_deg`` keys in degrees). The cases are
the Cartesian product of the ``--vary`` values (the last ``--vary`` changing fastest), or with
``--samples K`` K random draws (uniform within each range, its COUNT then unused; uniform over
each list), from ``--seed`` (default 0, so that the same command draws the same cases). ``--set``
overrides apply to every case, before the varied keys.

Checks, all before anything runs (exit 2, one line, nothing written): a key that is unknown, a
section, or given twice; a spec that is neither a list nor START:STOP:COUNT; a value that its key
never allows (type, range, choices); the scenario file itself; and (for a product sweep) a value
for which every case is invalid, with the first case's reason. A case invalid only in combination
(e.g. an anchor below a seabed made shallower by another key) is recorded as failed with the reason.

Running: each case is ``runner.run(sc, keep_nodes=False)``. ``--jobs 1`` (the default) runs them
in this process; ``--jobs N`` runs N at a time: N - 1 worker processes of a
``concurrent.futures.ProcessPoolExecutor`` (``spawn`` context: MuJoCo and ``fork`` do not mix)
take cases from the front of the queue while this process takes them from the back (so the
workers' start-up, about 0.7 s of imports each, is not lost time). ``--ray [ADDRESS]`` runs
them as Ray tasks instead (``ray.init(address=ADDRESS or None)``; a local Ray is given
``--jobs`` CPUs if set; ``pip install mjtether[ray]``; the cluster's nodes need mjtether installed).
A case that fails (``RunFailed``, ``SimulationDiverged``, ``ValueError``, any other exception in
the case) records its error text and the sweep goes on. A worker process that dies stops the
sweep (exit 1); the cases finished so far are kept for a resume. From Python: ``sweep(...)``
(the same arguments; raises ``SweepError``); with ``jobs`` > 1 the worker processes re-import the
main module (``spawn``), so call it from a file, under ``if __name__ == "__main__":``.

Output ``DIR`` (``outdir`` rules, as ``mjtether run --out``: refused if it holds anything unless it
is purely an earlier sweep and ``--overwrite`` is given; written into a staging folder and
renamed into place complete, with a manifest):

* ``cases.csv``, ``cases.parquet``: one row per case (``COLUMNS`` lists the figures): ``case``
  (0-based), each varied input (named by its key path, plus ``_<unit>`` where the key does not
  already end in its unit: ``tether.length_m``, ``water.current.surface_speed_kn``), ``status``
  (ok / failed), ``error``, then the figures (empty / null where not available). The CSV holds
  floats at full precision (``repr``); the Parquet file (pyarrow) the same rows, typed.
* ``summary.png``: peak ship-end tension and length on the seabed at the end against the first
  varied key, coloured by the second; failed cases marked with a red x along the bottom.
* ``sweep.json``: the sweep (scenario file, ``--set``, ``--vary``, samples, seed, each case's
  overrides, versions, counts); ``scenario.toml``: the scenario file as read.

Parquet needs pyarrow, an optional dependency (``pip install mjtether[sweep]``, also in ``dev``):
it is about 170 MB installed, too much to impose on every user of ``mjtether run``. Without it
``mjtether sweep`` stops at once with that one-line instruction, before anything runs.

Resume (design). The rule for results stays as in ``outdir``: ``DIR`` appears complete or not at
all. Progress therefore lives outside it, in a hidden folder beside it,
``.<DIR name>.mjtether-sweep/`` (``Journal``): a marker ``progress.json`` (proof that mjtether
made the folder: anything else at that name is refused, never deleted), a ``lock`` (``flock``:
two sweeps into one ``DIR`` at once are refused), and ``cases/<key>.json``, one small file per
finished case, written atomically (temporary file, then rename) by this process as each result
comes in. ``<key>`` is a SHA-256 of the case's complete checked scenario (``Scenario.to_dict``)
and the mjtether and MuJoCo versions, so a result is reused exactly when the same physics would
be rerun: rerunning the same command after an interrupt (Ctrl-C, SIGTERM, SIGKILL, a worker that
died, a power cut) runs only the cases not finished; changing ``--vary`` reuses the cases that
are still in it; failed cases count as finished (they are deterministic). When every case is
done the results are staged, committed to ``DIR``, and only then is the progress folder removed.
``--restart`` discards the progress folder first (e.g. after changing mjtether's code without
changing its version). An abandoned progress folder stays until a sweep into the same ``DIR``
finishes or it is removed by hand.
"""

from __future__ import annotations

import concurrent.futures as cf
import contextlib
import csv
import datetime
import errno
import hashlib
import itertools
import json
import math
import multiprocessing
import os
import re
import shutil
import signal
import sys
import threading
import time
import tomllib
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .config import ConfigError, Param, params, split_index, subsections, table_lists, unknown_key_message
from .outdir import terminate_as_exit
from .scenario import Scenario, load_scenario
from .units import KNOT

FORMAT = "mjtether-sweep/1"
"""``format`` of ``sweep.json`` in a sweep results folder (what ``--overwrite`` may replace)."""
PROGRESS_FORMAT = "mjtether-sweep-progress/1"
MAX_CASES = 100_000
"""More cases than this is refused (a typo in a COUNT, most likely)."""

COLUMNS = [
    ("peak_ship_tension_N", "largest ship-end tension of the run"),
    ("peak_tow_tension_N", "largest tow-point tension of the run"),
    ("final_ship_tension_N", "ship-end tension at the end"),
    ("final_tow_tension_N", "tow-point tension at the end"),
    ("final_deployed_length_m", "unstretched deployed length at the end"),
    ("final_length_on_seabed_m", "tether length lying on the seabed at the end"),
    ("touchdown_start_m", "quasi-static start: arc length from the ship to the touchdown (SteadyState.touchdown; "
                          "empty if the cable hangs free or the run settled from a guessed shape)"),
    ("touchdown_end_m", "at the end: unstretched length from the ship to the first element lying on the seabed "
                        "(the length_on_seabed criterion); empty if none does"),
    ("min_node_z_m", "lowest height of any tether node over the recorded samples"),
    ("diverged_at_s", "simulated time at which the run diverged (SimulationDiverged), else empty"),
    ("wall_s", "wall-clock time of the case (s)"),
    ("started_at", "wall-clock start of the case (UTC, ISO 8601)"),
    ("initial_state", "how the run started (runner's initial-state note)"),
]
"""The figures of each case, after ``case``, the varied inputs, ``status`` and ``error``."""
_TEXT_COLUMNS = {"started_at", "initial_state"}


class SweepError(Exception):
    """A one-line reason the sweep cannot go on; ``code`` is the exit status (2: bad input,
    nothing run or written; 1: stopped while running, finished cases kept)."""

    def __init__(self, message: str, code: int = 2):
        super().__init__(message)
        self.code = code


# ------------------------------------------------------------------ --vary


@dataclass(frozen=True)
class Vary:
    """One ``--vary KEY=SPEC``: a list of ``values`` (with their TOML ``texts``) or a range."""

    key: str  # as given, e.g. water.current.surface_speed_kn
    spec: str
    path: str  # the parameter's key path (without _kn)
    param: Param
    values: tuple  # the grid: the list, or the range's COUNT points
    texts: tuple  # TOML text of each value (what goes into the override)
    range: tuple | None = None  # (start, stop) for a range

    @property
    def knots(self) -> bool:
        return self.key != self.path

    @property
    def column(self) -> str:
        unit = "kn" if self.knots else self.param.unit.replace(" ", "").replace("/", "per")
        if not unit or self.key.endswith(f"_{unit}"):
            return self.key
        return f"{self.key}_{unit}"

    @property
    def numeric(self) -> bool:
        return self.param.kind in ("float", "int")

    def draw(self, rng: np.random.Generator):
        """One random value (and its text): uniform within the range / over the list."""
        if self.range is None:
            k = int(rng.integers(len(self.values)))
            return self.values[k], self.texts[k]
        lo, hi = sorted(self.range)
        if self.param.kind == "int":
            v = int(rng.integers(math.ceil(lo), math.floor(hi), endpoint=True))
        else:
            v = float(rng.uniform(lo, hi))
        return v, _toml(v)


def parse_vary(item: str) -> Vary:
    """A checked ``Vary`` from ``KEY=SPEC``; raises SweepError naming it."""
    key, sep, spec = str(item).partition("=")
    key, spec = key.strip(), spec.strip()
    where = f"--vary {item}"
    if not sep or not key or not spec:
        raise SweepError(f"{where}: must be KEY=START:STOP:COUNT or KEY=V1,V2,..., "
                         "e.g. --vary tether.length=200:1000:9")
    path, param = _resolve(key, where)
    colons = _split(spec, ":")
    if len(colons) > 1:
        if len(colons) != 3 or len(_split(spec, ",")) > 1:
            raise SweepError(f"{where}: a range is START:STOP:COUNT (COUNT values, both ends included), "
                             "e.g. 200:1000:9; a list is V1,V2,...")
        if param.kind not in ("float", "int"):
            raise SweepError(f"{where}: {path} is not a number ({param.allowed()}); give a list, V1,V2,...")
        try:
            start, stop = (float(tomllib.loads(f"v = {c.strip()}")["v"]) for c in colons[:2])
            count = tomllib.loads(f"v = {colons[2].strip()}")["v"]
        except (tomllib.TOMLDecodeError, TypeError, ValueError):
            raise SweepError(f"{where}: START and STOP must be numbers and COUNT an integer, "
                             "e.g. 200:1000:9") from None
        if isinstance(count, bool) or not isinstance(count, int) or count < 2:
            raise SweepError(f"{where}: COUNT must be an integer >= 2 (the number of values, both ends included)")
        if count > MAX_CASES:
            raise SweepError(f"{where}: COUNT {count} is more than {MAX_CASES} cases")
        if not (math.isfinite(start) and math.isfinite(stop)):
            raise SweepError(f"{where}: START and STOP must be finite numbers")
        grid = [float(v) for v in np.linspace(start, stop, count)]
        if param.kind == "int":
            if any(abs(v - round(v)) > 1e-9 * max(1.0, abs(v)) for v in grid):
                raise SweepError(f"{where}: {path} is an integer, and {spec} gives {_show_list(grid)}; "
                                 "choose START, STOP and COUNT that give integers, or give a list")
            grid = [int(round(v)) for v in grid]
        values, rng = tuple(grid), (start, stop)
        texts = tuple(_toml(v) for v in values)
    else:
        texts = tuple(t.strip() for t in _split(spec, ","))
        if any(not t for t in texts):
            raise SweepError(f"{where}: an empty item in the list (V1,V2,...)")
        values, rng = tuple(_parse_value(t) for t in texts), None
    v = Vary(key, spec, path, param, values, texts, rng)
    for value in values:  # a value its key never allows is wrong in every case
        x = value * KNOT if v.knots and _is_number(value) else value
        try:
            param.check(path, x)
        except ConfigError:
            unit = " kn" if v.knots else ""
            raise SweepError(f"{where}: {key} = {_show(value)}{unit} is never allowed: {path} must be "
                             f"{param.allowed()}") from None
    return v


def _resolve(key: str, where: str) -> tuple[str, Param]:
    """(key path of the parameter, its Param) for a key as written (``_kn`` alias allowed)."""
    parts = [p.strip() for p in key.split(".")]
    if any(not p for p in parts):
        raise SweepError(f"{where}: {key!r} is not a key path (e.g. tether.length)")
    cls = Scenario
    for part in parts[:-1]:
        try:
            s, index = split_index(part)
        except ConfigError as exc:
            raise SweepError(f"{where}: {exc}") from None
        subs = table_lists(cls) if index is not None else subsections(cls)  # (tether.floats[0].start)
        if s not in subs:
            raise SweepError(f"{where}: {unknown_key_message(cls, s)}")
        cls = subs[s]
    leaf = parts[-1]
    ps = params(cls)
    if leaf in ps:
        return ".".join(parts), ps[leaf]
    if leaf.endswith("_kn") and leaf[:-3] in ps and ps[leaf[:-3]].knots:
        return ".".join(parts[:-1] + [leaf[:-3]]), ps[leaf[:-3]]
    if leaf in subsections(cls):
        raise SweepError(f"{where}: {key} is a section [{key}], not a key; vary one of its keys")
    raise SweepError(f"{where}: {unknown_key_message(cls, leaf)}")


def _split(text: str, sep: str) -> list[str]:
    """``text`` split at ``sep`` outside brackets, braces and quotes."""
    out, depth, quote, cur = [], 0, None, []
    for ch in text:
        if quote:
            if ch == quote:
                quote = None
        elif ch in "\"'":
            quote = ch
        elif ch in "[{":
            depth += 1
        elif ch in "]}":
            depth -= 1
        elif ch == sep and depth == 0:
            out.append("".join(cur))
            cur = []
            continue
        cur.append(ch)
    out.append("".join(cur))
    return out


def _parse_value(text: str):
    """A value as ``--set`` reads it: TOML, else a bare word (a string)."""
    try:
        return tomllib.loads(f"v = {text}")["v"]
    except tomllib.TOMLDecodeError:
        return text


def _is_number(v) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def _toml(v) -> str:
    """TOML text of a value (floats exactly)."""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        return "nan" if math.isnan(v) else ("inf" if v > 0 else "-inf") if math.isinf(v) else repr(v)
    if isinstance(v, str):
        return json.dumps(v)
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_toml(x) for x in v) + "]"
    raise TypeError(f"no TOML text for {v!r}")


def _show(v) -> str:
    return _toml(v) if not isinstance(v, str) else v


def _show_list(values) -> str:
    return ", ".join(f"{v:g}" for v in values)


# ------------------------------------------------------------------ the cases


@dataclass
class Case:
    index: int
    values: tuple  # one per Vary
    overrides: list  # every override of the case (--set, then the varied keys)
    sc: Scenario | None  # None: invalid (``error`` says why)
    error: str = ""
    key: str = ""  # resume key (see the module docstring)


@dataclass
class Plan:
    scenario: str  # the file as given
    text: str
    sets: list
    varies: list
    samples: int | None
    seed: int
    cases: list


def make_plan(scenario, varies: list[Vary], *, sets=(), samples: int | None = None, seed: int = 0) -> Plan:
    """Every case, checked (see the module docstring); raises SweepError for input that is
    wrong in every case."""
    import mujoco

    from . import __version__

    name = str(scenario)
    p = Path(scenario)
    if p.is_dir():
        raise SweepError(f"{name}: is a folder; give a scenario .toml file")
    try:
        text = p.read_bytes().decode("utf-8-sig")
    except OSError as exc:
        raise SweepError(f"{name}: cannot read the scenario ({exc.strerror})") from None
    except UnicodeDecodeError:
        text = None  # load_scenario says what is wrong with it
    seen = {}
    for v in varies:
        if v.path in seen:
            raise SweepError(f"--vary {v.key}: {v.path} is varied twice (also as --vary {seen[v.path]})")
        seen[v.path] = v.key
    varied = set(seen)
    try:  # the file and --set on their own (an error about a varied key may be one the cases fix)
        load_scenario(scenario, text=text, name=name, overrides=list(sets))
    except ConfigError as exc:
        if exc.key not in varied or text is None:
            raise SweepError(str(exc)) from None
    if samples is not None:
        if not 1 <= samples <= MAX_CASES:
            raise SweepError(f"--samples {samples}: must be in [1, {MAX_CASES}]")
        rng = np.random.default_rng(seed)
        combos = [[v.draw(rng) for v in varies] for _ in range(samples)]
    else:
        n = math.prod(len(v.values) for v in varies)
        if n > MAX_CASES:
            raise SweepError(f"--vary: {n} cases is more than {MAX_CASES}; use fewer values or --samples")
        combos = itertools.product(*[list(zip(v.values, v.texts)) for v in varies])
    versions = {"mjtether": __version__, "mujoco": mujoco.__version__}
    cases = []
    for i, combo in enumerate(combos):
        ov = list(sets) + [f"{v.key}={t}" for v, (_, t) in zip(varies, combo)]
        case = Case(i, tuple(x for x, _ in combo), ov, None)
        try:
            case.sc = load_scenario(scenario, text=text, name=name, overrides=ov)
        except ConfigError as exc:
            case.error = f"invalid case: {exc}"
        else:
            blob = json.dumps({"scenario": case.sc.to_dict(), **versions}, sort_keys=True)
            case.key = hashlib.sha256(blob.encode()).hexdigest()[:32]
        cases.append(case)
    if samples is None:
        _refuse_always_invalid(varies, cases)
    elif all(c.sc is None for c in cases):
        raise SweepError(f"every case is invalid; case 0: {cases[0].error}")
    return Plan(name, text or "", list(sets), list(varies), samples, seed, cases)


def _refuse_always_invalid(varies, cases) -> None:
    """A value of a product sweep for which every case is invalid is an input error."""
    valid, first = set(), {}
    for c in cases:
        for j, value in enumerate(c.values):
            k = (j, _show(value))
            if c.sc is not None:
                valid.add(k)
            else:
                first.setdefault(k, c)
    for j, v in enumerate(varies):
        for value in v.values:
            k = (j, _show(value))
            if k not in valid and k in first:
                why = first[k].error.removeprefix("invalid case: ")
                raise SweepError(f"--vary {v.key}={v.spec}: {v.key} = {_show(value)} is invalid in every case "
                                 f"({why})")


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


def run_case(sc: Scenario) -> dict:
    """Run one case (in whichever process): its figures (``COLUMNS``), ``status`` and ``error``.
    Never raises for a failing case; KeyboardInterrupt and SystemExit pass through."""
    from .results import summary
    from .runner import RECORD_FIELDS, RunFailed, run
    from .simulation import SimulationDiverged

    started = time.time()
    t0 = time.perf_counter()
    rec = {name: None for name, _ in COLUMNS}
    rec.update(status="ok", error="", started_at=_iso(started))
    probe = _RunProbe()
    try:
        rows, _, info = run(sc, keep_nodes=False, on_start=probe.start, on_end=probe.end)
    except (RunFailed, SimulationDiverged, ValueError, RuntimeError) as exc:
        rec.update(status="failed", error=str(exc) or type(exc).__name__)
        _failed_figures(rec, exc, probe, SimulationDiverged)
    except Exception as exc:  # noqa: BLE001 - one bad case must not stop a long sweep
        rec.update(status="failed", error=f"{type(exc).__name__}: {exc}")
        _failed_figures(rec, exc, probe, SimulationDiverged)
    else:
        s = summary(sc, rows, info, None)
        col = {name: i for i, (name, _, _) in enumerate(RECORD_FIELDS)}
        rec.update(peak_ship_tension_N=s["peak"]["ship_tension_N"], peak_tow_tension_N=s["peak"]["tow_tension_N"],
                   final_ship_tension_N=s["final"]["ship_tension_N"], final_tow_tension_N=s["final"]["tow_tension_N"],
                   final_deployed_length_m=s["final"]["deployed_length_m"],
                   final_length_on_seabed_m=float(rows[-1, col["length_on_seabed"]]),
                   touchdown_start_m=probe.touchdown_start, touchdown_end_m=probe.touchdown_end,
                   min_node_z_m=float(rows[:, col["tether_lowest_z"]].min()), initial_state=info["initial_state"])
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


def _claim_and_run(i: int, sc: Scenario) -> dict | None:
    """In a worker: run case ``i`` unless the main process took it (then None)."""
    return run_case(sc) if _claim(_CLAIMS, i) else None


# ------------------------------------------------------------------ running them


def run_local(cases: list[Case], jobs: int, on_result) -> None:
    """Run ``cases``, ``jobs`` at a time, calling ``on_result(case, record)`` in this process as
    each finishes. ``jobs`` > 1: every case is submitted to a pool of ``jobs - 1`` worker
    processes, which take them from the front, while this process takes them from the back;
    a shared flag per case says who took it (a worker handed a case already taken skips it).
    (Cancelling queued futures instead would be simpler, but Python 3.11's executor then fails
    on them when its workers are stopped after a Ctrl-C.)"""
    if jobs <= 1 or len(cases) <= 1:
        for c in cases:
            on_result(c, run_case(c.sc))
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
                futures[ex.submit(_claim_and_run, i, c.sc)] = c
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
                on_result(mine, run_case(mine.sc))
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


# ------------------------------------------------------------------ progress (resume)


class Journal:
    """The progress folder of a sweep into ``target`` (see the module docstring)."""

    MARK = "progress.json"

    def __init__(self, target: Path):
        self.target = Path(target)
        self.dir = self.target.parent / f".{self.target.name}.mjtether-sweep"
        self._lock = None

    def open(self, restart: bool = False) -> dict:
        """Create or take over the folder; returns {key: record} of the finished cases."""
        d = self.dir
        if os.path.lexists(d):
            if d.is_symlink() or not d.is_dir() or not self._ours():
                raise SweepError(f"{str(d)!r} (where a sweep into {str(self.target)!r} keeps its progress) exists "
                                 "and was not made by mjtether; move it away or choose another --out")
        d.mkdir(parents=True, exist_ok=True)
        self._take_lock()
        if restart and (d / "cases").is_dir():
            shutil.rmtree(d / "cases")
        (d / "cases").mkdir(exist_ok=True)
        mark = d / self.MARK
        if not mark.is_file():
            _atomic_write(mark, json.dumps({"format": PROGRESS_FORMAT, "target": str(self.target)}) + "\n")
        return self._finished()

    def _ours(self) -> bool:
        try:
            return json.loads((self.dir / self.MARK).read_text()).get("format") == PROGRESS_FORMAT
        except (OSError, ValueError, AttributeError):
            return False

    def _take_lock(self) -> None:
        try:
            import fcntl
        except ImportError:  # not on POSIX: no lock
            return
        fh = open(self.dir / "lock", "a")
        try:
            fcntl.flock(fh, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError as exc:
            fh.close()
            if exc.errno in (errno.EWOULDBLOCK, errno.EAGAIN, errno.EACCES):
                raise SweepError(f"another mjtether sweep into {str(self.target)!r} is running; wait for it or "
                                 "choose another --out") from None
            raise
        self._lock = fh

    def _finished(self) -> dict:
        done = {}
        for p in (self.dir / "cases").glob("*.json"):
            try:
                data = json.loads(p.read_text())
            except (OSError, ValueError):
                continue  # unreadable: run it again
            if isinstance(data, dict) and data.get("key") == p.stem and isinstance(data.get("record"), dict):
                done[p.stem] = data["record"]
        return done

    def add(self, case: Case, record: dict) -> None:
        data = {"format": PROGRESS_FORMAT, "key": case.key, "overrides": case.overrides, "record": record}
        _atomic_write(self.dir / "cases" / f"{case.key}.json", json.dumps(data, allow_nan=True) + "\n")

    def close(self) -> None:
        if self._lock is not None:
            self._lock.close()
            self._lock = None

    def remove(self) -> None:
        self.close()
        shutil.rmtree(self.dir, ignore_errors=True)


def _atomic_write(path: Path, text: str) -> None:
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    tmp.write_text(text)
    os.replace(tmp, path)


# ------------------------------------------------------------------ results


def table(plan: Plan, records: dict) -> tuple[list[str], list[list]]:
    """(column names, rows) of the results: one row per case, ``records`` {case index: record}."""
    names = ["case"] + [v.column for v in plan.varies] + ["status", "error"] + [n for n, _ in COLUMNS]
    rows = []
    for c in plan.cases:
        r = records.get(c.index) or {"status": "failed", "error": c.error or "not run"}
        rows.append([c.index, *c.values, r.get("status"), r.get("error", "")] + [r.get(n) for n, _ in COLUMNS])
    return names, rows


def write_csv(path: Path, names, rows) -> None:
    def cell(v):
        if v is None:
            return ""
        if isinstance(v, (bool, list, tuple)):
            return _toml(v)
        if isinstance(v, float):
            return repr(v)
        return v

    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(names)
        for r in rows:
            w.writerow([cell(v) for v in r])


def write_parquet(path: Path, plan: Plan, names, rows) -> None:
    import pyarrow as pa
    import pyarrow.parquet as pq

    kinds = {"float": pa.float64(), "int": pa.int64(), "bool": pa.bool_(), "str": pa.string()}
    types = [pa.int64()] + [kinds.get(v.param.kind, pa.string()) for v in plan.varies] + [pa.string(), pa.string()]
    types += [pa.string() if n in _TEXT_COLUMNS else pa.float64() for n, _ in COLUMNS]
    cols = []
    for j, (name, typ) in enumerate(zip(names, types)):
        vals = [r[j] for r in rows]
        if typ == pa.string():
            vals = [v if v is None or isinstance(v, str) else _toml(v) for v in vals]
        elif typ == pa.float64():
            vals = [None if v is None else float(v) for v in vals]
        cols.append(pa.array(vals, type=typ))
    pq.write_table(pa.table(cols, names=names), path)


def plot(path: Path, plan: Plan, names, rows) -> None:
    """``summary.png``: two figures against the first varied key, coloured by the second."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib import transforms

    col = {n: j for j, n in enumerate(names)}
    vx = plan.varies[0]
    vc = plan.varies[1] if len(plan.varies) > 1 else None
    xs = [r[1] for r in rows]
    if vx.numeric:
        xpos, xticks = [float(x) for x in xs], None
    else:
        labels = list(dict.fromkeys(_show(x) for x in xs))
        xpos, xticks = [labels.index(_show(x)) for x in xs], labels
    colours, legend, norm = {}, [], None  # colours: {second key's value as text: colour}
    if vc is not None:
        cs = [r[2] for r in rows]
        if vc.numeric and len(set(cs)) > 1:
            norm = matplotlib.colors.Normalize(min(cs), max(cs))
            cmap = matplotlib.colormaps["viridis"]
            colours = {_show(c): cmap(norm(c)) for c in cs}
        else:
            palette = matplotlib.colormaps["tab10"]
            colours = {lv: palette(k % 10) for k, lv in enumerate(dict.fromkeys(_show(c) for c in cs))}
            legend = list(colours.items())
    panels = [("peak_ship_tension_N", "peak ship-end tension (N)"),
              ("final_length_on_seabed_m", "length on the seabed at the end (m)")]
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.5), layout="constrained")
    ok = [k for k, r in enumerate(rows) if r[col["status"]] == "ok"]
    bad = [k for k, r in enumerate(rows) if r[col["status"]] != "ok"]
    groups = {}
    for k in ok:
        groups.setdefault(_show(rows[k][2]) if vc is not None else "", []).append(k)
    for ax, (name, label) in zip(axes, panels):
        for g, ks in groups.items():
            ks = sorted(ks, key=lambda k: xpos[k])
            colour = colours[_show(rows[ks[0]][2])] if colours else "C0"
            if plan.samples is None and len(plan.varies) <= 2:
                ax.plot([xpos[k] for k in ks], [rows[k][col[name]] for k in ks], "-", color=colour, alpha=0.6)
            ax.scatter([xpos[k] for k in ks], [rows[k][col[name]] for k in ks], color=colour, s=22, zorder=3)
        if bad:
            trans = transforms.blended_transform_factory(ax.transData, ax.transAxes)
            ax.scatter([xpos[k] for k in bad], [0.03] * len(bad), marker="x", color="red", s=40, transform=trans,
                       zorder=4, label=f"failed ({len(bad)})", clip_on=False)
            ax.legend(loc="upper right", fontsize=8)
        ax.set_xlabel(vx.column)
        ax.set_ylabel(label)
        if xticks is not None:
            ax.set_xticks(range(len(xticks)), xticks, rotation=30, fontsize=8)
        ax.grid(alpha=0.3)
    if vc is not None and legend:
        handles = [plt.Line2D([], [], marker="o", ls="", color=c, label=str(lv)) for lv, c in legend]
        if bad:
            handles.append(plt.Line2D([], [], marker="x", ls="", color="red", label=f"failed ({len(bad)})"))
        axes[0].legend(handles=handles, title=vc.column, fontsize=8, title_fontsize=8, loc="best")
    elif norm is not None:
        sm = matplotlib.cm.ScalarMappable(norm=norm, cmap=cmap)
        fig.colorbar(sm, ax=axes, label=vc.column)
    fig.suptitle(f"{len(rows)} cases, {len(bad)} failed" + (f" ({plan.samples} random draws)" if plan.samples else ""))
    fig.savefig(path, dpi=110)
    plt.close(fig)


def write_results(target: Path, plan: Plan, records: dict, *, overwrite: bool) -> Path:
    """Stage and commit the results folder (``outdir.Staging``)."""
    import mujoco

    from . import __version__
    from .outdir import Staging

    names, rows = table(plan, records)
    with Staging(target, overwrite=overwrite) as st:
        write_csv(st.path / "cases.csv", names, rows)
        write_parquet(st.path / "cases.parquet", plan, names, rows)
        plot(st.path / "summary.png", plan, names, rows)
        (st.path / "scenario.toml").write_text(plan.text)
        n_ok = sum(1 for r in rows if r[names.index("status")] == "ok")
        meta = {"format": FORMAT, "scenario_file": plan.scenario, "set": plan.sets,
                "vary": [{"key": v.key, "spec": v.spec, "column": v.column} for v in plan.varies],
                "samples": plan.samples, "seed": plan.seed if plan.samples else None,
                "cases": len(rows), "ok": n_ok, "failed": len(rows) - n_ok,
                "columns": {n: m for n, m in COLUMNS},
                "case_overrides": [c.overrides for c in plan.cases],
                "mjtether": __version__, "mujoco": mujoco.__version__}
        (st.path / "sweep.json").write_text(json.dumps(meta, indent=2) + "\n")
        return st.commit()


def check_out(out, *, overwrite: bool, scenario) -> Path:
    """``outdir.check_target`` for a sweep, and ``--overwrite`` only replaces an earlier sweep."""
    from .outdir import OutputError, check_target

    try:
        target = check_target(out, overwrite=overwrite, protect=[scenario])
    except OutputError as exc:
        raise SweepError(str(exc)) from None
    if target.is_dir() and any(target.iterdir()):
        try:
            fmt = json.loads((target / "sweep.json").read_text()).get("format")
        except (OSError, ValueError, AttributeError):
            fmt = None
        if fmt != FORMAT:
            raise SweepError(f"results folder {str(out)!r} is an earlier mjtether result but not a sweep; "
                             "--overwrite only replaces an earlier sweep there; choose another --out")
    return target


# ------------------------------------------------------------------ the command


def require_pyarrow() -> None:
    try:
        import pyarrow  # noqa: F401
        import pyarrow.parquet  # noqa: F401
    except ImportError:
        raise SweepError("writing cases.parquet needs pyarrow, which is not installed: "
                         "pip install mjtether[sweep]") from None


def sweep(scenario, vary: list[str], out, *, sets=(), samples: int | None = None, seed: int = 0,
          jobs: int | None = None, ray: str | None = None, overwrite: bool = False, restart: bool = False,
          progress: bool = True, log=print) -> Path:
    """The ``mjtether sweep`` command from Python; returns the results folder. Raises
    SweepError, KeyboardInterrupt or SystemExit (SIGTERM) — the finished cases are kept."""
    if jobs is not None and jobs < 1:
        raise SweepError(f"--jobs {jobs}: must be at least 1")
    require_pyarrow()
    if ray is not None:
        _import_ray()
    varies = [parse_vary(v) for v in vary]
    if not varies:
        raise SweepError("give at least one --vary KEY=SPEC")
    plan = make_plan(scenario, varies, sets=sets, samples=samples, seed=seed)
    target = check_out(out, overwrite=overwrite, scenario=scenario)
    from .outdir import OutputError

    journal = Journal(target)
    done = journal.open(restart=restart)
    try:
        records = {}
        todo = []
        reused = 0
        by_key = {}
        for c in plan.cases:
            if c.sc is None:
                continue
            if c.key in done:
                records[c.index] = done[c.key]
                reused += 1
            elif c.key in by_key:  # the same scenario twice: run once
                by_key[c.key].append(c)
            else:
                by_key[c.key] = [c]
                todo.append(c)
        invalid = sum(1 for c in plan.cases if c.sc is None)
        # longest first (Scenario.estimate), so that no long case starts last
        todo.sort(key=lambda c: -c.sc.estimate()["wall_hours"])
        n = len(plan.cases)
        if ray is not None:
            how = "as Ray tasks" + (f" at {ray}" if ray else "")
        else:
            how = f"{jobs} at a time" if jobs and jobs > 1 else "in this process"
        log(f"mjtether sweep: {n} cases" + (f", {reused} finished earlier" if reused else "")
            + (f", {invalid} invalid" if invalid else "") + (f"; running {len(todo)} ({how})" if todo else ""))
        from tqdm import tqdm

        bar = tqdm(total=n, initial=n - len(todo) - sum(len(v) - 1 for v in by_key.values()), unit="case",
                   desc="mjtether sweep", leave=False, disable=not progress)
        failed = [0]

        def on_result(case, rec):
            journal.add(case, rec)
            for c in by_key[case.key]:
                records[c.index] = rec
            bar.update(len(by_key[case.key]))
            if rec.get("status") != "ok":
                failed[0] += 1
                bar.set_postfix(failed=failed[0])

        t0 = time.perf_counter()
        try:
            with terminate_as_exit():
                if todo and ray is not None:
                    run_ray(todo, ray or None, jobs, on_result)
                elif todo:
                    run_local(todo, jobs or 1, on_result)
        finally:
            bar.close()
        wall = time.perf_counter() - t0
        try:
            path = write_results(target, plan, records, overwrite=overwrite)
        except OutputError as exc:
            raise SweepError(f"{exc}; the finished cases are kept in {str(journal.dir)!r}", code=1) from None
    finally:
        journal.close()
    journal.remove()  # only once the results are in place
    names, rows = table(plan, records)
    bad = [r for r in rows if r[names.index("status")] != "ok"]
    log(f"{n} cases ({n - len(bad)} ok, {len(bad)} failed"
        + (f", {reused} from an earlier interrupted run" if reused else "") + f") in {wall:.1f} s; results in {path}/")
    for r in bad[:5]:
        log(f"  case {r[0]} failed: {r[names.index('error')]}")
    if len(bad) > 5:
        log(f"  ... and {len(bad) - 5} more (see cases.csv)")
    return path


def progress_folder(out) -> Path:
    """Where a sweep into ``out`` keeps its finished cases until it is complete."""
    return Journal(Path(os.path.abspath(os.fspath(out)))).dir


def cli(args) -> int:
    """``mjtether sweep`` (``args`` from the cli's parser)."""
    try:
        sweep(args.scenario, args.vary, args.out, sets=args.set, samples=args.samples, seed=args.seed,
              jobs=args.jobs, ray=args.ray, overwrite=args.overwrite, restart=args.restart)
    except SweepError as exc:
        print(f"mjtether sweep: {exc}", file=sys.stderr)
        return exc.code
    except (KeyboardInterrupt, SystemExit) as exc:
        code = 130 if isinstance(exc, KeyboardInterrupt) else (exc.code if isinstance(exc.code, int) else 1)
        kept = progress_folder(args.out)
        print("mjtether sweep: interrupted; " + (f"the finished cases are kept in {str(kept)!r}: rerun the same "
              "command to resume" if kept.is_dir() else "nothing was run"), file=sys.stderr)
        return code
    return 0
