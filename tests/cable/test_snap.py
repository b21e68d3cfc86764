"""Snap loads: slack-to-taut events found in tension histories built here with known slack spells.

The histories are sampled at dt = 1/64 s, so that every sample time (k dt) and every difference
of two is exact in binary: the expected times and durations below come from the sample indices
the histories were built with, and are compared to 1e-12 s (round-off only)."""

import math

import numpy as np
import pytest

from mjtether.cable.snap import (SnapDetector, by_element, dnv_slack_check, slack_threshold, snap_summary,
                                 worst_events)

DT = 1.0 / 64
STATIC = 1000.0  # N, every element's static tension
N = 6


def history(n_samples, spells, seed=0):
    """Tensions (n_samples, N): STATIC with +-5 % ripple, and for each (element, first slack
    sample, first taut sample, peak N) a slack spell at 0.2 N (below the 10 N threshold), then
    a half-sine snap of 0.5 s (32 samples) whose sample 16 is exactly the peak."""
    rng = np.random.default_rng(seed)
    T = STATIC * (1.0 + 0.05 * rng.uniform(-1.0, 1.0, (n_samples, N)))
    for e, k0, k1, peak in spells:
        T[k0:k1, e] = 0.2
        s = np.arange(33)
        T[k1:k1 + 33, e] = STATIC + (peak - STATIC) * np.sin(np.pi * s / 32)
    return T


def run(T, **kw):
    det = SnapDetector(N, slack_threshold(np.full(N, STATIC)), **kw)
    for k, row in enumerate(T):
        det.update(k * DT, row)
    return det


SPELLS = [(1, 128, 160, 5000.0), (4, 200, 328, 8000.0), (1, 400, 416, 3000.0)]


def test_events_at_the_right_times_elements_peaks_and_durations():
    """Three slack spells built into a 6-element history (two on element 1, one on element 4):
    each is one event, at the first taut sample, with the built peak and the built slack
    duration ((first taut - first slack sample) dt); no other element reports one."""
    det = run(history(600, SPELLS))
    ev = det.events
    assert [e["element"] for e in ev] == [1, 4, 1]
    for e, (el, k0, k1, peak) in zip(ev, SPELLS):
        assert e["time_s"] == pytest.approx(k1 * DT, abs=1e-12)
        assert e["slack_duration_s"] == pytest.approx((k1 - k0) * DT, abs=1e-12)
        assert e["peak_tension_N"] == pytest.approx(peak, rel=1e-12)
    assert not det.slack_now.any()
    assert det.min_tension_N[1] == 0.2 and det.min_tension_N[0] > 0.9 * STATIC


def test_summary_groups_by_element_and_keeps_the_worst():
    """Grouping and ranking of the same three events, against the built spells."""
    ev = run(history(600, SPELLS)).events
    groups = by_element(ev)
    assert [(g["element"], g["count"]) for g in groups] == [(1, 2), (4, 1)]
    assert groups[0]["peak_tension_N"] == pytest.approx(5000.0)
    assert groups[0]["first_time_s"] == pytest.approx(160 * DT)
    assert groups[0]["slack_duration_s"] == pytest.approx(32 * DT)  # the longer of 32 and 16 samples
    assert [e["peak_tension_N"] for e in worst_events(ev, 2)] == pytest.approx([8000.0, 5000.0])
    s = snap_summary(ev, worst=1)
    assert s["count"] == 3 and s["max_peak_tension_N"] == pytest.approx(8000.0)
    assert s["longest_slack_s"] == pytest.approx(128 * DT) and len(s["worst"]) == 1
    assert snap_summary([]) == {"count": 0, "max_peak_tension_N": 0.0, "longest_slack_s": 0.0,
                                "elements": [], "worst": []}


def test_a_line_that_never_goes_slack_reports_none():
    """Tensions swinging between about 14 % and 195 % of the static tension (never at the 1 % slack
    threshold): no event, and the least tension is the history's own minimum."""
    T = history(600, [])
    T *= 1.0 + 0.9 * np.sin(2 * np.pi * np.arange(600) * DT / 1.3)[:, None] / 1.05
    det = run(T)
    assert det.events == [] and det.summary()["count"] == 0
    np.testing.assert_array_equal(det.min_tension_N, T.min(axis=0))


def test_noise_near_the_threshold_makes_no_events():
    """Noise just above the slack threshold (10 N to 10.5 N) on every element: never slack.
    Then element 2 goes slack and ripples between 5 N and 19.9 N (across the slack threshold,
    below the 20 N taut one) for 3 s before it is taut again: one event, whose slack spell
    began at its first sample at or below 10 N."""
    rng = np.random.default_rng(1)
    T = 10.0 * (1.0 + 1e-9 + 0.05 * rng.uniform(0.0, 1.0, (400, N)))
    assert not run(T).events
    T = history(700, [])
    T[100:292, 2] = rng.uniform(5.0, 19.9, 192)
    T[100, 2] = 12.0  # the spell starts at sample 101
    T[101, 2] = 9.0
    ev = run(T).events
    assert len(ev) == 1 and ev[0]["element"] == 2
    assert ev[0]["time_s"] == pytest.approx(292 * DT) and ev[0]["slack_duration_s"] == pytest.approx(191 * DT)


