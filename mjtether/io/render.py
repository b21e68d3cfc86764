"""Headless rendering of a scenario run (or, through ``network_view``, a network of lines) to MP4
(H.264) or GIF, with the lines coloured by tension.

No display is needed: the OpenGL context is EGL (Mesa's EGL also runs on a CPU-only machine),
or OSMesa if EGL is missing; ``MUJOCO_GL`` picks one explicitly. Each frame shows the model as
built (seabed, ship, walker), and, drawn into the scene for the frame only:

* the tether as capsules coloured by each element's axial tension on a scale fixed for the video
  (0 to ``tension_scale`` N, blue (slack) to red, the ``turbo`` colour map), by default from the
  run's own tensions (``ScenarioView.default_scale``), not the rated load;
* the water surface as a translucent plane at z = 0;
* current arrows at a few depths (length proportional to speed, stated in the overlay);
* a text overlay (time, tow tension, ship-end tension, deployed length, the cable's clearance from a
  vehicle; a warning, top right, when the tangle monitor's thresholds are crossed) and a colour bar;
* the caller's ``FrameRenderer.markers`` (``Marker``: e.g. a goal), geoms of the scene only.

What is drawn comes from a ``FrameView``: ``ScenarioView`` reads a ``runner.ScenarioRun`` (or the
replay's stand-in for one); ``network_view.NetworkView`` reads a ``network.run.NetworkRun``. The
renderer only reads the simulation (``mjv_updateScene`` and the lines' constraint forces), so a
run gives the same time series with and without video (``tests/io/test_render.py``,
``tests/io/test_network_render.py``).
Frames are taken at t = k / fps, k = 0 .. round(duration fps) - 1, at the first step on or after
each. Units SI; frames world, z up.
"""

from __future__ import annotations

import math
import os
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import mujoco
import numpy as np

CAMERAS = ("track", "side", "top", "walker")
FORMATS = (".mp4", ".gif")
BACKENDS = ("egl", "osmesa")
SYSTEM_PACKAGES = {"egl": "libegl1 and libgl1-mesa-dri (Debian/Ubuntu: apt install libegl1 libgl1-mesa-dri)",
                   "osmesa": "libosmesa6 (Debian/Ubuntu: apt install libosmesa6)"}
SURFACE_RGBA = (0.25, 0.55, 0.85, 0.25)
ARROW_RGBA = (0.95, 0.95, 0.95, 0.9)
WATER_RGB = (0.05, 0.22, 0.32)  # haze and background


class RenderUnavailable(RuntimeError):
    """No headless OpenGL context could be made (the message names the missing package)."""


# ------------------------------------------------------------------ pure kernels


def tension_colours(tension: np.ndarray, scale: float) -> np.ndarray:
    """RGBA (n, 4) for element tensions (N) on the fixed scale [0, ``scale``] N, blue (slack) to
    red (``scale`` and above), matplotlib's ``turbo`` map (elements carry tension only)."""
    from matplotlib import colormaps

    if not scale > 0:
        raise ValueError(f"tension scale must be > 0 N, got {scale!r}")
    t = np.asarray(tension, dtype=float)
    return colormaps["turbo"](np.clip(t / scale, 0.0, 1.0))


def nice_scale(value: float) -> float:
    """The smallest 1, 2 or 5 x 10^k at or above ``value`` (> 0)."""
    k = math.floor(math.log10(value))
    for m in (1.0, 2.0, 5.0, 10.0):
        if m * 10**k >= value * (1 - 1e-12):
            return m * 10**k
    return 10.0 ** (k + 1)  # pragma: no cover


def frame_times(duration: float, fps: float) -> np.ndarray:
    """Times (s) of the frames of a video of ``duration`` s at ``fps``."""
    return np.arange(int(round(duration * fps))) / fps


# ------------------------------------------------------------------ OpenGL context

_backend: str | None = None


def _probe(backend: str) -> str | None:
    """Try a context of ``backend`` in a child process (PyOpenGL binds one platform per
    process); returns None if it works, else the error text."""
    code = (f"import mujoco.{backend} as b; c = b.GLContext(16, 16); c.make_current(); c.free()")
    env = dict(os.environ, MUJOCO_GL=backend, PYOPENGL_PLATFORM=backend)
    try:
        r = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=60)
    except (OSError, subprocess.TimeoutExpired) as exc:
        return str(exc)
    return None if r.returncode == 0 else (r.stderr.strip().splitlines() or ["failed"])[-1]


