"""The OUTPUTS section of a MoorDyn file, checked as MoorDyn-C 2.7 checks it.

mjtether does not use the section (its outputs are every line's end forces and nodes), but
MoorDyn-C refuses a file whose outputs name a line, point, rod or body it does not have
(``MoorDyn2.cpp``: "Invalid Line ID specifier", ...), so a file that mjtether runs is one
MoorDyn-C may not: ``unknown_objects`` says which output words those are, for a warning.
"""

from __future__ import annotations

import re

_KINDS = {"FAIRTEN": "line", "ANCHTEN": "line", "L": "line", "LINE": "line", "P": "point", "POINT": "point",
          "R": "rod", "ROD": "rod", "B": "body", "BODY": "body"}
"""MoorDyn-C's output words (their leading letters) and the object each names by number."""
_PLURAL = {"line": "lines", "point": "points", "rod": "rods", "body": "bodies"}


def unknown_objects(rows, counts: dict) -> list[tuple[int, str]]:
    """(file line number, why) for each output word of ``rows`` ([(line number, words)], the
    OUTPUTS section) that names an object beyond ``counts`` ({"line": n, "point": n, "rod": n,
    "body": n}: how many of each the file has, numbered from 1)."""
    out = []
    for no, words in rows:
        for word in words:
            m = re.match(r"([A-Za-z]*)(\d*)", word)
            kind = _KINDS.get(m.group(1).upper())
            if kind is None or not m.group(2):
                continue
            n = int(m.group(2))
            if not 1 <= n <= counts.get(kind, 0):
                have = counts.get(kind, 0)
                objects = kind if have == 1 else _PLURAL[kind]
                out.append((no, (f"output {word!r} names {kind} {n}, and the file has {have} {objects}: MoorDyn-C "
                                 "2.7 refuses the file; mjtether does not use the OUTPUTS section")))
    return out
