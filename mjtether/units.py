"""Unit conversions used at the edges (configuration, command line).

Everything inside mjtether is SI. Knots appear only in user-facing inputs and
outputs and are converted here, in one place.
"""

KNOT = 1852.0 / 3600.0
"""One knot in metres per second: 1852 m (a nautical mile) in 3600 s, exactly."""


def knots(value: float) -> float:
    """Convert a speed in knots to metres per second."""
    return value * KNOT


def to_knots(speed: float) -> float:
    """Convert a speed in metres per second to knots."""
    return speed / KNOT