def gl_backend() -> str:
    """The headless OpenGL backend to use: ``MUJOCO_GL`` if it names egl or osmesa, else EGL,
    falling back to OSMesa with a message. Raises ``RenderUnavailable`` naming the system
    packages to install if neither works."""
    global _backend
    if _backend is not None:
        return _backend
    asked = os.environ.get("MUJOCO_GL", "").lower().strip()
    order = [asked] if asked in BACKENDS else list(BACKENDS)
    errors = {}
    for b in order:
        err = _probe(b)
        if err is None:
            if b != order[0]:
                print(f"mjtether render: EGL is not available ({errors[order[0]]}); using OSMesa, which is "
                      "slower", file=sys.stderr)
            _backend = b
            return b
        errors[b] = err
    need = " or ".join(SYSTEM_PACKAGES[b] for b in order)
    raise RenderUnavailable(f"no headless OpenGL: {'; '.join(f'{b}: {e}' for b, e in errors.items())}. "
                            f"Install {need}.")


def _gl_context(width: int, height: int):
    backend = gl_backend()
    os.environ.setdefault("PYOPENGL_PLATFORM", backend)
    if os.environ["PYOPENGL_PLATFORM"] != backend:
        raise RenderUnavailable(f"PYOPENGL_PLATFORM is {os.environ['PYOPENGL_PLATFORM']!r} in this process; "
                                f"rendering needs {backend!r} (set MUJOCO_GL={backend} before starting Python)")
    if backend == "egl":
        from mujoco.egl import GLContext
    else:
        from mujoco.osmesa import GLContext
    ctx = GLContext(width, height)
    ctx.make_current()
    return ctx


# ------------------------------------------------------------------ settings and the recorder


@dataclass
class VideoSettings:
    """What to render. ``tuned`` visuals (no shadows, reflections or anti-aliasing, coarser
    capsules) render several times faster on a CPU than MuJoCo's defaults. ``tension_scale``
    (N) is the top of the colour scale (``--tension-scale``); by default (None) the view's
    ``default_scale``, from the run's own tensions: a replay's largest element tension over the
    whole run, a live video's twice the largest at the start, each rounded up to 1, 2 or 5 x 10^k
    (the rated load is not used: often a line type's breaking load, 176.8 kN for a cable under
    1 kN, it would draw every element dark blue; give it here to colour against it)."""

    width: int = 640
    height: int = 480
    fps: float = 30.0
    camera: str = "track"
    tuned: bool = True
    tension_scale: float | None = None
    current_arrows: int = 5

    def __post_init__(self):
        for name, lo, hi in (("width", 16, 4096), ("height", 16, 4096)):
            v = getattr(self, name)
            if not isinstance(v, int) or not lo <= v <= hi or v % 2:
                raise ValueError(f"video.{name} must be an even number of pixels in [{lo}, {hi}], got {v!r}")
        if not (isinstance(self.fps, (int, float)) and 1.0 <= self.fps <= 120.0):
            raise ValueError(f"video.fps must be in [1, 120] frames/s, got {self.fps!r}")
        if self.camera not in CAMERAS:
            raise ValueError(f"video.camera must be one of {', '.join(CAMERAS)}; got {self.camera!r}")
        if self.tension_scale is not None and not self.tension_scale > 0:
            raise ValueError(f"video.tension_scale must be > 0 N, got {self.tension_scale!r}")
        if not 0 <= self.current_arrows <= 20:
            raise ValueError(f"video.current_arrows must be in [0, 20], got {self.current_arrows!r}")


def model_camera_id(model: mujoco.MjModel, camera: int | str) -> int:
    """The id of a camera of ``model`` given by id or name; a ValueError lists the cameras."""
    names = [model.camera(i).name for i in range(model.ncam)]
    if isinstance(camera, str) and camera in names:
        return names.index(camera)
    if isinstance(camera, (int, np.integer)) and not isinstance(camera, bool) and 0 <= camera < model.ncam:
        return int(camera)
    raise ValueError(f"no camera {camera!r} in the model; its cameras are "
                     f"{', '.join(f'{i}: {n!r}' for i, n in enumerate(names)) or 'none'}")


