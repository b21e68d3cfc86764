"""The weather a run's surface vessels feel, as configuration and as the part of a run that
applies it before each physics step: ``[wind]`` (the wind load of Hong et al. 2020, Eqs. 7-9
with Fossen's coefficients: ``vehicles.wind``) and ``[water.current.gauss_markov]`` (the
current's speed and direction as first-order Gauss-Markov processes, Hong et al.'s Sec. 2.4.3
after Fossen: ``physics.gauss_markov``).

Conventions (Fossen's): the wind's ``direction_deg`` is the way the air moves, the direction it
blows **towards** (as ``water.current.heading_deg`` is the way the water flows), from +x towards
+y; its velocity in a craft's body axes is V_w (cos(beta_w - psi), sin(beta_w - psi)), the form
of Hong et al.'s Eq. 10 for the current. A meteorological bearing (where the wind comes
from) is this plus 180 deg. The wind load acts on every surface vessel of the run (the ship's
``ship.vessel`` and a robot vehicle with a ``[surface]``), from the relative wind (the wind
minus the vessel's own velocity over the ground at its origin), at its origin (on its
waterline, as Eq. 7's yaw moment is taken) and in its horizontal plane: Eq. 7 has no heeling
moment. The windage (areas, length, coefficients) is the vessel's own reading
(``vehicles.wind.WINDAGE``) unless ``[wind]`` gives it. A wind of speed 0 applies nothing.

The Gauss-Markov current: ``water.current.speed`` and ``heading_deg`` (type ``constant``) are the
processes' means; each is stepped exactly (the Ornstein-Uhlenbeck transition) once per physics
step from ``seed``, and saturated in its band (Fossen's V_min <= V_c <= V_max), so that every
line, body and vehicle reads the same current at each step. No noise (``sigma`` and
``heading_sigma_deg`` both 0) leaves the constant current as it is.

``Weather`` is that part (``update(run, t, dt)``, as ``controllers``); ``attach(run)`` puts it
first among a ``runner.ScenarioRun``'s controllers. Units SI, degrees at this edge only.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .config import INF, ConfigError, Section, param

NO_WINDAGE = "wind.frontal_area, wind.lateral_area and wind.length"


@dataclass(frozen=True)
class Wind(Section):
    PATH = "wind"
    speed: float = param(0.0, 0.0, 60.0, "m/s", "the true wind's speed at the vessels (uniform, steady); 0: no "
                         "wind load", knots=True)
    direction_deg: float = param(0.0, -360.0, 360.0, "deg", "the direction the wind blows towards (Fossen's "
                                 "beta_w: its velocity's direction, as water.current.heading_deg), from +x towards "
                                 "+y; where it comes from is this + 180")
    air_density: float = param(1.225, 0.5, 2.0, "kg/m^3", "rho_a of Eq. 7 (ISA sea level)")
    frontal_area: float = param(0.0, 0.0, 1e5, "m^2", "A_T, projected above the waterline; 0: the vessel's own "
                                "(vehicles.wind.WINDAGE)")
    lateral_area: float = param(0.0, 0.0, 1e5, "m^2", "A_L, projected above the waterline; 0: the vessel's own")
    length: float = param(0.0, 0.0, 1e3, "m", "L, length overall; 0: the vessel's own")
    cx: float | None = param(None, 0.5, 0.9, "", "c_x of Eq. 8 (Eq. 9's range); none: the vessel's own",
                             kind="float")
    cy: float | None = param(None, 0.7, 0.95, "", "c_y of Eq. 8 (Eq. 9's range); none: the vessel's own",
                             kind="float")
    cn: float | None = param(None, 0.05, 0.2, "", "c_n of Eq. 8 (Eq. 9's range); none: the vessel's own",
                             kind="float")

    def _check(self):
        given = [k for k in ("frontal_area", "lateral_area", "length") if getattr(self, k) > 0.0]
        if given and len(given) < 3:
            missing = [k for k in ("frontal_area", "lateral_area", "length") if k not in given]
            self._bad(missing[0], f"give {NO_WINDAGE} together (or none: the vessel's own)")

    @property
    def blowing(self) -> bool:
        return self.speed > 0.0


@dataclass(frozen=True)
class CurrentGaussMarkov(Section):
    PATH = "water.current.gauss_markov"
    mu: float = param(0.0, 0.0, 100.0, "1/s", "speed: Fossen's mu in V_c' + mu (V_c - mean) = w (1/mu: the "
                      "correlation time; 0: a random walk)")
    sigma: float = param(0.0, 0.0, 10.0, "m/s/sqrt(s)", "speed: the white noise w's intensity (the stationary "
                         "standard deviation is sigma / sqrt(2 mu)); 0 with heading_sigma_deg 0: a constant current")
    v_min: float = param(0.0, 0.0, 10.0, "m/s", "speed: the saturation's floor")
    v_max: float = param(10.0, 0.0, 10.0, "m/s", "speed: the saturation's ceiling")
    heading_mu: float = param(0.0, 0.0, 100.0, "1/s", "direction: its mu")
    heading_sigma_deg: float = param(0.0, 0.0, 360.0, "deg/sqrt(s)", "direction: its noise intensity")
    heading_min_deg: float = param(-INF, -INF, INF, "deg", "direction: the saturation's floor")
    heading_max_deg: float = param(INF, -INF, INF, "deg", "direction: the saturation's ceiling")
    seed: int = param(0, 0, 2**31 - 1, "", "the noise's seed (a run is reproducible)")

    def _check(self):
        if self.v_min > self.v_max:
            self._bad("v_min", f"must be <= water.current.gauss_markov.v_max ({self.v_max:g} m/s)")
        if self.heading_min_deg > self.heading_max_deg:
            self._bad("heading_min_deg", f"must be <= water.current.gauss_markov.heading_max_deg "
                      f"({self.heading_max_deg:g} deg)")

    @property
    def active(self) -> bool:
        return self.sigma > 0.0 or self.heading_sigma_deg > 0.0


def gauss_markov_current(c):
    """The ``physics.gauss_markov.GaussMarkovCurrent`` of a ``[water.current]`` section ``c``
    whose ``gauss_markov`` has noise, about ``c.speed`` and ``c.heading_deg``; None without noise.
    ConfigError for a profile other than ``constant`` or a mean outside the band."""
    g = c.gauss_markov
    if not g.active:
        return None
    if c.type != "constant":
        raise ConfigError(f"water.current.gauss_markov is for a uniform current: water.current.type = "
                          f"{c.type!r} must be 'constant' (its speed and heading_deg are the processes' means)",
                          "water.current.gauss_markov")
    if not g.v_min <= c.speed <= g.v_max:
        raise ConfigError(f"water.current.speed = {c.speed:g}: the Gauss-Markov current's mean must lie in "
                          f"[water.current.gauss_markov.v_min, v_max] = [{g.v_min:g}, {g.v_max:g}] m/s",
                          "water.current.speed")
    if not g.heading_min_deg <= c.heading_deg <= g.heading_max_deg:
        raise ConfigError(f"water.current.heading_deg = {c.heading_deg:g}: the mean direction must lie in "
                          f"[water.current.gauss_markov.heading_min_deg, heading_max_deg] = "
                          f"[{g.heading_min_deg:g}, {g.heading_max_deg:g}] deg", "water.current.heading_deg")
    from mjtether.physics.gauss_markov import GaussMarkovCurrent
    r = math.radians
    return GaussMarkovCurrent(c.speed, g.mu, g.sigma, g.v_min, g.v_max, r(c.heading_deg), g.heading_mu,
                              r(g.heading_sigma_deg), r(g.heading_min_deg), r(g.heading_max_deg), seed=g.seed)


def windage_for(wind: Wind, vessel: str, key: str):
    """The ``vehicles.wind.Windage`` of the vessel named ``vessel`` (scenario key ``key``) under
    ``wind``: its shipped reading, with what ``[wind]`` gives instead."""
    from mjtether.vehicles import wind as wl
    own = wl.WINDAGE.get(vessel)
    if wind.frontal_area > 0.0:
        areas = {"frontal_area": wind.frontal_area, "lateral_area": wind.lateral_area, "length": wind.length}
    elif own is not None:
        areas = {"frontal_area": own.frontal_area, "lateral_area": own.lateral_area, "length": own.length}
    else:
        raise ConfigError(f"wind.speed = {wind.speed:g}: {key} = {vessel!r} has no windage of its own (shipped: "
                          f"{', '.join(sorted(wl.WINDAGE))}); give {NO_WINDAGE}", "wind.frontal_area")
    base = own or wl.Windage(1.0, 1.0, 1.0)
    coef = {k: getattr(base, k) if getattr(wind, k) is None else getattr(wind, k) for k in ("cx", "cy", "cn")}
    return wl.Windage(**areas, **coef, air_density=wind.air_density)


@dataclass
class VesselWind:
    """One vessel the wind acts on: its bound hydrodynamics (``vehicles.vehicle.BoundVehicle``:
    ``id``, ``velocity``), its windage and, after each update, the load applied (``load``: F_x N,
    F_y N, M_z N m about its origin, world frame)."""

    label: str
    body: object
    windage: object
    load: np.ndarray


class Weather:
    """The wind on the run's surface vessels and the Gauss-Markov current, updated before each
    physics step (module docstring). ``current``: the ``GaussMarkovCurrent`` the water column
    holds, or None; ``wind``: the true wind's world velocity (m/s, (3,)); ``vessels``: the
    ``VesselWind`` of each surface vessel (none without wind)."""

    def __init__(self, current=None, wind=None, vessels=()):
        self.current, self.wind, self.vessels = current, wind, list(vessels)
        self.steps = 0  # the current's steps taken

    def update(self, run, t: float, dt: float) -> None:
        """Step the current to time ``t`` (s; one exact step of ``dt`` per physics step, so that
        the step from t to t + dt reads the process's value at t), then set each vessel's wind
        load from its state now (``data.xfrc_applied``, held through the step)."""
        if self.current is not None:
            due = int(round(t / dt))
            while self.steps < due:
                self.current.step(dt)
                self.steps += 1
        if not self.vessels:
            return
        from mjtether.vehicles.wind import wind_load_world
        d = run.sim.data
        for v in self.vessels:
            nu, R = v.body.velocity(d)
            heading = math.atan2(R[1, 0], R[0, 0])
            v.load = wind_load_world(v.windage, self.wind, R @ nu[:3], heading)
            i = v.body.id
            force = np.array([v.load[0], v.load[1], 0.0])
            # Eq. 7's force at the origin, its moment about it: moved to the centre of mass, where
            # MuJoCo applies xfrc_applied
            d.xfrc_applied[i, :3] = force
            d.xfrc_applied[i, 3:] = np.cross(d.xpos[i] - d.xipos[i], force) + (0.0, 0.0, v.load[2])

    def summary(self) -> dict:
        """The weather now, for a report: the current's surface speed (m/s) and direction (deg)
        where it varies, and each vessel's last wind load (N, N m, world)."""
        out = {}
        if self.current is not None:
            out["current_speed_mps"] = float(self.current.speed)
            out["current_heading_deg"] = math.degrees(self.current.heading)
        for v in self.vessels:
            out[f"{v.label}_wind_load"] = [float(x) for x in v.load]
        return out


def driver_from(run) -> Weather | None:
    """The run's ``Weather`` (None where there is neither a Gauss-Markov current nor wind):
    the water column's current if it is a Gauss-Markov one, and the wind on every surface
    vessel; ConfigError for wind with no vessel to act on, or a vessel with no windage."""
    from mjtether.physics.gauss_markov import GaussMarkovCurrent
    from mjtether.vehicles.wind import wind_velocity
    sc, scene = run.sc, run.scene
    current = run.water.current if isinstance(run.water.current, GaussMarkovCurrent) else None
    wind = getattr(sc, "wind", None)
    vessels = []
    if wind is not None and wind.blowing:
        named = {getattr(b, "name", None): b for b in run.sim.bodies}
        if scene.vessel is not None:
            vessels.append(VesselWind("ship", named["ship"], windage_for(wind, sc.ship.vessel, "ship.vessel"),
                                      np.zeros(3)))
        if scene.vehicle is not None and scene.vehicle.hydro.surface is not None:
            from .scene import VEHICLE
            vessels.append(VesselWind("robot", named[VEHICLE], windage_for(wind, sc.robot.vehicle, "robot.vehicle"),
                                      np.zeros(3)))
        if not vessels:
            raise ConfigError(f"wind.speed = {wind.speed:g}: the wind load acts on a surface vessel (ship.vessel, or "
                              "a robot.vehicle with a [surface]); this scenario has none", "wind.speed")
    if current is None and not vessels:
        return None
    return Weather(current, wind_velocity(wind.speed, math.radians(wind.direction_deg)) if vessels else None, vessels)


def attach(run) -> Weather | None:
    """Put the run's ``Weather`` (``driver_from``) first among ``run.controllers`` (once; a run
    that has it already keeps it) and as ``run.weather``; returns it (None: no weather)."""
    have = getattr(run, "weather", None)
    if have is not None and have in run.controllers:
        return have
    run.weather = driver_from(run)
    if run.weather is not None:
        run.controllers.insert(0, run.weather)
    return run.weather
