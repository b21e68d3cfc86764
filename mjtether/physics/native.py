"""Native passive forces: a compiled ``mjcb_passive`` that MuJoCo calls itself, on any thread.

MuJoCo asks one global passive-force callback for the forces of every ``mjData`` it steps:
``mj_step`` on the main thread, and ``mujoco.rollout``'s worker threads, which never enter
Python. A Python callback is skipped there (a cable in vacuum); this module's callback is a
numba ``@cfunc`` that MuJoCo calls directly, so every ``mjData`` of a registered model gets its
tether, rigid-body and vehicle loads, a rollout's too, without the GIL.

**Force blocks.** ``Simulation`` registers a *force block* under its model's address
(``register``): for each provider (a tether, a rigid body, a vehicle) a table of its integer
and real parameters and the addresses of its arrays (``Block``). The simulation keeps the
arrays alive and updates them in place as the cable pays out (rest lengths, inertia, first
deployed node). Per-``mjData`` state (the seabed stick points) lives in ``data.userdata``, so
threads never share it. ``register_copy`` registers a copy of the model (``mujoco.rollout``
with one model per rollout) to the same block. The callback looks the model up in a table of
at most ``CAPACITY`` models and leaves any other model alone.

**What it reads.** The callback reads ``mjData``'s and ``mjModel``'s arrays through their
pointers in the C structs; their offsets are found once per process by matching the
addresses of the NumPy views that MuJoCo's Python bindings give (``_offsets``), so they follow
the installed MuJoCo. Rigid bodies use MuJoCo's own ``mj_objectVelocity`` and ``mj_applyFT``.

**The loads** are ``compiled``'s kernels, the functions the Python providers call with the
compiled kernels; ``tests/physics/test_native.py`` checks them against the NumPy reference kernels
(1e-12) and a rollout against ``Simulation.step`` (1e-10). In waves, tethers and rigid bodies evaluate the
sea (``waves.state_kernel``) at the ``mjData``'s time where the Python path does (``test_native_waves.py``).

**Writes to the model.** The normal added mass (``added_mass="normal"``) and a vehicle's
added mass turn tendons in ``model.wrap_prm`` at every step, from the state of the ``mjData``
being stepped: two ``mjData`` stepping one such model (threads, or turns) would each get the
other's mass matrix. The block of such a model therefore has an *owner*, the simulation's own
``mjData``: any other gets NaN forces (its states come back NaN, not silently wrong).
``rollouts.rollout`` gives each rollout its own registered copy of such a model, which any one
``mjData`` at a time may step.

Units SI, world frame, as in ``compiled``.
"""

from __future__ import annotations

import ctypes
import glob
import os
import warnings

import mujoco
import numpy as np

from mjtether.physics import actuation, compiled, jitcache
from mjtether.physics.hydro import GAUSS_POINTS
from mjtether.physics.waves import state_kernel

numba = compiled.numba
if numba is not None:
    from numba import types
    from numba.extending import intrinsic

CAPACITY = 1024
"""Models registered at once, at most (copies included)."""

TETHER, BODY, VEHICLE = 0, 1, 2
SLOTS = 32
"""Rows of a provider's table: (address, length) of each of its arrays."""

# the mjData / mjModel arrays the callback reads, in the order of offsets()
_DATA_FIELDS = ("qvel", "qacc", "qfrc_passive", "flexvert_xpos", "userdata", "xpos", "xmat", "act", "ctrl", "act_dot")
_MODEL_FIELDS = ("wrap_prm", "actuator_dynprm", "actuator_actadr", "actuator_actnum")
(QVEL, QACC, QFRC, FLEXVERT, USERDATA, XPOS, XMAT, ACT, CTRL, ACT_DOT, WRAP_PRM, DYNPRM, ACTADR, ACTNUM,
 TIMESTEP, TIME) = range(16)
# (TIMESTEP, TIME: the words of mjModel's opt.timestep and mjData's time themselves, numbers, not pointers)


def available() -> bool:
    """Whether the native callback can run here: numba imports, the kernels are numba's, and
    this MuJoCo's structs could be read (else a warning says why, once, and the loads run in
    Python, where MuJoCo's rollout threads cannot call them). Compiles two small probe models
    the first time: call it where compiling is safe (``dispatch.suspended``)."""
    if numba is None or compiled.backend() != "numba" or "unavailable" in _state:
        return False
    try:
        _link()
    except RuntimeError as exc:
        _state["unavailable"] = str(exc)
        warnings.warn(f"{exc}; the hydrodynamic loads run in Python instead (MJTETHER_KERNELS=numpy to silence "
                      "this), and rollouts with them are refused", RuntimeWarning, stacklevel=2)
        return False
    return True


# --------------------------------------------------------------------------- struct offsets


