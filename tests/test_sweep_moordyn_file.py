"""A sweep of a MoorDyn file of one line (read as the scenario it is): its cases run as
``mjtether run`` of the same file does (it was refused as "not valid TOML")."""

import csv
import json
from pathlib import Path

from mjtether import cli

FILE = Path(__file__).parent / "data" / "moordyn" / "tests" / "Mooring" / "WD0050_Chain.txt"


def test_a_moordyn_line_sweeps_as_its_run(tmp_path):
    """Case 1 (1 s) is the run of the file for 1 s: the same ship-end tension, bit for bit as
    written (both print 17 significant figures of the same run)."""
    sets = ["--set", "simulation.duration=1"]
    assert cli.main(["sweep", str(FILE), *sets, "--vary", "simulation.duration=0.5,1",
                     "--out", str(tmp_path / "sw")]) == 0
    with open(tmp_path / "sw" / "cases.csv") as fh:
        rows = list(csv.DictReader(fh))
    assert [r["status"] for r in rows] == ["ok", "ok"]
    assert cli.main(["run", str(FILE), *sets, "--out", str(tmp_path / "run"), "--no-plots"]) == 0
    s = json.loads((tmp_path / "run" / "summary.json").read_text())
    assert float(rows[1]["final_ship_tension_N"]) == s["final"]["ship_tension_N"]
    assert "[tether]" in (tmp_path / "sw" / "scenario.toml").read_text()
