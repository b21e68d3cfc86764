"""Argument checks that raise ``ValueError`` naming the field and its allowed range."""

from __future__ import annotations

import math

import numpy as np


def finite(name: str, value) -> float:
    """Return ``value`` as a float, or raise if it is not a finite number (text and booleans
    are refused: ``"100"`` is not a length)."""
    if isinstance(value, (str, bytes, bool, np.bool_)):
        raise ValueError(f"{name} must be a finite number, got {value!r}")
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a finite number, got {value!r}") from None
    if not math.isfinite(x):
        raise ValueError(f"{name} must be a finite number, got {value!r}")
    return x


def positive(name: str, value, unit: str = "") -> float:
    """A finite number > 0."""
    x = finite(name, value)
    if x <= 0.0:
        raise ValueError(f"{name} must be > 0{(' ' + unit) if unit else ''}, got {value!r}")
    return x


def non_negative(name: str, value, unit: str = "") -> float:
    """A finite number >= 0."""
    x = finite(name, value)
    if x < 0.0:
        raise ValueError(f"{name} must be >= 0{(' ' + unit) if unit else ''}, got {value!r}")
    return x


def in_range(name: str, value, lo: float, hi: float, unit: str = "") -> float:
    """A finite number in the closed interval [lo, hi]."""
    x = finite(name, value)
    if not lo <= x <= hi:
        raise ValueError(f"{name} must be in [{lo}, {hi}]{(' ' + unit) if unit else ''}, got {value!r}")
    return x


def positive_int(name: str, value, minimum: int = 1) -> int:
    """An integer >= minimum (bools are refused)."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise ValueError(f"{name} must be an integer >= {minimum}, got {value!r}")
    if value < minimum:
        raise ValueError(f"{name} must be an integer >= {minimum}, got {value!r}")
    return int(value)


def vector3(name: str, value) -> np.ndarray:
    """A finite 3-vector (booleans and text are refused: ``[true, 0, 0]`` is not a point)."""
    if isinstance(value, (str, bytes)) or _has_flag_or_text(value):
        raise ValueError(f"{name} must be three finite numbers (x, y, z), got {value!r}")
    try:
        v = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be three finite numbers (x, y, z), got {value!r}") from None
    if v.shape != (3,) or not np.all(np.isfinite(v)):
        raise ValueError(f"{name} must be three finite numbers (x, y, z), got {value!r}")
    return v


def _has_flag_or_text(value) -> bool:
    """Whether ``value`` holds a boolean or text anywhere (NumPy would read them as 1.0 and
    ``float("6136")``)."""
    if isinstance(value, np.ndarray):
        return value.dtype.kind in "bSUO" and (value.dtype.kind != "O" or _has_flag_or_text(value.tolist()))
    if isinstance(value, (list, tuple)):
        return any(_has_flag_or_text(v) for v in value)
    return isinstance(value, (str, bytes, bool, np.bool_))


def _span(lo: float, hi: float, unit: str, above: bool) -> str:
    return f"{'(' if above else '['}{lo:g}, {hi:g}]" + (f" {unit}" if unit else "")


def number(name: str, value, lo: float = -math.inf, hi: float = math.inf, unit: str = "", *,
           above: bool = False) -> float:
    """A finite number in [lo, hi] ((lo, hi] where ``above``), or ValueError stating the range
    in the scenario's words (``mjtether.scenario.config.Param``): ``"vehicle.mass = True: must
    be a number in (0, 1e+09] kg"``. Text and booleans are refused."""
    ok = not isinstance(value, (str, bytes, bool, np.bool_)) and isinstance(value, (int, float, np.integer,
                                                                                     np.floating))
    x = float(value) if ok else math.nan
    if not (math.isfinite(x) and (lo < x if above else lo <= x) and x <= hi):
        raise ValueError(f"{name} = {value!r}: must be a number in {_span(lo, hi, unit, above)}")
    return x


def numbers(name: str, value, lo: float = -math.inf, hi: float = math.inf, unit: str = "", *,
            count: tuple = (), above: bool = False) -> tuple:
    """A list of finite numbers, each in [lo, hi] (``number``); ``count``: the lengths allowed
    (any but 0 where empty). Errors name the entry (``hydro.added_mass[2]``)."""
    if isinstance(value, np.ndarray):
        value = value.tolist()
    allowed = " or ".join(map(str, count)) if count else "one or more"
    if not isinstance(value, (list, tuple)) or (len(value) not in count if count else not value):
        raise ValueError(f"{name} = {value!r}: must be a list of {allowed} numbers, each in "
                         f"{_span(lo, hi, unit, above)}")
    return tuple(number(f"{name}[{k}]", v, lo, hi, unit, above=above) for k, v in enumerate(value))


def text(name: str, value) -> str:
    """Non-empty text (a name), or ValueError."""
    if not isinstance(value, str) or not value.strip():
        raise ValueError(f"{name} = {value!r}: must be text (a name)")
    return value


MAX_FILE_BYTES = 64 * 1024 * 1024
"""The largest input text file read (bytes): a vehicle file, a MoorDyn file's side files."""


def read_text(label: str, path, max_bytes: int = MAX_FILE_BYTES, *, kind: str = "text file") -> str:
    """The UTF-8 text of the file ``path`` (a byte-order mark allowed), or ValueError starting
    with ``label`` (the file as the error names it) saying what is wrong: no such file, a folder
    or a device, too large, UTF-16, a byte that is not UTF-8 (its line). Never the file's
    contents. ``kind``: what the file should be (``"scenario .toml file"``), for the advice."""
    from pathlib import Path
    p = Path(path)
    if not p.exists():
        raise ValueError(f"{label}: no such file")
    if not p.is_file():
        raise ValueError(f"{label}: is {'a folder' if p.is_dir() else 'not a regular file'}; give a {kind}")
    try:
        size = p.stat().st_size
        if size > max_bytes:
            raise ValueError(f"{label}: is {size / 2**20:.0f} MiB; a text input file must be at most "
                             f"{max_bytes / 2**20:.0f} MiB")
        raw = p.read_bytes()
    except OSError as exc:
        raise ValueError(f"{label}: cannot read it ({exc.strerror or type(exc).__name__})") from None
    if raw.startswith((b"\xff\xfe", b"\xfe\xff")):
        raise ValueError(f"{label}: is UTF-16 text; save it as UTF-8")
    try:
        return raw.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        line = raw[:exc.start].count(b"\n") + 1
        raise ValueError(f"{label}: line {line}: byte 0x{raw[exc.start]:02x} is not UTF-8 (a binary file?); "
                         "save it as UTF-8 text") from None
