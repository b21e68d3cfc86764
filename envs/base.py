"""What the two environments share: a scenario built afresh each episode (randomised current,
route or goal), the walker on the seabed at the end of a tether from a ship holding station at
the origin, stepping with ``frame_skip``, tether readouts, rendering (``render_mode="rgb_array"``
through ``mjtether.io.render``, ``"human"`` through MuJoCo's passive viewer; ``camera_name`` /
``camera_id`` as in Gymnasium's MuJoCo environments) and pickling.

Frames: world, z up, surface z = 0, the ship's fairlead at the origin. Units SI.
"""

from __future__ import annotations

import functools
import math
import os
import sys
import time
from dataclasses import dataclass, fields

import gymnasium as gym
import numpy as np

from mjtether.io.render import CAMERAS, Marker, RenderUnavailable, model_camera_id, tension_colours
from mjtether.scenario import load_scenario
from mjtether.scenario.config import ConfigError, Section, param
from mjtether.scenario.runner import RunFailed, ScenarioRun
from mjtether.units import KNOT

CURRENT_DEPTHS = (0.05, 0.25, 0.75)
"""Depths, as fractions of the water depth, at which the current is observed."""

DEFAULT_CAMERA_CONFIG = {"camera": "track"}
CAMERA_CONFIG_KEYS = ("camera", "tension_scale")
NO_DISPLAY = "render_mode='human' needs a display; use render_mode='rgb_array'"


@functools.cache
def model_cameras() -> tuple[str, ...]:
    """The cameras of the environments' MuJoCo model, in id order (the walker's, prefixed
    ``walker/``: its model is the only part of the scene that has cameras)."""
    from mjtether.walker import walker_spec

    return tuple(f"walker/{c.name}" for c in walker_spec().cameras)


