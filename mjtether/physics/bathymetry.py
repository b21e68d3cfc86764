"""A seabed from a bathymetry grid: heights on a regular grid, interpolated bilinearly (pure
NumPy; MuJoCo's height field is built from it in ``mjtether.cable.builder.add_seabed_grid``).

Two kinds of file are read:

* MoorDyn's 3-D seafloor file (``SeafloorFile``; M. Hall et al., MoorDyn v2): a line
  ``NX NY``, a line of the NX x coordinates, a line of the NY y coordinates, then one line
  ``x y z`` per grid node (z: the seabed's height, negative below the surface). MoorDyn-C
  interpolates it bilinearly, as here.
* a plain grid of depths (m, positive down) as CSV (comma- or space-separated; ``#`` starts a
  comment) or NumPy ``.npy``: rows along +y, columns along +x, with its spacing (m) and the world
  position of its first node (m).

A grid has at most ``MAX_NODES`` nodes; a larger one is refused before its heights are read. An
error names the file and what is wrong (its line and field), never what the file holds.

Units SI, world frame z up, water surface at z = 0. The grid must be regular (equal spacing
along each axis), as MuJoCo's height field is; outside it there is no seabed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

import numpy as np


class BathymetryError(ValueError):
    """A bathymetry file that cannot be used; the message names the file and what is wrong."""


@dataclass(frozen=True, eq=False)
class Bathymetry:
    """Seabed heights ``z`` (ny, nx) m on the grid ``x`` (nx,) by ``y`` (ny,) m, both increasing
    with equal steps."""

    x: np.ndarray
    y: np.ndarray
    z: np.ndarray

    def __post_init__(self):
        x, y, z = (np.asarray(a, dtype=float) for a in (self.x, self.y, self.z))
        if x.ndim != 1 or y.ndim != 1 or len(x) < 2 or len(y) < 2:
            raise BathymetryError("a bathymetry grid needs at least 2 x 2 nodes")
        if len(x) * len(y) > MAX_NODES:
            raise BathymetryError(f"a grid of {len(y)} x {len(x)} nodes; at most {MAX_NODES:,} are allowed "
                                  "(bathymetry.MAX_NODES)")
        if z.shape != (len(y), len(x)):
            raise BathymetryError(f"the heights are {z.shape[0]} x {z.shape[1]}, the grid {len(y)} x {len(x)} "
                                  "(rows along y, columns along x)")
        if not (np.all(np.isfinite(x)) and np.all(np.isfinite(y)) and np.all(np.isfinite(z))):
            raise BathymetryError("the grid holds a value that is not a finite number")
        for name, a in (("x", x), ("y", y)):
            step = np.diff(a)
            if np.any(step <= 0) or np.ptp(step) > 1e-6 * step.mean():
                raise BathymetryError(f"the {name} coordinates must increase in equal steps (MuJoCo's height field "
                                      f"is regular); got steps from {step.min():g} to {step.max():g} m")
        if z.max() >= 0.0:
            raise BathymetryError(f"the seabed reaches z = {z.max():g} m, at or above the surface")
        object.__setattr__(self, "x", x)
        object.__setattr__(self, "y", y)
        object.__setattr__(self, "z", z)

    @property
    def bounds(self) -> tuple[float, float, float, float]:
        """(x min, x max, y min, y max), m."""
        return float(self.x[0]), float(self.x[-1]), float(self.y[0]), float(self.y[-1])

    def covers(self, x, y, margin: float = 0.0) -> bool:
        """Whether every (x, y) (m) lies on the grid, ``margin`` m inside its edge."""
        x0, x1, y0, y1 = self.bounds
        x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
        return bool(np.all((x >= x0 + margin) & (x <= x1 - margin) & (y >= y0 + margin) & (y <= y1 - margin)))

    def _cell(self, x, y):
        x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
        dx, dy = self.x[1] - self.x[0], self.y[1] - self.y[0]
        u = np.clip((x - self.x[0]) / dx, 0.0, len(self.x) - 1.0)  # (beyond the edge: the edge's height)
        v = np.clip((y - self.y[0]) / dy, 0.0, len(self.y) - 1.0)
        i = np.minimum(u.astype(int), len(self.x) - 2)
        j = np.minimum(v.astype(int), len(self.y) - 2)
        z = self.z
        return u - i, v - j, z[j, i], z[j, i + 1], z[j + 1, i], z[j + 1, i + 1], dx, dy

    def height(self, x, y):
        """Seabed height (m, z up) at (x, y) m, interpolated bilinearly (as MoorDyn-C does)."""
        a, b, z00, z10, z01, z11, _, _ = self._cell(x, y)
        return (1 - b) * ((1 - a) * z00 + a * z10) + b * ((1 - a) * z01 + a * z11)

    def normal(self, x, y) -> np.ndarray:
        """Unit normal (..., 3) of the seabed at (x, y) m, pointing up into the water."""
        return self.height_and_normal(x, y)[1]

    def height_and_normal(self, x, y):
        """``height`` and ``normal`` at (x, y) m, from one lookup of the cells (the friction's
        per-step call)."""
        a, b, z00, z10, z01, z11, dx, dy = self._cell(x, y)
        h = (1 - b) * ((1 - a) * z00 + a * z10) + b * ((1 - a) * z01 + a * z11)
        gx = ((1 - b) * (z10 - z00) + b * (z11 - z01)) / dx
        gy = ((1 - a) * (z01 - z00) + a * (z11 - z10)) / dy
        n = np.stack([-gx, -gy, np.ones_like(gx)], axis=-1)
        return h, n / np.linalg.norm(n, axis=-1, keepdims=True)

    def plane_at(self, x: float, y: float, radius: float) -> tuple[float, float]:
        """The plane fitted (least squares) to the grid within ``radius`` m of (x, y): its slope
        (rad) and the heading it rises towards (rad from +x towards +y). Where fewer than three
        nodes are that near, the local gradient."""
        X, Y = np.meshgrid(self.x, self.y)
        near = (X - x) ** 2 + (Y - y) ** 2 <= radius ** 2
        if near.sum() >= 3:
            A = np.c_[X[near] - x, Y[near] - y, np.ones(near.sum())]
            gx, gy, _ = np.linalg.lstsq(A, self.z[near], rcond=None)[0]
        else:
            nx, ny, nz = self.normal(x, y)
            gx, gy = -nx / nz, -ny / nz
        return math.atan(math.hypot(gx, gy)), math.atan2(gy, gx) if (gx or gy) else 0.0


MAX_NODES = 4_000_000
"""The most nodes a bathymetry grid may have (2000 x 2000: 2 km square at 1 m). Measured here, a
grid of that size reads, becomes a MuJoCo height field and compiles in about 1 s and 0.4 GB;
time and memory grow with the node count (the heights in float64, the list of them handed to
MuJoCo, a height field for each seabed copy a network makes, one per line diameter), so that a
10 000 x 10 000 grid would take tens of GB and minutes. A larger grid is refused before its
heights are read."""
TEXT_BYTES_PER_NODE = 64
"""Bytes of text a grid file may spend per node (an ``x y z`` row of MoorDyn's file in full
precision is about 60): a text file over MAX_NODES times this is refused before it is read."""


def _too_many(p: Path, nx: int, ny: int) -> None:
    if nx * ny > MAX_NODES:
        raise BathymetryError(f"{p}: a grid of {nx} x {ny} nodes; at most {MAX_NODES:,} nodes are allowed "
                              "(bathymetry.MAX_NODES: memory and build time grow with them; coarsen the grid or "
                              "cut it to the area the cable and robot use)")


def _text_of(p: Path, what: str) -> str:
    """The UTF-8 text of grid file ``p``, refused (naming MAX_NODES) when it is larger than a grid
    of MAX_NODES nodes can be as text; errors name the file and what is wrong, never its contents."""
    from mjtether import _checks
    try:
        size = p.stat().st_size
    except OSError as exc:
        raise BathymetryError(f"{p}: cannot read the {what} ({exc.strerror or type(exc).__name__})") from None
    if size > MAX_NODES * TEXT_BYTES_PER_NODE:
        raise BathymetryError(f"{p}: {size / 2**20:.0f} MiB, more than a grid of at most {MAX_NODES:,} nodes takes "
                              f"as text (bathymetry.MAX_NODES, {TEXT_BYTES_PER_NODE} bytes a node)")
    try:
        return _checks.read_text(str(p), p, max_bytes=MAX_NODES * TEXT_BYTES_PER_NODE)
    except ValueError as exc:
        raise BathymetryError(str(exc)) from None


def _numbers(p: Path, line: int, fields, what: str) -> np.ndarray:
    """``fields`` (strings) of ``line`` as floats; an error names the line and the field, not its text."""
    out = np.empty(len(fields))
    for k, f in enumerate(fields):
        try:
            out[k] = float(f)
        except ValueError:
            raise BathymetryError(f"{p}: not a grid of numbers: line {line}, field {k + 1} ({what}) is not a "
                                  "number") from None
    return out


def read_moordyn_seafloor(path) -> Bathymetry:
    """MoorDyn's 3-D seafloor file (see the module docstring); at most MAX_NODES nodes."""
    p = Path(path)
    lines = [(k + 1, ln.split()) for k, ln in enumerate(_text_of(p, "seafloor file").splitlines()) if ln.strip()]
    if not lines or len(lines[0][1]) < 2 or not all(w.isdigit() for w in lines[0][1][:2]):
        raise BathymetryError(f"{p}: not a MoorDyn 3-D seafloor file: its first line must be NX NY (two whole "
                              "numbers), then the x line, the y line, then x y z rows")
    nx, ny = int(lines[0][1][0]), int(lines[0][1][1])
    _too_many(p, nx, ny)
    if len(lines) != 3 + nx * ny:
        raise BathymetryError(f"{p}: {nx} x {ny} nodes announced on line 1, {max(len(lines) - 3, 0)} x y z rows "
                              "given")
    axes = []
    for (no, fields), n, name in ((lines[1], nx, "x"), (lines[2], ny, "y")):
        if len(fields) < n:
            raise BathymetryError(f"{p}: line {no}: {len(fields)} {name} coordinates, NX NY announce {n}")
        axes.append(_numbers(p, no, fields[:n], f"{name} coordinate"))
    x, y = axes
    rows = lines[3:3 + nx * ny]
    try:
        nodes = np.array([fields[:3] for _, fields in rows], dtype=float).reshape(len(rows), 3)
    except ValueError:  # (find the row and field, without showing them)
        for no, fields in rows:
            if len(fields) < 3:
                raise BathymetryError(f"{p}: line {no}: an x y z row needs 3 fields, it has {len(fields)}") from None
            _numbers(p, no, fields[:3], "x, y or z")
    z = np.full((ny, nx), np.nan)
    i = np.searchsorted(x, nodes[:, 0])
    j = np.searchsorted(y, nodes[:, 1])
    ok = (i < nx) & (j < ny)
    ok[ok] &= np.isclose(x[i[ok]], nodes[ok, 0]) & np.isclose(y[j[ok]], nodes[ok, 1])
    if not ok.all():
        raise BathymetryError(f"{p}: line {rows[int(np.flatnonzero(~ok)[0])][0]}: its x, y is not a node of the "
                              "grid (the x line by the y line)")
    z[j, i] = nodes[:, 2]
    if np.isnan(z).any():  # (a node given twice, another not at all)
        jj, ii = np.argwhere(np.isnan(z))[0]
        raise BathymetryError(f"{p}: the node of x number {ii + 1} and y number {jj + 1} has no x y z row")
    try:
        return Bathymetry(x, y, z)
    except BathymetryError as exc:
        raise BathymetryError(f"{p}: {exc}") from None


