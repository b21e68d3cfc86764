"""The HTML report (mjtether.io.report): the page's inlined payload, decoded here in Python, holds
the results folder's own numbers (float32 of its float64: the payload's stated rounding, exact
equality with ``np.float32`` of the folder's values); the folder stays an mjtether result; what
is not one is refused; networks and sweeps have reports too; the default walker run's page stays
under 10 MB."""

import hashlib
import json
import math
import os
import re
import stat
from pathlib import Path

import numpy as np
import pytest

import mjtether
from mjtether.files import outdir
from mjtether.io import report, report_data, results
from mjtether.io.report import ReportError, write_report
from mjtether.io.report_data import decode, frame_indices
from mjtether.scenario import load_scenario
from mjtether.scenario.runner import run

DEFAULT = Path(mjtether.__file__).parent / "scenarios" / "default.toml"
"""The built-in scenario (``mjtether run`` without a file)."""
WAVES = """
[simulation]
duration = 1.0
output_interval = 0.25
[water]
depth = 50.0
[robot]
type = "anchor"
position = [30.0, 0.0, -50.0]
[tether]
length = 70.0
segments = 10
rated_load = 800.0
[waves]
type = "regular"
height = 2.0
period = 6.0
heading_deg = 30.0
phase_deg = 40.0
ramp_periods = 0.0
"""


def _write(sc, out, **kw):
    rows, history, info = run(sc)
    return results.write(out, sc, rows, history, info, plots=False, **kw)


@pytest.fixture(scope="module")
def walker(tmp_path_factory):
    """The default walker scenario at its full length (60 s: 121 samples, 2-3 s to run)."""
    folder = _write(load_scenario(DEFAULT), tmp_path_factory.mktemp("walker") / "run")
    return folder, write_report(folder)


@pytest.fixture(scope="module")
def waves(tmp_path_factory):
    folder = _write(load_scenario(text=WAVES), tmp_path_factory.mktemp("waves") / "run")
    return folder, write_report(folder)


def payload(page):
    text = page.read_text()
    return decode(re.search(r'<script type="application/octet-stream" id="payload">([^<]*)</script>', text).group(1))


def csv_columns(folder):
    data = report_data.read_timeseries(folder / "timeseries.csv")
    return data


def test_payload_is_the_folder(walker):
    """Every frame kept (121 samples fit the budget); nodes, tensions, times and the plotted
    time-series columns equal the folder's, rounded to float32 (exact equality)."""
    folder, page = walker
    meta, a = payload(page)
    with np.load(folder / "lines.npz") as z:
        assert meta["frames"] == {"kept": len(z["time_s"]), "samples": len(z["time_s"]), "stride": 1}
        assert np.array_equal(a["t"], z["time_s"].astype(np.float32))
        assert np.array_equal(a["line/tether/nodes"], z["linetether_nodes"].astype(np.float32))
        assert np.array_equal(a["line/tether/tension"], z["linetether_tension"].astype(np.float32))
    ts = csv_columns(folder)
    for col in ("time_s", "tow_tension_N", "ship_tension_N", "deployed_length_m"):
        assert np.array_equal(a[f"ts/{col}"], ts[col].astype(np.float32)), col
    labels = [s["array"] for s in meta["plots"]["end_tension"]]
    assert labels == ["ts/tow_tension_N", "ts/ship_tension_N"]  # end A is the robot, B the ship
    assert meta["rated_load_N"] is None  # (the default tether has no rated load: the run's own range)
    assert meta["tension_scale"]["max_N"] == pytest.approx(float(np.max(a["line/tether/tension"])), rel=1e-6)
    assert {m["kind"] for m in meta["markers"]} == {"ship", "walker"}


def test_touchdown_against_the_runs_own_seabed_length(walker):
    """Touchdown: arc length from the ship (end B) to the first element lying on the seabed (both
    nodes within one diameter, 0.025 m, of z = -200 m). Checked two ways: the elements it calls
    lying, times their rest length 260/100 = 2.6 m, are the run's own ``length_on_seabed``
    (readouts; the CSV's 9 figures: 1e-6 m); and the arc, summed here in a plain loop over the
    stretched ``element_length`` of lines.npz, is the page's (float32 of ~200 m: 1e-4 m)."""
    folder, page = walker
    meta, a = payload(page)
    ts = csv_columns(folder)
    td = a["td/tether"]
    with np.load(folder / "lines.npz") as z:
        nodes, lengths = z["linetether_nodes"][:, ::-1], z["linetether_element_length"][:, ::-1]
    assert np.array_equal(a["td_t"], ts["time_s"].astype(np.float32))
    touched = 0
    for k in range(len(nodes)):
        low = [p[2] < -200.0 + 0.025 for p in nodes[k]]
        lying = [low[j] and low[j + 1] for j in range(len(low) - 1)]
        assert sum(lying) * 2.6 == pytest.approx(ts["length_on_seabed_m"][k], abs=1e-6)
        if not any(lying):
            assert math.isnan(td[k])
            continue
        touched += 1
        arc = 0.0
        for j in range(lying.index(True)):
            arc += lengths[k, j]
        assert td[k] == pytest.approx(arc, abs=1e-4)
    assert touched > 100


