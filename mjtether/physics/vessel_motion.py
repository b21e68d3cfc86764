"""The ship's wave-frequency motion: displacement RAOs, and a prescribed heave (issue 43).

A ``ShipMotion`` or ``PrescribedHeave`` gives the 6-DOF displacement of the ship's reference
point and the offset, velocity and acceleration of a point fixed on the ship (a fairlead, a
winch), for the fairleads and winches to ride on (``scenario.controllers.Ship``). NumPy/SciPy;
the motion at one time, which a run asks for at every step, has a compiled twin
(``motion_kernel``, where the compiled kernels run: ``physics.compiled``).

Frames. World: z up, headings from +x towards +y (rad). Ship axes (OrcaFlex's vessel axes): x
forward (surge), y to port (sway), z up (heave), origin at the **reference point** (the RAO
origin, whose motion the RAOs give; it is also the phase origin). Roll, pitch and yaw are
right-handed rotations about the ship's x, y, z (roll: starboard down; pitch: bow down; yaw: bow
to port). The ship is at zero forward speed (on DP): no encounter-frequency shift.

Waves: regular components as ``mjtether.physics.waves`` gives them (not imported here):
amplitude a_i (m), omega_i (rad/s), k_i (rad/m), heading b_i (rad, the direction the wave
travels), phase e_i (rad), with eta(x, y, t) = sum a_i cos(k_i (x cos b_i + y sin b_i) -
omega_i t + e_i). At the reference point (x0, y0) that is a_i cos(omega_i t - psi_i) with
psi_i = k_i (x0 cos b_i + y0 sin b_i) + e_i; each component's heading relative to the ship is
b_i - (ship heading).

RAO conventions (the table file's header names one):

- ``"orcaflex"`` (OrcaFlex's default): the phase is a lag, in degrees, from the wave crest passing
  the phase origin to the maximum positive motion: x(t) = A a cos(omega t - phase) where
  eta = a cos(omega t) at the origin. The wave direction relative to the vessel is the direction
  of travel: 0 deg = waves from astern (travelling along +x), 90 deg = from starboard (travelling
  to port, +y). Rotations in deg per m of wave amplitude. Orcina, OrcaFlex help, "Vessel theory:
  RAOs and phases" and "Vessel types: RAOs"
  (https://www.orcina.com/webhelp/OrcaFlex/Content/html/Vesseltheory,RAOsandphases.htm); its
  "RAO quality checks" page lists the long-wave limits (heave 1 at lag 0; pitch |cos b| per unit
  wave slope at lag -90 deg for waves from astern) that the example table is tested against.
- ``"wamit"``: WAMIT User Manual v7.4, ch. 3, eqs. (3.1)-(3.2)
  (https://www.wamit.com/manualv7.4/wamit_v74manualch3.html): outputs are Re{(U + iV) e^{i omega t}}
  = W cos(omega t + delta) against the incident wave Re{A e^{i omega t}} at X = Y = 0, delta > 0 a
  lead; so x(t) = A a cos(omega t + phase). WAMIT's heading beta is the angle from +x to the
  direction the waves travel, positive towards +y (its theory chapter writes the incident wave
  as exp(-iK(x cos beta + y sin beta)); 0 = waves onto the stern, as Flexcom's "RAO conversions:
  WAMIT" page, https://flexcom.fea.solutions/theory_vessels_rao_wamit.html, also says), as
  here. Two things a WAMIT ``.4`` file holds
  differently and that must be converted before writing this table: rotations there are
  non-dimensional (xi L / A, rad): multiply by 180 / (pi L) for deg/m; and its phases are relative
  to the global origin, so the body must sit there (XBODY = 0) for them to be relative to the
  reference point.

Inside, an RAO is one complex number per DOF, H, with motion Re{H a e^{i(omega t - psi)}}
(m per m; rad per m for rotations): H = A e^{-i phase} (OrcaFlex lag), A e^{+i phase} (WAMIT lead).
The table is interpolated linearly in period and heading on H's real and imaginary parts, not on
amplitude and phase (no phase unwrapping; exact on a table linear in H, and on one linear in
amplitude at a common phase).

The rotations act about the reference point in their **linear, small-angle form**:
offset = d + theta x r. RAOs are a first-order (linear) theory and transfer to other points in
this form (OrcaFlex's vessel response report does the same); the offset stays a sum of
harmonics, so the velocity and acceleration given are its exact time derivatives. The error
against a rigid rotation is second order, |theta|^2 |r| / 2: 0.11 m at 5 deg and 30 m.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from scipy.interpolate import RegularGridInterpolator

from mjtether import _checks
from mjtether.physics import compiled

DOFS = ("surge", "sway", "heave", "roll", "pitch", "yaw")
"""The six DOFs, in the order of every array here (ship axes)."""

COLUMNS = ("period_s", "heading_deg") + tuple(
    c for d in DOFS for c in (f"{d}_amp_{'m' if d in DOFS[:3] else 'deg'}_per_m", f"{d}_phase_deg"))
"""The RAO table's columns (any order, each once): translations in m per m of wave amplitude,
rotations in deg per m, phases in deg."""

CONVENTIONS = {"orcaflex": -1.0, "wamit": +1.0}
"""Phase conventions read: H = A exp(sign * i * phase) (a lag in OrcaFlex, a lead in WAMIT)."""

MIRRORED = np.array([1.0, -1.0, 1.0, -1.0, 1.0, -1.0])
"""A port/starboard symmetric ship at relative heading -b: surge, heave, pitch as at +b; sway,
roll and yaw reversed (the reflection y -> -y; rotations are pseudovectors)."""


class RAOError(ValueError):
    """A displacement RAO table that cannot be read; the message names the file and the line."""


class PointMotion(NamedTuple):
    """A ship-fixed point's motion from its rest position, world axes."""
    offset: np.ndarray        # m
    velocity: np.ndarray      # m/s
    acceleration: np.ndarray  # m/s^2


