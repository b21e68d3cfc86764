"""``python -m mjtether.cli``: the command line, as ``mjtether``."""

import sys

from . import main

if __name__ == "__main__":  # (not when imported, e.g. by pkgutil.walk_packages)
    sys.exit(main())
