"""The sweep's input: ``--vary`` specs (``Vary``, ``parse_vary``) and the checked cases
(``Case``, ``Plan``, ``make_plan``; a network's: ``load_network``, ``make_network_plan``, its
figures ``network_columns``), with ``SweepError``, the one-line reason a sweep cannot go on."""

from __future__ import annotations

import hashlib
import itertools
import json
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import tomllib

from mjtether.scenario.config import (
    ConfigError,
    Param,
    params,
    split_index,
    subsections,
    table_lists,
    unknown_key_message,
)

from ..network import Network, NetworkError, to_dict
from ..network import overrides as net_overrides
from ..scenario import Scenario, load_scenario
from ..units import KNOT

MAX_CASES = 100_000
"""More cases than this is refused (a typo in a COUNT, most likely)."""


class SweepError(Exception):
    """A one-line reason the sweep cannot go on; ``code`` is the exit status (2: bad input,
    nothing run or written; 1: stopped while running, finished cases kept)."""

    def __init__(self, message: str, code: int = 2):
        super().__init__(message)
        self.code = code


# ------------------------------------------------------------------ --vary


@dataclass(frozen=True)
class Vary:
    """One ``--vary KEY=SPEC``: a list of ``values`` (with their TOML ``texts``) or a range."""

    key: str  # as given, e.g. water.current.surface_speed_kn
    spec: str
    path: str  # the parameter's key path (without _kn)
    param: Param
    values: tuple  # the grid: the list, or the range's COUNT points
    texts: tuple  # TOML text of each value (what goes into the override)
    range: tuple | None = None  # (start, stop) for a range

    @property
    def knots(self) -> bool:
        return self.key != self.path

    @property
    def column(self) -> str:
        unit = "kn" if self.knots else self.param.unit.replace(" ", "").replace("/", "per")
        if not unit or self.key.endswith(f"_{unit}"):
            return self.key
        return f"{self.key}_{unit}"

    @property
    def numeric(self) -> bool:
        return self.param.kind in ("float", "int")

    def draw(self, rng: np.random.Generator):
        """One random value (and its text): uniform within the range / over the list."""
        if self.range is None:
            k = int(rng.integers(len(self.values)))
            return self.values[k], self.texts[k]
        lo, hi = sorted(self.range)
        if self.param.kind == "int":
            v = int(rng.integers(math.ceil(lo), math.floor(hi), endpoint=True))
        else:
            v = float(rng.uniform(lo, hi))
        return v, _toml(v)