class RAOTable:
    """Displacement RAOs on a grid of wave periods (s) and wave headings relative to the ship
    (deg, the direction of travel, from the ship's +x towards +y).

    ``H``: complex RAOs, shape (periods, headings, 6), in this module's form (see the module
    docstring; m/m and rad/m). ``symmetric``: headings lie in [0, 180] and the ship is port/
    starboard symmetric, so -b is the mirror of b (``MIRRORED``). A table that is not symmetric
    is read as periodic in heading and must not leave a gap of 180 deg or more.
    """

    def __init__(self, periods, headings_deg, H, symmetric: bool = False, name: str = "RAO table"):
        T = np.asarray(periods, dtype=float)
        h = np.asarray(headings_deg, dtype=float)
        H = np.asarray(H, dtype=complex)
        if T.ndim != 1 or T.size < 2 or np.any(~np.isfinite(T)) or np.any(T <= 0) or np.any(np.diff(T) <= 0):
            raise RAOError(f"{name}: periods must be at least two finite increasing periods > 0 s")
        if h.ndim != 1 or h.size < 1 or np.any(~np.isfinite(h)) or np.any(np.diff(h) <= 0):
            raise RAOError(f"{name}: headings must be finite increasing headings (deg)")
        if H.shape != (T.size, h.size, 6) or not np.all(np.isfinite(H)):
            raise RAOError(f"{name}: the RAOs must be finite, shape ({T.size}, {h.size}, 6); got {H.shape}")
        lo, hi = (0.0, 180.0) if symmetric else (0.0, 360.0)
        if h[0] < lo or h[-1] > hi or (not symmetric and h[-1] >= 360.0):
            raise RAOError(f"{name}: headings must lie in [0, 180] deg for a symmetric table, in [0, 360) "
                           "otherwise")
        self.periods, self.headings_deg, self.H, self.symmetric, self.name = T, h, H, bool(symmetric), name
        if symmetric:   # the starboard half: 360 - b for 0 < b < 180, sway, roll, yaw reversed
            inner = (h > 0.0) & (h < 180.0)
            h = np.concatenate([h, 360.0 - h[inner][::-1]])
            H = np.concatenate([H, H[:, inner][:, ::-1] * MIRRORED], axis=1)
        gap = np.max(np.diff(np.append(h, h[0] + 360.0)))
        if gap >= 180.0:
            advice = ("add headings between 0 and 180 deg: beam seas cannot be guessed from head and "
                      "following seas" if symmetric else "for a port/starboard symmetric ship with headings "
                      "0-180 deg, say '# symmetric = true'")
            raise RAOError(f"{name}: the headings leave a gap of {gap:g} deg around the circle; it must be under "
                           f"180 deg ({advice})")
        h_wrap = np.concatenate([h, [h[0] + 360.0]])  # periodic: the first heading again, one turn on
        H_wrap = np.concatenate([H, H[:, :1]], axis=1)
        self._interp = RegularGridInterpolator((T, h_wrap), H_wrap, method="linear")
        self._h0 = h[0]

    @classmethod
    def from_csv(cls, path) -> "RAOTable":
        """Read a table file (comma-separated; see examples/raos/box_barge_heave_pitch.csv).

        Lines starting with ``#`` are comments; two of them are settings:
        ``# convention = orcaflex`` or ``wamit`` (required) and ``# symmetric = true`` or
        ``false`` (default false). The first other line names the columns (``COLUMNS``, any
        order); each later line is one (period, heading) of a full grid. Errors name the file,
        the line and the column, never the file's text.
        """
        name = str(path)
        text = _checks.read_text(name, path, kind="displacement RAO table (.csv)")
        settings, header, rows = _parse(name, text)
        convention = settings.get("convention")
        if convention is None:
            raise RAOError(f"{name}: no '# convention = orcaflex' (or wamit) line: the phase convention must "
                           "be stated")
        symmetric = settings.get("symmetric", "false")
        T, h, A, phase = _grid(name, header, rows, symmetric == "true")
        A = A * np.where(np.arange(6) < 3, 1.0, math.pi / 180.0)  # deg/m -> rad/m
        H = A * np.exp(1j * CONVENTIONS[convention] * np.radians(phase))
        return cls(T, h, H, symmetric=symmetric == "true", name=name)

    def at(self, periods, rel_headings_deg, outside: str = "error") -> np.ndarray:
        """Complex RAOs (n, 6) at wave periods (s) and headings relative to the ship (deg, any
        value: wrapped). A period outside the table's range is refused (``outside="error"``),
        given RAO 0 (``"zero"``: the waves too short or too long for the table move nothing) or,
        with ``"short_zero"``, RAO 0 below the shortest period only (a ship does not follow waves
        much shorter than itself; a long wave it does follow, so a period above the table's is
        refused)."""
        if outside not in OUTSIDE:
            raise ValueError(f"outside = {outside!r}: must be one of {', '.join(OUTSIDE)}")
        T = np.atleast_1d(np.asarray(periods, dtype=float))
        b = np.atleast_1d(np.asarray(rel_headings_deg, dtype=float))
        out = (T < self.periods[0]) | (T > self.periods[-1])
        if outside == "short_zero":
            out = T < self.periods[0]
            if np.any(T > self.periods[-1]):
                i = int(np.flatnonzero(T > self.periods[-1])[0])
                raise ValueError(f"{self.name}: wave period[{i}] = {T[i]:g} s is longer than the table's longest, "
                                 f"{self.periods[-1]:g} s")
        if np.any(out) and outside != "error":
            H = np.zeros((T.size, 6), dtype=complex)
            H[~out] = self.at(T[~out], b[~out])
            return H
        if np.any(out):
            i = int(np.flatnonzero(out)[0])
            raise ValueError(f"{self.name}: wave period[{i}] = {T[i]:g} s is outside the table's "
                             f"[{self.periods[0]:g}, {self.periods[-1]:g}] s")
        b = self._h0 + np.mod(b - self._h0, 360.0)
        return self._interp(np.column_stack([T, b]))


