"""The EA a line keeps at a time step: where the step is too long for a stiff element's axial
mode, MuJoCo's constraint makes the element as stiff as the step allows and no stiffer
(``cable.builder``), so the cable stretches more than its EA says. ``softening`` reports the
element furthest below the EA asked for; ``warn`` says so once, naming the line, the effective
EA and how far it stretches. Units SI."""

from __future__ import annotations

import warnings

import numpy as np


class EAWarning(UserWarning):
    """A line runs softer than its EA at the time step taken."""


SOFT = 0.99
"""An element below this share of its EA is reported as softened."""


def softening(asked, effective) -> dict | None:
    """{"asked_N", "effective_N", "ratio"} of the element with the lowest effective / asked EA
    (N; ``asked`` a scalar or one per element, ``effective`` one per element), or None for an
    inextensible line (``asked`` None)."""
    if asked is None:
        return None
    eff = np.asarray(effective, dtype=float)
    asked = np.broadcast_to(np.asarray(asked, dtype=float), eff.shape)
    ratio = eff / asked
    worst = int(np.argmin(ratio))
    return {"asked_N": float(asked[worst]), "effective_N": float(eff[worst]), "ratio": float(ratio[worst])}


def warn(what: str, report: dict | None, timestep: float, keep: str = "", stacklevel: int = 3) -> None:
    """Warn (``EAWarning``) where ``report`` (``softening``) is below ``SOFT``: ``what`` names the
    key or line, ``keep`` says which step keeps the EA."""
    if report is None or report["ratio"] >= SOFT:
        return
    r = report["ratio"]
    warnings.warn(f"{what}: at simulation.timestep = {timestep:g} s the cable is as stiff as the step allows: "
                  f"effective EA {report['effective_N']:.3g} N of the {report['asked_N']:.3g} N asked "
                  f"({100 * r:.0f} %: it stretches {1 / r:.3g} times as much){keep}", EAWarning, stacklevel=stacklevel)
