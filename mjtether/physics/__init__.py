"""The water and the forces it puts on things, with no knowledge of cables' bookkeeping or of
scenarios.

* ``water``: the water column (density and current profiles, seabed depth, gravity);
* ``hydro``: the pure NumPy force kernels (Morison drag, buoyancy, bending), the reference;
* ``compiled``: their numba twins, and which kernels a run uses;
* ``native``: the compiled passive-force callback that MuJoCo calls itself;
* ``dispatch``: the one process-wide ``mjcb_passive`` slot, shared by simulations;
* ``actuation``: linear actuator responses (a thruster's transfer function) through the one
  process-wide ``mjcb_act_dyn``;
* ``rigidbody``: buoyancy, drag and added mass of rigid bodies (clump weights, floats).

Imports: NumPy, SciPy, numba and MuJoCo, and ``mjtether._checks``; nothing else of the package.
"""
