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
from mjtether.physics import compiled

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


def _differs(a: np.ndarray, b: np.ndarray, bitwise: bool) -> str | None:
    """Why ``a`` (now) is not ``b`` (golden), or None: bit for bit, or else within 1e-9 of
    ``b``'s largest value (an empty array, e.g. the tensions of a run without a tether, agrees
    with an empty one)."""
    if a.shape != b.shape:
        return f"shape {a.shape}, was {b.shape}"
    if bitwise:
        diff = np.flatnonzero(a.ravel() != b.ravel())
        return f"{len(diff)} of {a.size} values differ, the largest by {np.max(np.abs(a - b)):.3g}" if len(diff) else None
    if a.size == 0:
        return None
    scale = max(float(np.max(np.abs(b))), 1e-300)
    worst = float(np.max(np.abs(a - b))) / scale
    return None if worst <= 1e-9 else f"differs by {worst:.3g} of its largest value"


@pytest.mark.parametrize("name, parts", CASES, ids=[c[0] for c in CASES])
def test_run_is_bitwise_the_same(now, name, parts):
    """Bit for bit on the machine that wrote the file; within 1e-9 everywhere (the other
    machines' check runs here too, so that it is exercised on every machine)."""
    with np.load(GOLDEN) as old:
        same_machine = str(old["_machine"]) == machine()
        for part in parts:
            key = f"{name}/{part}"
            a, b = now[key], old[key]
            why = _differs(a, b, bitwise=False)
            assert why is None, f"{key}: {why} (this machine: {machine()!r}, written on {str(old['_machine'])!r})"
            if same_machine:
                why = _differs(a, b, bitwise=True)
                assert why is None, f"{key}: {why}"


def test_the_tolerance_check_can_fail():
    """The cross-machine comparison rejects a change of the physics and takes empty arrays."""
    b = np.linspace(-3.0, 5.0, 40)
    assert _differs(b.copy(), b, bitwise=False) is None
    assert _differs(b * (1 + 1e-12), b, bitwise=False) is None
    assert _differs(b * (1 + 1e-7), b, bitwise=False) is not None
    assert _differs(b[:-1], b, bitwise=False) is not None
    assert _differs(np.zeros((0, 3)), np.zeros((0, 3)), bitwise=False) is None
    assert _differs(np.zeros((0, 3)), np.zeros((0, 3)), bitwise=True) is None
