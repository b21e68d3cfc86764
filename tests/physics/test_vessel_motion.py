"""The ship's motion from displacement RAOs and a prescribed heave (mjtether.physics.vessel_motion).

Every expected value is written here from the conventions' definitions (OrcaFlex: x = A a
cos(omega t - lag) against eta = a cos(omega t) at the RAO origin; WAMIT: a lead), the wave
elevation's closed form, rigid-body kinematics or a closed-form barge model, never read back
from the module. Tables are written as csv files, so the reader is exercised too."""

import math
from pathlib import Path

import numpy as np
import pytest

from mjtether.physics.vessel_motion import PrescribedHeave, RAOError, RAOTable, ShipMotion

G = 9.81
DOFS = ("surge", "sway", "heave", "roll", "pitch", "yaw")
HEADER = ["period_s", "heading_deg"] + [c for d, u in zip(DOFS, ["m"] * 3 + ["deg"] * 3)
                                        for c in (f"{d}_amp_{u}_per_m", f"{d}_phase_deg")]
EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "raos" / "box_barge_heave_pitch.csv"


def write_table(path, periods, headings, rao, convention="orcaflex", symmetric=False):
    """A table file whose row (T, h) holds ``rao(T, h)``: {dof: (amplitude, phase_deg)}, others 0."""
    lines = ["# a test table", f"# convention = {convention}", f"# symmetric = {str(symmetric).lower()}",
             ",".join(HEADER)]
    for T in periods:
        for h in headings:
            given = rao(T, h)
            values = [v for d in DOFS for v in given.get(d, (0.0, 0.0))]
            lines.append(",".join(repr(float(x)) for x in [T, h] + values))
    path.write_text("\n".join(lines) + "\n")
    return path


def waves(n, seed=0):
    """n deep-water components: (amplitude m, omega rad/s, k rad/m, heading rad, phase rad)."""
    rng = np.random.default_rng(seed)
    omega = 2 * np.pi / rng.uniform(4.0, 14.0, n)
    return (rng.uniform(0.2, 1.5, n), omega, omega ** 2 / G, rng.uniform(-np.pi, np.pi, n),
            rng.uniform(-np.pi, np.pi, n))


def elevation(comp, x, y, t):
    """eta(x, y, t) = sum a cos(k (x cos b + y sin b) - omega t + e), the waves' definition."""
    a, w, k, b, e = comp
    return np.sum(a * np.cos(k * (x * np.cos(b) + y * np.sin(b)) - np.multiply.outer(t, w) + e), axis=-1)


ALL_HEADINGS = np.arange(0.0, 360.0, 30.0)


def test_unit_heave_rao_follows_the_elevation_at_the_reference_point(tmp_path):
    """Heave RAO 1 at lag 0 for every period and heading, all else 0: the reference point's z is
    the wave elevation at its rest position, whatever the ship's heading, and nothing else
    moves. Tolerance 1e-12 m: the same cosines summed in another order."""
    table = RAOTable.from_csv(write_table(tmp_path / "heave.csv", [2.0, 30.0], ALL_HEADINGS,
                                          lambda T, h: {"heave": (1.0, 0.0)}))
    comp = waves(6)
    ship = ShipMotion(table, comp, heading=0.7, origin=(12.0, -7.0))
    t = np.linspace(0.0, 40.0, 201)
    pose = ship.pose(t)
    np.testing.assert_allclose(pose[:, 2], elevation(comp, 12.0, -7.0, t), rtol=0, atol=1e-12)
    np.testing.assert_allclose(pose[:, [0, 1, 3, 4, 5]], 0.0, atol=1e-15)


def test_surge_follows_the_ships_axes_and_the_relative_heading(tmp_path):
    """A surge RAO of 1 (lag 0) only for waves from astern (relative heading 0; 0 at 90 and
    270): a ship heading along world +y in waves travelling along +y surges along world y by the
    elevation at its reference point; turned 90 deg away from the waves, it does not move.
    Tolerance 1e-12 m."""
    table = RAOTable.from_csv(write_table(tmp_path / "surge.csv", [2.0, 30.0], ALL_HEADINGS,
                                          lambda T, h: {"surge": (abs(math.cos(math.radians(h))),
                                                                  0.0 if math.cos(math.radians(h)) >= 0 else 180.0)}))
    comp = (np.array([0.8]), np.array([0.9]), np.array([0.9 ** 2 / G]), np.array([math.pi / 2]), np.array([0.4]))
    t = np.linspace(0.0, 20.0, 101)
    along = ShipMotion(table, comp, heading=math.pi / 2, origin=(3.0, 5.0)).pose(t)
    np.testing.assert_allclose(along[:, 1], elevation(comp, 3.0, 5.0, t), atol=1e-12)
    np.testing.assert_allclose(along[:, [0, 2]], 0.0, atol=1e-12)
    across = ShipMotion(table, comp, heading=0.0, origin=(3.0, 5.0)).pose(t)
    np.testing.assert_allclose(across, 0.0, atol=1e-12)


