"""The compiled kernels (``mjtether.physics.compiled``) against the NumPy reference kernels.

The NumPy kernels state the physics (and are tested against hand-computed Morison loads and
Coulomb's law in ``test_hydro_kernel`` and ``test_seabed_friction``); the compiled loops must
give the same numbers. Tolerance: 1e-12 of the largest load in the array. The two compute the
same expressions in a different order of additions, so they differ by a few ulp of the terms
summed (1e-16 relative); 1e-12 leaves room for that and for nothing else.
"""

import mujoco
import numpy as np
import pytest

from mjtether.physics import compiled, hydro, water as wm
from mjtether.scenario.runner import ScenarioRun
from mjtether.scenario import load_scenario
from mjtether.cable.seabed import CONTACT_TOLERANCE, seabed_friction

pytestmark = pytest.mark.skipif(compiled.numba is None, reason="numba is not installed")

TOL = 1e-12
RNG = np.random.default_rng(7)

PROFILES = [
    (wm.ConstantDensity(1030.0), wm.ConstantCurrent(0.7, heading=0.4)),
    (wm.LinearDensity(1025.0, 980.0, 500.0), wm.ExponentialCurrent(2.5, decay_depth=15.0, heading=-1.0)),
    (wm.TabulatedDensity([0.0, 20.0, 80.0], [1022.0, 1026.0, 1028.0]), wm.LinearCurrent(1.0, 0.2, 60.0, heading=2.0)),
    (wm.ConstantDensity(), wm.PowerLawCurrent(1.2, seabed_depth=90.0, exponent=1 / 7, heading=0.3)),
    (wm.ConstantDensity(), wm.TabulatedCurrent([0.0, 10.0, 50.0], [1.0, 0.5, 0.1], [0.0, 1.0, 2.5])),
]


def close(a, b, tol=TOL):
    scale = max(float(np.max(np.abs(b))), 1e-300)
    assert np.max(np.abs(a - b)) <= tol * scale, f"{np.max(np.abs(a - b)) / scale:.3g} of the largest load"


def polyline(n, crossing=True):
    """A wavy cable of n elements from 95 m deep to (with ``crossing``) 2 m above the surface, so
    that some elements are dry and one is partly wet."""
    s = np.linspace(0.0, 1.0, n + 1)
    top = 2.0 if crossing else -5.0
    x = np.c_[120 * s, 15 * np.sin(7 * s), -95 + (95 + top) * s ** 1.5]
    return x + RNG.normal(scale=0.05, size=x.shape)


@pytest.mark.parametrize("density, current", PROFILES, ids=lambda p: type(p).__name__)
def test_tether_loads_match_the_numpy_kernel(density, current):
    water = wm.WaterColumn(depth=100.0, density=density, current=current)
    n = 60
    x, v = polyline(n), RNG.normal(scale=0.8, size=(n + 1, 3))
    rest = RNG.uniform(1.5, 2.5, n)
    d, cdn, cdt = RNG.uniform(0.02, 0.06, n), RNG.uniform(1.0, 1.5, n), RNG.uniform(0.005, 0.02, n)
    area = np.pi * d ** 2 / 4 * RNG.uniform(1.0, 3.0, n)  # floats on some
    cda = np.where(RNG.random(n) < 0.3, RNG.uniform(0.01, 0.1, n), 0.0)
    codes = compiled.profile_codes(water)
    assert codes is not None
    # (and with waves: a surface moved over each element and the particle velocity at the Gauss points)
    waves = (None, None), (RNG.uniform(-0.4, 0.4, n), RNG.normal(scale=0.5, size=(2, n, 3)))
    for share in (0.5, 0.07):
        for surface, wave_u in waves:
            ref = hydro.tether_loads(x, v, segment_length=rest, diameter=d, cd_normal=cdn, cd_tangential=cdt,
                                     rho_fn=water.rho, current_fn=water.velocity, gravity=water.gravity,
                                     first_share=share, area=area, float_cd_area=cda, surface=surface,
                                     wave_velocity=wave_u)
            rho, u, f = np.empty(2 * n), np.empty((2 * n, 3)), np.full((n + 1, 3), np.nan)
            compiled.element_water(x, *codes, rho, u)
            zg = np.minimum(hydro.gauss_heights(x[:, 2]), 0.0).T.ravel()  # (element i's two at 2i, 2i + 1)
            close(rho, water.rho(zg))
            close(u, water.velocity(zg))
            if wave_u is not None:
                u += wave_u.transpose(1, 0, 2).reshape(2 * n, 3)
            compiled.tether_loads(x, v, rest, d, cdn, cdt, area, cda, rho, u, water.gravity, share, f,
                                  np.zeros(n) if surface is None else surface)
            close(f, ref)


