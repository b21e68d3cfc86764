"""Results folders (mjtether.files.outdir): complete or absent, never replacing what mjtether did not write."""

import json
import os
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

import pytest

from mjtether import cli
from mjtether.io import results
from mjtether.files.outdir import MANIFEST, MARKER, OutputError, Staging, check_target, partial_prefix
from mjtether.scenario.runner import run
from mjtether.scenario import load_scenario

SCENARIO = """
[simulation]
duration = {duration}
output_interval = 0.5
[robot]
type = "anchor"
position = [40.0, 0.0, -100.0]
[water]
depth = 100.0
[tether]
length = 120.0
segments = 10
"""


# ------------------------------------------------------------------ helpers


def scenario(tmp_path, duration=1.0, name="s.toml") -> Path:
    """A short real scenario in its own folder (so tmp_path itself is not the scenario's folder)."""
    f = tmp_path / "scen" / name
    f.parent.mkdir(exist_ok=True)
    f.write_text(SCENARIO.format(duration=duration))
    return f


def snapshot(folder: Path) -> dict:
    """Everything under ``folder``: {relative path: bytes, or 'dir', or 'link -> target'}."""
    out = {}
    for p in sorted(folder.rglob("*")):
        rel = p.relative_to(folder).as_posix()
        out[rel] = f"link -> {os.readlink(p)}" if p.is_symlink() else "dir" if p.is_dir() else p.read_bytes()
    return out


def leftovers(folder: Path) -> list[Path]:
    """Temporary staging folders anywhere under ``folder``."""
    return [p for p in folder.rglob("*") if "mjtether-partial-" in p.name]


def earlier_result(folder: Path, files=None) -> Path:
    """A folder exactly as mjtether writes it (through Staging, manifest included)."""
    with Staging(folder) as st:
        for name, text in (files or {"summary.json": "{}", "timeseries.csv": "time_s\n0\n"}).items():
            (st.path / name).write_text(text)
        return st.commit()


def user_folder(folder: Path) -> Path:
    (folder / "notes").mkdir(parents=True)
    (folder / "thesis.tex").write_text("months of work")
    (folder / "notes" / "n.txt").write_text("more work")
    return folder


def run_cli(*argv) -> int:
    return cli.main(["run", *map(str, argv)])


def marked_temp(parent: Path, name: str, suffix: str, pid: int, host: str | None = None) -> Path:
    """A temporary folder as a Staging for target ``name`` would leave it, owned by ``pid``."""
    d = parent / f"{partial_prefix(name)}{suffix}"
    (d / "result").mkdir(parents=True)
    (d / "result" / "summary.json").write_text("{}")
    (d / MARKER).write_text(f"{pid} {host or socket.gethostname()}\n")
    return d


def dead_pid() -> int:
    p = subprocess.Popen([sys.executable, "-c", "pass"])
    p.wait()
    return p.pid


# ------------------------------------------------------------------ refusals, before anything is simulated


def test_empty_out_is_refused(tmp_path, capsys):
    """--out '' is a one-line error (exit 2), not a traceback, and writes nothing."""
    f = scenario(tmp_path)
    before = snapshot(tmp_path)
    with pytest.raises(OutputError, match="empty"):
        check_target("", overwrite=True)
    assert run_cli(f, "--out", "") == 2
    err = capsys.readouterr().err
    assert err.startswith("mjtether run: ") and err.count("\n") == 1 and "empty" in err
    assert snapshot(tmp_path) == before


def test_user_folder_is_refused_before_simulating_and_left_untouched(tmp_path, capsys):
    """A non-empty folder of the user's is refused at once (nothing simulated), byte-identical afterwards."""
    f = scenario(tmp_path)
    out = user_folder(tmp_path / "res")
    before = snapshot(tmp_path)
    t0 = time.perf_counter()
    assert run_cli(f, "--out", out) == 2
    assert time.perf_counter() - t0 < 5.0
    cap = capsys.readouterr()
    assert cap.out == "" and "simulated" not in cap.err  # refused before the run started
    assert "exists and is not empty" in cap.err and "--overwrite" in cap.err
    assert snapshot(tmp_path) == before


def test_default_results_folder_is_protected_too(tmp_path, monkeypatch, capsys):
    """The default ./results holding user files is refused like any other folder."""
    f = scenario(tmp_path)
    user_folder(tmp_path / "results")
    monkeypatch.chdir(tmp_path)
    before = snapshot(tmp_path)
    assert run_cli(f) == 2
    assert "'results' exists and is not empty" in capsys.readouterr().err
    assert snapshot(tmp_path) == before


def _user(tmp_path, monkeypatch):
    return user_folder(tmp_path / "res"), "not purely an earlier mjtether result (no valid"


