"""The demo run: a tether hanging from a fixed surface point with a clump weight at its lower
end, in an exponential current. Prints the end tensions as the tether settles."""

from __future__ import annotations

import mujoco
import numpy as np
from tqdm import tqdm

from mjtether import (
    BodyPoint,
    ExponentialCurrent,
    FixedPoint,
    LinearDensity,
    RigidBodyHydro,
    Simulation,
    TetherSpec,
    WaterColumn,
    _checks,
    add_body_hydro,
    add_tether,
)
from mjtether.cable import stability


def hanging_tether(length: float = 200.0, segments: int = 50, current: float = 1.5,
                   clump_mass: float = 300.0, timestep: float = 0.005):
    """Build the demo: ``length`` m of 25 mm umbilical, a ``clump_mass`` kg steel clump weight
    (0.6 m sphere), ``current`` m/s at the surface decaying over 30 m."""
    water = WaterColumn(depth=length + 100.0, density=LinearDensity(1025.0, 980.0, 500.0),
                        current=ExponentialCurrent(current, decay_depth=30.0))
    tether = TetherSpec(length=length, segments=segments, diameter=0.025, density=1300.0, EA=5e6)
    spec = mujoco.MjSpec()
    spec.modelname = "hanging_tether"
    spec.option.timestep = timestep
    spec.option.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    r = 0.3
    clump = spec.worldbody.add_body(name="clump", pos=[0, 0, -length - r])
    clump.add_freejoint()
    clump.add_geom(type=mujoco.mjtGeom.mjGEOM_SPHERE, size=[r, 0, 0], mass=clump_mass,
                   contype=0, conaffinity=0)
    area = np.pi * r * r
    volume = 4 / 3 * np.pi * r**3
    hydro = add_body_hydro(spec, "clump", RigidBodyHydro(
        volume=volume, drag_cd=0.5, drag_area=area, added_mass=0.5 * 1025 * volume, height=2 * r))
    tm = add_tether(spec, tether, FixedPoint([0, 0, 0]), BodyPoint("clump", (0, 0, r)), water=water)
    if timestep > stability.max_timestep(tether, water):
        raise ValueError(f"timestep must be <= {stability.max_timestep(tether, water):.4f} s for this current")
    return Simulation(spec, water, [tm], [hydro])


def main(duration: float = 120.0, report_every: float = 20.0, **kwargs) -> dict:
    """Run the demo for ``duration`` s (at most a day), printing every ``report_every`` s."""
    _checks.in_range("demo duration", duration, 1e-3, 86400.0, "s")
    _checks.in_range("demo report_every", report_every, 1e-3, 86400.0, "s")
    with hanging_tether(**kwargs) as sim:
        tt = sim.tether()
        rows = []
        steps = int(round(duration / sim.timestep))
        every = max(1, int(round(report_every / sim.timestep)))
        print(f"{'t (s)':>7} {'ship-end tension (N)':>21} {'weight-end tension (N)':>23} {'clump offset x (m)':>19}")
        with tqdm(total=steps, unit="step", leave=False) as bar:
            for k in range(0, steps, every):
                n = min(every, steps - k)
                sim.step(n)
                bar.update(n)
                top = float(np.linalg.norm(tt.end_force(sim.data, "start")))
                bottom = float(np.linalg.norm(tt.end_force(sim.data, "end")))
                x = float(tt.nodes(sim.data)[-1, 0])
                rows.append((sim.time, top, bottom, x))
                tqdm.write(f"{sim.time:7.1f} {top:21.1f} {bottom:23.1f} {x:19.2f}")
        return {"time": sim.time, "ship_tension": rows[-1][1], "weight_tension": rows[-1][2],
                "offset_x": rows[-1][3]}
