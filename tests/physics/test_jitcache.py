"""Compiled kernels never run stale code: a change to a kernel that another kernel inlines, in
another module, is seen through numba's on-disk cache (``mjtether.physics.jitcache``).

The case numba's own cache misses: ``quasistatic.kernels._element_load`` calls
``physics.compiled._density``; with numba's stamp (the caller's own file's time and size) an
edit to ``_density`` alone left the cached ``_element_load`` computing the old density. Here a
copy of the package is run twice in fresh processes sharing one cache folder, the second time
with the constant density doubled in ``compiled.py`` only: the buoyancy the caller computes must
double with it (an exact answer: rho A l g is linear in rho)."""

import os
import shutil
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from mjtether.physics import compiled

pytestmark = pytest.mark.skipif(compiled.numba is None, reason="numba is not installed")

PACKAGE = Path(__file__).resolve().parents[2] / "mjtether"

PROBE = textwrap.dedent("""
    import numpy as np
    from mjtether.physics import compiled
    from mjtether.quasistatic import kernels
    import mjtether
    assert mjtether.__file__.startswith({root!r}), mjtether.__file__
    codes = compiled.profile_codes(mjtether.WaterColumn(density=mjtether.ConstantDensity(1000.0)))
    f = np.empty(3)
    # a vertical element 1 m long, 0.1 m across, massless, in still water: f[2] is its buoyancy
    kernels._element_load(-10.0, np.array([0.0, 0.0, 1.0]), 1.0, 1.0, 0.1, 0.25 * np.pi * 0.01, 0.0, 1.2, 0.03,
                          0.0, *codes, np.zeros(3), 9.81, f)
    print(repr(float(f[2])))
""")


def _buoyancy(root: Path, cache: Path) -> float:
    env = dict(os.environ, PYTHONPATH=str(root), NUMBA_CACHE_DIR=str(cache), MJTETHER_KERNELS="numba")
    r = subprocess.run([sys.executable, "-c", PROBE.format(root=str(root))], env=env, cwd=root,
                       capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr[-2000:]
    return float(r.stdout.strip().splitlines()[-1])


def test_a_changed_inlined_kernel_is_recompiled(tmp_path):
    root, cache = tmp_path / "src", tmp_path / "cache"
    shutil.copytree(PACKAGE, root / "mjtether", ignore=shutil.ignore_patterns("__pycache__"))
    before = _buoyancy(root, cache)
    assert before == pytest.approx(1000.0 * 0.25 * 3.141592653589793 * 0.01 * 9.81, rel=1e-12)
    source = root / "mjtether" / "physics" / "compiled.py"
    text = source.read_text()
    constant = "    if kind == 0:\n        return p[0]\n"
    assert constant in text, "compiled._density changed shape: update this test's edit"
    source.write_text(text.replace(constant, "    if kind == 0:\n        return 2.0 * p[0]\n", 1))
    after = _buoyancy(root, cache)
    assert after == pytest.approx(2.0 * before, rel=1e-12), "the cached caller ran the old _density"


def test_the_first_run_says_it_compiles_then_never_again(tmp_path, monkeypatch, capsys):
    """A run whose kernels are not known to be cached says it is compiling them before its
    progress bar starts, and marks them cached once it has run; the next run says nothing."""
    from helpers import small

    from mjtether import cli
    from mjtether.physics import jitcache

    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path / "cache"))  # (where the marker goes)
    monkeypatch.setattr(jitcache, "CACHE", True)
    monkeypatch.setenv(compiled.KERNELS_ENV, "numba")
    assert not jitcache.warm()
    f = tmp_path / "s.toml"
    f.write_text(small(0.5))
    assert cli.main(["run", str(f), "--out", str(tmp_path / "a"), "--no-plots"]) == 0
    first = capsys.readouterr().err
    assert "compiling the force kernels" in first
    assert jitcache.warm()
    assert cli.main(["run", str(f), "--out", str(tmp_path / "b"), "--no-plots"]) == 0
    assert "compiling" not in capsys.readouterr().err


def test_every_compiled_function_is_stamped_by_its_own_source():
    """The stamp covers the source of every function numba compiles in the package, wherever the
    compiled object is kept: a function defined in one module and compiled (or inlined) from
    another is stamped through its defining module's file. Found: a kernel compiled in
    ``native`` from a plain function of ``actuation`` left ``actuation.py`` out of the stamp."""
    import importlib
    import pkgutil

    import mjtether
    from mjtether.physics import jitcache

    stamped = set(jitcache.kernel_modules())
    seen = 0
    for info in pkgutil.walk_packages(mjtether.__path__, "mjtether."):
        module = importlib.import_module(info.name)
        for value in vars(module).values():
            py_func = getattr(value, "py_func", None)
            if py_func is None or not hasattr(value, "signatures"):  # not a numba dispatcher
                continue
            source = Path(py_func.__code__.co_filename).resolve()
            if source.is_relative_to(PACKAGE.resolve()):
                seen += 1
                assert str(source.relative_to(PACKAGE.resolve())) in stamped, (info.name, py_func.__name__, source)
    assert seen > 20
