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


# ------------------------------------------------------------ every public function annotated (issue 44, item 7)


def _public_definitions(tree: ast.Module) -> list[tuple[ast.FunctionDef | ast.AsyncFunctionDef, bool]]:
    """``(def, is_method)`` of every public function and method: at module level or in a public class, under
    ``if``/``try`` too, not nested in a function; a name starting with ``_`` is private (dunders included)."""
    out = []

    def walk(body: list[ast.stmt], in_class: bool) -> None:
        for node in body:
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                if not node.name.startswith("_"):
                    out.append((node, in_class))
            elif isinstance(node, ast.ClassDef) and not node.name.startswith("_"):
                walk(node.body, True)
            elif isinstance(node, (ast.If, ast.Try)):
                walk(node.body + node.orelse + [s for h in getattr(node, "handlers", []) for s in h.body], in_class)

    walk(tree.body, False)
    return out


def unannotated(node: ast.FunctionDef | ast.AsyncFunctionDef, is_method: bool) -> list[str]:
    """The parameters (and ``return``) of a definition that have no annotation; ``self``/``cls`` need none."""
    args = node.args
    params = [*args.posonlyargs, *args.args, *args.kwonlyargs]
    static = any(ast.unparse(d) == "staticmethod" for d in node.decorator_list)
    if is_method and not static and params:
        params = params[1:]
    missing = [p.arg for p in params if p.annotation is None]
    missing += [v.arg for v in (args.vararg, args.kwarg) if v is not None and v.annotation is None]
    return missing + (["return"] if node.returns is None else [])


def _public_modules() -> list[tuple[str, object]]:
    return [(name, path) for name, path in installed_modules()
            if not any(part.startswith("_") and part not in ("__init__", "__main__") for part in name.split("."))]


def annotation_share() -> tuple[int, int, list[str]]:
    """``(annotated, public, the unannotated)`` over the installed package (no module exempt)."""
    annotated = total = 0
    offenders = []
    for name, path in _public_modules():
        for node, is_method in _public_definitions(ast.parse(path.read_text())):
            missing = unannotated(node, is_method)
            total += 1
            annotated += not missing
            if missing:
                offenders.append(f"{name}:{node.lineno} {node.name} {missing}")
    return annotated, total, offenders


def test_the_annotation_count_sees_what_is_missing():
    """A control: public functions and methods with and without annotations, private ones not counted."""
    tree = ast.parse(textwrap.dedent("""
        def f(N, k: int = 1) -> int: ...
        def g(N: int) -> int: ...
        def _private(x): ...
        class A:
            def m(self, x): ...
            @staticmethod
            def s(x: int) -> int: ...
            @classmethod
            def c(cls) -> "A": ...
            def __repr__(self): ...
        class _B:
            def m(self, x): ...
        def outer() -> None:
            def inner(x): ...
    """))
    found = {node.name: unannotated(node, is_method) for node, is_method in _public_definitions(tree)}
    assert found == {"f": ["N"], "g": [], "m": ["x", "return"], "s": [], "c": [], "outer": []}


def test_every_public_function_is_annotated():
    """Every public function and method of the installed package: parameters and return annotated (share 1.0)."""
    annotated, total, offenders = annotation_share()
    assert total > 500, total  # the walk sees the package
    assert not offenders, (f"{len(offenders)} public functions not fully annotated ({annotated}/{total} over the "
                           "package):\n" + "\n".join(offenders))
    assert annotated / total == 1.0, (annotated, total)