def _scan(obj, fields: tuple[str, ...]) -> list[int]:
    """Offsets (in 8-byte words) of the pointer fields ``fields`` in the C struct behind ``obj``
    (an MjModel or MjData): where the struct holds the address of the field's NumPy view. Reads
    the struct 512 bytes at a time, no further than the last field found."""
    want = {f: getattr(obj, f).ctypes.data for f in fields}
    found: dict[str, int] = {}
    chunk, start = 64, 0
    while len(found) < len(want):
        if start > 1 << 18:
            raise RuntimeError(f"mjtether.physics.native: the fields {sorted(set(want) - set(found))} were not found in "
                               f"{type(obj).__name__}; this MuJoCo is not supported by the native callback")
        words = np.frombuffer(ctypes.string_at(obj._address + 8 * start, 8 * chunk), dtype=np.uint64)
        for f, addr in want.items():
            if f not in found:
                hits = np.flatnonzero(words == np.uint64(addr))
                if len(hits):
                    found[f] = start + int(hits[0])
        start += chunk
    return [found[f] for f in fields]


def _offsets() -> np.ndarray:
    """Word offsets of ``_DATA_FIELDS`` in mjData, ``_MODEL_FIELDS`` in mjModel and of mjModel's
    ``opt.timestep``, each checked on two models of different sizes (every field non-empty)."""
    xml = """<mujoco><option gravity="0 0 -9.81"/><worldbody>{}</worldbody>
      <actuator><general joint="j0" dyntype="integrator"/></actuator>
      <tendon><fixed><joint joint="j0" coef="1"/></fixed></tendon>
      <deformable><flex name="f" dim="1" body="{}" vertex="0 0 0 0 0 0" element="0 1"/></deformable></mujoco>"""
    out = []
    for n in (2, 3):
        bodies = "".join(f'<body name="b{i}" pos="{i} 0 0"><joint name="j{i}" type="slide"/>'
                         f'<geom size=".1" mass="1"/></body>' for i in range(n))
        spec = mujoco.MjSpec.from_string(xml.format(bodies, " ".join(f"b{i}" for i in range(2))))
        spec.nuserdata = 3
        with warnings.catch_warnings():  # (a flex of two vertices, for its vertex array only)
            warnings.simplefilter("ignore")
            m = spec.compile()
        d = mujoco.MjData(m)
        m.opt.timestep = 0.00123456789 * n  # values to find
        d.time = 1234.0987654321 * n
        out.append(_scan(d, _DATA_FIELDS) + _scan(m, _MODEL_FIELDS) + [_find_double(m, m.opt.timestep),
                                                                        _find_double(d, d.time, 1 << 20)])
    if out[0] != out[1]:
        raise RuntimeError("mjtether.physics.native: MuJoCo's struct layout could not be read consistently")
    return np.array(out[0], dtype=np.int64)


def _find_double(obj, value: float, most: int = 4096) -> int:
    """Offset (in 8-byte words) of the float64 ``value`` in the C struct behind ``obj``: where an
    embedded number (``opt.timestep``, mjData's ``time``) lives. Read 4 KiB at a time, up to the
    first 4 KiB that holds it (and no further than ``most`` bytes); exactly one match there."""
    for start in range(0, most, 4096):
        hits = np.flatnonzero(np.frombuffer(ctypes.string_at(obj._address + start, 4096), dtype=np.float64) == value)
        if len(hits) == 1:
            return start // 8 + int(hits[0])
        if len(hits) > 1:
            break
    raise RuntimeError(f"mjtether.physics.native: {type(obj).__name__}'s time (step) was not found; this MuJoCo is not "
                       "supported by the native callback")


def _mujoco_library() -> str:
    """The path of the MuJoCo shared library the Python bindings load."""
    folder = os.path.dirname(mujoco.__file__)
    for pattern in ("libmujoco.so*", "libmujoco*.dylib", "mujoco.dll"):
        hits = sorted(glob.glob(os.path.join(folder, pattern)))
        if hits:
            return hits[0]
    raise RuntimeError(f"mjtether.physics.native: MuJoCo's library was not found in {folder}")


# --------------------------------------------------------------------------- the kernels

if numba is not None:
    def _cast(target):
        """An intrinsic: the integer address ``addr`` as a pointer of numba type ``target``."""
        @intrinsic
        def cast(typingctx, addr):
            def codegen(context, builder, signature, args):
                return builder.inttoptr(args[0], context.get_value_type(target))
            return target(types.int64), codegen
        return cast

    _f64 = _cast(types.CPointer(types.float64))  # float64 pointer
    _i64 = _cast(types.CPointer(types.int64))  # int64 pointer
    _i32 = _cast(types.CPointer(types.int32))  # int32 pointer (mjModel's integer arrays)
    _void = _cast(types.voidptr)  # void pointer, for MuJoCo's functions

    @intrinsic
    def _address(typingctx, ptr):
        """The integer address of the void pointer ``ptr``."""
        sig = types.int64(types.voidptr)

        def codegen(context, builder, signature, args):
            return builder.ptrtoint(args[0], context.get_value_type(types.int64))
        return sig, codegen

    # MuJoCo's functions and this process's registry, by symbol name (resolved when the compiled
    # code is loaded, so that it can be cached on disk: see _link)
    _object_velocity = types.ExternalFunction("mj_objectVelocity", types.void(
        types.voidptr, types.voidptr, types.int32, types.int32, types.voidptr, types.int32))
    _apply_ft = types.ExternalFunction("mj_applyFT", types.void(
        types.voidptr, types.voidptr, types.voidptr, types.voidptr, types.voidptr, types.int32, types.voidptr))
    _registry_address = types.ExternalFunction("mjtether_native_registry", types.int64())
    _OBJ_BODY = int(mujoco.mjtObj.mjOBJ_BODY)