def test_pitch_moves_a_fairlead_at_half_length_in_heave(tmp_path):
    """Pitch RAO 2 deg/m at lag 30 deg: a fairlead at x = L/2 on the centreline heaves by
    -L/2 theta(t) (pitch positive bow down), theta = 2 pi/180 a cos(omega t - e' - 30 deg), and
    does not move along x (the linear form). Tolerance 1e-12 m; and within the second-order
    term L/2 |theta|^3 / 6 of the rigid rotation's -L/2 sin(theta)."""
    L = 60.0
    table = RAOTable.from_csv(write_table(tmp_path / "pitch.csv", [2.0, 30.0], ALL_HEADINGS,
                                          lambda T, h: {"pitch": (2.0, 30.0)}))
    a, T, e = 1.5, 8.0, 0.25
    w = 2 * math.pi / T
    comp = (np.array([a]), np.array([w]), np.array([w * w / G]), np.array([0.0]), np.array([e]))
    t = np.linspace(0.0, 16.0, 161)
    theta = math.radians(2.0) * a * np.cos(w * t - e - math.radians(30.0))
    fair = ShipMotion(table, comp).point([L / 2, 0.0, 0.0], t)
    np.testing.assert_allclose(fair.offset[:, 2], -L / 2 * theta, rtol=0, atol=1e-12)
    np.testing.assert_allclose(fair.offset[:, :2], 0.0, atol=1e-12)
    assert np.all(np.abs(fair.offset[:, 2] + L / 2 * np.sin(theta)) <= L / 2 * np.abs(theta) ** 3 / 6 + 1e-12)


@pytest.mark.parametrize("convention, t_max", [("orcaflex", 0.25), ("wamit", 0.75)])
def test_a_90_deg_phase_puts_the_maximum_a_quarter_period_from_the_crest(tmp_path, convention, t_max):
    """Heave RAO 1 at phase 90 deg, the crest at the origin at t = 0: OrcaFlex's lag puts the
    maximum heave a quarter period after the crest (t = T/4); WAMIT's lead a quarter period
    before it (t = 3T/4 in the cycle). Tolerance: one sample of T/4000 on the time grid; the
    heave at the crest is 0 to 1e-12 m."""
    table = RAOTable.from_csv(write_table(tmp_path / "lag.csv", [2.0, 30.0], ALL_HEADINGS,
                                          lambda T, h: {"heave": (1.0, 90.0)}, convention=convention))
    T = 10.0
    comp = (np.array([1.0]), np.array([2 * math.pi / T]), np.array([(2 * math.pi / T) ** 2 / G]), np.array([1.0]),
            np.array([0.0]))
    t = np.linspace(0.0, T, 4001)
    z = ShipMotion(table, comp).pose(t)[:, 2]
    assert abs(t[np.argmax(z)] - t_max * T) <= T / 4000
    assert abs(z[0]) < 1e-12


