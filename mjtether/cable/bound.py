"""A ``TetherModel`` bound to a compiled model: the parts that run a tether, composed.

* ``layout.CableLayout``: where the tether is in the model (bodies, dofs, tendons, equalities);
* ``drum.Drum``: payout, release and take-back of nodes, masses and element parameters;
* ``slack.SlackSwitch``: tension-only elements (taut/slack switching of the equalities);
* ``friction.SeabedContact``: the seabed friction's stick points;
* ``loads.CableLoads``: the hydrodynamic, bending, point and friction loads, the added mass's
  orientation, and the arrays the native callback reads;
* ``readouts.TetherReadouts``: tensions, lengths, node positions, end forces, and each
  element's largest push since it was last taken (``take_peak_compression``), and the snap
  loads found at every step (``start_snaps``, ``snaps``).

``BoundTether`` offers their methods under one name (``bt.set_length``, ``bt.tension``, ...) and
is the force provider that ``mjtether.physics.dispatch`` calls (``apply``).
"""

from __future__ import annotations

import mujoco
import numpy as np

from mjtether.physics import compiled
from mjtether.physics.rigidbody import make_not_simple
from mjtether.physics.water import WaterColumn

from .builder import TetherModel
from .drum import Drum
from .friction import SeabedContact
from .layout import CableLayout
from .loads import CableLoads, compiled_arrays
from .readouts import TetherReadouts
from .slack import SlackSwitch


