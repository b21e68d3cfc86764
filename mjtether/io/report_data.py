"""The data of a run's HTML report (``io.report``): read from its results folder, cut to the
frames the page shows, and packed into the one compressed payload the page inlines.

Payload (``encode`` / ``decode``): gzip of ``MAGIC`` (4 bytes), the header's length (uint32,
little-endian), the header (UTF-8 JSON, padded with spaces to a multiple of 4 bytes:
``{"meta": {...}, "arrays": {name: {"offset": bytes, "shape": [...]}}}``) and then every array as
float32, little-endian, C order, at its offset from the end of the header; base64 of that in the
page. Every number the page draws is one of these float32 values: the folder's float64 values
rounded to float32 (relative error <= 2**-24), nothing else changed.

Arrays (SI units; world frame, z up, surface at z = 0; F the frames kept, ``frame_indices``):

* ``t`` (F,): the frames' times (s), samples of ``lines.npz``;
* per line NAME: ``line/NAME/nodes`` (F, e+1, 3; m), ``line/NAME/tension`` (F, e; N),
  ``line/NAME/s`` (F, e; m: arc length from end A to each element's centre, stretched, from
  the nodes); ``td/NAME`` (n,): the touchdown at every sample of ``lines.npz`` (``touchdown``),
  against ``td_t`` (n,);
* ``marker/K`` (F, 3) or (1, 3) for a marker that does not move (m): the ship, the robot,
  points, bodies, vehicles and walkers, from the time series' positions;
* ``ts/COLUMN`` (rows,): the time series' columns the plots draw (``timeseries.csv``), every row;
* ``surface/eta`` (F, gy, gx; m): the sea surface on a grid over the scene, where the run had waves:
  the run's own sea, its build-up ramp included, built again from ``summary.json`` (``sea_of``);
* ``seabed/z`` (gy, gx; m): a bathymetry grid's heights, where the run had one.
"""

from __future__ import annotations

import base64
import csv
import gzip
import json
import math
import re
import struct
from pathlib import Path

import numpy as np

from mjtether.files.results_folder import LINES, SUMMARY, TIMESERIES
from mjtether.io.replay import restore

MAGIC = b"MJR1"
RATED_IN_VIEW = 2.0
"""The rated load sets the colour scale and is drawn as a band on the tension plots where it is at
most this many times the run's largest element tension (as ``line_tension.png`` draws it); further
off, the run's own largest tension sets the scale and the page says where the rating is (a rated
load of 1500 N on an ROV's umbilical pulling 4 N would draw every curve flat and the cable dark)."""
MAX_FRAME_BYTES = 6_000_000
"""The largest size (bytes, float32 before compression) of the per-frame arrays: longer runs keep
every k-th sample (``frame_indices``). The page, base64 of gzip, is then under ~9 MB with the
3-D library (the float32 of cable nodes compresses by ~10 %, base64 adds 33 %)."""
GRID = 25
"""Points along each side of the sea-surface and bathymetry grids drawn."""


class ReportError(ValueError):
    """The folder cannot be reported on; the message names the path and what is missing."""


# ------------------------------------------------------------------ the payload


def encode(meta: dict, arrays: dict) -> str:
    """The page's payload (base64 text) of ``meta`` (JSON-able) and ``arrays`` {name: array}."""
    index, blobs, offset = {}, [], 0
    for name, a in arrays.items():
        b = np.ascontiguousarray(a, dtype="<f4").tobytes()
        index[name] = {"offset": offset, "shape": list(np.shape(a))}
        blobs.append(b)
        offset += len(b)
    head = json.dumps({"meta": meta, "arrays": index}, allow_nan=False).encode()
    head += b" " * (-len(head) % 4)
    raw = MAGIC + struct.pack("<I", len(head)) + head + b"".join(blobs)
    return base64.b64encode(gzip.compress(raw, compresslevel=6, mtime=0)).decode("ascii")