def test_interpolation_is_exact_on_a_linear_table(tmp_path):
    """Amplitudes linear in period and heading at one phase per DOF are interpolated exactly
    between rows and columns (tolerance 1e-12); a heading is wrapped (-10 = 350 = 710 deg), and
    between the last heading (330) and the first (0, one turn on) the RAO is their mean at 345."""
    heave = lambda T, h: 0.1 + 0.02 * T + 0.001 * h            # noqa: E731  m/m
    roll = lambda T, h: 0.5 + 0.01 * T + 0.002 * h             # noqa: E731  deg/m
    table = RAOTable.from_csv(write_table(tmp_path / "linear.csv", [4.0, 6.0, 10.0, 16.0], ALL_HEADINGS,
                                          lambda T, h: {"heave": (heave(T, h), 40.0), "roll": (roll(T, h), -70.0)}))
    T, h = np.array([7.3, 4.0, 15.9, 12.5]), np.array([47.0, 0.0, 329.0, 100.0])
    H = table.at(T, h)
    np.testing.assert_allclose(H[:, 2], heave(T, h) * np.exp(-1j * math.radians(40.0)), rtol=0, atol=1e-12)
    np.testing.assert_allclose(H[:, 3], np.radians(roll(T, h)) * np.exp(1j * math.radians(70.0)), rtol=0, atol=1e-12)
    wrapped = table.at([7.0] * 3, [-10.0, 350.0, 710.0])
    np.testing.assert_allclose(wrapped[1:], np.repeat(wrapped[:1], 2, axis=0), rtol=0, atol=1e-14)
    mid = table.at([6.0], [345.0])[0, 2]
    expected = 0.5 * (heave(6.0, 330.0) + heave(6.0, 0.0)) * np.exp(-1j * math.radians(40.0))
    assert abs(mid - expected) < 1e-12


def _symmetric_rao(T, h):
    """A port/starboard-symmetric ship: roll 3 |sin h| deg/m (lag 10), pitch 2 |cos h| deg/m,
    its sign in the phase, heave 1."""
    c, s = math.cos(math.radians(h)), math.sin(math.radians(h))
    return {"heave": (1.0, 0.0), "roll": (3.0 * abs(s), 10.0), "pitch": (2.0 * abs(c), -90.0 if c >= 0 else 90.0)}


def test_a_beam_sea_gives_roll_and_no_pitch_on_a_symmetric_table(tmp_path):
    """Ship heading 30 deg, waves travelling at 120 deg: relative heading 90 (from starboard):
    roll 3 deg/m at lag 10 and no pitch. Waves at -60 deg (relative -90, from port) are the
    mirror image: the table is mirrored, so the roll is reversed (y -> -y reverses roll) and
    heave unchanged. Tolerance 1e-12 (rad, m)."""
    table = RAOTable.from_csv(write_table(tmp_path / "sym.csv", [2.0, 30.0], [0, 45, 90, 135, 180],
                                          _symmetric_rao, symmetric=True))
    a, w = 1.2, 2 * math.pi / 9.0
    t = np.linspace(0.0, 18.0, 91)
    roll = math.radians(3.0) * a * np.cos(w * t - math.radians(10.0))

    def pose(b):
        comp = (np.array([a]), np.array([w]), np.array([w * w / G]), np.array([math.radians(b)]), np.array([0.0]))
        return ShipMotion(table, comp, heading=math.radians(30.0)).pose(t)
    starboard, port = pose(120.0), pose(-60.0)
    np.testing.assert_allclose(starboard[:, 3], roll, rtol=0, atol=1e-12)
    np.testing.assert_allclose(starboard[:, 4], 0.0, atol=1e-12)
    np.testing.assert_allclose(port[:, 3], -roll, rtol=0, atol=1e-12)
    np.testing.assert_allclose(port[:, 2], starboard[:, 2], rtol=0, atol=1e-12)


def test_velocity_and_acceleration_are_the_offsets_derivatives(tmp_path):
    """A fairlead at (25, -5, 4) m in six waves on a table with all six DOFs: its velocity and
    acceleration match central differences of its offset (step 1e-3 s; the difference's error
    h^2/6 |x'''| is below 1e-7 here, the tolerance 1e-6 in m/s and m/s^2)."""
    rao = lambda T, h: {d: (0.3 + 0.1 * i + 0.01 * T, 20.0 * i + h / 10) for i, d in enumerate(DOFS)}  # noqa: E731
    table = RAOTable.from_csv(write_table(tmp_path / "six.csv", [2.0, 8.0, 30.0], ALL_HEADINGS, rao))
    ship = ShipMotion(table, waves(6, seed=3), heading=-0.4, origin=(1.0, 2.0))
    t, dt = np.linspace(0.0, 30.0, 61), 1e-3
    r = [25.0, -5.0, 4.0]
    now, before, after = ship.point(r, t), ship.point(r, t - dt), ship.point(r, t + dt)
    np.testing.assert_allclose(now.velocity, (after.offset - before.offset) / (2 * dt), rtol=0, atol=1e-6)
    np.testing.assert_allclose(now.acceleration, (after.offset - 2 * now.offset + before.offset) / dt ** 2,
                               rtol=0, atol=1e-6)


