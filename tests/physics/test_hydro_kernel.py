"""The force kernels are pure functions: checked against hand-computed Morison loads."""

import numpy as np
import pytest

from mjtether.physics.hydro import bending_forces, rigid_body_loads, tether_loads, wet_fraction

RHO = 1025.0


def rho_fn(z):
    return np.full(np.shape(z), RHO)


def current(u):
    return lambda z: np.tile(np.asarray(u, float), (len(z), 1))


def loads(x, v, u, **kw):
    args = dict(segment_length=np.linalg.norm(x[1] - x[0]), diameter=0.02, cd_normal=1.2,
                cd_tangential=0.01, rho_fn=rho_fn, current_fn=current(u))
    args.update(kw)
    return tether_loads(x, v, **args)


def test_normal_drag_and_buoyancy_on_a_horizontal_element():
    x = np.array([[0, 0, -10.0], [2, 0, -10.0]])
    f = loads(x, np.zeros((2, 3)), [0, 1.5, 0])
    drag = 0.5 * RHO * 1.2 * 0.02 * 2.0 * 1.5**2
    buoy = RHO * 9.81 * np.pi * 0.01**2 * 2.0
    np.testing.assert_allclose(f.sum(axis=0), [0, drag, buoy], rtol=1e-12)
    np.testing.assert_allclose(f[0], f[1], rtol=1e-12)


def test_tangential_drag_uses_wetted_area_and_relative_velocity():
    x = np.array([[0, 0, -10.0], [2, 0, -10.0]])
    v = np.tile([0.5, 0, 0], (2, 1))  # cable moving along itself at 0.5 m/s in 2 m/s current
    f = loads(x, v, [2.0, 0, 0])
    ft = 0.5 * RHO * 0.01 * np.pi * 0.02 * 2.0 * 1.5**2
    assert f.sum(axis=0)[0] == pytest.approx(ft, rel=1e-12)


def test_partly_submerged_element():
    frac, centre = wet_fraction(np.array([-1.0, -3.0, 1.0]), np.array([3.0, -1.0, 2.0]))
    np.testing.assert_allclose(frac, [0.25, 1.0, 0.0])
    assert centre[0] == pytest.approx(0.125)  # wet quarter next to node i
    x = np.array([[0, 0, -1.0], [0, 0, 3.0]])
    f = loads(x, np.zeros((2, 3)), [0, 0, 0])
    buoy = RHO * 9.81 * np.pi * 0.01**2 * 1.0  # 1 m of 4 m is wet
    np.testing.assert_allclose(f[:, 2], [buoy * 0.875, buoy * 0.125], rtol=1e-12)


def test_bending_forces_straighten_a_kink_and_balance():
    x = np.array([[0, 0, 0], [1, 0, 0], [2, 0.1, 0]], float)
    f = bending_forces(x, EI=10.0, segment_length=1.0)
    np.testing.assert_allclose(f.sum(axis=0), 0, atol=1e-12)  # internal forces
    assert f[1, 1] > 0 and f[2, 1] < 0  # pushes the kink back
    # small angle: the end force equals EI * theta / l^2 (a beam's tip force for a hinge kink)
    theta = np.arctan(0.1)
    assert abs(f[2, 1]) == pytest.approx(10.0 * np.sin(theta) / 1.0**2 * np.cos(theta), rel=0.02)


def test_rigid_body_drag_per_body_axis():
    R = np.array([[0, -1, 0], [1, 0, 0], [0, 0, 1.0]])  # body x along world y
    f, tq = rigid_body_loads(R, np.array([0, 0, -50.0]), np.zeros(3), np.zeros(3), volume=2.0,
                             height=1.0, drag_cd=np.array([1.0, 0.5, 0.8]), drag_area=np.array([3.0, 4.0, 5.0]),
                             angular_drag=np.zeros(3), rho_fn=rho_fn, current_fn=current([0, 1.0, 0]))
    # current along world y = body x: drag 1/2 rho Cx Sx u^2 along world y
    np.testing.assert_allclose(f, [0, 0.5 * RHO * 1.0 * 3.0, RHO * 9.81 * 2.0], rtol=1e-12)
    np.testing.assert_allclose(tq, 0)


def test_first_share_moves_the_first_elements_load_and_halves_the_seconds():
    """``first_share`` (the drum element's lumping, while paying out) gives node 0 that part of
    element 0's load (drag and buoyancy) and node 1 the rest, and splits element 1's drag half and
    half, as the two elements' masses are lumped; every other element keeps the lever rule. The
    total is unchanged to 1e-12, the nodes past element 1 keep their lever-rule loads, node 0
    holds 0.1 of element 0's load (worked out from element 0 alone) and node 2 half of element
    1's (from element 1 alone, less the lever rule's share)."""
    x = np.array([[0, 0, -5.0], [1.5, 0, -6.0], [3, 0, -8.0], [4, 1, -9.0], [5, 1, -10.0]])
    v = np.array([[0, 0, 0], [0.2, 0, -0.1], [0.1, 0.3, 0], [0, 0, 0.2], [0.1, 0.1, 0.1]])
    lever = loads(x, v, [0.5, 0.2, 0])
    share = loads(x, v, [0.5, 0.2, 0], first_share=0.1)
    np.testing.assert_allclose(share.sum(axis=0), lever.sum(axis=0), rtol=1e-12)
    np.testing.assert_allclose(share[3:], lever[3:], rtol=1e-12)
    element0 = loads(x[:2], v[:2], [0.5, 0.2, 0], segment_length=np.linalg.norm(x[1] - x[0]))
    np.testing.assert_allclose(share[0], 0.1 * element0.sum(axis=0), rtol=1e-12)
    element1 = loads(x[1:3], v[1:3], [0.5, 0.2, 0], segment_length=np.linalg.norm(x[1] - x[0]))
    np.testing.assert_allclose(share[2] - lever[2], element1[0] - 0.5 * element1.sum(axis=0), rtol=1e-9, atol=1e-12)


