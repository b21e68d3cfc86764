"""A network run of days, or of more output than allowed, or of more lines than a build takes, is
refused before anything is built (it ran until killed: a 1e9 s run, 1000 lines), naming the key
and the limit."""

import pytest

from mjtether.network import NetworkError, from_dict, run
from mjtether.network.config import MAX_LINES


def _net(lines: int = 1, **simulation):
    points = {f"a{i}": {"kind": "fixed", "position": [float(i), 0.0, -50.0]} for i in range(lines)}
    points.update({f"b{i}": {"kind": "fixed", "position": [float(i), 0.0, -10.0]} for i in range(lines)})
    return from_dict({"water": {"depth": 100.0}, "simulation": simulation,
                      "line_types": {"rope": {"diameter": 0.02, "mass_per_length": 1.0, "EA": 1e7}},
                      "points": points,
                      "lines": [{"name": f"l{i}", "type": "rope", "a": f"a{i}", "b": f"b{i}", "length": 41.0,
                                 "segments": 10} for i in range(lines)]})


def test_a_run_of_a_billion_seconds_is_refused_by_its_range():
    with pytest.raises(NetworkError, match=r"simulation.duration must be in \[0.001, 1000000.0\] s"):
        _net(duration=1e9)


def test_a_run_of_days_is_refused_with_its_estimate():
    """1e6 s at the line's own step: hundreds of hours at the cost model's 340 us a step."""
    with pytest.raises(NetworkError, match=r"simulation.duration = 1e\+06 s: .* over simulation.max_wall_hours = 6 h"):
        run.build(_net(duration=1e6))


def test_more_output_than_allowed_is_refused():
    with pytest.raises(NetworkError, match=r"simulation.output_interval = 0.0001 s: .* over "
                                           r"simulation.max_output_gb = 0.01 GB"):
        run.build(_net(duration=1000.0, output_interval=1e-4, max_output_gb=0.01))


def test_too_many_lines_are_refused_before_a_build():
    with pytest.raises(NetworkError, match=f"lines: {MAX_LINES + 1} lines; a network takes at most {MAX_LINES}"):
        _net(lines=MAX_LINES + 1)


def test_the_estimate_counts_the_drum_and_the_samples():
    """10 elements deployed plus the drum's: a line paying out from 41 m to 82 m holds 20."""
    net = _net(duration=10.0, output_interval=0.5)
    est = run.cost.estimate(net, 0.01)
    assert est["steps"] == pytest.approx(1000.0) and est["samples"] == pytest.approx(21.0)
    assert est["elements"] == 10
    import dataclasses
    paying = dataclasses.replace(net, lines=(dataclasses.replace(net.lines[0], payout_speed=1.0, max_length=82.0),))
    assert run.cost.estimate(paying, 0.01)["elements"] == 20