def parse_vary(item: str, net: Network | None = None) -> Vary:
    """A checked ``Vary`` from ``KEY=SPEC`` (a key of the network ``net`` where given: see
    ``mjtether.network.overrides``); raises SweepError naming it."""
    key, sep, spec = str(item).partition("=")
    key, spec = key.strip(), spec.strip()
    where = f"--vary {item}"
    if not sep or not key or not spec:
        raise SweepError(f"{where}: must be KEY=START:STOP:COUNT or KEY=V1,V2,..., "
                         "e.g. --vary tether.length=200:1000:9")
    path, param = _resolve(key, where) if net is None else _resolve_network(net, key, where)
    colons = _split(spec, ":")
    if len(colons) > 1:
        if len(colons) != 3 or len(_split(spec, ",")) > 1:
            raise SweepError(f"{where}: a range is START:STOP:COUNT (COUNT values, both ends included), "
                             "e.g. 200:1000:9; a list is V1,V2,...")
        if param.kind not in ("float", "int"):
            raise SweepError(f"{where}: {path} is not a number ({param.allowed()}); give a list, V1,V2,...")
        try:
            start, stop = (float(tomllib.loads(f"v = {c.strip()}")["v"]) for c in colons[:2])
            count = tomllib.loads(f"v = {colons[2].strip()}")["v"]
        except (tomllib.TOMLDecodeError, TypeError, ValueError):
            raise SweepError(f"{where}: START and STOP must be numbers and COUNT an integer, "
                             "e.g. 200:1000:9") from None
        if isinstance(count, bool) or not isinstance(count, int) or count < 2:
            raise SweepError(f"{where}: COUNT must be an integer >= 2 (the number of values, both ends included)")
        if count > MAX_CASES:
            raise SweepError(f"{where}: COUNT {count} is more than {MAX_CASES} cases")
        if not (math.isfinite(start) and math.isfinite(stop)):
            raise SweepError(f"{where}: START and STOP must be finite numbers")
        grid = [float(v) for v in np.linspace(start, stop, count)]
        if param.kind == "int":
            if any(abs(v - round(v)) > 1e-9 * max(1.0, abs(v)) for v in grid):
                raise SweepError(f"{where}: {path} is an integer, and {spec} gives {_show_list(grid)}; "
                                 "choose START, STOP and COUNT that give integers, or give a list")
            grid = [int(round(v)) for v in grid]
        values, rng = tuple(grid), (start, stop)
        texts = tuple(_toml(v) for v in values)
    else:
        texts = tuple(t.strip() for t in _split(spec, ","))
        if any(not t for t in texts):
            raise SweepError(f"{where}: an empty item in the list (V1,V2,...)")
        values, rng = tuple(_parse_value(t) for t in texts), None
    v = Vary(key, spec, path, param, values, texts, rng)
    for value in values:  # a value its key never allows is wrong in every case
        x = value * KNOT if v.knots and _is_number(value) else value
        try:
            param.check(path, x)
        except ConfigError:
            unit = " kn" if v.knots else ""
            raise SweepError(f"{where}: {key} = {_show(value)}{unit} is never allowed: {path} must be "
                             f"{param.allowed()}") from None
    return v


def _resolve(key: str, where: str) -> tuple[str, Param]:
    """(key path of the parameter, its Param) for a key as written (``_kn`` alias allowed)."""
    parts = [p.strip() for p in key.split(".")]
    if any(not p for p in parts):
        raise SweepError(f"{where}: {key!r} is not a key path (e.g. tether.length)")
    cls = Scenario
    for part in parts[:-1]:
        try:
            s, index = split_index(part)
        except ConfigError as exc:
            raise SweepError(f"{where}: {exc}") from None
        subs = table_lists(cls) if index is not None else subsections(cls)  # (tether.floats[0].start)
        if s not in subs:
            raise SweepError(f"{where}: {unknown_key_message(cls, s)}")
        cls = subs[s]
    leaf = parts[-1]
    ps = params(cls)
    if leaf in ps:
        return ".".join(parts), ps[leaf]
    if leaf.endswith("_kn") and leaf[:-3] in ps and ps[leaf[:-3]].knots:
        return ".".join(parts[:-1] + [leaf[:-3]]), ps[leaf[:-3]]
    if leaf in subsections(cls):
        raise SweepError(f"{where}: {key} is a section [{key}], not a key; vary one of its keys")
    raise SweepError(f"{where}: {unknown_key_message(cls, leaf)}")


def _split(text: str, sep: str) -> list[str]:
    """``text`` split at ``sep`` outside brackets, braces and quotes."""
    out, depth, quote, cur = [], 0, None, []
    for ch in text:
        if quote:
            if ch == quote:
                quote = None
        elif ch in "\"'":
            quote = ch
        elif ch in "[{":
            depth += 1
        elif ch in "]}":
            depth -= 1
        elif ch == sep and depth == 0:
            out.append("".join(cur))
            cur = []
            continue
        cur.append(ch)
    out.append("".join(cur))
    return out


def _parse_value(text: str):
    """A value as ``--set`` reads it: TOML, else a bare word (a string)."""
    try:
        return tomllib.loads(f"v = {text}")["v"]
    except tomllib.TOMLDecodeError:
        return text


