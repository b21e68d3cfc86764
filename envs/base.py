"""What the two environments share: a scenario built afresh each episode (randomised current,
route or goal), the walker on the seabed at the end of a tether from a ship holding station at
the origin, stepping with ``frame_skip``, tether readouts, and ``render_mode="rgb_array"``
through ``mjtether.render``.

Frames: world, z up, surface z = 0, the ship's fairlead at the origin. Units SI.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields

import gymnasium as gym
import mujoco
import numpy as np

from mjtether.config import ConfigError, Section, param
from mjtether.runner import RunFailed, ScenarioRun
from mjtether.scenario import load_scenario
from mjtether.units import KNOT

CURRENT_DEPTHS = (0.05, 0.25, 0.75)
"""Depths, as fractions of the water depth, at which the current is observed."""

DEFAULT_CAMERA_CONFIG = {"camera": "track"}


@dataclass(frozen=True)
class TetherEnvConfig(Section):
    """The keyword arguments both environments take (SI units)."""

    depth: float = param(100.0, 5.0, 2000.0, "m", "depth of the seabed")
    tether_length: float = param(130.0, 1.0, 20000.0, "m", "deployed tether length at the start (spread by "
                                 "reset_noise_scale)")
    segments: int = param(30, 4, 400, "", "tether elements over tether_length")
    diameter: float = param(0.025, 1e-3, 0.5, "m", "tether diameter")
    cable_density: float = param(2500.0, 500.0, 20000.0, "kg/m^3", "tether bulk density")
    EA: float = param(5.0e6, 1e3, 1e12, "N", "tether axial stiffness")
    min_length: float | None = param(None, 0.0, 20000.0, "m", "shortest deployed length (None: depth + 5 m)",
                                     kind="float")
    max_length: float = param(300.0, 1.0, 20000.0, "m", "longest deployed length")
    max_rate: float = param(1.0, 0.01, 5.0, "m/s", "fastest payout or reel-in")
    rated_load: float = param(3000.0, 10.0, 1e8, "N", "rated load; the episode ends above it")
    current_max_kn: float = param(2.0, 0.0, 6.0, "kn", "largest surface current drawn")
    start_distance: float = param(40.0, 1.0, 10000.0, "m", "horizontal distance of the walker from the ship")
    timestep: float = param(0.01, 1e-4, 0.02, "s", "MuJoCo time step")
    frame_skip: int = param(10, 1, 1000, "", "MuJoCo steps per environment step")
    reset_noise_scale: float = param(0.05, 0.0, 0.5, "", "relative spread of the starting length")
    width: int = param(480, 16, 4096, "px", "rendered frame width")
    height: int = param(360, 16, 4096, "px", "rendered frame height")

    def _check(self):
        lo = self.depth + 5.0 if self.min_length is None else self.min_length
        if lo > self.tether_length:
            self._bad("min_length", f"{lo:g} m must be <= tether_length ({self.tether_length:g} m)"
                      + (" (the default is depth + 5 m)" if self.min_length is None else ""))
        if self.max_length < self.tether_length:
            self._bad("max_length", f"must be >= tether_length ({self.tether_length:g} m)")
        shortest = self.tether_length * (1.0 - self.reset_noise_scale)
        reach = math.hypot(self.start_distance, self.depth)
        if reach >= shortest:
            self._bad("start_distance", f"the walker {reach:.0f} m from the fairlead (start_distance, depth) is out "
                      f"of reach of the shortest starting tether, {shortest:.0f} m (tether_length x (1 - "
                      "reset_noise_scale))")


def kwargs_table(cls) -> str:
    """The keyword-argument table of an environment's docstring, from its ``Config``."""
    rows = [(f.name, repr(f.default), f.metadata["param"].allowed(), f.metadata["param"].doc) for f in fields(cls)]
    w = [max(len(r[k]) for r in rows + [("keyword", "default", "allowed", "meaning")]) for k in range(4)]
    line = "  ".join("=" * n for n in w)
    head = "  ".join(h.ljust(n) for h, n in zip(("keyword", "default", "allowed", "meaning"), w))
    body = ["  ".join(c.ljust(n) for c, n in zip(r, w)).rstrip() for r in rows]
    return "\n".join(["", "Keyword arguments (checked in the constructor):", "", line, head, line, *body, line, ""])


