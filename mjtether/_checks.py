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
    """A finite 3-vector."""
    try:
        v = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be three finite numbers (x, y, z), got {value!r}") from None
    if v.shape != (3,) or not np.all(np.isfinite(v)):
        raise ValueError(f"{name} must be three finite numbers (x, y, z), got {value!r}")
    return v
