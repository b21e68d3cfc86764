"""Every Python snippet of README.md runs as a user would paste it: in order, in one namespace
(a later snippet uses what an earlier one made), from a temporary folder outside the
repository (so that none leans on a checkout's relative paths)."""

import os
import re
from pathlib import Path

README = Path(__file__).resolve().parents[1] / "README.md"


def test_the_readme_python_snippets_run_from_outside_the_repository(tmp_path, monkeypatch, capsys):
    blocks = re.findall(r"^```python\n(.*?)^```", README.read_text(), flags=re.S | re.M)
    assert len(blocks) >= 4
    monkeypatch.chdir(tmp_path)
    namespace = {"__name__": "__readme__"}
    for k, code in enumerate(blocks, 1):
        try:
            exec(compile(code, f"README.md python snippet {k}", "exec"), namespace)
        except Exception as exc:  # (say which snippet, with the error)
            raise AssertionError(f"README.md python snippet {k} failed: {type(exc).__name__}: {exc}") from exc
    if "env" in namespace:  # (the environment snippet leaves its environment open, as a script may)
        namespace["env"].close()
    assert os.getcwd() == str(tmp_path)


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
