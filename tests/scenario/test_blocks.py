"""A scenario whose controllers hold still steps in blocks (``ScenarioRun.advance``): the same bits.

The reference is the same run one ``ScenarioRun.step`` at a time (``ScenarioRun.blocks =
False``): the controllers before every step, the rated-load check after it. Where every
controller writes the same values at every step (a ship holding station on a flat sea, a fixed
winch), calling them once per block changes nothing, so the two must agree bit for bit
(tolerance 0); a run with a rated load to check, or a controller that moves, is stepped one step
at a time, and fails where the step-by-step run fails.
"""

import numpy as np
import pytest

from mjtether.io import moordyn
from mjtether.scenario.runner import RunFailed, ScenarioRun, run

CHAIN = "tests/data/moordyn/tests/Mooring/WD0050_Chain.txt"  # (one chain from a held fairlead to an anchor)


def _run(monkeypatch, blocks: bool, *overrides):
    monkeypatch.setattr(ScenarioRun, "blocks", blocks)
    sc = moordyn.read(CHAIN, overrides=["simulation.duration=10", *overrides])
    seen = {}
    result = run(sc, keep_nodes=True, on_end=lambda r: seen.update(calls=r.sim._stepper.calls, idle=[
        getattr(c, "idle", False) for c in r.controllers]))
    return result, seen


def test_a_held_chain_steps_in_blocks_with_the_same_bits(monkeypatch):
    """MoorDyn's 50 m-water chain, its fairlead held, 10 s: every row of the time series and
    every sample of the history as the step-by-step run gives them, in far fewer compiled calls
    than steps (one block per output sample)."""
    (rows_a, hist_a, info_a), one = _run(monkeypatch, False)
    (rows_b, hist_b, info_b), blocks = _run(monkeypatch, True)
    assert all(blocks["idle"]) and info_a["steps"] == info_b["steps"] > 100
    assert one["calls"] >= info_a["steps"] and blocks["calls"] < info_b["steps"] / 5
    np.testing.assert_array_equal(rows_a, rows_b)
    for key in hist_a:
        np.testing.assert_array_equal(hist_a[key], hist_b[key], err_msg=key)


def test_a_rated_load_is_checked_at_every_step(monkeypatch):
    """The same chain with a rated load just under its fairlead tension: both runs fail, at the
    same step, with the same message (the check is not left to a block's end)."""
    (rows, _, _), _ = _run(monkeypatch, False)
    rated = 0.999 * float(rows[:, 1].max())
    messages = []
    for blocks in (False, True):
        with pytest.raises(RunFailed) as err:
            _run(monkeypatch, blocks, f"tether.rated_load={rated!r}")
        messages.append(str(err.value))
    assert messages[0] == messages[1] and "rated load" in messages[0]


def test_a_heaving_ship_is_stepped_one_step_at_a_time(monkeypatch):
    """The same chain under a ship heaving 1 m at 8 s: its ship is not idle, so both runs step
    one step at a time and agree; a block would hold the fairlead where the block began."""
    heave = ("ship.heave_amplitude=1.0", "ship.heave_period=8.0")
    (rows_a, _, _), _ = _run(monkeypatch, False, *heave)
    (rows_b, _, info), seen = _run(monkeypatch, True, *heave)
    assert not all(seen["idle"]) and seen["calls"] >= info["steps"]
    np.testing.assert_array_equal(rows_a, rows_b)
    assert np.ptp(rows_a[:, 1]) > 0.01 * rows_a[:, 1].mean()  # (the heave shows in the fairlead tension)