class BoundTether:
    """A ``TetherModel`` bound to a compiled model: indices, force provider, payout, readouts.

    Nodes and elements are numbered as in ``builder``: from the drum's core (0) to the robot end
    (``n``); only nodes ``first`` .. n are deployed, ``first`` at the fairlead. Readouts named
    after the deployed cable (``nodes``, ``tension``) return the deployed part only, its first
    row at the ship; ``element_*`` readouts return all ``n`` elements, 0 for those on the drum.
    Readouts refer to the state of the last ``mj_forward``/``mj_step``. Forces are those the
    tether exerts on its ends (N, world frame).
    """

    def __init__(self, tm: TetherModel, model: mujoco.MjModel, data: mujoco.MjData, water: WaterColumn):
        L = self.layout = CableLayout(tm, model, data, water)
        self.tm, self.spec, self.water, self.makeup, self.line = tm, L.spec, water, L.makeup, L.line
        self.model, self.data = model, data
        self.n, self.l0, self.max_length = L.n, L.l0, L.max_length
        self.vertadr, self.tadr, self.eq0, self.drum_eq, self.end_eq = L.vertadr, L.tadr, L.eq0, L.drum_eq, L.end_eq
        self._bids, self._dof0, self._ten, self._eqs, self._normal_prm = L.bids, L.dof0, L.ten, L.eqs, L.normal_prm
        make_not_simple(model, L.bids)  # masses and armature change with the deployed length
        self.drum = Drum(L, water)
        self.switch = SlackSwitch(L, self.drum)
        self.contact = SeabedContact(L, self.drum)
        self.forces = CableLoads(L, self.drum, self.contact)
        self.readouts = TetherReadouts(L, self.drum, self.switch)
        # the compiled kernels (and the native callback) know Morison's drag law only
        L.fast = compiled_arrays(L) if compiled.backend() == "numba" and L.spec.drag_law == "morison" else None
        self.drum.relayout()
        # the parts' methods, under the names a tether has always offered
        dr, sw, ro = self.drum, self.switch, self.readouts
        self.set_length, self.payout_state, self.restore_payout = dr.set_length, dr.payout_state, dr.restore_payout
        self.drum_element, self._sync_native = dr.drum_element, dr.sync_native
        self.update_slack, self.use_snapshot, self.efc_active = sw.update, sw.use_snapshot, sw.efc_active
        self._element_rows = sw.element_rows
        self.apply, self._loads, self.native_table = self.forces.apply, self.forces.buffer, self.forces.native_table
        self.nodes, self.all_nodes, self.tension, self.element_tension = ro.nodes, ro.all_nodes, ro.tension, \
            ro.element_tension
        self.element_compression, self.take_peak_compression = ro.element_compression, ro.take_peak_compression
        self.track_peak_compression, self.clear_peak_compression = ro.track_peak_compression, \
            ro.clear_peak_compression
        self.element_length, self.slack_count, self.stretched_length = ro.element_length, ro.slack_count, \
            ro.stretched_length
        self.end_force, self.end_tension, self._rows = ro.end_force, ro.end_tension, ro.rows
        self.start_snaps, self.track_snaps = ro.start_snaps, ro.track_snaps

    @property
    def snaps(self):
        """The line's snap-load detector (``snap.SnapDetector``, from ``start_snaps``), or None."""
        return self.readouts.snaps

    # ----------------------------------------------------------------- the payout state

    @property
    def first(self) -> int:
        """The deployed node at the fairlead (nodes before it are on the drum)."""
        return self.drum.first

    @property
    def drum_rest(self) -> float:
        """Rest length of the drum element (m)."""
        return self.drum.drum_rest

    @property
    def payout_rate(self) -> float:
        """Payout rate of the last ``set_length`` (m/s)."""
        return self.drum.payout_rate

    @property
    def axial(self):
        """The elements' axial solver parameters (``builder.axial_params``) as last set."""
        return self.drum.axial

    @property
    def fairlead_share(self) -> float:
        """See ``Drum.fairlead_share`` (m)."""
        return self.drum.fairlead_share

    @property
    def rest_lengths(self) -> np.ndarray:
        """Unstretched length of every element (m), shape (n,); 0 for elements on the drum."""
        return self.drum.rest_lengths

    @property
    def deployed_length(self) -> float:
        """Unstretched deployed length (m)."""
        return self.drum.deployed_length

    @property
    def effective_EA(self) -> np.ndarray:
        """Axial stiffness (N) each deployed element has in statics: EA, or less where the time
        step cannot resolve it (see ``builder``; always so for an inextensible tether)."""
        return self.drum.effective_EA

    @property
    def N(self) -> int:
        """Number of deployed elements (the drum element included)."""
        return self.n - self.drum.first

    @property
    def segment_length(self) -> float:
        """Nominal element length l0 = initial length / segments (m)."""
        return self.l0

    # the parts' arrays under their former private names (the simulation's divergence check,
    # rollouts and tests read them)
    _rest = property(lambda self: self.drum.rest)
    _deployed_rest = property(lambda self: self.drum.deployed_rest)
    _K = property(lambda self: self.drum.K)
    _inertia = property(lambda self: self.drum.inertia)
    _native_state = property(lambda self: self.drum.native_state)
    _seabed = property(lambda self: self.contact.seabed)
    _row_cache = property(lambda self: self.readouts.row_cache)

    @property
    def _fast(self):
        """The compiled kernels' arrays (``loads.compiled_arrays``), or None: the NumPy kernels."""
        return self.layout.fast

    @_fast.setter
    def _fast(self, value) -> None:
        self.layout.fast = value

    # ----------------------------------------------------------------- state and loads

    def loads(self, data: mujoco.MjData) -> np.ndarray:
        """Hydrodynamic (+ bending, + seabed friction) loads on the deployed nodes (N, shape
        (n-first+1, 3)); updates the seabed stick points."""
        return self.forces.buffer(data).copy()

    def preload_friction(self, data: mujoco.MjData, tension) -> None:
        """Start the seabed friction from a steady state: set the stick points of the laid nodes
        so that friction holds them as they are, with element ``tension`` (N, the deployed
        elements', e.g. ``SteadyState.tension``), current and weight (each node's share up to
        mu N). Without it a laid line starts with no friction mobilised, as a cable just laid
        and never pulled; a steady state with friction (MoorPy's, ``steady_state``) assumes it
        fully mobilised, as after the pull that brought the line there. Uses the positions and
        velocities in ``data`` (qpos, qvel)."""
        self.contact.preload(data, tension, self.forces.hydro)

    def set_state(self, data: mujoco.MjData, nodes=None, velocity=None) -> None:
        """Set the deployed nodes' positions (m) and/or velocities (m/s), world frame, shape
        (deployed elements + 1, 3), e.g. from a ``quasistatic.steady_state``; call
        ``Simulation.forward()`` afterwards."""
        L, k, n = self.layout, self.drum.first, self.n
        for label, arr in (("nodes", nodes), ("velocity", velocity)):
            if arr is None:
                continue
            a = np.asarray(arr, dtype=float)
            if a.shape != (n - k + 1, 3) or not np.all(np.isfinite(a)):
                raise ValueError(f"{label} must be a finite array of shape ({n - k + 1}, 3)")
            if label == "nodes":
                data.qpos[L.q0 + 3 * k:L.q0 + 3 * (n + 1)] = a.ravel() - L.body0[3 * k:]
            else:
                data.qvel[L.dof0 + 3 * k:L.dof0 + 3 * (n + 1)] = a.ravel()
