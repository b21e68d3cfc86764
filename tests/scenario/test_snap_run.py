"""Snap loads in a run: every element's slack-to-taut events found at every time step, reported
in summary.json, the time series and the plot.

The answer the detector is checked against is written here: the element tensions read after
every step through the NumPy readouts (``BoundTether.element_tension``, not the compiled twin
the run uses) and a plain loop over steps and elements that applies the definition of a snap
(``mjtether.cable.snap``'s docstring: slack at or below 1 % of the element's static tension,
taut again above twice that, the peak sought until the element goes slack again or 2 s have
passed)."""

import json
import math

import numpy as np
import pytest

from mjtether.cable import snap
from mjtether.io.results import column_names, write
from mjtether.scenario import load_scenario
from mjtether.scenario.recording import run
from mjtether.scenario.runner import ScenarioRun

from scenario.test_sea_state_run import TAUT  # a nearly taut 60 m line from a fairlead heaving 1 m at 8 s

STEPS = 3200  # 16 s at 5 ms: two heave periods


def _stepped(amplitude: float):
    """(the run, every step's time (s) and element tensions (steps, n) N, the static tensions)."""
    r = ScenarioRun(load_scenario(text=TAUT.replace("heave_amplitude = 1.0", f"heave_amplitude = {amplitude}")))
    static = r.bt.element_tension(r.sim.data)
    times, tensions = [], []
    for _ in range(STEPS):
        r.step()
        times.append(r.sim.time)
        tensions.append(r.bt.element_tension(r.sim.data))
    return r, np.array(times), np.array(tensions), static


def _snaps_by_hand(times, tensions, static, window=2.0):
    """The definition of a snap applied step by step, element by element."""
    slack_at, taut_at = np.maximum(0.01 * static, 1.0), 2.0 * np.maximum(0.01 * static, 1.0)
    events = []
    for e in range(tensions.shape[1]):
        slack, since, open_ = False, None, None
        for t, T in zip(times, tensions[:, e]):
            if open_ is not None:
                open_["peak_tension_N"] = max(open_["peak_tension_N"], T)
                if T <= slack_at[e] or t - open_["time_s"] >= window:
                    events.append(open_)
                    open_ = None
            if T <= slack_at[e] and not slack:
                slack, since = True, t
            if slack and T > taut_at[e]:
                slack = False
                open_ = {"time_s": t, "element": e, "peak_tension_N": T, "slack_duration_s": t - since}
        if open_ is not None:
            events.append(open_)
    return sorted(events, key=lambda ev: (ev["time_s"], ev["element"]))


def test_a_line_that_never_goes_slack_reports_no_snap():
    """Heaving 2 cm, the line's least tension stays above half its static tension in every
    element (read here at every step): no event, and DNV-RP-H103's check says not slack with
    the least top tension read here (to 1e-12 relative)."""
    r, times, tensions, static = _stepped(0.02)
    try:
        assert np.all(tensions.min(axis=0) > 0.5 * static)
        assert r.bt.snaps.events == []
        assert r.bt.snaps.min_tension_N[0] == pytest.approx(tensions[:, 0].min(), rel=1e-12)
    finally:
        r.close()


def test_the_snaps_found_are_those_of_every_steps_tensions():
    """Heaving 1 m at 8 s, the falling fairlead lets the line below its top go slack each
    period, and it snaps taut again: the detector's events (found by the compiled twin as the
    run steps) are those the definition gives on every step's tensions, the same times,
    elements and durations (to 1e-12 s) and peaks (1e-9 relative: the same tensions, read by
    another path). There are many (each period's slack spell runs down the line), none at the
    fairlead's element (the ship holds it taut)."""
    r, times, tensions, static = _stepped(1.0)
    try:
        got = r.bt.snaps.events
        want = _snaps_by_hand(times, tensions, static)
        assert len(want) >= 20
        assert [(e["element"]) for e in got] == [e["element"] for e in want]
        for a, b in zip(got, want):
            assert a["time_s"] == pytest.approx(b["time_s"], abs=1e-12)
            assert a["slack_duration_s"] == pytest.approx(b["slack_duration_s"], abs=1e-12)
            assert a["peak_tension_N"] == pytest.approx(b["peak_tension_N"], rel=1e-9)
        assert all(e["element"] != 0 for e in got)
    finally:
        r.close()


def test_a_runs_results_show_its_snaps(tmp_path):
    """The same run through ``run`` and the writer: ``summary.json``'s ``snap_loads`` counts what
    the CSV's last ``snap_count`` says, its worst event is the largest peak of its events, every
    element is numbered from end A (the anchor) as lines.npz numbers them, and the
    ``peak_tension`` column (the largest element tension since the previous sample) is never
    below the largest element tension sampled; DNV-RP-H103's check compares the top's least
    tension with a tenth of its static one; the plot marks the snaps."""
    sc = load_scenario(text=TAUT)
    rows, history, info = run(sc)
    folder = write(tmp_path / "out", sc, rows, history, info)
    summary = json.loads((folder / "summary.json").read_text())
    loads = summary["snap_loads"]
    cols = column_names()
    assert loads["count"] == rows[-1, cols.index("snap_count")] >= 20
    assert loads["max_peak_tension_N"] == max(e["peak_tension_N"] for e in loads["worst"])
    assert "snap_loads" not in summary["run"]
    with np.load(folder / "lines.npz") as z:
        peak = z["linetether_peak_tension"]
    n = peak.shape[1]
    for e in loads["worst"]:  # (end A's numbering: the anchor's element is 0, the fairlead's n - 1)
        assert 0 <= e["element"] < n - 1
        assert e["from_ship_m"] == pytest.approx((n - 1 - e["element"] + 0.5) * sc.tether.length / n, rel=1e-9)
        k = int(np.searchsorted(rows[:, 0], e["time_s"] + 2.0 - 1e-9))  # (a sample within the snap's window)
        assert peak[:k + 1, e["element"]].max() >= e["peak_tension_N"] * (1 - 1e-12)
    assert np.all(rows[:, cols.index("peak_tension_N")] >= history["tension"].max(axis=1))
    dnv = loads["dnv_slack"]  # (the top's least tension, over every step, is at most the least sampled one)
    assert dnv["element"] == n - 1 and dnv["min_tension_N"] <= history["tension"][:, 0].min() + 1e-9
    assert dnv["limit_N"] == pytest.approx(0.1 * history["tension"][0, 0], rel=1e-9)
    assert dnv["slack"] is (dnv["min_tension_N"] < dnv["limit_N"])
    assert "tension.png" in summary["plots"]
    assert not math.isnan(summary["peak"]["element_tension_N"])
