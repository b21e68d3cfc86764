"""The fields of a MoorDyn file read as numbers, and the files it names beside it: a 3-D seafloor
(``SeafloorFile``) and MoorDyn's steady current profile (``Currents = 1``). Errors are
``ScenarioError``s naming the file and its line, as ``mjtether.io.moordyn``'s are.
"""

from __future__ import annotations

import math
from pathlib import Path

from mjtether.scenario import ScenarioError


def number(name, no, text, what):
    """``text`` (the field ``what`` on line ``no`` of the file ``name``) as a float."""
    try:
        return float(text)
    except ValueError:
        raise ScenarioError(f"{name}: line {no}: {what} must be a number, got {text!r}") from None


def seafloor_path(name: str, no: int, value: str) -> str:
    """The absolute path of a SeafloorFile named on line ``no``: beside the input file, or in the
    working folder (where MoorDyn-C looks); checked as a bathymetry grid."""
    from mjtether.physics import bathymetry
    here = Path(name).parent if name != "<moordyn>" else Path.cwd()
    found = next((p for p in (here / value, Path.cwd() / value) if p.is_file()), None)
    if found is None:
        raise ScenarioError(f"{name}: line {no}: SeafloorFile {value}: no such file beside the input file ({here}) "
                            f"nor in the working folder ({Path.cwd()}, where MoorDyn-C looks)")
    try:
        bathymetry.read_moordyn_seafloor(found)
    except ValueError as exc:
        raise ScenarioError(f"{name}: line {no}: SeafloorFile: {exc}") from None
    return str(found.resolve())


CURRENT_FILE = "current_profile.txt"
"""MoorDyn's steady current profile, beside the input file: three header lines, then rows of
z (m, up), ux, uy, uz (m/s)."""


def read_current_profile(name: str, no: int) -> tuple:
    """(depths m, speeds m/s, headings deg) of the ``CURRENT_FILE`` beside the file ``name``."""
    path = Path(name).parent / CURRENT_FILE
    try:
        rows = path.read_text().splitlines()[3:]
    except OSError as exc:
        raise ScenarioError(f"{name}: line {no}: Currents = 1 reads {path}: {exc.strerror or exc}") from None
    table = []
    for k, row in enumerate(rows, 4):
        f = row.split()
        if not f:
            continue
        v = [number(str(path), k, x, "z/ux/uy/uz") for x in f[:4]] + [0.0] * (4 - len(f[:4]))
        if v[3] != 0.0:
            raise ScenarioError(f"{path}: line {k}: a vertical current (uz = {v[3]:g} m/s) is not supported by "
                                "mjtether")
        if v[0] <= 0.0:
            table.append((-v[0], math.hypot(v[1], v[2]), math.degrees(math.atan2(v[2], v[1]))))
    if not table:
        raise ScenarioError(f"{path}: line 4: no row of the current profile is in the water (z <= 0)")
    table.sort()
    return tuple(zip(*table))