def test_manifest_lists_the_report_and_overwrite_still_works(walker):
    folder, page = walker
    files = json.loads((folder / outdir.MANIFEST).read_text())["files"]
    assert files["report.html"] == {"size": page.stat().st_size,
                                    "sha256": hashlib.sha256(page.read_bytes()).hexdigest()}
    assert outdir.foreign_content(folder) is None
    assert outdir.check_target(folder, overwrite=True) == folder


def test_the_page_is_as_readable_as_any_new_file(walker):
    """A report is made to be passed on: its mode is what the umask gives a new file (0666 less
    the umask), not the owner-only 0600 of the temporary file it was written through."""
    folder, page = walker
    umask = os.umask(0)
    os.umask(umask)
    assert stat.S_IMODE(page.stat().st_mode) == 0o666 & ~umask


def test_replaces_only_its_own_page(walker, tmp_path):
    folder, page = walker
    assert write_report(folder) == page  # (ours: replaced)
    mine = tmp_path / "report.html"
    mine.write_text("<html>my notes</html>")
    with pytest.raises(ReportError, match="not written by mjtether report"):
        write_report(folder, out=mine)
    assert mine.read_text() == "<html>my notes</html>"
    other = write_report(folder, out=tmp_path / "elsewhere.html")
    assert other.is_file() and "report.html" in json.loads((folder / outdir.MANIFEST).read_text())["files"]
    assert not list(tmp_path.glob(".*partial"))


def test_refuses_what_is_not_a_result(tmp_path):
    (tmp_path / "summary.json").write_text("{}")
    with pytest.raises(ReportError, match=r"not an mjtether results folder: no timeseries.csv, no lines.npz") as e:
        write_report(tmp_path)
    assert str(tmp_path) in str(e.value)
    with pytest.raises(ReportError, match="is not a folder"):
        write_report(tmp_path / "summary.json")
    assert not (tmp_path / "report.html").exists()
    assert issubclass(ReportError, ValueError)


def test_no_half_written_page(walker, monkeypatch):
    """A failure while writing leaves the earlier page and no temporary file."""
    folder, page = walker
    before = page.read_bytes()

    def broken(*_):
        raise OSError("disk full")
    monkeypatch.setattr(report, "_list_in_manifests", broken)
    monkeypatch.setattr(report.os, "replace", lambda *a: (_ for _ in ()).throw(OSError("disk full")))
    with pytest.raises(OSError):
        write_report(folder)
    assert page.read_bytes() == before
    assert not [p for p in folder.iterdir() if p.name.startswith(".")]


def test_offline_page(walker):
    """One file: the library and data inlined, a CSP that forbids every fetch, no URL to load."""
    _, page = walker
    text = page.read_text()
    csp = re.search(r'http-equiv="Content-Security-Policy" content="([^"]*)"', text).group(1)
    assert "default-src 'none'" in csp and "connect-src 'none'" in csp
    assert not re.search(r'(src|href)="(https?:|//)', text)
    assert "<script src" not in text


def test_default_walker_page_under_10_MB(walker):
    """The default run (60 s, 121 samples, 155 elements allocated) is far under 10 MB; a run
    too long for the budget keeps every k-th frame."""
    _, page = walker
    assert page.stat().st_size < 10e6


def test_frame_indices():
    assert list(frame_indices(5, 10, 1000)) == [0, 1, 2, 3, 4]
    idx = frame_indices(1001, 1000, 100_000)  # 1001 * 1000 bytes over a 100 kB budget: every 11th
    assert idx[1] - idx[0] == math.ceil(1001 * 1000 / 100_000) and idx[-1] == 1000
    assert (len(idx) - 1) * 1000 <= 100_000
    assert list(frame_indices(1, 10**9, 10)) == [0]


def test_decimated_page_keeps_every_kth_frame(walker, tmp_path):
    """A budget of ~30 frames: every k-th sample of lines.npz, the last one too, and the page says so."""
    folder, _ = walker
    with np.load(folder / "lines.npz") as z:
        nodes, t = z["linetether_nodes"], z["time_s"]
    per = nodes[0].size * 4 + 2 * nodes.shape[1] * 4
    page = write_report(folder, out=tmp_path / "small.html", max_frame_bytes=30 * per)
    meta, a = payload(page)
    k = meta["frames"]["stride"]
    assert k == math.ceil(len(t) / 30)
    expect = list(range(0, len(t), k)) + ([len(t) - 1] if (len(t) - 1) % k else [])
    assert np.array_equal(a["t"], t[expect].astype(np.float32))
    assert np.array_equal(a["line/tether/nodes"], nodes[expect].astype(np.float32))
    assert len(a["ts/time_s"]) == len(t)  # (the time plots keep every row)


