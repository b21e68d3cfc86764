"""``mjtether/TetherWinch-v0``: pay out and reel in the tether behind a walker on a scripted route.

The hexapod walker sets off from ``start_distance`` m ahead of a ship holding station, on a
seabed ``depth`` m down, and follows a route drawn at each reset: three legs of equal duration
over ``route_duration`` s, each at a speed in [0.15, 0.45] m/s, half of them turning at up to
0.06 rad/s. The current is exponential in depth, with a surface speed up to ``current_max_kn``,
a decay depth in [10, 40] m and any heading. The agent commands the winch.

Action (``Box(-1, 1, (1,))``): the payout rate as a fraction of ``max_rate`` (m/s; negative reels
in). The drum follows it at up to ``max_accel`` (m/s^2, default 0.2).

``sea_state`` (default None: a flat sea, the ship holding station at rest; the environment is
then exactly as without it) puts the ship in waves: a dict of the scenario's ``[waves]`` keys
(``mjtether.scenario.sea.Waves``: ``{"type": "regular", "height": 3, "period": 9}``, ``{"type":
"jonswap", "hs": 3, "tp": 9}``, ...) and, for the ship's motion, ``"motion"`` (a dict of
``[ship.motion]`` keys: ``{"type": "rao", "rao_file": ..., "fairlead_m": [x, y, z]}``; a relative
``rao_file`` is read from the working folder) or a prescribed heave (``"heave_amplitude"`` m,
``"heave_period"`` s: ``[ship]``'s sinusoid), not both. Without either, in waves, the ship rides
on the shipped box barge's heave and pitch RAOs (``BOX_BARGE_RAOS``, the fairlead at their
reference point: heave only; components shorter than the table's 3 s move it not at all);
``{"motion": {"type": "none"}}`` keeps it still (the waves then act on the line only). The sea
goes into the scenario each episode is built from (its ``[waves]`` and ``[ship]`` tables).
A JONSWAP or Pierson-Moskowitz sea without a ``"seed"`` draws its phases' seed from the
environment's generator at each reset (after the route and current, which are then those of the
flat-sea environment at the same reset seed): ``reset(seed=s)`` gives the same sea again, and
each unseeded reset a new one; with a ``"seed"``, every episode has the same sea.

Observation (``Box``, float32, physical units, 16 values, 18 with a ``sea_state``, clipped to the bounds):

====  ==================================================  =========================
 0    deployed length (m)                                 [0, max_length]
 1    ship-end tension (N)                                [0, 2 rated_load]
 2    tow-point tension (N)                               [0, 2 rated_load]
 3    horizontal distance of the tow point from the ship  [0, 1e4] m
 4-5  sin, cos of its bearing from the ship (from +x)     [-1, 1]
 6    the walker's horizontal speed (m/s)                 [0, 3]
 7    its range rate, d(distance)/dt (m/s)                [-3, 3]
 8-13 current (x, y) at 5 %, 25 % and 75 % of the depth   [-5, 5] m/s
 14   tether length lying on the seabed (m)               [0, max_length]
 15   the drum's payout rate now (m/s)                    [-max_rate, max_rate]
 16   sea_state only: the fairlead's heave (m, up, about   [-30, 30]
      its mean: the ship's motion in the waves)
 17   sea_state only: its heave velocity (m/s)             [-30, 30]
====  ==================================================  =========================

Reward per step (dimensionless, per ``dt`` = frame_skip x timestep s)::

    r = - w_tension  * T_tow / T_ref                      (keep the tow tension low ...)
        - w_steady   * |T_tow - T_tow,prev| / T_ref        (... and steady)
        - w_slack    * max(0, L_seabed - slack_allowance) / slack_allowance   (no excess on the bottom)
        - failure_penalty  on termination
    and with a ``sea_state``, the snap-load terms on the ship-end (top) tension T_top:
        - w_excursion  * max(0, max T_top - T_static) / T_ref     (its peak in the step above static)
        - w_slack_time * n_slack / frame_skip                     (the part of the step spent slack)
        - w_snap       * max(0, T_peak - T_static) / T_ref        (once per slack-to-taut event)

with T_ref = ``tension_ref`` N. The snap terms read T_top at each of the step's ``frame_skip``
physics steps (a snap's peak lasts less than a step). T_static is the top tension at the
episode's start (the steady start); the line is slack while T_top < ``slack_fraction`` T_static
(DNV-RP-H103's criterion is 10 % of the static submerged weight: here the static top tension
stands for it), n_slack the physics steps of the step it was; a slack-to-taut event is the line
going slack and taut again, T_peak the first maximum of T_top after it is taut again (the snap),
charged at the physics step after that maximum. ``_get_rew`` returns the terms.

The episode terminates when the ship-end tension exceeds the rated load or the deployed length
reaches ``min_length`` or ``max_length``; it is truncated by ``max_episode_steps`` (600: 60 s at
the default 0.1 s per step).

``info`` holds the reward terms (``reward_tension``, ``reward_steady``, ``reward_slack``,
``reward_failure``; with a ``sea_state`` also ``reward_excursion``, ``reward_slack_time``,
``reward_snap``), the tensions, the deployed length, the tow point's position and the walker's
speed; with a ``sea_state`` also the fairlead's heave and heave velocity (``fairlead_heave`` m,
``fairlead_heave_velocity`` m/s), the top tension's extremes over the step (``top_tension_max``,
``top_tension_min``, N), ``static_tension`` (N) and the slack-to-taut events so far
(``snap_events``: a list of dicts with ``time`` s at the peak, ``peak_tension`` N, ``slack_s``).
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

import numpy as np
from gymnasium import spaces

from mjtether.scenario.config import ConfigError, build, param, params
from mjtether.scenario.runner import RunFailed
from mjtether.scenario.sea import Waves
from mjtether.scenario.sections import Ship

from .base import TetherEnv, TetherEnvConfig, _finite_action, kwargs_table

WAVE_KEYS = tuple(params(Waves))
"""The ``[waves]`` keys a ``sea_state`` may hold."""
SHIP_KEYS = ("motion", "heave_amplitude", "heave_period")
"""Its keys for the ship's motion: ``[ship.motion]`` (a dict) or ``[ship]``'s prescribed heave."""
SEEDED = ("jonswap", "pierson_moskowitz")
BOX_BARGE_RAOS = "raos/box_barge_heave_pitch.csv"
"""The RAO table a ship in waves rides on by default, in the shipped examples' folder."""
HEAVE_BOUND = 30.0
"""Bounds (m, m/s) of the observed fairlead heave and heave velocity."""


