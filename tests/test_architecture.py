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
    allowed = ("forcenet.exact.validation", "forcenet.exact.reference")
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