def _result_plus_user_file(tmp_path, monkeypatch):
    out = earlier_result(tmp_path / "res")
    (out / "my-notes.txt").write_text("added by the user later")
    return out, "'my-notes.txt' is not one of its files"


def _result_plus_user_subfolder(tmp_path, monkeypatch):
    out = earlier_result(tmp_path / "res")
    (out / "analysis").mkdir()
    return out, "'analysis' is not one of its files"


def _symlink(tmp_path, monkeypatch):
    real = earlier_result(tmp_path / "real")
    (tmp_path / "res").symlink_to(real)
    return tmp_path / "res", "symbolic link"


def _file(tmp_path, monkeypatch):
    (tmp_path / "res").write_text("a file of the user's")
    return tmp_path / "res", "is a file, not a folder"


def _cwd(tmp_path, monkeypatch):
    earlier_result(tmp_path / "work")  # even an mjtether result is not replaced when it is the current folder
    monkeypatch.chdir(tmp_path / "work")
    return ".", "it is the current folder"


def _parent(tmp_path, monkeypatch):
    (tmp_path / "work").mkdir()
    monkeypatch.chdir(tmp_path / "work")
    return "..", "it contains the current folder"


def _home(tmp_path, monkeypatch):
    home = earlier_result(tmp_path / "home")
    monkeypatch.setenv("HOME", str(home))
    return home, "it is the home folder"


def _scenario_folder(tmp_path, monkeypatch):
    return tmp_path / "scen", "s.toml"


def _under_a_file(tmp_path, monkeypatch):
    (tmp_path / "file.txt").write_text("x")
    return tmp_path / "file.txt" / "sub", "is a file, not a folder"


@pytest.mark.parametrize("case", [_user, _result_plus_user_file, _result_plus_user_subfolder, _symlink, _file,
                                  _cwd, _parent, _home, _scenario_folder, _under_a_file])
def test_overwrite_refuses_what_mjtether_did_not_write(tmp_path, monkeypatch, capsys, case):
    """--overwrite still refuses (exit 2, one line, nothing simulated, nothing changed) a user folder, a result
    with a user file or folder added, a link, a file, cwd, its parent, home, the scenario's folder, a path
    under a file."""
    f = scenario(tmp_path)
    out, message = case(tmp_path, monkeypatch)
    before = snapshot(tmp_path)
    assert run_cli(f, "--out", out, "--overwrite", "--no-plots") == 2
    cap = capsys.readouterr()
    assert cap.out == "" and cap.err.startswith("mjtether run: ") and cap.err.count("\n") == 1
    assert message in cap.err
    assert snapshot(tmp_path) == before


def test_unwritable_parent_is_refused_even_as_root(tmp_path, monkeypatch):
    """Where access() says the parent is not writable (read-only mount, no permission), check_target says so
    in one line (os.access is patched: root passes every permission check)."""
    monkeypatch.setattr(os, "access", lambda path, mode: Path(path) != tmp_path)
    with pytest.raises(OutputError, match="no permission to write in .*read-only") as info:
        check_target(tmp_path / "a" / "res", overwrite=False)
    assert "\n" not in str(info.value)


@pytest.mark.skipif(os.name != "posix" or os.geteuid() == 0, reason="root ignores folder permissions")
def test_read_only_parent_is_refused_in_one_line(tmp_path, capsys):
    """A parent folder mjtether may not write in is reported before simulating, in one line."""
    f = scenario(tmp_path)
    ro = tmp_path / "ro"
    ro.mkdir()
    ro.chmod(0o555)
    try:
        assert run_cli(f, "--out", ro / "a" / "res") == 2
    finally:
        ro.chmod(0o755)
    err = capsys.readouterr().err
    assert "no permission to write in" in err and err.count("\n") == 1
    assert list(ro.iterdir()) == []


# ------------------------------------------------------------------ what is accepted


def test_empty_existing_folder_is_used(tmp_path):
    """An existing empty folder is fine: the run fills it."""
    f = scenario(tmp_path)
    (tmp_path / "res").mkdir()
    assert run_cli(f, "--out", tmp_path / "res", "--no-plots") == 0
    assert (tmp_path / "res" / "summary.json").is_file() and not leftovers(tmp_path)


def test_overwrite_replaces_an_earlier_mjtether_result(tmp_path, capsys):
    """A second run into the same folder is refused without --overwrite and replaces the first with it;
    the manifest lists exactly the files written, with their sizes."""
    f1, f2 = scenario(tmp_path, 1.0, "one.toml"), scenario(tmp_path, 0.5, "two.toml")
    out = tmp_path / "res"
    assert run_cli(f1, "--out", out, "--no-plots") == 0
    first = snapshot(out)
    assert run_cli(f2, "--out", out, "--no-plots") == 2
    assert snapshot(out) == first
    assert run_cli(f2, "--out", out, "--no-plots", "--overwrite") == 0
    s = json.loads((out / "summary.json").read_text())
    assert s["scenario_file"].endswith("two.toml") and s["samples"] == 2
    manifest = json.loads((out / MANIFEST).read_text())
    names = {p.name for p in out.iterdir()} - {MANIFEST}
    assert set(manifest["files"]) == names == {"summary.json", "lines.npz", "timeseries.csv"}
    assert all(manifest["files"][n]["size"] == (out / n).stat().st_size for n in names)
    assert not leftovers(tmp_path)


