"""Write box_barge_heave_pitch.csv: ILLUSTRATIVE heave and pitch RAOs of a 60 m x 12 m x 3 m-draft
box barge from single-DOF closed forms (not a hydrodynamic analysis; no radiation/diffraction
solution, no coupling, surge/sway/roll/yaw left at zero).

Run: ``python examples/raos/box_barge_heave_pitch.py`` (rewrites the csv beside it).

Model (SI, deep water k = omega^2 / g, ship axes x forward, y to port, z up, origin at the
waterplane centre, which is the RAO and phase origin; wave heading b relative to the barge, the
direction of travel, 0 = from astern; kappa = k cos b):

- Froude-Krylov excitation of the undisturbed wave, with the Smith factor exp(-k T) for the
  pressure's decay to the keel, integrated over the length:
  heave force F3 = rho g B L exp(-kT) a sin(u)/u, u = kappa L / 2 (at the crest time);
  pitch moment (about +y, bow down positive) M5 = Re{i rho g B exp(-kT) a (L^2/2)
  (sin u - u cos u)/u^2 e^{i omega t}};
- mass m = rho L B T; pitch inertia m (0.25 L)^2;
- heave added mass A33 = 0.5 * 0.897 * rho (pi/4) B^2 L: DNV-RP-H103 (2011) Table A-2, a flat
  rectangular plate of side ratio 5 in infinite fluid (C_A = 0.897), halved for the free
  surface; pitch added inertia A55 = A33 L^2 / 12 (uniform along the length);
- stiffness C33 = rho g L B, C55 = rho g B L^3 / 12 (waterplane inertia only);
- linear damping 10 % of critical in each DOF (a stated guess);
- X = F / (C - omega^2 (M + A) + i omega Bd); phase lag (OrcaFlex) = -arg X.
"""

from pathlib import Path

import numpy as np

RHO, G = 1025.0, 9.81
L, B, T = 60.0, 12.0, 3.0
ZETA = 0.10
PERIODS = np.arange(3.0, 26.0, 1.0)
HEADINGS = np.array([0.0, 45.0, 90.0, 135.0, 180.0])


def raos(period, heading_deg):
    """(heave, pitch) complex RAOs: m/m and rad/m, motion Re{X a e^{i omega t}}."""
    w = 2 * np.pi / period
    k = w * w / G
    kappa = k * np.round(np.cos(np.radians(heading_deg)), 12)  # (exactly 0 in a beam sea)
    u = kappa * L / 2
    smith = np.exp(-k * T)
    sinc = np.sinc(u / np.pi)
    lever = (L * L / 2) * np.where(abs(u) > 1e-6, (np.sin(u) - u * np.cos(u)) / np.where(u == 0, 1, u) ** 2, u / 3)
    m = RHO * L * B * T
    a33 = 0.5 * 0.897 * RHO * np.pi / 4 * B * B * L
    i55, a55 = m * (0.25 * L) ** 2, a33 * L * L / 12
    c33, c55 = RHO * G * L * B, RHO * G * B * L ** 3 / 12
    d33, d55 = 2 * ZETA * np.sqrt(c33 * (m + a33)), 2 * ZETA * np.sqrt(c55 * (i55 + a55))
    heave = c33 * smith * sinc / (c33 - w * w * (m + a33) + 1j * w * d33)
    pitch = 1j * RHO * G * B * smith * lever / (c55 - w * w * (i55 + a55) + 1j * w * d55)
    return heave, pitch


def _lag(x: complex) -> float:
    """OrcaFlex's phase lag (deg) of a complex RAO; 0 where the RAO is 0."""
    return float(-np.degrees(np.angle(x))) + 0.0 if x != 0 else 0.0


HEADER = """\
# mjtether displacement RAO table: box barge 60 m x 12 m x 3 m draft, HEAVE AND PITCH ONLY
# ILLUSTRATIVE: single-DOF closed forms (Froude-Krylov excitation with the Smith factor,
# heave added mass from DNV-RP-H103 Table A-2 halved, 10 % critical damping), NOT a
# hydrodynamic analysis; surge, sway, roll and yaw are not modelled and are zero. The
# formulas and their sources: box_barge_heave_pitch.py beside this file, which writes it.
# Reference point (RAO and phase origin): waterplane centre (midships, centreline, z = 0).
# Ship axes x forward, y to port, z up; rotations right-handed (pitch positive bow down).
# Headings: the waves' direction of travel relative to the ship, 0 = from astern.
# Phases: OrcaFlex's lag from the crest at the origin: x(t) = A a cos(omega t - phase).
# Amplitudes: m per m of wave amplitude; rotations deg per m. Deep water, zero speed.
# convention = orcaflex
# symmetric = true
"""


def main() -> None:
    cols = ["period_s", "heading_deg"]
    for d, unit in zip(("surge", "sway", "heave", "roll", "pitch", "yaw"), ("m",) * 3 + ("deg",) * 3):
        cols += [f"{d}_amp_{unit}_per_m", f"{d}_phase_deg"]
    lines = [",".join(cols)]
    for period in PERIODS:
        for h in HEADINGS:
            heave, pitch = raos(period, h)
            values = [0.0, 0.0, 0.0, 0.0, abs(heave), _lag(heave), 0.0, 0.0, np.degrees(abs(pitch)), _lag(pitch),
                      0.0, 0.0]
            lines.append(f"{period:g},{h:g}," + ",".join(f"{v:.6g}" for v in values))
    Path(__file__).with_suffix(".csv").write_text(HEADER + "\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
