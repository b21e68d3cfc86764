"""The wheel ships what a run needs outside the source tree (.ci/run also runs it from a venv)."""

import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
# build outputs and run products that must not leak into the copy that is built
IGNORE = shutil.ignore_patterns(".git", "build", "dist", "*.egg-info", "__pycache__", ".venv", ".pytest_cache",
                                "results", "runs", "*.mp4", "MUJOCO_LOG.TXT")


def test_wheel_contains_the_runtime_files(tmp_path):
    # build a clean copy: setuptools reuses ./build/lib, which can hold stale files, and other
    # builds may be using it
    src = tmp_path / "src"
    shutil.copytree(REPO, src, ignore=IGNORE)
    r = subprocess.run([sys.executable, "-m", "pip", "wheel", "--no-deps", "--no-build-isolation", "--quiet",
                        "-w", str(tmp_path / "dist"), str(src)], capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    (wheel,) = (tmp_path / "dist").glob("mjtether-*.whl")
    names = set(zipfile.ZipFile(wheel).namelist())
    for need in ("mjtether/assets/walker/walker.xml", "mjtether/assets/walker/scene.xml",
                 "mjtether/scenarios/default.toml", "mjtether/envs/__init__.py", "mjtether/io/mjlog.py",
                 "mjtether/cable/linetypes.toml", "mjtether/cable/bound.py", "mjtether/sweep/execute.py",
                 "mjtether/examples/default_walker.toml", "mjtether/examples/seabed_patch.csv",
                 "mjtether/examples/networks/rov_cage_excursion.toml", "mjtether/cli/__init__.py",
                 "mjtether/io/report_page/run.html", "mjtether/io/report_page/sweep.html",
                 "mjtether/io/report_page/report.js", "mjtether/io/report_page/report.css",
                 "mjtether/io/report_page/vendor/three.module.min.js",
                 "mjtether/io/report_page/vendor/OrbitControls.js", "mjtether/io/report_page/vendor/LICENSE"):
        assert need in names, f"{need} is not in {wheel.name}"
    # the fixed top-level folders (assets/, envs/, tests/...) only ship under mjtether/
    stray = sorted(n for n in names if not n.startswith(("mjtether/", "mjtether-")))
    assert not stray, stray
