"""Moved to ``mjtether.files.packagedata`` (it imports nothing of the package, so the packages below ``io`` use it
without importing ``io``); this name still imports it."""

import sys

from mjtether.files import packagedata as _moved

sys.modules[__name__] = _moved
