"""``mjtether/TetheredSystem-v0``: fly one vehicle of a *system*, a network of lines, points,
bodies and vehicles (``mjtether.network``), to hold a station on its lines.

The system comes from a file (a network TOML file with ``[[lines]]``, or a MoorDyn file that
reads as a network, through ``mjtether.io.moordyn.load_any``; a shipped example by name, such as
``"networks/rov_cage_excursion"``), or is a ``mjtether.network.Network``. It is built as
``mjtether run`` builds it (``network.run.build``: the steady start; then ``network.run.settle``
where the file asks for settling), and the flown vehicle's autopilot is replaced by the agent's
commands (``AgentPilot``): every other vehicle flies on its own autopilot, and every line paying
out pays out as in the file. The default system, ``examples/networks/rov_cage_excursion.toml``:
a ship holds a cage 100 m down on a 100 m umbilical; the BlueROV2 Heavy ``rov`` flies from 12 m
off the cage on an excursion tether paying out at 0.1 m/s, to hold station 30 m from the cage,
in a 0.15 m/s current (at 100 m, towards +x).

Each reset returns to the steady start (the first build's state, restored exactly:
``Simulation.restore_state``; rebuilt instead where another vehicle's autopilot has a state of its
own, or after a divergence), with the station drawn within ``station_noise`` m of ``station``.

Action (``Box(-1, 1, (n,))``, n thrusters of the vehicle, 8 for the BlueROV2 Heavy): each
thruster's thrust as a fraction of its forward (action > 0) or reverse (action < 0) maximum (N);
each thruster lags its command with its time constant.

Observation (``Box``, float32, physical units, 11 + 2 L values for L lines; named element by element
in ``observation_names``; world frame, z up, unless said):

=========  ============================================================  ============
 0-2       the vehicle's origin less the station (m)                       unbounded
 3-5       its velocity (m/s)                                              unbounded
 6-8       its angular velocity in its own frame (x ahead, z up; rad/s)    unbounded
 9-10      sin, cos of its heading (from +x towards +y)                   [-1, 1]
 11+2k     line k's tension at its end A (kN), lines in the file's order   [0, inf)
 12+2k     line k's tension at its end B (kN)                              [0, inf)
=========  ============================================================  ============

The tensions are the magnitudes of ``NetworkRun.line_forces`` (the forces of the last step,
found at the state it began from, as ``mjtether run`` writes them).

Reward per step (``_get_rew``; its terms are in ``info``)::

    r = - w_distance * |p - station| / distance_ref              (reward_distance)
        - w_control  * mean(action^2)                              (reward_control)
        - w_tension  * sum over lines of max(0, T / T_rated - 1)   (reward_tension; T: the line's
                                                                    larger end tension)
        - failure_penalty on termination                           (reward_failure)

``T_rated``: ``rated_tension`` (N) for every line, or by default twice the largest end tension each
line reaches in the first ``RATING_PROBE_S`` (5) s from the start with the thrusters off (found
once, in the constructor: the start is no guide, as the default system's free cage starts where
the file puts it, its umbilical carrying 64 N of the cage's 4.8 kN wet weight, as its own
catenary, and all of it, 7.8 kN at the ship at the peak, within half a second; its rated
tensions come out 15.6 kN and 0.56 kN). The episode terminates when the simulation diverges
(``mjtether.simulation.SimulationDiverged``: ``info["diverged"]`` holds its message, and the
observation is the last finite one; reset before stepping again) or the vehicle is more than
``max_distance`` m from the station; it is truncated by ``max_episode_steps`` (600). ``info``
also holds the station, the distance to it, the vehicle's position, each line's end tensions (N)
and the time (s).

``render_mode="rgb_array"``: ``render()`` returns a (height, width, 3) uint8 frame from the video's
renderer (``mjtether.io.network_view``: every line coloured by tension, the camera framing the
whole system, its own headless OpenGL context), the station as a translucent green sphere.

Pickling keeps the constructor's keyword arguments, the random generator's state and ``spec``
(the unpickled environment builds its system again and must be ``reset()``).
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, fields

import gymnasium as gym
import numpy as np
from gymnasium import spaces

from mjtether.network import Network
from mjtether.network import run as network_run
from mjtether.scenario.config import ConfigError, Section, param
from mjtether.simulation import SimulationDiverged

from .base import PickledByKeywords, _finite_action, kwargs_table

DEFAULT_SYSTEM = "networks/rov_cage_excursion"
"""The default system: the shipped ``examples/networks/rov_cage_excursion.toml`` (by its shipped
name, so that it is found from any folder)."""


STATION_RADIUS = 0.5
"""The station's sphere in rendered frames (m)."""
STATION_RGBA = (0.1, 0.95, 0.2, 0.55)
"""The station's colour in rendered frames (translucent green, as ``TetheredROV-v0``'s target)."""
RATING_PROBE_S = 5.0
"""How long (s) the default rated tension's probe runs from the start with the thrusters off."""


