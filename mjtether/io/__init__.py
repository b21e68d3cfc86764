"""What comes in and goes out: results folders, MoorDyn files, rendering, MuJoCo's warnings and
the generated scenario reference.

* ``outdir``: a results folder that is either complete or absent, never over the user's files;
* ``results``: a run's files (CSV, NPZ, JSON, plots);
* ``moordyn``: MoorDyn v2 input files to scenarios and back;
* ``render``: headless video of a run;
* ``mjlog``: MuJoCo's warnings as Python warnings;
* ``reference``: ``docs/scenarios.md``, made from the typed scenario;
* ``packagedata``: where the shipped data folders are.

``outdir``, ``render``, ``mjlog`` and ``packagedata`` import nothing of the package; ``results``,
``moordyn`` and ``reference`` read scenarios and runs (they sit above ``mjtether.scenario``).
"""
