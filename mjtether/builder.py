"""Old path of ``mjtether.cable.builder`` (the flat layout's ``mjtether.builder``), kept so that
``import mjtether.builder`` and ``from mjtether.builder import add_tether`` work as before: this
name is the moved module itself, not a copy."""

import sys

from mjtether.cable import builder as _moved

sys.modules[__name__] = _moved
