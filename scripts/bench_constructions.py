"""Compare O(N) MuJoCo constructions of a tether (the numbers in mjtether/builder.py).

A 1000 m, 20 mm, 1050 kg/m^3 line between (0, 0, 0) and (600, 0, -700), no hydrodynamics
(the passive callback costs the same for every construction), 5 ms step, implicitfast,
Newton solver; microseconds per step after 100 settling steps.

    python scripts/bench_constructions.py [--json]
"""

from __future__ import annotations

import argparse
import json
import time

import mujoco
import numpy as np

import mjtether as mt

L, D, RHO_C = 1000.0, 0.02, 1050.0
P0, P1 = np.array([0.0, 0.0, 0.0]), np.array([600.0, 0.0, -700.0])


def _spec(dt=0.005):
    s = mujoco.MjSpec()
    s.option.timestep = dt
    s.option.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    return s


def capsule_chain(N: int, subchain: int = 1) -> mujoco.MjSpec:
    """Capsule bodies; every ``subchain``-th has a free joint, the others hang from it by ball
    joints; consecutive sub-chains and the ends are joined by ``connect`` equalities."""
    s = _spec()
    l = L / N
    nodes = mt.sagged_polyline(P0, P1, L, N)
    m = RHO_C * np.pi * D * D / 4 * l
    parent = None
    for i in range(N):
        t = nodes[i + 1] - nodes[i]
        q = np.zeros(4)
        mujoco.mju_quatZ2Vec(q, t / np.linalg.norm(t))
        if i % subchain == 0:
            b = s.worldbody.add_body(name=f"seg{i}", pos=0.5 * (nodes[i] + nodes[i + 1]), quat=q)
            b.add_freejoint()
        else:  # keep the parent's orientation; the chain settles from there
            b = parent.add_body(name=f"seg{i}", pos=[0, 0, l])
            b.add_joint(type=mujoco.mjtJoint.mjJNT_BALL, pos=[0, 0, -l / 2])
        b.add_geom(type=mujoco.mjtGeom.mjGEOM_CAPSULE, size=[D / 2, l / 2, 0], mass=m,
                   contype=0, conaffinity=0)
        parent = b
    for i in range(N - 1):
        if (i + 1) % subchain == 0:
            e = s.add_equality(type=mujoco.mjtEq.mjEQ_CONNECT, name1=f"seg{i}", name2=f"seg{i + 1}",
                               objtype=mujoco.mjtObj.mjOBJ_BODY)
            e.data[0:3] = [0, 0, l / 2]
    for name, z in (("seg0", -l / 2), (f"seg{N - 1}", l / 2)):
        e = s.add_equality(type=mujoco.mjtEq.mjEQ_CONNECT, name1=name, objtype=mujoco.mjtObj.mjOBJ_BODY)
        e.data[0:3] = [0, 0, z]
    return s


def flex_chain(N: int) -> mujoco.MjSpec:
    """mjtether's construction: a 1-D flex over node bodies with three slide joints."""
    s = _spec()
    mt.add_tether(s, mt.TetherSpec(length=L, segments=N, diameter=D, density=RHO_C),
                  mt.FixedPoint(P0), mt.FixedPoint(P1))
    return s


def us_per_step(spec: mujoco.MjSpec, steps: int = 400) -> float:
    model = spec.compile()
    data = mujoco.MjData(model)
    mujoco.mj_step(model, data, 100)
    t0 = time.perf_counter()
    mujoco.mj_step(model, data, steps)
    return (time.perf_counter() - t0) / steps * 1e6


def main(argv=None):
    ap = argparse.ArgumentParser()
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args(argv)
    Ns = [100, 200, 400]
    out = {"N": Ns,
           "free_capsules_connect": [round(us_per_step(capsule_chain(N)), 1) for N in Ns],
           "ball_subchains_of_5": [round(us_per_step(capsule_chain(N, 5)), 1) for N in Ns],
           "flex_nodes": [round(us_per_step(flex_chain(N)), 1) for N in Ns]}
    if args.json:
        print(json.dumps(out))
    else:
        for k, v in out.items():
            print(f"{k:>24}: {v}")


if __name__ == "__main__":
    main()