@dataclass(frozen=True)
class TetherWinchConfig(TetherEnvConfig):
    """``TetherWinch-v0``'s keyword arguments: the site and tether, the route, the reward."""

    route_duration: float = param(60.0, 1.0, 1e5, "s", "duration of the three-leg route")
    max_accel: float = param(0.2, 0.01, 10.0, "m/s^2", "fastest change of the drum's payout rate")
    tension_ref: float = param(500.0, 1.0, 1e8, "N", "T_ref, the reward's tension scale")
    slack_allowance: float = param(10.0, 0.1, 1e4, "m", "tether on the seabed before w_slack applies")
    w_tension: float = param(1.0, 0.0, 1e3, "", "weight of the tow tension")
    w_steady: float = param(0.5, 0.0, 1e3, "", "weight of the change in tow tension")
    w_slack: float = param(0.5, 0.0, 1e3, "", "weight of excess cable on the seabed")
    failure_penalty: float = param(50.0, 0.0, 1e6, "", "penalty on termination")
    slack_fraction: float = param(0.1, 0.0, 1.0, "", "sea_state: the line is slack below this part of "
                                  "T_static")
    w_excursion: float = param(1.0, 0.0, 1e3, "", "sea_state: weight of the top tension's peak above T_static")
    w_slack_time: float = param(1.0, 0.0, 1e3, "", "sea_state: weight of the time the line is slack")
    w_snap: float = param(5.0, 0.0, 1e3, "", "sea_state: weight of a slack-to-taut event's peak")


def _sea_key(text: str) -> str:
    """A scenario key path in ``text`` as the ``sea_state`` dict names it."""
    text = re.sub(r"\bship\.motion\.(\w+)", r"sea_state['motion']['\1']", text)
    text = re.sub(r"\bship\.(\w+)", r"sea_state['\1']", text)
    return re.sub(r"\bwaves\.(\w+)", r"sea_state['\1']", text)


def sea_sections(sea_state) -> tuple[dict, dict] | None:
    """The ``[waves]`` and ``[ship]`` entries (plain dicts, checked) of a ``sea_state``, or None
    for None; a ValueError naming ``sea_state`` and the key otherwise."""
    if sea_state is None:
        return None
    allowed = ", ".join(WAVE_KEYS + SHIP_KEYS)
    if not isinstance(sea_state, dict):
        raise ValueError(f"sea_state must be None or a dict of [waves] keys ({allowed}), got {sea_state!r}")
    unknown = sorted(str(k) for k in set(sea_state) - set(WAVE_KEYS + SHIP_KEYS))
    if unknown:
        raise ConfigError(f"sea_state: unknown key {unknown[0]!r}; allowed: {allowed}", "sea_state")
    waves = {k: v for k, v in sea_state.items() if k in WAVE_KEYS}
    ship = {k: v for k, v in sea_state.items() if k in SHIP_KEYS}
    if "motion" in ship and ("heave_amplitude" in ship or "heave_period" in ship):
        raise ConfigError("sea_state: give the ship's motion as 'motion' ([ship.motion]) or as a prescribed heave "
                          "('heave_amplitude', 'heave_period'), not both", "sea_state")
    if isinstance(ship.get("motion"), dict):
        ship["motion"] = dict(ship["motion"])
        rao = ship["motion"].get("rao_file")
        if isinstance(rao, str) and rao:  # (from the working folder now: resets may run elsewhere)
            from pathlib import Path
            ship["motion"]["rao_file"] = str(Path(rao).resolve())
    try:
        flat = build(Waves, waves).flat
        build(Ship, ship)
    except ConfigError as exc:
        raise ConfigError(f"sea_state: {_sea_key(str(exc))}", "sea_state") from None
    if not flat and not ship:  # (the default: the ship rides on the box barge's RAOs)
        from mjtether.files.packagedata import examples_dir
        ship = {"motion": {"type": "rao", "rao_file": str(examples_dir() / BOX_BARGE_RAOS), "short_waves": "zero"}}
    return waves, ship