def check_output_path(path, overwrite: bool = True) -> Path:
    """The video file's path, if its suffix is a supported format (.mp4 or .gif), it is not a
    folder, and (unless ``overwrite``) no file is there yet."""
    p = Path(path)
    if p.suffix.lower() not in FORMATS:
        raise ValueError(f"video file must end in {' or '.join(FORMATS)}, got {str(path)!r}")
    if p.is_dir():
        raise ValueError(f"video file {str(path)!r} is a folder; give a file name ending in {' or '.join(FORMATS)}")
    if p.exists() and not overwrite:
        raise ValueError(f"video file {str(path)!r} exists; choose another name or pass --overwrite to replace it")
    parent = p.resolve().parent
    while not parent.exists():
        parent = parent.parent
    if not parent.is_dir():
        raise ValueError(f"video file {str(path)!r}: {parent} is a file, not a folder")
    return p


@dataclass
class Marker:
    """A geom drawn into every frame (added to the scene, not to the model, so the physics does
    not see it): MuJoCo geom type ``gtype`` at ``pos`` (m, world, axes aligned with the world's),
    ``size`` as a scene geom (``mjvGeom``) takes it, three values (a cylinder: radius, radius,
    half-height; a sphere: the radius three times), colour ``rgba`` (alpha < 1: translucent)."""

    pos: tuple
    size: tuple
    rgba: tuple = (0.1, 0.9, 0.2, 0.5)
    gtype: int = mujoco.mjtGeom.mjGEOM_CYLINDER


class FrameView:
    """What ``FrameRenderer`` draws, read from a run: a subclass gives the model and its data
    (``model``, ``data``: the state drawn), the water column (``water``), the run's ``duration``
    (s), the ``lines`` as (nodes (n+1, 3) m world, element tensions (n,) N, radius m), the points
    the camera frames, what ``track`` follows, the overlay's text and the default top of the
    colour scale (N). ``what`` names the lines in the colour scale's legend."""

    what = "line"
    colour_bar = True

    @property
    def model(self) -> mujoco.MjModel:
        raise NotImplementedError

    @property
    def data(self) -> mujoco.MjData:
        raise NotImplementedError

    @property
    def duration(self) -> float:
        raise NotImplementedError

    def lines(self) -> list:
        """[(nodes (n+1, 3) m world, element tensions (n,) N, capsule radius m)], one per line."""
        raise NotImplementedError

    def framed(self, nodes: np.ndarray) -> np.ndarray:
        """Points (m, world) the side and top cameras frame, given the lines' ``nodes``."""
        return nodes

    def track(self):
        """(point looked at (m, world), distance m) of the ``track`` camera; None: the whole of
        ``framed``, seen from the same angle."""
        return None

    def walker_refusal(self) -> str | None:
        """Why the ``walker`` camera cannot be used, or None."""
        return "video.camera 'walker' needs a walker scenario (robot.type = 'walker')"

    def node_count(self) -> int:
        """Room to keep in the scene for the lines' capsules."""
        raise NotImplementedError

    def default_scale(self) -> float:
        raise NotImplementedError

    def overlay(self) -> list:
        """[(``mjtGridPos``, left text, right text)], drawn in order."""
        raise NotImplementedError

    def colours(self, lines: list, scale: float) -> list:
        """RGBA (n, 4) of each line's elements on the scale [0, ``scale``] N (``tension_colours``)."""
        return [tension_colours(t, scale) for _, t, _ in lines]


