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
