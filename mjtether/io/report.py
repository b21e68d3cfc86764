"""``mjtether report DIR``: one self-contained HTML file of a run that opens anywhere from disk.

``write_report(folder)`` writes ``folder/report.html`` for a results folder of ``mjtether run``
(a scenario's or a network's: ``timeseries.csv``, ``lines.npz``, ``summary.json``) or of
``mjtether sweep`` (``sweep.json``, ``cases.csv``). The page needs no network: the 3-D library
(three.js 0.170.0, MIT, ``report_page/vendor/``) and the run's data (``report_data``: float32,
gzip, base64) are inlined, decoded in the page (``DecompressionStream``), and a
Content-Security-Policy forbids every fetch. It shows a 3-D replay of every line coloured by
tension, the points, bodies, ship and robot as markers at their positions, the seabed and the sea
surface (moving where the run had waves), with play, pause, scrub and speed; and a time cursor
tied to plots of end tensions (with the rated-load band, where the rating is within
``report_data.RATED_IN_VIEW`` times the run's largest tension), tension along each line at the cursor,
the touchdown and the payout. Long runs are shown at every k-th sample (``report_data.MAX_FRAME_BYTES``;
the page says so). A sweep's page is a table of its cases, with links to each case's report where
a case has a results folder of its own.

The file is written beside its target and renamed into place (never half written), added to the
folder's ``mjtether-manifest.json`` (so that ``--overwrite`` still recognises the folder as an
mjtether result), and an existing ``report.html`` is replaced only if an mjtether report wrote it.

Hooks for tests and links: ``report.html#play`` starts playing, ``#t=3`` (s) or ``#frame=5`` set the
cursor (``#t=3&play`` both); ``#frame`` shows the frame (``data-frame``: 0-based index of the
frame shown); ``#plot-data`` (JSON) holds the numbers each plot draws, in SI units, as given to
the drawing (the axes may show kN); ``#errors`` lists any error the page met.
"""

from __future__ import annotations

import base64
import csv
import gzip
import hashlib
import html
import json
import os
import re
import tempfile
from importlib import resources
from pathlib import Path

from mjtether.files.outdir import MANIFEST, MANIFEST_FORMAT
from mjtether.files.results_folder import LINES, SUMMARY, TIMESERIES

from . import report_data
from .report_data import MAX_FRAME_BYTES, ReportError, collect, encode

__all__ = ["REPORT", "ReportError", "write_report", "result_kind"]

REPORT = "report.html"
GENERATOR = "mjtether report"
"""The page's ``<meta name="generator">``: how an existing report.html is known to be ours."""
_SWEEP_FORMAT = "mjtether-sweep/1"


def result_kind(folder) -> str:
    """``"scenario"``, ``"network"`` or ``"sweep"``: the kind of results ``folder`` holds; raises
    ReportError naming the path and what is missing where it is not an mjtether result."""
    d = Path(folder)
    if not d.is_dir():
        raise ReportError(f"{str(folder)!r} is not a folder: give the results folder of mjtether run or sweep")
    if (d / "sweep.json").is_file():
        try:
            fmt = json.loads((d / "sweep.json").read_text()).get("format")
        except (OSError, ValueError, AttributeError):
            fmt = None
        if fmt != _SWEEP_FORMAT:
            raise ReportError(f"{str(folder)!r}: sweep.json is not an mjtether sweep's (format {_SWEEP_FORMAT!r})")
        if not (d / "cases.csv").is_file():
            raise ReportError(f"{str(folder)!r} is not a complete sweep result: no cases.csv")
        return "sweep"
    missing = [n for n in (SUMMARY, TIMESERIES, LINES) if not (d / n).is_file()]
    if missing:
        raise ReportError(f"{str(folder)!r} is not an mjtether results folder: no {', no '.join(missing)} "
                          "(give the folder mjtether run or mjtether sweep wrote)")
    try:
        kind = json.loads((d / SUMMARY).read_text()).get("kind", "scenario")
    except (OSError, ValueError, AttributeError):
        raise ReportError(f"{str(folder)!r}: {SUMMARY} is not valid JSON") from None
    if kind not in ("scenario", "network"):
        raise ReportError(f"{str(folder)!r}: {SUMMARY} has kind {kind!r}; a report needs 'scenario' or 'network'")
    return kind


