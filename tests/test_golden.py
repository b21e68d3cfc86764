"""Restructuring the runner changes no result: every example scenario gives, bit for bit, the
rows, nodes and tensions it gave before, and each environment the same observations and rewards
(``tests/golden.py`` says when they were written and how).

Tolerance: none (bitwise) on the machine the golden runs were written on (the CPU model and
the NumPy, SciPy, MuJoCo and numba versions, kept in the file): the same operations in the same
order give the same bits, and this test is what shows that moving code between modules moved
no arithmetic. Elsewhere BLAS picks other kernels by CPU and the last bits differ, so there the
runs must agree to 1e-9 of each array's largest value (a trajectory's rounding grows over 2 s to
about 1e-12; 1e-9 still catches any change of the physics). It runs with the compiled kernels."""

import os

import numpy as np
import pytest

from golden import ENVS, EXAMPLES, GOLDEN, machine, runs
from mjtether import compiled

pytestmark = pytest.mark.skipif(compiled.numba is None, reason="the golden runs were written with numba's kernels")


@pytest.fixture(scope="module")
def now():
    was = os.environ.pop(compiled.KERNELS_ENV, None)  # the compiled kernels, as the golden runs
    try:
        return runs()
    finally:
        if was is not None:
            os.environ[compiled.KERNELS_ENV] = was


def test_every_example_is_in_the_golden_file(now):
    with np.load(GOLDEN) as old:
        assert sorted(f for f in old.files if f != "_machine") == sorted(now)
    assert len(now) == 3 * len(EXAMPLES) + 2 * len(ENVS) >= 28


CASES = [(p.stem, ("rows", "nodes", "tension")) for p in EXAMPLES] + \
    [(e.split("/")[1], ("obs", "reward")) for e in ENVS]


@pytest.mark.parametrize("name, parts", CASES, ids=[c[0] for c in CASES])
def test_run_is_bitwise_the_same(now, name, parts):
    with np.load(GOLDEN) as old:
        for part in parts:
            key = f"{name}/{part}"
            a, b = now[key], old[key]
            assert a.shape == b.shape, f"{key}: shape {a.shape}, was {b.shape}"
            if str(old["_machine"]) == machine():
                diff = np.flatnonzero(a.ravel() != b.ravel())
                assert len(diff) == 0, (f"{key}: {len(diff)} of {a.size} values differ, the largest by "
                                        f"{np.max(np.abs(a - b)):.3g}")
            else:
                scale = max(float(np.max(np.abs(b))), 1e-300)
                assert np.max(np.abs(a - b)) <= 1e-9 * scale, (
                    f"{key}: differs by {np.max(np.abs(a - b)) / scale:.3g} of its largest value (another "
                    f"machine: {machine()!r}, written on {str(old['_machine'])!r})")