def _parse(name: str, text: str):
    """(settings, (line, header fields), [(line, fields)]) of a table file."""
    settings, header, rows = {}, None, []
    for no, raw in enumerate(text.splitlines(), start=1):
        line = raw.strip()
        if not line:
            continue
        if line.startswith("#"):
            key, eq, value = line[1:].partition("=")
            key, value = key.strip().lower(), value.strip().lower()
            if eq and key in ("convention", "symmetric"):
                allowed = tuple(CONVENTIONS) if key == "convention" else ("true", "false")
                if value not in allowed:
                    raise RAOError(f"{name}: line {no}: '{key}' must be one of {', '.join(allowed)}")
                if key in settings:
                    raise RAOError(f"{name}: line {no}: '{key}' is set twice")
                settings[key] = value
            continue
        fields = [f.strip() for f in line.split(",")]
        if header is None:
            header = (no, fields)
        else:
            rows.append((no, fields))
    if header is None or not rows:
        raise RAOError(f"{name}: no {'column header' if header is None else 'rows of RAOs'} found")
    return settings, header, rows


def _grid(name: str, header, rows, symmetric: bool):
    """The table's periods (s), headings (deg), amplitudes (n_T, n_h, 6) and phases (deg)."""
    hno, names = header
    for c, col in enumerate(names, start=1):
        if col not in COLUMNS:
            raise RAOError(f"{name}: line {hno}, column {c}: not a column of an RAO table; the columns are "
                           f"{', '.join(COLUMNS)}")
        if names.index(col) != c - 1:
            raise RAOError(f"{name}: line {hno}, column {c}: the column {col} is named twice")
    missing = [col for col in COLUMNS if col not in names]
    if missing:
        raise RAOError(f"{name}: line {hno}: the column header lacks {', '.join(missing)}")
    where = [names.index(col) for col in COLUMNS]
    data = np.empty((len(rows), len(COLUMNS)))
    for r, (no, fields) in enumerate(rows):
        if len(fields) != len(names):
            raise RAOError(f"{name}: line {no}: {len(fields)} columns, the header names {len(names)}")
        for j, k in enumerate(where):
            data[r, j] = _field(name, no, k + 1, COLUMNS[j], fields[k], symmetric)
    T, h = np.unique(data[:, 0]), np.unique(data[:, 1])
    slot = np.full((T.size, h.size), -1)
    for r, (no, _) in enumerate(rows):
        i, j = np.searchsorted(T, data[r, 0]), np.searchsorted(h, data[r, 1])
        if slot[i, j] >= 0:
            raise RAOError(f"{name}: line {no}: repeats the period and heading of line {rows[slot[i, j]][0]}")
        slot[i, j] = r
    if np.any(slot < 0):
        i, j = np.argwhere(slot < 0)[0]
        raise RAOError(f"{name}: {T.size} periods x {h.size} headings make {slot.size} grid points and "
                       f"{len(rows)} rows are given: period {T[i]:g} s at heading {h[j]:g} deg has no row")
    if T.size < 2:
        raise RAOError(f"{name}: the table has one period; it needs at least two to interpolate between")
    grid = data[slot]                                     # (n_T, n_h, columns)
    return T, h, grid[..., 2::2], grid[..., 3::2]