def write_report(folder, out=None, *, max_frame_bytes: int = MAX_FRAME_BYTES) -> Path:
    """Write the HTML report of the results ``folder``; returns its path. ``out``: the file
    (default ``folder/report.html``, then listed in the folder's manifest). Raises ReportError
    for a folder that is not an mjtether result or an ``out`` that is a file mjtether did not write."""
    d = Path(folder)
    kind = result_kind(d)
    target = Path(os.path.abspath(d / REPORT if out is None else out))
    _refuse_foreign(target)
    if kind == "sweep":
        page = _sweep_page(d, max_frame_bytes)
    else:
        try:
            meta, arrays = collect(d, max_frame_bytes)
        except (KeyError, OSError, ValueError) as exc:
            if isinstance(exc, ReportError):
                raise
            raise ReportError(f"{str(folder)!r}: cannot read its results ({type(exc).__name__}: {exc})") from None
        page = run_page(meta, arrays)
    _atomic_write(target, page)
    _list_in_manifests(target)
    return target


# ------------------------------------------------------------------ the pages


def _asset(name: str) -> str:
    return (resources.files("mjtether.io") / "report_page" / name).read_text(encoding="utf-8")


def _gz64(text: str) -> str:
    return base64.b64encode(gzip.compress(text.encode(), compresslevel=9, mtime=0)).decode("ascii")


def _fill(template: str, values: dict) -> str:
    """``template`` with every ``{{KEY}}`` replaced by ``values[KEY]``, in one pass (what is put in
    is not searched again); a key without a value, or a value without its key, is an error."""
    missing = set(values) - set(re.findall(r"\{\{([A-Z]+)\}\}", template))
    if missing:
        raise RuntimeError(f"report template: no {{{{{sorted(missing)[0]}}}}}")
    return re.sub(r"\{\{([A-Z]+)\}\}", lambda m: values[m.group(1)], template)


def run_page(meta: dict, arrays: dict) -> str:
    """The HTML of a scenario's or network's report from ``report_data.collect``'s (meta, arrays)."""
    return _fill(_asset("run.html"), {
        "GENERATOR": GENERATOR,
        "TITLE": html.escape(meta["title"]),
        "CSS": _asset("report.css"),
        "THREE": _gz64(_asset("vendor/three.module.min.js")),
        "ORBIT": _gz64(_asset("vendor/OrbitControls.js")),
        "PAYLOAD": encode(meta, arrays),
        "APP": _asset("report.js"),
    })


def _case_folder(d: Path, index: int) -> Path | None:
    """A sweep case's own results folder, where the sweep kept one (``case<i>``, ``case_<i>`` or
    ``cases/<i>`` holding a scenario or network result), else None."""
    for name in (f"case{index}", f"case_{index}", f"cases/{index}"):
        p = d / name
        if (p / SUMMARY).is_file() and (p / LINES).is_file():
            return p
    return None


def _sweep_page(d: Path, max_frame_bytes: int) -> str:
    sweep = json.loads((d / "sweep.json").read_text())
    with open(d / "cases.csv", newline="") as fh:
        rows = list(csv.reader(fh))
    names, body = rows[0], rows[1:]
    described = sweep.get("columns") or {}
    links = {}
    status_col = names.index("status") if "status" in names else None
    for r in body:
        ok = status_col is None or (len(r) > status_col and r[status_col] == "ok")
        case = _case_folder(d, int(r[0])) if ok and r and r[0].isdigit() else None
        if case is not None:
            write_report(case, max_frame_bytes=max_frame_bytes)
            _relist(d, case / MANIFEST)
            links[r[0]] = (case / REPORT).relative_to(d).as_posix()
    head = "".join(f'<th title="{html.escape(described.get(n, n))}">{html.escape(n)}</th>' for n in names)
    lines = []
    for r in body:
        cells = []
        for j, v in enumerate(r):
            text = html.escape(_short(v))
            if j == 0 and r[0] in links:
                text = f'<a href="{html.escape(links[r[0]])}" title="case {text}\'s own report">{text}</a>'
            cls = f' class="{html.escape(v)}"' if j == status_col else ""
            cells.append(f"<td{cls}>{text}</td>")
        lines.append("<tr>" + "".join(cells) + "</tr>")
    png = d / "summary.png"
    image = (f'<img alt="the sweep\'s summary plot" src="data:image/png;base64,'
             f'{base64.b64encode(png.read_bytes()).decode()}">' if png.is_file() else "")
    data = json.dumps({"columns": names, "rows": body, "links": links}).replace("</", "<\\/")
    varied = ", ".join(v.get("key", "") for v in sweep.get("vary") or [])
    return _fill(_asset("sweep.html"), {
        "GENERATOR": GENERATOR,
        "TITLE": html.escape(f"sweep of {sweep.get('scenario_file') or 'a scenario'}"),
        "CSS": _asset("report.css"),
        "INTRO": html.escape(f"{sweep.get('cases', len(body))} cases ({sweep.get('ok', '?')} ok, "
                             f"{sweep.get('failed', '?')} failed), varying {varied or 'nothing'}"
                             + (f"; set: {', '.join(sweep['set'])}" if sweep.get("set") else "")),
        "HEAD": head, "ROWS": "\n".join(lines), "IMAGE": image, "DATA": data,
        "NOTE": _sweep_note(sweep, links),
    })


