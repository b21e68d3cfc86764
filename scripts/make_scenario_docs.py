"""Write docs/scenarios.md from the scenario schema and the recorded columns.

    python scripts/make_scenario_docs.py
"""

from pathlib import Path

from mjtether.results import column_names
from mjtether.runner import RECORD_FIELDS
from mjtether.scenario import scenario_docs

HEAD = '# Scenario files\n\nA scenario is a TOML file with the sections below; every key is optional unless marked\nrequired, and takes the default shown. Units are SI. Speeds marked "or `<key>_kn`" may be given\nin knots instead (1 kn = 0.514444 m/s). Unknown sections or keys, wrong types and values out of\nrange are errors that name the file, the key and the allowed range; `mjtether run` then exits\nwith status 2 and writes nothing.\n\n```bash\nmjtether run examples/static_anchor_current.toml --out results/static   # simulate, write results\nmjtether solve examples/static_anchor_current.toml                      # quasi-static answer only\n```\n\nExamples are in `examples/`; the built-in scenario (used when no file is given) is\n`mjtether/scenarios/default.toml`.\n\nFrames: world, z up, water surface at z = 0, seabed at z = -depth. Headings are measured from\n+x towards +y (rad).\n\n## Keys\n\n'

TAIL = '\n## Results folder (`mjtether run --out DIR`)\n\nThe folder appears only when the run has finished; a failed run (divergence, a tension above\n`tether.rated_load`, bad input) writes nothing and exits non-zero, and an older folder of the\nsame name is left as it was.\n\n- `timeseries.csv`: one row per `simulation.output_interval`, starting at t = 0:\n\n| column | unit | meaning |\n|---|---|---|\n{COLUMNS}\n\n- `tether.npz`, one row per sample: `time` (n,) in s; `nodes` (n, e+1, 3) in m; `tension` (n, e) in N,\n  the axial tension of every element, never negative (elements carry tension only: a slack element\n  carries 0; bending stiffness, where `tether.EI` is set, is a separate transverse force and is not\n  in it); `element_length` (n, e) in m, the stretched length of each element. The e elements are all\n  those allocated for `winch.max_length`, numbered from the core of the drum to the robot: element j is\n  the same piece of cable all run. Cable still on the drum has `element_length` and `tension` 0 and\n  its nodes sit at the fairlead; the deployed cable is the elements with a length, the first of\n  them (the drum element, at most 1.2 times the nominal length `tether.length / tether.segments`)\n  at the ship, the last at the robot.\n- `summary.json`: the scenario as read (defaults filled in, SI units), final and peak tensions,\n  wall time, real-time factor and how the tether was started (`initial_state`: `quasi-static steady state`,\n  or `settled with the robot held` where `simulation.start` allows it; a scenario with no consistent\n  start stops before simulating, saying why).\n- `tension.png`, `profile.png` (side and top views of six snapshots), `track.png`.\n'


def main():
    cols = "\n".join(f"| `{c}` | {u} | {d} |" for c, (n, u, d) in zip(column_names(), RECORD_FIELDS))
    out = Path(__file__).resolve().parents[1] / "docs" / "scenarios.md"
    out.write_text(HEAD + scenario_docs() + TAIL.replace("{COLUMNS}", cols))
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
