"""The sea state and what rides on it, as configuration: ``[waves]`` (regular or irregular
linear waves, ``physics.waves``), ``[ship.motion]`` (the ship's response to them from a table of
displacement RAOs, ``physics.vessel_motion``) and ``[winch.heave_compensation]`` (active or
passive, ``cable.heave_compensation``). SI units, angles in degrees at this edge (radians inside).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from .config import Section, param

WAVE_TYPES = ("none", "regular", "jonswap", "pierson_moskowitz")


@dataclass(frozen=True)
class Waves(Section):
    PATH = "waves"
    type: str = param("none", doc="none (a flat sea), regular (one Airy wave), jonswap or pierson_moskowitz (an "
                      "irregular sea summed from components)", choices=WAVE_TYPES)
    height: float = param(0.0, 0.0, 40.0, "m", "regular: crest-to-trough height")
    period: float = param(8.0, 1.0, 40.0, "s", "regular: period")
    phase_deg: float = param(0.0, -360.0, 360.0, "deg", "regular: phase (the elevation at x = y = 0 is "
                             "H/2 cos(phase - omega t))")
    hs: float = param(2.0, 0.01, 30.0, "m", "jonswap/pierson_moskowitz: significant wave height")
    tp: float = param(9.0, 1.0, 40.0, "s", "jonswap/pierson_moskowitz: peak period")
    gamma: float = param(3.3, 1.0, 7.0, "", "jonswap: peak enhancement factor (DNV-RP-C205's form)")
    seed: int = param(0, 0, 2**31 - 1, "", "jonswap/pierson_moskowitz: the random phases' seed (a sea state is "
                      "reproducible)")
    components: int = param(100, 1, 2000, "", "jonswap/pierson_moskowitz: frequency components summed")
    spreading_s: float = param(0.0, 0.0, 100.0, "", "jonswap/pierson_moskowitz: cos-2s directional spreading "
                               "exponent s (0: long-crested)")
    directions: int = param(9, 1, 101, "", "jonswap/pierson_moskowitz: directions summed with spreading_s > 0")
    heading_deg: float = param(0.0, -360.0, 360.0, "deg", "direction the waves travel to, from +x towards +y")
    ramp_periods: float = param(1.0, 0.0, 100.0, "", "the sea's build-up: the waves and the ship's motion on them "
                                "ramp in over this many wave periods (period, or tp) from t = 0 (a half-cosine, as "
                                "OrcaFlex's build-up stage), so that the line does not start with a jerk; 0: the full "
                                "sea from the start")
    stretching: str = param("wheeler", doc="kinematics above the mean water line: wheeler (the profile stretched "
                            "to the instantaneous surface) or none (linear theory cut at z = 0)",
                            choices=("wheeler", "none"))

    def _check(self):
        if self.type == "regular" and self.height <= 0.0:
            self._bad("height", "must be > 0 m for waves.type = 'regular' (or set waves.type = 'none')")

    @property
    def flat(self) -> bool:
        return self.type == "none"


def wave_field(waves: Waves, depth: float, gravity: float):
    """The ``physics.waves.WaveField`` of ``waves`` in water ``depth`` m deep (the dispersion's
    depth) under ``gravity`` m/s^2, or None for a flat sea."""
    if waves.flat:
        return None
    from mjtether.physics import waves as wv
    heading = math.radians(waves.heading_deg)
    if waves.type == "regular":
        comps = wv.regular(waves.height, waves.period, heading, depth, gravity, math.radians(waves.phase_deg))
    else:
        spread = {} if waves.spreading_s <= 0.0 else {"spreading_s": waves.spreading_s,
                                                       "n_directions": waves.directions}
        make = wv.jonswap if waves.type == "jonswap" else wv.pierson_moskowitz
        kw = {"gamma": waves.gamma} if waves.type == "jonswap" else {}
        comps = make(waves.hs, waves.tp, heading=heading, depth=depth, g=gravity, seed=waves.seed,
                     n_components=waves.components, **kw, **spread)
    ramp = waves.ramp_periods * (waves.period if waves.type == "regular" else waves.tp)
    return wv.WaveField(comps, depth, gravity, stretching=waves.stretching, ramp_s=ramp)


@dataclass(frozen=True)
class ShipMotion(Section):
    PATH = "ship.motion"
    type: str = param("none", doc="none (the ship's path only, with ship.heave_amplitude's sinusoid) or rao (its "
                      "wave-frequency motion in the [waves] sea from a table of displacement RAOs)",
                      choices=("none", "rao"))
    rao_file: str = param("", doc="rao: the RAO table (a CSV, relative to the scenario file; its header names the "
                          "phase convention, orcaflex or wamit: see mjtether.physics.vessel_motion)")
    fairlead_m: tuple = param((0.0, 0.0, 0.0), -500.0, 500.0, "m", "rao: the fairlead in ship axes (x forward, "
                              "y to port, z up) from the RAOs' reference point: the lever arm of the ship's roll, "
                              "pitch and yaw (the fairlead itself is at ship.position, ship.fairlead_z)", kind="vec3")
    short_waves: str = param("error", doc="rao: a wave component shorter than the table's shortest period is "
                             "refused (error) or moves the ship not at all (zero: a ship does not follow waves much "
                             "shorter than itself; an irregular sea's tail reaches 0.2 Tp)", choices=("error", "zero"))

    def _check(self):
        if self.type != "rao":
            return
        if not self.rao_file:
            self._bad("rao_file", "is required with ship.motion.type = 'rao'")
        from mjtether.physics.vessel_motion import RAOTable
        try:
            RAOTable.from_csv(self.rao_file)
        except (OSError, ValueError) as exc:
            self._bad("rao_file", str(exc))


@dataclass(frozen=True)
class HeaveCompensation(Section):
    PATH = "winch.heave_compensation"
    type: str = param("none", doc="none, active (the drum pays out and reels in against the fairlead's measured "
                      "heave, within the winch's max_rate and max_accel) or passive (a spring-damper in the line at "
                      "the winch)", choices=("none", "active", "passive"))
    lag_s: float = param(0.0, 0.0, 10.0, "s", "active: the measurement's delay")
    gain: float = param(1.0, 0.0, 2.0, "", "active: the part of the heave compensated")
    stiffness: float = param(1e5, 1.0, 1e9, "N/m", "passive: the compensator's spring")
    damping: float = param(0.0, 0.0, 1e9, "N s/m", "passive: its damper")
    stroke: float = param(10.0, 0.01, 100.0, "m", "the most line the compensation may pay out (the drum's "
                          "default max_length grows by it); passive: its full stroke")


def compensator_from(sc):
    """The winch's heave compensator (``cable.heave_compensation``) for the scenario ``sc``, or
    None: active within the winch's max_rate and max_accel, or passive."""
    hc = sc.winch.heave_compensation
    if hc.type == "none":
        return None
    from mjtether.cable import heave_compensation as h
    if hc.type == "active":
        return h.ActiveHeaveCompensation(hc.lag_s, sc.winch.max_rate, sc.winch.max_accel, hc.gain)
    return h.PassiveHeaveCompensation(hc.stiffness, hc.damping, stroke_m=hc.stroke)


def check_scenario(sc, bad) -> None:
    """The sea's checks across sections: RAOs answer a sea (``ship.motion.type = "rao"`` needs
    ``[waves]``), heave compensation needs a tether, and the vessel model (``ship.vessel``) moves
    on its own hydrodynamics, not on RAOs. ``bad(key, value, why)`` raises."""
    if sc.ship.motion.type == "rao" and sc.waves.flat:
        bad("ship.motion.type", '"rao"', "answers a sea: give [waves] (waves.type is \"none\")")
    if sc.ship.motion.type == "rao" and sc.ship.vessel:
        bad("ship.motion.type", '"rao"', "is for a prescribed ship: a vessel (ship.vessel) moves in the waves on its "
            "own hydrodynamics")
    if sc.winch.heave_compensation.type != "none" and not sc.tether.attached:
        bad("winch.heave_compensation.type", repr(sc.winch.heave_compensation.type), "needs a tether")