def _is_number(v) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def _toml(v) -> str:
    """TOML text of a value (floats exactly)."""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        return "nan" if math.isnan(v) else ("inf" if v > 0 else "-inf") if math.isinf(v) else repr(v)
    if isinstance(v, str):
        return json.dumps(v)
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_toml(x) for x in v) + "]"
    raise TypeError(f"no TOML text for {v!r}")


def _show(v) -> str:
    return _toml(v) if not isinstance(v, str) else v


def _show_list(values) -> str:
    return ", ".join(f"{v:g}" for v in values)


# ------------------------------------------------------------------ the cases


@dataclass
class Case:
    index: int
    values: tuple  # one per Vary
    overrides: list  # every override of the case (--set, then the varied keys)
    sc: Scenario | Network | None  # None: invalid (``error`` says why)
    error: str = ""
    key: str = ""  # resume key (see the package docstring)


@dataclass
class Plan:
    scenario: str  # the file as given
    text: str
    sets: list
    varies: list
    samples: int | None
    seed: int
    cases: list
    kind: str = "scenario"  # or "network" (the cases' ``sc`` are then ``Network``s)
    columns: list | None = None  # a network's figures ((name, meaning), as ``outputs.COLUMNS``)
    copy_name: str = "scenario.toml"  # the results folder's copy of the file


def make_plan(scenario, varies: list[Vary], *, sets=(), samples: int | None = None, seed: int = 0) -> Plan:
    """Every case, checked (see the package docstring); raises SweepError for input that is
    wrong in every case."""
    import mujoco

    from mjtether import __version__
    from mjtether.io.packagedata import shipped_example

    name = str(scenario)
    p = shipped_example(scenario) or Path(scenario)  # (a shipped example by name: "default_walker")
    if p.is_dir():
        raise SweepError(f"{name}: is a folder; give a scenario .toml file")
    try:
        text = p.read_bytes().decode("utf-8-sig")
    except OSError as exc:
        raise SweepError(f"{name}: cannot read the scenario ({exc.strerror})") from None
    except UnicodeDecodeError:
        text = None  # load_scenario says what is wrong with it
    if text is not None and p.suffix.lower() != ".toml":
        text = _moordyn_as_toml(name, text)
    varied = _varied_once(varies)
    try:  # the file and --set on their own (an error about a varied key may be one the cases fix)
        load_scenario(scenario, text=text, name=name, overrides=list(sets))
    except ConfigError as exc:
        if exc.key not in varied or text is None:
            raise SweepError(str(exc)) from None
    combos = _combos(varies, samples, seed)
    versions = {"mjtether": __version__, "mujoco": mujoco.__version__}
    cases = []
    for i, combo in enumerate(combos):
        ov = list(sets) + [f"{v.key}={t}" for v, (_, t) in zip(varies, combo)]
        case = Case(i, tuple(x for x, _ in combo), ov, None)
        try:
            case.sc = load_scenario(scenario, text=text, name=name, overrides=ov)
        except ConfigError as exc:
            case.error = f"invalid case: {exc}"
        else:
            blob = json.dumps({"scenario": case.sc.to_dict(), **versions}, sort_keys=True)
            case.key = hashlib.sha256(blob.encode()).hexdigest()[:32]
        cases.append(case)
    _refuse_invalid(varies, cases, samples)
    return Plan(name, text or "", list(sets), list(varies), samples, seed, cases)


def _moordyn_as_toml(name: str, text: str) -> str:
    """A MoorDyn file of one line (read as a scenario: ``io.moordyn.read``) as the scenario TOML
    its cases vary (``scenario.to_toml``; it is what the sweep copies as ``scenario.toml``); any
    other text as it is."""
    from mjtether.io.moordyn import is_moordyn, read

    from ..scenario import ScenarioError, to_toml

    if not is_moordyn(text):
        return text
    try:
        return to_toml(read(text=text, name=name))
    except ScenarioError as exc:
        raise SweepError(str(exc)) from None


