"""Where a tether lives in a compiled model: its bodies, degrees of freedom, tendons and
equalities, found once by name and checked to be contiguous, and the node positions and
velocities read and written through them.

Nodes and elements are numbered as in ``builder``: from the drum's core (0) to the robot end
(``n``). Every part of a bound tether (``drum``, ``slack``, ``friction``, ``loads``,
``readouts``) reads the model through one ``CableLayout``. Units SI, world frame.
"""

from __future__ import annotations

import mujoco
import numpy as np

from mjtether.physics.water import WaterColumn

from .builder import TetherModel

_ROWS_OF = {int(mujoco.mjtEq.mjEQ_CONNECT): 3, int(mujoco.mjtEq.mjEQ_WELD): 6, int(mujoco.mjtEq.mjEQ_JOINT): 1,
            int(mujoco.mjtEq.mjEQ_TENDON): 1}
"""Constraint rows of each kind of equality that may come before the tether's elements."""


class CableLayout:
    """A ``TetherModel``'s indices into a compiled ``model`` and its ``data``.

    Attributes: ``n`` elements, nominal element length ``l0`` (m), ``vertadr`` (its flex's first
    vertex), ``tadr`` and ``ten`` (the element tendons), ``eq0`` and ``eqs`` (the element
    equalities), ``drum_eq`` (the connects of each node to the fairlead, None for a free start)
    and ``end_eq``, ``bids`` (node bodies), ``dof0`` and ``q0`` (the first node's dof and qpos
    address; the nodes' are contiguous), ``normal_ten`` and ``normal_prm`` (the normal
    added-mass tendons and a view of their joint coefficients, None for isotropic added mass),
    ``rows_before`` (constraint rows of each equality defined before the elements), and
    ``fast``: the compiled kernels' per-element arrays (``loads.compiled_arrays``), or None
    where the NumPy kernels run.

    The line is always a ``makeup.LineMakeup`` (``line``, the deployed elements at the start; a
    uniform ``TetherSpec`` is its one-section make-up; ``makeup`` is ``tm.makeup``, None for a
    uniform line, for the parts that still read it so); ``element(a)`` and ``node(a)`` extend
    its per-element and per-node arrays over the ``tm.first`` elements and nodes waiting on the
    drum (more of its first section, no point loads), and ``nominal`` is every element's
    unstretched length (m). ``pays_out`` (``LineMakeup.pays_out``): the drum pays out and takes
    back (a uniform line; a make-up's length is fixed, see ``builder.add_tether``), lumping the
    masses with its one mass per length in the scalar arithmetic of ``Drum.update_drum``.
    """

    def __init__(self, tm: TetherModel, model: mujoco.MjModel, data: mujoco.MjData, water: WaterColumn):
        self.tm = tm
        self.spec = tm.spec
        self.water = water
        self.model, self.data = model, data
        self.n = n = tm.n
        self.l0 = tm.nominal_length
        self.max_length = tm.max_length
        self.line = tm.line  # (a uniform tether: its one section)
        self.makeup = tm.makeup
        self.pays_out = self.line.pays_out  # (the builder allows payout for a uniform line only)
        self._drum_nodes = tm.first
        self.nominal = self.element(self.line.element_length)
        fid = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_FLEX, tm.name)
        self.vertadr = int(model.flex_vertadr[fid])
        self.tadr = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_TENDON, tm.element_tendon(0))
        self.ten = slice(self.tadr, self.tadr + n)
        # the normal added mass's tendons (two per node, see builder) and their joint coefficients
        self.normal_ten = self.normal_prm = None  # (isotropic added mass: none)
        if tm.added_mass == "normal":
            nadr = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_TENDON, tm.normal_tendon(0, 0))
            if nadr < 0 or not np.all(model.tendon_num[nadr:nadr + 2 * (n + 1)] == 3) or \
                    not np.all(np.diff(model.tendon_adr[nadr:nadr + 2 * (n + 1)]) == 3):
                raise RuntimeError("tether normal added-mass tendons missing or not contiguous")
            self.normal_ten = slice(nadr, nadr + 2 * (n + 1))
            w0 = int(model.tendon_adr[nadr])
            self.normal_prm = model.wrap_prm[w0:w0 + 6 * (n + 1)].reshape(n + 1, 2, 3)  # a view
        self.eq0 = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_EQUALITY, tm.element_tendon(0))
        self.eqs = slice(self.eq0, self.eq0 + n)
        # constraint rows of each equality defined before the elements' (see slack.element_rows)
        before = model.eq_type[:self.eq0]
        if any(int(t) not in _ROWS_OF for t in before):
            raise ValueError("a tether must be added before any flex equality of the spec")
        self.rows_before = np.array([_ROWS_OF[int(t)] for t in before], dtype=np.int64)
        start = tm.connects.get("start")
        self.drum_eq = None if start is None else np.array(
            [mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_EQUALITY, c) for c in start])
        self.end_eq = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_EQUALITY, tm.connects["end"]) \
            if "end" in tm.connects else None
        self.bids = np.array([mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, b) for b in tm.node_bodies])
        dofs = (model.body_dofadr[self.bids][:, None] + np.arange(3)).ravel()
        if not np.all(np.diff(dofs) == 1):
            raise RuntimeError("tether node dofs must be contiguous")
        self.dof0 = int(dofs[0])
        qadr = (model.jnt_qposadr[model.body_jntadr[self.bids]][:, None] + np.arange(3)).ravel()
        if not np.all(np.diff(qadr) == 1):
            raise RuntimeError("tether node qpos must be contiguous")
        self.q0 = int(qadr[0])
        self.body0 = tm.initial_nodes.ravel().copy()  # node body positions at qpos = 0
        self.fast = None

    def element(self, a) -> np.ndarray:
        """A per-element array of the deployed line (``line.element_*``, shape (n - first,)),
        over all ``n`` elements: the ones on the drum take its first element's value."""
        a = np.asarray(a, dtype=float)
        return np.concatenate([np.full(self._drum_nodes, a[0]), a])

    def node(self, a) -> np.ndarray:
        """A per-node array of the deployed line's point loads (``line.node_*``, shape
        (n - first + 1,)), over all ``n + 1`` nodes: 0 on the nodes waiting on the drum."""
        return np.concatenate([np.zeros(self._drum_nodes), np.asarray(a, dtype=float)])

    def x(self, i0: int = 0, i1: int | None = None) -> np.ndarray:
        """Positions (m) of nodes i0..i1-1 from qpos (valid before mj_forward)."""
        i1 = self.n + 1 if i1 is None else i1
        return (self.data.qpos[self.q0 + 3 * i0:self.q0 + 3 * i1] + self.body0[3 * i0:3 * i1]).reshape(-1, 3)

    def v(self, i0: int = 0, i1: int | None = None) -> np.ndarray:
        """Velocities (m/s) of nodes i0..i1-1 (a view of qvel)."""
        i1 = self.n + 1 if i1 is None else i1
        return self.data.qvel[self.dof0 + 3 * i0:self.dof0 + 3 * i1].reshape(-1, 3)

    def place(self, i: int, x, v) -> None:
        """Put node ``i`` at ``x`` (m) moving at ``v`` (m/s)."""
        self.data.qpos[self.q0 + 3 * i:self.q0 + 3 * i + 3] = np.asarray(x) - self.body0[3 * i:3 * i + 3]
        self.data.qvel[self.dof0 + 3 * i:self.dof0 + 3 * i + 3] = v