def test_bending_matches_the_numpy_kernel():
    n = 40
    x = polyline(n, crossing=False)
    EI = RNG.uniform(10.0, 500.0, n - 1)
    ref = hydro.bending_forces(x, EI, 2.0)
    f = np.zeros((n + 1, 3))
    compiled.add_bending_forces(x, EI / 2.0, f)
    close(f, ref)


def test_seabed_friction_matches_the_numpy_kernel():
    """Nodes off the seabed, landing (no stick point), sticking and sliding, on a sloping seabed.
    The stick force k (s - x_foot) is a difference of positions some 50 m from the origin: an ulp
    of those (7e-15 m) moves it by k ulp, more than 1e-12 of the load (forces to within 4 k ulp)."""
    n = 80
    normal = np.array([0.1, -0.05, 1.0])
    normal /= np.linalg.norm(normal)
    point = np.array([3.0, -2.0, -50.0])
    x = RNG.uniform(-40, 40, size=(n, 3))
    height = RNG.choice([0.0, 0.0095, 0.0105, 0.2], size=n)  # radius 0.01: on, on, just on, off
    x -= (((x - point) @ normal) - height)[:, None] * normal
    v = RNG.normal(scale=0.3, size=(n, 3))
    stick = x + RNG.normal(scale=[0.004, 0.004, 0.0], size=(n, 3))  # some within mu N, some beyond
    stick[RNG.random(n) < 0.2] = np.nan
    N = RNG.uniform(0.0, 50.0, n)
    N[::9] = 0.0  # buoyant nodes do not press on the seabed
    k, c = RNG.uniform(1e3, 1e4, n), RNG.uniform(0.0, 50.0, n)
    ref_f, ref_s = seabed_friction(x, v, stick, point=point, normal=normal, radius=0.01, normal_force=N, mu=0.6,
                                   stiffness=k, damping=c)
    f, s = np.empty((n, 3)), np.empty((n, 3))
    compiled.seabed_friction(x, v, stick, point, normal, 0.01, N, 0.6, k, c, CONTACT_TOLERANCE, f, s)
    ulp = np.spacing(np.max(np.abs(x)))
    assert np.max(np.abs(f - ref_f)) <= 4 * k.max() * ulp
    assert np.array_equal(np.isnan(s), np.isnan(ref_s))
    on = ~np.isnan(ref_s[:, 0])
    assert 10 < on.sum() < n  # the case covers both
    close(s[on], ref_s[on])


def test_a_profile_of_another_class_is_left_to_numpy():
    class Doubling(wm.ExponentialCurrent):
        def speed_at(self, z):
            return 2 * super().speed_at(z)

    assert compiled.profile_codes(wm.WaterColumn(current=Doubling(1.0))) is None


def test_bad_kernel_choice_is_named(monkeypatch):
    monkeypatch.setenv(compiled.KERNELS_ENV, "fortran")
    with pytest.raises(ValueError, match="MJTETHER_KERNELS must be 'numba' or 'numpy', got 'fortran'"):
        compiled.backend()


def _walk(monkeypatch, kernels, seconds=3.0):
    """The built-in walker scenario (payout, seabed friction, current, the walker's hydro) for
    ``seconds``: the tether's nodes and tensions."""
    monkeypatch.setenv(compiled.KERNELS_ENV, kernels)
    sc = load_scenario(overrides=[f"simulation.duration={seconds}"])
    run = ScenarioRun(sc)
    try:
        for _ in range(int(round(seconds / run.sim.timestep))):
            run.step()
        t = run.sim.tether()
        return t.all_nodes(run.sim.data).copy(), t.element_tension(run.sim.data).copy()
    finally:
        run.close()


def test_a_walker_run_is_the_same_with_either_kernel(monkeypatch):
    """600 steps of the default scenario: the compiled and the NumPy kernels leave the cable in the
    same place to 1e-9 m and the tensions to 1e-6 of the largest (rounding differences of 1e-16 per
    step, grown by the slack switching's thresholds: a larger difference is a different force)."""
    x_np, T_np = _walk(monkeypatch, "numpy")
    x_nb, T_nb = _walk(monkeypatch, "numba")
    assert np.max(np.abs(x_nb - x_np)) < 1e-9
    close(T_nb, T_np, tol=1e-6)