class TetherWinchEnv(TetherEnv):
    """See the module docstring."""

    Config = TetherWinchConfig

    def __init__(self, *, sea_state: dict | None = None, **kwargs):
        self.sea = sea_sections(sea_state)  # (checked first: a bad one is named before anything is built)
        super().__init__(**kwargs)
        if sea_state is not None:  # (what pickling keeps)
            self._init_kwargs["sea_state"] = dict(sea_state)
        self.sea_state = sea_state
        T2 = 2.0 * self.rated_load
        lo = [0.0, 0.0, 0.0, 0.0, -1.0, -1.0, 0.0, -3.0] + [-5.0] * 6 + [0.0, -self.max_rate]
        hi = [self.max_length, T2, T2, 1e4, 1.0, 1.0, 3.0, 3.0] + [5.0] * 6 + [self.max_length, self.max_rate]
        if self.sea is not None:
            lo, hi = lo + [-HEAVE_BOUND] * 2, hi + [HEAVE_BOUND] * 2
        self.observation_space = spaces.Box(np.array(lo, np.float32), np.array(hi, np.float32), dtype=np.float32)
        self.action_space = spaces.Box(-1.0, 1.0, (1,), dtype=np.float32)

    def _robot_section(self, rng):
        legs = 3
        t = np.arange(legs) * self.route_duration / legs
        speed = rng.uniform(0.15, 0.45, legs)
        turn = np.where(rng.uniform(size=legs) < 0.5, 0.0, rng.uniform(-0.06, 0.06, legs))
        heading = float(rng.uniform(-0.5, 0.5))
        start = [self.start_distance * math.cos(heading), self.start_distance * math.sin(heading)]
        return {"type": "walker", "start": start, "heading_deg": math.degrees(heading),
                "commands": [[float(a), float(b), math.degrees(c)] for a, b, c in zip(t, speed, turn)]}

    def _scenario(self, rng):
        data = super()._scenario(rng)
        data["winch"]["max_accel"] = self.max_accel  # (the default is the driven winch's own, DRIVEN_ACCEL)
        if self.sea is not None:
            waves, ship = self.sea
            data["waves"] = dict(waves)
            if waves.get("type") in SEEDED and "seed" not in waves:  # (drawn last: see the module docstring)
                data["waves"]["seed"] = int(rng.integers(0, 2**31 - 1))
            data["ship"].update(ship)
        return data

    # ---------------------------------------------------------------- gymnasium API

    def reset(self, *, seed=None, options=None):
        self._start_episode(seed)
        tow, _, _ = self.robot_kinematics()
        self._prev_distance = float(np.hypot(tow[0], tow[1]))
        self._static = self.ship_tension()
        self._top = np.array([self._static])
        self._slack_since = self._peak = None  # (s: the time the line went slack; N: the snap's peak so far)
        self.snap_events = []
        self._human_frame()
        ro = self._readouts()
        return self._get_obs(ro), self._info({}, ro)

    def step(self, action):
        if self.runner is None:
            raise RuntimeError("call reset() before step()")
        a = float(_finite_action(action, 1)[0])
        self.runner.winch.command(a * self.max_rate)
        self._advance()
        ro = self._readouts()
        obs = self._get_obs(ro)
        terminated = bool(self.broke or self.at_length_limit())
        reward, terms = self._get_rew(ro, terminated)
        self._prev_tow = ro["tow_tension"]
        self._human_frame()
        return obs, reward, terminated, False, self._info(terms, ro)

    def _get_rew(self, ro: dict, terminated: bool) -> tuple[float, dict]:
        """(reward, its terms by name) for the step just taken (see the module docstring)."""
        tow = ro["tow_tension"]
        terms = {
            "reward_tension": -self.w_tension * tow / self.tension_ref,
            "reward_steady": -self.w_steady * abs(tow - self._prev_tow) / self.tension_ref,
            "reward_slack": -self.w_slack * max(0.0, ro["length_on_seabed"] - self.slack_allowance)
            / self.slack_allowance,
        }
        terms["reward_failure"] = -self.failure_penalty if terminated else 0.0
        if self.sea is not None:
            top, over = self._top, self._snap_peaks
            terms["reward_excursion"] = -self.w_excursion * max(0.0, float(top.max()) - self._static) / self.tension_ref
            terms["reward_slack_time"] = -self.w_slack_time * self._slack_steps / self.frame_skip
            terms["reward_snap"] = -self.w_snap * sum(max(0.0, p - self._static) for p in over) / self.tension_ref
        return float(sum(terms.values())), terms

    def _advance(self) -> None:
        """``frame_skip`` physics steps; with a ``sea_state``, the top tension at each of them
        and the slack-to-taut events they hold."""
        if self.sea is None:
            return super()._advance()
        top = []
        try:
            for _ in range(self.frame_skip):
                self.runner.step()
                top.append(self.ship_tension())
        except RunFailed:
            self.broke = True
        self._top = np.array(top or [self.ship_tension()])
        self._slack_steps, self._snap_peaks = 0, []
        slack, t0 = self.slack_fraction * self._static, self.runner.named.time - len(top) * self.timestep
        for k, T in enumerate(top):
            t = t0 + (k + 1) * self.timestep
            if T < slack:
                self._slack_steps += 1
                if self._peak is not None:  # (slack again before a maximum: the snap so far is one)
                    self._end_snap()
                if self._slack_since is None:
                    self._slack_since = t
            elif self._slack_since is not None and self._peak is None:  # taut again: the snap begins
                self._peak, self._peak_t, self._slack_s = T, t, t - self._slack_since
            elif self._peak is not None and T >= self._peak:
                self._peak, self._peak_t = T, t
            elif self._peak is not None:  # past its first maximum
                self._end_snap()

    def _end_snap(self) -> None:
        """Record the slack-to-taut event whose peak has passed."""
        self._snap_peaks.append(self._peak)
        self.snap_events.append({"time": self._peak_t, "peak_tension": self._peak, "slack_s": self._slack_s})
        self._peak = self._slack_since = None

    # ---------------------------------------------------------------- observation

    def fairlead_heave(self) -> tuple[float, float]:
        """The fairlead's heave (m, up, about its mean) and heave velocity (m/s) now, as a
        motion reference unit on the ship measures them (0, 0 on a flat sea)."""
        offset, velocity = self.runner.ship.wave_motion(self.runner.named.time)
        return float(offset[2]), float(velocity[2])

    def _readouts(self) -> dict:
        """What the observation, the reward and ``info`` read, once per step (N, m, m/s, world)."""
        n = self.runner.named
        tow, _, v = self.robot_kinematics()
        ro = {"ship_tension": n.ship_tension, "tow_tension": n.tow_tension, "length_on_seabed": self.length_on_seabed(),
              "tow_point": tow, "velocity": v}
        if self.sea is not None:
            ro["heave"] = self.fairlead_heave()
        return ro

    def _get_obs(self, ro: dict) -> np.ndarray:
        n = self.runner.named
        tow, v = ro["tow_point"], ro["velocity"]
        dist = float(np.hypot(tow[0], tow[1]))
        bearing = math.atan2(tow[1], tow[0])
        radial = float(v @ (tow[:2] / max(dist, 1e-9)))
        obs = np.array([n.deployed_length, ro["ship_tension"], ro["tow_tension"], dist,
                        math.sin(bearing), math.cos(bearing), float(np.hypot(*v)), radial,
                        *self.currents(), ro["length_on_seabed"], n.payout_rate, *ro.get("heave", ())],
                       dtype=np.float32)
        return np.clip(obs, self.observation_space.low, self.observation_space.high)

    def _info(self, terms: dict, ro: dict) -> dict:
        n = self.runner.named
        info = {**terms, "ship_tension": ro["ship_tension"], "tow_tension": ro["tow_tension"],
                "deployed_length": n.deployed_length, "tow_point": ro["tow_point"],
                "robot_speed": float(np.hypot(*ro["velocity"])), "length_on_seabed": ro["length_on_seabed"],
                "rated_load_exceeded": self.broke, "time": n.time}
        if self.sea is not None:
            info.update(fairlead_heave=ro["heave"][0], fairlead_heave_velocity=ro["heave"][1],
                        top_tension_max=float(self._top.max()), top_tension_min=float(self._top.min()),
                        static_tension=self._static, snap_events=list(self.snap_events))
        return info


TetherWinchEnv.__doc__ += kwargs_table(TetherWinchConfig) + (
    "\nAnd ``sea_state`` (default None): the waves and the ship's motion, a dict (see the module docstring).\n")