# ------------------------------------------------------------------ stale temporary folders


def test_stale_temp_folders_only_of_dead_runs_are_removed(tmp_path):
    """check_target removes a marked temp folder whose pid is dead; keeps a live run's, an unmarked one,
    another host's, and any for a different target name."""
    dead = marked_temp(tmp_path, "res", "dead", dead_pid())
    live = marked_temp(tmp_path, "res", "live", os.getpid())
    other_host = marked_temp(tmp_path, "res", "far", dead_pid(), host="some-other-host")
    other_name = marked_temp(tmp_path, "other", "dead", dead_pid())
    unmarked = tmp_path / f"{partial_prefix('res')}mine"
    (unmarked / "result").mkdir(parents=True)
    check_target(tmp_path / "res", overwrite=False)
    assert not dead.exists()
    assert live.exists() and other_host.exists() and other_name.exists() and (unmarked / "result").is_dir()


# ------------------------------------------------------------------ Staging: exceptions, disk errors, signals


def test_exception_while_writing_leaves_nothing(tmp_path):
    """An exception inside Staging removes the temp folder; the target never appears."""
    out = check_target(tmp_path / "res", overwrite=False)
    with pytest.raises(RuntimeError, match="boom"):
        with Staging(out) as st:
            (st.path / "summary.json").write_text("{}")
            raise RuntimeError("boom")
    assert list(tmp_path.iterdir()) == []


def test_failed_overwrite_keeps_the_earlier_result(tmp_path):
    """If writing the new result fails, the earlier one is left exactly as it was."""
    out = earlier_result(tmp_path / "res")
    before = snapshot(tmp_path)
    with pytest.raises(RuntimeError):
        with Staging(check_target(out, overwrite=True), overwrite=True) as st:
            (st.path / "summary.json").write_text('{"new": 1}')
            raise RuntimeError("plotting failed")
    assert snapshot(tmp_path) == before


def test_commit_rechecks_that_the_old_result_is_still_ours(tmp_path):
    """A user file added to the old result during the run makes commit refuse, leaving it alone."""
    out = earlier_result(tmp_path / "res")
    with pytest.raises(OutputError, match="changed during the run"):
        with Staging(check_target(out, overwrite=True), overwrite=True) as st:
            (st.path / "summary.json").write_text('{"new": 1}')
            (out / "added-meanwhile.txt").write_text("mine")
            st.commit()
    assert (out / "added-meanwhile.txt").exists() and (out / "summary.json").read_text() == "{}"
    assert not leftovers(tmp_path)


@pytest.mark.skipif(not Path("/dev/full").exists(), reason="needs /dev/full")
def test_full_disk_is_one_line_and_leaves_nothing(tmp_path):
    """A real ENOSPC (writing to /dev/full) becomes OutputError 'no space left on device ... nothing was written'."""
    with pytest.raises(OutputError, match="no space left on device while writing results to .*nothing was written"):
        with Staging(check_target(tmp_path / "res", overwrite=False)) as st:
            (st.path / "tether.npz").symlink_to("/dev/full")
            with open(st.path / "tether.npz", "w") as fh:
                fh.write("x" * 100_000)
    assert list(tmp_path.iterdir()) == []


def test_results_write_from_python_refuses_user_content_and_cleans_up(tmp_path):
    """results.write (called from Python) re-checks: it refuses a user folder even with overwrite, and an
    exception while writing (a missing extra file) leaves no folder and no summary.json."""
    sc = load_scenario(scenario(tmp_path))
    rows, history, info = run(sc)
    user = user_folder(tmp_path / "mine")
    before = snapshot(tmp_path)
    with pytest.raises(OutputError, match="not purely an earlier mjtether result"):
        results.write(user, sc, rows, history, info, plots=False, overwrite=True)
    with pytest.raises(FileNotFoundError):
        results.write(tmp_path / "res", sc, rows, history, info, plots=False,
                      extra_files={"video.mp4": tmp_path / "missing.mp4"})
    assert snapshot(tmp_path) == before