def _field(name: str, no: int, col: int, what: str, text: str, symmetric: bool) -> float:
    """One table entry, checked: a finite number; periods > 0; amplitudes >= 0; headings in
    [0, 180] (symmetric) or [0, 360)."""
    def bad(why: str):
        return RAOError(f"{name}: line {no}, column {col} ({what}): {why}")
    try:
        x = float(text)
    except ValueError:
        raise bad("not a number") from None
    if not math.isfinite(x):
        raise bad("not a finite number")
    if what == "period_s" and x <= 0.0:
        raise bad("a wave period must be > 0 s")
    if "_amp_" in what and x < 0.0:
        raise bad("an RAO amplitude must be >= 0 (the sign goes in the phase)")
    if what == "heading_deg" and not (0.0 <= x <= 180.0 if symmetric else 0.0 <= x < 360.0):
        raise bad("a heading must lie in [0, 180] deg in a symmetric table" if symmetric else
                  "a heading must lie in [0, 360) deg (or say '# symmetric = true' for 0-180)")
    return x


class _Harmonic:
    """Motion as a sum of harmonics: q(t) = Re{sum_i c_i e^{i omega_i t}}, q the six DOFs in
    ship axes (m, rad), c (n, 6) complex, omega (n,) rad/s; ``heading``: the ship's x axis in the
    world, from +x towards +y (rad)."""

    def __init__(self, omega: np.ndarray, c: np.ndarray, heading: float, ramp_s: float = 0.0):
        self._omega, self._c = omega, c
        ch, sh = math.cos(heading), math.sin(heading)
        self._R = np.array([[ch, -sh, 0.0], [sh, ch, 0.0], [0.0, 0.0, 1.0]])  # ship axes -> world
        self.ramp_s = _checks.non_negative("ramp_s", ramp_s, "s")
        self.compiled = compiled.backend() == "numba"  # (``motion_kernel`` at one time)
        self._re, self._im = np.ascontiguousarray(c.real), np.ascontiguousarray(c.imag)
        self._hq = np.array([math.cos(heading / 2), math.sin(heading / 2)])  # the heading's quaternion (w, z)
        self._last = (math.nan, None, None, None, None)  # (t, r, q (3, 6), r's motion (3, 3), hull (4,)): _at

    def _at(self, t: float, r: np.ndarray = None) -> tuple[np.ndarray, np.ndarray | None, np.ndarray]:
        """(q and its first two time derivatives (3, 6), the offset, velocity and acceleration
        (3, 3) of the point ``r`` (m, ship axes; None: not asked), and the hull's attitude (4,),
        ``hull``'s) at one time ``t`` (s), from one evaluation of each harmonic, kept for the next
        call at the same ``t`` and ``r`` (the ship, the winch's compensator and the hull's pose
        all read the motion of one step). Compiled (``motion_kernel``) where ``compiled``, else
        NumPy."""
        last = self._last
        if t == last[0] and (r is None or r is last[1] or (last[1] is not None and np.array_equal(r, last[1]))):
            return last[2], (None if r is None else last[3]), last[4]
        if self.compiled:
            q, p, quat = np.empty((3, 6)), np.empty((3, 3)), np.empty(4)
            motion_kernel(t, self._omega, self._re, self._im, self.ramp_s, _ORIGIN if r is None else r, self._R,
                          self._hq, q, p, quat)
        else:
            e = np.exp(1j * t * self._omega)
            iw = 1j * self._omega
            q = np.array([(e @ self._c).real, ((e * iw) @ self._c).real, ((e * iw * iw) @ self._c).real])
            if self.ramp_s > 0.0 and t < self.ramp_s:  # (the build-up, by Leibniz's rule)
                from .waves import build_up
                a, da, dda = (float(v) for v in build_up(t, self.ramp_s))
                q = np.array([a * q[0], a * q[1] + da * q[0], a * q[2] + 2.0 * da * q[1] + dda * q[0]])
            p = None if r is None else self._moved(q, r)
            quat = np.empty(4)
            _attitude(self._hq, *q[0, 3:], quat)
        self._last = (t, r, q, p, quat)
        return q, (None if r is None else p), quat

    def _q(self, t, order: int) -> np.ndarray:
        """The ``order``-th time derivative of q at times ``t`` (s): (6,) or (len(t), 6); with a
        build-up (``ramp_s`` > 0, ``waves.build_up``) of the ramped motion r(t) q(t), by Leibniz's
        rule."""
        if np.ndim(t) == 0 and order <= 2:
            return self._at(float(t))[0][order].copy()
        t = np.asarray(t, dtype=float)
        tt = np.atleast_1d(t)
        e = np.exp(1j * np.multiply.outer(tt, self._omega))      # (m, n)
        if self.ramp_s > 0.0 and np.any(tt < self.ramp_s):
            from .waves import build_up
            r = build_up(tt, self.ramp_s)
            q = sum(math.comb(order, j) * r[j][:, None] * ((e * (1j * self._omega) ** (order - j)) @ self._c).real
                    for j in range(order + 1))
        else:
            q = ((e * (1j * self._omega) ** order) @ self._c).real
        return q[0] if t.ndim == 0 else q

    def pose(self, t) -> np.ndarray:
        """The reference point's displacement at time(s) ``t`` (s): x, y, z (m, world axes) and
        roll, pitch, yaw (rad, about the ship's axes); shape (6,) or (len(t), 6)."""
        if np.ndim(t) == 0:  # (one time: a run's step)
            q, out = self._at(float(t))[0][0], np.empty(6)
            out[:3], out[3:] = self._R @ q[:3], q[3:]
            return out
        q = self._q(t, 0)
        return np.concatenate([q[..., :3] @ self._R.T, q[..., 3:]], axis=-1)

    def point(self, r_body, t) -> PointMotion:
        """Offset (m), velocity (m/s), acceleration (m/s^2), world axes, of the point ``r_body``
        (m, ship axes from the reference point) at time(s) ``t`` (s): d + theta x r, the
        rotations linear about the reference point (module docstring)."""
        last = self._last[1]
        r = last if r_body is last else _checks.vector3("r_body", r_body)  # (a run asks for one point)
        if np.ndim(t) == 0:  # one time (a run's step): the three derivatives at once
            return PointMotion(*self._at(float(t), r)[1].copy())
        return PointMotion(*(self._moved(self._q(t, n), r) for n in range(3)))

    def hull(self, r_body, t: float) -> tuple[np.ndarray, np.ndarray]:
        """(offset (3,) m, world axes, of the point ``r_body`` (m, ship axes from the reference
        point), the hull's attitude (4,): the unit quaternion w, x, y, z from the world to the
        ship's axes, the heading turned by roll, pitch and yaw in that order about the turning
        axes, as MuJoCo's ``mju_euler2Quat(.., "xyz")`` then ``mju_mulQuat(heading, ..)``) at one
        time ``t`` (s), from the one evaluation of the step that ``point`` also reads: what a
        ship's mocap body takes (``scenario.controllers.Ship.update``). New arrays."""
        last = self._last[1]
        r = last if r_body is last else _checks.vector3("r_body", r_body)
        _, p, quat = self._at(_checks.finite("t", t), r)
        return p[0].copy(), quat.copy()

    def _moved(self, q: np.ndarray, r: np.ndarray) -> np.ndarray:
        a, b = q[..., 3:], r  # (theta x r, written out: np.cross is slow on one vector)
        cross = np.stack([a[..., 1] * b[2] - a[..., 2] * b[1], a[..., 2] * b[0] - a[..., 0] * b[2],
                          a[..., 0] * b[1] - a[..., 1] * b[0]], axis=-1)
        return (q[..., :3] + cross) @ self._R.T