@pytest.mark.parametrize("density, current", PROFILES[:3], ids=lambda p: type(p).__name__)
def test_rigid_body_loads_match_the_numpy_kernel(density, current):
    """A tilted, spinning body half out of the water, and one deep down."""
    water = wm.WaterColumn(depth=100.0, density=density, current=current)
    codes = compiled.profile_codes(water)
    q = np.array([0.9, 0.2, -0.3, 0.25])
    R = np.zeros(9)
    mujoco.mju_quat2Mat(R, q / np.linalg.norm(q))
    R = R.reshape(3, 3)
    cd, area, ang = np.array([0.8, 1.1, 1.3]), np.array([0.3, 0.5, 0.7]), np.array([2.0, 3.0, 4.0])
    for p in ([1.0, 2.0, -0.1], [3.0, -1.0, -40.0]):
        p, v, w = np.array(p), np.array([0.4, -0.3, 0.2]), np.array([0.1, -0.5, 0.3])
        ref = hydro.rigid_body_loads(R, p, v, w, volume=0.05, height=0.4, drag_cd=cd, drag_area=area,
                                     angular_drag=ang, rho_fn=water.rho, current_fn=water.velocity,
                                     gravity=water.gravity)
        f, tq = np.empty(3), np.empty(3)
        compiled.rigid_body_loads(R, p, v, w, 0.05, 0.4, cd, area, ang, *codes, water.gravity, f, tq)
        close(f, ref[0])
        close(tq, ref[1])


def _vehicle(name):
    """A shipped vehicle; ``remus100_stall``: the REMUS 100 with fins that stall at 10 deg (to 60 %
    of their peak lift) and turn to 30 deg; ``remus100_midpoint``: the REMUS 100 with the
    midpoint cross-flow sum (``hull.crossflow = "midpoint"``; its file has Fossen's)."""
    import dataclasses
    import math

    from mjtether.vehicles.files import load_vehicle

    if name == "remus100_midpoint":
        vs = load_vehicle("remus100")
        hull = dataclasses.replace(vs.hydro.hull, crossflow="midpoint")
        return dataclasses.replace(vs, hydro=dataclasses.replace(vs.hydro, hull=hull))
    if name != "remus100_stall":
        return load_vehicle(name)
    vs = load_vehicle("remus100")
    fins = tuple(dataclasses.replace(f, stall_angle=math.radians(10.0), post_stall_lift=0.6,
                                     max_angle=math.radians(30.0)) for f in vs.fins)
    return dataclasses.replace(vs, fins=fins)


def _vehicle_wrenches(monkeypatch, kernels, name, water, states):
    """``BoundVehicle.wrench`` of the vehicle ``name`` (``_vehicle``) at each (qpos, qvel, act)."""
    from mjtether.simulation import Simulation
    from mjtether.vehicles.files import build_vehicle

    monkeypatch.setenv(compiled.KERNELS_ENV, kernels)
    spec = mujoco.MjSpec()
    vm = build_vehicle(spec, _vehicle(name), "auv", pos=(0.0, 0.0, -10.0))
    out = []
    with Simulation(spec, water, bodies=[vm]) as sim:
        bv = sim.bodies[0]
        assert (bv._codes is not None) == (kernels == "numba")
        for qpos, qvel, act in states:
            sim.data.qpos[:], sim.data.qvel[:], sim.data.act[:] = qpos, qvel, act
            mujoco.mj_kinematics(sim.model, sim.data)
            out.append(bv.wrench(sim.model, sim.data))
    return np.array(out)


@pytest.mark.parametrize("name", ["remus100", "remus100_midpoint", "remus100_stall", "bluerov2_heavy", "otter"])
@pytest.mark.parametrize("density, current", PROFILES, ids=lambda p: type(p).__name__)
def test_vehicle_wrench_matches_the_numpy_kernel(monkeypatch, name, density, current):
    """Random states of a vehicle (orientation, depth 0.5-60 m, or for the Otter heave within
    0.3 m of its waterline, velocities, fin angles up to 0.5 rad, past a 10 deg stall for
    ``remus100_stall``, shaft speeds ahead and astern) in each water column: the compiled
    ``vehicle_wrench`` against ``BoundVehicle.wrench``'s NumPy path (hull lift and drag,
    cross-flow by Fossen's sum and by the midpoint rule, fins, propeller, C_A with its zeroed
    entries, faded damping, buoyancy, a surface vessel's hydrostatics about its centre of
    flotation and its cross-flow drag; a submerged vehicle at the surface, its hull partly wet,
    fins and thrusters in the air)."""
    from mjtether.vehicles.files import build_vehicle

    water = wm.WaterColumn(depth=100.0, density=density, current=current)
    spec = mujoco.MjSpec()
    build_vehicle(spec, _vehicle(name), "auv")
    m = spec.compile()
    states = []
    for k in range(50):
        q = RNG.normal(size=4)
        z = RNG.uniform(-0.3, 0.3) if name == "otter" else -RNG.uniform(0.5, 60.0) if k % 2 else \
            RNG.uniform(-0.8, 0.5)  # (every other one at the surface: partly wet, fins and thrusters in the air)
        qpos = np.r_[RNG.normal(size=2), z, q / np.linalg.norm(q)]
        qvel = RNG.normal(size=6) * [1.5, 1.0, 1.0, 0.5, 0.5, 0.5]
        act = RNG.uniform(-0.5, 0.5, size=m.na)
        if name.startswith("remus100"):
            act[-1] = RNG.uniform(-1525.0, 1525.0)  # the propeller, the last actuator
        states.append((qpos, qvel, act))
    close(_vehicle_wrenches(monkeypatch, "numba", name, water, states),
          _vehicle_wrenches(monkeypatch, "numpy", name, water, states))


