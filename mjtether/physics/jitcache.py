"""numba's on-disk cache for the package's kernels, keyed on the source of every kernel.

numba keys a cached function on its own file's modification time and size. A kernel that calls
(and inlines) a kernel of another module does not see that module change: after an edit to
``compiled._density`` alone, ``quasistatic.kernels.hang_up`` ran the old density from the cache,
bit for bit, until the cache folder was deleted (an editable install after a ``git pull`` does
the same). Here every kernel of the package is stamped instead with one hash of the source of
every module that defines kernels (each ``.py`` file of the package that uses ``jit``): any
change to any of them recompiles them all, once.

The cache lives where numba would put it: ``NUMBA_CACHE_DIR`` if set, else the package's
``__pycache__`` folders, else numba's user-wide cache. Where numba's cache machinery is not
what this module knows (another numba version), the kernels are compiled without a cache:
slower to start, never stale.
"""

from __future__ import annotations

import functools
import hashlib
import os
import re
from pathlib import Path

PACKAGE = Path(__file__).resolve().parents[1]
"""The ``mjtether`` package folder."""
_KERNEL = re.compile(rb"^[ \t]*@(?:[\w.]+\.)?_?jit\b|numba\.cfunc\(", re.M)
"""What marks a module that defines kernels: a ``@jit`` (``@compiled.jit``, ``@_jit``)
decorator, or a numba ``cfunc``."""


@functools.lru_cache(maxsize=1)
def source_stamp() -> str:
    """SHA-256 of the sources of every module of the package that defines kernels (path and
    contents, in path order)."""
    h = hashlib.sha256()
    for path in sorted(PACKAGE.rglob("*.py")):
        text = path.read_bytes()
        if _KERNEL.search(text):
            h.update(str(path.relative_to(PACKAGE)).encode() + b"\0" + text + b"\0")
    return h.hexdigest()


def kernel_modules() -> list[str]:
    """The modules ``source_stamp`` reads (paths in the package)."""
    return [str(p.relative_to(PACKAGE)) for p in sorted(PACKAGE.rglob("*.py")) if _KERNEL.search(p.read_bytes())]


def _ours(py_file: str) -> bool:
    try:
        return Path(py_file).resolve().is_relative_to(PACKAGE)
    except (OSError, ValueError):
        return False


def _install() -> bool:
    """Put locators that stamp the package's kernels with ``source_stamp`` in front of numba's
    own (for the package's files only). Returns False where numba's cache machinery is not the
    one this was written for."""
    try:
        from numba.core import caching
        locators = caching.CacheImpl._locator_classes
        bases = (caching.UserProvidedCacheLocator, caching.InTreeCacheLocator, caching.UserWideCacheLocator)
    except (ImportError, AttributeError):
        return False
    if not isinstance(locators, list) or any(getattr(c, "_mjtether", False) for c in locators):
        return isinstance(locators, list)

    def stamped(base):
        class Locator(base):
            _mjtether = True

            def get_source_stamp(self):
                return source_stamp()

            @classmethod
            def from_function(cls, py_func, py_file):
                return super().from_function(py_func, py_file) if _ours(py_file) else None

        Locator.__name__ = Locator.__qualname__ = "Mjtether" + base.__name__
        return Locator

    locators[:0] = [stamped(b) for b in bases]
    return True


CACHE = os.environ.get("NUMBA_DISABLE_CACHE", "").strip() not in ("1", "true") and _install()
"""Whether the kernels are cached on disk (keyed on ``source_stamp``)."""


def _marker() -> Path | None:
    """The file that says the kernels of this ``source_stamp`` were compiled and cached, where
    numba keeps them: in ``NUMBA_CACHE_DIR`` if it is set (numba then looks nowhere else), else
    beside the package's caches, else in the user's cache folder; None if none is writable."""
    if os.environ.get("NUMBA_CACHE_DIR"):
        folders = [Path(os.environ["NUMBA_CACHE_DIR"])]
    else:
        folders = [PACKAGE / "physics" / "__pycache__",
                   Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "mjtether"]
    name = f"kernels-{source_stamp()[:16]}.compiled"
    for folder in folders:
        try:
            folder.mkdir(parents=True, exist_ok=True)
        except OSError:
            continue
        if (folder / name).exists() or os.access(folder, os.W_OK):
            return folder / name
    return None


def warm() -> bool:
    """Whether the kernels of this source were compiled and cached by an earlier run (see
    ``mark_warm``); False where they are not cached at all."""
    marker = _marker() if CACHE else None
    return marker is not None and marker.exists()


def mark_warm() -> None:
    """Note that a run has compiled (and cached) every kernel it uses."""
    marker = _marker() if CACHE else None
    if marker is not None:
        try:
            marker.touch()
        except OSError:
            pass


class CompileClock:
    """The seconds a first run has spent compiling, shown on ``file`` (stderr) as they pass: on a
    terminal one line that a background thread redraws every ``every`` s (``desc: 12 s``), from
    ``start()`` to ``stop()``, which clears it and returns the seconds; written to a file or a
    pipe (a CI log), a line of its own every ``LOG_EVERY`` s instead (no carriage returns). The
    kernels are compiled as a run is built, by numba, one inlined into the next; they cannot be
    counted one by one, so the clock counts time, not kernels."""

    LOG_EVERY = 15.0
    """Seconds between the clock's lines where ``file`` is not a terminal."""

    def __init__(self, desc: str, file=None, every: float = 1.0):
        import sys
        import threading

        self.desc, self.file = desc, file or sys.stderr
        try:
            self._tty = bool(self.file.isatty())
        except (AttributeError, OSError, ValueError):
            self._tty = False
        self.every = every if self._tty else self.LOG_EVERY
        self._done = threading.Event()
        self._thread = threading.Thread(target=self._tick, daemon=True)
        self._t0 = None
        self.seconds = None

    def _line(self, elapsed: float) -> str:
        return f"{self.desc}: {elapsed:.0f} s"

    def _tick(self) -> None:
        import time

        while not self._done.wait(self.every):
            line = self._line(time.perf_counter() - self._t0)
            self._show("\r" + line if self._tty else line + "\n")

    def _show(self, text: str) -> None:
        try:
            self.file.write(text)
            self.file.flush()
        except (OSError, ValueError):  # (a closed or broken stderr loses the clock, not the run)
            pass

    def start(self) -> CompileClock:
        import time

        self._t0 = time.perf_counter()
        if self._tty:
            self._show(self._line(0.0))
        self._thread.start()
        return self

    def stop(self) -> float:
        """Stop the clock (again: no effect); the seconds from ``start``."""
        import time

        if self.seconds is None:
            self.seconds = time.perf_counter() - self._t0
            self._done.set()
            self._thread.join()
            if self._tty:
                self._show("\r" + " " * len(self._line(self.seconds)) + "\r")
        return self.seconds
