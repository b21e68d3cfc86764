"""Every environment passes Gymnasium's ``check_env`` as ``gymnasium.make`` builds it, render
checks included, on a machine without a display and (the viewer a stand-in) with one, where
``"human"`` is listed and checked; and the ids are known after ``import mjtether`` or through the
``"module:id"`` form, from a fresh interpreter (Gymnasium >= 1.0 has no entry-point plugins: see
docs/environments.md).

The answer each test checks against is Gymnasium's own checker (``check_env`` raises on a
violation of its API) and its registry's behaviour in a fresh process, not this package's code.
"""

import os
import subprocess
import sys
import warnings

import gymnasium as gym
import pytest
from gymnasium.utils.env_checker import check_env

import mjtether  # noqa: F401 - registers the environments
from mjtether.envs.base import has_display
from mjtether.io.render import RenderUnavailable

IDS = ["mjtether/TetherWinch-v0", "mjtether/TetheredWalker-v0", "mjtether/TetheredROV-v0",
       "mjtether/TetheredSystem-v0"]

WRAPPED = "is different from the unwrapped version"
"""check_env's warning when given the wrapped environment: meant (we pass it on purpose)."""
INFINITE = ("A Box observation space minimum value is -infinity", "A Box observation space maximum value is infinity")
"""check_env's warnings for TetheredSystem-v0: its observation (the vehicle's offset from the
station, its velocities, the lines' tensions) has no bound the physics keeps."""


@pytest.fixture
def headless(monkeypatch):
    """No DISPLAY, no WAYLAND_DISPLAY: a machine without a display (Linux)."""
    if sys.platform in ("darwin", "win32"):
        pytest.skip("has_display() is always true on macOS and Windows")
    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)
    assert not has_display()


def _checked(env_id: str, unwrap: bool) -> list[str]:
    """Run check_env (render and close checks included) on gym.make(env_id) or its unwrapped
    environment; return the warnings Gymnasium gave (its logger's, "WARN: ..."; the physics' own
    warnings, such as a vehicle's TrimDensityWarning, are other tests' business)."""
    env = gym.make(env_id)
    try:
        assert env.unwrapped.metadata["render_modes"] and "human" not in env.metadata["render_modes"]
        with warnings.catch_warnings(record=True) as got:
            warnings.simplefilter("always")
            check_env(env.unwrapped if unwrap else env)
    finally:
        env.close()
    return [str(w.message) for w in got if "WARN: " in str(w.message)]


@pytest.mark.parametrize("env_id", IDS)
def test_check_env_passes_without_a_display(env_id, headless):
    """check_env(env.unwrapped) and check_env(env) pass; the only warnings are the meant ones
    (module docstring, WRAPPED and INFINITE)."""
    allowed = INFINITE if env_id.endswith("TetheredSystem-v0") else ()
    for unwrap in (True, False):
        for message in _checked(env_id, unwrap):
            assert (not unwrap and WRAPPED in message) or any(a in message for a in allowed), message


def test_human_is_refused_without_a_display(headless):
    """Without a display an instance leaves "human" out of its metadata (its class lists it), and
    asking for it is refused by the constructor, naming DISPLAY."""
    env = gym.make(IDS[0])
    try:
        assert "human" in type(env.unwrapped).metadata["render_modes"]
        assert env.metadata["render_modes"] == ["rgb_array", "depth_array"]
    finally:
        env.close()
    with pytest.raises(RenderUnavailable, match="DISPLAY"):
        gym.make(IDS[0], render_mode="human")


class _Viewer:
    """Stands in for ``mujoco.viewer.launch_passive``'s handle (this machine has no window system)."""

    def __init__(self, model, data, **_):
        import mujoco

        self.cam, self.user_scn = mujoco.MjvCamera(), mujoco.MjvScene(model, maxgeom=1000)
        self.syncs, self.closed = 0, False

    def lock(self):
        import contextlib

        return contextlib.nullcontext()

    def sync(self):
        self.syncs += 1

    def is_running(self):
        return not self.closed

    def close(self):
        self.closed = True


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="DISPLAY/WAYLAND_DISPLAY decide on Linux only")
@pytest.mark.parametrize("env_id", IDS[:3])
def test_check_env_passes_with_a_display(env_id, monkeypatch):
    """With DISPLAY set (the viewer a stand-in), an instance lists "human" and check_env builds
    and renders it: one viewer opened, shown at reset and at render (2 syncs), closed."""
    import mujoco.viewer

    opened = []
    monkeypatch.setenv("DISPLAY", ":99")
    monkeypatch.setattr(mujoco.viewer, "launch_passive", lambda m, d, **kw: opened.append(_Viewer(m, d)) or opened[-1])
    env = gym.make(env_id)
    try:
        assert env.metadata["render_modes"] == ["human", "rgb_array", "depth_array"]
        with warnings.catch_warnings(record=True) as got:
            warnings.simplefilter("always")
            check_env(env.unwrapped)
    finally:
        env.close()
    assert [m for m in map(str, (w.message for w in got)) if "WARN: " in m] == []
    assert [(v.syncs, v.closed) for v in opened] == [(2, True)]


FRESH = {
    # the plain id fails in a fresh interpreter (Gymnasium reads no entry points); import mjtether
    # registers without loading the environment modules; then "mjtether.envs:" works
    "envs": """
import sys
import gymnasium as gym
try:
    gym.make("mjtether/TetherWinch-v0")
    raise SystemExit("the plain id worked without an import")
except gym.error.NamespaceNotFound:
    pass
import mjtether
assert "mjtether.envs" not in sys.modules, "import mjtether imported the environments"
env = gym.make("mjtether.envs:mjtether/TetherWinch-v0")
print(env.spec.id)
""",
    # "mjtether:" works with no import, and registers the four ids
    "package": """
import gymnasium as gym
env = gym.make("mjtether:mjtether/TetheredROV-v0")
print(env.spec.id, sorted(i for i in gym.registry if i.startswith("mjtether/")))
""",
}


def test_the_ids_are_known_from_a_fresh_interpreter(tmp_path):
    """The two documented ways, each in a fresh interpreter started outside the repository."""
    env = dict(os.environ, MUJOCO_GL=os.environ.get("MUJOCO_GL", "egl"))
    runs = {k: subprocess.Popen([sys.executable, "-c", code], cwd=tmp_path, env=env, text=True,
                                stdout=subprocess.PIPE, stderr=subprocess.PIPE) for k, code in FRESH.items()}
    out = {}
    for k, p in runs.items():
        stdout, stderr = p.communicate(timeout=120)
        assert p.returncode == 0, f"{k}: {stderr[-2000:]}"
        out[k] = stdout
    assert out["envs"].strip() == "mjtether/TetherWinch-v0"
    assert out["package"].strip() == "mjtether/TetheredROV-v0 " + repr(sorted(IDS))
