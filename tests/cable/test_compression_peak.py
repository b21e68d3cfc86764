"""The recorded pushes are the largest since the previous sample, not the push at the sample's
step: ``max_compression`` (timeseries.csv) and ``compression`` (lines.npz) against MuJoCo's own
constraint forces read here after every step (``efc_force`` of each element equality
``tether/element<j>``'s row, found by ``efc_type``/``efc_id`` and the equality's name, without
mjtether's readouts or row cache).

The case: a line paid out at 2 m/s from 250 m to an anchor 200 m down, sampled every 0.5 s
(``test_compression``'s payout): at touchdown single elements push by 0.3-1.9 N for a step or
two between samples, while the push at the sample steps is 0 (measured over the first 5 s:
interval peaks 1.93, 1.21, 0.30 and 0.50 N, each sample 0 but one of 0.26 N)."""

import re

import mujoco
import numpy as np
import pytest

from mjtether.physics import compiled
from mjtether.scenario import load_scenario
from mjtether.scenario import runner as runner_mod
from mjtether.scenario.readouts import RECORD_FIELDS
from mjtether.scenario.runner import ScenarioRun

PAYOUT = """[simulation]
duration = 5.0
timestep = 0.005
output_interval = 0.5
[water]
depth = 200.0
[tether]
length = 250.0
segments = 50
diameter = 0.03
mass_per_length = 1.5
EA = 1e7
seabed_friction = 0.0
[ship]
mode = "fixed"
[winch]
mode = "constant"
rate = 2.0
max_length = 700.0
[robot]
type = "anchor"
position = [100.0, 0.0, -200.0]
"""
EVERY = 100  # steps per sample (0.5 s / 5 ms)
COLUMN = [f[0] for f in RECORD_FIELDS].index("max_compression")


class RawPushes:
    """Each deployed element's push (N, >= 0) straight from MuJoCo's constraint rows."""

    def __init__(self, m):
        self.element = np.full(m.neq, -1)  # equality id -> element number (-1: not an element)
        for i in range(m.neq):
            hit = re.fullmatch(r"tether/element(\d+)", mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_EQUALITY, i) or "")
            if hit:
                self.element[i] = int(hit.group(1))
        self.n = int(self.element.max()) + 1

    def __call__(self, d, first: int) -> np.ndarray:
        out = np.zeros(self.n)
        rows = np.flatnonzero(d.efc_type[:d.nefc] == mujoco.mjtConstraint.mjCNSTR_EQUALITY)
        j = self.element[d.efc_id[rows]]
        keep = j >= first  # elements on the drum are not deployed cable
        np.maximum.at(out, j[keep], np.maximum(d.efc_force[rows[keep]], 0.0))
        return out


def _interval_peaks(raw: list) -> np.ndarray:
    """The expected record: at t = 0 the push then; at each later sample the largest push of
    each element over the steps since the previous sample (shape (samples, n))."""
    steps = np.array(raw[1:])
    return np.vstack([raw[0], steps.reshape(-1, EVERY, steps.shape[1]).max(axis=1)])


@pytest.fixture(params=["numba", "numpy"])
def kernels(request, monkeypatch):
    if request.param == "numba" and compiled.numba is None:
        pytest.skip("numba is not installed")
    monkeypatch.setenv(compiled.KERNELS_ENV, request.param)
    return request.param


def test_the_record_holds_the_largest_push_since_the_previous_sample(kernels, monkeypatch):
    """``runner.run`` on the payout: every sample's ``compression`` row equals, element by
    element, the largest of the raw pushes of the steps since the previous sample (exactly: the
    same floats, a maximum taken), ``max_compression`` the largest of those; so each is >= every
    push in its interval. Not vacuous: some sample step has no push while its interval had one
    over 1 N (what the record showed before: the sample step's push alone). With the compiled
    kernels and with the NumPy reference."""
    raw, read = [], {}
    step = ScenarioRun.step

    def step_and_read(self):
        step(self)
        raw.append(read["f"](self.sim.data, self.bt.first))

    def on_start(run):
        read["f"] = RawPushes(run.sim.model)
        raw.append(read["f"](run.sim.data, run.bt.first))

    monkeypatch.setattr(ScenarioRun, "step", step_and_read)
    rows, history, _ = runner_mod.run(load_scenario(text=PAYOUT), on_start=on_start)
    assert len(raw) == 1 + 10 * EVERY and rows.shape[0] == 11
    expected = _interval_peaks(raw)
    comp = history["compression"]
    assert comp.shape == expected.shape
    assert np.array_equal(comp, expected)
    assert np.array_equal(rows[:, COLUMN], expected.max(axis=1))
    steps = np.array(raw[1:]).reshape(-1, EVERY, expected.shape[1])
    assert np.all(rows[1:, COLUMN][:, None] >= steps.max(axis=2))
    at_sample = steps[:, -1].max(axis=1)
    assert np.any((at_sample == 0.0) & (rows[1:, COLUMN] > 1.0)), (at_sample, rows[:, COLUMN])


def test_take_peak_compression_between_takes(kernels):
    """``BoundTether.take_peak_compression`` (what the network's record calls) stepped by hand:
    each take, every 100 steps, is the element-wise largest raw push since the previous take;
    a second take at once gives the push now only; after ``restore_state`` the peak starts
    again from the restored state (the steps undone, which pushed by over 1 N, are forgotten).
    Exact (the same floats)."""
    run = ScenarioRun(load_scenario(text=PAYOUT))
    try:
        sim, bt = run.sim, run.bt
        raw = RawPushes(sim.model)
        assert np.array_equal(bt.take_peak_compression(), raw(sim.data, bt.first))
        worst = 0.0
        for _ in range(5):
            seen = []
            for _ in range(EVERY):
                run.step()
                seen.append(raw(sim.data, bt.first))
            peak = bt.take_peak_compression()
            assert np.array_equal(peak, np.max(seen, axis=0))
            assert np.array_equal(bt.take_peak_compression(), seen[-1])
            worst = max(worst, float(peak.max()))
        assert worst > 1.0
        saved = sim.save_state()
        seen = []
        for _ in range(EVERY):
            run.step()
            seen.append(raw(sim.data, bt.first))
        sim.restore_state(saved)
        run.step()  # (the same step as the first undone: the run is deterministic)
        now = raw(sim.data, bt.first)
        assert np.array_equal(now, seen[0]) and np.max(seen) > 1.0 > now.max()  # (forgetting the undone shows)
        assert np.array_equal(bt.take_peak_compression(), now)
    finally:
        run.close()
