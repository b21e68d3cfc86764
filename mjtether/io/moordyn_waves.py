"""MoorDyn-C 2.7's waves given as frequency components (``WaveKin`` 2 and 7): the side file
``wave_frequencies.txt`` read as MoorDyn-C reads it (``Waves/WaveSpectrum.cpp``,
``spectrumFromFile``; ``Waves/WaveGrid.cpp``, ``constructWaveGridSpectrumData``;
``Waves/SpectrumKin.cpp``) and written as ``physics.waves.WaveComponents``' rows.

The file sits beside the input file (MoorDyn-C looks in the input file's folder). Every line is
one component: ``omega re im [beta]``, omega the angular frequency (rad/s, the first row 0 and
ascending), ``re + i im`` its complex amplitude (m), beta the direction it travels towards (rad,
from +x towards +y, in [-2 pi, 2 pi]; 0 when left out). With A = re + i im, phi = arg A and
l = x cos beta + y sin beta, MoorDyn-C's surface is

* ``WaveKin 7`` (``SpectrumKin``, the components summed at each node):
  eta = sum |A| sin(omega t - k l + phi);
* ``WaveKin 2`` (``fillWaveGrid``: an inverse FFT of A times nt / 2 on the grid of
  ``water_grid.txt``): eta = sum Re(A exp(i (omega t - k l))) = sum |A| cos(omega t - k l + phi).

mjtether's components are eta = sum a cos(k l - omega t + p) (``WaveComponents``), so
a = |A|, the heading is beta, and the phase is p = pi/2 - phi under WaveKin 7 and p = -phi under
WaveKin 2 (cos is even; sin x = cos(pi/2 - x)). Both MoorDyn-C forms give the linear Airy
kinematics of that surface, Wheeler-stretched to the instantaneous surface, with the
dispersion relation at WtrDpth, as mjtether's ``WaveField`` does.

WaveKin 2 first puts the components on an even frequency grid, d_omega the smallest step
between the file's rows, omega_i = i d_omega up to the last row's frequency, each amplitude and
beta interpolated linearly from the file's rows (``interpEvenlySpaced``): mjtether reads the same
grid. The grid's top frequency is the FFT's Nyquist bin, which MoorDyn-C samples as a saw-tooth,
not a wave: its amplitude must be 0 here. MoorDyn-C then interpolates the kinematics linearly
between the points of ``water_grid.txt`` (clamped to its edges) and between time samples
pi / omega_top apart; mjtether evaluates the components exactly at each point (a difference
of about (omega dt)^2 / 8 of a component's amplitude, stated in the notes). A non-zero 0 rad/s
row (a mean water level offset: re / 2 under WaveKin 2, im under WaveKin 7) is refused.
Errors name the file and its line, never what it holds.
"""

from __future__ import annotations

import math
from pathlib import Path

from mjtether import _checks
from mjtether.scenario import ScenarioError

WAVE_FILE = "wave_frequencies.txt"
"""MoorDyn's wave frequency components, beside the input file: rows of omega (rad/s), re, im (m)
and, optionally, beta (rad)."""

WAVE_KINDS = {2: "frequency components on the grid of water_grid.txt",
              7: "frequency components summed at the nodes"}
"""The ``WaveKin`` values read (from ``WAVE_FILE``); 0 is no waves."""

_OTHERS = {1: "kinematics set through MoorDyn's API", 3: "an elevation time series on a grid",
           4: "an elevation FFT at the nodes", 5: "an elevation time series at the nodes",
           6: "grids of velocity and acceleration"}
MAX_OMEGA = 100.0
"""The highest component frequency taken (rad/s: a 0.06 s wave)."""


def refuse(name: str, no: int, value: str) -> None:
    """ScenarioError for a ``WaveKin`` value that is neither 0 nor one of ``WAVE_KINDS``."""
    what = _OTHERS.get(_whole(value), "not a MoorDyn-C 2.7 WaveKin")
    raise ScenarioError(f"{name}: line {no}: WaveKin = {value} ({what}): waves are not supported by mjtether in "
                        f"this form; WaveKin 0 (none), 2 and 7 (frequency components from {WAVE_FILE} beside the "
                        "file) are")


def _whole(value: str):
    try:
        v = float(value)
    except ValueError:
        return None
    return int(v) if v.is_integer() else None


