"""Property test over the scenario configuration (hypothesis): any tree of sections, keys and
values, known or not, of any type, either builds a checked ``Scenario`` or is refused with a
``ConfigError`` whose message names a key path; never another exception. The same for
``--set`` strings on the command line. A scenario that validates is also checked to round-trip:
written back as a dict, it loads to the same scenario.
"""

from __future__ import annotations

import math

from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

from mjtether.scenario.config import ConfigError, params, subsections
from mjtether.scenario import Scenario, load_scenario


def _key_paths(cls, prefix=""):
    out = []
    for name in params(cls):
        out.append(prefix + name)
    for name, sub in subsections(cls).items():
        out += _key_paths(sub, f"{prefix}{name}.")
    return out


KEYS = _key_paths(Scenario)
SECTIONS = {k.rsplit(".", 1)[0] for k in KEYS if "." in k}

numbers = st.one_of(st.floats(allow_nan=True, allow_infinity=True), st.integers(-10**9, 10**9),
                    st.sampled_from([0, 1, 2, 4, 60, 0.005, 0.5, 100.0, 200.0, 1e5, 1e12, -1.0, math.nan]))
scalars = st.one_of(numbers, st.booleans(), st.text(max_size=12),
                    st.sampled_from(["steady", "settle", "auto", "walker", "anchor", "table", "exponential",
                                     "fixed", "follow", "waypoints", "tension", "free", "constant"]))
values = st.recursive(scalars, lambda inner: st.lists(inner, max_size=4), max_leaves=8)
key_names = st.one_of(st.sampled_from(KEYS), st.sampled_from(sorted(SECTIONS)),
                      st.sampled_from([k + "_kn" for k in KEYS]), st.text(min_size=1, max_size=8))


def _insert(tree: dict, path: str, value) -> None:
    *sections, leaf = path.split(".")
    node = tree
    for s in sections:
        nxt = node.setdefault(s, {})
        if not isinstance(nxt, dict):
            return
        node = nxt
    node[leaf] = value


def _param(path: str):
    cls = Scenario
    *sections, leaf = path.split(".")
    for s in sections:
        cls = subsections(cls)[s]
    return params(cls)[leaf]


@st.composite
def plausible(draw, path: str):
    """A value of the key's own kind, mostly inside its range (so that many trees validate)."""
    p = _param(path)
    lo, hi = max(p.lo, -1e6), min(p.hi, 1e6)
    num = st.floats(lo, hi) if p.kind != "int" else st.integers(int(max(lo, -10**6)), int(min(hi, 10**6)))
    if p.choices:
        return draw(st.sampled_from(p.choices))
    if p.kind in ("float", "int"):
        return draw(num)
    if p.kind in ("vec2", "vec3"):
        return draw(st.lists(num, min_size=int(p.kind[-1]), max_size=int(p.kind[-1])))
    if p.kind == "list":
        return sorted(draw(st.lists(num, min_size=1, max_size=4)))
    if p.kind in ("rows2", "rows3"):
        n = int(p.kind[-1])
        return draw(st.lists(st.lists(num, min_size=n, max_size=n), min_size=1, max_size=3))
    return draw(values)


@st.composite
def raw_scenarios(draw):
    """A valid anchor scenario with up to 8 keys set to plausible or arbitrary values."""
    tree: dict = {"robot": {"type": "anchor", "position": [40.0, 0.0, -90.0]}, "water": {"depth": 100.0}}
    for _ in range(draw(st.integers(0, 8))):
        if draw(st.booleans()):
            key = draw(st.sampled_from(KEYS))
            _insert(tree, key, draw(plausible(key)))
        else:
            _insert(tree, draw(key_names), draw(values))
    return tree


def _names_a_key(exc: ConfigError) -> bool:
    text = str(exc)
    return bool(exc.key) and exc.key.split(".")[0] in text or any(k in text for k in KEYS)


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(raw_scenarios())
@example({"robot": {"type": "anchor", "position": [40.0, 0.0, -90.0]}, "water": {"depth": 100.0},
          "": {"": 0.0}})  # an empty key (TOML allows "" = 0): shown as "" (found by Hypothesis)
def test_any_tree_validates_or_is_refused_with_a_named_key(raw):
    try:
        sc = load_scenario(data=raw, name="<generated>")
    except ConfigError as exc:
        assert str(exc).startswith("<generated>: "), str(exc)
        assert _names_a_key(exc), str(exc)
        return
    assert isinstance(sc, Scenario)
    assert load_scenario(data=sc.to_dict()) == sc  # what validated round-trips


@settings(max_examples=200, deadline=None)
@given(st.lists(st.tuples(key_names, st.text(max_size=16)), max_size=3))
def test_any_set_override_validates_or_is_refused_with_a_named_key(pairs):
    overrides = [f"{k}={v}" for k, v in pairs]
    try:
        load_scenario(overrides=overrides)
    except ConfigError as exc:
        assert _names_a_key(exc) or "--set" in str(exc), str(exc)