def has_display() -> bool:
    """Whether a window can be opened: DISPLAY or WAYLAND_DISPLAY set (macOS and Windows: always)."""
    return sys.platform in ("darwin", "win32") or bool(os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY"))


def usable_render_modes(modes) -> list[str]:
    """The render modes of ``modes`` that work on this machine now: all of them, less ``"human"``
    where there is no display (``has_display``). An instance's ``metadata["render_modes"]``: what
    Gymnasium's ``check_env`` builds and renders; the class's lists every mode it implements."""
    return [m for m in modes if m != "human" or has_display()]


def check_camera_config(config: dict | None) -> dict:
    """``default_camera_config`` with its defaults, or a ValueError naming the bad entry."""
    config = {} if config is None else config
    if isinstance(config, str):
        raise ValueError(f"default_camera_config = {config!r}: must be a dict, as in Gymnasium's MuJoCo environments "
                         f"(default_camera_config={{'camera': {config!r}}}; keys {', '.join(CAMERA_CONFIG_KEYS)}), "
                         f"or give camera_name={config!r}")
    if not isinstance(config, dict):
        raise ValueError(f"default_camera_config = {config!r}: must be a dict with keys "
                         f"{', '.join(CAMERA_CONFIG_KEYS)}, or None")
    unknown = sorted(set(config) - set(CAMERA_CONFIG_KEYS))
    if unknown:
        raise ValueError(f"default_camera_config: unknown key {unknown[0]!r}; allowed: {', '.join(CAMERA_CONFIG_KEYS)}")
    out = dict(DEFAULT_CAMERA_CONFIG, **config)
    if out["camera"] not in CAMERAS:
        raise ValueError(f"default_camera_config['camera'] must be one of {', '.join(CAMERAS)}; got {out['camera']!r}")
    scale = out.get("tension_scale")
    if scale is not None and not (isinstance(scale, (int, float)) and not isinstance(scale, bool) and scale > 0):
        raise ValueError(f"default_camera_config['tension_scale'] must be a number > 0 (N), got {scale!r}")
    return out


def select_camera(camera_name, camera_id, default_view: str) -> tuple[str, str | None]:
    """(renderer view, model camera or None) for Gymnasium's ``camera_name`` / ``camera_id``.

    ``camera_name``: a view of ``mjtether.io.render`` ("track", "side", "top", "walker") or a
    camera of the model ("walker/track", "walker/front"). ``camera_id``: a camera of the model
    by id, or -1 for the default view (``default_camera_config["camera"]``). At most one."""
    views, cams = ", ".join(map(repr, CAMERAS)), ", ".join(map(repr, model_cameras()))
    if camera_name is not None and camera_id is not None:
        raise ValueError("camera_name and camera_id cannot both be given (as in Gymnasium's MuJoCo environments)")
    if camera_name is not None:
        if camera_name in CAMERAS:
            return camera_name, None
        if camera_name in model_cameras():
            return default_view, camera_name
        raise ValueError(f"camera_name must be one of the renderer's views ({views}) or a camera of the model "
                         f"({cams}); got {camera_name!r}")
    if camera_id is not None:
        ok = isinstance(camera_id, (int, np.integer)) and not isinstance(camera_id, bool)
        if ok and camera_id == -1:
            return default_view, None
        if ok and 0 <= camera_id < len(model_cameras()):
            return default_view, model_cameras()[camera_id]
        ids = ", ".join(f"{i} ({n!r})" for i, n in enumerate(model_cameras()))
        raise ValueError(f"camera_id must be -1 (the default view, default_camera_config['camera'] = "
                         f"{default_view!r}) or the id of a camera of the model: {ids}; got {camera_id!r}")
    return default_view, None


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
    extra = ("Also ``render_mode`` (None, \"rgb_array\", \"depth_array\" or \"human\"), ``camera_name``, ``camera_id`` and "
             "``default_camera_config``: see ``TetherEnv``.")
    return "\n".join(["", "Keyword arguments (checked in the constructor):", "", line, head, line, *body, line, "",
                      extra, ""])


def _finite_action(action, n: int) -> np.ndarray:
    """The action as a float vector of ``n``, or a ValueError that names it."""
    try:
        a = np.asarray(action, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        raise ValueError(f"action must be {n} numbers in [-1, 1], got {action!r}") from None
    if a.shape != (n,) or not np.all(np.isfinite(a)):
        raise ValueError(f"action must be {n} finite numbers in [-1, 1], got {action!r}")
    return np.clip(a, -1.0, 1.0)


class PickledByKeywords:
    """Pickling for an environment whose state is its MuJoCo run: it keeps the constructor's
    keyword arguments (``_init_kwargs``), the random generator's state and ``spec``; the
    unpickled environment builds its run again (and must be ``reset()``)."""

    def __getstate__(self) -> dict:
        return {"kwargs": dict(self._init_kwargs), "np_random": self._np_random,
                "np_random_seed": self._np_random_seed, "spec": self.spec}

    def __setstate__(self, state: dict) -> None:
        type(self).__init__(self, **state["kwargs"])
        self._np_random, self._np_random_seed = state["np_random"], state["np_random_seed"]
        self.spec = state["spec"]


class TetherEnv(PickledByKeywords, gym.Env):
    """Base class; subclasses define ``Config`` (a ``TetherEnvConfig`` with their own keys),
    ``_robot_section``, the spaces, ``_get_obs`` and the reward.

    Keyword arguments: those of ``Config`` (see its table in the subclass docstring, checked in
    the constructor: a bad one raises ``mjtether.scenario.config.ConfigError``, a ValueError, naming it),
    plus, as in Gymnasium's MuJoCo environments (all checked in the constructor, a ValueError
    listing what is allowed):

    * ``render_mode``: None, ``"rgb_array"`` (``render()`` returns a frame (height, width, 3)
      uint8, drawn offscreen by ``mjtether.io.render``: no display needed) or ``"human"`` (a window,
      MuJoCo's passive viewer, updated on every ``reset`` and ``step`` and paced to real time;
      without a display, DISPLAY or WAYLAND_DISPLAY, the constructor raises
      ``mjtether.io.render.RenderUnavailable``, a RuntimeError, and the instance's
      ``metadata["render_modes"]`` leaves ``"human"`` out, so that Gymnasium's ``check_env``, which
      builds every mode listed there, passes on a headless machine; the class's ``metadata`` lists
      all three), or ``"depth_array"`` (``render()``
      returns (height, width) float32, the distance in m from the camera along its viewing axis
      to the first surface, as Gymnasium's MuJoCo environments give it; the physical objects
      only: no water surface, current arrows or goal marker).
    * ``default_camera_config``: {"camera": "track" | "side" | "top" | "walker", "tension_scale":
      N}: the renderer's view (see ``mjtether.io.render``) and the top of the tether's tension
      colour scale (default: the rated load). Other keys are refused (Gymnasium's free-camera
      keys, such as ``distance``, do not apply: the views place the camera themselves).
    * ``camera_name``: one of the renderer's views above, or a camera of the MuJoCo model
      (``model_cameras()``: "walker/track", "walker/front"); it overrides
      ``default_camera_config["camera"]``.
    * ``camera_id``: the id of a camera of the model (0: "walker/track", 1: "walker/front"), or
      -1 for the default view. At most one of ``camera_name`` and ``camera_id``.

    A ``TetheredWalker-v0`` frame shows the goal as a translucent green column (``goal_marker``),
    drawn into the scene only: the physics is the same with and without rendering.

    Pickling (``pickle``, ``copy.deepcopy``, a vector environment's ``spawn`` context) keeps the
    constructor's keyword arguments, the random generator's state and ``spec``, and drops the
    simulation, renderer and viewer: an unpickled environment must be ``reset()`` before
    ``step()`` (an episode in progress is not carried over). Its ``reset()`` without a seed
    draws the same episode as the original's next ``reset()`` would.
    """

    metadata = {"render_modes": ["human", "rgb_array", "depth_array"], "render_fps": 10}
    Config = TetherEnvConfig

    def __init__(self, *, render_mode: str | None = None, default_camera_config: dict | None = None,
                 camera_name: str | None = None, camera_id: int | None = None, **kwargs):
        unknown = sorted(set(kwargs) - {f.name for f in fields(self.Config)})
        if unknown:
            raise ConfigError(f"{type(self).__name__}: unknown keyword argument {unknown[0]!r}; allowed: "
                              f"{', '.join(f.name for f in fields(self.Config))}, render_mode, camera_name, "
                              "camera_id, default_camera_config", unknown[0])
        check_camera_config(default_camera_config)  # (before anything uses it: a str is refused, naming it)
        # what pickling keeps (see the class docstring)
        self._init_kwargs = dict(kwargs, render_mode=render_mode, camera_name=camera_name, camera_id=camera_id,
                                 default_camera_config=None if default_camera_config is None
                                 else dict(default_camera_config))
        try:
            self.config = cfg = self.Config(**kwargs)
        except ConfigError as exc:
            raise ConfigError(f"{type(self).__name__}: {exc}", exc.key) from None
        for f in fields(cfg):
            setattr(self, f.name, getattr(cfg, f.name))
        if hasattr(cfg, "min_length"):  # (TetheredROV-v0's umbilical has a fixed length)
            self.min_length = self.depth + 5.0 if cfg.min_length is None else cfg.min_length
        self.current_max = KNOT * cfg.current_max_kn
        if render_mode is not None and render_mode not in self.metadata["render_modes"]:
            raise ValueError(f"render_mode must be None or one of {self.metadata['render_modes']}, got {render_mode!r}")
        if render_mode == "human" and not has_display():
            raise RenderUnavailable(f"{NO_DISPLAY} (neither DISPLAY nor WAYLAND_DISPLAY is set)")
        self.render_mode = render_mode
        self.camera_config = check_camera_config(default_camera_config)
        self.camera_name, self.camera_id = camera_name, camera_id
        self._view, self._model_camera = select_camera(camera_name, camera_id, self.camera_config["camera"])
        self.metadata = dict(self.metadata, render_fps=round(1.0 / self.dt),
                             render_modes=usable_render_modes(type(self).metadata["render_modes"]))
        self.runner: ScenarioRun | None = None
        self._renderer = None
        self._viewer = None  # render_mode "human": MuJoCo's passive viewer of the current runner
        self._viewer_runner = None
        self._last_frame = 0.0  # wall-clock time of the last "human" frame

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
        return self.runner.named.tow_tension

    def ship_tension(self) -> float:
        return self.runner.named.ship_tension

    def length_on_seabed(self) -> float:
        """Tether length lying on the seabed (m): elements with both nodes within a diameter."""
        return self.runner.named.length_on_seabed()

    def currents(self) -> np.ndarray:
        """Current (x, y) at the observed depths, flattened (m/s)."""
        z = -np.array(CURRENT_DEPTHS) * self.depth
        return self.runner.named.current_at(z)[:, :2].ravel()

    def at_length_limit(self) -> bool:
        w = self.runner.winch
        return w.length <= w.min_length + 1e-3 or w.length >= w.max_length - 1e-3

    def robot_kinematics(self):
        """(tow point (3,), yaw (rad), horizontal velocity (2,) in m/s, world frame)."""
        n = self.runner.named
        return n.robot_position, n.robot_heading, n.robot_velocity

    # ---------------------------------------------------------------- rendering and closing

    def render_markers(self) -> list[Marker]:
        """Geoms drawn into each frame only (none here; ``TetheredWalker-v0``: the goal)."""
        return []

    def render(self):
        if self.render_mode is None:
            gym.logger.warn("render() called without a render_mode; pass render_mode='rgb_array'")
            return None
        if self.runner is None:
            raise RuntimeError("call reset() before render()")
        if self.render_mode == "human":
            return self._render_human()
        if self._renderer is None:
            from mjtether.io.render import FrameRenderer, VideoSettings

            settings = VideoSettings(self.width, self.height, fps=float(self.metadata["render_fps"]),
                                     camera=self._view,
                                     tension_scale=self.camera_config.get("tension_scale", self.rated_load))
            self._renderer = FrameRenderer(self.runner, settings, fixed_camera=self._model_camera)
        if self.render_mode == "depth_array":
            return self._renderer.render_depth().copy()
        self._renderer.markers = self.render_markers()
        # (the renderer returns a view of its own buffer, which the next frame overwrites)
        return self._renderer.render().copy()

    def _human_frame(self) -> None:
        """``render_mode="human"``: called at the end of ``reset`` and ``step``."""
        if self.render_mode == "human":
            self.render()

    def _render_human(self) -> None:
        """Show the state in MuJoCo's passive viewer (a new window for each episode's model),
        with the tether coloured by tension and the markers, paced to ``dt`` per frame."""
        import mujoco.viewer

        r = self.runner
        if self._viewer is not None and (self._viewer_runner is not r or not self._viewer.is_running()):
            self._close_viewer()
        v = self._viewer
        if v is None:
            m = r.sim.model
            self._viewer = v = mujoco.viewer.launch_passive(m, r.sim.data)
            self._viewer_runner = r
            if self._model_camera is not None or self._view == "walker":
                v.cam.type = mujoco.mjtCamera.mjCAMERA_FIXED
                v.cam.fixedcamid = model_camera_id(m, self._model_camera or "walker/track")
            else:  # track (side, top: from further away): follow the walker
                v.cam.type = mujoco.mjtCamera.mjCAMERA_TRACKING
                v.cam.trackbodyid = r.torso
                v.cam.distance = {"track": 9.0, "side": 60.0, "top": 60.0}[self._view]
                v.cam.azimuth, v.cam.elevation = {"track": (135.0, -20.0), "side": (90.0, -5.0),
                                                  "top": (90.0, -89.9)}[self._view]
        x = r.named.tether_nodes
        colours = tension_colours(r.named.tether_tension, self.camera_config.get("tension_scale", self.rated_load))
        with v.lock():
            scn = v.user_scn
            scn.ngeom = 0
            for i, rgba in enumerate(colours):
                if scn.ngeom >= scn.maxgeom:
                    break
                g = scn.geoms[scn.ngeom]
                mujoco.mjv_initGeom(g, mujoco.mjtGeom.mjGEOM_CAPSULE, np.zeros(3), np.zeros(3), np.eye(3).ravel(),
                                    np.asarray(rgba, np.float32))
                mujoco.mjv_connector(g, mujoco.mjtGeom.mjGEOM_CAPSULE, max(r.contact_diameter, 0.05), x[i],
                                     x[i + 1])
                scn.ngeom += 1
            for mk in self.render_markers():
                if scn.ngeom >= scn.maxgeom:
                    break
                mujoco.mjv_initGeom(scn.geoms[scn.ngeom], mk.gtype, np.asarray(mk.size, float),
                                    np.asarray(mk.pos, float), np.eye(3).ravel(), np.asarray(mk.rgba, np.float32))
                scn.ngeom += 1
        v.sync()
        wait = self._last_frame + self.dt - time.perf_counter()
        if wait > 0:
            time.sleep(wait)
        self._last_frame = time.perf_counter()
        return None

    def _close_viewer(self) -> None:
        if self._viewer is not None:
            self._viewer.close()
            self._viewer = None
            self._viewer_runner = None

    def _close_sim(self) -> None:
        self._close_viewer()  # (it shows this episode's model)
        if self._renderer is not None:
            self._renderer.close()
            self._renderer = None
        if self.runner is not None:
            self.runner.close()
            self.runner = None

    def close(self):
        self._close_sim()
