"""The golden runs of ``test_golden``: every example scenario for 2 s after its start, and 20
steps of each environment.

``runs()`` returns, per example, the recorded rows (``runner.RECORD_FIELDS``, every 0.25 s) and
the tether's nodes and element tensions at the end, at full precision. They were written to
``tests/data/golden_runs.npz`` before the runner was split into scene, start, controllers and
readouts (issue 15), with the compiled kernels, so that the test shows the split changed no bit
of any result. Regenerate only for a change of the physics or of the order of its arithmetic,
and say which here:

* one Morison kernel for the statics and the dynamics (``hydro.morison_drag``): the statics add
  a float's drag before the buoyancy, no longer after; the lazy-wave umbilical's start moved by
  rounding (largest change 5e-12 of the largest record value); nothing else changed.
* the ROV example (``examples/rov_umbilical.toml``) added; every other run unchanged bit for bit.
* the ROV autopilot's allocation takes the least-thrust least-squares answer where it is within
  the thrusters' limits (before: scipy's bounded solver every time): the ROV example changed.
* the REMUS 100 examples (``remus_fibre_payout``, ``remus_turning_circle``) and
  ``TetheredROV-v0`` added; the vehicle's forces by the compiled kernel
  (``compiled.vehicle_wrench``): the ROV example moved by rounding (largest change 2.6e-11 of
  a record value); every other run unchanged bit for bit.
* the REMUS 100's pitch loop gained an integral (``pitch_ki``): ``remus_turning_circle`` changed;
  every other run unchanged bit for bit.
* the record gained three columns at its end (``cable_moment_body_x/y/z``); the 29 before them
  unchanged bit for bit in every run.
* the Otter, Hong et al. and fibre-paying AUV examples added (``otter_*``, ``hong2020_platform``,
  ``auv_fibre_*``); the record gained the tangle monitor's four columns at its end
  (``cable_clearance``, ``cable_self_clearance``, ``cable_plan_crossings``, ``cable_wrap``); the
  free drum pays out by a backward-Euler law: the 32 columns before them, the nodes and tensions
  of every earlier run unchanged bit for bit (the free-drum example's first 2 s included: its
  payout is limited by the drum's acceleration there).
* a prescribed path's vehicle is carried by the current from rest, ramped in over the path's
  first interval: the fibre examples in a current (``auv_fibre_circle*``, ``auv_fibre_spiral``)
  changed; every other run unchanged bit for bit.
* issue 17: the loads are applied by the native callback (``native``), the steady march, the
  slack hang, the gait, the slack switching and the divergence search are compiled, tabulated
  profiles are interpolated without numba's ``np.interp``, and the steady state's coarse-to-fine
  cascade starts at 12 elements (not 5). Every run moved by rounding (1e-16 relative per step)
  or by its start's steady state moving within the solver's tolerance: the largest changes are
  0.26 N of 381 N in ``ship_away_tension_band``'s first tow force (its new start has a residual
  of 3e-10 m against 6e-6 m before: EA = 5e6 N on 3 m elements turns micrometres into tenths of
  a newton), 1.6e-5 of the default walker's ship force, and the count of slack elements in
  ``walker_ship_follows`` by up to 4 of 24 (elements of a laid cable at zero tension switch on
  thresholds; its forces moved by 1.3e-8); every other column by at most 6e-4 of its largest
  value (columns that are zero to rounding, below 1e-9, moved by rounding).
* the walker stands alone on a scene of its own (the seabed, the water and the walker: no
  ship), its stand is kept for runs with the same seabed, water, start and gait
  (``start.stand_walker``), and it is put back at its commanded place from the positions at
  the stand's end (before, the heading was read from the kinematics of the stand's last step,
  one step behind). The walker runs moved: their ship and tow forces by at most 5e-5 of the
  largest, element tensions by at most 3.7 N of 1450 N (``default_walker``'s gait jerking a
  laid element), ``walker_up_slope``'s body-frame cable moment by 8e-3 N m of 0.3 N m and its
  tangle monitor's near-contact clearance by 0.2 mm, the count of slack elements and plan
  crossings by a few (elements and crossings at thresholds); the environments' observations
  by at most 3e-3 of 812. Every other run unchanged bit for bit.
* the steady state's first guess adds the top's share of the current's drag
  (``steady._drag_share``): every start with a current moved within the solver's tolerance,
  the runs by at most 4e-5 of a column's largest value (``default_walker``'s ship force), a
  laid element's tension by 3.2 N of 1450 N at the end of ``default_walker`` (its gait jerking
  it); columns that are zero to rounding (below 1e-15) moved by rounding.
* the walker is placed with its torso ``WALKER_STAND_HEIGHT`` over the seabed, as documented
  (walker.xml's own 0.9 m torso height had been added on top: it fell 0.9 m for 1.2 s of its
  2 s stand, was still bouncing at its end, and sank its tow point 6.5 cm below the steady
  start's during the pre-roll), and stands 1 s (``STAND_S``), by when it has settled. Every
  walker run and the walker environments changed: the cable, started to the tow point where
  the walker then stays, takes up its slack about 1 s sooner once the walker sets off
  (``walker_turning_cross_current``'s tow tension reaches 238 N at 2 s, where it had 8 N;
  over 20 s both runs go through the same cycle of 170-380 N, shifted by about 1 s, and end
  at the same place to 1 cm). The anchor, vehicle and vessel runs are unchanged bit for bit.
* the walker stands in still water (the current comes in with the pre-roll), on a flat seabed
  at the origin facing +x, moved and turned into place, the stand kept for every run on the
  same seabed (``start.stand_walker``). The walker runs and environments moved:
  ``walker_turning_cross_current`` (0.4 m/s across the walker) most, its tow force by 23 N of
  182 N at 2 s while the cable takes up its slack (from 4 s on its tow tension, sampled each
  second of 20 s through a 170-380 N cycle, stays within 4 N, and it ends at the same place);
  ``default_walker``'s ship force by 0.39 N of 1470 N and a laid element by 12 N of 1440 N;
  ``TetheredWalker-v0``'s observations by at most 19.5 of 812; the others by rounding or a
  slack element at a threshold.
* issue 29: the seabed from a bathymetry grid; a steady start solved on a level seabed that lies
  above a sloped or gridded one settles onto it first, the robot held (``start.floats_over_seabed``):
  ``walker_up_slope`` changed (its laid umbilical had started up to 10 m above the slope and fell
  during the run); ``walker_bathymetry`` added. Rewritten on an AMD EPYC machine (before: an Intel
  Xeon); every other run within the cross-machine tolerance of the file it replaced.
* issue 30: a free drum has no acceleration limit unless one is given (``winch.max_accel`` 0):
  ``remus_fibre_payout`` changed (its drum had been held to 0.2 m/s^2); every other run unchanged
  bit for bit.
* issue 30: the record gained ``max_compression`` at its end; every column before it, the nodes
  and tensions of every run unchanged bit for bit.
* issue 30: the tangle monitor's vehicle clearance counts the part of the first element beyond
  the hull (it had left the whole element out): ``cable_clearance`` of ``hong2020_platform``,
  ``otter_rov_launch``, ``remus_fibre_payout`` and ``rov_umbilical`` changed, nothing else.
* issue 30: the REMUS 100's volume is its mass over its trim water's density exactly (it was
  rounded to 7 figures): the REMUS and fibre-paying AUV runs moved by at most 8e-7 of a column's
  largest value; every other run unchanged bit for bit.
* issue 30: the REMUS 100 sums its cross-flow drag as Fossen's code does (``hull.crossflow =
  "fossen"``: 21 points of L/20, sway and yaw only): ``remus_fibre_payout`` changed (by 1.7e-2
  of a column's largest value), ``remus_turning_circle`` (9.5e-4), ``auv_fibre_spiral`` (2.8e-5)
  and ``auv_fibre_circle*`` (in columns that are zero to rounding); only those records were
  rewritten, every other run unchanged bit for bit.
* issue 30: a line that is not paying out lumps its first element half and half on its two
  nodes (``cable.drum.fairlead_share``), the Hong et al. cable takes their drag law
  (``tether.drag_law = "loading_functions"``), and a push above a tenth of an element's weight
  no longer survives a step when the element is still longer than its rest length
  (``cable.slack``). Every tethered run moved: the anchored and walker runs by at most 5e-3 of a
  column's largest value (``walker_ship_follows``' ship force 3 %, ``walker_bathymetry``'s
  3.5 %, both at a jerk of the cable), ``hong2020_platform`` by 3e-3; ``TetheredROV-v0``'s tow
  force at one step by 36 N of 44 (a slack tether's snap, sampled at its peak: 44 N before,
  8.9 N now); the fibre-paying AUV runs by rounding.
* issue 29 (tripod.txt): an element's wet part is its cylinder's below the surface, not its
  axis' (``hydro.wet_fraction``'s ``half_height``): a cable whose top node is at z = 0 loses the
  buoyancy and drag of the sliver above the surface. Every run with its fairlead at the surface
  moved by up to 3.1e-5 of a column's largest value (``static_anchor_current``), the walkers on
  uneven or followed ground by up to 2.9e-3 (``walker_bathymetry``, ``walker_ship_follows``:
  their gaits' footing); the envs' observations by at most 1.2e-6.
* issue 30 (the sheared current's convergence): each element's drag is taken at its two Gauss
  points and goes to its nodes by the lever rule (``hydro.GAUSS_POINTS``), in the dynamics and
  the statics alike; while paying out, the element next to the drum's splits its drag half and
  half. Every run in a current or moving through the water moved: the anchored and vehicle runs
  by at most 3.8e-3 of an array's largest value (``remus_fibre_payout``), the walkers by up to
  3.8e-2 (``walker_ship_follows``: its gait's footing), ``TetherWinch-v0``'s and
  ``TetheredWalker-v0``'s observations by 6e-3 (rewards by 0.21 and 6e-4); ``TetheredROV-v0``'s
  tow force at one step by 9 N of 18 (its slack tether's snap, sampled), its rewards by 0.02.
* one knot is 1852/3600 m/s exactly (``units.KNOT``; it was 0.514444, 8.6e-7 slow): every run
  with a speed in knots moved, the anchored runs and the environments by at most 8.3e-7 of an
  array's largest value, the walkers by up to 3.8e-3 (``walker_ship_follows``' rows,
  ``walker_bathymetry``'s 1.2e-3: their gaits' footing on thresholds); every other run
  unchanged bit for bit.
* a steady start falling onto a sloped or gridded seabed settles at the run's own step, not a
  quarter of it (``start.preroll``'s ``substeps``; the finer steps are for a guessed shape):
  ``walker_bathymetry`` and ``walker_up_slope`` start from another moment of their walkers'
  jitter, their tow forces (tens of N) moved by up to 27 N and 7 N, their ship tensions by up to
  0.6 % and 0.17 %, their nodes by up to 0.46 m and 0.10 m; every other run unchanged bit for bit.

    python tests/golden.py   # rewrites tests/data/golden_runs.npz
* issue 42 (the first part): ``max_compression`` is the largest push since the previous sample,
  not the sample step's: it moved in ``auv_fibre_pitch_down``, ``auv_fibre_straight`` and
  ``auv_fibre_zigzag`` (0 to 3.2e-7 N), ``walker_bathymetry`` (largest 0.042 to 0.095 N) and
  ``walker_ship_follows`` (8e-7 to 1.4e-3 N); every other column, node and tension of every run,
  and every environment, is bit for bit what the code before it (17d946e) gives on the machine
  that rewrote the file. That machine reports the same CPU label as the one before, but 17d946e
  already gave it other bits: rounding (at most 1e-11 of a value) and ``hong2020_platform``'s
  ``cable_wrap`` at 360 deg instead of 0 (a wrap angle on its seam), so the file was rewritten
  there (the seam is removed by issue 43's cost change below).
* issue 43: the record gained five columns at its end (``peak_tension``, ``snap_count``,
  ``wave_elevation``, ``fairlead_z``, ``heave_compensation``) and the snap detector runs at every
  step; the 37 columns before them, the nodes, tensions and environments of every run unchanged
  bit for bit (checked against the file before, on the machine that wrote both). The sea-state
  examples (``walker_sea_state``, ``walker_sea_state_compensated``) added; every other run,
  and the environments, unchanged bit for bit. Then the native callback took the waves: those
  two moved by rounding (at most 8e-10 N in a row, 5e-13 of a value; the walker body's loads
  summed in other order), nothing else. Then the ship's RAO motion at one time became
  compiled (``vessel_motion.motion_kernel``: each harmonic's cosine and sine in place of one
  complex exponential): those two moved by rounding again (at most 8e-10 N in a row), nothing
  else.
* issue 45's compiled tangle monitor found that the distance from an element to a vehicle's
  point (a thruster, a fin) was measured from the element's first node, not its nearest point
  (``tangle.segment_distance``, Ericson's case of a segment that is a point): fixed, the
  ``cable_clearance`` column of ``rov_umbilical`` and ``otter_rov_launch`` moved (by up to 1.5 m:
  0.40 m instead of 1.94 m); every other column and run unchanged bit for bit.
* issue 43's cost: the sea kernel and the ship's motion kernel fuse their multiply-adds
  (``compiled.jit(fma=True)``) and the ship's hull attitude is computed in the motion kernel
  (``ShipMotion.hull``, in place of MuJoCo's ``mju_euler2Quat`` and ``mju_mulQuat``): the two
  sea-state examples moved by rounding (at most 8e-10 N in a row, 4e-11 of a column's largest
  value; nodes by 3e-14 m). The plan-view wrap angle no longer counts an element that passes
  over the vehicle's centre (``tangle.wrap_angle``: a cable hanging straight under the hull had
  swept +-180 deg each side with a sign from rounding, 180 or 360 deg by CPU): ``cable_wrap`` of
  ``hong2020_platform`` and ``otter_rov_launch`` is 0, where it read 180 and 360. Every other
  column and run unchanged bit for bit (both files written on one Intel Xeon, before and after).
  The file is now this machine's.
"""

