"""The house rules of notes/architecture.md, checked on the source of every module."""

import ast
from pathlib import Path

import pytest
from installed import installed_modules


def _modules():
    """(name, file) of every module of the installed package (the sources under their import names)."""
    return installed_modules()


MODULES = _modules()


def _imports(path: Path, name: str):
    """Absolute names of every module imported by the file (relative imports resolved)."""
    tree = ast.parse(path.read_text())
    package = name if path.name == "__init__.py" else name.rsplit(".", 1)[0]
    found = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            found += [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")
                base = base[: len(base) - node.level + 1]
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module or ""
            found.append(target)
            found += [f"{target}.{alias.name}" for alias in node.names]
    return found


def test_every_module_is_found():
    names = {name for name, _ in MODULES}
    assert {"forcenet.exact.validation", "forcenet.numeric.chicken_wire.bethe", "forcenet.cli.common"} <= names


@pytest.mark.parametrize("name, path", [m for m in MODULES if m[0].startswith("forcenet.exact")], ids=lambda x: str(x))
def test_exact_imports_neither_numeric_nor_the_cli(name, path):
    bad = [m for m in _imports(path, name) if m.startswith(("forcenet.numeric", "forcenet.cli", "numeric", "matplotlib"))]
    assert not bad, f"{name} imports {bad}"


@pytest.mark.parametrize("name, path", MODULES, ids=lambda x: str(x))
def test_no_generic_top_level_imports(name, path):
    """Inside the package everything is imported as forcenet.* (nothing generic at the top of site-packages)."""
    bad = [m for m in _imports(path, name) if m.split(".")[0] in ("exact", "numeric")]
    assert not bad, f"{name} imports {bad}"


@pytest.mark.parametrize("name, path", [m for m in MODULES if m[0].startswith("forcenet.exact.reference")], ids=lambda x: str(x))
def test_reference_routes_share_no_code_with_what_they_check(name, path):
    allowed = ("forcenet.exact.validation", "forcenet.exact.errors", "forcenet.exact.reference")
    ours = [m for m in _imports(path, name) if m.startswith("forcenet") and not m.startswith(allowed)]
    assert not ours, f"{name} imports {ours}"


def _integer_checks(tree):
    """Places that test for integers by hand: isinstance(x, int / Integral / np.integer) or __index__ probes."""
    hits = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Call) and getattr(node.func, "id", None) == "isinstance" and len(node.args) == 2:
            kinds = node.args[1]
            names = [kinds] if not isinstance(kinds, ast.Tuple) else list(kinds.elts)
            for k in names:
                text = ast.unparse(k)
                if text in ("int", "bool", "Integral", "numbers.Integral", "np.integer", "numpy.integer"):
                    hits.append((node.lineno, ast.unparse(node)))
        if isinstance(node, ast.Constant) and node.value == "__index__":
            hits.append((node.lineno, "'__index__'"))
        if isinstance(node, ast.Attribute) and node.attr == "__index__":
            hits.append((node.lineno, ast.unparse(node)))
    return hits


@pytest.mark.parametrize("name, path", [m for m in MODULES if m[0] != "forcenet.exact.validation"], ids=lambda x: str(x))
def test_one_integer_check_for_the_whole_package(name, path):
    """Every integer argument is checked by forcenet.exact.validation (one message format, one policy)."""
    hits = _integer_checks(ast.parse(path.read_text()))
    assert not hits, f"{name} checks integers by hand at {hits}; use forcenet.exact.validation"


def test_no_module_sets_a_global_precision():
    for name, path in MODULES:
        text = path.read_text()
        for pattern in ("mp.dps =", "mp.prec =", "ctx.dps =", "ctx.prec ="):
            assert pattern not in text, f"{name} sets a global precision ({pattern})"


def test_files_stay_readable():
    too_long = [(name, n) for name, path in MODULES if (n := len(path.read_text().splitlines())) > 600]
    assert not too_long, f"modules over 600 lines (split by job): {too_long}"


# ---------------------------------------------------------------- errors (notes/architecture.md, "Errors")

_BUILTIN_BASES = {"Exception", "ValueError", "TypeError"}  # only exact/errors.py derives from these directly
_ERRORS_MODULE = "forcenet.exact.errors"


def _raised_name(node: ast.Raise) -> str | None:
    exc = node.exc.func if isinstance(node.exc, ast.Call) else node.exc
    return exc.id if isinstance(exc, ast.Name) else None


@pytest.mark.parametrize("name, path", MODULES, ids=lambda x: str(x))
def test_library_raises_the_family_not_bare_builtins_and_has_no_assert(name, path):
    """Argument errors are ArgumentError/ArgumentTypeError (still ValueError/TypeError); no assert (python -O)."""
    tree = ast.parse(path.read_text())
    raises = [(n.lineno, _raised_name(n)) for n in ast.walk(tree)
              if isinstance(n, ast.Raise) and n.exc is not None and _raised_name(n) in ("ValueError", "TypeError")]
    asserts = [n.lineno for n in ast.walk(tree) if isinstance(n, ast.Assert)]
    assert not raises, f"{name} raises builtins at {raises}: raise forcenet.exact.errors.ArgumentError / ArgumentTypeError"
    assert not asserts, f"{name} has bare assert at lines {asserts}: raise an error instead (python -O strips asserts)"


@pytest.mark.parametrize("name, path", MODULES, ids=lambda x: str(x))
def test_exception_classes_end_in_error_and_join_the_family_at_its_base(name, path):
    for node in ast.walk(ast.parse(path.read_text())):
        if not isinstance(node, ast.ClassDef):
            continue
        bases = {ast.unparse(b) for b in node.bases}
        if not any(b.endswith(("Error", "Exception")) for b in bases):
            continue  # not an exception class
        assert node.name.endswith("Error"), f"{name}.{node.name}: an exception class name ends in Error"
        if name != _ERRORS_MODULE:
            assert not bases & _BUILTIN_BASES, (
                f"{name}.{node.name} derives from {sorted(bases & _BUILTIN_BASES)}: derive from the family "
                "(forcenet.exact.errors) if it is an expected failure")


def _handlers(function: ast.FunctionDef) -> list[str]:
    names = []
    for node in ast.walk(function):
        if isinstance(node, ast.ExceptHandler) and node.type is not None:
            kinds = node.type.elts if isinstance(node.type, ast.Tuple) else [node.type]
            names += [ast.unparse(k) for k in kinds]
    return names


def test_the_command_line_boundary_catches_only_the_family():
    """main(): the family, the file system, memory, interruption; any other exception is the bug handler's."""
    path = dict(MODULES)["forcenet.cli"]
    main = next(n for n in ast.parse(path.read_text()).body if isinstance(n, ast.FunctionDef) and n.name == "main")
    caught = _handlers(main)
    assert "ForcenetError" in caught
    assert caught[-1] == "Exception", "the last handler of main() is the bug handler (exit 1, internal error)"
    allowed = {"SystemExit", "ForcenetError", "MemoryError", "KeyboardInterrupt", "BrokenPipeError", "OSError", "Exception"}
    assert set(caught) <= allowed, f"main() catches {sorted(set(caught) - allowed)}: a bug would pass as a usage error"