_jit = compiled.jit


@_jit
def _field(base, offs, which):
    """The address held in pointer field ``which`` (``_OFFS``) of the struct at ``base``."""
    return numba.carray(_i64(base + 8 * offs[which]), (1,))[0]


@_jit
def _vec(table, slot):
    """Array ``slot`` of a provider's table, 1-D float64."""
    return numba.carray(_f64(table[slot, 0]), (table[slot, 1],))


@_jit
def _ints(table, slot):
    return numba.carray(_i64(table[slot, 0]), (table[slot, 1],))


# A tether's table (cable.loads.CableLoads.native_table): its arrays by slot
T_INT, T_REAL, T_STATE, T_REST, T_INERTIA, T_DIAMETER, T_CDN, T_CDT, T_AREA, T_CDAF, T_BEND, T_DP, T_CP, \
    T_NODE_WET, T_NODE_VOLUME, T_NODE_CDA, T_WAVES, T_WAVE_REAL, T_ADDED, T_AXIAL, T_NODE_ADDED = range(21)
# T_INT: n, flex vertex address, first dof, seabed mode (0 none, 1 uniform weight, 2 per node,
# 3 buoyant: none), stick-point userdata address, bending (0/1), density kind, current kind,
# point loads (0/1), normal added-mass wrap address (-1: isotropic), waves (0/1)
# T_REAL: gravity, stick stiffness (times dt^2) and damping (times dt) per kg, weight per metre on the seabed, mu,
# radius, contact tolerance, seabed point (3), seabed normal (3)
# T_STATE: first deployed node, its share of the drum element, payout rate (m/s; 0 without drum)
# T_WAVES: the sea's (13, M) table (``WaveField``'s, for ``waves.state_kernel``), flat; T_WAVE_REAL:
# depth, ramp (s), Wheeler stretching (0/1); T_ADDED, T_AXIAL: each element's added-mass area per metre
# normal to it and along it (``loads._wave_added_mass``); T_NODE_ADDED: each node's added volume
_GP0, _GP1 = GAUSS_POINTS


