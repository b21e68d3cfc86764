"""Reading and writing a scenario's TOML: ``load_scenario`` (a file, a text or a dict, with
``--set``-style overrides) and ``to_toml`` (a checked ``Scenario`` back to TOML). The tree itself
and its checks are ``sections``."""

from __future__ import annotations

from pathlib import Path

import tomllib

from mjtether import _checks

from .config import ConfigError, build, split_index, subsections, table_lists, unknown_key_message
from .sections import Scenario, ScenarioError


def load_scenario(path=None, *, text: str | None = None, data: dict | None = None, name: str | None = None,
                  overrides=()) -> Scenario:
    """A checked ``Scenario`` from a TOML file ``path`` (or a shipped example's name,
    ``"default_walker"``: ``mjtether.files.packagedata.shipped_example``), TOML ``text`` or ``data`` (the nested
    dict TOML would give); with none of them, the defaults. ``overrides``: ``"key.path=value"``
    strings (values in TOML syntax; a bare word is a string), applied before checking, as
    ``mjtether run --set`` does; an item may also be a pair (``"key.path=value"``, the label to
    blame, e.g. ``"--duration 5"``). ``name`` labels errors (default: the file name); an error in
    a key an override set names the override instead (``--set tether.length=abc: ...``). A
    relative ``water.bathymetry`` or ``ship.motion.rao_file`` in a file is taken beside the file;
    one given in ``overrides``, from the working folder."""
    if path is not None and text is None and data is None:
        from mjtether.files.packagedata import shipped_example
        path = shipped_example(path) or path  # (a shipped example by name: "default_walker")
    if name is None:
        name = str(path) if path is not None else "<text>" if text is not None else "<data>"
    if data is not None:
        raw = _copy_tree(data)
    elif text is not None or path is not None:
        raw = _parse(name, _read(name, path) if text is None else text)
    else:
        raw = {}
    if path is not None:  # (the files a scenario names, beside it)
        for table, key in ((raw.get("water"), "bathymetry"), ((raw.get("ship") or {}).get("motion"), "rao_file")):
            if isinstance(table, dict) and isinstance(table.get(key), str) and table[key] \
                    and not Path(table[key]).is_absolute():
                table[key] = str(Path(path).resolve().parent / table[key])
    labels = {}  # {key path: what set it} for the overrides
    for item in overrides:
        item, label = item if isinstance(item, tuple) else (item, f"--set {item}")
        try:
            key = _override(raw, item)
        except ConfigError as exc:
            if "=" not in str(item):  # (not KEY=VALUE: the message shows the item as given)
                raise
            msg = _after(str(exc), f"--set {item}: ", f"--set {item!r}: ", f"--set {_key_of(item)}: ")
            raise ScenarioError(f"{label}: {msg}", exc.key) from None
        labels[key] = label
    try:
        return build(Scenario, raw, name)
    except ConfigError as exc:
        label = _blame(exc.key, labels)
        if label is None:
            raise
        raise ScenarioError(f"{label}: {_after(str(exc), f'{name}: ')}", exc.key) from None


def _key_of(item: str) -> str:
    return str(item).partition("=")[0].strip()


def _after(msg: str, *prefixes: str) -> str:
    """``msg`` without the first of ``prefixes`` it starts with."""
    for p in prefixes:
        if msg.startswith(p):
            return msg[len(p):]
    return msg


def _blame(key: str, labels: dict) -> str | None:
    """The label of the override that set ``key`` (an error's key path), or of a section or a
    key below it that an override set; None where no override did (the file's mistake)."""
    if not key:
        return None
    norm = {k.removesuffix("_kn"): v for k, v in labels.items()}
    if key in norm:
        return norm[key]
    for k, v in reversed(list(norm.items())):  # the last override of a section or a key in it
        if k.startswith((key + ".", key + "[")) or key.startswith(k + "."):
            return v
    return None


def _read(name: str, path) -> str:
    """The file's text: UTF-8 as TOML requires (a byte-order mark is allowed); any other
    encoding, a folder, a missing or huge file is an error that says how to fix it
    (``_checks.read_text``)."""
    try:
        return _checks.read_text(name, path, kind="scenario .toml file")
    except ValueError as exc:
        raise ScenarioError(str(exc)) from None


def _parse(name: str, text: str) -> dict:
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ScenarioError(f"{name}: not valid TOML: {exc}") from None


def _copy_tree(d):
    return {k: _copy_tree(v) for k, v in d.items()} if isinstance(d, dict) else d


def _override(raw: dict, item: str) -> str:
    """Apply one ``key.path=value`` to the raw tree (the key is checked when the tree is built;
    sections must exist in the schema); returns the key path."""
    key, sep, value = str(item).partition("=")
    key = key.strip()
    if not sep or not key or any(not p.strip() for p in key.split(".")):
        raise ScenarioError(f"--set {item!r}: must be KEY=VALUE, e.g. simulation.duration=10")
    try:
        v = tomllib.loads(f"v = {value.strip()}")["v"]
    except tomllib.TOMLDecodeError:
        v = value.strip()  # a bare word: a string (e.g. simulation.start=settle)
    *sections, leaf = [p.strip() for p in key.split(".")]
    node, cls = raw, Scenario
    for i, part in enumerate(sections):
        try:
            s, index = split_index(part)
        except ConfigError as exc:
            raise ScenarioError(f"--set {key}: {exc}", key) from None
        if index is not None:  # one table of an array of tables: tether.floats[0].start
            lists = table_lists(cls)
            if s not in lists:
                raise ScenarioError(f"--set {key}: {unknown_key_message(cls, s)}", key)
            items = node.get(s, [])
            if not isinstance(items, list) or index >= len(items):
                n = len(items) if isinstance(items, list) else 0
                raise ScenarioError(f"--set {key}: the scenario has {n} [[{lists[s].PATH}]] table(s), numbered "
                                    f"from 0; {part} is not one of them", key)
            node, cls = items[index], lists[s]
            continue
        subs = subsections(cls)
        if s not in subs:
            raise ScenarioError(f"--set {key}: {unknown_key_message(cls, s)}", key)
        cls = subs[s]
        nxt = node.setdefault(s, {})
        if not isinstance(nxt, dict):
            raise ScenarioError(f"--set {key}: {'.'.join(sections[:i + 1])} is not a section", key)
        node = nxt
    node[leaf] = v
    return ".".join([*sections, leaf])


def to_toml(sc: Scenario) -> str:
    """The scenario as a TOML file: the keys that differ from their defaults (and the robot's
    type), section by section; ``load_scenario`` reads it back to the same scenario."""
    import tomli_w

    def diff(now: dict, default: dict) -> dict:
        out = {}
        for k, v in now.items():
            if isinstance(v, dict):
                sub = diff(v, default[k])
                if sub:
                    out[k] = sub
            elif v is not None and v != default[k]:
                out[k] = v
        return out

    tree = diff(sc.to_dict(), Scenario().to_dict())
    tree.setdefault("robot", {})["type"] = sc.robot.type
    return tomli_w.dumps(tree)
