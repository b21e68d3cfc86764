"""The tether: its properties, its MJCF, and its parts at run time.

* ``tether``: ``TetherSpec`` (EA, EI, Cd, Ca, diameter, mass per length);
* ``makeup``: line make-ups (sections, point loads, floats) and the line-type library
  (``linetypes.toml``);
* ``builder``: the MJCF chain (``add_tether``), built with ``MjSpec``, and the axial element's
  solver parameters;
* ``winch``: the winch's laws (fixed, speed, tension band, free drum);
* ``seabed``: Coulomb friction of laid cable with stick points;
* ``tangle``: the clearance and crossing geometry of a cable;
* ``stability``: the largest stable time step;
* the parts of a tether bound to a compiled model, which ``bound.BoundTether`` composes over one
  ``layout`` (where the tether is in the model): ``drum`` (payout, release and take-back of
  nodes, masses and element parameters), ``slack`` (tension-only switching), ``friction``
  (seabed friction's stick points), ``loads`` (hydrodynamic, bending and point loads, added
  mass's orientation) and ``readouts`` (tensions, lengths, end forces); ``kernels`` holds the
  compiled twins of their per-step bookkeeping.

Imports: the physics and NumPy/MuJoCo; never the scenario, the CLI or the environments.
"""