def _varied_once(varies) -> set:
    """The varied key paths; a key varied twice is refused."""
    seen = {}
    for v in varies:
        if v.path in seen:
            raise SweepError(f"--vary {v.key}: {v.path} is varied twice (also as --vary {seen[v.path]})")
        seen[v.path] = v.key
    return set(seen)


def _combos(varies, samples, seed):
    """Each case's ((value, text) per Vary): ``samples`` random draws, or the product."""
    if samples is not None:
        if not 1 <= samples <= MAX_CASES:
            raise SweepError(f"--samples {samples}: must be in [1, {MAX_CASES}]")
        rng = np.random.default_rng(seed)
        return [[v.draw(rng) for v in varies] for _ in range(samples)]
    n = math.prod(len(v.values) for v in varies)
    if n > MAX_CASES:
        raise SweepError(f"--vary: {n} cases is more than {MAX_CASES}; use fewer values or --samples")
    return itertools.product(*[list(zip(v.values, v.texts)) for v in varies])


def _refuse_invalid(varies, cases, samples) -> None:
    if samples is None:
        _refuse_always_invalid(varies, cases)
    elif all(c.sc is None for c in cases):
        raise SweepError(f"every case is invalid; case 0: {cases[0].error}")


def _refuse_always_invalid(varies, cases) -> None:
    """A value of a product sweep for which every case is invalid is an input error."""
    valid, first = set(), {}
    for c in cases:
        for j, value in enumerate(c.values):
            k = (j, _show(value))
            if c.sc is not None:
                valid.add(k)
            else:
                first.setdefault(k, c)
    for j, v in enumerate(varies):
        for value in v.values:
            k = (j, _show(value))
            if k not in valid and k in first:
                why = first[k].error.removeprefix("invalid case: ")
                raise SweepError(f"--vary {v.key}={v.spec}: {v.key} = {_show(value)} is invalid in every case "
                                 f"({why})")


# ------------------------------------------------------------------ a network


@dataclass(frozen=True)
class NetParam:
    """What a network key (``mjtether.network.overrides.Key``) may hold, in the shape ``Vary``
    reads a scenario's ``Param``: its kind (float, int, vec3, str) and unit. Its range is the
    network's own checks, made on each case (``make_network_plan``)."""

    kind: str
    unit: str = ""
    knots: bool = False

    def allowed(self) -> str:
        unit = f" ({self.unit})" if self.unit else ""
        return {"float": f"a number{unit}", "int": "a whole number", "vec3": f"three numbers [x, y, z]{unit}",
                "vec2": f"two numbers [x, y]{unit}", "str": "text"}[self.kind]

    def check(self, key: str, value):
        """``value`` if it is of this kind, or ConfigError."""
        ok = {"float": _is_number(value) and math.isfinite(value),
              "int": isinstance(value, int) and not isinstance(value, bool),
              "vec3": isinstance(value, list) and len(value) == 3 and all(_is_number(x) for x in value),
              "vec2": isinstance(value, list) and len(value) == 2 and all(_is_number(x) for x in value),
              "str": isinstance(value, str)}[self.kind]
        if not ok:
            raise ConfigError(f"{key} = {_show(value)}: must be {self.allowed()}", key)
        return value


def network_columns(net) -> list[tuple[str, str]]:
    """The figures of each case of a network sweep (as ``outputs.COLUMNS``): per line of ``net`` its
    peak and final end tensions (N; the ends' tensions of ``mjtether.network.run.columns``, one
    per output interval), then the peak over every line, the time step and the scenario sweep's
    bookkeeping."""
    cols = []
    for ln in net.lines:
        cols += [(f"line{ln.name}_peak_tension_N", f"line {ln.name}: largest tension at either end over the samples"),
                 (f"line{ln.name}_final_A_tension_N", f"line {ln.name}: tension at end A ({ln.a}) at the end"),
                 (f"line{ln.name}_final_B_tension_N", f"line {ln.name}: tension at end B ({ln.b}) at the end")]
    return cols + [
        ("peak_tension_N", "largest line_peak_tension_N over the lines"),
        ("timestep_s", "the run's time step (s; mjtether's choice where simulation.timestep is not given)"),
        ("diverged_at_s", "simulated time at which the run diverged (SimulationDiverged), else empty"),
        ("wall_s", "wall-clock time of the case (s)"),
        ("started_at", "wall-clock start of the case (UTC, ISO 8601)"),
        ("initial_state", "how the run started (NetworkRun.note)"),
    ]


