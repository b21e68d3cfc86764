"""The water column: seabed depth, water density rho(z) and current u(z).

Frame: world, z up, water surface at z = 0, seabed at z = -depth (depth > 0).
Every profile is evaluated vectorised over an array of heights ``z`` (m, <= 0 in
the water); points above the surface take the surface value.

Currents are horizontal vectors (m/s). A heading is measured from +x towards +y
(radians). Density is in kg/m^3.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from mjtether import _checks

GRAVITY = 9.81
"""Gravitational acceleration used throughout, m/s^2."""


def _depth(z) -> np.ndarray:
    """Depth below the surface (m, >= 0) of heights ``z``."""
    return np.maximum(-np.asarray(z, dtype=float), 0.0)


def _sorted_table(name: str, depths, *columns) -> tuple[np.ndarray, ...]:
    d = np.asarray(depths, dtype=float)
    cols = [np.asarray(c, dtype=float) for c in columns]
    if d.ndim != 1 or d.size < 2:
        raise ValueError(f"{name}.depths must list at least two depths (m), got {depths!r}")
    for c in cols:
        if c.shape != d.shape:
            raise ValueError(f"{name}: every column must have as many rows as depths ({d.size})")
    if not np.all(np.isfinite(d)) or not all(np.all(np.isfinite(c)) for c in cols):
        raise ValueError(f"{name} contains a non-finite value (NaN or inf)")
    if np.any(d < 0):
        raise ValueError(f"{name}.depths must be >= 0 m (depth below the surface), got {d.min()}")
    if np.any(np.diff(d) <= 0):
        raise ValueError(f"{name}.depths must be sorted by depth, strictly increasing (m)")
    return (d, *cols)


# --------------------------------------------------------------------------- density


class DensityProfile:
    """Water density rho(z), kg/m^3."""

    def __call__(self, z) -> np.ndarray:  # pragma: no cover - interface
        raise NotImplementedError


@dataclass(frozen=True)
class ConstantDensity(DensityProfile):
    """Uniform density (kg/m^3)."""

    rho: float = 1025.0

    def __post_init__(self):
        _checks.in_range("density.rho", self.rho, 900.0, 1100.0, "kg/m^3")

    def __call__(self, z):
        return np.full(np.shape(z), float(self.rho))


@dataclass(frozen=True)
class LinearDensity(DensityProfile):
    """Density varying linearly from ``rho_surface`` at z = 0 to ``rho_ref`` at ``depth_ref``.

    Beyond ``depth_ref`` the same gradient continues (Khan et al. 2023 use
    1025 kg/m^3 at the surface and 980 kg/m^3 at 500 m, and run cases to 550 m).
    """

    rho_surface: float = 1025.0
    rho_ref: float = 980.0
    depth_ref: float = 500.0

    def __post_init__(self):
        _checks.in_range("density.rho_surface", self.rho_surface, 900.0, 1100.0, "kg/m^3")
        _checks.in_range("density.rho_ref", self.rho_ref, 900.0, 1100.0, "kg/m^3")
        _checks.positive("density.depth_ref", self.depth_ref, "m")

    def __call__(self, z):
        g = (self.rho_ref - self.rho_surface) / self.depth_ref
        return self.rho_surface + g * _depth(z)


class TabulatedDensity(DensityProfile):
    """Density interpolated linearly in a (depth, rho) table; constant beyond its ends."""

    def __init__(self, depths, rho):
        self.depths, self.rho = _sorted_table("density table", depths, rho)
        if np.any((self.rho < 900.0) | (self.rho > 1100.0)):
            raise ValueError("density table rho must be in [900, 1100] kg/m^3")

    def __call__(self, z):
        return np.interp(_depth(z), self.depths, self.rho)

    def __repr__(self):
        return f"TabulatedDensity({len(self.depths)} rows, {self.depths[0]:g}-{self.depths[-1]:g} m)"


def teos10_density(depths, temperature, salinity, latitude: float = 0.0) -> TabulatedDensity:
    """In-situ density from TEOS-10 (``gsw``) for a CTD-like profile.

    ``depths`` (m, increasing), in-situ ``temperature`` (deg C, ITS-90) and
    practical ``salinity`` (PSS-78) per depth. Longitude is taken as 0; the
    absolute-salinity anomaly this ignores is below 0.03 kg/m^3 in the open ocean.
    """
    import gsw  # optional dependency: pip install mjtether[seawater]

    d, t, sp = _sorted_table("TEOS-10 profile", depths, temperature, salinity)
    p = gsw.p_from_z(-d, latitude)
    sa = gsw.SA_from_SP(sp, p, 0.0, latitude)
    ct = gsw.CT_from_t(sa, t, p)
    return TabulatedDensity(d, gsw.rho(sa, ct, p))


# --------------------------------------------------------------------------- current


def _heading_vectors(speed: np.ndarray, heading) -> np.ndarray:
    out = np.zeros(speed.shape + (3,))
    out[..., 0] = speed * np.cos(heading)
    out[..., 1] = speed * np.sin(heading)
    return out


class CurrentProfile:
    """Horizontal current u(z) (m/s, world frame) as an array of shape ``z.shape + (3,)``;
    ``speed_at(z)`` gives its magnitude."""

    heading: float = 0.0

    def speed_at(self, z) -> np.ndarray:  # pragma: no cover - interface
        raise NotImplementedError

    def __call__(self, z) -> np.ndarray:
        return _heading_vectors(self.speed_at(z), self.heading)

    def max_speed(self, depth: float) -> float:
        """Largest speed between the surface and ``depth`` (m), sampled finely."""
        return float(np.max(np.abs(self.speed_at(-np.linspace(0.0, depth, 2001)))))


def _check_heading(name, heading):
    return _checks.finite(name, heading)


@dataclass(frozen=True)
class ConstantCurrent(CurrentProfile):
    """Uniform current of ``speed`` (m/s) towards ``heading`` (rad)."""

    speed: float = 0.0
    heading: float = 0.0

    def __post_init__(self):
        _checks.in_range("current.speed", self.speed, 0.0, 10.0, "m/s")
        _check_heading("current.heading", self.heading)

    def speed_at(self, z):
        return np.full(np.shape(z), float(self.speed))


@dataclass(frozen=True)
class LinearCurrent(CurrentProfile):
    """Speed varying linearly from ``surface_speed`` to ``bottom_speed`` at ``depth_ref`` (m),
    constant below."""

    surface_speed: float = 0.0
    bottom_speed: float = 0.0
    depth_ref: float = 100.0
    heading: float = 0.0

    def __post_init__(self):
        _checks.in_range("current.surface_speed", self.surface_speed, 0.0, 10.0, "m/s")
        _checks.in_range("current.bottom_speed", self.bottom_speed, 0.0, 10.0, "m/s")
        _checks.positive("current.depth_ref", self.depth_ref, "m")
        _check_heading("current.heading", self.heading)

    def speed_at(self, z):
        f = np.minimum(_depth(z) / self.depth_ref, 1.0)
        return self.surface_speed + (self.bottom_speed - self.surface_speed) * f


@dataclass(frozen=True)
class ExponentialCurrent(CurrentProfile):
    """u = surface_speed * exp(-depth / decay_depth): the surface current decaying with depth
    (Khan et al. 2023, Sec. 3.5: "almost zero at 50-60 m"; a decay depth of 15 m leaves 2 %
    at 60 m)."""

    surface_speed: float = 0.0
    decay_depth: float = 15.0
    heading: float = 0.0

    def __post_init__(self):
        _checks.in_range("current.surface_speed", self.surface_speed, 0.0, 10.0, "m/s")
        _checks.positive("current.decay_depth", self.decay_depth, "m")
        _check_heading("current.heading", self.heading)

    def speed_at(self, z):
        return self.surface_speed * np.exp(-_depth(z) / self.decay_depth)


@dataclass(frozen=True)
class PowerLawCurrent(CurrentProfile):
    """Tidal power law u = surface_speed * ((h - depth) / h) ** exponent, zero at the seabed
    depth h (DNV-RP-C205, Sec. 4.1.3; exponent 1/7 by default)."""

    surface_speed: float = 0.0
    seabed_depth: float = 100.0
    exponent: float = 1.0 / 7.0
    heading: float = 0.0

    def __post_init__(self):
        _checks.in_range("current.surface_speed", self.surface_speed, 0.0, 10.0, "m/s")
        _checks.positive("current.seabed_depth", self.seabed_depth, "m")
        _checks.in_range("current.exponent", self.exponent, 0.0, 2.0)
        _check_heading("current.heading", self.heading)

    def speed_at(self, z):
        h = self.seabed_depth
        frac = np.clip((h - _depth(z)) / h, 0.0, 1.0)
        return self.surface_speed * frac**self.exponent


class TabulatedCurrent(CurrentProfile):
    """Current from a (depth, speed, heading) table, e.g. an ADCP profile.

    The east/north components are interpolated linearly in depth (so a current that turns
    with depth turns smoothly, with no wrap-around at +-pi); constant beyond the table.
    Depths in m (increasing), speeds in m/s, headings in rad.
    """

    def __init__(self, depths, speeds, headings=None):
        if headings is None:
            headings = np.zeros(np.shape(depths))
        self.depths, self.speeds, self.headings = _sorted_table("current table", depths, speeds, headings)
        if np.any((self.speeds < 0) | (self.speeds > 10)):
            raise ValueError("current table speeds must be in [0, 10] m/s")
        self._ux = self.speeds * np.cos(self.headings)
        self._uy = self.speeds * np.sin(self.headings)

    def speed_at(self, z):
        return np.linalg.norm(self(z), axis=-1)

    def __call__(self, z):
        dz = _depth(z)
        out = np.zeros(dz.shape + (3,))
        out[..., 0] = np.interp(dz, self.depths, self._ux)
        out[..., 1] = np.interp(dz, self.depths, self._uy)
        return out

    def __repr__(self):
        return f"TabulatedCurrent({len(self.depths)} rows, {self.depths[0]:g}-{self.depths[-1]:g} m)"


# --------------------------------------------------------------------------- column


@dataclass(frozen=True)
class WaterColumn:
    """Seabed depth (m, positive), density profile and current profile.

    >>> water = WaterColumn(depth=500, density=LinearDensity(1025, 980, 500),
    ...                     current=ExponentialCurrent(2.5, decay_depth=15))
    >>> water.current([-0.0, -15.0])[:, 0].round(3).tolist()
    [2.5, 0.92]
    """

    depth: float = 200.0
    density: DensityProfile = field(default_factory=ConstantDensity)
    current: CurrentProfile = field(default_factory=ConstantCurrent)
    gravity: float = GRAVITY
    waves: object = None
    """The sea state (``physics.waves.WaveField``: ``elevation(x, y, t)`` m and ``kinematics(points,
    t)``: particle velocity m/s and local acceleration m/s^2), or None: a flat sea."""

    def __post_init__(self):
        _checks.in_range("water.depth", self.depth, 0.1, 12000.0, "m")
        if self.waves is not None and not (callable(getattr(self.waves, "elevation", None))
                                           and callable(getattr(self.waves, "kinematics", None))):
            raise ValueError(f"water.waves must be a wave field (physics.waves.WaveField), got "
                             f"{type(self.waves).__name__}")
        _checks.in_range("water.gravity", self.gravity, 0.0, 20.0, "m/s^2")
        if not isinstance(self.density, DensityProfile):
            raise ValueError(f"water.density must be a DensityProfile, got {type(self.density).__name__}")
        if not isinstance(self.current, CurrentProfile):
            raise ValueError(f"water.current must be a CurrentProfile, got {type(self.current).__name__}")

    @property
    def seabed_z(self) -> float:
        """Height of the seabed, z = -depth (m)."""
        return -float(self.depth)

    def rho(self, z) -> np.ndarray:
        """Water density at heights ``z`` (kg/m^3)."""
        return self.density(z)

    def velocity(self, z) -> np.ndarray:
        """Current velocity at heights ``z`` (m/s, shape ``z.shape + (3,)``)."""
        return self.current(z)
