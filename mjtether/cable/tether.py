"""Tether (umbilical) specification: geometry, mass, hydrodynamic coefficients, stiffness.

Names follow the ocean-engineering literature (MoorDyn/MoorPy): ``EA`` axial stiffness (N),
``EI`` bending stiffness (N m^2), ``cd_normal``/``cd_tangential`` drag coefficients (the
normal one on the projected area d*l, the tangential one on the wetted area pi*d*l) and
``ca_normal`` the normal added-mass coefficient.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from mjtether import _checks
from mjtether.physics.hydro import DRAG_LAWS

MAX_LENGTH = 1e5
"""Longest tether (m): 100 km."""
MAX_SEGMENTS = 5000
"""Most elements a tether may have (one MuJoCo body per node; the run costs about 1 us per element
and step, and MuJoCo's arena runs out in the tens of thousands)."""
MAX_COEFFICIENT = 10.0
"""Largest drag or added-mass coefficient a line takes (Cd, Ca; a cylinder's are near 1): a
guard against a typo, shared by tethers, make-up sections and network line types."""
MIN_AXIAL_DAMPING_RATIO, MAX_AXIAL_DAMPING_RATIO = 0.3, 10.0
"""Range of ``TetherSpec.axial_damping_ratio``. Measured (tests/cable/test_axial_damping_bound.py;
catenaries of 100-160 m between fixed points, started 5-30 % of an element off their static shape,
steps 1-20 ms): at 0 the run diverges within a second; at 0.05-0.15 the axial modes (slowed to
``builder.AXIAL_OMEGA_DT`` / dt, the constraint's damping applied explicitly) never settle: the top
tension swings between about 1 N and 2-50 kN and its mean is 2-360 % off; from 0.2-0.25 up it
settles on the closed-form catenary (mean within 0.05 %) as at 1. 0.3 leaves a margin."""
MAX_REACH_STRAIN = 1e-3
"""The most an elastic tether may be stretched to reach its ends at the start (a scenario's
``_check_reach`` and ``start.steady_start``): a taut line's stretch under its working load (Hong et
al.'s 3 m platform tether starts at 1.7e-5). Before, up to 10 % was let through: the default walker
with 205 m of tether for its 214 m span started near 220 kN and diverged in 0.06 s, blaming the step."""


ADDED_MASS = ("isotropic", "normal")
"""How a node carries its added mass: on all three axes, or normal to the cable only."""


@dataclass(frozen=True)
class TetherSpec:
    """A uniform tether.

    Attributes:
        length: unstretched deployed length L (m).
        segments: number of elements N (nodes 0..N, node 0 at the ship).
        diameter: hydrodynamic and buoyancy diameter d (m).
        density: cable bulk density (kg/m^3); give this or ``mass_per_length``.
        mass_per_length: cable mass per metre in air (kg/m); overrides ``density``.
        cd_normal: normal drag coefficient C_dn (on d*l).
        cd_tangential: tangential drag coefficient C_dt (on pi*d*l).
        ca_normal: normal added-mass coefficient C_a (on rho*A*l).
        EA: axial stiffness (N), or ``None`` for an inextensible tether (the solver then keeps
            the strain at working tension below 1e-3; see ``mjtether.cable.builder``).
        EI: bending stiffness (N m^2); 0 for a perfectly flexible cable.
        axial_damping_ratio: damping ratio of the axial (stretch) mode of one element, as the
            internal damping MoorDyn calls BA expressed relative to critical; in
            [MIN_AXIAL_DAMPING_RATIO, MAX_AXIAL_DAMPING_RATIO] (below, the tensions ring).
        added_mass: ``"isotropic"`` (default): each node's added mass C_a rho A l on all three
            axes, along the cable too, where a slender cylinder has none; ``"normal"``: normal to
            the cable only (see ``mjtether.cable.builder``), which reproduces the flexible jumper of Lowe
            and Langley (2006) but is not yet made safe with slack elements and touchdown.
        drag_law: ``"morison"`` (default): C_dn on the flow's normal part, C_dt on its tangential
            part (``physics.hydro.morison_drag``); ``"loading_functions"``: Hong et al.'s (2020,
            J. Mar. Sci. Eng. 8, 485) Eq. 20-21, ``cd_normal`` as the one C_d on d*l scaled by
            loading functions of the flow's angle to the cable, tangential part included
            (``physics.hydro.loading_function_drag``; ``cd_tangential`` unused). Runs on the
            NumPy kernels (the compiled ones and the native callback know Morison's only).
    """

    length: float
    segments: int = 60
    diameter: float = 0.02
    density: float | None = None
    mass_per_length: float | None = None
    cd_normal: float = 1.2
    cd_tangential: float = 0.008
    ca_normal: float = 1.0
    EA: float | None = None
    EI: float = 0.0
    axial_damping_ratio: float = 1.0
    added_mass: str = "isotropic"
    drag_law: str = "morison"

    def __post_init__(self):
        _checks.in_range("tether.length", self.length, 1e-3, MAX_LENGTH, "m")
        _checks.positive_int("tether.segments", self.segments, 1)
        if self.segments > MAX_SEGMENTS:
            raise ValueError(f"tether.segments must be an integer in [1, {MAX_SEGMENTS}], got {self.segments!r}")
        _checks.positive("tether.diameter", self.diameter, "m")
        if self.density is not None and self.mass_per_length is not None:
            raise ValueError("tether: give either density or mass_per_length, not both")
        if self.density is not None:
            _checks.in_range("tether.density", self.density, 1.0, 20000.0, "kg/m^3")
        if self.mass_per_length is not None:
            _checks.positive("tether.mass_per_length", self.mass_per_length, "kg/m")
        _checks.in_range("tether.cd_normal", self.cd_normal, 0.0, MAX_COEFFICIENT)
        _checks.in_range("tether.cd_tangential", self.cd_tangential, 0.0, MAX_COEFFICIENT)
        _checks.in_range("tether.ca_normal", self.ca_normal, 0.0, MAX_COEFFICIENT)
        if self.EA is not None:
            _checks.positive("tether.EA", self.EA, "N")
        _checks.non_negative("tether.EI", self.EI, "N m^2")
        zeta = _checks.finite("tether.axial_damping_ratio", self.axial_damping_ratio)
        if not MIN_AXIAL_DAMPING_RATIO <= zeta <= MAX_AXIAL_DAMPING_RATIO:
            why = ": below it the cable's stretch modes do not settle (the tensions swing or diverge)" \
                if zeta < MIN_AXIAL_DAMPING_RATIO else ""
            raise ValueError(f"tether.axial_damping_ratio must be in [{MIN_AXIAL_DAMPING_RATIO}, "
                             f"{MAX_AXIAL_DAMPING_RATIO}] (fraction of critical), got {self.axial_damping_ratio!r}{why}")
        if self.added_mass not in ADDED_MASS:
            raise ValueError(f"tether.added_mass must be one of {', '.join(ADDED_MASS)}, got {self.added_mass!r}")
        if self.drag_law not in DRAG_LAWS:
            raise ValueError(f"tether.drag_law must be one of {', '.join(DRAG_LAWS)}, got {self.drag_law!r}")

    @property
    def area(self) -> float:
        """Cross-section area A = pi d^2 / 4 (m^2)."""
        return math.pi * self.diameter**2 / 4.0

    @property
    def mu(self) -> float:
        """Mass per unit length in air (kg/m); 1025 kg/m^3 bulk density if nothing is given."""
        if self.mass_per_length is not None:
            return float(self.mass_per_length)
        rho_c = 1025.0 if self.density is None else self.density
        return rho_c * self.area

    @property
    def segment_length(self) -> float:
        """Unstretched element length l = L / N (m)."""
        return self.length / self.segments

    @property
    def inextensible(self) -> bool:
        return self.EA is None

    def wet_weight_per_length(self, rho_water: float, gravity: float = 9.81) -> float:
        """Submerged weight per metre w = (mu - rho A) g (N/m); negative if buoyant."""
        return (self.mu - rho_water * self.area) * gravity
