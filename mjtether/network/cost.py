"""What a network's run will cost, estimated before it runs (as ``scenario.cost`` for a scenario):
steps, samples, elements, wall time on one core and the size of its recorded history; ``check``
refuses a run of days or of more output than allowed."""

from __future__ import annotations

import math

from .config import Network, NetworkError

US_PER_STEP = (300.0, 4.2, 50.0)
"""Cost model of one network step on one core (us): fixed, per allocated line element, per walker.
Fitted to 10, 50 and 200 lines of 20 elements between held points on this project's 2-core CI
machine (measured 0.97, 3.0 and 16.7 ms a step; the model within about 50 %): it only has to
tell minutes from days."""


def estimate(net: Network, timestep: float) -> dict:
    """What the run of ``net`` at ``timestep`` (s) will cost: ``steps``, ``samples``, ``elements``
    (deployed plus those a drum can pay out), ``us_per_step``, ``wall_hours`` on one core and
    ``output_gb`` of recorded history (every line's nodes, tensions and pushes, float64)."""
    elements = sum(max(ln.segments, math.ceil(ln.max_length / (ln.length / ln.segments)))
                   if ln.payout_speed > 0 else ln.segments for ln in net.lines)
    steps = net.duration / timestep
    samples = net.duration / net.output_interval + 1
    a, b, walker = US_PER_STEP
    us = a + b * elements + walker * len(net.walkers)
    per_sample = 8 * (3 * (elements + len(net.lines)) + 2 * elements + 64)
    return {"steps": steps, "samples": samples, "elements": elements, "us_per_step": us,
            "wall_hours": steps * us * 1e-6 / 3600.0, "output_gb": samples * per_sample / 1e9}


def check(net: Network, timestep: float) -> None:
    """Refuse (``NetworkError``, naming the key) a run estimated (``estimate``) to take longer than
    ``simulation.max_wall_hours`` or to record more than ``simulation.max_output_gb``."""
    est = estimate(net, timestep)
    if est["wall_hours"] > net.max_wall_hours:
        raise NetworkError(f"simulation.duration = {net.duration:g} s: at a step of {timestep:g} s that is "
                           f"{est['steps']:.3g} steps of about {est['us_per_step']:.0f} us, about "
                           f"{est['wall_hours']:.3g} h on one core: over simulation.max_wall_hours = "
                           f"{net.max_wall_hours:g} h (shorten the run, use fewer segments, or raise "
                           "simulation.max_wall_hours)")
    if est["output_gb"] > net.max_output_gb:
        raise NetworkError(f"simulation.output_interval = {net.output_interval:g} s: that is {est['samples']:.3g} "
                           f"samples of {est['elements']} elements, about {est['output_gb']:.3g} GB of results: over "
                           f"simulation.max_output_gb = {net.max_output_gb:g} GB (record less often, or raise it)")