def _sweep_note(sweep: dict, links: dict) -> str:
    """What the page says of the per-case reports: where the links are, or why there are none."""
    if links:
        return (f"The number of each case that ran ok links to its own report (cases/&lt;case&gt;/{REPORT}); "
                "a failed case has none: its status and error say why.")
    if sweep.get("keep_cases"):
        return "No case ran ok, so no case has a results folder or a report of its own."
    return ("The sweep kept no results folder per case, so there is no per-case report: run it with "
            "<code>--keep-cases</code> (<code>sweep(..., keep_cases=True)</code> from Python) for a link from "
            "each case to its own report.")


def _relist(root: Path, path: Path) -> None:
    """Refresh ``path``'s size and SHA-256 in ``root``'s manifest where it lists it (a case's own
    manifest, which its report has just changed, in the sweep's manifest)."""
    m = root / MANIFEST
    try:
        data = json.loads(m.read_text())
    except (OSError, ValueError):
        return
    rel = path.relative_to(root).as_posix()
    if m.is_symlink() or not isinstance(data, dict) or data.get("format") != MANIFEST_FORMAT \
            or not isinstance(data.get("files"), dict) or rel not in data["files"] or not path.is_file():
        return
    data["files"][rel] = {"size": path.stat().st_size, "sha256": hashlib.sha256(path.read_bytes()).hexdigest()}
    _atomic_write(m, json.dumps(data, indent=2) + "\n")


def _short(v: str) -> str:
    """A table cell: a long float's text to 6 significant figures (the CSV keeps them all)."""
    try:
        f = float(v)
    except ValueError:
        return v
    return v if v.lstrip("-").isdigit() or len(v) <= 10 else f"{f:.6g}"


# ------------------------------------------------------------------ writing, and the manifest


def _is_ours(path: Path) -> bool:
    try:
        with open(path, encoding="utf-8", errors="replace") as fh:
            head = fh.read(4096)
    except OSError:
        return False
    return f'<meta name="generator" content="{GENERATOR}">' in head


def _refuse_foreign(target: Path) -> None:
    if os.path.islink(target) or (os.path.lexists(target) and not target.is_file()):
        raise ReportError(f"{str(target)!r} exists and is not a plain file; choose another output")
    if target.is_file() and not _is_ours(target):
        raise ReportError(f"{str(target)!r} exists and was not written by {GENERATOR}; move it away "
                          "or choose another output")


def _atomic_write(target: Path, text: str) -> None:
    """``text`` into ``target`` by a temporary file beside it, renamed into place; readable as
    any new file of the user's is (the umask's mode, not mkstemp's owner-only 0600: a report is
    made to be passed on)."""
    fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".partial", dir=target.parent)
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as fh:
            fh.write(text)
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)
        os.replace(tmp, target)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


def _list_in_manifests(path: Path) -> None:
    """Add ``path`` (size, SHA-256) to the manifest of every mjtether results folder holding it
    (its own folder's, and a sweep's above), so that ``--overwrite`` still replaces the folder."""
    h = hashlib.sha256(path.read_bytes()).hexdigest()
    entry = {"size": path.stat().st_size, "sha256": h}
    for root in [path.parent, *path.parent.parents][:3]:
        m = root / MANIFEST
        if m.is_symlink() or not m.is_file():
            continue
        try:
            data = json.loads(m.read_text())
        except (OSError, ValueError):
            continue
        if not isinstance(data, dict) or data.get("format") != MANIFEST_FORMAT or not isinstance(data.get("files"), dict):
            continue
        data["files"][path.relative_to(root).as_posix()] = entry
        data["files"] = dict(sorted(data["files"].items()))
        _atomic_write(m, json.dumps(data, indent=2) + "\n")


decode = report_data.decode