# --------------------------------------------------------------------------- the steady march

def _cables():
    """A uniform tether, and a make-up with floats (sections of two line types), in each water
    column, towed at 0.3 m/s."""
    from mjtether.quasistatic import steady

    tether = mt_tether()
    line = mt_makeup()
    for density, current in PROFILES:
        water = wm.WaterColumn(depth=300.0, density=density, current=current)
        for t in (tether, line):
            yield steady._Cable(t, water, (0.3, -0.1, 0.0), "tether" if t is line else t.EA)


def mt_tether():
    from mjtether.cable.tether import TetherSpec

    return TetherSpec(length=250.0, segments=60, diameter=0.03, density=1300.0, EA=2e6)


def mt_makeup():
    from mjtether.cable.makeup import DistributedBuoyancy, LineMakeup, Section

    return LineMakeup([Section(80.0, 20, 0.05, 12.0, EA=5e7), Section(120.0, 30, 0.04, 1.5, EA=1e6, cd_normal=1.5)],
                      [DistributedBuoyancy(90.0, 130.0, 0.02, 5.0, 0.1)])


def test_steady_march_matches_the_numpy_march():
    """Four shots (top forces around a hanging cable's, one crossing the surface from a fairlead
    above it) through ``_Cable.march``, compiled and NumPy, in every water column: nodes, tensions
    and forces to 1e-12 of their largest, the touchdown element the same."""
    rng = np.random.default_rng(3)
    for cable in _cables():
        x0 = np.array([[0.0, 0.0, 2.0], [0.0, 0.0, -5.0], [10.0, 0.0, -1.0], [0.0, 5.0, 0.0]])
        W = float(np.sum(cable.mu_e * cable.l_e)) * 9.81
        P0 = np.array([[-0.3 * W, 0.0, -0.8 * W]] * 4) * rng.uniform(0.6, 1.4, size=(4, 1))
        fast = cable.march(x0, P0, stop_on_touchdown=True)
        cable.fast = None
        ref = cable.march(x0, P0, stop_on_touchdown=True)
        for a, b in zip(fast[:3], ref[:3]):
            close(a, b)
        np.testing.assert_array_equal(fast[3], ref[3])


def test_shot_residuals_match_the_numpy_lay():
    """The residuals of the steady solver's shots (``quasistatic.kernels.shot_residuals`` against
    ``steady._residuals``, which lays the rest of a touched-down shot on the seabed with
    ``_lay``) on the same marches: shots that touch down short of the bottom end, at it and
    beyond, and shots that hang clear; the bottom end on the seabed (with and without seabed
    friction) and off it; extensible and inextensible lines; every water column. To 1e-12 of the
    largest residual."""
    from dataclasses import replace

    from mjtether.quasistatic import kernels, steady

    for cable in _cables():
        if not cable.uniform:
            continue  # (make-ups shoot through _shoot_makeup)
        for EA in (cable.EA, None):
            c = steady._Cable(replace(mt_tether(), EA=EA), cable.water, cable.v_tow, EA)
            W = c.mu * c.L * 9.81
            F = np.array([[a * W, 0.1 * W, -b * W] for a in (0.05, 0.2, 0.6) for b in (0.1, 0.3, 0.9)])
            X, T, P, td = c.march(np.tile([0.0, 0.0, -1.0], (len(F), 1)), F, stop_on_touchdown=True)
            assert 0 < np.count_nonzero(td >= 0) < len(F)  # some touch down, some hang clear
            for bottom, cb in (((150.0, 20.0, -300.0), 0.0), ((150.0, 20.0, -300.0), 0.8), ((60.0, 0.0, -200.0), 0.5)):
                pb = dict(top=np.array([0.0, 0.0, -1.0]), bottom=np.array(bottom), seabed_z=-300.0, cb=cb,
                          contact=bottom[2] == -300.0, seabed=True)
                fast, ref = np.empty((len(F), 3)), np.empty((len(F), 3))
                kernels.shot_residuals(X, P, td, pb["bottom"], pb["contact"], -300.0, cb,
                                       c.seabed_wet_weight(-300.0), c.L, c.l, c.EA, fast)
                steady._residuals(c, pb, X, T, P, td, ref)
                close(fast, ref)