@dataclass(frozen=True)
class TetheredSystemConfig(Section):
    """``TetheredSystem-v0``'s keyword arguments besides ``system`` (SI units)."""

    vehicle: str | None = param(None, kind="str", doc="the vehicle flown (None: the system's only vehicle)")
    station: tuple | None = param(None, -1e6, 1e6, "m", "(x, y, depth below the surface) held (None: the "
                                  "vehicle's station in the system)", kind="vec3")
    station_noise: float = param(0.0, 0.0, 1000.0, "m", "each reset draws the station uniformly within this "
                                 "distance of ``station``")
    rated_tension: float | None = param(None, 1e-3, 1e10, "N", "the tension term's rated tension for every line "
                                        "(None: twice the most each line carries in the first 5 s with the "
                                        "thrusters off)", kind="float")
    max_distance: float = param(100.0, 0.1, 1e5, "m", "the episode ends this far from the station")
    distance_ref: float = param(1.0, 0.01, 1e3, "m", "the reward's distance scale")
    w_distance: float = param(1.0, 0.0, 1e3, "", "weight of the distance from the station")
    w_control: float = param(0.05, 0.0, 1e3, "", "weight of the thrust asked for")
    w_tension: float = param(1.0, 0.0, 1e3, "", "weight of the tension above the rated tension")
    failure_penalty: float = param(50.0, 0.0, 1e6, "", "penalty on termination")
    frame_skip: int = param(20, 1, 1000, "", "MuJoCo steps per environment step")
    width: int = param(480, 16, 4096, "px", "rendered frame width")
    height: int = param(360, 16, 4096, "px", "rendered frame height")

    def _check(self):
        if self.station is not None and self.station[2] < 0:
            self._bad("station", "its depth (the third number, m below the surface) must be >= 0")


def load_system(system) -> tuple[Network, str]:
    """(the network, a name for messages) of ``system``: a ``Network``, or a path (or shipped
    example name) that ``load_any`` reads as one; anything else is a ValueError naming it."""
    if isinstance(system, Network):
        return system, f"network {system.name!r}"
    if not isinstance(system, (str, os.PathLike)):
        raise ValueError(f"system = {system!r}: must be a network file's path (TOML with [[lines]], or MoorDyn), "
                         "a shipped example's name or a mjtether.network.Network")
    from mjtether.io.moordyn import load_any

    try:
        net = load_any(system)
    except (OSError, ValueError) as exc:
        raise ValueError(f"system = {os.fspath(system)!r}: {exc}") from None
    if not isinstance(net, Network):
        raise ValueError(f"system = {os.fspath(system)!r}: is a single-tether scenario (one tether from a ship to a "
                         "robot), not a network; give a network file (with [[lines]]: examples/networks/), or use "
                         "mjtether/TetheredROV-v0")
    return net, f"system {os.fspath(system)!r}"


class AgentPilot:
    """Stands in for the flown vehicle's autopilot in ``NetworkRun.pilots``: ``update`` (called
    before each step by ``NetworkRun.advance``) writes ``thrust`` (N, one per thruster) to the
    thrusters' actuators."""

    def __init__(self, actuators: np.ndarray):
        self.actuators = actuators
        self.thrust = np.zeros(len(actuators))

    def update(self, run, t: float, dt: float) -> None:
        run.sim.data.ctrl[self.actuators] = self.thrust


