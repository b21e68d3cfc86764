"""Where the package's data folders are: ``assets/<name>`` (the walker's MJCF, the vehicle files).

They install as the package data ``mjtether.assets`` (see pyproject.toml) of a wheel, found
through ``importlib.resources`` (real files, as ``MjSpec.from_file`` needs); an editable install
serves them from the source tree's ``assets/<name>``: setuptools' editable finder cannot import
``mjtether.assets`` because the folder has no ``__init__.py``.
"""

from __future__ import annotations

from importlib.resources import files
from pathlib import Path


def asset_dir(name: str, probe: str) -> Path:
    """The folder ``assets/<name>`` (``probe``: a file it must hold, to tell a real one)."""
    try:
        return Path(str(files("mjtether.assets") / name))
    except ModuleNotFoundError:
        src = Path(__file__).resolve().parents[2] / "assets" / name
        if (src / probe).is_file():
            return src
        raise FileNotFoundError(f"mjtether: the package data mjtether.assets/{name} is not installed; "
                                "reinstall mjtether") from None


def examples_dir() -> Path:
    """The shipped example scenarios (``examples/``, installed as ``mjtether.examples``)."""
    try:
        return Path(str(files("mjtether.examples")))
    except ModuleNotFoundError:
        src = Path(__file__).resolve().parents[2] / "examples"
        if (src / "default_walker.toml").is_file():
            return src
        raise FileNotFoundError("mjtether: the package data mjtether.examples is not installed; reinstall "
                                "mjtether") from None


def shipped_example(name) -> Path | None:
    """The shipped example called ``name`` (``"default_walker"``, ``"networks/rov_cage_excursion"``,
    with or without ``.toml``), or None where ``name`` is a path that exists or names none."""
    p = Path(str(name))
    if p.exists() or p.is_absolute():
        return None
    try:
        folder = examples_dir()
    except FileNotFoundError:
        return None
    candidate = folder / (p if p.suffix == ".toml" else p.with_name(p.name + ".toml"))
    return candidate if candidate.is_file() else None
