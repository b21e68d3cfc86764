"""Running a MoorDyn input file in MoorDyn-C (the ``moordyn`` package from PyPI, 2.7.x): the
reference the MoorDyn tests compare mjtether against. Nothing here comes from mjtether."""

from __future__ import annotations

import os
import shutil
import tempfile
from contextlib import contextmanager
from pathlib import Path

import numpy as np

moordyn = __import__("pytest").importorskip("moordyn")


@contextmanager
def _cwd(folder):
    old = os.getcwd()
    os.chdir(folder)
    try:
        yield
    finally:
        os.chdir(old)


def _scratch(fn):
    """``fn(path, ...)`` run on a copy of ``path``'s folder (MoorDyn-C writes its .log and .out
    beside the file); ``options`` ({name: value}) are written into the copy's OPTIONS section,
    ahead of the file's own (MoorDyn-C takes the last value it reads, so the file's would win:
    an option named here must not be in the file)."""
    def wrapped(path, *args, options=None):
        src = Path(path).resolve()
        scratch = Path(tempfile.mkdtemp(prefix="moordyn-c-"))
        shutil.copytree(src.parent, scratch / "run")
        if options:
            lines = src.read_text().splitlines()
            assert not [k for k in options if any(ln.split()[1:2] == [k] for ln in lines)], options
            at = next(i for i, ln in enumerate(lines) if "OPTIONS" in ln.upper() and ln.lstrip().startswith("-"))
            lines[at + 1:at + 1] = [f"{v}   {k}" for k, v in options.items()]
            (scratch / "run" / src.name).write_text("\n".join(lines) + "\n")
        try:
            return fn(scratch / "run" / src.name, *args)
        finally:
            shutil.rmtree(scratch, ignore_errors=True)
    return wrapped


@_scratch
def run_along(path, duration: float, every: float) -> dict:
    """Run ``path`` in MoorDyn-C (its initial-condition solver, then its ``dtM``) for ``duration``
    s and return, every ``every`` s, ``time_s``, each free point's position (``point<n>_x`` ...,
    m), each rod's middle (``rod<n>_x`` ..., m: halfway between its end nodes) and each line's
    end tensions (``line<n>_A_tension``, ``line<n>_B_tension``: the end segments' tension, N),
    as arrays."""
    with _cwd(path.parent):
        s = moordyn.Create(str(path))
        try:
            moordyn.Init(s, np.zeros(0), np.zeros(0))  # (no coupled points: these files have none)
            points = {i + 1: moordyn.GetPoint(s, i + 1) for i in range(moordyn.GetNumberPoints(s))}
            points = {i: p for i, p in points.items() if moordyn.GetPointType(p) == moordyn.POINT_TYPE_FREE}
            lines = {i + 1: moordyn.GetLine(s, i + 1) for i in range(moordyn.GetNumberLines(s))}
            rods = {i + 1: moordyn.GetRod(s, i + 1) for i in range(moordyn.GetNumberRods(s))}
            out, t = {}, 0.0
            for _ in range(round(duration / every)):
                moordyn.Step(s, np.zeros(0), np.zeros(0), t, every)
                t += every
                row = {"time_s": t}
                for i, p in points.items():
                    row.update(zip((f"point{i}_{k}" for k in "xyz"), moordyn.GetPointPos(p)))
                for i, rod in rods.items():
                    ends = np.array([moordyn.GetRodNodePos(rod, k) for k in (0, moordyn.GetRodN(rod))])
                    row.update(zip((f"rod{i}_{k}" for k in "xyz"), ends.mean(axis=0)))
                for i, ln in lines.items():
                    row[f"line{i}_A_tension"] = np.linalg.norm(moordyn.GetLineNodeTen(ln, 0))
                    row[f"line{i}_B_tension"] = np.linalg.norm(moordyn.GetLineNodeTen(ln, moordyn.GetLineN(ln)))
                for k, v in row.items():
                    out.setdefault(k, []).append(v)
            return {k: np.array(v) for k, v in out.items()}
        finally:
            moordyn.Close(s)


@_scratch
def end_loads(path, duration: float, window: float) -> dict:
    """Run ``path`` in MoorDyn-C (its own initial-condition solver, then ``duration`` s at its
    ``dtM``) and return {line number: (mean force on the support at end A, at end B, final
    nodes A to B)} with the forces (N, world) averaged over the last ``window`` s: the end
    segment's pull (``GetLineNodeTen`` of an end node points along the line from A to B), the end
    node's weight with buoyancy, and its seabed reaction with its bending force (the shear a line
    with EI passes to a pinned end: MoorDyn-C's ``GetLineNodeSeabedForce`` returns the two
    together, ``B[i] + Bs[i]`` in its Line.hpp), i.e. what the line pulls its support with (at a
    coupled point this is MoorDyn's own ``GetPointForce``, to 0.1 %)."""
    with _cwd(path.parent):
        s = moordyn.Create(str(path))
        try:
            x = []
            for i in range(moordyn.GetNumberBodies(s)):
                b = moordyn.GetBody(s, i + 1)
                if moordyn.GetBodyType(b) == moordyn.BODY_TYPE_COUPLED:
                    x += list(moordyn.GetBodyState(b)[0])
            for i in range(moordyn.GetNumberPoints(s)):
                p = moordyn.GetPoint(s, i + 1)
                if moordyn.GetPointType(p) == moordyn.POINT_TYPE_COUPLED:
                    x += list(moordyn.GetPointPos(p))
            x = np.array(x, float)
            v = np.zeros_like(x)
            moordyn.Init(s, x, v)
            lines = [moordyn.GetLine(s, i + 1) for i in range(moordyn.GetNumberLines(s))]

            def loads():
                out = []
                for ln in lines:
                    n = moordyn.GetLineN(ln)
                    f = []
                    for i, sign in ((0, 1.0), (n, -1.0)):  # (the end tensions point from A to B)
                        f.append(sign * np.array(moordyn.GetLineNodeTen(ln, i))
                                 + np.array(moordyn.GetLineNodeWeight(ln, i))
                                 + np.array(moordyn.GetLineNodeSeabedForce(ln, i)))
                    out.append(f)
                return out

            t, dt, acc, k = 0.0, 0.05, None, 0
            while t < duration - 1e-9:
                moordyn.Step(s, x, v, t, dt)
                t += dt
                if t >= duration - window - 1e-9:
                    now = loads()
                    acc = now if acc is None else [[a + b for a, b in zip(x1, x2)] for x1, x2 in zip(acc, now)]
                    k += 1
            result = {}
            for j, ln in enumerate(lines, 1):
                n = moordyn.GetLineN(ln)
                nodes = np.array([moordyn.GetLineNodePos(ln, i) for i in range(n + 1)])
                result[j] = (acc[j - 1][0] / k, acc[j - 1][1] / k, nodes)
            return result
        finally:
            moordyn.Close(s)
