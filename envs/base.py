"""What the two environments share: a scenario built afresh each episode (randomised current,
route or goal), the walker on the seabed at the end of a tether from a ship holding station at
the origin, stepping with ``frame_skip``, tether readouts, and ``render_mode="rgb_array"``
through ``mjtether.render``.

Frames: world, z up, surface z = 0, the ship's fairlead at the origin. Units SI.
"""

from __future__ import annotations

import math

import gymnasium as gym
import mujoco
import numpy as np

from mjtether.runner import RunFailed, ScenarioRun
from mjtether.scenario import ScenarioError, load_scenario
from mjtether.units import KNOT

CURRENT_DEPTHS = (0.05, 0.25, 0.75)
"""Depths, as fractions of the water depth, at which the current is observed."""

DEFAULT_CAMERA_CONFIG = {"camera": "track"}


def _check(name: str, value, lo: float, hi: float, unit: str = "") -> float:
    v = float(value)
    if not (math.isfinite(v) and lo <= v <= hi):
        raise ValueError(f"{name} must be in [{lo:g}, {hi:g}]{' ' + unit if unit else ''}, got {value!r}")
    return v


class TetherEnv(gym.Env):
    """Base class; subclasses define ``_robot_section``, the spaces, ``_get_obs`` and the reward.

    Keyword arguments (SI units): ``depth`` of the seabed; the tether's starting
    ``tether_length``, ``segments``, ``diameter``, ``cable_density`` and ``EA``; the winch's
    ``min_length`` (default depth + 5 m), ``max_length`` and ``max_rate``; the tether's
    ``rated_load`` (N, the episode ends above it); ``current_max_kn`` (largest surface current
    drawn); ``start_distance`` of the walker from the ship; MuJoCo's ``timestep`` and
    ``frame_skip`` steps per environment step; ``reset_noise_scale`` (relative spread of the
    starting length); ``render_mode`` (None or "rgb_array"), ``width``, ``height`` and
    ``default_camera_config`` ({"camera": "track" | "side" | "top" | "walker",
    "tension_scale": N}, see ``mjtether.render``).
    """

    metadata = {"render_modes": ["rgb_array"], "render_fps": 10}

    def __init__(self, *, depth: float = 100.0, tether_length: float = 130.0, segments: int = 30,
                 diameter: float = 0.025, cable_density: float = 2500.0, EA: float = 5.0e6,
                 min_length: float | None = None, max_length: float = 300.0, max_rate: float = 1.0,
                 rated_load: float = 3000.0, current_max_kn: float = 2.0, start_distance: float = 40.0,
                 timestep: float = 0.01, frame_skip: int = 10, reset_noise_scale: float = 0.05,
                 render_mode: str | None = None, width: int = 480, height: int = 360,
                 default_camera_config: dict | None = None):
        self.depth = _check("depth", depth, 5.0, 2000.0, "m")
        self.tether_length = _check("tether_length", tether_length, 1.0, 20000.0, "m")
        if not (isinstance(segments, int) and 2 <= segments <= 400):
            raise ValueError(f"segments must be an integer in [2, 400], got {segments!r}")
        self.segments = segments
        self.diameter = _check("diameter", diameter, 1e-3, 0.5, "m")
        self.cable_density = _check("cable_density", cable_density, 500.0, 20000.0, "kg/m^3")
        self.EA = _check("EA", EA, 1e3, 1e12, "N")
        self.min_length = _check("min_length", self.depth + 5.0 if min_length is None else min_length, 0.0,
                                 self.tether_length, "m")
        self.max_length = _check("max_length", max_length, self.tether_length, 20000.0, "m")
        self.max_rate = _check("max_rate", max_rate, 0.01, 5.0, "m/s")
        self.rated_load = _check("rated_load", rated_load, 10.0, 1e8, "N")
        self.current_max = KNOT * _check("current_max_kn", current_max_kn, 0.0, 6.0, "kn")
        self.start_distance = _check("start_distance", start_distance, 1.0, 10000.0, "m")
        self.timestep = _check("timestep", timestep, 1e-4, 0.02, "s")
        if not (isinstance(frame_skip, int) and 1 <= frame_skip <= 1000):
            raise ValueError(f"frame_skip must be an integer in [1, 1000], got {frame_skip!r}")
        self.frame_skip = frame_skip
        self.reset_noise_scale = _check("reset_noise_scale", reset_noise_scale, 0.0, 0.5)
        if render_mode is not None and render_mode not in self.metadata["render_modes"]:
            raise ValueError(f"render_mode must be None or one of {self.metadata['render_modes']}, got {render_mode!r}")
        self.render_mode = render_mode
        self.width, self.height = width, height
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
            "simulation": {"timestep": self.timestep, "duration": 1e5, "output_interval": self.dt, "start": "auto"},
            "water": {"depth": self.depth,
                      "current": {"type": "exponential", "surface_speed": float(rng.uniform(0.0, self.current_max)),
                                  "decay_depth": float(rng.uniform(10.0, 40.0)),
                                  "heading": float(rng.uniform(-math.pi, math.pi))}},
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
        try:
            sc = load_scenario(data=data, name=type(self).__name__)
        except ScenarioError as exc:
            raise ValueError(str(exc)) from None
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