def _read_npy(p: Path) -> np.ndarray:
    """A 2-D array of numbers from ``.npy`` file ``p``, its header checked (size, kind) before its data
    is read."""
    try:
        with open(p, "rb") as f:
            version = np.lib.format.read_magic(f)
            shape, _, dtype = (np.lib.format.read_array_header_1_0 if version == (1, 0)
                               else np.lib.format.read_array_header_2_0)(f)
    except (OSError, ValueError) as exc:
        why = exc.strerror if isinstance(exc, OSError) and exc.strerror else "not a NumPy .npy file"
        raise BathymetryError(f"{p}: cannot read the depth grid ({why})") from None
    if len(shape) != 2:
        raise BathymetryError(f"{p}: a depth grid is 2-D (rows along y, columns along x); got {len(shape)}-D")
    _too_many(p, shape[1], shape[0])
    if dtype.kind not in "iuf":
        raise BathymetryError(f"{p}: a depth grid holds numbers (integers or floats); this .npy holds {dtype}")
    try:
        return np.load(p, allow_pickle=False)
    except (OSError, ValueError):
        raise BathymetryError(f"{p}: cannot read the depth grid (its data does not fit its header)") from None


def _read_depth_text(p: Path) -> tuple[np.ndarray, list]:
    """A depth grid as text: its array and the file line of each row. ``#`` starts a comment; the
    fields are comma-separated if any row (not a comment) holds a comma, else by spaces."""
    rows = [(k + 1, ln.split("#", 1)[0]) for k, ln in enumerate(_text_of(p, "depth grid").splitlines())]
    rows = [(no, ln) for no, ln in rows if ln.strip()]
    comma = any("," in ln for _, ln in rows)
    fields = [[f.strip() for f in ln.split(",")] if comma else ln.split() for _, ln in rows]
    if not fields:
        raise BathymetryError(f"{p}: not a grid of numbers (no rows)")
    _too_many(p, len(fields[0]), len(fields))
    for (no, _), fs in zip(rows, fields):
        if len(fs) != len(fields[0]):
            raise BathymetryError(f"{p}: not a grid of numbers: line {no} has {len(fs)} columns where line "
                                  f"{rows[0][0]} has {len(fields[0])}")
    try:
        depth = np.array(fields, dtype=float)
    except ValueError:  # (find the line and column, without showing them)
        for (no, _), fs in zip(rows, fields):
            _numbers(p, no, fs, "a depth")
    return depth, [no for no, _ in rows]