_ORIGIN = np.zeros(3)


def _attitude(hq, roll, pitch, yaw, out):
    """Into ``out`` (4,) the hull's attitude (``_Harmonic.hull``): the heading's quaternion ``hq``
    (cos, sin of half the heading) times those of ``roll``, ``pitch`` and ``yaw`` (rad) about x,
    then the new y, then the new z (the NumPy twin's; ``motion_kernel`` runs it compiled)."""
    cr, sr = math.cos(0.5 * roll), math.sin(0.5 * roll)
    cp, sp = math.cos(0.5 * pitch), math.sin(0.5 * pitch)
    cy, sy = math.cos(0.5 * yaw), math.sin(0.5 * yaw)
    w, x, y, z = cr * cp, sr * cp, cr * sp, sr * sp  # q_x(roll) q_y(pitch)
    w, x, y, z = w * cy - z * sy, x * cy + y * sy, y * cy - x * sy, w * sy + z * cy  # times q_z(yaw)
    hw, hz = hq[0], hq[1]
    out[0], out[1], out[2], out[3] = hw * w - hz * z, hw * x - hz * y, hw * y + hz * x, hw * z + hz * w


_attitude_kernel = compiled.jit(fma=True)(_attitude)


@compiled.jit(fma=True)
def motion_kernel(t, omega, c_re, c_im, ramp_s, r, R, hq, q, p, quat):
    """``_Harmonic._at`` compiled: into ``q`` (3, 6) the six DOFs (ship axes, m and rad) and
    their first two time derivatives at time ``t`` (s), Re{sum_i c_i (i omega_i)^n
    e^{i omega_i t}} (``c_re``, ``c_im``: c's parts (n, 6); ``omega`` (n,), rad/s), times the
    build-up of ``ramp_s`` (s; ``waves.build_up``) by Leibniz's rule; into ``p`` (3, 3) the
    offset, velocity and acceleration (world, m, m/s, m/s^2) of the point ``r`` (m, ship axes):
    (d + theta x r) turned by ``R`` (ship axes to world), as ``_moved``; into ``quat`` (4,) the
    hull's attitude from the heading's ``hq`` (``_attitude``)."""
    for n in range(3):
        for j in range(6):
            q[n, j] = 0.0
    for i in range(omega.shape[0]):
        w = omega[i]
        co, si = math.cos(w * t), math.sin(w * t)
        for j in range(6):  # e c = (co + i si)(cr + i ci); i w e c; -w^2 e c
            re = co * c_re[i, j] - si * c_im[i, j]
            im = si * c_re[i, j] + co * c_im[i, j]
            q[0, j] += re
            q[1, j] -= w * im
            q[2, j] -= w * w * re
    if ramp_s > 0.0 and t < ramp_s:
        a = da = dda = 0.0
        if t > 0.0:
            v = math.pi / ramp_s
            a, da, dda = 0.5 * (1.0 - math.cos(v * t)), 0.5 * v * math.sin(v * t), 0.5 * v * v * math.cos(v * t)
        for j in range(6):
            q0, q1 = q[0, j], q[1, j]
            q[0, j] = a * q0
            q[1, j] = a * q1 + da * q0
            q[2, j] = a * q[2, j] + 2.0 * da * q1 + dda * q0
    for n in range(3):
        x = q[n, 0] + (q[n, 4] * r[2] - q[n, 5] * r[1])
        y = q[n, 1] + (q[n, 5] * r[0] - q[n, 3] * r[2])
        z = q[n, 2] + (q[n, 3] * r[1] - q[n, 4] * r[0])
        for k in range(3):
            p[n, k] = R[k, 0] * x + R[k, 1] * y + R[k, 2] * z
    _attitude_kernel(hq, q[0, 3], q[0, 4], q[0, 5], quat)