@pytest.mark.parametrize("ramp_s", [0.0, 12.0])
def test_one_time_and_many_times_give_the_same_motion(tmp_path, ramp_s):
    """The motion at one time (the run's path: one evaluation for the three derivatives, kept
    for the next call at that time; compiled, ``motion_kernel``, where the compiled kernels run,
    and with ``MJTETHER_KERNELS=numpy`` the NumPy twin) equals the vectorised NumPy reference at
    the same times, with and
    without a build-up (12 s: half the times inside it), to 1e-12 of the largest value; and the
    ramped velocity and acceleration are still the offset's derivatives (central differences,
    as above)."""
    rao = lambda T, h: {d: (0.3 + 0.1 * i + 0.01 * T, 20.0 * i + h / 10) for i, d in enumerate(DOFS)}  # noqa: E731
    table = RAOTable.from_csv(write_table(tmp_path / "six.csv", [2.0, 8.0, 30.0], ALL_HEADINGS, rao))
    ship = ShipMotion(table, waves(6, seed=3), heading=-0.4, origin=(1.0, 2.0), ramp_s=ramp_s)
    t, r = np.linspace(0.0, 24.0, 49), [25.0, -5.0, 4.0]
    many = ship.point(r, t)
    for k, tk in enumerate(t):
        one = ship.point(r, float(tk))
        again = ship.point(r, float(tk))
        for a, b, c in zip(one, many, again):
            np.testing.assert_allclose(a, b[k], rtol=0, atol=1e-12 * np.abs(b).max())
            np.testing.assert_array_equal(a, c)
        np.testing.assert_allclose(ship.pose(float(tk)), ship.pose(t)[k], rtol=0, atol=1e-12)
    dt = 1e-3
    before, after = ship.point(r, t - dt), ship.point(r, t + dt)
    inside = (t > dt) & (t < ramp_s - dt) if ramp_s else t > dt
    np.testing.assert_allclose(many.velocity[inside], ((after.offset - before.offset) / (2 * dt))[inside],
                               rtol=0, atol=1e-6)
    np.testing.assert_allclose(many.acceleration[inside],
                               ((after.offset - 2 * many.offset + before.offset) / dt ** 2)[inside], rtol=0, atol=1e-6)


@pytest.mark.parametrize("kernels", ["numba", "numpy"])
def test_the_hull_attitude_is_mujocos_euler_quaternion_turned_by_the_heading(tmp_path, monkeypatch, kernels):
    """``hull``: the fairlead's offset is ``point``'s, and the attitude is what MuJoCo's own
    ``mju_euler2Quat(rpy, "xyz")`` and ``mju_mulQuat(heading, .)`` make of ``pose``'s roll, pitch
    and yaw (what the ship's mocap body took before), to 1e-15, with large angles so that every
    product's sign shows; on the compiled kernel and on the NumPy twin."""
    import mujoco
    monkeypatch.setenv("MJTETHER_KERNELS", kernels)
    rao = lambda T, h: {d: (0.2 + 0.05 * i + 12.0 * (i >= 3), 35.0 * i + h / 7) for i, d in enumerate(DOFS)}  # noqa: E731
    table = RAOTable.from_csv(write_table(tmp_path / "six.csv", [2.0, 8.0, 30.0], ALL_HEADINGS, rao))
    heading = 2.3
    ship = ShipMotion(table, waves(5, seed=7), heading=heading, origin=(3.0, -1.0))
    assert ship.compiled == (kernels == "numba")
    r = np.array([-25.0, 3.0, 6.0])
    for t in np.linspace(0.0, 30.0, 17):
        offset, attitude = ship.hull(r, float(t))
        np.testing.assert_array_equal(offset, ship.point(r, float(t)).offset)
        small, want = np.zeros(4), np.zeros(4)
        mujoco.mju_euler2Quat(small, ship.pose(float(t))[3:], "xyz")
        mujoco.mju_mulQuat(want, np.array([math.cos(heading / 2), 0.0, 0.0, math.sin(heading / 2)]), small)
        np.testing.assert_allclose(attitude, want, rtol=0, atol=1e-15)
    assert np.abs(ship.pose(np.linspace(0.0, 30.0, 17))[:, 3:]).max() > 0.3  # (angles large enough to matter)


