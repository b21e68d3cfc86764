"""The fields of a MoorDyn file read as numbers, and the files it names beside it: a 3-D seafloor
(``SeafloorFile``) and MoorDyn's steady current profile (``Currents = 1``). Errors are
``ScenarioError``s naming the file and its line, as ``mjtether.io.moordyn``'s are.
"""

from __future__ import annotations

import math
from pathlib import Path

from mjtether import _checks
from mjtether.scenario import ScenarioError
from mjtether.scenario.config import params
from mjtether.scenario.sections import Current


def number(name, no, text, what):
    """``text`` (the field ``what`` on line ``no`` of the file ``name``) as a float."""
    try:
        return float(text)
    except ValueError:
        raise ScenarioError(f"{name}: line {no}: {what} must be a number, got {text!r}") from None


def seafloor_path(name: str, no: int, value: str) -> str:
    """The absolute path of a SeafloorFile named on line ``no``: beside the input file, or in the
    working folder (where MoorDyn-C looks); checked as a bathymetry grid. A path out of the folder
    (``../grids/floor.txt``, ``/data/floor.txt``) is allowed: it is read if it is a grid, and an
    error names it and what is wrong, never what it holds."""
    from mjtether.physics import bathymetry
    here = Path(name).parent if name != "<moordyn>" else Path.cwd()
    found = next((p for p in (here / value, Path.cwd() / value) if p.is_file()), None)
    if found is None:
        raise ScenarioError(f"{name}: line {no}: SeafloorFile {value}: no such file beside the input file ({here}) "
                            f"nor in the working folder ({Path.cwd()}, where MoorDyn-C looks)")
    try:
        _checks.read_text(value, found)  # (a binary or non-UTF-8 file named so, before the grid reader sees it)
        bathymetry.read_moordyn_seafloor(found)
    except ValueError as exc:
        raise ScenarioError(f"{name}: line {no}: SeafloorFile: {exc}") from None
    return str(found.resolve())


CURRENT_FILE = "current_profile.txt"
"""MoorDyn's steady current profile, beside the input file: three header lines, then rows of
z (m, up), ux, uy, uz (m/s)."""


_COLUMNS = ("z", "ux", "uy", "uz")


def read_current_profile(name: str, no: int) -> tuple:
    """(depths m, speeds m/s, headings deg) of the ``CURRENT_FILE`` beside the file ``name``
    (named on its line ``no``, ``Currents = 1``). The file may be a link or sit elsewhere through
    one (a side file kept in a sibling folder): it is read if it is a valid profile. Errors name
    the file, its line and column and the range allowed (``water.current``'s), never its
    contents: a link to a file that is not a profile (``/etc/passwd``) says which line is not
    numbers, not what it holds."""
    path = Path(name).parent / CURRENT_FILE
    try:
        rows = _checks.read_text(str(path), path).splitlines()[3:]
    except ValueError as exc:
        raise ScenarioError(f"{name}: line {no}: Currents = 1: {exc}") from None
    depths, speeds = params(Current)["depths"], params(Current)["speeds"]
    table, seen = [], {}
    for k, row in enumerate(rows, 4):
        f = row.split()
        if not f:
            continue
        v = [_cell(path, k, c, x) for c, x in enumerate(f[:4])] + [0.0] * (4 - len(f[:4]))
        if v[3] != 0.0:
            raise ScenarioError(f"{path}: line {k}: a vertical current (uz = {v[3]:g} m/s) is not supported by "
                                "mjtether")
        if v[0] > 0.0:
            continue  # (above the water)
        depth, speed = -v[0], math.hypot(v[1], v[2])
        if not depths.lo <= depth <= depths.hi:
            raise ScenarioError(f"{path}: line {k}: z = {v[0]:g} m: must be in [{-depths.hi:g}, 0] m for a row in the "
                                f"water (z > 0: above it, skipped)")
        if not speed <= speeds.hi:
            raise ScenarioError(f"{path}: line {k}: the current (ux, uy) = ({v[1]:g}, {v[2]:g}) m/s is {speed:g} m/s: "
                                f"must be in [{speeds.lo:g}, {speeds.hi:g}] m/s (water.current.speeds)")
        if depth in seen:
            raise ScenarioError(f"{path}: line {k}: z = {v[0]:g} m again (line {seen[depth]}): give each depth once")
        seen[depth] = k
        table.append((depth, speed, math.degrees(math.atan2(v[2], v[1]))))
    if not table:
        raise ScenarioError(f"{path}: line 4: no row of the current profile is in the water (z <= 0)")
    table.sort()
    return tuple(zip(*table))


def _cell(path, no: int, column: int, text: str) -> float:
    """Field ``column`` (0-based) of line ``no`` of the side file ``path`` as a finite number;
    the error does not show the field (the file may be anything a link points at)."""
    try:
        x = float(text)
    except ValueError:
        x = None
    if x is None or not math.isfinite(x):
        raise ScenarioError(f"{path}: line {no}: column {column + 1} ({_COLUMNS[column]}, "
                            f"{'m' if column == 0 else 'm/s'}) is not a finite number: a row is z ux uy uz")
    return x