def _resolve_network(net: Network, key: str, where: str) -> tuple[str, NetParam]:
    """(the key, its NetParam) for a key of ``net`` (``overrides.resolve``), or SweepError."""
    key = key.strip()
    try:
        k = net_overrides.resolve(net, key)
    except NetworkError as exc:
        why = str(exc).removeprefix(f"--set {key}: ").replace("takes --set KEY=VALUE with KEY", "takes --vary KEY=SPEC "
                                                                "with KEY")
        raise SweepError(f"{where}: {why}") from None
    return key, NetParam("float" if k.kind == "timestep" else k.kind, k.unit)


def load_network(source):
    """(the ``Network``, the file's text) if ``source`` is a network (a TOML file with
    ``[[lines]]``, or a MoorDyn file that ``load_any`` reads as one), else None: the file then
    goes to the scenario sweep, whose checks say what is wrong with it. Raises SweepError for a
    network file that cannot be read as one."""
    from mjtether.io.moordyn import is_moordyn, load_any
    from mjtether.io.packagedata import shipped_example

    p = shipped_example(source) or Path(source)
    try:
        text = p.read_bytes().decode("utf-8-sig")
    except (OSError, UnicodeDecodeError):
        return None
    if p.suffix.lower() != ".toml" and is_moordyn(text):
        network = True
    else:
        try:
            network = "lines" in tomllib.loads(text)
        except tomllib.TOMLDecodeError:
            return None
    if not network:
        return None
    try:
        net = load_any(source)
    except ValueError as exc:
        raise SweepError(str(exc)) from None
    return (net, text) if isinstance(net, Network) else None


def make_network_plan(source, net: Network, text: str, varies: list[Vary], *, sets=(), samples: int | None = None,
                      seed: int = 0) -> Plan:
    """Every case of a network sweep, each the network with ``--set`` and its varied keys
    (``with_overrides``, which checks it), keyed by a SHA-256 of its ``to_dict`` and the versions;
    raises SweepError for input that is wrong in every case (as ``make_plan``)."""
    import mujoco

    from mjtether import __version__
    from mjtether.io.packagedata import shipped_example

    _varied_once(varies)
    labelled = [(s, f"--set {s}") for s in sets]
    try:
        net_overrides.with_overrides(net, labelled)
    except NetworkError as exc:
        raise SweepError(str(exc)) from None
    versions = {"mjtether": __version__, "mujoco": mujoco.__version__}
    cases = []
    for i, combo in enumerate(_combos(varies, samples, seed)):
        mine = [f"{v.key}={t}" for v, (_, t) in zip(varies, combo)]
        case = Case(i, tuple(x for x, _ in combo), list(sets) + mine, None)
        try:
            case.sc = net_overrides.with_overrides(net, labelled + [(m, m) for m in mine])
        except NetworkError as exc:
            case.error = f"invalid case: {exc}"
        else:
            blob = json.dumps({"network": to_dict(case.sc), **versions}, sort_keys=True)
            case.key = hashlib.sha256(blob.encode()).hexdigest()[:32]
        cases.append(case)
    _refuse_invalid(varies, cases, samples)
    suffix = (shipped_example(source) or Path(source)).suffix.lower()
    copy = "network" + (suffix if suffix[1:].isalnum() else ".txt")
    return Plan(str(source), text, list(sets), list(varies), samples, seed, cases, kind="network",
                columns=network_columns(net), copy_name=copy)