@_jit
def _sea(table, slot, dp, offs, points, eta, vel, acc):
    """``WaveField.state`` at ``points`` (N, 3), m, at the ``mjData``'s time into ``eta``, ``vel``, ``acc``:
    the table's waves at ``slot`` (``T_WAVES`` or ``B_WAVES``), then their depth, ramp and stretching."""
    W, wp = _vec(table, slot), _vec(table, slot + 1)
    t = numba.carray(_f64(dp), (offs[TIME] + 1,))[offs[TIME]]
    state_kernel(points, t, W.reshape((13, W.shape[0] // 13)), wp[0], wp[2] != 0.0, wp[1], eta, vel, acc, True)


@_jit
def _tether(mp, dp, table, offs):
    I, P, S = _ints(table, T_INT), _vec(table, T_REAL), _vec(table, T_STATE)
    n, vertadr, dof0 = I[0], I[1], I[2]
    k = int(S[0])
    m = n - k  # deployed elements
    xall = numba.carray(_f64(_field(dp, offs, FLEXVERT)), ((vertadr + n + 1) * 3,))
    x = xall[3 * (vertadr + k):3 * (vertadr + n + 1)].reshape((m + 1, 3))
    qvel = numba.carray(_f64(_field(dp, offs, QVEL)), (dof0 + 3 * (n + 1),))
    v0 = qvel[dof0 + 3 * k:dof0 + 3 * (n + 1)].reshape((m + 1, 3))
    v = v0
    rate = S[2]
    if rate != 0.0:  # the cable at the fairlead leaves the drum at the payout rate (cable.loads.CableLoads.hydro)
        v = v0.copy()
        e0, e1, e2 = x[1, 0] - x[0, 0], x[1, 1] - x[0, 1], x[1, 2] - x[0, 2]
        s = rate / max(np.sqrt(e0 * e0 + e1 * e1 + e2 * e2), 1e-9)
        v[0, 0] += s * e0
        v[0, 1] += s * e1
        v[0, 2] += s * e2
    rho, u, f = np.empty(2 * m), np.empty((2 * m, 3)), np.empty((m + 1, 3))
    dp_, cp_ = _vec(table, T_DP), _vec(table, T_CP)
    compiled.element_water(x, I[6], dp_, I[7], cp_, rho, u)
    gravity, waves, surface, wa = P[0], I[10] != 0, np.zeros(m), np.empty((2 * m, 3))
    if waves:  # (``CableLoads.sea``: element i's two Gauss points at 2i, 2i + 1)
        gp, eta, wu = np.empty((2 * m, 3)), np.empty(2 * m), np.empty((2 * m, 3))
        for i in range(m):
            for j in range(3):
                gp[2 * i, j] = x[i, j] + _GP0 * (x[i + 1, j] - x[i, j])
                gp[2 * i + 1, j] = x[i, j] + _GP1 * (x[i + 1, j] - x[i, j])
        _sea(table, T_WAVES, dp, offs, gp, eta, wu, wa)
        for i in range(m):
            surface[i] = 0.5 * (eta[2 * i] + eta[2 * i + 1])
        u += wu
    rest, area, diameter = _vec(table, T_REST)[k:], _vec(table, T_AREA)[k:], _vec(table, T_DIAMETER)[k:]
    compiled.tether_loads(x, v, rest, diameter, _vec(table, T_CDN)[k:], _vec(table, T_CDT)[k:], area,
                          _vec(table, T_CDAF)[k:], rho, u, gravity, S[1], f, surface)
    if waves:
        compiled.add_wave_inertia(x, rest, area, diameter, surface, rho, wa, _vec(table, T_ADDED)[k:],
                                  _vec(table, T_AXIAL)[k:], f)
    if I[5]:
        compiled.add_bending_forces(x, _vec(table, T_BEND)[k:], f)
    if I[8]:
        eta, wu, wa = np.zeros(m + 1), np.zeros((m + 1, 3)), np.zeros((m + 1, 3))
        if waves:  # (``CableLoads._point_loads``: the sea at the nodes)
            _sea(table, T_WAVES, dp, offs, np.ascontiguousarray(x), eta, wu, wa)
        _point_loads(x, v, _vec(table, T_NODE_VOLUME)[k:], _vec(table, T_NODE_ADDED)[k:] if waves else eta,
                     _vec(table, T_NODE_CDA)[k:], I[6], dp_, I[7], cp_, gravity, eta, wu, wa, f)
    mode = I[3]
    if mode:
        ud = numba.carray(_f64(_field(dp, offs, USERDATA)), (I[4] + 3 * (n + 1),))
        stick = ud[I[4]:I[4] + 3 * (n + 1)].reshape((n + 1, 3))
        for i in range(k):
            for j in range(3):
                stick[i, j] = np.nan
        if mode == 3:  # a buoyant cable does not press on the seabed
            for i in range(k, n + 1):
                for j in range(3):
                    stick[i, j] = np.nan
        else:
            nf = np.empty(m + 1)
            if mode == 1:  # each node's half of its elements
                rest = _vec(table, T_REST)[k:]
                half = (0.5 * P[3]) * rest
                nf[:-1] = half
                nf[-1] = 0.0
                nf[1:] += half
            else:
                nf[:] = np.maximum(_vec(table, T_NODE_WET)[k:], 0.0)
            inertia = _vec(table, T_INERTIA)[k:]
            force, new = np.empty((m + 1, 3)), np.empty((m + 1, 3))
            dt = numba.carray(_f64(mp), (offs[TIMESTEP] + 1,))[offs[TIMESTEP]]  # (the model's, now)
            compiled.seabed_friction(x, v0, stick[k:], P[7:10], P[10:13], P[5], nf, P[4], (P[1] / dt ** 2) * inertia,
                                     (P[2] / dt) * inertia, P[6], force, new)
            stick[k:] = new
            f += force
    qfrc = numba.carray(_f64(_field(dp, offs, QFRC)), (dof0 + 3 * (n + 1),))
    out = qfrc[dof0 + 3 * k:dof0 + 3 * (n + 1)]
    for i in range(m + 1):
        for j in range(3):
            out[3 * i + j] += f[i, j]
    if I[9] >= 0 and m >= 1:
        prm = numba.carray(_f64(_field(mp, offs, WRAP_PRM)), (I[9] + 6 * (n + 1),))[I[9]:]
        _orient_normals(x, prm[6 * k:])


@_jit
def _point_loads(x, v, volume, added, cda, dkind, dp, ckind, cp, gravity, eta, wu, wa, f):
    """``cable.loads.CableLoads._point_loads``: each node's point load's buoyancy under the surface
    ``eta`` (m, at each node) and its drag 1/2 rho CdA |u - v| (u - v), with the waves' particle
    velocity ``wu`` in u and their inertia load rho (V + V_a) ``wa`` (zeros without waves), added to ``f`` (N)."""
    any_cda = False
    for i in range(cda.shape[0]):
        any_cda = any_cda or cda[i] > 0
    one = np.empty((2, 3))
    rho, u = np.empty(2), np.empty((2, 3))
    for i in range(x.shape[0]):
        z = min(x[i, 2], 0.0)
        wet = 1.0 if x[i, 2] <= eta[i] else 0.0
        one[0, 2] = one[1, 2] = z  # a zero-length element at the node: its water
        one[0, 0] = one[1, 0] = one[0, 1] = one[1, 1] = 0.0
        compiled.element_water(one, dkind, dp, ckind, cp, rho, u)
        s = rho[0] * wet * (volume[i] + added[i])
        for j in range(3):
            f[i, j] += s * wa[i, j]
        f[i, 2] += rho[0] * volume[i] * gravity * wet
        if any_cda:
            r0, r1, r2 = (u[0, 0] + wu[i, 0]) - v[i, 0], (u[0, 1] + wu[i, 1]) - v[i, 1], (u[0, 2] + wu[i, 2]) - v[i, 2]
            s = 0.5 * rho[0] * cda[i] * wet * np.sqrt(r0 * r0 + r1 * r1 + r2 * r2)
            f[i, 0] += s * r0
            f[i, 1] += s * r1
            f[i, 2] += s * r2


@_jit
def _orient_normals(x, prm):
    """``cable.loads.orient_added_mass``: each deployed node's two normal added-mass tendons
    (``prm``: 6 per node, from the first deployed) turned normal to the cable at ``x``."""
    m = x.shape[0] - 1
    e = np.empty((m, 3))
    for i in range(m):
        e0, e1, e2 = x[i + 1, 0] - x[i, 0], x[i + 1, 1] - x[i, 1], x[i + 1, 2] - x[i, 2]
        inv = max(np.sqrt(e0 * e0 + e1 * e1 + e2 * e2), 1e-300)
        e[i, 0], e[i, 1], e[i, 2] = e0 / inv, e1 / inv, e2 / inv
    for i in range(m + 1):
        if i == 0:
            t0, t1, t2 = e[0, 0], e[0, 1], e[0, 2]
        elif i == m:
            t0, t1, t2 = e[m - 1, 0], e[m - 1, 1], e[m - 1, 2]
        else:
            t0, t1, t2 = e[i - 1, 0] + e[i, 0], e[i - 1, 1] + e[i, 1], e[i - 1, 2] + e[i, 2]
        norm = np.sqrt(t0 * t0 + t1 * t1 + t2 * t2)
        if not norm > 1e-6:  # no direction here: keep the last one
            continue
        t0, t1, t2 = t0 / norm, t1 / norm, t2 / norm
        if abs(t2) < 0.9:  # first normal: z x t, or x x t near vertical
            a0, a1, a2 = 0.0, 0.0, 1.0
        else:
            a0, a1, a2 = 1.0, 0.0, 0.0
        n0, n1, n2 = a1 * t2 - a2 * t1, a2 * t0 - a0 * t2, a0 * t1 - a1 * t0
        nn = np.sqrt(n0 * n0 + n1 * n1 + n2 * n2)
        n0, n1, n2 = n0 / nn, n1 / nn, n2 / nn
        p = prm[6 * i:6 * i + 6]
        p[0], p[1], p[2] = n0, n1, n2
        p[3], p[4], p[5] = t1 * n2 - t2 * n1, t2 * n0 - t0 * n2, t0 * n1 - t1 * n0


# A rigid body's table (BoundBodyHydro.native_table)
B_INT, B_REAL, B_CD, B_AREA, B_ANG, B_DP, B_CP, B_WAVES, B_WAVE_REAL, B_ADDED = range(10)
# B_INT: body id, density kind, current kind, waves (0/1); B_REAL: volume, height, gravity, centre of
# buoyancy (3); B_WAVES, B_WAVE_REAL: as T_WAVES, T_WAVE_REAL; B_ADDED: free joint (0/1), added mass (3)


@_jit
def _body_loads(dp, table, offs, vel):
    """A rigid body's loads: force (N) at the centre of buoyancy, torque (N m) and that point
    (world frame), from its velocity ``vel`` (mj_objectVelocity's: angular, linear at its origin)."""
    I, P = _ints(table, B_INT), _vec(table, B_REAL)
    b = I[0]
    xpos = numba.carray(_f64(_field(dp, offs, XPOS)), (3 * (b + 1),))[3 * b:3 * b + 3]
    R = numba.carray(_f64(_field(dp, offs, XMAT)), (9 * (b + 1),))[9 * b:9 * b + 9].reshape((3, 3))
    p = np.empty(3)
    for j in range(3):
        p[j] = xpos[j] + (R[j, 0] * P[3] + R[j, 1] * P[4] + R[j, 2] * P[5])
    rx, ry, rz = p[0] - xpos[0], p[1] - xpos[1], p[2] - xpos[2]
    w = vel[:3]
    v = np.empty(3)
    v[0] = vel[3] + (w[1] * rz - w[2] * ry)
    v[1] = vel[4] + (w[2] * rx - w[0] * rz)
    v[2] = vel[5] + (w[0] * ry - w[1] * rx)
    force, torque = np.empty(3), np.empty(3)
    if I[3]:  # (``BoundBodyHydro.wave_loads``)
        eta, uw, aw = np.empty(1), np.empty((1, 3)), np.empty((1, 3))
        _sea(table, B_WAVES, dp, offs, p.reshape((1, 3)), eta, uw, aw)
        A = _vec(table, B_ADDED)
        compiled.rigid_body_wave_loads(R, p, v, w, P[0], P[1], _vec(table, B_CD), _vec(table, B_AREA),
                                       _vec(table, B_ANG), A[0] != 0.0, A[1:], I[1], _vec(table, B_DP), I[2],
                                       _vec(table, B_CP), P[2], eta[0], uw[0], aw[0], force, torque)
        return force, torque, p
    compiled.rigid_body_loads(R, p, v, w, P[0], P[1], _vec(table, B_CD), _vec(table, B_AREA), _vec(table, B_ANG),
                              I[1], _vec(table, B_DP), I[2], _vec(table, B_CP), P[2], force, torque)
    return force, torque, p


@_jit
def _body(mp, dp, table, offs):
    """``rigidbody.BoundBodyHydro.apply``: MuJoCo's velocity of the body, its loads, applied
    with MuJoCo's ``mj_applyFT``."""
    vel = np.empty(6)
    _object_velocity(_void(mp), _void(dp), _OBJ_BODY, _ints(table, B_INT)[0],
                     _void(vel.ctypes.data), 0)
    force, torque, p = _body_loads(dp, table, offs, vel)
    _apply_ft(_void(mp), _void(dp), _void(force.ctypes.data), _void(torque.ctypes.data), _void(p.ctypes.data),
              _ints(table, B_INT)[0], _void(_field(dp, offs, QFRC)))


# A vehicle's table (BoundVehicle.native_table)
V_INT, V_REAL, V_MA, V_KEEP, V_DL, V_FADE, V_DQ, V_MLIN, V_RB, V_HULL, V_FINS, V_PROP, V_SURFACE, V_DP, V_CP, \
    V_FIN_ACT, V_AXES, V_EXPLICIT, V_SIZE, V_THR, V_THR_ACT = range(21)
# V_INT: body id, first linear dof, first angular dof, density kind, current kind, propeller's
# activation address (-1: none), added-mass tendons' wrap address, has an explicit remainder
# V_REAL: gravity, volume


@_jit
def _vehicle(mp, dp, table, offs):
    I, P = _ints(table, V_INT), _vec(table, V_REAL)
    b, dv, dw = I[0], I[1], I[2]
    R = numba.carray(_f64(_field(dp, offs, XMAT)), (9 * (b + 1),))[9 * b:9 * b + 9].reshape((3, 3))
    z = numba.carray(_f64(_field(dp, offs, XPOS)), (3 * (b + 1),))[3 * b + 2]
    nv = max(dv, dw) + 3
    qvel = numba.carray(_f64(_field(dp, offs, QVEL)), (nv,))
    nu = np.empty(6)
    for k in range(3):
        nu[k] = R[0, k] * qvel[dv] + R[1, k] * qvel[dv + 1] + R[2, k] * qvel[dv + 2]
        nu[3 + k] = qvel[dw + k]
    fin_act = _ints(table, V_FIN_ACT)
    thr_act = _ints(table, V_THR_ACT)
    nact = I[5] + 1
    for i in range(fin_act.shape[0]):
        nact = max(nact, fin_act[i] + 1)
    for i in range(thr_act.shape[0]):
        nact = max(nact, thr_act[i] + 1)
    act = numba.carray(_f64(_field(dp, offs, ACT)), (nact,)) if nact > 0 else np.zeros(1)
    deltas = np.empty(fin_act.shape[0])
    for i in range(fin_act.shape[0]):
        deltas[i] = act[fin_act[i]]
    rpm = act[I[5]] if I[5] >= 0 else 0.0
    thr_force = np.empty(thr_act.shape[0])
    for i in range(thr_act.shape[0]):
        thr_force[i] = act[thr_act[i]]
    MA = _vec(table, V_MA).reshape((6, 6))
    tau = np.empty(6)
    compiled.vehicle_wrench(nu, R, min(z, 0.0), I[3], _vec(table, V_DP), I[4], _vec(table, V_CP), P[0], MA,
                            _vec(table, V_KEEP).reshape((6, 6)), _vec(table, V_DL).reshape((6, 6)),
                            _vec(table, V_FADE), _vec(table, V_DQ), _vec(table, V_MLIN).reshape((3, 3)), P[1],
                            _vec(table, V_RB), _vec(table, V_HULL), _vec(table, V_FINS).reshape((-1, 10)), deltas,
                            _vec(table, V_PROP), rpm, _vec(table, V_SURFACE), z, _vec(table, V_SIZE),
                            _vec(table, V_THR).reshape((-1, 6)), thr_force, tau)
    if I[7]:  # the rest of M_A nu', from the last step's acceleration
        qacc = numba.carray(_f64(_field(dp, offs, QACC)), (nv,))
        a = np.empty(6)
        for k in range(3):
            a[k] = R[0, k] * qacc[dv] + R[1, k] * qacc[dv + 1] + R[2, k] * qacc[dv + 2]
            a[3 + k] = qacc[dw + k]
        a[0] -= nu[4] * nu[2] - nu[5] * nu[1]
        a[1] -= nu[5] * nu[0] - nu[3] * nu[2]
        a[2] -= nu[3] * nu[1] - nu[4] * nu[0]
        E = _vec(table, V_EXPLICIT).reshape((6, 6))
        for i in range(6):
            s = 0.0
            for j in range(6):
                s += E[i, j] * a[j]
            tau[i] -= s
    qfrc = numba.carray(_f64(_field(dp, offs, QFRC)), (nv,))
    for j in range(3):
        qfrc[dv + j] += R[j, 0] * tau[0] + R[j, 1] * tau[1] + R[j, 2] * tau[2]
        qfrc[dw + j] += tau[3 + j]
    axes = _vec(table, V_AXES).reshape((3, 3))
    prm = numba.carray(_f64(_field(mp, offs, WRAP_PRM)), (I[6] + 9,))[I[6]:]
    for kk in range(3):  # tendon kk along the linear block's principal axis kk, turned by R
        for j in range(3):
            prm[3 * kk + j] = R[j, 0] * axes[0, kk] + R[j, 1] * axes[1, kk] + R[j, 2] * axes[2, kk]


@_jit
def passive(mp, dp, registry, offs):
    """Add the registered loads of model ``mp`` to ``qfrc_passive`` of data ``dp`` (addresses);
    nothing for a model not in ``registry`` (rows: model address, provider list address, number
    of providers, address of the block's owner word: the only ``mjData`` allowed, -1 for any)."""
    r = -1
    for i in range(registry.shape[0]):
        if registry[i, 0] == mp:
            r = i
            break
    if r < 0 or registry[r, 1] == 0:
        return
    owner = numba.carray(_i64(registry[r, 3]), (1,))[0]
    if owner != -1 and owner != dp:  # another mjData on a model the loads write to: refused
        qfrc = numba.carray(_f64(_field(dp, offs, QFRC)), (1,))
        qfrc[0] = np.nan
        return
    items = numba.carray(_i64(registry[r, 1]), (registry[r, 2], 2))
    for i in range(items.shape[0]):
        table = numba.carray(_i64(items[i, 1]), (SLOTS, 2))
        if items[i, 0] == TETHER:
            _tether(mp, dp, table, offs)
        elif items[i, 0] == BODY:
            _body(mp, dp, table, offs)
        else:
            _vehicle(mp, dp, table, offs)


@_jit
def _passive_here(mp, dp):
    """``passive`` with this process's offsets and registry (``_table``, found through ``_link``'s
    symbol)."""
    base = _registry_address()
    passive(mp, dp, numba.carray(_i64(base + 8 * OFFSET_WORDS), (CAPACITY, 4)),
            numba.carray(_i64(base), (OFFSET_WORDS,)))


def _mjcb_passive(m, d):
    """The ``mjcb_passive`` MuJoCo calls: ``passive`` for this process's registered models
    (compiled by ``callback``, after ``_link``)."""
    _passive_here(_address(m), _address(d))


@_jit
def _act_dyn_here(mp, dp, i):
    """``actuation``'s activation rate for actuator ``i`` of the model at ``mp``, written to the
    ``mjData`` at ``dp``; returns the last one (MuJoCo's for an actuator of one activation)."""
    offs = numba.carray(_i64(_registry_address()), (OFFSET_WORDS,))
    adr = numba.carray(_i32(_field(mp, offs, ACTADR)), (i + 1,))[i]
    k = numba.carray(_i32(_field(mp, offs, ACTNUM)), (i + 1,))[i]
    if k < 1:
        return 0.0
    prm = numba.carray(_f64(_field(mp, offs, DYNPRM)), (10 * (i + 1),))[10 * i:]
    act = numba.carray(_f64(_field(dp, offs, ACT)), (adr + k,))[adr:]
    act_dot = numba.carray(_f64(_field(dp, offs, ACT_DOT)), (adr + k,))[adr:]
    u = numba.carray(_f64(_field(dp, offs, CTRL)), (i + 1,))[i]
    dt = numba.carray(_f64(mp), (offs[TIMESTEP] + 1,))[offs[TIMESTEP]]
    actuation.response_act_dot(prm, act, u, dt, act_dot)
    return act_dot[k - 1]


def _mjcb_act_dyn(m, d, i):
    """The ``mjcb_act_dyn`` MuJoCo calls (compiled by ``act_dyn_callback``, after ``_link``)."""
    return _act_dyn_here(_address(m), _address(d), i)


# --------------------------------------------------------------------------- registration

OFFSET_WORDS = 16
"""Words at the start of ``_table`` for the struct offsets (``offsets``)."""
_table = np.zeros(OFFSET_WORDS + 4 * CAPACITY, dtype=np.int64)  # the offsets, then the registry
_registry = _table[OFFSET_WORDS:].reshape(CAPACITY, 4)  # rows: model address, provider list address,
# providers, owner word address
_blocks: dict[int, "Block"] = {}  # model address -> its block (kept alive here)
_state: dict[str, object] = {}


def _link() -> None:
    """Once per process: find the struct offsets, make MuJoCo's library and ``_table`` known to
    the compiled code by name (so that it is cached on disk, and only the first run on a machine
    compiles it, in about a minute)."""
    if "registry getter" in _state:
        return
    offs = _offsets()
    if len(offs) > OFFSET_WORDS:
        raise RuntimeError("mjtether.physics.native: more struct offsets than OFFSET_WORDS")
    _table[:len(offs)] = offs
    import llvmlite.binding as llvm

    llvm.load_library_permanently(_mujoco_library())
    address = _table.ctypes.data
    getter = numba.cfunc(types.int64())(lambda: address)
    llvm.add_symbol("mjtether_native_registry", getter.address)
    _state["registry getter"] = getter  # (kept alive)


def offsets() -> np.ndarray:
    """Word offsets of the arrays the callback reads in mjData and mjModel (``_DATA_FIELDS``,
    ``_MODEL_FIELDS``), and of mjModel's ``opt.timestep`` and mjData's ``time``."""
    _link()
    return _table[:len(_DATA_FIELDS) + len(_MODEL_FIELDS) + 2]


class Block:
    """The force block of one simulation: its providers' tables. ``tables`` is a list of
    (kind, list of arrays by slot); every array is kept alive here and must be updated in place."""

    def __init__(self, tables, writes_model: bool):
        self._keep = []
        rows = []
        for kind, arrays in tables:
            t = np.zeros((SLOTS, 2), dtype=np.int64)
            for slot, a in enumerate(arrays):
                if a is None:
                    continue
                if not (isinstance(a, np.ndarray) and a.flags.c_contiguous and a.dtype in (np.float64, np.int64)):
                    raise TypeError(f"native table slot {slot}: a C-contiguous float64 or int64 array is needed")
                t[slot] = (a.ctypes.data if a.size else 0, a.size)
                self._keep.append(a)
            self._keep.append(t)
            rows.append((kind, t.ctypes.data))
        self.items = np.array(rows, dtype=np.int64).reshape(-1, 2)
        self.owner = np.array([-1], dtype=np.int64)  # see register
        self.writes_model = writes_model


def register(model: mujoco.MjModel, block: Block, owner: mujoco.MjData | None = None) -> None:
    """Apply ``block``'s loads to every ``mjData`` of ``model`` that MuJoCo steps; with
    ``owner``, and a block that writes its model, to ``owner`` only (the module docstring)."""
    free = np.flatnonzero(_registry[:, 0] == 0)
    if model._address in _blocks:
        raise RuntimeError("mjtether.physics.native: this model is registered already")
    if not len(free):
        raise RuntimeError(f"mjtether.physics.native: more than {CAPACITY} models registered at once; close simulations "
                           "you no longer use")
    offsets()
    r = int(free[0])
    _blocks[model._address] = block
    block.owner[0] = owner._address if owner is not None and block.writes_model else -1
    _registry[r, 1:] = (block.items.ctypes.data, len(block.items), block.owner.ctypes.data)
    _registry[r, 0] = model._address  # last: the row is complete before the callback can match it


def register_copy(model: mujoco.MjModel, original: mujoco.MjModel) -> None:
    """Give ``model`` (a copy of ``original``, e.g. one per rollout) ``original``'s loads, for
    any ``mjData`` (one at a time: a copy that the loads write to is one rollout's). The copy
    reads the block's state (payout) as the simulation has it now; unregister it when done."""
    block = _blocks.get(original._address)
    if block is None:
        raise ValueError("mjtether.physics.native: the original model is not registered")
    copy = Block.__new__(Block)
    copy._keep, copy.items, copy.writes_model = [block], block.items, block.writes_model
    copy.owner = np.array([-1], dtype=np.int64)
    register(model, copy)


def unregister(model: mujoco.MjModel) -> None:
    """Stop applying loads to ``model``'s data."""
    rows = np.flatnonzero(_registry[:, 0] == model._address)
    _registry[rows, 0] = 0
    _registry[rows, 1:] = 0
    _blocks.pop(model._address, None)


def is_registered(model: mujoco.MjModel) -> bool:
    return model._address in _blocks


def apply(model: mujoco.MjModel, data: mujoco.MjData) -> None:
    """The callback's work for one step, called from Python (``dispatch``'s Python callback)."""
    _link()
    _passive_here(model._address, data._address)


def act_dyn_callback():
    """The compiled ``mjcb_act_dyn`` (``actuation``), a ctypes function pointer for
    ``mujoco.set_mjcb_act_dyn``."""
    _link()
    cb = _state.get("act_dyn")
    if cb is None:
        cb = _state["act_dyn"] = numba.cfunc(types.float64(types.voidptr, types.voidptr, types.int32), nogil=True,
                                             cache=jitcache.CACHE, error_model="numpy")(_mjcb_act_dyn)
    return cb.ctypes


def callback():
    """The compiled ``mjcb_passive``, a ctypes function pointer for ``mujoco.set_mjcb_passive``."""
    _link()
    cb = _state.get("callback")
    if cb is None:
        cb = _state["callback"] = numba.cfunc(types.void(types.voidptr, types.voidptr), nogil=True, cache=jitcache.CACHE,
                                              error_model="numpy")(_mjcb_passive)
    return cb.ctypes