class TetheredSystemEnv(PickledByKeywords, gym.Env):
    """See the module docstring."""

    metadata = {"render_modes": ["rgb_array"], "render_fps": 10}
    Config = TetheredSystemConfig

    def __init__(self, system=DEFAULT_SYSTEM, *, render_mode: str | None = None, **kwargs):
        names = [f.name for f in fields(self.Config)]
        unknown = sorted(set(kwargs) - set(names))
        if unknown:
            raise ConfigError(f"{type(self).__name__}: unknown keyword argument {unknown[0]!r}; allowed: system, "
                              f"{', '.join(names)}, render_mode", unknown[0])
        self._init_kwargs = dict(kwargs, system=system, render_mode=render_mode)
        try:
            self.config = cfg = self.Config(**kwargs)
        except ConfigError as exc:
            raise ConfigError(f"{type(self).__name__}: {exc}", exc.key) from None
        for f in fields(cfg):
            setattr(self, f.name, getattr(cfg, f.name))
        if render_mode is not None and render_mode not in self.metadata["render_modes"]:
            raise ValueError(f"render_mode must be None or one of {self.metadata['render_modes']}, got {render_mode!r}")
        self.render_mode = render_mode
        self.net, where = load_system(system)
        vehicles = list(self.net.vehicles)
        if not vehicles:
            raise ValueError(f"{where} has no vehicle to fly ([vehicles.NAME]; a MoorDyn file holds none)")
        if self.vehicle is None:
            if len(vehicles) > 1:
                raise ValueError(f"vehicle: {where} has {len(vehicles)} vehicles; choose one: {', '.join(vehicles)}")
            self.vehicle = vehicles[0]
        elif self.vehicle not in vehicles:
            raise ValueError(f"vehicle = {self.vehicle!r} is not a vehicle of {where}; its vehicles: "
                             f"{', '.join(vehicles)}")
        v = self.net.vehicles[self.vehicle]
        self.thrusters = v.spec.thrusters
        if not self.thrusters:
            raise ValueError(f"vehicle = {self.vehicle!r} ({v.vehicle}) has no thrusters to command")
        self._max_fwd = np.array([t.max_forward for t in self.thrusters])
        self._max_rev = np.array([t.max_reverse for t in self.thrusters])
        self.line_names = tuple(ln.name for ln in self.net.lines)
        self.home = np.array(self.station if self.station is not None else v.station, dtype=float)  # x, y, depth
        self.runner = None
        self._renderer = None
        self.diverged: str | None = None  # the message of the divergence that ended the episode
        self._build()
        self.rated = (np.full(len(self.line_names), self.rated_tension) if self.rated_tension is not None
                      else self._probe_rating(where))
        n, L = len(self.thrusters), len(self.line_names)
        lo = np.r_[np.full(9, -np.inf), -1.0, -1.0, np.zeros(2 * L)].astype(np.float32)
        hi = np.r_[np.full(9, np.inf), 1.0, 1.0, np.full(2 * L, np.inf)].astype(np.float32)
        self.observation_space = spaces.Box(lo, hi, dtype=np.float32)
        self.action_space = spaces.Box(-1.0, 1.0, (n,), dtype=np.float32)
        name = self.vehicle
        self.observation_names = (
            *(f"{name} {k} - station {k} m" for k in "xyz"), *(f"{name} v{k} m/s" for k in "xyz"),
            *(f"{name} w{k} rad/s (its frame)" for k in "xyz"), f"{name} sin heading", f"{name} cos heading",
            *(f"line {ln} {end} tension kN" for ln in self.line_names for end in "AB"))
        self.metadata = dict(self.metadata, render_fps=max(1, round(1.0 / self.dt)))
        self.station_now = self._station_world(self.home)
        self._last_obs = None

    # ---------------------------------------------------------------- building and restoring

    def _build(self) -> None:
        """Build the system at its steady start (settled where it asks to be, as ``mjtether run``
        does), put ``AgentPilot`` in the flown vehicle's place and keep the start's state."""
        self._close_sim()
        r = network_run.build(self.net)
        if self.net.settle > 0 and self.net.start == "steady":
            network_run.settle(r, self.net.settle)
        for bt in r.sim.tethers.values():  # (the settling's pushes are not the episode's)
            bt.clear_peak_compression()
        acts = np.array([r.sim.model.actuator(f"body/{self.vehicle}/{t.name}").id for t in self.thrusters], dtype=int)
        self.pilot = AgentPilot(acts)
        r.pilots[self.vehicle] = self.pilot
        r.sim.data.ctrl[acts] = 0.0
        self.runner = r
        self._start = r.sim.save_state()  # (each drum's payout with it: ``Drum.payout_state``)
        # another vehicle's autopilot keeps integrals of its own, which a restore does not reset
        self._restorable = len(r.pilots) == 1

    def _probe_rating(self, where: str) -> np.ndarray:
        """Twice the largest end tension (N) each line reaches in the first ``RATING_PROBE_S`` s
        from the start with the thrusters off (the default ``rated_tension``); then back to the
        start."""
        peak = self.line_tensions().max(axis=1, initial=0.0)
        try:
            for _ in range(max(1, round(RATING_PROBE_S / self.dt))):
                self.runner.advance(self.frame_skip)
                peak = np.maximum(peak, self.line_tensions().max(axis=1, initial=0.0))
        except SimulationDiverged as exc:
            raise ValueError(f"{where}: the simulation diverges within {RATING_PROBE_S:g} s of its start with "
                             f"vehicle {self.vehicle!r}'s thrusters off ({exc})") from None
        self._restore()
        return 2.0 * np.maximum(peak, 1e-3)

    def _restore(self) -> None:
        """Back to the steady start: restored exactly where it can be, else built again."""
        if not self._restorable or self.diverged is not None:
            self._build()
            return
        sim = self.runner.sim
        sim.restore_state(self._start)
        self.pilot.thrust[:] = 0.0
        # twice: the first brings the added mass's orientation, which the force providers set in the
        # model from the state as they run (``wrap_prm``), to the restored state; the second finds
        # the forces with it, bit for bit as at the first build (measured; once, tensions 1.5 % off)
        sim.forward()
        sim.forward()

    @property
    def dt(self) -> float:
        """Simulated time per environment step (s): the system's time step x ``frame_skip``."""
        return self.runner.timestep * self.frame_skip

    def _station_world(self, station) -> np.ndarray:
        return np.array([station[0], station[1], -station[2]], dtype=float)

    # ---------------------------------------------------------------- gymnasium API

    def reset(self, *, seed=None, options=None):
        super().reset(seed=seed)
        self._restore()
        self.diverged = None
        st = self.home.copy()
        if self.station_noise > 0:
            u = self.np_random.normal(size=3)
            u *= self.station_noise * float(self.np_random.uniform()) ** (1.0 / 3.0) / max(np.linalg.norm(u), 1e-12)
            st = st + np.array([u[0], u[1], -u[2]])
            st[2] = max(st[2], 0.0)
        self.station_now = self._station_world(st)
        self._last_obs = obs = self._get_obs()
        return obs, self._info({})

    def step(self, action):
        if self.runner is None:
            raise RuntimeError("call reset() before step()")
        if self.diverged is not None:
            raise RuntimeError(f"the simulation diverged ({self.diverged}); call reset()")
        a = _finite_action(action, len(self.thrusters))
        self.pilot.thrust[:] = np.where(a >= 0.0, a * self._max_fwd, a * self._max_rev)
        try:
            self.runner.advance(self.frame_skip)
            obs = self._get_obs()
            if not np.all(np.isfinite(obs)):
                raise SimulationDiverged(f"a non-finite observation at t = {self.runner.sim.time:.4f} s")
        except SimulationDiverged as exc:
            self.diverged = str(exc)
            obs = self._last_obs
        self._last_obs = obs
        terminated = bool(self.diverged is not None or self._distance() > self.max_distance)
        reward, terms = self._get_rew(a, terminated)
        return obs, reward, terminated, False, self._info(terms)

    def _get_rew(self, action: np.ndarray, terminated: bool) -> tuple[float, dict]:
        """(reward, its terms by name): see the module docstring."""
        distance, over = 0.0, 0.0  # (after a divergence the state is not the system's: no terms from it)
        if self.diverged is None:
            distance = self._distance()
            over = float(np.sum(np.maximum(self.line_tensions().max(axis=1, initial=0.0) / self.rated - 1.0, 0.0)))
        terms = {
            "reward_distance": -self.w_distance * distance / self.distance_ref,
            "reward_control": -self.w_control * float(np.mean(action * action)),
            "reward_tension": -self.w_tension * over,
            "reward_failure": -self.failure_penalty if terminated else 0.0,
        }
        return float(sum(terms.values())), terms

    # ---------------------------------------------------------------- readouts

    def line_tensions(self) -> np.ndarray:
        """Each line's tension at its ends A and B (N), shape (lines, 2), in the file's order."""
        r = self.runner
        return np.array([[np.linalg.norm(f) for f in r.line_forces(n)] for n in self.line_names]).reshape(-1, 2)

    def vehicle_state(self):
        """(origin (3,) m, R body to world, velocity (3,) m/s, angular velocity (3,) rad/s in its
        frame), at ``sim.time``."""
        r = self.runner
        body = r.vehicle_bodies[self.vehicle]
        now = r.poses_now()
        nu, R_last = body.velocity(r.sim.data)  # (R_last: the last step's kinematics, as nu's frame)
        return now.xpos[body.id].copy(), now.xmat[body.id].reshape(3, 3).copy(), R_last @ nu[:3], nu[3:].copy()

    def _distance(self) -> float:
        return float(np.linalg.norm(self.vehicle_state()[0] - self.station_now))

    def _get_obs(self) -> np.ndarray:
        p, R, v, w = self.vehicle_state()
        yaw = math.atan2(R[1, 0], R[0, 0])
        return np.array([*(p - self.station_now), *v, *w, math.sin(yaw), math.cos(yaw),
                         *(self.line_tensions().ravel() / 1000.0)], dtype=np.float32)

    def _info(self, terms: dict) -> dict:
        out = {**terms, "station": self.station_now.copy(), "time": float(self.runner.sim.time),
               "diverged": self.diverged}
        if self.diverged is None:
            out.update(distance=self._distance(), position=self.vehicle_state()[0],
                       line_tensions={n: tuple(t) for n, t in zip(self.line_names, self.line_tensions())})
        return out

    # ---------------------------------------------------------------- rendering, pickling, closing

    def render(self):
        if self.render_mode is None:
            gym.logger.warn("render() called without a render_mode; pass render_mode='rgb_array'")
            return None
        import mujoco

        from mjtether.io.network_view import NetworkView
        from mjtether.io.render import FrameRenderer, Marker, VideoSettings

        if self._renderer is None:  # (the video's renderer: it makes its own headless OpenGL context)
            self._renderer = FrameRenderer(NetworkView(self.runner),
                                           VideoSettings(width=self.width, height=self.height, camera="track"))
        self._renderer.markers = [Marker(tuple(self.station_now), (STATION_RADIUS,) * 3, STATION_RGBA,
                                         mujoco.mjtGeom.mjGEOM_SPHERE)]
        return self._renderer.render().copy()

    def _close_sim(self) -> None:
        if self._renderer is not None:
            self._renderer.close()
            self._renderer = None
        if self.runner is not None:
            self.runner.sim.close()
            self.runner = None

    def close(self):
        self._close_sim()


TetheredSystemEnv.__doc__ += ("\n\nKeyword arguments: ``system`` (default ``\"networks/rov_cage_excursion\"``: "
                              "see the module docstring), ``render_mode`` (None or \"rgb_array\") and\n"
                              + kwargs_table(TetheredSystemConfig).split("\nAlso ")[0])
