"""Old path of ``mjtether.scenario.runner`` (the flat layout's ``mjtether.runner``), kept so that
``import mjtether.runner`` and ``from mjtether.runner import ScenarioRun`` work as before: this
name is the moved module itself, not a copy."""

import sys

from mjtether.scenario import runner as _moved

sys.modules[__name__] = _moved