def test_the_peak_is_sought_within_the_window_or_until_slack_again():
    """A tension ramping up at 1000 N/s for 5 s after re-tautening: the peak is the value at the
    window's end (window_s = 2 s: 100 + 2000 N); a snap cut short by a new slack spell 0.5 s in
    ends there (its peak the ramp's value at 0.5 s - dt), and the new spell is timed from then."""
    T = history(900, [])
    T[100:200, 0] = 0.0
    T[200:520, 0] = 100.0 + 1000.0 * np.arange(320) * DT
    T[100:200, 3] = 0.0
    T[200:232, 3] = 100.0 + 1000.0 * np.arange(32) * DT
    T[232:300, 3] = 0.0
    ev = run(T, window_s=2.0).events
    assert [e["element"] for e in ev] == [0, 3, 3]
    assert ev[0]["peak_tension_N"] == pytest.approx(2100.0)
    assert ev[1]["peak_tension_N"] == pytest.approx(100.0 + 1000.0 * 31 * DT)
    assert ev[2]["time_s"] == pytest.approx(300 * DT) and ev[2]["slack_duration_s"] == pytest.approx(68 * DT)


def test_slack_threshold_default_and_bad_input():
    """1 % of the static tension, at least 1 N; bad input names the field and its range."""
    np.testing.assert_allclose(slack_threshold([2000.0, 50.0, 0.0]), [20.0, 1.0, 1.0])
    with pytest.raises(ValueError, match="slack_threshold_N must be > 0"):
        SnapDetector(3, 0.0)
    with pytest.raises(ValueError, match="taut_threshold_N must be >= slack_threshold_N"):
        SnapDetector(3, 10.0, taut_threshold_N=5.0)
    with pytest.raises(ValueError, match="slack_threshold_N must be one finite tension"):
        SnapDetector(3, [1.0, 2.0])
    det = SnapDetector(3, 1.0)
    with pytest.raises(ValueError, match="tension_N must hold 3"):
        det.update(0.0, [1.0, 2.0])
    with pytest.raises(ValueError, match="tension_N must be finite and >= 0 N.*element 1"):
        det.update(0.0, [1.0, -2.0, 3.0])
    det.update(0.0, [1.0, 2.0, 3.0])
    with pytest.raises(ValueError, match="later than"):
        det.update(0.0, [1.0, 2.0, 3.0])
    with pytest.raises(ValueError, match="n_elements"):
        SnapDetector(0, 1.0)


def test_dnv_slack_criterion():
    """DNV-RP-H103's criterion: slack below 10 % of the static submerged weight (here 2000 N:
    the limit 200 N), computed by hand."""
    r = dnv_slack_check(150.0, 2000.0)
    assert r["slack"] and r["limit_N"] == pytest.approx(200.0) and r["ratio"] == pytest.approx(0.075)
    assert "below 10 %" in r["verdict"] and "DNV-RP-H103" in r["criterion"]
    r = dnv_slack_check(200.0, 2000.0)
    assert not r["slack"] and r["ratio"] == pytest.approx(0.1)
    with pytest.raises(ValueError, match="static_submerged_weight_N must be > 0"):
        dnv_slack_check(10.0, 0.0)


@pytest.mark.skipif(__import__("mjtether.physics.compiled", fromlist=["numba"]).numba is None,
                    reason="the compiled twin needs numba")
def test_the_compiled_twin_agrees_with_the_numpy_reference():
    """``update_from_constraints`` by the compiled twin (``kernels.snap_update``) against the
    NumPy ``update`` on 400 steps of a 12-element line whose elements go slack and taut at
    random, switch their equalities off (slack: no row) and are reeled onto the drum and paid
    out again (``first`` from 0 to 4 and back): the same events, states and extremes, exactly
    (the same comparisons in the same order)."""
    rng = np.random.default_rng(7)
    n = 12
    thr = slack_threshold(rng.uniform(50.0, 500.0, n))
    a, b = SnapDetector(n, thr, window_s=0.5, compiled=True), SnapDetector(n, thr, window_s=0.5, compiled=False)
    assert a.compiled and not b.compiled
    for k in range(400):
        tension = np.where(rng.uniform(size=n) < 0.2, rng.uniform(0.0, 3.0, n), rng.uniform(0.0, 900.0, n))
        active = rng.uniform(size=n) > 0.1
        first = int(4 * abs(math.sin(k / 60)))
        for det in (a, b):
            det.update_from_constraints((k + 1) * DT, active, -tension[active], first)
    assert a.events == b.events and len(a.events) > 50
    for key in ("slack_now", "min_tension_N", "max_tension_N", "interval_max_N", "_peak", "_t_taut"):
        np.testing.assert_array_equal(getattr(a, key), getattr(b, key), err_msg=key)


def test_a_copy_goes_on_alone_from_where_it_was_taken():
    """``copy`` (what ``Simulation.save_state`` keeps): the original fed 300 more samples (the
    second and third spells) leaves the copy as it was; the copy fed the same samples then gives
    the same three events as a detector fed the whole history at once."""
    T = history(600, SPELLS)
    det = SnapDetector(N, slack_threshold(np.full(N, STATIC)))
    for k in range(300):
        det.update(k * DT, T[k])
    saved = det.copy()
    before = (len(saved.events), saved.min_tension_N.copy(), saved.time)
    for k in range(300, 600):
        det.update(k * DT, T[k])
    assert (len(saved.events), saved.time) == (before[0], before[2])
    np.testing.assert_array_equal(saved.min_tension_N, before[1])
    for k in range(300, 600):
        saved.update(k * DT, T[k])
    assert saved.events == det.events == run(T).events and len(det.events) == 3
