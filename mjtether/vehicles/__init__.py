"""Free-swimming and surface vehicles.

* ``fossen``: Fossen's manoeuvring terms (rigid-body and added-mass Coriolis, damping);
* ``vehicle``: a vehicle body in MuJoCo, its hydrodynamics through the compiled wrench;
* ``files``: vehicle parameter files (``load_vehicle``; shipped ones in ``assets/vehicles``);
* ``thruster``, ``propeller``, ``fins``: actuators;
* ``allocation``: an autopilot's wrench shared among them within their limits, the moments first.

Imports: the physics and ``mjtether.files.packagedata``; never the cable, the scenario, the CLI or
the environments.
"""
