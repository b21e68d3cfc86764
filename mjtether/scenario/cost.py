"""What a scenario's run will cost, estimated before it runs: steps, samples, elements, wall time on
one core and the memory its recorded history needs (``Scenario.estimate``; the checks refuse a
run of days or of more memory than allowed)."""

from __future__ import annotations

import math

US_PER_STEP = (300.0, 1.3, 50.0)
"""Cost model of one step on one core (us): fixed, per allocated tether element, walker. Fitted
to steps of 60 to 2000 allocated elements on this project's 2-core CI machine (MuJoCo 4.0;
measured 390-2900 us, the model within about 30 %); it only has to tell minutes from days."""


def estimate(sc, max_length: float | None = None) -> dict:
    """What the run of scenario ``sc`` will cost: ``steps``, ``samples``, ``elements`` allocated
    (deployed plus those waiting on the drum, for a drum of ``max_length`` m, default the
    winch's), ``us_per_step`` and ``wall_hours`` on one core (the ``US_PER_STEP`` model),
    ``output_gb`` of recorded history (node positions, element tensions and lengths as
    float64)."""
    t, s = sc.tether, sc.simulation
    max_length = sc.winch.max_length if max_length is None else max_length
    l0 = t.length / t.segments
    elements = max(t.segments, int(math.ceil(max_length / l0 - 0.5)) + 1)  # builder.drum_capacity
    steps = s.duration / s.timestep
    samples = s.duration / s.output_interval + 1
    from .robot_ends import ROBOT_ENDS
    a, b, walker = US_PER_STEP
    us = a + b * elements + (walker if ROBOT_ENDS[sc.robot.type].walker else 0.0)
    per_sample = 8 * (3 * (elements + 1) + 2 * elements + 32)
    return {"steps": steps, "samples": samples, "elements": elements, "us_per_step": us,
            "wall_hours": steps * us * 1e-6 / 3600.0, "output_gb": samples * per_sample / 1e9}