from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = sorted((ROOT / "examples").glob("*.toml"))
GOLDEN = ROOT / "tests" / "data" / "golden_runs.npz"
SECONDS = 2.0


def runs() -> dict[str, np.ndarray]:
    from mjtether.scenario.runner import run
    from mjtether.scenario import load_scenario

    out = {}
    for path in EXAMPLES:
        sc = load_scenario(path, overrides=[f"simulation.duration={SECONDS}", "simulation.output_interval=0.25"])
        rows, history, _ = run(sc)
        out[f"{path.stem}/rows"] = rows
        out[f"{path.stem}/nodes"] = history["nodes"][-1]
        out[f"{path.stem}/tension"] = history["tension"][-1]
    out.update(env_runs())
    return out


ENVS = ("mjtether/TetherWinch-v0", "mjtether/TetheredWalker-v0", "mjtether/TetheredROV-v0")


def env_runs(steps: int = 20) -> dict[str, np.ndarray]:
    """Each environment from ``reset(seed=3)`` for ``steps`` seeded random actions: the
    observations and rewards."""
    import gymnasium as gym

    import mjtether.envs  # noqa: F401 - registers the environments

    out = {}
    for env_id in ENVS:
        env = gym.make(env_id)
        try:
            env.action_space.seed(5)
            obs, _ = env.reset(seed=3)
            seen, rewards = [obs], []
            for _ in range(steps):
                obs, reward, terminated, truncated, _ = env.step(env.action_space.sample())
                seen.append(obs)
                rewards.append(reward)
                if terminated or truncated:
                    break
        finally:
            env.close()
        name = env_id.split("/")[1]
        out[f"{name}/obs"] = np.array(seen)
        out[f"{name}/reward"] = np.array(rewards)
    return out


def machine() -> str:
    """What the arithmetic depends on: the CPU (BLAS kernels are chosen by it) and the versions
    of NumPy, SciPy, MuJoCo and numba."""
    import platform

    import mujoco
    import numba
    import scipy

    cpu = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo") as f:
            cpu = next((line.split(":", 1)[1].strip() for line in f if line.startswith("model name")), cpu)
    except OSError:
        pass
    return f"{cpu} | numpy {np.__version__} | scipy {scipy.__version__} | mujoco {mujoco.__version__} | numba {numba.__version__}"


if __name__ == "__main__":
    np.savez_compressed(GOLDEN, **runs(), _machine=np.array(machine()))
    print(f"wrote {GOLDEN}")
