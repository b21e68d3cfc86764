"""Networks of mooring lines: several lines between fixed, coupled, body and free points
(``config``), vehicles flying on their autopilots, seabed walkers walking on their gait
(``walkers``) and lines paying out from winches, their steady state as MoorPy solves it
(``statics``; ``solve``: ``mjtether solve`` on a network), their run in MuJoCo (``run``) and
``--set`` on them (``overrides``). A MoorDyn file that is not one line from a fairlead to an
anchor reads as a network (``mjtether.io.moordyn.read``)."""

from .config import (
    WALKER_TOW_POINT,
    Body,
    Line,
    LineType,
    Network,
    NetworkError,
    Point,
    Vehicle,
    Walker,
    from_dict,
    to_dict,
)
from .overrides import with_overrides

__all__ = ["WALKER_TOW_POINT", "Body", "Line", "LineType", "Network", "NetworkError", "Point", "Vehicle", "Walker",
           "from_dict", "to_dict", "with_overrides"]