def read_components(name: str, no: int, mode: int) -> tuple[tuple, tuple]:
    """((amplitude m, omega rad/s, heading deg, phase deg) per component, in mjtether's convention;
    notes) of the ``WAVE_FILE`` beside the MoorDyn file ``name``, its ``WaveKin = mode`` (2 or 7)
    on line ``no``. Components of zero amplitude are left out."""
    path = (Path(name).parent if name != "<moordyn>" else Path.cwd()) / WAVE_FILE
    label = f"{name}: line {no}: WaveKin = {mode}: {path}"
    try:
        text = _checks.read_text(label, path)
    except ValueError as exc:
        raise ScenarioError(str(exc)) from None
    rows = []
    for k, raw in enumerate(text.splitlines(), 1):
        f = raw.split()
        if not f:
            raise ScenarioError(f"{path}: line {k}: is blank; every line is one component, omega re im [beta] "
                                "(MoorDyn-C reads each line)")
        if len(f) < 3:
            raise ScenarioError(f"{path}: line {k}: a component is omega (rad/s) re im (m) [beta (rad)]: 3 or 4 "
                                f"columns, got {len(f)}")
        v = [_cell(path, k, c, x) for c, x in enumerate(f[:4])]
        if len(v) == 4 and not -2 * math.pi <= v[3] <= 2 * math.pi:
            raise ScenarioError(f"{path}: line {k}: beta = {v[3]:g}: must be in [-2 pi, 2 pi] rad (as MoorDyn-C "
                                "requires)")
        if not 0.0 <= v[0] <= MAX_OMEGA:
            raise ScenarioError(f"{path}: line {k}: omega = {v[0]:g} rad/s: must be in [0, {MAX_OMEGA:g}] rad/s")
        rows.append((v[0], complex(v[1], v[2]), v[3] if len(v) == 4 else 0.0, k))
    if len(rows) < 2:
        raise ScenarioError(f"{path}: line 1: at least 2 components are needed (as MoorDyn-C requires), got "
                            f"{len(rows)}")
    if rows[0][0] != 0.0:
        raise ScenarioError(f"{path}: line 1: the first component's omega must be 0 rad/s (as MoorDyn-C "
                            "requires)")
    if rows[0][1] != 0:
        raise ScenarioError(f"{path}: line 1: the 0 rad/s row's amplitude must be 0: a mean water level offset is "
                            "not supported by mjtether")
    for (w0, *_), (w1, _a, _b, k) in zip(rows, rows[1:]):
        if not w1 > w0:
            raise ScenarioError(f"{path}: line {k}: omega = {w1:g} rad/s: the frequencies must ascend (as MoorDyn-C "
                                "requires)")
    notes = []
    if mode == 2:
        rows = _even(rows)
        top = rows[-1]
        if top[1] != 0:
            raise ScenarioError(f"{path}: WaveKin = 2: the top frequency, {top[0]:g} rad/s, is MoorDyn-C's "
                                "Nyquist bin (sampled as a saw-tooth, not a wave): its amplitude must be 0; "
                                "add a row of zero amplitude above it")
        dt = math.pi / top[0]
        worst = max((w for w, a, _b in rows if a != 0), default=0.0)
        notes.append(f"line {no}: WaveKin = 2: MoorDyn-C interpolates the waves between the points of "
                     f"water_grid.txt and between time samples {dt:.4g} s apart (up to "
                     f"{100 * (worst * dt) ** 2 / 8:.2g} % of a component's amplitude); mjtether sums them exactly")
    lead = math.pi / 2 if mode == 7 else 0.0
    tiny = 1e-9 * max(abs(r[1]) for r in rows)  # (WaveKin 2's interpolation leaves 1e-15 m between rows)
    out = tuple((abs(a), w, math.degrees(b), math.degrees(math.remainder(lead - math.atan2(a.imag, a.real),
                                                                          2 * math.pi)))
                for w, a, b, *_ in rows if abs(a) > tiny and w > 0)
    if not out:
        notes.append(f"line {no}: WaveKin = {mode}: every component's amplitude in {WAVE_FILE} is 0: a flat sea")
    return out, tuple(notes)


def _even(rows: list) -> list:
    """MoorDyn-C's ``interpEvenlySpaced``: (omega, amplitude, beta) at i d_omega, i = 0 ... up to
    the last row's omega, d_omega the smallest step between rows, amplitude and beta linear in
    omega between the rows (the same double-precision steps as its C++)."""
    omegas = [r[0] for r in rows]
    dw = min(b - a for a, b in zip(omegas, omegas[1:]))
    out, j = [], 1
    for i in range(math.floor(omegas[-1] / dw) + 1):
        x = i * dw
        if x <= omegas[j - 1]:
            f = 0.0
        elif x >= omegas[-1]:
            j, f = len(omegas) - 1, 1.0
        else:
            while x > omegas[j]:
                j += 1
            f = (x - omegas[j - 1]) / (omegas[j] - omegas[j - 1])
        (_, a0, b0, _), (_, a1, b1, _) = rows[j - 1], rows[j]
        out.append((x, a0 * (1 - f) + a1 * f, b0 * (1 - f) + b1 * f))
    return out


_COLUMNS = ("omega (rad/s)", "re (m)", "im (m)", "beta (rad)")


def _cell(path, no: int, column: int, text: str) -> float:
    """Field ``column`` (0-based) of line ``no`` of ``path`` as a finite number; the error does
    not show the field."""
    try:
        x = float(text)
    except ValueError:
        x = None
    if x is None or not math.isfinite(x):
        raise ScenarioError(f"{path}: line {no}: column {column + 1} ({_COLUMNS[column]}) is not a finite number: "
                            "a row is omega re im [beta]")
    return x