def test_prescribed_heave():
    """z = A cos(2 pi t / T - phase): with phase 90 deg, 2 sin(2 pi t / 8); every point of the
    ship heaves alike; its velocity and acceleration are the closed-form derivatives.
    Tolerance 1e-12."""
    ship = PrescribedHeave(2.0, 8.0, phase_deg=90.0)
    t = np.linspace(0.0, 16.0, 81)
    w = 2 * math.pi / 8.0
    pose = ship.pose(t)
    np.testing.assert_allclose(pose[:, 2], 2.0 * np.sin(w * t), atol=1e-12)
    np.testing.assert_allclose(pose[:, [0, 1, 3, 4, 5]], 0.0, atol=1e-15)
    p = ship.point([30.0, 4.0, -2.0], t)
    np.testing.assert_allclose(p.offset, np.column_stack([0 * t, 0 * t, 2.0 * np.sin(w * t)]), atol=1e-12)
    np.testing.assert_allclose(p.velocity[:, 2], 2.0 * w * np.cos(w * t), atol=1e-12)
    np.testing.assert_allclose(p.acceleration[:, 2], -2.0 * w * w * np.sin(w * t), atol=1e-12)


@pytest.mark.parametrize("args, field", [((-1.0, 8.0), "amplitude"), ((1.0, 0.0), "period"),
                                         ((1.0, math.inf), "period"), ((1.0, 8.0, math.nan), "phase_deg")])
def test_prescribed_heave_refuses_bad_arguments(args, field):
    with pytest.raises(ValueError, match=field):
        PrescribedHeave(*args)


@pytest.mark.parametrize("bad, field", [(0, "components.amplitude"), (1, "components.omega"),
                                        (2, "components.k"), (4, "components.phase")])
def test_ship_motion_refuses_bad_waves(tmp_path, bad, field):
    """Bad wave arrays are refused naming the array; a period outside the table is refused
    naming it and the range, or (outside="zero") moves nothing: tolerance 1e-12 m."""
    table = RAOTable.from_csv(write_table(tmp_path / "h.csv", [2.0, 30.0], ALL_HEADINGS,
                                          lambda T, h: {"heave": (1.0, 0.0)}))
    comp = [np.array([1.0]), np.array([1.0]), np.array([0.1]), np.array([0.0]), np.array([0.0])]
    comp[bad] = np.array([math.nan if bad == 4 else -1.0])
    with pytest.raises(ValueError, match=field):
        ShipMotion(table, comp)
    long = [np.array([1.0]), np.array([2 * math.pi / 40.0]), np.array([0.01]), np.array([0.0]), np.array([0.0])]
    with pytest.raises(ValueError, match=r"period\[0\] = 40 s is outside the table's \[2, 30\] s"):
        ShipMotion(table, long)
    w = 2 * math.pi / 10.0
    both = [np.array([1.0, 2.0]), np.array([w, 2 * math.pi / 40.0]), np.array([w * w / G, 0.0025]),
            np.array([0.3, 0.0]), np.array([0.2, 0.0])]
    t = np.linspace(0.0, 40.0, 9)  # outside="zero": the 40 s wave moves nothing, the 10 s one heaves it
    z = ShipMotion(table, both, outside="zero").pose(t)[:, 2]
    np.testing.assert_allclose(z, elevation([c[:1] for c in both], 0.0, 0.0, t), rtol=0, atol=1e-12)


GOOD = ["# convention = orcaflex", ",".join(HEADER)] + [
    ",".join(["%g" % T, "%g" % h] + ["0.5", "0"] * 6) for T in (4, 8) for h in range(0, 360, 90)]


def _edit(line, column, text):
    fields = GOOD[line - 1].split(",")
    fields[column - 1] = text
    return {line: ",".join(fields)}


