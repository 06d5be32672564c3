"""The installed forcenet, module by module, as the import system finds it (regular or editable install).

The sources are laid out differently from the import names (``exact/`` installs as ``forcenet.exact``,
``src/forcenet/`` as ``forcenet``: pyproject.toml's ``package-dir``), so the tests never walk the
checkout: they walk what ``import forcenet`` reaches, package by package (the list in pyproject.toml,
which tests/test_packaging.py checks is complete).
"""

from __future__ import annotations

import importlib.util
import pkgutil
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]  # the checkout (or unpacked source distribution) under test


def setuptools_config() -> dict:
    """``[tool.setuptools]`` of the checkout's pyproject.toml."""
    with open(ROOT / "pyproject.toml", "rb") as f:
        return tomllib.load(f)["tool"]["setuptools"]


def packages() -> list[str]:
    """Every package the distribution installs (pyproject.toml's explicit list)."""
    return list(setuptools_config()["packages"])


def source_dir(package: str) -> Path:
    """The folder of the checkout that installs as ``package`` (the longest package-dir prefix)."""
    mapping = setuptools_config()["package-dir"]
    parts = package.split(".")
    for n in range(len(parts), -1, -1):
        key = ".".join(parts[:n])
        if key in mapping:
            return ROOT / mapping[key] / Path(*parts[n:])
    return ROOT / Path(*parts)


def installed_modules() -> list[tuple[str, Path]]:
    """Sorted ``(dotted name, file)`` of every installed module and package of forcenet (``__main__`` too)."""
    out: dict[str, Path] = {}
    for package in packages():
        spec = importlib.util.find_spec(package)
        if spec is None or spec.origin is None:
            raise ModuleNotFoundError(f"{package} is listed in pyproject.toml but not importable")
        out[package] = Path(spec.origin)
        for info in pkgutil.iter_modules(spec.submodule_search_locations, prefix=package + "."):
            if not info.ispkg:
                out[info.name] = Path(info.module_finder.path) / (info.name.rsplit(".", 1)[1] + ".py")
    return sorted(out.items())
