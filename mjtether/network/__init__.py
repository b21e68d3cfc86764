"""Networks of mooring lines: several lines between fixed, coupled, body and free points
(``config``), vehicles flying on their autopilots and lines paying out from winches, their
steady state as MoorPy solves it (``statics``), and their run in MuJoCo
(``run``). A MoorDyn file that is not one line from a fairlead to an anchor reads as a network
(``mjtether.io.moordyn.read``)."""

from .config import (
    Body,
    Line,
    LineType,
    Network,
    NetworkError,
    Point,
    Vehicle,
    from_dict,
    with_overrides,
)

__all__ = ["Body", "Line", "LineType", "Network", "NetworkError", "Point", "Vehicle", "from_dict",
           "with_overrides"]
