"""A sweep of a vehicle with no tether (``tether.attached = false``): its cases run, with the
tension figures left empty (it stopped with a KeyError on the summary's missing "peak")."""

import csv

from mjtether import cli


def test_a_vehicle_alone_sweeps(tmp_path):
    rc = cli.main(["sweep", "otter_manoeuvres", "--set", "simulation.duration=1",
                   "--vary", "simulation.duration=0.5,1", "--out", str(tmp_path / "sw")])
    assert rc == 0
    with open(tmp_path / "sw" / "cases.csv") as fh:
        rows = list(csv.DictReader(fh))
    assert [r["status"] for r in rows] == ["ok", "ok"]
    assert all(r["peak_ship_tension_N"] == "" for r in rows)
