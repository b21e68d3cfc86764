"""A results folder that is either complete or absent, and never replaces what mjtether did not write.

Why: ``mjtether run --out DIR`` used to delete an existing DIR wholesale, whatever it held (the
current folder, a parent, a folder of the user's own files), and left half-written folders behind
when killed. The rules here:

* ``check_target`` runs *before* anything is simulated, so a bad ``--out`` costs nothing. It refuses
  a folder holding anything (unless ``overwrite`` and the folder is purely an earlier mjtether
  result: it has our ``MANIFEST`` and nothing the manifest does not list), a file or a symbolic
  link at the path, the current folder, the home folder, ``/`` or any of their parents, and
  protected paths (the scenario file) or folders containing them. An empty folder is used.
* ``Staging`` writes into a temporary folder beside the target and renames it into place only when
  complete (``commit``), so a result is never half there. An earlier result being overwritten is
  moved aside, the new one moved in, and only then is the old one deleted.
* On an exception, SIGINT, SIGTERM or SIGHUP the temporary folder is removed. A process killed
  outright (SIGKILL, power loss) cannot clean up: its temporary folder carries a marker with its
  pid, and the next ``check_target`` for the same target removes it once that pid is gone.
"""

from __future__ import annotations

import contextlib
import errno
import hashlib
import json
import os
import shutil
import signal
import socket
import tempfile
import threading
from pathlib import Path

MANIFEST = "mjtether-manifest.json"
"""Written into every results folder last, listing its files: proof that mjtether wrote them."""
MANIFEST_FORMAT = "mjtether-result/1"
MARKER = "mjtether-owner"
"""Inside a temporary folder: "<pid> <host>" of the process writing it (see ``remove_stale``)."""

_DISK_ERRORS = {errno.ENOSPC, errno.EDQUOT, errno.EROFS, errno.EACCES, errno.EPERM}
_SIGNALS = tuple(getattr(signal, n) for n in ("SIGINT", "SIGTERM", "SIGHUP") if hasattr(signal, n))


class OutputError(Exception):
    """The results folder cannot be used or written; the message is one line naming the path and
    what to do. Nothing has been written or removed when it is raised."""


def partial_prefix(name: str) -> str:
    """Name prefix of the temporary folders for a target called ``name`` (hidden, beside it)."""
    return f".{name}.mjtether-partial-"


# ------------------------------------------------------------------ checking the target


def check_target(out, *, overwrite: bool = False, protect=()) -> Path:
    """The absolute path of results folder ``out`` if mjtether may write it; raises OutputError if not.

    Call before simulating. ``protect``: paths (e.g. the scenario file) that must neither be the
    target nor lie inside it. Also removes stale temporary folders of dead mjtether runs beside it.
    """
    if os.fspath(out) == "":
        raise OutputError("the results folder name is empty; give one with --out")
    target = Path(os.path.abspath(os.fspath(out)))
    _refuse_protected(out, target, protect)
    _refuse_existing(out, target, overwrite)
    _refuse_unwritable_parent(out, target)
    if target.parent.is_dir():
        remove_stale(target.parent, target.name)
    return target


def _refuse_protected(out, target: Path, protect) -> None:
    """Folders whose loss would be a disaster are refused even with overwrite (they may well
    hold a manifest from an earlier ``--out .``): a typo must never cost the user a home folder."""
    named = [("the current folder", Path.cwd()), ("the root folder", Path("/"))]
    with contextlib.suppress(RuntimeError, KeyError):  # no home folder known
        named.append(("the home folder", Path.home()))
    named += [(f"{str(p)!r}", Path(p)) for p in protect if p is not None and os.fspath(p) != ""]
    real = Path(os.path.realpath(target))
    for label, p in named:
        rp = Path(os.path.realpath(p))
        if rp == real:
            raise OutputError(f"refusing to write results to {str(out)!r}: it is {label}; choose another --out")
        if rp.is_relative_to(real):
            raise OutputError(f"refusing to write results to {str(out)!r}: it contains {label}; "
                              "choose another --out")


