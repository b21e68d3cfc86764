"""The validation page's plot of MoorPy's catenary case (docs/validation_moorpy.png).

    python scripts/make_validation_plots.py

MoorPy's own catenary test case (NREL/MoorPy, tests/test_catenary.py; the numbers are those of
tests/quasistatic/test_moorpy_case.py): a 500 m line of 800 N/m submerged weight, practically
inextensible, from an anchor on the seabed to a fairlead 400 m away and 200 m above it. Drawn:
the closed-form elastic catenary (``catenary``) and the lumped 200-element ``steady_state`` that
a dynamic run starts from, with seabed friction 0 and 0.1 (the shape is the same; the friction
changes only the anchor force), with MoorPy's published fairlead forces and laid length beside
ours. Takes a second.
"""

import math
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import mjtether as mt
from mjtether.quasistatic import catenary, steady_state

OUT = Path(__file__).resolve().parents[1] / "docs" / "validation_moorpy.png"
SPAN, HEIGHT, LENGTH, EA, W = 400.0, 200.0, 500.0, 7.51e12, 800.0
MOORPY_H, MOORPY_V, MOORPY_LAID = 96643.42815934008, 237751.75535996316, 202.81030580004602
D, DEPTH, RHO, G = 0.1, 250.0, 1025.0, 9.81


def main():
    c = catenary([0.0, 0.0, 0.0], [SPAN, 0.0, HEIGHT], LENGTH, W, EA=EA, cb=0.1)
    s = np.linspace(0.0, LENGTH, 501)
    p = c.points(s)
    mu = W / G + RHO * math.pi * D * D / 4
    tether = mt.TetherSpec(length=LENGTH, segments=200, diameter=D, mass_per_length=mu, EA=EA)
    anchor = np.array([0.0, 0.0, -DEPTH])
    ss = steady_state(tether, mt.WaterColumn(depth=DEPTH), anchor + [SPAN, 0.0, HEIGHT], anchor,
                      seabed=True, seabed_friction=0.1)
    fig, ax = plt.subplots(figsize=(6.4, 3.4), dpi=100)
    ax.plot(p[:, 0], p[:, 2], lw=3, color="0.7", label="closed-form catenary")
    ax.plot(ss.nodes[:, 0], ss.nodes[:, 2] + DEPTH, "--", lw=1.2, color="tab:blue",
            label="steady_state, 200 elements")
    ax.axhline(0.0, color="0.3", lw=0.8)
    ax.set_xlabel("x from the anchor (m)")
    ax.set_ylabel("height above the seabed (m)")
    text = (f"fairlead H: MoorPy {MOORPY_H / 1e3:.2f} kN, ours {-ss.top_force[0] / 1e3:.2f} kN\n"
            f"fairlead V: MoorPy {MOORPY_V / 1e3:.2f} kN, ours {-ss.top_force[2] / 1e3:.2f} kN\n"
            f"laid length: MoorPy {MOORPY_LAID:.1f} m, closed form {c.laid_length:.1f} m")
    ax.text(0.02, 0.97, text, transform=ax.transAxes, va="top", fontsize=8)
    ax.legend(loc="lower right", fontsize=8)
    ax.set_title("MoorPy's catenary case: 500 m, 800 N/m, span 400 m, 200 m rise", fontsize=9)
    fig.tight_layout()
    fig.savefig(OUT)
    print(f"wrote {OUT}")


if __name__ == "__main__":
    main()
