"""Every Python and shell snippet of README.md and docs/*.md runs as a user would paste it: a
file's snippets in order, the Python ones in one namespace (a later snippet uses what an earlier
one made), the shell ones with bash in the same folder (a later one reads what an earlier one
wrote), from a temporary folder outside the repository (so that none leans on a checkout's
relative paths). ``mjtether`` and ``python`` in a shell snippet are this interpreter with this
checkout's package.

A snippet that installs packages or runs for minutes is skipped only by a visible rule: the
comment ``<!-- skip: REASON -->`` on the line before its fence (the reason must be given), or, for
README.md's "Set-up (two commands)" section, which stays exactly as it is, the entry in
SKIPPED_SECTIONS below."""

from __future__ import annotations

import os
import re
import subprocess
import sys
import tomllib
from dataclasses import dataclass
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
README = ROOT / "README.md"
DOC_FILES = [README] + sorted((ROOT / "docs").glob("*.md"))
LANGUAGES = {"python", "bash"}
# (file, section heading) -> why every snippet of that section is skipped
SKIPPED_SECTIONS = {
    ("README.md", "## Set-up (two commands)"): "installs the package with pip, runs the built-in scenario for "
                                               "minutes and the whole test suite: what CI runs (.ci/run)",
}
MAX_SKIPPED = 8  # the skipped snippets stay few

FENCE = re.compile(r"^```(\w*)[^\n]*\n(.*?)^```[ \t]*$", re.S | re.M)
SKIP = re.compile(r"^<!--\s*skip:(.*?)-->\s*$")


@dataclass
class Snippet:
    file: Path
    line: int
    lang: str
    code: str
    skip: str | None  # the reason, where skipped

    def where(self) -> str:
        return f"{self.file.relative_to(ROOT)}:{self.line}"


def snippets(path: Path) -> list[Snippet]:
    text = path.read_text()
    lines = text.splitlines()
    out = []
    for m in FENCE.finditer(text):
        lang = m[1]
        if lang not in LANGUAGES:
            continue
        line = text.count("\n", 0, m.start()) + 1
        before = lines[line - 2].strip() if line >= 2 else ""
        skip = None
        if (s := SKIP.match(before)) is not None:
            skip = s[1].strip()
            assert skip, f"{path.name}:{line}: a skip comment must give its reason (<!-- skip: REASON -->)"
        heading = next((h for h in reversed(lines[:line - 1]) if h.startswith("#")), "")
        skip = skip or SKIPPED_SECTIONS.get((path.name, heading.strip()))
        out.append(Snippet(path, line, lang, m[2], skip))
    return out


def _shims(folder: Path) -> dict:
    """An environment whose ``mjtether`` and ``python`` are this interpreter with this checkout."""
    folder.mkdir()
    (folder / "mjtether").write_text(
        f'#!/bin/sh\nexec "{sys.executable}" -c "import sys; from mjtether.cli import main; sys.exit(main())" "$@"\n')
    (folder / "python").write_text(f'#!/bin/sh\nexec "{sys.executable}" "$@"\n')
    for f in folder.iterdir():
        f.chmod(0o755)
    env = dict(os.environ)
    env["PATH"] = f"{folder}{os.pathsep}{env.get('PATH', '')}"
    env["PYTHONPATH"] = os.pathsep.join([str(ROOT)] + [p for p in [env.get("PYTHONPATH")] if p])
    env["MPLBACKEND"] = "Agg"
    return env


FILES_WITH_SNIPPETS = [p for p in DOC_FILES if any(not s.skip for s in snippets(p))]


