"""The sweep's summary figure: each failed case's red x sits in each panel at its own case's x,
inside the panel (it used to fall outside the left panel's x range, into the right panel, when a
failed case lay beyond the ok ones), and the ok cases' points at theirs."""

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

from mjtether import sweep  # noqa: E402

ANCHOR = """\
[simulation]
duration = 2.0
[water]
depth = 100.0
[tether]
length = 120.0
segments = 10
[robot]
type = "anchor"
position = [40.0, 0.0, -90.0]
"""


def _failed_marks(ax):
    """The red x collections of ``ax`` (the failed cases), as display coordinates."""
    out = []
    for c in ax.collections:
        if tuple(np.round(c.get_facecolor()[0][:3], 3)) == (1.0, 0.0, 0.0):
            out.append(c.get_offset_transform().transform(c.get_offsets()))
    return np.vstack(out) if out else np.empty((0, 2))


@pytest.mark.parametrize("vary, failed", [
    ("tether.length=110,120,130,140", [2, 3]),   # failed cases beyond the ok ones (to the right)
    ("tether.length=110,120,130,140", [0]),      # and before them
    ("tether.line_type=fathom_rov_tether,polyester_rope_24mm", [1]),  # text values: x is the case's tick
])
def test_failed_markers_sit_on_their_own_case_in_each_panel(tmp_path, vary, failed):
    f = tmp_path / "s.toml"
    f.write_text(ANCHOR)
    plan = sweep.make_plan(f, [sweep.parse_vary(vary)])
    records = {c.index: {"status": "ok", "peak_ship_tension_N": 100.0 + c.index, "final_length_on_seabed_m": 5.0}
               for c in plan.cases if c.index not in failed}
    names, rows = sweep.table(plan, records)
    fig = sweep.summary_figure(plan, names, rows)
    try:
        fig.canvas.draw()
        axes = fig.axes[:2]
        for ax in axes:
            marks = _failed_marks(ax)
            assert len(marks) == len(failed)
            x_data = ax.transData.inverted().transform(marks)[:, 0]
            # (text values: the case's tick, 0, 1, ... in order of first appearance, distinct here)
            want = [plan.cases[k].values[0] if plan.varies[0].numeric else k for k in failed]
            np.testing.assert_allclose(sorted(x_data), sorted(want), atol=1e-6)
            left, right = ax.bbox.x0, ax.bbox.x1
            assert np.all((marks[:, 0] >= left) & (marks[:, 0] <= right)), (marks[:, 0], left, right)
            bottom, top = ax.bbox.y0, ax.bbox.y1
            assert np.all((marks[:, 1] >= bottom) & (marks[:, 1] <= bottom + 0.1 * (top - bottom)))
    finally:
        plt.close(fig)
