"""Parameter sweeps: one scenario run over a grid (or a random sample) of key values.

    mjtether sweep SCENARIO.toml --vary KEY=SPEC [--vary ...] [--samples K [--seed S]]
                   [--set KEY=VALUE ...] [--jobs N | --ray [ADDRESS]] --out DIR [--overwrite] [--restart]
                   [--keep-cases] [--report]

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

Running: each case is ``runner.run(sc, keep_nodes=False)`` (``keep_nodes=True`` with
``--keep-cases``: the recorded nodes do not change the run). ``--jobs 1`` (the default) runs them
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

* ``cases.csv``, and ``cases.parquet`` where pyarrow is installed: one row per case (``COLUMNS``
  lists the figures): ``case``
  (0-based), each varied input (named by its key path, plus ``_<unit>`` where the key does not
  already end in its unit: ``tether.length_m``, ``water.current.surface_speed_kn``), ``status``
  (ok / failed), ``error``, then the figures (empty / null where not available). The CSV holds
  floats at full precision (``repr``); the Parquet file (pyarrow) the same rows, typed.
* ``summary.png``: peak ship-end tension and length on the seabed at the end against the first
  varied key, coloured by the second; failed cases marked with a red x along the bottom.
* ``sweep.json``: the sweep (scenario file, ``--set``, ``--vary``, samples, seed, each case's
  overrides, versions, counts, ``keep_cases`` and ``case_folders``, the cases that have one);
  ``scenario.toml``: the scenario file as read;
* with ``--keep-cases`` (``keep_cases=True``): ``cases/<i>/`` (``i`` the ``case`` of
  ``cases.csv``) for each case that ran ok, its whole results folder as ``mjtether run --out``
  writes it (``io.results.write``; a network's ``network.run.write``: ``timeseries.csv``,
  ``lines.npz``, ``summary.json``, the plots, its own manifest), from the same run as its row
  (its figures are the row's, bit for bit). A failed case has none. Each is written by the
  process that runs the case (a worker process too) into the progress folder
  (``folders/<key>/``, staged and renamed complete), and put into ``DIR``'s staging folder
  (hard links, else copies) when the sweep is done, so ``DIR`` still appears complete or not at
  all, every file in its manifest. Not with ``--ray`` (refused: a cluster's nodes need not share
  this disk). A resumed case that an earlier run finished without its folder (a sweep without
  ``--keep-cases``) is run again for it (the same deterministic run: the same figures); a
  failed case is not. ``mjtether report DIR`` (``--report``) writes each case's ``report.html``
  too, and the sweep's table links each case number to ``cases/<i>/report.html``.

Parquet needs pyarrow, an optional dependency (``pip install mjtether[sweep]``, also in ``dev``):
it is about 170 MB installed, too much to impose on every user of ``mjtether run``. Without it
``mjtether sweep`` runs all the same and writes ``cases.csv`` only (``sweep.json``'s
``parquet`` says which); the CSV holds the same rows at full precision.

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

Networks. ``SCENARIO`` may be a network of lines instead (a TOML file with ``[[lines]]``, as in
``examples/networks/``, or a MoorDyn file that ``mjtether.io.moordyn.load_any`` reads as a
``Network``; ``plan.load_network``). Its keys are those ``--set`` takes on a network
(``mjtether.network.overrides``): ``simulation.KEY``, ``water.KEY``, ``line_types.NAME.KEY``,
``lines.NAME.KEY``, ``points.NAME.KEY`` (``position`` as ``[x, y, z]``), ``bodies.NAME.KEY``,
``vehicles.NAME.KEY``, ``walkers.NAME.KEY`` (``position`` as ``[x, y]``); an unknown key or
name, or a value not of the key's kind (a number, a whole number, two or three numbers), is refused before anything runs, and a value the network's own
checks refuse (a range, a line too short for its held ends) makes its case invalid, so refused
as for a scenario when it is so in every case. ``--set`` alone must give a valid network. Each
case is ``mjtether.network.run.simulate(net)`` (``execute.run_network_case``), its figures
(``plan.network_columns``): per line ``line<NAME>_peak_tension_N`` (largest tension at
either end over the samples), ``line<NAME>_final_A_tension_N`` and ``..._final_B_tension_N``,
then ``peak_tension_N`` (the largest over the lines), ``timestep_s``, ``diverged_at_s``,
``wall_s``, ``started_at``, ``initial_state`` (the run's note). The resume key is a SHA-256
of the case's ``mjtether.network.to_dict`` (JSON, sorted keys) and the versions;
``summary.png`` has one panel, the peak tension; the file's copy is ``network.toml`` (a MoorDyn
file's: ``network`` and its suffix) and ``sweep.json`` says ``"kind": "network"``.
``--jobs`` and ``--ray`` run network cases the same way.

The package, by idea:

* ``plan``: ``--vary`` specs (``Vary``, ``parse_vary``) and the checked cases (``Case``, ``Plan``,
  ``make_plan``; a network's: ``load_network``, ``make_network_plan``, ``network_columns``), with
  ``SweepError``;
* ``execute``: one case (``run_case``; a network's: ``run_network_case``) and running the cases
  on this process and a pool of worker processes (``run_local``) or as Ray tasks (``run_ray``);
* ``outputs``: the progress folder (``Journal``, ``progress_folder``) and the results folder
  (``table``, ``write_csv``, ``write_parquet``, ``plot``, ``write_results``, ``check_out``);
* this module: the command, ``sweep(...)`` and ``cli(args)``.

Imports: the scenario (``mjtether.scenario``: its config, loading and runner), the network
(``mjtether.network``: its config, overrides and run), ``mjtether.io``
(``outdir``, and ``results`` for a case's figures), ``simulation`` (``SimulationDiverged``) and
``units``; never the environments (``mjtether.envs``). Within the package ``plan`` imports none of
the others, ``outputs`` imports ``plan``, ``execute`` imports ``plan`` and ``outputs``. Every name
the flat ``mjtether/sweep.py`` module defined is still an attribute of ``mjtether.sweep``; a test
that replaces one (``run_case``) must replace it in the submodule that looks it up
(``mjtether.sweep.execute``).
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

from mjtether.io.outdir import terminate_as_exit
from mjtether.network import Network

from . import execute
from .execute import (
    _claim,
    _claim_and_run,
    _failed_figures,
    _import_ray,
    _iso,
    _result,
    _RunProbe,
    _stop_workers,
    _worker_init,
    _worker_start,
    run_case,
    run_local,
    run_network_case,
    run_ray,
)
from .outputs import (
    _TEXT_COLUMNS,
    COLUMNS,
    FORMAT,
    PROGRESS_FORMAT,
    Journal,
    _atomic_write,
    check_out,
    columns_of,
    have_pyarrow,
    plot,
    progress_folder,
    require_pyarrow,
    summary_figure,
    table,
    write_csv,
    write_parquet,
    write_results,
)
from .plan import (
    MAX_CASES,
    Case,
    Plan,
    SweepError,
    NetParam,
    Vary,
    _is_number,
    _parse_value,
    _refuse_always_invalid,
    _resolve,
    _show,
    _show_list,
    _split,
    _toml,
    load_network,
    make_network_plan,
    make_plan,
    network_columns,
    parse_vary,
)

__all__ = [
    "COLUMNS", "FORMAT", "MAX_CASES", "PROGRESS_FORMAT", "Case", "Journal", "NetParam", "Plan", "SweepError", "Vary",
    "check_out", "cli", "columns_of", "have_pyarrow", "load_network", "make_network_plan", "make_plan",
    "network_columns", "parse_vary", "plot", "progress_folder", "require_pyarrow", "run_case", "run_network_case",
    "summary_figure",
    "run_local", "run_ray", "sweep", "table", "write_csv", "write_parquet", "write_results",
    # the flat module's private helpers, still attributes here (tests and older code reach for them)
    "_TEXT_COLUMNS", "_RunProbe", "_atomic_write", "_claim", "_claim_and_run", "_failed_figures", "_import_ray",
    "_is_number", "_iso", "_parse_value", "_refuse_always_invalid", "_resolve", "_result", "_show",
    "_show_list", "_split", "_stop_workers", "_toml", "_worker_init", "_worker_start",
]


def __getattr__(name: str):
    """``_CLAIMS``, a worker's claim flags: set at run time in ``execute``, so read from there."""
    if name == "_CLAIMS":
        return execute._CLAIMS
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