OUTSIDE = ("error", "zero", "short_zero")
"""What ``RAOTable.at`` does with a wave period outside the table's (see it)."""


class ShipMotion(_Harmonic):
    """The ship's first-order motion in waves from its displacement RAOs.

    ``raos``: an ``RAOTable``; ``components``: the waves, an object with arrays ``amplitude`` (m),
    ``omega`` (rad/s), ``k`` (rad/m), ``heading`` (rad) and ``phase`` (rad), or a sequence of
    those five arrays in that order; ``heading``: the ship's heading (rad, world, its +x from +x
    towards +y); ``origin``: the reference point's rest position in the world (x, y, m), where
    the waves' phases are taken; ``outside``: a wave period outside the table's range is refused
    (``"error"``) or moves nothing (``"zero"``; say so where a spectrum's tail passes the table),
    or only one shorter than the table's shortest moves nothing (``"short_zero"``); ``ramp_s``:
    the sea's build-up (s, ``waves.build_up``: the motion times r(t); 0: none).
    """

    def __init__(self, raos: RAOTable, components, heading: float = 0.0, origin=(0.0, 0.0),
                 outside: str = "error", ramp_s: float = 0.0):
        a, omega, k, b, e = _components(components)
        heading = _checks.finite("heading", heading)
        x0, y0 = _checks.numbers("origin", origin, count=(2,), unit="m")
        H = raos.at(2.0 * math.pi / omega, np.degrees(b - heading), outside)
        psi = k * (x0 * np.cos(b) + y0 * np.sin(b)) + e
        super().__init__(omega, (a * np.exp(-1j * psi))[:, None] * H, heading, ramp_s)