@pytest.mark.parametrize("change, expected", [
    (_edit(5, 3, "SECRETWORD"), r"line 5, column 3 \(surge_amp_m_per_m\): not a number"),
    (_edit(4, 7, "-0.1"), r"line 4, column 7 \(heave_amp_m_per_m\): an RAO amplitude must be >= 0"),
    (_edit(3, 1, "0"), r"line 3, column 1 \(period_s\): a wave period must be > 0 s"),
    (_edit(6, 2, "400"), r"line 6, column 2 \(heading_deg\): a heading must lie in \[0, 360\)"),
    (_edit(6, 2, "nan"), r"line 6, column 2 \(heading_deg\): not a finite number"),
    (_edit(2, 4, "surge_phase"), r"line 2, column 4: not a column of an RAO table"),
    (_edit(2, 4, "surge_amp_m_per_m"), r"line 2, column 4: the column surge_amp_m_per_m is named twice"),
    ({4: "4,90,0.5"}, r"line 4: 3 columns, the header names 14"),
    ({4: GOOD[2]}, r"line 4: repeats the period and heading of line 3"),
    ({4: ""}, r"period 4 s at heading 90 deg has no row"),
    ({1: "# a table with no convention"}, r"no '# convention = orcaflex'"),
    ({1: "# convention = SECRETWORD"}, r"line 1: 'convention' must be one of orcaflex, wamit"),
])
def test_bad_files_are_refused_with_the_line_named(tmp_path, change, expected):
    """Each fault is refused with the file, the line (and the column) named, and never the
    file's text (the planted word SECRETWORD never appears in the message)."""
    lines = [change.get(no, line) for no, line in enumerate(GOOD, start=1)]
    path = tmp_path / "bad.csv"
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(RAOError, match=expected) as err:
        RAOTable.from_csv(path)
    assert str(path) in str(err.value) and "secretword" not in str(err.value).lower()


def test_a_half_circle_table_must_say_it_is_symmetric(tmp_path):
    """Headings 0-180 without '# symmetric = true' leave half the circle uncovered, and a
    symmetric table of head and following seas only leaves the beam: both refused with advice; a
    missing file is named."""
    path = write_table(tmp_path / "half.csv", [2.0, 30.0], [0, 90, 180], lambda T, h: {"heave": (1.0, 0.0)})
    with pytest.raises(RAOError, match="symmetric = true"):
        RAOTable.from_csv(path)
    ends = write_table(tmp_path / "ends.csv", [2.0, 30.0], [0, 180], lambda T, h: {"heave": (1.0, 0.0)},
                       symmetric=True)
    with pytest.raises(RAOError, match="beam seas cannot be guessed"):
        RAOTable.from_csv(ends)
    with pytest.raises(ValueError, match="nothere.csv: no such file"):
        RAOTable.from_csv(tmp_path / "nothere.csv")


def test_the_example_barge_table_meets_the_long_wave_limit_and_its_closed_form():
    """examples/raos/box_barge_heave_pitch.csv (illustrative). In 25 s waves the barge rides
    like a raft (OrcaFlex's RAO quality checks): heave 1 at lag 0; pitch k per m (the wave
    slope) at lag -90 deg from astern, +90 from ahead, 0 in a beam sea. Tolerance 8 % and 5 deg:
    the dynamic amplification (omega/omega_n)^2 ~ 5 % and the Smith factor exp(-kT) ~ 2 % are
    what separates the barge from a raft at 25 s. At 6 s in a beam sea the heave matches the
    single-DOF closed form written here (to the file's 6 digits)."""
    table = RAOTable.from_csv(EXAMPLE)
    w = 2 * math.pi / 25.0
    k = w * w / G
    H = table.at([25.0] * 3, [0.0, 180.0, 90.0])
    np.testing.assert_allclose(np.abs(H[:, 2]), 1.0, rtol=0.08)
    assert np.all(np.abs(np.degrees(np.angle(H[:, 2]))) < 5.0)
    np.testing.assert_allclose(np.abs(H[:2, 4]), k, rtol=0.08)
    lag = -np.degrees(np.angle(H[:2, 4]))
    assert abs(lag[0] + 90.0) < 5.0 and abs(lag[1] - 90.0) < 5.0
    assert abs(H[2, 4]) == 0.0
    # heave at 6 s, beam sea: C e^{-kT} / (C - w^2 (m + A33) + i w B33), A33 from DNV-RP-H103
    rho, L, B, T = 1025.0, 60.0, 12.0, 3.0
    w6 = 2 * math.pi / 6.0
    m, a33, c = rho * L * B * T, 0.5 * 0.897 * rho * math.pi / 4 * B * B * L, rho * G * L * B
    x = c * math.exp(-w6 * w6 / G * T) / (c - w6 * w6 * (m + a33) + 1j * w6 * 0.2 * math.sqrt(c * (m + a33)))
    got = table.at([6.0], [90.0])[0, 2]
    assert abs(abs(got) / abs(x) - 1) < 1e-5 and abs(np.angle(got) - np.angle(x)) < 1e-5