def test_equality_rows_match_the_numpy_search():
    """The constraint rows of every equality of the built-in scenario's model
    (``TetherReadouts.rows``: the tether's end connects, the drum's, the elements'), compiled
    (``cable.kernels.equality_rows``) and in NumPy, after a few steps: found with nothing kept, kept
    when still right, and found again when the kept block is stale (shifted by one row, or
    empty). Row indices: equal."""
    run = ScenarioRun(load_scenario())
    try:
        for _ in range(5):
            run.step()
        bt, d, m = run.bt, run.sim.data, run.sim.model
        fast = bt._fast
        assert d.nefc > 0
        hits = 0
        for eq in range(m.neq):
            for hint in (None, "right", "shifted", "empty"):
                got = []
                for kernels in (fast, None):
                    bt._fast = kernels
                    bt._row_cache.clear()
                    if hint is not None:
                        r = bt._rows(d, eq)
                        bt._row_cache[eq] = {"right": r, "shifted": slice(r.start + 1, r.stop + 1),
                                             "empty": slice(0, 0)}[hint]
                    got.append(bt._rows(d, eq))
                assert got[0] == got[1], (eq, hint, got)
                hits += got[0].stop > got[0].start
        assert hits > 0  # (some equalities are active and have rows)
    finally:
        bt._fast = fast
        run.close()


def test_hang_up_matches_the_numpy_hang():
    """A slack cable's free hang marched up from its touchdown (``_hang_up``), compiled and
    NumPy, in every water column: nodes, tensions and the top force to 1e-12 of their largest."""
    from mjtether.quasistatic import kernels, steady

    for cable in _cables():
        if not cable.uniform:
            continue  # (the slack hang is solved for uniform lines)
        fast = steady._hang_up(cable, 201.3, -300.0)
        cable.fast = None
        ref = steady._hang_up(cable, 201.3, -300.0)
        for a, b in zip(fast[:3], ref[:3]):
            close(a, b)
        assert fast[3] == ref[3]


@pytest.mark.parametrize("added_mass", ["isotropic", "normal"])
def test_payout_bookkeeping_matches_the_python_step(added_mass):
    """A payout step's bookkeeping (``Drum.update_drum``: the fairlead node's and the
    first free node's masses and armature, the two drum elements' solver parameters and rest
    length), compiled (``cable.kernels.drum_update``) and in the scalar Python it twins, writes the
    same numbers into the model, to 1e-12 relative: two copies of the built-in scenario pay out
    reel in and pay out through the same lengths (1 cm steps, and across a node's take-back and release), one with
    each. Nothing is stepped, so nothing but the bookkeeping can differ."""
    runs = [ScenarioRun(load_scenario(overrides=[f"tether.added_mass={added_mass!r}"])) for _ in range(2)]
    try:
        runs[1].bt._fast = None  # (only the bookkeeping reads it when nothing is stepped)
        L0 = runs[0].bt.deployed_length
        l0 = runs[0].bt.l0
        lengths = [L0 - 0.01 * i for i in range(1, 6)] + [L0 - f * l0 for f in (0.5, 1.2, 1.25, 0.3, 0.31)]
        firsts = set()
        for L in lengths:
            for r in runs:
                r.bt.set_length(L)
            a, b = (r.sim.model for r in runs)
            for name in ("body_mass", "dof_armature", "tendon_invweight0", "tendon_armature", "eq_solref", "eq_solimp",
                         "eq_data"):
                close(getattr(a, name), getattr(b, name))
            for name in ("rest", "inertia", "lead", "K"):
                close(getattr(runs[0].bt.drum, name), getattr(runs[1].bt.drum, name))
            assert runs[0].bt.first == runs[1].bt.first
            firsts.add(runs[0].bt.first)
        assert len(firsts) > 1  # (a node was taken back onto the drum and released again)
    finally:
        for r in runs:
            r.close()