@pytest.mark.parametrize("path", FILES_WITH_SNIPPETS, ids=lambda p: p.name)
def test_the_snippets_run_from_outside_the_repository(path, tmp_path, monkeypatch, capsys):
    work = tmp_path / "work"
    work.mkdir()
    env = _shims(tmp_path / "bin")
    monkeypatch.chdir(work)
    namespace = {"__name__": "__docs__"}
    for k, snip in enumerate(snippets(path), 1):
        if snip.skip:
            continue
        if snip.lang == "python":
            try:
                exec(compile(snip.code, f"{snip.where()} (python snippet {k})", "exec"), namespace)
            except Exception as exc:  # (say which snippet, with the error)
                raise AssertionError(f"{snip.where()}: python snippet failed: {type(exc).__name__}: {exc}") from exc
        else:
            r = subprocess.run(["bash", "-euo", "pipefail", "-c", snip.code], cwd=work, env=env,
                               capture_output=True, text=True, timeout=300)
            assert r.returncode == 0, (f"{snip.where()}: shell snippet failed ({r.returncode}):\n{snip.code}\n"
                                       f"stdout: {r.stdout[-2000:]}\nstderr: {r.stderr[-3000:]}")
    if "env" in namespace and hasattr(namespace["env"], "close"):  # (a Gymnasium snippet leaves it open)
        namespace["env"].close()
    assert os.getcwd() == str(work)


def test_snippets_are_found_and_few_are_skipped():
    """The snippets the test above runs, in numbers; every skip has its reason, and skips stay few."""
    every = [s for p in DOC_FILES for s in snippets(p)]
    ran = [s for s in every if not s.skip]
    skipped = [s for s in every if s.skip]
    assert sum(s.lang == "python" for s in ran) >= 4
    assert sum(s.lang == "bash" for s in ran) >= 10
    assert all(s.skip.strip() for s in skipped)
    assert len(skipped) <= MAX_SKIPPED, [f"{s.where()}: {s.skip}" for s in skipped]
    # the README's set-up commands are the ones skipped by section (they stay exactly as written)
    readme = [s for s in snippets(README) if s.skip]
    assert [s.code.strip() for s in readme] == ['python -m pip install -e ".[dev]" && mjtether run --out results',
                                                "python -m pytest -q"]


def test_a_skip_comment_without_a_reason_is_refused(tmp_path):
    doc = tmp_path / "page.md"
    doc.write_text("text\n\n<!-- skip: -->\n```bash\nfalse\n```\n")
    with pytest.raises(AssertionError, match="must give its reason"):
        snippets(doc)
    doc.write_text("text\n\n<!-- skip: installs a package -->\n```bash\nfalse\n```\n\n```python\nx = 1\n```\n")
    got = snippets(doc)
    assert [(s.lang, s.skip) for s in got] == [("bash", "installs a package"), ("python", None)]


def test_a_shipped_example_runs_by_name_from_anywhere(tmp_path, monkeypatch, capsys):
    """`mjtether solve default_walker` and a network example by name, from a folder with no
    examples in it: the shipped examples are package data (``mjtether.examples``)."""
    from mjtether import cli
    from mjtether.io import moordyn

    monkeypatch.chdir(tmp_path)
    assert cli.main(["solve", "default_walker"]) == 0
    assert capsys.readouterr().out.startswith("steady state of")
    net = moordyn.load_any("networks/rov_cage_excursion")
    assert "rov" in net.vehicles


def test_the_readme_says_what_its_test_command_runs():
    """README.md's account of `python -m pytest -q` quotes pyproject.toml's pytest options as they
    are (the `-n auto` a reader gets without typing it), and the marker, the options and the file
    it tells a reader to use exist."""
    readme = README.read_text()
    opts = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["pytest"]["ini_options"]
    section = readme[readme.index("## Set-up (two commands)"):readme.index("\n## ", readme.index("## Set-up") + 1)]
    assert f'`addopts = "{opts["addopts"]}"`' in section
    assert "-n auto" in opts["addopts"] and "pytest-xdist" in section  # (the README explains -n auto)
    assert any(m.split(":")[0].strip() == "slow" for m in opts["markers"]) and '-m "not slow"' in section
    for path in re.findall(r"`python -m pytest -q -n 0 (tests/\S+\.py)`", section):
        assert (ROOT / path).is_file(), path
    assert re.search(r"`python -m pytest -q -n 0 tests/\S+\.py`", section)
