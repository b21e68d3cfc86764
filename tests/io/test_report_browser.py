"""The HTML report in a real browser: Debian's chromium, headless, loading the page from file://
with the network switched off (the page's own CSP forbids every fetch, and chromium is given a
proxy that does not exist, so any request would fail and be logged). Checked: no console message
and no error on the page, WebGL drawn (SwiftShader, on the CPU), the frame counter advances when
played, screenshots of the 3-D view at two times differ, and the numbers each plot draws (the
page's ``#plot-data``) equal the results folder's, to float32 (the payload's stated rounding).

Skipped only when no chromium can be found (``MJTETHER_CHROMIUM``, ``chromium``,
``chromium-browser``, ``google-chrome``); CI installs Debian's ``chromium``."""

import html
import json
import os
import re
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

import mjtether
from mjtether.io import report_data, results
from mjtether.io.report import write_report
from mjtether.scenario import load_scenario
from mjtether.scenario.runner import run


def _chromium():
    for name in (os.environ.get("MJTETHER_CHROMIUM"), "chromium", "chromium-browser", "google-chrome"):
        if name and shutil.which(name):
            return shutil.which(name)
    return None


CHROMIUM = _chromium()
pytestmark = pytest.mark.skipif(CHROMIUM is None, reason="no chromium found (set MJTETHER_CHROMIUM or "
                                "apt-get install chromium): the report's browser test needs one")
FLAGS = ["--headless=new", "--no-sandbox", "--use-angle=swiftshader", "--enable-unsafe-swiftshader",
         "--no-first-run", "--no-default-browser-check", "--disable-extensions", "--disable-background-networking",
         "--proxy-server=127.0.0.1:9", "--enable-logging=stderr", "--v=0", "--window-size=1280,900",
         "--hide-scrollbars"]


def browse(page: Path, fragment: str, *, budget_ms: int = 2500, screenshot: Path | None = None,
           profile: Path) -> tuple[str, list[str]]:
    """(the DOM after ``budget_ms`` of virtual time, the console lines) of ``page#fragment``,
    and its screenshot into ``screenshot`` where given (one chromium start for both)."""
    args = [CHROMIUM, *FLAGS, f"--user-data-dir={profile}", f"--virtual-time-budget={budget_ms}", "--dump-dom"]
    args += [f"--screenshot={screenshot}"] if screenshot else []
    done = subprocess.run(args + [page.as_uri() + fragment], capture_output=True, text=True, timeout=60)
    console = [ln for ln in done.stderr.splitlines() if ":CONSOLE" in ln or "Refused" in ln]
    return done.stdout, console


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    """The built-in walker scenario for 4 s (9 samples, 0.5 s apart)."""
    sc = load_scenario(Path(mjtether.__file__).parent / "scenarios" / "default.toml",
                       overrides=["simulation.duration=4.0"])
    rows, history, info = run(sc)
    out = results.write(tmp_path_factory.mktemp("browser") / "run", sc, rows, history, info, plots=False)
    write_report(out)
    return out


@pytest.fixture(scope="module")
def at_1s(folder, tmp_path_factory):
    """(DOM, console lines, screenshot) of the page at #t=1."""
    tmp = tmp_path_factory.mktemp("chromium")
    dom, console = browse(folder / "report.html", "#t=1", screenshot=tmp / "t1.png", profile=tmp / "p")
    return dom, console, tmp / "t1.png"


def element(dom: str, id_: str) -> str:
    m = re.search(rf'<[^>]* id="{id_}"[^>]*>', dom)
    assert m, f"no #{id_} in the page"
    return m.group(0)


def test_loads_offline_and_plots_the_folders_numbers(folder, at_1s):
    """#t=1: the cursor at the sample at 1 s; each plot's numbers are the folder's (float32)."""
    dom, console, _ = at_1s
    assert console == []
    assert re.search(r'<pre id="errors" hidden="">\s*</pre>', dom), "the page reported errors"
    assert 'data-ready="1"' in dom and 'data-webgl="1"' in dom
    assert 'data-frame="2"' in element(dom, "frame")
    data = json.loads(html.unescape(re.search(r'id="plot-data">(.*?)</script>', dom, re.S).group(1)))
    ts = report_data.read_timeseries(folder / "timeseries.csv")
    f32 = lambda v: np.asarray(v, dtype=float).astype(np.float32)  # noqa: E731
    ends = data["end_tension"]["series"]
    assert np.array_equal(f32(ends["tether end A (robot)"]["y"]), ts["tow_tension_N"].astype(np.float32))
    assert np.array_equal(f32(ends["tether end B (ship)"]["y"]), ts["ship_tension_N"].astype(np.float32))
    assert np.array_equal(f32(ends["tether end A (robot)"]["x"]), ts["time_s"].astype(np.float32))
    assert np.array_equal(f32(data["payout"]["series"]["deployed length"]["y"]),
                          ts["deployed_length_m"].astype(np.float32))
    with np.load(folder / "lines.npz") as z:
        tension = z["linetether_tension"][2]
        nodes = z["linetether_nodes"][2]
    along = data["along"]
    assert along["frame"] == 2 and along["time_s"] == 1.0
    assert np.array_equal(f32(along["series"]["tether"]["y"]), tension.astype(np.float32))
    # the along-line x: arc length to each element's centre, from the nodes (float32 of ~260 m)
    seg = np.linalg.norm(np.diff(nodes, axis=0), axis=1)
    s = np.cumsum(seg) - seg / 2
    x = np.array([np.nan if v is None else v for v in along["series"]["tether"]["x"]], dtype=float)
    deployed = seg > 1e-9
    assert np.all(np.isnan(x[~deployed]))
    assert np.allclose(x[deployed], s[deployed], atol=1e-4, rtol=0)


def test_frame_counter_advances_when_played(folder, tmp_path):
    dom, console = browse(folder / "report.html", "#play", budget_ms=3000, profile=tmp_path / "p")
    assert console == []
    frame = int(re.search(r'data-frame="(\d+)"', element(dom, "frame")).group(1))
    assert frame >= 2  # (3 s of virtual time at 1x: the 0.5 s samples up to about t = 3 s)


def test_screenshots_at_two_times_differ(folder, at_1s, tmp_path):
    from PIL import Image, ImageChops

    dom, console = browse(folder / "report.html", "#t=3", screenshot=tmp_path / "t3.png", profile=tmp_path / "p")
    assert console == [] and 'data-frame="6"' in element(dom, "frame")
    view = (20, 110, 900, 550)  # (the 3-D view, left of its legend, above the plots)
    a, b = (Image.open(png).convert("RGB").crop(view) for png in (at_1s[2], tmp_path / "t3.png"))
    assert len(a.getcolors(maxcolors=1 << 20)) > 20, "the 3-D view is blank"
    assert ImageChops.difference(a, b).getbbox() is not None
