"""Network TOML that cannot be right is refused before a build, naming the line and the limit."""

import pytest

from mjtether.network import NetworkError, from_dict


def _net(lines, span=80.0):
    return {"water": {"depth": 100.0},
            "line_types": {"rope": {"diameter": 0.08, "mass_per_length": 12.0, "EA": 5e7}},
            "points": {"a": {"kind": "fixed", "position": [0.0, 0.0, -100.0]},
                       "b": {"kind": "fixed", "position": [span, 0.0, -100.0]},
                       "c": {"kind": "fixed", "position": [0.0, 10.0, -100.0]}},
            "lines": lines}


def test_a_held_line_far_too_short_for_its_ends_is_refused():
    """10 m of line between fixed points 80 m apart (700 % stretch, 6 MN at this EA) is refused
    naming the line, the span and the shortest length allowed; 45 m (78 %) still builds."""
    with pytest.raises(NetworkError, match=r"line 'x': length 10 m .* 80 m apart .* 700 %.*length >= 40 m"):
        from_dict(_net([{"name": "x", "type": "rope", "a": "a", "b": "b", "length": 10.0, "segments": 5}]))
    from_dict(_net([{"name": "x", "type": "rope", "a": "a", "b": "b", "length": 45.0, "segments": 5}]))


def test_line_names_whose_arrays_collide_in_lines_npz_are_refused():
    """Lines "1" and "1_nodes" would both write lines.npz's line1_nodes."""
    lines = [{"name": "1", "type": "rope", "a": "a", "b": "b", "length": 90.0, "segments": 5},
             {"name": "1_nodes", "type": "rope", "a": "a", "b": "c", "length": 20.0, "segments": 5}]
    with pytest.raises(NetworkError, match=r"line '1_nodes': .*line1_nodes"):
        from_dict(_net(lines))
    lines[1]["name"] = "1b"
    from_dict(_net(lines))


@pytest.mark.parametrize("value", [0.0, -1.0, float("nan"), "tall", True])
def test_a_float_s_waterline_height_is_checked(value):
    data = _net([{"name": "x", "type": "rope", "a": "a", "b": "f", "length": 90.0, "segments": 5}])
    data["points"]["f"] = {"kind": "free", "position": [50.0, 0.0, -20.0], "volume": 1.0, "height": value}
    with pytest.raises(NetworkError, match=r"point 'f': height"):
        from_dict(data)