def _finite_action(action, n: int) -> np.ndarray:
    """The action as a float vector of ``n``, or a ValueError that names it."""
    try:
        a = np.asarray(action, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        raise ValueError(f"action must be {n} numbers in [-1, 1], got {action!r}") from None
    if a.shape != (n,) or not np.all(np.isfinite(a)):
        raise ValueError(f"action must be {n} finite numbers in [-1, 1], got {action!r}")
    return np.clip(a, -1.0, 1.0)


class TetherEnv(gym.Env):
    """Base class; subclasses define ``Config`` (a ``TetherEnvConfig`` with their own keys),
    ``_robot_section``, the spaces, ``_get_obs`` and the reward.

    Keyword arguments: those of ``Config`` (see its table in the subclass docstring, checked in
    the constructor: a bad one raises ``mjtether.config.ConfigError``, a ValueError, naming it),
    plus ``render_mode`` (None or "rgb_array") and ``default_camera_config`` ({"camera":
    "track" | "side" | "top" | "walker", "tension_scale": N}, see ``mjtether.render``).
    """

    metadata = {"render_modes": ["rgb_array"], "render_fps": 10}
    Config = TetherEnvConfig

    def __init__(self, *, render_mode: str | None = None, default_camera_config: dict | None = None, **kwargs):
        unknown = sorted(set(kwargs) - {f.name for f in fields(self.Config)})
        if unknown:
            raise ConfigError(f"{type(self).__name__}: unknown keyword argument {unknown[0]!r}; allowed: "
                              f"{', '.join(f.name for f in fields(self.Config))}, render_mode, default_camera_config",
                              unknown[0])
        try:
            self.config = cfg = self.Config(**kwargs)
        except ConfigError as exc:
            raise ConfigError(f"{type(self).__name__}: {exc}", exc.key) from None
        for f in fields(cfg):
            setattr(self, f.name, getattr(cfg, f.name))
        self.min_length = self.depth + 5.0 if cfg.min_length is None else cfg.min_length
        self.current_max = KNOT * cfg.current_max_kn
        if render_mode is not None and render_mode not in self.metadata["render_modes"]:
            raise ValueError(f"render_mode must be None or one of {self.metadata['render_modes']}, got {render_mode!r}")
        self.render_mode = render_mode
        self.camera_config = dict(DEFAULT_CAMERA_CONFIG, **(default_camera_config or {}))
        self.metadata = dict(self.metadata, render_fps=round(1.0 / self.dt))
        self.runner: ScenarioRun | None = None
        self._renderer = None

    @property
    def dt(self) -> float:
        """Simulated time per environment step (s)."""
        return self.timestep * self.frame_skip

    # ---------------------------------------------------------------- episode set-up

    def _robot_section(self, rng: np.random.Generator) -> dict:  # pragma: no cover - abstract
        raise NotImplementedError

    def _scenario(self, rng: np.random.Generator) -> dict:
        """The episode's scenario (a dict as a TOML file would give), randomised by ``rng``."""
        noise = self.reset_noise_scale
        length = self.tether_length * (1.0 + noise * rng.uniform(-1.0, 1.0))
        length = float(np.clip(length, self.min_length, self.max_length))
        return {
            # a steady-state start where one exists, else the cable settles with the walker held
            # (an episode steps until the agent stops, records nothing, and its length is the
            # TimeLimit's: the run-size limits of a scenario file do not apply)
            "simulation": {"timestep": self.timestep, "duration": 1e4, "output_interval": 1.0, "start": "auto",
                           "max_wall_hours": 1000.0, "max_output_gb": 1000.0},
            "water": {"depth": self.depth,
                      "current": {"type": "exponential", "surface_speed": float(rng.uniform(0.0, self.current_max)),
                                  "decay_depth": float(rng.uniform(10.0, 40.0)),
                                  "heading_deg": math.degrees(rng.uniform(-math.pi, math.pi))}},
            "tether": {"length": length, "segments": self.segments, "diameter": self.diameter,
                       "density": self.cable_density, "EA": self.EA, "rated_load": self.rated_load},
            "ship": {"mode": "fixed", "position": [0.0, 0.0]},
            "winch": {"mode": "external", "min_length": self.min_length, "max_length": self.max_length,
                      "max_rate": self.max_rate},
            "robot": self._robot_section(rng),
        }

    def _start_episode(self, seed):
        super().reset(seed=seed)
        self._close_sim()
        data = self._scenario(self.np_random)
        sc = load_scenario(data=data, name=type(self).__name__)
        self.runner = ScenarioRun(sc)
        self.broke = False
        self._prev_tow = self.tow_tension()

    def _advance(self) -> None:
        """``frame_skip`` physics steps; sets ``self.broke`` if the rated load was exceeded."""
        try:
            for _ in range(self.frame_skip):
                self.runner.step()
        except RunFailed:
            self.broke = True

    # ---------------------------------------------------------------- readouts

    def tow_tension(self) -> float:
        return self.runner.bt.end_tension(self.runner.sim.data, "end")

    def ship_tension(self) -> float:
        return self.runner.bt.end_tension(self.runner.sim.data, "start")

    def length_on_seabed(self) -> float:
        """Tether length lying on the seabed (m): elements with both nodes within a diameter."""
        return self.runner.length_on_seabed()

    def currents(self) -> np.ndarray:
        """Current (x, y) at the observed depths, flattened (m/s)."""
        z = -np.array(CURRENT_DEPTHS) * self.depth
        return self.runner.water.velocity(z)[:, :2].ravel()

    def at_length_limit(self) -> bool:
        w = self.runner.winch
        return w.length <= w.min_length + 1e-3 or w.length >= w.max_length - 1e-3

    def robot_kinematics(self):
        """(tow point (3,), yaw (rad), horizontal velocity (2,) in m/s, world frame)."""
        r = self.runner
        tow, yaw, _, _ = r.robot_state()
        vel = np.zeros(6)  # (angular, linear) of the torso frame, world axes
        mujoco.mj_objectVelocity(r.sim.model, r.sim.data, mujoco.mjtObj.mjOBJ_BODY, r.torso, vel, 0)
        return tow, yaw, vel[3:5].copy()

    # ---------------------------------------------------------------- rendering and closing

    def render(self):
        if self.render_mode is None:
            gym.logger.warn("render() called without a render_mode; pass render_mode='rgb_array'")
            return None
        if self.runner is None:
            raise RuntimeError("call reset() before render()")
        if self._renderer is None:
            from mjtether.render import FrameRenderer, VideoSettings

            settings = VideoSettings(self.width, self.height, fps=float(self.metadata["render_fps"]),
                                     camera=self.camera_config.get("camera", "track"),
                                     tension_scale=self.camera_config.get("tension_scale", self.rated_load))
            self._renderer = FrameRenderer(self.runner, settings)
        return self._renderer.render()

    def _close_sim(self) -> None:
        if self._renderer is not None:
            self._renderer.close()
            self._renderer = None
        if self.runner is not None:
            self.runner.close()
            self.runner = None

    def close(self):
        self._close_sim()