class PrescribedHeave(_Harmonic):
    """A prescribed heave for quick studies: z(t) = amplitude cos(2 pi t / period - phase), no
    other DOF (phase in deg, a lag as OrcaFlex's: ``phase_deg = 90`` starts at z = 0 rising)."""

    def __init__(self, amplitude: float, period: float, phase_deg: float = 0.0):
        A = _checks.non_negative("amplitude", amplitude, "m")
        T = _checks.positive("period", period, "s")
        phase = math.radians(_checks.finite("phase_deg", phase_deg))
        c = np.zeros((1, 6), dtype=complex)
        c[0, 2] = A * np.exp(-1j * phase)
        super().__init__(np.array([2.0 * math.pi / T]), c, 0.0)


def _components(components) -> tuple[np.ndarray, ...]:
    """The waves' (amplitude, omega, k, heading, phase) as checked float arrays of one length."""
    names = ("amplitude", "omega", "k", "heading", "phase")
    if all(hasattr(components, n) for n in names):
        arrays = [getattr(components, n) for n in names]
    elif isinstance(components, (list, tuple)) and len(components) == 5:
        arrays = list(components)
    else:
        raise ValueError("components must have arrays amplitude, omega, k, heading, phase (or be those "
                         "five arrays in that order)")
    out = []
    for n, v in zip(names, arrays):
        x = np.atleast_1d(np.asarray(v, dtype=float))
        if x.ndim != 1 or x.shape != np.atleast_1d(np.asarray(arrays[0], dtype=float)).shape:
            raise ValueError(f"components.{n} must be a 1-D array as long as components.amplitude")
        if not np.all(np.isfinite(x)):
            raise ValueError(f"components.{n} must hold finite numbers only")
        out.append(x)
    if np.any(out[0] < 0):
        raise ValueError("components.amplitude must be >= 0 m")
    if np.any(out[1] <= 0):
        raise ValueError("components.omega must be > 0 rad/s (a wave period 2 pi / omega)")
    if np.any(out[2] < 0):
        raise ValueError("components.k must be >= 0 rad/m")
    return tuple(out)