def _lstat(path: Path):
    """``os.lstat`` or None if nothing is there (a file in the way of a parent counts as nothing;
    ``_refuse_unwritable_parent`` reports it)."""
    try:
        return os.lstat(path)
    except (FileNotFoundError, NotADirectoryError):
        return None
    except OSError as exc:
        raise OutputError(f"cannot look at {str(path)!r}: {_reason(exc)}; choose another --out") from exc


def _refuse_existing(out, target: Path, overwrite: bool) -> None:
    st = _lstat(target)
    if st is None:
        return
    if os.path.islink(target):
        raise OutputError(f"results folder {str(out)!r} is a symbolic link; mjtether neither writes through "
                          "nor replaces links; choose another --out")
    if not target.is_dir():
        raise OutputError(f"results folder {str(out)!r} exists and is a file, not a folder; choose another --out")
    if _is_empty(target):
        return
    if not overwrite:
        raise OutputError(f"results folder {str(out)!r} exists and is not empty; choose another --out or pass "
                          "--overwrite to replace an earlier mjtether result")
    why = foreign_content(target)
    if why:
        raise OutputError(f"results folder {str(out)!r} is not purely an earlier mjtether result ({why}); "
                          "--overwrite only replaces those; choose another --out")


def _is_empty(folder: Path) -> bool:
    try:
        with os.scandir(folder) as it:
            return next(it, None) is None
    except OSError as exc:
        raise OutputError(f"cannot read results folder {str(folder)!r}: {_reason(exc)}") from exc


def _refuse_unwritable_parent(out, target: Path) -> None:
    """Say now, in one line, that the folder could not be created, not after an hour of simulation."""
    parent = target.parent
    while _lstat(parent) is None and parent != parent.parent:
        parent = parent.parent
    if not parent.is_dir():
        raise OutputError(f"cannot create results folder {str(out)!r}: {str(parent)!r} is a file, not a folder")
    if not os.access(parent, os.W_OK | os.X_OK):
        raise OutputError(f"cannot create results folder {str(out)!r}: no permission to write in {str(parent)!r} "
                          "(or it is read-only); choose another --out")


# ------------------------------------------------------------------ what is ours


def foreign_content(folder: Path) -> str | None:
    """Why ``folder`` is not purely an mjtether result (None if it is): it must hold our manifest
    and nothing the manifest does not list; a file the user added later makes it theirs too."""
    listed = _manifest_files(folder)
    if listed is None:
        return f"no valid {MANIFEST}"
    dirs = {Path(f).parent.as_posix() for f in listed}
    for root, subdirs, files in os.walk(folder):
        for n in subdirs + files:
            p = Path(root, n)
            rel = p.relative_to(folder).as_posix()
            if p.is_symlink():
                return f"{rel!r} is a link mjtether did not make"
            if p.is_dir():
                if not any(d == rel or d.startswith(rel + "/") for d in dirs):
                    return f"{rel!r} is not one of its files"
            elif rel != MANIFEST and rel not in listed:
                return f"{rel!r} is not one of its files"
    return None


def _manifest_files(folder: Path) -> set[str] | None:
    """The file names listed by ``folder``'s manifest, or None if it has no valid one."""
    m = folder / MANIFEST
    if m.is_symlink() or not m.is_file():
        return None
    try:
        data = json.loads(m.read_text())
    except (OSError, ValueError):
        return None
    if not isinstance(data, dict) or data.get("format") != MANIFEST_FORMAT or not isinstance(data.get("files"), dict):
        return None
    return set(data["files"])


def write_manifest(folder: Path) -> None:
    """List every file under ``folder`` (size, sha256) in its manifest: what ``--overwrite`` may replace."""
    files = {}
    for root, _, names in os.walk(folder):
        for n in sorted(names):
            p = Path(root, n)
            rel = p.relative_to(folder).as_posix()
            if rel == MANIFEST or p.is_symlink():
                continue
            h = hashlib.sha256()
            with open(p, "rb") as fh:
                for block in iter(lambda: fh.read(1 << 20), b""):
                    h.update(block)
            files[rel] = {"size": p.stat().st_size, "sha256": h.hexdigest()}
    data = {"format": MANIFEST_FORMAT, "written_by": "mjtether", "files": dict(sorted(files.items()))}
    (folder / MANIFEST).write_text(json.dumps(data, indent=2) + "\n")


