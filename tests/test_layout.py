"""The package's layout: imports run one way, modules stay small, and the flat layout's module
paths still import.

The ranks below are the "Package layout" list of docs/layout.md: a module may import only modules of a lower
rank or of its own area. Read from the source (``ast``), function-local imports included, so a
late import cannot hide an upward dependency."""

import ast
import importlib
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "mjtether"

LEAVES = {"mjtether._checks", "mjtether.units", "mjtether.analytic", "mjtether.files.packagedata",
          "mjtether.files.mjlog", "mjtether.files.outdir", "mjtether.io.render"}
RANK = {"files": 0, "physics": 1, "cable": 2, "vehicles": 2, "walker": 3, "simulation": 4, "quasistatic": 5, "scenario": 6,
        "network": 7, "io": 8, "sweep": 9, "rollouts": 9, "demo": 9, "cli": 10}  # (a network flies vehicles
# with the scenario's autopilot)


def _module(path: Path) -> str:
    parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _imports(path: Path):
    """(line, imported module) of every import of the package in ``path``; ``from X import y``
    counts as importing ``X.y`` where that is a module."""
    mod = _module(path)
    pkg = mod if path.name == "__init__.py" else mod.rsplit(".", 1)[0]
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                up = pkg.split(".")[:len(pkg.split(".")) - node.level + 1]
                base = ".".join(up + ([node.module] if node.module else []))
            if base.split(".")[0] != "mjtether":
                continue
            for alias in node.names:
                sub = f"{base}.{alias.name}"
                yield node.lineno, sub if (PACKAGE.parent / (sub.replace(".", "/") + ".py")).exists() or \
                    (PACKAGE.parent / sub.replace(".", "/")).is_dir() else base
        elif isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name.split(".")[0] == "mjtether":
                    yield node.lineno, alias.name


def _rank(module: str) -> tuple[str, int]:
    if module in LEAVES or module == "mjtether":
        return "leaf", 0
    area = module.split(".")[1]
    return area, RANK[area]


SOURCES = sorted(p for p in PACKAGE.rglob("*.py") if _module(p) not in ("mjtether", "mjtether.builder",
                                                                          "mjtether.runner"))


@pytest.mark.parametrize("path", SOURCES, ids=lambda p: str(p.relative_to(PACKAGE)))
def test_imports_run_one_way(path):
    """No module imports one of a higher rank (the cable and the physics never import the
    scenario, the CLI or the environments; the leaves import nothing of the package but
    ``_checks`` and ``units``)."""
    me = _module(path)
    area, rank = _rank(me)
    for line, other in _imports(path):
        if other in ("mjtether", "mjtether._checks", "mjtether.units") or other == me:
            continue
        their_area, their_rank = _rank(other)
        if area == "leaf":
            assert False, f"{me}:{line} imports {other}: a leaf module imports nothing of the package"
        assert their_area == area or their_rank < rank, f"{me} (rank {rank}):{line} imports {other} (rank {their_rank})"


def test_no_package_imports_another_that_imports_it():
    """The areas (``io``, ``scenario``, ``network``, ...) import each other one way only: no
    import cycle between two packages, the leaves (``files``, ``_checks``, ...) included."""
    graph = {}
    for path in SOURCES:
        me = _module(path).split(".")
        mine = me[1] if len(me) > 1 else "mjtether"
        for _, other in _imports(path):
            theirs = other.split(".")[1] if other.count(".") else "mjtether"
            if theirs not in (mine, "mjtether"):
                graph.setdefault(mine, set()).add(theirs)
    for a, deps in graph.items():
        for b in deps:
            assert a not in graph.get(b, ()), f"mjtether.{a} and mjtether.{b} import each other"


def test_small_modules_and_classes():
    """At most about 12 modules at the package's top level besides the subpackages; no module
    over about 700 lines; no class over about 400 lines."""
    top = sorted(p.name for p in PACKAGE.glob("*.py"))
    assert len(top) <= 12, top
    for path in PACKAGE.rglob("*.py"):
        text = path.read_text()
        assert text.count("\n") <= 700, f"{path.relative_to(PACKAGE)}: {text.count(chr(10))} lines"
        for node in ast.walk(ast.parse(text)):
            if isinstance(node, ast.ClassDef):
                size = node.end_lineno - node.lineno + 1
                assert size <= 400, f"{path.relative_to(PACKAGE)}: class {node.name} has {size} lines"


@pytest.mark.parametrize("old, new", [("mjtether.builder", "mjtether.cable.builder"),
                                      ("mjtether.runner", "mjtether.scenario.runner")])
def test_the_flat_layouts_paths_are_the_moved_modules(old, new):
    assert importlib.import_module(old) is importlib.import_module(new)
    assert importlib.import_module(old).__name__ == new


def test_the_flat_layouts_names_still_import():
    """What code written against the flat layout imports: the five old module paths, and the
    module attributes ``import mjtether as mt`` offered (``mt.water``, ``mt.builder``, ...)."""
    import mjtether as mt
    from mjtether.builder import add_tether
    from mjtether.quasistatic import steady_state  # noqa: F401
    from mjtether.runner import ScenarioRun, run  # noqa: F401
    from mjtether.scenario import Scenario, ScenarioError, load_scenario, to_toml  # noqa: F401
    from mjtether.simulation import FAIRLEAD_SHARE, SLACK_FORCE, BoundTether, Simulation  # noqa: F401

    assert add_tether is mt.add_tether
    for name, moved in {"water": "physics.water", "hydro": "physics.hydro", "compiled": "physics.compiled",
                        "native": "physics.native", "dispatch": "physics.dispatch", "rigidbody": "physics.rigidbody",
                        "builder": "cable.builder", "tether": "cable.tether", "makeup": "cable.makeup",
                        "winch": "cable.winch", "seabed": "cable.seabed", "stability": "cable.stability",
                        "fossen": "vehicles.fossen", "vehicle": "vehicles.vehicle", "fins": "vehicles.fins",
                        "propeller": "vehicles.propeller", "mjlog": "files.mjlog"}.items():
        assert getattr(mt, name) is importlib.import_module(f"mjtether.{moved}"), name
