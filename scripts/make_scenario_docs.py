"""Write docs/scenarios.md from the typed scenario and the recorded columns.

    python scripts/make_scenario_docs.py
"""

from pathlib import Path

from mjtether.io.reference import scenarios_md


def main():
    out = Path(__file__).resolve().parents[1] / "docs" / "scenarios.md"
    out.write_text(scenarios_md())
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
