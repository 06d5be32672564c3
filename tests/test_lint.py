"""Types, linters and the public functions' docstrings (issue 25, item 5), in the default suite.

mypy and ruff run as ``python tests/typecheck.py`` runs them (the project's configuration in pyproject.toml);
every function a package ``__init__`` exports is fully annotated and carries the numpydoc sections.
"""

from __future__ import annotations

import ast
import importlib
import inspect
import re
import textwrap

import pytest
import typecheck
from installed import installed_modules


def test_mypy_finds_nothing():
    code, found = typecheck.mypy()
    assert not found, f"mypy: {len(found)} findings (python tests/typecheck.py):\n" + "\n".join(found[:50])
    assert code == 0


def test_ruff_finds_nothing():
    code, found = typecheck.ruff()
    assert not found, f"ruff: {len(found)} findings (python tests/typecheck.py):\n" + "\n".join(found[:50])
    assert code == 0


# -------------------------------------------------------------------------- the exported functions


def _packages() -> list[str]:
    """Every package ``__init__`` whose exports are public API (the command line's parser is not)."""
    return [name for name, path in installed_modules() if path.name == "__init__.py" and not name.startswith("forcenet.cli")]


def exported_functions() -> list[tuple[str, object]]:
    """``(package.name, function)`` for every function a package exports (``__all__``, else its public names)."""
    out: dict[str, tuple[str, object]] = {}
    for package in _packages():
        module = importlib.import_module(package)
        names = getattr(module, "__all__", None) or [n for n in vars(module) if not n.startswith("_")]
        for name in names:
            obj = getattr(module, name, None)
            function = inspect.unwrap(obj) if callable(obj) and hasattr(obj, "__wrapped__") else obj
            if inspect.isfunction(function) and function.__module__.startswith("forcenet"):
                key = f"{function.__module__}.{function.__qualname__}"
                out.setdefault(key, (f"{package}.{name}", function))
    return sorted(out.values(), key=lambda item: item[0])


EXPORTED = exported_functions()


def _section(doc: str, title: str) -> bool:
    return re.search(rf"^\s*{title}\s*\n\s*-{{3,}}\s*$", doc, re.MULTILINE) is not None


def _raises(function) -> bool:
    """Does the body raise (a ``raise`` with an exception, or a call of a ``check_*`` argument check)?"""
    try:
        tree = ast.parse(textwrap.dedent(inspect.getsource(function)))
    except (OSError, TypeError):
        return False
    body = tree.body[0]
    for node in ast.walk(body):
        if node is not body and isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda)):
            continue
        if isinstance(node, ast.Raise) and node.exc is not None:
            return True
        if isinstance(node, ast.Call):
            callee = node.func.attr if isinstance(node.func, ast.Attribute) else getattr(node.func, "id", "")
            if callee.startswith("check_"):
                return True
    return False


def missing_annotations(function) -> list[str]:
    signature = inspect.signature(function)
    missing = [p.name for p in signature.parameters.values() if p.annotation is inspect.Parameter.empty]
    if signature.return_annotation is inspect.Signature.empty:
        missing.append("return")
    return missing


def missing_sections(function) -> list[str]:
    doc = inspect.getdoc(function) or ""
    wanted = []
    if inspect.signature(function).parameters:
        wanted.append("Parameters")
    wanted.append("Returns")
    if _raises(function):
        wanted.append("Raises")
    wanted.append("Examples")
    return [title for title in wanted if not _section(doc, title)]


def test_the_exported_functions_are_found():
    names = {name for name, _ in EXPORTED}
    assert {"forcenet.exact.mean_W", "forcenet.testing.assert_agrees", "forcenet.exact.thesis.count_lambda"} <= names
    assert len(EXPORTED) > 80


def test_the_checks_see_what_is_missing():
    """A control: a function without annotations or sections, and one with everything."""

    def bare(N, k=1):
        """Something."""
        if N < 0:
            raise ValueError(N)
        return N

    def check_layers(N: int) -> None:
        """Stands for an argument check."""

    def complete(N: int) -> int:
        """Something.

        Parameters
        ----------
        N : int

        Returns
        -------
        int

        Raises
        ------
        ArgumentError

        Examples
        --------
        >>> 1
        1
        """
        check_layers(N)
        return N

    assert missing_annotations(bare) == ["N", "k", "return"]
    assert missing_sections(bare) == ["Parameters", "Returns", "Raises", "Examples"]
    assert missing_annotations(complete) == [] and missing_sections(complete) == []


@pytest.mark.parametrize("name, function", EXPORTED, ids=[name for name, _ in EXPORTED])
def test_exported_functions_are_fully_annotated(name, function):
    missing = missing_annotations(function)
    assert not missing, f"{name}: not annotated: {missing}"


@pytest.mark.parametrize("name, function", EXPORTED, ids=[name for name, _ in EXPORTED])
def test_exported_functions_have_the_numpydoc_sections(name, function):
    missing = missing_sections(function)
    assert not missing, f"{name}: docstring lacks the numpydoc section(s) {missing}"