# ------------------------------------------------------------------ stale temporary folders


def remove_stale(parent: Path, name: str) -> list[Path]:
    """Remove temporary folders for target ``name`` in ``parent`` left by dead mjtether runs
    (SIGKILL, power loss); returns them. Only folders with our prefix *and* a marker naming a pid
    on this host that is no longer running: never a live run's, never anything unmarked."""
    removed = []
    prefix = partial_prefix(name)
    try:
        entries = [e for e in os.scandir(parent) if e.name.startswith(prefix) and e.is_dir(follow_symlinks=False)]
    except OSError:
        return removed
    for e in entries:
        owner = _read_marker(Path(e.path))
        if owner is not None and owner[1] == socket.gethostname() and not _pid_alive(owner[0]):
            shutil.rmtree(e.path, ignore_errors=True)
            removed.append(Path(e.path))
    return removed


def _read_marker(folder: Path) -> tuple[int, str] | None:
    m = folder / MARKER
    try:
        if m.is_symlink() or not m.is_file():
            return None
        pid, host = m.read_text().split(maxsplit=1)
        return (int(pid), host.strip()) if int(pid) > 0 else None
    except (OSError, ValueError):
        return None


def _pid_alive(pid: int) -> bool:
    """Whether process ``pid`` exists; when unsure, yes (keeping a stale folder is harmless)."""
    if os.name == "nt":  # os.kill(pid, 0) would terminate it there
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except OSError:
        return True  # e.g. another user's process
    return True


# ------------------------------------------------------------------ staging