def test_signal_inside_nested_stagings_cleans_both(tmp_path):
    """results.write stages inside the cli's staging: SIGTERM in the inner one removes both temp folders."""
    previous = signal.getsignal(signal.SIGTERM)
    with pytest.raises(SystemExit):
        with Staging(check_target(tmp_path / "res", overwrite=False)):
            with Staging(check_target(tmp_path / "res", overwrite=False)) as inner:
                (inner.path / "summary.json").write_text("{}")
                assert len(leftovers(tmp_path)) >= 2
                os.kill(os.getpid(), signal.SIGTERM)
                time.sleep(5)
    assert signal.getsignal(signal.SIGTERM) == previous
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("sig, exc, code", [(signal.SIGTERM, SystemExit, 143),
                                            (signal.SIGINT, KeyboardInterrupt, None)])
def test_signal_during_staging_cleans_up_and_restores_handlers(tmp_path, sig, exc, code):
    """SIGTERM/SIGINT while staging remove the temp folder, end with exit 143 / KeyboardInterrupt,
    and the handlers in place before are restored. (Python's own handlers are put in place first:
    a test process started in the background, as CI may start it, inherits SIGINT ignored, which
    Staging rightly leaves ignored.)"""
    python_default = {signal.SIGINT: signal.default_int_handler, signal.SIGTERM: signal.SIG_DFL}[sig]
    inherited = signal.signal(sig, python_default)
    try:
        with pytest.raises(exc) as info:
            with Staging(check_target(tmp_path / "res", overwrite=False)) as st:
                (st.path / "summary.json").write_text("{}")
                os.kill(os.getpid(), sig)
                time.sleep(5)  # the handler interrupts this
        if code is not None:
            assert info.value.code == code
        assert signal.getsignal(sig) == python_default
    finally:
        signal.signal(sig, inherited)
    assert list(tmp_path.iterdir()) == []


# ------------------------------------------------------------------ a real process, killed


def _start_long_run(tmp_path) -> tuple[subprocess.Popen, Path]:
    """`python -m mjtether.cli run` on a 300 s scenario, once its staging folder exists and it is simulating."""
    f = scenario(tmp_path, duration=300.0)
    out = tmp_path / "res"
    p = subprocess.Popen([sys.executable, "-m", "mjtether.cli", "run", str(f), "--out", str(out), "--no-plots"],
                         cwd=tmp_path, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                         preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))  # not ignored, as in `cmd &`
    deadline = time.monotonic() + 600  # (a hang guard: the first compile may take a minute or more)
    while not leftovers(tmp_path) and p.poll() is None and time.monotonic() < deadline:
        time.sleep(0.05)
    assert leftovers(tmp_path) and p.poll() is None, p.stderr.read().decode() if p.poll() is not None else ""
    time.sleep(1.0)  # into the simulation
    return p, out


@pytest.mark.parametrize("sig, code", [(signal.SIGTERM, 143), (signal.SIGINT, 130)])
def test_signal_during_a_run_leaves_nothing(tmp_path, sig, code):
    """SIGTERM / SIGINT to a running `mjtether run`: exit 143 / 130, no results folder, no temp folder,
    no summary.json anywhere."""
    p, out = _start_long_run(tmp_path)
    p.send_signal(sig)
    p.communicate(timeout=30)
    assert p.returncode == code
    assert not out.exists() and not leftovers(tmp_path) and not list(tmp_path.rglob("summary.json"))


def test_sigkill_leaves_a_temp_folder_that_the_next_run_removes(tmp_path):
    """SIGKILL cannot be caught: its marked temp folder stays, and the next check of that target removes it."""
    p, out = _start_long_run(tmp_path)
    p.kill()
    p.communicate(timeout=30)
    assert leftovers(tmp_path) and not out.exists()
    check_target(out, overwrite=False)
    assert not leftovers(tmp_path) and not list(tmp_path.rglob("summary.json"))


def test_sigterm_during_a_render_leaves_no_video(tmp_path):
    """SIGTERM to `mjtether render` while it is drawing: exit 143, neither the video nor its
    half-written temporary file is left."""
    f = scenario(tmp_path, duration=300.0)
    video = tmp_path / "clip.gif"
    p = subprocess.Popen([sys.executable, "-m", "mjtether.cli", "render", str(f), "-o", str(video), "--width", "64",
                          "--height", "48", "--fps", "2"], cwd=tmp_path, stdout=subprocess.DEVNULL,
                         stderr=subprocess.PIPE)
    # wait for the drawing to start, however long the first compile takes (the limit only
    # guards against a hang: nothing here depends on the machine's speed)
    deadline = time.monotonic() + 600
    while not list(tmp_path.glob(".clip*")) and p.poll() is None and time.monotonic() < deadline:
        time.sleep(0.05)
    assert list(tmp_path.glob(".clip*")) and p.poll() is None, p.stderr.read().decode() if p.poll() is not None else ""
    p.send_signal(signal.SIGTERM)
    p.communicate(timeout=30)
    assert p.returncode == 143
    assert not video.exists() and not list(tmp_path.glob(".clip*"))
