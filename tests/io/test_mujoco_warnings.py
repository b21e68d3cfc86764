"""MuJoCo's warnings reach Python (mjtether.files.mjlog) and never MUJOCO_LOG.TXT in the working folder."""

import logging
import subprocess
import sys
import textwrap

import mujoco
import numpy as np
import pytest

import mjtether  # noqa: F401 - installs the warning callback
from mjtether.files import mjlog
from mjtether.files.mjlog import MujocoWarning

BALL = '<mujoco><worldbody><body><freejoint/><geom size="0.1"/></body></worldbody></mujoco>'


def _bad_qacc_step():
    """One mj_step of a fresh MjData with a NaN applied force: MuJoCo warns "Nan, Inf or huge
    value in QACC" and resets the data (each MjData reports a warning kind only once)."""
    m = mujoco.MjModel.from_xml_string(BALL)
    d = mujoco.MjData(m)
    d.qfrc_applied[0] = np.nan
    mujoco.mj_step(m, d)
    assert d.warning[mujoco.mjtWarning.mjWARN_BADQACC].number == 1


def test_installed_on_import():
    assert mjlog.installed() == "warnings"
    assert mujoco.get_mju_user_warning() is not None


def test_warning_is_a_python_warning_not_a_file(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    with pytest.warns(MujocoWarning, match="Nan, Inf or huge value in QACC"):
        _bad_qacc_step()
    assert not (tmp_path / "MUJOCO_LOG.TXT").exists()
    assert issubclass(MujocoWarning, RuntimeWarning)


def test_logging_route(tmp_path, monkeypatch, caplog):
    monkeypatch.chdir(tmp_path)
    assert mjlog.install(route="logging")
    try:
        with caplog.at_level(logging.WARNING, logger="mjtether.mujoco"):
            _bad_qacc_step()
    finally:
        mjlog.install()  # back to the warnings route for the rest of the session
    assert any(r.name == "mjtether.mujoco" and "QACC" in r.getMessage() for r in caplog.records)
    assert not (tmp_path / "MUJOCO_LOG.TXT").exists()


def _python(tmp_path, *code, args=()):
    # a subprocess: an exception thrown through MuJoCo's C code would abort this process
    src = "\n".join(textwrap.dedent(c) for c in code)
    return subprocess.run([sys.executable, *args, "-c", src], cwd=tmp_path, capture_output=True, text=True,
                          timeout=120)


TRIGGER = f"""
import mujoco, numpy as np
m = mujoco.MjModel.from_xml_string({BALL!r}); d = mujoco.MjData(m)
d.qfrc_applied[0] = np.nan
mujoco.mj_step(m, d)
"""


def test_warnings_as_errors_do_not_abort(tmp_path):
    """Under -W error the callback cannot raise (that would abort): it logs instead."""
    r = _python(tmp_path, "import mjtether", TRIGGER, "print('survived')", args=("-W", "error::RuntimeWarning"))
    assert r.returncode == 0, r.stderr
    assert "survived" in r.stdout
    assert "QACC" in r.stderr  # logging's last-resort handler
    assert not (tmp_path / "MUJOCO_LOG.TXT").exists()


def test_user_callback_is_kept(tmp_path):
    r = _python(tmp_path, """
        import mujoco
        got = []
        mujoco.set_mju_user_warning(got.append)
        import mjtether
        assert mjtether.files.mjlog.installed() is None
    """, TRIGGER, """
        assert len(got) == 1 and "QACC" in got[0], got
        print('kept')
    """)
    assert r.returncode == 0, r.stderr
    assert "kept" in r.stdout
    assert not (tmp_path / "MUJOCO_LOG.TXT").exists()