class Staging:
    """A temporary folder beside ``target`` (from ``check_target``) to write a result into.

    ``with Staging(target) as st:`` write into ``st.path``, then ``st.commit()`` to write the
    manifest and rename the folder into place. Leaving the block without ``commit`` (exception,
    early return, SIGINT/SIGTERM/SIGHUP) removes the temporary folder; a signal then becomes
    KeyboardInterrupt (SIGINT) or SystemExit(128 + signal number), after calling any Python
    handler installed before. ENOSPC, EDQUOT, EROFS, EACCES and EPERM become OutputError.
    Signal handlers are only installed in the main thread and are restored on leaving.

    Layout: ``.<name>.mjtether-partial-XXXX/`` holds ``MARKER`` and ``result/`` (``path``); the
    marker stays until the end, so a folder interrupted at any point can be recognised as stale.
    """

    def __init__(self, target, *, overwrite: bool = False):
        self.target = Path(target)
        self.overwrite = overwrite
        self.path: Path | None = None
        self._box: Path | None = None
        self._previous: dict = {}
        self._deferring = 0
        self._pending = None

    def __enter__(self) -> Staging:
        self._install_handlers()
        try:
            with self._signals_deferred(), self._disk_errors():  # never an unmarked temp folder
                self.target.parent.mkdir(parents=True, exist_ok=True)
                self._box = Path(tempfile.mkdtemp(prefix=partial_prefix(self.target.name), dir=self.target.parent))
                (self._box / MARKER).write_text(f"{os.getpid()} {socket.gethostname()}\n")
                self.path = self._box / "result"
                self.path.mkdir()
        except BaseException:
            self._remove_box()
            self._restore_handlers()
            raise
        return self

    def commit(self) -> Path:
        """Write the manifest, then move the result into place; returns the target."""
        with self._disk_errors():
            write_manifest(self.path)
            with self._signals_deferred():  # a half-done swap must not be interrupted
                self._move_into_place()
        return self.target

    def __exit__(self, exc_type, exc, tb):
        self._deferring += 1  # a second Ctrl-C must not cut the clean-up short
        try:
            self._remove_box()
        finally:
            self._restore_handlers()
            self._deferring -= 1
        if self._pending is not None and exc is None:
            self._deliver(*self._pending)
        if isinstance(exc, OSError) and exc.errno in _DISK_ERRORS:
            raise OutputError(_disk_message(exc, self.target)) from exc
        return False

    # -------------------------------------------------------------- internals

    def _move_into_place(self) -> None:
        """Rename ``path`` to the target. The target is re-checked: it may have changed during the run."""
        t = self.target
        if _lstat(t) is not None:
            if os.path.islink(t) or not t.is_dir():
                raise OutputError(f"a file or link appeared at {str(t)!r} during the run; results not written")
            if _is_empty(t):
                t.rmdir()
            elif self.overwrite and foreign_content(t) is None:
                old = self._box / "old"
                t.rename(old)  # moved aside, not deleted, until the new result is in place
                try:
                    self.path.rename(t)
                except BaseException:
                    old.rename(t)
                    raise
                return
            else:
                why = foreign_content(t) or "an earlier result, and --overwrite was not given"
                raise OutputError(f"results folder {str(t)!r} changed during the run ({why}); "
                                  "it was left alone and nothing was written")
        try:
            self.path.rename(t)
        except OSError as exc:
            if exc.errno in (errno.EEXIST, errno.ENOTEMPTY, errno.ENOTDIR, errno.EISDIR):
                raise OutputError(f"something appeared at {str(t)!r} during the run; it was left alone and "
                                  "nothing was written") from exc
            raise

    def _remove_box(self) -> None:
        if self._box is not None:
            shutil.rmtree(self._box, ignore_errors=True)
            self._box = None

    @contextlib.contextmanager
    def _disk_errors(self):
        try:
            yield
        except OSError as exc:  # a full disk, a read-only or odd file system (/proc): one line
            raise OutputError(_disk_message(exc, self.target)) from exc

    @contextlib.contextmanager
    def _signals_deferred(self):
        """Hold signals until the block is done (then deliver them): for steps that must not be
        left half-done (making the marked folder, swapping results)."""
        self._deferring += 1
        try:
            yield
        finally:
            self._deferring -= 1
        if not self._deferring and self._pending is not None:
            self._on_signal(*self._pending)

    def _install_handlers(self) -> None:
        if threading.current_thread() is not threading.main_thread():
            return
        for sig in _SIGNALS:
            prev = signal.getsignal(sig)
            if prev is signal.SIG_IGN:  # whoever started us wants it ignored (nohup)
                continue
            self._previous[sig] = prev
            signal.signal(sig, self._on_signal)

    def _restore_handlers(self) -> None:
        for sig, prev in self._previous.items():
            signal.signal(sig, prev if prev is not None else signal.SIG_DFL)
        self._previous = {}

    def _on_signal(self, signum, frame) -> None:
        if self._deferring:
            self._pending = (signum, frame)
            return
        self._pending = None
        self._deferring += 1
        try:
            self._remove_box()
        finally:
            self._deferring -= 1
        self._deliver(signum, frame)

    def _deliver(self, signum, frame) -> None:
        """Pass the signal on to the handler installed before ours (an outer Staging, Python's
        KeyboardInterrupt), then end the run if that did not."""
        self._pending = None
        prev = self._previous.get(signum, signal.getsignal(signum))
        if callable(prev) and prev != self._on_signal:
            prev(signum, frame)
        if signum == signal.SIGINT:
            raise KeyboardInterrupt
        raise SystemExit(128 + signum)


def _reason(exc: OSError) -> str:
    text = exc.strerror or str(exc)
    return text[:1].lower() + text[1:]


def _disk_message(exc: OSError, target: Path) -> str:
    return f"{_reason(exc)} while writing results to {str(target)!r}: nothing was written"


@contextlib.contextmanager
def terminate_as_exit():
    """SIGTERM raises SystemExit(143) while inside, so that ``finally`` and ``except`` clean-ups
    run (SIGTERM's default action kills the process with none); only in the main thread."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return

    def on_term(signum, frame):
        raise SystemExit(128 + signum)

    old = signal.signal(signal.SIGTERM, on_term)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, old)
