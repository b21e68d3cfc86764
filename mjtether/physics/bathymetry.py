"""A seabed from a bathymetry grid: heights on a regular grid, interpolated bilinearly (pure
NumPy; MuJoCo's height field is built from it in ``mjtether.cable.builder.add_seabed_grid``).

Two kinds of file are read:

* MoorDyn's 3-D seafloor file (``SeafloorFile``; M. Hall et al., MoorDyn v2): a line
  ``NX NY``, a line of the NX x coordinates, a line of the NY y coordinates, then one line
  ``x y z`` per grid node (z: the seabed's height, negative below the surface). MoorDyn-C
  interpolates it bilinearly, as here.
* a plain grid of depths (m, positive down) as CSV (comma- or space-separated) or NumPy
  ``.npy``: rows along +y, columns along +x, with its spacing (m) and the world position of its
  first node (m).

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


def read_moordyn_seafloor(path) -> Bathymetry:
    """MoorDyn's 3-D seafloor file (see the module docstring)."""
    p = Path(path)
    try:
        rows = [ln.split() for ln in p.read_text().splitlines() if ln.strip()]
    except OSError as exc:
        raise BathymetryError(f"{p}: cannot read the seafloor file ({exc.strerror})") from None
    try:
        nx, ny = int(rows[0][0]), int(rows[0][1])
        x, y = np.array(rows[1][:nx], float), np.array(rows[2][:ny], float)
        nodes = np.array([r[:3] for r in rows[3:]], float)
    except (IndexError, ValueError):
        raise BathymetryError(f"{p}: not a MoorDyn 3-D seafloor file (NX NY, the x line, the y line, then "
                              "x y z rows)") from None
    if len(x) != nx or len(y) != ny or len(nodes) != nx * ny:
        raise BathymetryError(f"{p}: {nx} x {ny} nodes announced, {len(x)} x, {len(y)} y and {len(nodes)} "
                              "x y z rows given")
    z = np.full((ny, nx), np.nan)
    i = np.searchsorted(x, nodes[:, 0])
    j = np.searchsorted(y, nodes[:, 1])
    ok = (i < nx) & (j < ny)
    ok[ok] &= np.isclose(x[i[ok]], nodes[ok, 0]) & np.isclose(y[j[ok]], nodes[ok, 1])
    if not ok.all():
        k = int(np.flatnonzero(~ok)[0])
        raise BathymetryError(f"{p}: row {k + 4} ({nodes[k, 0]:g}, {nodes[k, 1]:g}) is not a node of the grid")
    z[j, i] = nodes[:, 2]
    try:
        return Bathymetry(x, y, z)
    except BathymetryError as exc:
        raise BathymetryError(f"{p}: {exc}") from None


def read_depth_grid(path, spacing: float, origin=(0.0, 0.0)) -> Bathymetry:
    """A grid of depths (m, positive down) from CSV or ``.npy`` (see the module docstring);
    ``spacing`` (m) between nodes along x and y, ``origin`` (m) the world (x, y) of the first
    node (row 0, column 0)."""
    p = Path(path)
    if not (spacing > 0 and math.isfinite(spacing)):
        raise BathymetryError(f"{p}: the grid's spacing must be a number of metres > 0, got {spacing!r}")
    try:
        if p.suffix.lower() == ".npy":
            depth = np.load(p, allow_pickle=False)
        else:
            text = p.read_text()
            depth = np.loadtxt(text.splitlines(), delimiter="," if "," in text else None, ndmin=2)
    except OSError as exc:
        raise BathymetryError(f"{p}: cannot read the depth grid ({exc.strerror or exc})") from None
    except ValueError as exc:
        raise BathymetryError(f"{p}: not a grid of numbers ({exc})") from None
    depth = np.asarray(depth, dtype=float)
    if depth.ndim != 2:
        raise BathymetryError(f"{p}: a depth grid is 2-D (rows along y, columns along x); got {depth.ndim}-D")
    if np.any(depth <= 0):
        raise BathymetryError(f"{p}: depths are positive down (m); the grid holds {depth.min():g}")
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