# ------------------------------------------------------------------ the command


def sweep(scenario, vary: list[str], out, *, sets=(), samples: int | None = None, seed: int = 0,
          jobs: int | None = None, ray: str | None = None, overwrite: bool = False, restart: bool = False,
          keep_cases: bool = False, progress: bool = True, log=print) -> Path:
    """The ``mjtether sweep`` command from Python; returns the results folder. Raises
    SweepError, KeyboardInterrupt or SystemExit (SIGTERM) — the finished cases are kept.
    ``keep_cases``: ``--keep-cases`` (each case that ran ok keeps its results folder, ``cases/<i>/``)."""
    if jobs is not None and jobs < 1:
        raise SweepError(f"--jobs {jobs}: must be at least 1")
    if keep_cases and ray is not None:
        raise SweepError("--keep-cases is not available with --ray (a cluster's nodes need not share this disk); "
                         "use --jobs N, or leave out --keep-cases")
    if ray is not None:
        _import_ray()
    network = load_network(scenario)  # (None: a scenario)
    varies = [parse_vary(v, network[0] if network else None) for v in vary]
    if not varies:
        raise SweepError("give at least one --vary KEY=SPEC")
    if network is None:
        plan = make_plan(scenario, varies, sets=sets, samples=samples, seed=seed)
    else:
        plan = make_network_plan(scenario, *network, varies, sets=sets, samples=samples, seed=seed)
    target = check_out(out, overwrite=overwrite, scenario=scenario)
    from mjtether.io.outdir import OutputError

    journal = Journal(target)
    done = journal.open(restart=restart)
    try:
        records = {}
        todo = []
        reused = again = 0
        by_key = {}
        for c in plan.cases:
            if c.sc is None:
                continue
            if keep_cases and c.key in done and done[c.key].get("status") == "ok" and not journal.has_folder(c):
                del done[c.key]  # finished without its folder (by a sweep without --keep-cases): run again
                again += 1
            if c.key in done:
                records[c.index] = done[c.key]
                reused += 1
            elif c.key in by_key:  # the same scenario twice: run once
                by_key[c.key].append(c)
            else:
                by_key[c.key] = [c]
                todo.append(c)
        invalid = sum(1 for c in plan.cases if c.sc is None)
        # longest first (Scenario.estimate; a network's _cost), so that no long case starts last
        todo.sort(key=lambda c: -_cost(c.sc))
        n = len(plan.cases)
        if ray is not None:
            how = "as Ray tasks" + (f" at {ray}" if ray else "")
        else:
            how = f"{jobs} at a time" if jobs and jobs > 1 else "in this process"
        log(f"mjtether sweep: {n} cases" + (f", {reused} finished earlier" if reused else "")
            + (f", {again} finished earlier without their folder (run again for --keep-cases)" if again else "")
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
                    run_local(todo, jobs or 1, on_result, journal.folder if keep_cases else None)
        except OutputError as exc:  # a case's results folder could not be written (a full disk)
            raise SweepError(f"{exc}; the finished cases are kept in {str(journal.dir)!r}", code=1) from None
        finally:
            bar.close()
        wall = time.perf_counter() - t0
        folders = None
        if keep_cases:
            folders = {c.index: journal.folder(c) for c in plan.cases
                       if c.sc is not None and (records.get(c.index) or {}).get("status") == "ok"
                       and journal.has_folder(c)}
        try:
            path = write_results(target, plan, records, overwrite=overwrite, folders=folders)
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


def _cost(sc) -> float:
    """A case's expected run time, for their order only: ``Scenario.estimate``'s hours; for a
    network, its simulated time times its segments over its step (an unknown step: 1 ms), in
    no unit (a network sweep's cases are all networks)."""
    if isinstance(sc, Network):
        return (sc.duration + sc.settle) * sum(ln.segments for ln in sc.lines) / (sc.timestep or 1e-3)
    return sc.estimate()["wall_hours"]


def cli(args) -> int:
    """``mjtether sweep`` (``args`` from the cli's parser)."""
    try:
        sweep(args.scenario, args.vary, args.out, sets=args.set, samples=args.samples, seed=args.seed,
              jobs=args.jobs, ray=args.ray, overwrite=args.overwrite, restart=args.restart,
              keep_cases=getattr(args, "keep_cases", False))
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