def test_loading_function_drag_at_its_ends_and_between():
    """Hong et al.'s (2020) Eq. 20-21 on one element, against values worked out by hand: flow
    across the cable (eta = 90 deg) gives f_p = 1, Morison's normal drag 1/2 rho C_d d l U^2 with
    no tangential part; flow along it (eta = 0) gives f_p = 0 and the tangential
    1/2 rho C_d d l (0.02008) U^2 along the flow; at 45 deg f_p = 0.5 - 0.11 = 0.39 (the cosines
    cancel) across the cable. To 1e-12 (rounding)."""
    from mjtether.physics.hydro import loading_function_drag

    rho, cd, d, l, U = 1000.0, 2.5, 0.025, 0.5, 0.8
    q = 0.5 * rho * cd * d * l * U * U
    t = np.array([[0.0, 0.0, 1.0]])
    across = loading_function_drag(t, np.array([[U, 0.0, 0.0]]), rho, l, d, cd)
    np.testing.assert_allclose(across, [[q, 0.0, 0.0]], rtol=1e-12, atol=1e-12)
    along = loading_function_drag(t, np.array([[0.0, 0.0, -U]]), rho, l, d, cd)
    np.testing.assert_allclose(along, [[0.0, 0.0, -0.02008 * q]], rtol=1e-12, atol=1e-12)
    s = np.sqrt(0.5)
    oblique = loading_function_drag(t, np.array([[U * s, 0.0, U * s]]), rho, l, d, cd)
    assert oblique[0, 0] == pytest.approx(0.39 * q, rel=1e-12)
    assert oblique[0, 1] == 0.0 and 0.0 < oblique[0, 2] < 0.02008 * q


def test_the_drag_law_is_carried_to_the_run_and_refused_where_it_cannot_go():
    """``tether.drag_law`` reaches the tether's loads (the NumPy path) and the steady state, is
    checked by name, and is refused with a line make-up and in a MoorDyn export."""
    import mjtether as mt
    from mjtether.scenario import load_scenario
    from mjtether.scenario.scene import tether_from

    with pytest.raises(ValueError, match="tether.drag_law must be one of morison, loading_functions"):
        mt.TetherSpec(length=10.0, drag_law="hong")
    with pytest.raises(ValueError, match='tether.drag_law .*is for a uniform tether'):
        load_scenario("lazy_wave_umbilical", overrides=('tether.drag_law="loading_functions"',))
    sc = load_scenario("default_walker", overrides=('tether.drag_law="loading_functions"',))
    assert tether_from(sc).drag_law == "loading_functions"
    hong = load_scenario("hong2020_platform")
    assert hong.tether.drag_law == "loading_functions"
    from mjtether.io import moordyn_write
    fixed = load_scenario("static_anchor_current", overrides=('tether.drag_law="loading_functions"', 'winch.mode="fixed"'))
    with pytest.raises(ValueError, match="tether.drag_law: 'loading_functions' .*not expressible in a MoorDyn file"):
        moordyn_write.write(fixed)


@pytest.mark.parametrize("z0, z1", [(-0.1, 0.1), (0.05, 0.05), (-0.3, 0.2), (0.02, -0.4), (0.1, 0.6)])
def test_a_wide_element_is_wet_by_the_part_of_its_cylinder_under_the_surface(z0, z1):
    """A 0.5 m wide, 1 m long element whose axis runs from z0 to z1 (m): its wet fraction and
    the centre of its wet part along the axis against 400 000 points drawn uniformly in the 3-D
    cylinder, counting those below z = 0 (no slicing or formula of the kernel's). Tolerance 3e-3:
    four standard errors of the count."""
    rng = np.random.default_rng(3)
    r, length, n = 0.25, 1.0, 400_000
    t = np.array([np.sqrt(length ** 2 - (z1 - z0) ** 2), 0.0, z1 - z0]) / length
    e1 = np.array([-t[2], 0.0, t[0]])  # (square to the axis, in the vertical plane)
    e2 = np.array([0.0, 1.0, 0.0])
    s = rng.uniform(0.0, 1.0, n)
    rad, ang = r * np.sqrt(rng.uniform(0.0, 1.0, n)), rng.uniform(0.0, 2 * np.pi, n)
    z = z0 + s * length * t[2] + rad * (np.cos(ang) * e1[2] + np.sin(ang) * e2[2])
    wet = z < 0.0
    frac, centre = wet_fraction(np.array([z0]), np.array([z1]), r * np.sqrt(1.0 - t[2] ** 2))
    assert frac[0] == pytest.approx(wet.mean(), abs=3e-3)
    if wet.mean() > 0.01:
        assert centre[0] == pytest.approx(s[wet].mean(), abs=3e-3)