def test_waves_rated_load(waves):
    """The sea surface of a regular wave against Airy's eta = H/2 cos(k(x cos b + y sin b) - w t + p),
    k from w^2 = g k tanh(k h) solved here (float32 of ~1 m: 1e-5 m). This short line's tension
    peaks at about 10 N under its 800 N rating: more than ``RATED_IN_VIEW`` (2) times off, so the
    run's own largest tension sets the colour scale and the rating is named, not drawn."""
    folder, page = waves
    meta, a = payload(page)
    peak = float(np.max(a["line/tether/tension"]))
    assert meta["rated_load_N"] == 800.0 and 2.0 * peak < 800.0
    assert meta["tension_scale"]["max_N"] == pytest.approx(peak, rel=1e-6) and meta["rated_band_N"] is None
    assert meta["rated_note"].startswith("rated load 800 N, ") and f"{800.0 / peak:.0f}x" in meta["rated_note"]
    eta = a["surface/eta"]
    n = meta["surface"]["grid"]
    x0, x1, y0, y1 = meta["surface"]["box"]
    gx, gy = np.meshgrid(np.linspace(x0, x1, n), np.linspace(y0, y1, n))
    w, h, g = 2 * math.pi / 6.0, 50.0, 9.81
    k = w * w / g
    for _ in range(200):
        k = w * w / (g * math.tanh(k * h))
    b, p = math.radians(30.0), math.radians(40.0)
    for f, t in enumerate(a["t"]):
        expect = 1.0 * np.cos(k * (gx * math.cos(b) + gy * math.sin(b)) - w * float(t) + p)
        assert np.max(np.abs(eta[f] - expect)) < 1e-5
    assert eta.shape[0] == len(a["t"]) > 2


@pytest.fixture(scope="module")
def network(tmp_path_factory):
    from mjtether.io.moordyn import load_any
    from mjtether.network import run as network_run
    net = load_any("examples/networks/walker_clump_bridle.toml",
                   overrides=["simulation.duration=1.0", "simulation.settle=0.5"])
    out = tmp_path_factory.mktemp("net") / "run"
    network_run.run_to(net, out, plots=False)
    return out, write_report(out)


def test_network_report(network):
    """Every line's nodes and tensions, and each line end's tension over time, as in the folder."""
    folder, page = network
    meta, a = payload(page)
    names = [ln["name"] for ln in meta["lines"]]
    assert names == ["lead", "tail", "pendant"]
    with np.load(folder / "lines.npz") as z:
        for n in names:
            assert np.array_equal(a[f"line/{n}/nodes"], z[f"line{n}_nodes"].astype(np.float32))
            assert np.array_equal(a[f"line/{n}/tension"], z[f"line{n}_tension"].astype(np.float32))
    ts = csv_columns(folder)
    arrays = [s["array"] for s in meta["plots"]["end_tension"]]
    assert arrays == [f"ts/line{n}_{e}_tension_N" for n in names for e in "AB"]
    for s in arrays:
        assert np.array_equal(a[s], ts[s[3:]].astype(np.float32))
    labels = {m["label"] for m in meta["markers"]}
    assert {"ring", "clump", "crab", "ship"} <= labels
    assert "report.html" in json.loads((folder / outdir.MANIFEST).read_text())["files"]


def test_sweep_report(tmp_path):
    from mjtether.sweep import sweep
    out = sweep("default_walker", ["tether.length=250,270"], tmp_path / "sweep",
                sets=["simulation.duration=0.5"], progress=False, log=lambda *a, **k: None)
    page = write_report(out)
    text = page.read_text()
    data = json.loads(re.search(r'id="table-data">(.*?)</script>', text, re.S).group(1))
    import csv
    with open(out / "cases.csv", newline="") as fh:
        rows = list(csv.reader(fh))
    assert data["columns"] == rows[0] and data["rows"] == rows[1:]
    assert "peak_ship_tension_N" in data["columns"] and text.count("<tr>") == 3
    assert "report.html" in json.loads((out / outdir.MANIFEST).read_text())["files"]
    assert outdir.foreign_content(out) is None


def test_a_rated_load_near_the_run_sets_the_scale_and_is_drawn(waves, tmp_path):
    """The same results with the rating at 1.5 times the run's largest element tension (within
    ``RATED_IN_VIEW``): the rating sets the colour scale, the tension plots draw it as a band, and
    there is no note."""
    import shutil

    folder, page = waves
    peak = float(np.max(payload(page)[1]["line/tether/tension"]))
    copy = tmp_path / "run"
    shutil.copytree(folder, copy)
    summary = json.loads((copy / "summary.json").read_text())
    summary["scenario"]["tether"]["rated_load"] = 1.5 * peak
    (copy / "summary.json").write_text(json.dumps(summary))
    meta, _ = report_data.collect(copy, report_data.MAX_FRAME_BYTES)
    assert meta["tension_scale"] == {"max_N": 1.5 * peak, "source": "rated load"}
    assert meta["rated_band_N"] == 1.5 * peak and meta["rated_note"] is None
