"""What a sweep writes: the progress folder of finished cases (``Journal``) and the results
folder (``cases.csv``, ``cases.parquet``, ``summary.png``, ``sweep.json``, ``write_results``)."""

from __future__ import annotations

import csv
import errno
import json
import os
import shutil
from pathlib import Path

from .plan import Case, Plan, SweepError, _show, _toml

FORMAT = "mjtether-sweep/1"
"""``format`` of ``sweep.json`` in a sweep results folder (what ``--overwrite`` may replace)."""
PROGRESS_FORMAT = "mjtether-sweep-progress/1"

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


def columns_of(plan: Plan) -> list[tuple[str, str]]:
    """The figures of ``plan``'s cases: ``COLUMNS``, or its network's (``network_columns``)."""
    return COLUMNS if plan.columns is None else plan.columns


# ------------------------------------------------------------------ progress (resume)


class Journal:
    """The progress folder of a sweep into ``target`` (see the package docstring)."""

    MARK = "progress.json"
    FOLDERS = "folders"
    """Beside ``cases/``: ``folders/<key>/``, the results folder of each finished case (``--keep-cases``)."""

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
        for sub in ("cases", self.FOLDERS):
            if restart and (d / sub).is_dir():
                shutil.rmtree(d / sub)
            (d / sub).mkdir(exist_ok=True)
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

    def folder(self, case: Case) -> Path:
        """Where the results folder of ``case`` is written (``--keep-cases``; by ``results.write``,
        staged beside it, so that a folder there is complete)."""
        return self.dir / self.FOLDERS / case.key

    def has_folder(self, case: Case) -> bool:
        """Whether ``case``'s results folder is there, complete (its manifest is written last)."""
        from mjtether.files.outdir import MANIFEST

        p = self.folder(case)
        return not p.is_symlink() and (p / MANIFEST).is_file()

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


def progress_folder(out) -> Path:
    """Where a sweep into ``out`` keeps its finished cases until it is complete."""
    return Journal(Path(os.path.abspath(os.fspath(out)))).dir


# ------------------------------------------------------------------ results


def table(plan: Plan, records: dict) -> tuple[list[str], list[list]]:
    """(column names, rows) of the results: one row per case, ``records`` {case index: record}."""
    figures = [n for n, _ in columns_of(plan)]
    names = ["case"] + [v.column for v in plan.varies] + ["status", "error"] + figures
    rows = []
    for c in plan.cases:
        r = records.get(c.index) or {"status": "failed", "error": c.error or "not run"}
        rows.append([c.index, *c.values, r.get("status"), r.get("error", "")] + [r.get(n) for n in figures])
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
    types += [pa.string() if n in _TEXT_COLUMNS else pa.float64() for n, _ in columns_of(plan)]
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

    fig = summary_figure(plan, names, rows)
    fig.savefig(path, dpi=110)
    plt.close(fig)


def summary_figure(plan: Plan, names, rows):
    """The figure of ``plot``: a panel per figure (peak ship-end tension, length on the seabed;
    a network's: its peak line tension, the largest over its lines),
    the ok cases as points, each failed case a red x at its own x along the panel's bottom (both
    panels' x ranges take in every case, failed or not, so no x falls outside its panel)."""
    import matplotlib
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
    if plan.kind == "network":
        panels = [("peak_tension_N", "peak line tension, largest over the lines (N)")]
    fig, axes = plt.subplots(1, len(panels), figsize=(5.5 * len(panels), 4.5), layout="constrained", squeeze=False)
    axes = axes[0]
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
        lo, hi = min(xpos), max(xpos)
        pad = 0.05 * (hi - lo) if hi > lo else max(0.5, 0.05 * abs(lo))
        ax.set_xlim(lo - pad, hi + pad)  # (the failed cases' x (axes y) are not in the data limits)
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
    return fig


def write_results(target: Path, plan: Plan, records: dict, *, overwrite: bool, folders: dict | None = None) -> Path:
    """Stage and commit the results folder (``outdir.Staging``). ``folders`` (``--keep-cases``):
    {case index: its results folder in the progress folder}, each put in as ``cases/<index>/``
    (hard links where the file system has them, else copies: the progress folder keeps its own
    until the results are in place); None: the sweep kept none."""
    import mujoco

    from mjtether import __version__
    from mjtether.io.outdir import Staging

    names, rows = table(plan, records)
    with Staging(target, overwrite=overwrite) as st:
        write_csv(st.path / "cases.csv", names, rows)
        parquet = have_pyarrow()
        if parquet:
            write_parquet(st.path / "cases.parquet", plan, names, rows)
        plot(st.path / "summary.png", plan, names, rows)
        for i, src in sorted((folders or {}).items()):
            _link_tree(Path(src), st.path / "cases" / str(i))
        (st.path / plan.copy_name).write_text(plan.text)
        n_ok = sum(1 for r in rows if r[names.index("status")] == "ok")
        meta = {"format": FORMAT, **({"kind": "network", "copy": plan.copy_name} if plan.kind == "network" else {}),
                "scenario_file": plan.scenario, "set": plan.sets,
                "vary": [{"key": v.key, "spec": v.spec, "column": v.column} for v in plan.varies],
                "samples": plan.samples, "seed": plan.seed if plan.samples else None,
                "parquet": parquet, "cases": len(rows), "ok": n_ok, "failed": len(rows) - n_ok,
                "keep_cases": folders is not None, "case_folders": sorted(folders or {}),
                "columns": {n: m for n, m in columns_of(plan)},
                "case_overrides": [c.overrides for c in plan.cases],
                "mjtether": __version__, "mujoco": mujoco.__version__}
        (st.path / "sweep.json").write_text(json.dumps(meta, indent=2) + "\n")
        return st.commit()


def _link_tree(src: Path, dst: Path) -> None:
    """``src``'s files at ``dst``: hard links (no copy of the data), or copies where linking fails."""

    def link(a, b):
        try:
            os.link(a, b)
        except OSError:
            shutil.copy2(a, b)

    shutil.copytree(src, dst, copy_function=link, symlinks=True)


def check_out(out, *, overwrite: bool, scenario) -> Path:
    """``outdir.check_target`` for a sweep, and ``--overwrite`` only replaces an earlier sweep."""
    from mjtether.io.outdir import OutputError, check_target

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


def have_pyarrow() -> bool:
    """Whether pyarrow is installed: ``cases.parquet`` is written then (``cases.csv`` always)."""
    try:
        import pyarrow  # noqa: F401
        import pyarrow.parquet  # noqa: F401
    except ImportError:
        return False
    return True


def require_pyarrow() -> None:
    """Raise SweepError unless pyarrow is installed (a sweep no longer needs it: see
    ``have_pyarrow``)."""
    try:
        import pyarrow  # noqa: F401
        import pyarrow.parquet  # noqa: F401
    except ImportError:
        raise SweepError("writing cases.parquet needs pyarrow, which is not installed: "
                         "pip install mjtether[sweep]") from None