def read_depth_grid(path, spacing: float, origin=(0.0, 0.0)) -> Bathymetry:
    """A grid of depths (m, positive down) from CSV or ``.npy`` (see the module docstring);
    ``spacing`` (m) between nodes along x and y, ``origin`` (m) the world (x, y) of the first
    node (row 0, column 0); at most MAX_NODES nodes."""
    p = Path(path)
    if not (spacing > 0 and math.isfinite(spacing)):
        raise BathymetryError(f"{p}: the grid's spacing must be a number of metres > 0, got {spacing!r}")
    if p.suffix.lower() == ".npy":
        depth, lines = _read_npy(p), None
    else:
        depth, lines = _read_depth_text(p)
    depth = np.asarray(depth, dtype=float)

    def where(mask) -> str:  # (the first node in mask: its line and column, or its row and column)
        r, c = np.argwhere(mask)[0]
        return f"line {lines[r]}, column {c + 1}" if lines is not None else f"row {r + 1}, column {c + 1}"

    if not np.all(np.isfinite(depth)):
        raise BathymetryError(f"{p}: {where(~np.isfinite(depth))}: a depth that is not a finite number")
    if np.any(depth <= 0):
        raise BathymetryError(f"{p}: {where(depth <= 0)}: depths are positive down (m); this one is not")
    x = origin[0] + spacing * np.arange(depth.shape[1])
    y = origin[1] + spacing * np.arange(depth.shape[0])
    try:
        return Bathymetry(x, y, -depth)
    except BathymetryError as exc:
        raise BathymetryError(f"{p}: {exc}") from None


def is_moordyn_seafloor(path) -> bool:
    """Whether ``path`` starts as MoorDyn's 3-D seafloor file does (two integers on its first line)."""
    try:
        with open(path) as f:
            first = f.readline().split()
    except (OSError, UnicodeDecodeError):
        return False
    return len(first) == 2 and all(w.isdigit() for w in first)


@lru_cache(maxsize=8)
def _load(path: str, mtime: float, spacing: float, origin: tuple) -> Bathymetry:
    if is_moordyn_seafloor(path):
        return read_moordyn_seafloor(path)
    return read_depth_grid(path, spacing, origin)


def load(path, spacing: float = 0.0, origin=(0.0, 0.0)) -> Bathymetry:
    """A MoorDyn 3-D seafloor file, or a depth grid (``read_depth_grid``; ``spacing`` needed),
    told apart by the first line; read once per file version."""
    p = Path(path)
    if not p.is_file():
        raise BathymetryError(f"{p}: no such file")
    if not spacing and not is_moordyn_seafloor(p):
        raise BathymetryError(f"{p}: a grid of depths needs water.bathymetry_spacing_m (m between nodes)")
    return _load(str(p.resolve()), p.stat().st_mtime, float(spacing), tuple(map(float, origin)))