class ScenarioView(FrameView):
    """A ``runner.ScenarioRun`` (or ``replay.Replay``) as ``FrameRenderer`` draws it: its tether,
    its robot followed by ``track``, the scenario's overlay (time, tow and ship-end tensions,
    deployed length, the cable's clearance from a vehicle, a tangle warning; a vehicle alone:
    its speed, depth and heading, no colour bar)."""

    what = "tether"

    def __init__(self, runner):
        if not hasattr(runner, "named") and hasattr(runner, "net"):
            raise TypeError("a network run is drawn through mjtether.io.network_view (NetworkView, network_video)")
        self.runner = runner
        self.water = runner.water
        self.colour_bar = bool(runner.tethered)

    model = property(lambda self: self.runner.sim.model)
    data = property(lambda self: self.runner.sim.data)
    duration = property(lambda self: self.runner.sc.simulation.duration)

    def lines(self) -> list:
        n = self.runner.named
        return [(n.tether_nodes, n.tether_tension, self.runner.contact_diameter / 2)]

    def framed(self, nodes: np.ndarray) -> np.ndarray:
        r = self.runner
        return nodes if r.tethered else np.vstack([nodes, r.named.robot_position])

    def track(self):
        return self.runner.named.robot_position, 9.0

    def walker_refusal(self) -> str | None:
        return None if self.runner.walker else super().walker_refusal()

    def node_count(self) -> int:
        return len(self.runner.named.tether_nodes)

    def default_scale(self) -> float:
        """The top of the colour scale (N) from the run's own tensions: a replay of a results
        folder (``replay.Replay``, whose ``saved.tension`` holds every sample) its largest
        element tension over the run, a live run (whose future is unknown) twice the largest
        now, at its start; rounded up to 1, 2 or 5 x 10^k, and at least 1 N."""
        saved = getattr(self.runner, "saved", None)
        if saved is not None and getattr(saved, "tension", None) is not None and np.size(saved.tension):
            return nice_scale(max(float(np.max(saved.tension)), 1.0))
        t = self.runner.named.tether_tension
        return nice_scale(2.0 * max(float(t.max(initial=0.0)), 1.0))

    def overlay(self) -> list:
        n, top_left, top_right = self.runner.named, mujoco.mjtGridPos.mjGRID_TOPLEFT, mujoco.mjtGridPos.mjGRID_TOPRIGHT
        if not self.runner.tethered:  # a vehicle alone: its speed, depth and heading, no colour bar
            left = "time\nspeed\ndepth\nheading"
            right = (f"{n.time:7.2f} s\n{n.robot_speed:7.2f} m/s\n{-n.robot_position[2]:7.1f} m\n"
                     f"{math.degrees(n.robot_heading):7.0f} deg")
            return [(top_left, left, right)]
        left = "time\ntow tension\nship tension\ndeployed"
        right = f"{n.time:7.2f} s\n{n.tow_tension:7.0f} N\n{n.ship_tension:7.0f} N\n{n.deployed_length:7.1f} m"
        t = n.tangle() if n.hulls or self.runner.sc.tangle.self_clearance_m > 0 else None
        if t is not None and n.hulls:
            left += "\ncable clearance"
            right += f"\n{t['clearance']:7.2f} m" if math.isfinite(t["clearance"]) else "\n      -"
        out = [(top_left, left, right)]
        if t is not None:  # the tangle monitor's thresholds (scenario [tangle]) crossed: say so, top right
            cfg, warn = self.runner.sc.tangle, []
            if cfg.clearance_m > 0 and t["clearance"] < cfg.clearance_m:
                warn.append(f"cable within {t['clearance']:.2f} m of the vehicle" if t["clearance"] >= 0.0 else
                            f"cable through the vehicle ({t['clearance']:.2f} m)")
            if cfg.self_clearance_m > 0 and (t["self_clearance"] < cfg.self_clearance_m or t["plan_crossings"]):
                warn.append(f"cable within {t['self_clearance']:.2f} m of itself")
            if warn:
                out.append((top_right, "TANGLE RISK", "\n".join(warn)))
        return out


def view_of(runner) -> FrameView:
    """``runner`` itself if it is a ``FrameView``, else a ``ScenarioView`` of it."""
    return runner if isinstance(runner, FrameView) else ScenarioView(runner)