def decode(text: str) -> tuple[dict, dict]:
    """(meta, {name: float32 array}) of a payload ``encode`` wrote."""
    raw = gzip.decompress(base64.b64decode(text))
    if raw[:4] != MAGIC:
        raise ValueError("not an mjtether report payload")
    (n,) = struct.unpack("<I", raw[4:8])
    head = json.loads(raw[8:8 + n])
    base = 8 + n
    arrays = {}
    for name, a in head["arrays"].items():
        count = int(np.prod(a["shape"], dtype=np.int64))
        arrays[name] = np.frombuffer(raw, "<f4", count, base + a["offset"]).reshape(a["shape"])
    return head["meta"], arrays


def clean(x):
    """``x`` for JSON: non-finite floats as None, NumPy scalars as numbers, through dicts and lists."""
    if isinstance(x, dict):
        return {str(k): clean(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [clean(v) for v in x]
    if isinstance(x, (np.floating, np.integer)):
        x = x.item()
    if isinstance(x, float) and not math.isfinite(x):
        return None
    return x


def frame_indices(samples: int, bytes_per_frame: int, budget: int = MAX_FRAME_BYTES) -> np.ndarray:
    """The samples the page shows: every one if ``samples * bytes_per_frame`` fits ``budget``
    bytes, else every k-th (k the smallest that fits), the last sample always included."""
    if samples <= 0:
        return np.zeros(0, dtype=int)
    stride = max(1, math.ceil(samples * bytes_per_frame / max(budget, 1)))
    idx = np.arange(0, samples, stride)
    if idx[-1] != samples - 1:
        idx = np.append(idx, samples - 1)
    return idx


# ------------------------------------------------------------------ reading the folder


def read_timeseries(path: Path) -> dict:
    """{column name: float64 array} of ``timeseries.csv`` (an empty cell as NaN)."""
    with open(path, newline="") as fh:
        rows = list(csv.reader(fh))
    if not rows:
        raise ReportError(f"{str(path)!r} is empty: no header")
    names, body = rows[0], rows[1:]
    data = np.array([[float(v) if v != "" else math.nan for v in r] for r in body], dtype=float).reshape(-1, len(names))
    return {n: data[:, j] for j, n in enumerate(names)}


def _finite(v):
    """A number from a summary value (``"inf"`` text as inf), or None."""
    try:
        v = float(v)
    except (TypeError, ValueError):
        return None
    return v


def scenario_of(summary: dict):
    """The checked ``Scenario`` of a scenario run's summary, or None where it cannot be rebuilt
    (a file it names has moved): the report then draws a plane seabed and a flat sea."""
    from mjtether.scenario import load_scenario
    try:
        return load_scenario(data=restore(summary["scenario"]))
    except Exception:  # (any failure: the report goes on without what it would add)
        return None


def network_of(summary: dict):
    """The ``Network`` of a network run's summary (``summary.json``'s "network", ``network.to_dict``),
    or None where it cannot be rebuilt (a file it names has moved): the report then draws a flat sea."""
    from mjtether.network import from_dict
    try:
        return from_dict(restore(summary["network"]), name="summary.json")
    except Exception:  # (any failure: the report goes on without what it would add)
        return None


def sea_of(sc, net):
    """The run's sea, a ``physics.waves.WaveField`` (its build-up ramp, ``waves.ramp_periods``,
    included), built again by the very code the run built it with: a scenario's
    ``scenario.sea.wave_field`` in its water's depth and gravity (as ``scenario.scene`` calls it),
    a network's ``Network.wave_field`` (``[waves]`` or ``water.wave_components``, as
    ``network.run.water_of`` calls it); None for a flat sea or a run not rebuilt (``sc`` and
    ``net`` None)."""
    if net is not None:
        return net.wave_field()
    if sc is None:
        return None
    from mjtether.scenario.sea import wave_field
    return wave_field(sc.waves, sc.water.depth, sc.water.gravity)


def line_names(summary: dict, files: list[str]) -> list[str]:
    """The lines of ``lines.npz`` (``files``), in the summary's order where it lists them."""
    have = [k[4:-6] for k in files if k.startswith("line") and k.endswith("_nodes")]
    listed = [n for n in (summary.get("lines") or {}) if n in have]
    return listed + [n for n in have if n not in listed]


def arc_centres(nodes: np.ndarray) -> np.ndarray:
    """Arc length (m) from node 0 to each element's centre, from ``nodes`` (..., e+1, 3); NaN for
    an element of no length (cable still on a drum: the along-line plot leaves it out)."""
    seg = np.linalg.norm(np.diff(nodes, axis=-2), axis=-1)
    return np.where(seg > 1e-9, np.cumsum(seg, axis=-1) - 0.5 * seg, math.nan)


def touchdown(nodes: np.ndarray, seabed_z, tolerance: float) -> np.ndarray:
    """Per sample, the arc length (m, stretched, from end B: the last node, the fairlead) to the
    first element lying on the seabed: both its nodes less than ``tolerance`` m above
    ``seabed_z(x, y)`` (as the run's ``length_on_seabed`` counts them); NaN where none does.
    ``nodes`` (n, e+1, 3) from end A to end B."""
    x = nodes[:, ::-1]  # (from end B)
    on = x[..., 2] < seabed_z(x[..., 0], x[..., 1]) + tolerance
    lying = on[:, 1:] & on[:, :-1]
    seg = np.linalg.norm(np.diff(x, axis=1), axis=-1)
    before = np.cumsum(seg, axis=1) - seg  # (length from B to each element's start)
    first = np.argmax(lying, axis=1)
    out = before[np.arange(len(x)), first]
    return np.where(lying.any(axis=1), out, math.nan)


def _markers(summary: dict, ts: dict) -> list[tuple[str, str, dict | list]]:
    """(label, kind, columns {x, y, z} or a fixed position) of every marker the scene draws."""
    out = []
    if summary.get("kind") == "scenario":
        sc = summary.get("scenario", {})
        if "ship_x_m" in ts:
            out.append(("ship", "ship", {"x": "ship_x_m", "y": "ship_y_m",
                                         "z": "fairlead_z_m" if "fairlead_z_m" in ts else None}))
        if "robot_x_m" in ts:
            kind = str((sc.get("robot") or {}).get("type", "robot"))
            out.append((kind, kind, {"x": "robot_x_m", "y": "robot_y_m", "z": "robot_z_m"}))
        return out
    net = summary.get("network") or {}
    for col in ts:
        m = re.fullmatch(r"(point|body|vehicle|walker)(.+)_x_m", col)
        if m and f"{col[:-4]}_y_m" in ts and f"{col[:-4]}_z_m" in ts:
            out.append((m.group(2), m.group(1), {k: f"{col[:-4]}_{k}_m" for k in "xyz"}))
    for name, p in (net.get("points") or {}).items():
        if p.get("kind") in ("fixed", "coupled", "anchor", "vessel") and len(p.get("position") or []) == 3:
            out.append((name, "ship" if p["kind"] in ("coupled", "vessel") and p["position"][2] >= 0 else "point",
                        [float(v) for v in p["position"]]))
    for name, b in (net.get("bodies") or {}).items():
        if f"body{name}_x_m" not in ts and len(b.get("position") or []) >= 3:
            out.append((name, "body", [float(v) for v in b["position"][:3]]))
    return out


def collect(folder: Path, budget: int = MAX_FRAME_BYTES) -> tuple[dict, dict]:
    """(meta, arrays) of the report of the scenario's or network's results ``folder``."""
    summary = json.loads((folder / SUMMARY).read_text())
    kind = summary.get("kind", "scenario")
    ts = read_timeseries(folder / TIMESERIES)
    with np.load(folder / LINES) as z:
        files = list(z.files)
        t_all = np.asarray(z["time_s"], float)
        names = line_names(summary, files)
        lines = {n: {"nodes": np.asarray(z[f"line{n}_nodes"], float), "tension": np.asarray(z[f"line{n}_tension"], float)}
                 for n in names}
    sc = scenario_of(summary) if kind == "scenario" else None
    net_cfg = network_of(summary) if kind == "network" else None
    scenario = summary.get("scenario") or {}
    net = summary.get("network") or {}
    water = scenario.get("water") or net.get("water") or {}
    depth = float(water.get("depth", 100.0))
    slope = math.radians(float(water.get("seabed_slope_deg", 0.0) or 0.0))
    heading = math.radians(float(water.get("seabed_slope_heading_deg", 0.0) or 0.0))
    grid = getattr(getattr(sc, "water", None), "grid", None)

    def seabed_z(x, y):
        if grid is not None:
            return np.asarray(grid.height(np.asarray(x, float), np.asarray(y, float)), float)
        return -depth + math.tan(slope) * (np.asarray(x) * math.cos(heading) + np.asarray(y) * math.sin(heading))

    # (the scene's extent: every node of every sample, every marker)
    markers = _markers(summary, ts)
    pts = [ln["nodes"].reshape(-1, 3) for ln in lines.values() if ln["nodes"].size]
    tcol = ts.get("time_s", t_all)
    for _, _, where in markers:
        if isinstance(where, dict):
            pts.append(np.column_stack([ts[where[k]] if where[k] else np.zeros_like(tcol) for k in "xyz"]))
        else:
            pts.append(np.asarray([where], float))
    allp = np.concatenate(pts) if pts else np.zeros((1, 3))
    allp = allp[np.isfinite(allp).all(axis=1)]
    lo, hi = allp.min(axis=0), allp.max(axis=0)
    pad = 0.15 * max(float(np.max(hi[:2] - lo[:2])), 0.2 * depth, 1.0)
    box = [float(lo[0] - pad), float(hi[0] + pad), float(lo[1] - pad), float(hi[1] + pad)]
    field = sea_of(sc, net_cfg)

    per_frame = sum(ln["nodes"][0].size + 2 * ln["tension"][0].size for ln in lines.values()) * 4
    per_frame += 12 * len(markers) + (4 * GRID * GRID if field is not None else 0)
    idx = frame_indices(len(t_all), per_frame, budget)
    t = t_all[idx]
    arrays = {"t": t}
    diameters = _diameters(summary, names)
    peak = 0.0
    for n, ln in lines.items():
        nodes = ln["nodes"]
        arrays[f"line/{n}/nodes"] = nodes[idx]
        arrays[f"line/{n}/tension"] = ln["tension"][idx]
        arrays[f"line/{n}/s"] = arc_centres(nodes[idx])
        arrays[f"td/{n}"] = touchdown(nodes, seabed_z, diameters.get(n, 0.05))
        if ln["tension"].size:
            peak = max(peak, float(np.nanmax(ln["tension"])))
    arrays["td_t"] = t_all
    marker_meta = []
    for k, (label, mkind, where) in enumerate(markers):
        if isinstance(where, dict):
            arrays[f"marker/{k}"] = np.column_stack([np.interp(t, tcol, ts[where[c]]) if where[c] else np.zeros_like(t)
                                                     for c in "xyz"])
        else:
            arrays[f"marker/{k}"] = np.asarray([where], float)
        marker_meta.append({"label": label, "kind": mkind, "array": f"marker/{k}"})
    surface = {"box": box, "grid": GRID if field is not None else 2}
    if field is not None:
        gx, gy = np.meshgrid(np.linspace(box[0], box[1], GRID), np.linspace(box[2], box[3], GRID))
        arrays["surface/eta"] = np.array([field.elevation(gx, gy, np.full_like(gx, ti)) for ti in t])
    seabed = {"box": box, "depth": depth, "slope_rad": slope, "heading_rad": heading, "grid": None}
    if grid is not None:
        gx, gy = np.meshgrid(np.linspace(box[0], box[1], GRID), np.linspace(box[2], box[3], GRID))
        arrays["seabed/z"] = seabed_z(gx, gy)
        seabed["grid"] = GRID
    rated = _finite((scenario.get("tether") or {}).get("rated_load")) if kind == "scenario" else None
    rated = rated if rated is not None and math.isfinite(rated) and rated > 0 else None
    in_view = rated is not None and rated <= RATED_IN_VIEW * peak  # (else it flattens the colours and plots)
    plots, ts_arrays = _plots(summary, ts, names)
    arrays.update({f"ts/{c}": ts[c] for c in ts_arrays})
    meta = {
        "kind": kind,
        "title": str(summary.get("scenario_file") or summary.get("source") or folder.name),
        "folder": folder.name,
        "lines": [{"name": n, "A": (summary.get("lines") or {}).get(n, {}).get("A", "A"),
                   "B": (summary.get("lines") or {}).get(n, {}).get("B", "B")} for n in names],
        "markers": marker_meta,
        "frames": {"kept": int(len(idx)), "samples": int(len(t_all)),
                   "stride": int(idx[1] - idx[0]) if len(idx) > 1 else 1},
        "tension_scale": {"max_N": rated if in_view else (peak if peak > 0 else 1.0),
                          "source": "rated load" if in_view else "the run's largest element tension"},
        "rated_load_N": rated,
        "rated_band_N": rated if in_view else None,
        "rated_note": None if rated is None or in_view else
        f"rated load {rated:.4g} N, {rated / max(peak, 1e-300):.0f}x the largest tension here: off the scale",
        "seabed": seabed, "surface": surface, "plots": plots,
        "scene": {"lo": [float(v) for v in lo], "hi": [float(v) for v in hi]},
    }
    return clean(meta), arrays


def _diameters(summary: dict, names) -> dict:
    """{line: diameter (m)}: the touchdown's tolerance, as the run's ``length_on_seabed``."""
    if summary.get("kind") == "scenario":
        return {n: float((summary.get("scenario") or {}).get("tether", {}).get("diameter", 0.05)) for n in names}
    net = summary.get("network") or {}
    types = net.get("line_types") or {}
    out = {}
    for ln in net.get("lines") or []:
        if isinstance(ln, dict) and ln.get("name") in names:
            out[ln["name"]] = float((types.get(ln.get("type")) or {}).get("diameter", 0.05))
    return out


def _plots(summary: dict, ts: dict, names) -> tuple[dict, list[str]]:
    """The 2-D plots' series ({plot: [{label, array}]}) and the time series' columns they need."""
    lines = summary.get("lines") or {}
    ends = []
    for n in names:
        for end in ("A", "B"):
            col = f"line{n}_{end}_tension_N"
            if col not in ts and summary.get("kind") == "scenario":
                col = {"A": "tow_tension_N", "B": "ship_tension_N"}[end]
            if col in ts:
                ends.append({"label": f"{n} end {end} ({lines.get(n, {}).get(end, end)})", "array": f"ts/{col}"})
    payout = [{"label": "deployed length", "array": "ts/deployed_length_m"}] if "deployed_length_m" in ts else []
    payout += [{"label": f"{n} deployed", "array": f"ts/line{n}_deployed_m"} for n in names
               if f"line{n}_deployed_m" in ts]
    payout_label = "deployed (unstretched) length (m)"
    if not payout:
        payout = [{"label": f"{n} stretched", "array": f"ts/line{n}_length_m"} for n in names if f"line{n}_length_m" in ts]
        payout_label = "stretched length (m): no line pays out"
    cols = ["time_s"] + [s["array"][3:] for s in ends + payout]
    return {"time": "ts/time_s", "end_tension": ends, "payout": payout, "payout_label": payout_label,
            "touchdown": [{"label": n, "array": f"td/{n}"} for n in names]}, list(dict.fromkeys(cols))