class FrameRenderer:
    """Draws the current state of a run offscreen (see the module docstring): a
    ``runner.ScenarioRun``, or any ``FrameView`` (``network_view.NetworkView``: a network of lines);
    ``render()`` returns an RGB array. ``close()`` frees the OpenGL context.

    ``fixed_camera``: a camera of the model (its id, or its name such as ``"walker/front"``) to
    view from instead of ``settings.camera``. ``markers``: a list of ``Marker`` drawn into each
    frame; the caller may replace it between frames."""

    def __init__(self, runner, settings: VideoSettings | None = None, fixed_camera: int | str | None = None):
        self.s = s = settings or VideoSettings()
        self.runner = runner
        self.view = view = view_of(runner)
        m = view.model
        refusal = view.walker_refusal() if s.camera == "walker" and fixed_camera is None else None
        if refusal:
            raise ValueError(refusal)
        self.fixed_camera = None if fixed_camera is None else model_camera_id(m, fixed_camera)
        self.markers: list[Marker] = []
        # visual settings (model.vis is not used by the physics)
        m.vis.global_.offwidth = max(m.vis.global_.offwidth, s.width)
        m.vis.global_.offheight = max(m.vis.global_.offheight, s.height)
        m.vis.headlight.ambient[:] = 0.45
        m.vis.headlight.diffuse[:] = 0.6
        if s.tuned:
            m.vis.quality.offsamples = 0
            m.vis.quality.numslices = 12
            m.vis.quality.numstacks = 4
        self._gl = _gl_context(s.width, s.height)
        self.ctx = mujoco.MjrContext(m, mujoco.mjtFontScale.mjFONTSCALE_100)
        mujoco.mjr_setBuffer(mujoco.mjtFramebuffer.mjFB_OFFSCREEN, self.ctx)
        # room for what mjv_updateScene draws (geoms, sites, tendons) and what is added here:
        # a scene that is full drops the rest of the lines, the arrows and the markers
        room = m.ngeom + m.nsite + m.ntendon + view.node_count() + s.current_arrows + 100
        self.scene = mujoco.MjvScene(m, maxgeom=room)
        if s.tuned:
            for f in (mujoco.mjtRndFlag.mjRND_SHADOW, mujoco.mjtRndFlag.mjRND_REFLECTION,
                      mujoco.mjtRndFlag.mjRND_SKYBOX):
                self.scene.flags[f] = 0
        self.scene.flags[mujoco.mjtRndFlag.mjRND_FOG] = 1
        m.vis.rgba.fog[:] = (*WATER_RGB, 1.0)
        self.opt = mujoco.MjvOption()
        for f in (mujoco.mjtVisFlag.mjVIS_FLEXVERT, mujoco.mjtVisFlag.mjVIS_FLEXEDGE,
                  mujoco.mjtVisFlag.mjVIS_FLEXFACE, mujoco.mjtVisFlag.mjVIS_FLEXSKIN):
            self.opt.flags[f] = 0  # the lines are drawn here, coloured
        self.cam = mujoco.MjvCamera()
        self.viewport = mujoco.MjrRect(0, 0, s.width, s.height)
        self._rgb = np.zeros((s.height, s.width, 3), dtype=np.uint8)
        self._depth = None  # (height, width) float32, for render_depth
        self._background = (np.array(WATER_RGB) * 255).astype(np.uint8)
        self.scale = s.tension_scale or view.default_scale()
        self.legend = f"{view.what} tension colour scale: 0 N (blue) to {self.scale:g} N (red), turbo"
        self._closed = False

    # ------------------------------------------------------------- frame content

    def _extent(self, x: np.ndarray):
        """Centre and size (m) of the box around the points ``x``."""
        lo, hi = x.min(0), x.max(0)
        return 0.5 * (lo + hi), float(np.linalg.norm(hi - lo))

    def _place_camera(self, x: np.ndarray) -> float:
        """Set the camera to frame the points ``x``; returns the typical viewing distance (m)
        for line widths."""
        c, m = self.cam, self.view.model
        fov = math.radians(m.vis.global_.fovy)
        if self.fixed_camera is not None or self.s.camera == "walker":
            c.type = mujoco.mjtCamera.mjCAMERA_FIXED
            c.fixedcamid = m.camera("walker/track").id if self.fixed_camera is None else self.fixed_camera
            return 8.0
        c.type = mujoco.mjtCamera.mjCAMERA_FREE
        centre, size = self._extent(x)
        if self.s.camera == "track":
            followed = self.view.track()
            c.lookat[:], c.distance = followed if followed is not None else \
                (centre, 0.6 * size / math.tan(fov / 2) + 1.0)
            c.azimuth, c.elevation = 135.0, -20.0
            return c.distance
        c.lookat[:] = centre
        if self.s.camera == "side":
            c.distance = 0.6 * size / math.tan(fov / 2) + 1.0
            c.azimuth, c.elevation = 90.0, -5.0
        else:  # top: frame the horizontal extent, from above the surface
            span = float(np.ptp(x[:, :2], axis=0).max())
            c.distance = 0.6 * max(span, 10.0) / math.tan(fov / 2) + 1.0 + max(-centre[2], 0.0)
            c.azimuth, c.elevation = 90.0, -89.9
        return c.distance

    def _add_geom(self, gtype, rgba):
        sc = self.scene
        if sc.ngeom >= sc.maxgeom:
            return None
        g = sc.geoms[sc.ngeom]
        mujoco.mjv_initGeom(g, gtype, np.zeros(3), np.zeros(3), np.eye(3).ravel(), np.asarray(rgba, np.float32))
        g.category = mujoco.mjtCatBit.mjCAT_DECOR
        sc.ngeom += 1
        return g

    def _add_line(self, x: np.ndarray, colours: np.ndarray, width: float) -> None:
        for i, rgba in enumerate(colours):
            g = self._add_geom(mujoco.mjtGeom.mjGEOM_CAPSULE, rgba)
            if g is not None:
                mujoco.mjv_connector(g, mujoco.mjtGeom.mjGEOM_CAPSULE, width, x[i], x[i + 1])

    def _add_water_and_current(self, x: np.ndarray, view: float) -> None:
        centre, size = self._extent(x)
        half = max(size, view) * 1.5
        # (seen from above, the surface would veil the whole picture)
        g = self._add_geom(mujoco.mjtGeom.mjGEOM_BOX, SURFACE_RGBA) if self.s.camera != "top" else None
        if g is not None:
            g.size[:] = [half, half, 0.01]
            g.pos[:] = [centre[0], centre[1], 0.0]
        water = self.view.water
        n = self.s.current_arrows
        if n == 0:
            return
        depth = min(water.depth, max(-x[:, 2].min(), 1.0))
        z = -np.linspace(0.05, 0.95, n) * depth
        u = water.velocity(z)
        umax = max(float(np.linalg.norm(u, axis=1).max()), 1e-6)
        self.arrow_scale = 0.15 * max(size, 1.0) / umax  # m of arrow per m/s
        base = np.array([x[:, 0].min(), centre[1], 0.0])
        for zi, ui in zip(z, u):
            if np.linalg.norm(ui) < 1e-3:
                continue
            g = self._add_geom(mujoco.mjtGeom.mjGEOM_ARROW, ARROW_RGBA)
            if g is not None:
                p0 = base + [0.0, 0.0, zi]
                mujoco.mjv_connector(g, mujoco.mjtGeom.mjGEOM_ARROW, 0.004 * view, p0, p0 + self.arrow_scale * ui)

    def _add_markers(self) -> None:
        for mk in self.markers:
            g = self._add_geom(mk.gtype, mk.rgba)
            if g is not None:
                g.pos[:] = mk.pos
                g.size[:] = mk.size

    def _overlay(self) -> None:
        for where, left, right in self.view.overlay():
            mujoco.mjr_overlay(mujoco.mjtFont.mjFONT_NORMAL, where, self.viewport, left, right, self.ctx)
        if not self.view.colour_bar:
            return
        # colour bar, bottom left: 10 steps from 0 to the scale
        w, h = self.s.width, self.s.height
        bar_w, bar_h = max(w // 40, 4), max(h // 30, 3)
        steps = tension_colours(np.linspace(0, self.scale, 10), self.scale)
        for k, c in enumerate(steps):
            mujoco.mjr_rectangle(mujoco.MjrRect(8 + k * bar_w, 8, bar_w, bar_h), *c[:3], 1.0)
        mujoco.mjr_overlay(mujoco.mjtFont.mjFONT_NORMAL, mujoco.mjtGridPos.mjGRID_BOTTOMLEFT,
                           mujoco.MjrRect(8, 8 + bar_h, w, h), f"0 - {self.scale:g} N", "", self.ctx)

    def _draw(self, decorations: bool = True) -> None:
        """Draw the simulation's current state into the offscreen buffer; ``decorations``: the
        water surface, current arrows and markers too (not physical objects)."""
        v = self.view
        m, d = v.model, v.data
        lines = v.lines()
        x = np.vstack([nodes for nodes, _, _ in lines]) if lines else v.framed(np.zeros((0, 3)))
        view = self._place_camera(v.framed(x))
        mujoco.mjv_updateScene(m, d, self.opt, None, self.cam, mujoco.mjtCatBit.mjCAT_ALL, self.scene)
        for (nodes, _, radius), colours in zip(lines, v.colours(lines, self.scale)):
            self._add_line(nodes, colours, max(radius, 0.0025 * view))
        if decorations:
            self._add_water_and_current(x, view)
            self._add_markers()
        # underwater haze: fog in the water's colour from about the viewing distance on
        m.vis.map.fogstart = 1.0 * view / m.stat.extent
        m.vis.map.fogend = 4.0 * view / m.stat.extent
        mujoco.mjr_setBuffer(mujoco.mjtFramebuffer.mjFB_OFFSCREEN, self.ctx)
        mujoco.mjr_render(self.viewport, self.scene, self.ctx)

    def render_depth(self) -> np.ndarray:
        """Depth image of the current state: (height, width) float32, the distance (m) from the
        camera to the first surface at each pixel, along the camera's viewing axis (a plane
        facing the camera reads the same everywhere), as MuJoCo's ``Renderer`` gives it; the far
        clipping distance where nothing is drawn. Physical objects only (the model's geoms and
        the lines), no water surface, current arrows, markers or overlay."""
        self._draw(decorations=False)
        m = self.view.model
        if self._depth is None:
            self._depth = np.zeros((self.s.height, self.s.width), dtype=np.float32)
        mujoco.mjr_readPixels(None, self._depth, self.viewport, self.ctx)
        near = m.vis.map.znear * m.stat.extent
        far = m.vis.map.zfar * m.stat.extent
        # OpenGL's depth buffer (0 at near, 1 at far, hyperbolic in distance) to metres
        return np.flipud(near / (1.0 - self._depth * (1.0 - near / far)))

    def render(self) -> np.ndarray:
        """Render the simulation's current state; returns the frame (height, width, 3) uint8."""
        self._draw()
        self._overlay()
        mujoco.mjr_readPixels(self._rgb, None, self.viewport, self.ctx)
        f = self._rgb
        empty = (f[..., 0] | f[..., 1] | f[..., 2]) == 0  # nothing drawn there: open water
        np.copyto(f, self._background, where=empty[..., None])
        return np.flipud(f)

    def close(self) -> None:
        if not self._closed:
            self._closed = True
            self.ctx.free()
            self._gl.free()


class VideoRecorder:
    """Renders frames of a ``runner.ScenarioRun`` (or any ``FrameView``) into a video file
    (``FrameRenderer`` draws) for ``duration`` s, by default the run's (the scenario's
    ``simulation.duration``, a network's ``duration``).

    The file is written under a temporary name beside ``path`` and renamed on ``finish()``;
    ``abort()`` (or an exception inside ``with``) deletes it, so a failed run leaves no video.
    """

    def __init__(self, runner, path, settings: VideoSettings | None = None, duration: float | None = None):
        import imageio.v2 as imageio

        self.s = s = settings or VideoSettings()
        self.path = check_output_path(path)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        view = view_of(runner)
        self.times = frame_times(view.duration if duration is None else duration, s.fps)
        self.n_frames = len(self.times)
        self.frames = 0
        self.frame = FrameRenderer(view, s)
        self.frame.runner = runner
        self.scale = self.frame.scale
        self._tmp = self.path.with_name(f".{self.path.stem}.partial{self.path.suffix}")
        try:
            if self.path.suffix.lower() == ".mp4":
                self._writer = imageio.get_writer(self._tmp, fps=s.fps, codec="libx264", pixelformat="yuv420p",
                                                  macro_block_size=1, quality=7,
                                                  output_params=["-metadata", f"comment={self.frame.legend}"])
            else:
                self._writer = imageio.get_writer(self._tmp, mode="I", duration=1000.0 / s.fps, loop=0)
        except BaseException:
            self.frame.close()
            raise
        self._done = False

    def render(self) -> np.ndarray:
        return self.frame.render()

    def capture(self) -> None:
        """Render and append one frame."""
        self._writer.append_data(self.frame.render())
        self.frames += 1

    def due(self, t: float) -> bool:
        """Whether the next frame is due at simulated time ``t`` (s)."""
        return self.frames < self.n_frames and t >= self.times[self.frames] - 1e-9

    # ------------------------------------------------------------- file handling

    def finish(self) -> Path:
        """Close the file and move it into place; returns its path."""
        if self._done:
            return self.path
        self._close()
        self._tmp.replace(self.path)
        return self.path

    def abort(self) -> None:
        """Close and delete the partial file."""
        self._close()
        self._tmp.unlink(missing_ok=True)

    def _close(self) -> None:
        if not self._done:
            self._done = True
            try:
                self._writer.close()
            finally:
                self.frame.close()

    def __enter__(self):
        return self

    def __exit__(self, exc_type, *_):
        if exc_type is None:
            self.finish()
        else:
            self.abort()
