"""The house rules of notes/architecture.md (the map), checked on the source of every installed module.

The map is read, not copied: each package section's ``May import:`` line and each module bullet's
``May also import:`` / ``Imports only:`` are parsed here (grammar: the map's "How to read the rules"), so a rule
changed in the map changes the test, and a rule cannot live in the map without being checked.
"""

from __future__ import annotations

import ast
import functools
import re
import sys
from dataclasses import dataclass, field
from pathlib import Path

import pytest
from installed import ROOT, installed_modules

MAP = ROOT / "notes" / "architecture.md"

INSTALLED = installed_modules()
MODULES = sorted(INSTALLED)
NAMES = {name for name, _ in MODULES}
IS_PACKAGE = {name: path.name == "__init__.py" for name, path in MODULES}
# the packages: those installed, and forcenet.core (its modules exist before the folder does)
PACKAGES = {name for name, pkg in IS_PACKAGE.items() if pkg} | {"forcenet.core"}
PACKAGES_AND_MODULES = NAMES | PACKAGES


def package_of(name: str) -> str:
    return name if name in PACKAGES else name.rsplit(".", 1)[0]


# ------------------------------------------------------------------------------------------------ the map, parsed


@dataclass
class Bullet:
    files: list[str]
    also: list[str] = field(default_factory=list)
    only: list[str] | None = None


@dataclass
class Section:
    folder: str
    package: str
    may_import: list[str] | None = None
    bullets: list[Bullet] = field(default_factory=list)
    computing: list[str] | None = None  # the command line's section: the computing libraries it names


def _names_after(text: str, keyword: str) -> list[str] | None:
    """The backquoted names after ``keyword`` up to the sentence's end (a ``.`` or ``;`` outside backquotes)."""
    start = text.find(keyword)
    if start < 0:
        return None
    names, inside, buf = [], False, ""
    for ch in text[start + len(keyword):]:
        if ch == "`":
            if inside:
                names.append(buf)
                buf = ""
            inside = not inside
        elif inside:
            buf += ch
        elif ch in ".;":
            break
    return names


def _package_of_folder(folder: str) -> str:
    if folder.startswith("src/"):
        return folder[len("src/"):].replace("/", ".")
    return "forcenet." + folder.replace("/", ".")


def read_map(text: str | None = None) -> list[Section]:
    """The package sections of the map (headings ``## `folder` — title``) with their rules and bullets."""
    text = MAP.read_text() if text is None else text
    sections: list[Section] = []
    bullet_lines: list[str] = []

    def close_bullet() -> None:
        if bullet_lines and sections:
            body = " ".join(line.strip() for line in bullet_lines)
            head = body.split(" — ", 1)[0]
            files = [n for n in re.findall(r"`([^`]+)`", head) if n.endswith(".py")]
            if files:
                sections[-1].bullets.append(
                    Bullet(files, _names_after(body, "May also import:") or [], _names_after(body, "Imports only:")))
        bullet_lines.clear()

    current_is_package = False
    for line in text.splitlines():
        if line.startswith("## "):
            close_bullet()
            match = re.match(r"## `([\w/]+)` — ", line)
            current_is_package = bool(match)
            if match:
                sections.append(Section(match[1], _package_of_folder(match[1])))
            continue
        if not current_is_package:
            continue
        section = sections[-1]
        if line.startswith("- "):
            close_bullet()
            bullet_lines.append(line[2:])
        elif line.startswith("  ") and bullet_lines:
            bullet_lines.append(line)
        else:
            close_bullet()
            if line.startswith("May import:"):
                section.may_import = _names_after(line, "May import:")
            if "computing libraries (" in line:
                section.computing = _names_after(line, "computing libraries (")
    close_bullet()
    return sections


SECTIONS = read_map()
BY_PACKAGE = {s.package: s for s in SECTIONS}


def listed_modules() -> dict[str, tuple[Section, Bullet | None]]:
    """Every module the map lists (its section's package ``__init__`` included) with its section and bullet."""
    out: dict[str, tuple[Section, Bullet | None]] = {}
    for section in SECTIONS:
        out[section.package] = (section, None)
        for bullet in section.bullets:
            for file in bullet.files:
                stem = file[:-3]
                out[section.package if stem == "__init__" else f"{section.package}.{stem}"] = (section, bullet)
    return out


LISTED = listed_modules()

# --------------------------------------------------------------------------------------------- imports, resolved


_REAL_NAME = {path: name for name, path in INSTALLED}


def _resolve_relative_base(path: Path, name: str) -> str:
    real = _REAL_NAME.get(path, name)
    return real if path.name == "__init__.py" else real.rsplit(".", 1)[0]


@functools.cache
def module_imports(path: Path, name: str) -> list[str]:
    """Every module or package imported anywhere in the file (any scope), relative imports resolved.

    Relative imports resolve against the module's installed location. ``from P import a`` counts as importing ``P.a`` when that is a module of
    forcenet, else ``P``; libraries count by their top-level name. The package ``P`` itself, run first by any
    ``from P import ...``, does not count.
    """
    tree = ast.parse(path.read_text())
    return [target for node in ast.walk(tree) if isinstance(node, (ast.Import, ast.ImportFrom))
            for target in _resolve(node, path, name)]


def _resolve(node: ast.Import | ast.ImportFrom, path: Path, name: str) -> list[str]:
    """The names one import statement of the module imports (as :func:`module_imports` counts them)."""
    if isinstance(node, ast.Import):
        return [alias.name for alias in node.names]
    if node.level:
        base = _resolve_relative_base(path, name).split(".")
        target = ".".join(base[: len(base) - node.level + 1] + ([node.module] if node.module else []))
    else:
        target = node.module or ""
    out = []
    for alias in node.names:
        sub = f"{target}.{alias.name}"
        out.append(sub if sub in PACKAGES_AND_MODULES else target)
    return out


def _within(name: str, prefix: str) -> bool:
    return name == prefix or name.startswith(prefix + ".")


def _library(name: str) -> str:
    return name.split(".")[0]


def _stdlib(name: str) -> bool:
    return _library(name) in sys.stdlib_module_names or name == "__future__"


def allowed(module: str, target: str) -> bool:
    """May ``module`` import ``target`` by the map?"""
    if _stdlib(target):
        return True
    section, bullet = LISTED[module]
    if bullet is not None and bullet.only is not None:
        rules = bullet.only
    else:
        if package_of(target) == section.package and target.startswith("forcenet"):
            return True  # its own package
        rules = (section.may_import or []) + (bullet.also if bullet else [])
    if target.startswith("forcenet"):  # `forcenet` alone: the top of the package (its front door), not its tree
        return any(target == rule if rule == "forcenet" else _within(target, rule)
                   for rule in rules if rule.startswith("forcenet"))
    return _library(target) in rules


# ------------------------------------------------------------------------------------ the map lists every module


def test_the_map_is_read():
    assert {"forcenet.core", "forcenet.exact.triangle", "forcenet.cli", "forcenet.testing"} <= set(BY_PACKAGE)
    assert BY_PACKAGE["forcenet.exact.reference"].may_import == ["forcenet.core", "sympy", "networkx"]
    assert any(b.only == ["forcenet.exact.chicken_wire.square_triangle", "forcenet.core"] for b in BY_PACKAGE[
        "forcenet.exact.chicken_wire"].bullets)


def _rules_section(text: str | None = None) -> list[str]:
    """The bullets of the map's "The rules, each with its test", one string each."""
    text = MAP.read_text() if text is None else text
    section = text.split("\n## The rules, each with its test\n", 1)[1].split("\n## ", 1)[0]
    return [" ".join(b.split()) for b in ("\n" + section).split("\n- ")[1:]]


def _test_names() -> set[str]:
    """Every test function defined in tests/."""
    names: set[str] = set()
    for path in (ROOT / "tests").glob("test_*.py"):
        names |= {n.name for n in ast.walk(ast.parse(path.read_text())) if isinstance(n, ast.FunctionDef)
                  and n.name.startswith("test_")}
    return names


def test_every_rule_names_a_test():
    """Every rule of the map is a test: each bullet of its rules names at least one, and every name is defined."""
    rules, defined = _rules_section(), _test_names()
    assert len(rules) >= 10
    for rule in rules:
        named = re.findall(r"`(test_\w+)`", rule)
        assert named, f"the rule names no test: {rule[:100]}"
        assert set(named) <= defined, (set(named) - defined, rule[:100])


def test_the_rule_check_sees_a_rule_without_its_test():
    text = "\n## The rules, each with its test\n\n- A rule (`test_x`).\n- Another rule, untested.\n## Next\n"
    assert [re.findall(r"`(test_\w+)`", r) for r in _rules_section(text)] == [["test_x"], []]


def test_the_map_stays_short():
    """The map says what is, in at most 400 lines; the history of the house is notes/architecture_history.md."""
    assert len(MAP.read_text().splitlines()) <= 400


def test_the_parser_reads_each_kind_of_rule():
    """A control: a small map with each kind of line, parsed back."""
    text = ("## Prose\nMay import: `ignored`.\n## `exact/x` — a package\n\nMay import: `forcenet.core`, `numpy`.\n"
            "- `a.py`, `b.py` — two modules; May also import: `forcenet.exact.y` (why).\n"
            "- `c.py` — one,\n  over two lines. Imports only: `forcenet.core.errors`.\n"
            "- `d.py` — Imports only: the standard library.\n")
    (section,) = read_map(text)
    assert (section.package, section.may_import) == ("forcenet.exact.x", ["forcenet.core", "numpy"])
    assert [(b.files, b.also, b.only) for b in section.bullets] == [
        (["a.py", "b.py"], ["forcenet.exact.y"], None), (["c.py"], [], ["forcenet.core.errors"]), (["d.py"], [], [])]


def test_every_package_has_a_section_with_its_rule():
    packages = {package_of(name) for name in NAMES}
    assert not packages - set(BY_PACKAGE), f"packages without a section in the map: {sorted(packages - set(BY_PACKAGE))}"
    missing = [s.folder for s in SECTIONS if s.may_import is None]
    assert not missing, f"sections without a 'May import:' line: {missing}"


def test_every_installed_module_is_in_the_map():
    unlisted = sorted(NAMES - set(LISTED))
    assert not unlisted, f"modules missing from notes/architecture.md (add a bullet with its job and rule): {unlisted}"


def test_every_module_in_the_map_exists():
    ghosts = sorted(set(LISTED) - NAMES - {"forcenet.core"})
    assert not ghosts, f"notes/architecture.md lists modules that do not exist: {ghosts}"


def test_every_name_in_a_rule_exists():
    """A rule naming a module that does not exist allows nothing (a typo, or a module moved)."""
    bad = []
    for section in SECTIONS:
        rules = list(section.may_import or [])
        for bullet in section.bullets:
            rules += bullet.also + (bullet.only or [])
        bad += [(section.folder, r) for r in rules if r.startswith("forcenet") and r not in PACKAGES_AND_MODULES]
    assert not bad, f"rules naming no module: {bad}"


def test_every_module_named_in_the_equation_table_exists():
    table = MAP.read_text().split("## Where each thesis equation lives", 1)[1]
    named = {m for m in re.findall(r"`((?:exact|numeric)\.[\w.]+)`", table)}
    ghosts = sorted(m for m in named if "forcenet." + m not in PACKAGES_AND_MODULES)
    assert named and not ghosts, f"the equation table names modules that do not exist: {ghosts}"


def test_the_neutral_core_is_in_place():
    """forcenet.core is installed and holds the shared modules (errors, validation, plans, precision)."""
    real = {name for name, _ in INSTALLED}
    assert {f"forcenet.core.{m}" for m in ("errors", "validation", "plan", "precision")} <= real


@pytest.mark.parametrize("name, path", MODULES, ids=lambda x: str(x))
def test_the_map_is_the_only_statement_of_the_import_rules(name, path):
    """No module docstring restates an import rule: the map (notes/architecture.md) is the one statement."""
    doc = ast.get_docstring(ast.parse(path.read_text())) or ""
    stated = [line for line in doc.splitlines() if re.match(r"\s*(May import:|May also import:|Imports only:)", line)]
    assert not stated, f"{name} states import rules in its docstring ({stated[0].strip()!r}); they live in the map only"


# ----------------------------------------------------------------------------------------------- import rules


@pytest.mark.parametrize("name, path", MODULES, ids=lambda x: str(x))
def test_imports_follow_the_map(name, path):
    """Each module imports only its own package, its section's ``May import:`` and its bullet's additions."""
    if name not in LISTED:
        pytest.fail(f"{name} is not in notes/architecture.md")
    bad = sorted({t for t in module_imports(path, name) if not allowed(name, t)})
    assert not bad, f"{name} imports {bad}, which notes/architecture.md does not allow it"


def test_the_layering_holds_in_the_map_itself():
    """exact never imports numeric, the CLI or the testing toolkit; core nothing of forcenet; nothing the CLI."""
    for section in SECTIONS:
        rules = list(section.may_import or [])
        for bullet in section.bullets:
            rules += bullet.also + (bullet.only or [])
        ours = [r for r in rules if r.startswith("forcenet")]
        if _within(section.package, "forcenet.exact"):
            assert not [r for r in ours if not _within(r, "forcenet.exact") and not _within(r, "forcenet.core")], section
            assert "matplotlib" not in rules, section
        if _within(section.package, "forcenet.core"):
            assert not [r for r in ours if not _within(r, "forcenet.core")], section
        if _within(section.package, "forcenet.numeric"):
            assert not [r for r in ours if _within(r, "forcenet.cli") or _within(r, "forcenet.testing")], section
        if section.package != "forcenet":
            assert not [r for r in ours if _within(r, "forcenet.cli")], section


@pytest.mark.parametrize("name, path", MODULES, ids=lambda x: str(x))
def test_relative_imports_stay_inside_their_subpackage(name, path):
    """Across subpackages (exact, numeric, cli, testing, core) imports are absolute ``forcenet.*``."""
    real = _REAL_NAME[path]
    if real.count(".") < 1 or real in ("forcenet.__main__",):
        return  # the root package's own modules: the whole package is theirs
    home = real.split(".")[1]
    base = _resolve_relative_base(path, real)
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom) and node.level:
            parts = base.split(".")
            target = parts[: len(parts) - node.level + 1]
            assert len(target) > 1 and target[1] == home, (
                f"{real} line {node.lineno}: relative import out of forcenet.{home}; write forcenet.*")


def _cycles() -> list[list[str]]:
    """Import cycles between modules (any scope; a package's own ``__init__`` re-exports not counted)."""
    graph = {name: {t for t in module_imports(path, name) if t in NAMES and t != name and not (
        IS_PACKAGE.get(t) and _within(name, t))} for name, path in MODULES}
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on: set[str] = set()
    out: list[list[str]] = []

    def visit(v: str) -> None:  # Tarjan's strongly connected components
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in graph[v]:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                out.append(sorted(component))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return out


def test_no_import_cycles():
    """No two modules import each other, directly or around a loop (a package's re-exports aside)."""
    cycles = _cycles()
    assert not cycles, f"import cycles: {cycles}"


MAX_IMPORT_DEPTH = 6  # issue 44: no import chain inside exact/triangle deeper than 6 modules


def longest_import_chain(inside: str, graph: dict[str, set[str]] | None = None) -> list[str]:
    """The longest chain ``a -> b -> ...`` of imports (any scope) between the modules in ``inside``, as a list of
    modules (a package's ``__init__`` is a module; a module importing its own package does not count).

    ``graph`` (module -> modules it imports) defaults to the installed package's; the graph has no cycle
    (:func:`test_no_import_cycles`), so the longest path is well defined.
    """
    if graph is None:
        graph = {name: {t for t in module_imports(path, name) if t in NAMES and t != name and not (
            IS_PACKAGE.get(t) and _within(name, t))} for name, path in MODULES}
    nodes = {name for name in graph if _within(name, inside)}

    @functools.cache
    def chain(v: str) -> tuple[str, ...]:
        return (v,) + max((chain(w) for w in sorted(graph[v] & nodes)), key=len, default=())

    return list(max((chain(v) for v in sorted(nodes)), key=len, default=()))


def test_the_chain_measure_sees_chains():
    graph = {"p.a": {"p.b", "q.x"}, "p.b": {"p.c"}, "p.c": set(), "p.d": {"p.c"}, "q.x": {"p.a"}}
    assert longest_import_chain("p", graph) == ["p.a", "p.b", "p.c"]
    assert longest_import_chain("q", graph) == ["q.x"]


def test_import_chains_inside_the_triangle_are_short():
    """No import chain between the modules of ``forcenet.exact.triangle`` (its subpackages included) is longer
    than six modules: the algorithms' packages import what they use, nothing incidental."""
    chain = longest_import_chain("forcenet.exact.triangle")
    assert len(chain) >= 3  # the measure sees the package (a chain of one would mean an empty graph)
    assert len(chain) <= MAX_IMPORT_DEPTH, f"{len(chain)} modules deep: {' -> '.join(chain)}"


# the command line reaches the library only through these: the front door, the neutral core, the registry, the toolkit
_FRONT_DOOR_RULES = ("forcenet", "forcenet.core", "forcenet.exact.routes", "forcenet.testing")


def _cli_rules() -> list[str]:
    section = BY_PACKAGE["forcenet.cli"]
    rules = list(section.may_import or [])
    for bullet in section.bullets:
        rules += bullet.also + (bullet.only or [])
    return rules


def test_the_command_line_computes_nothing_by_structure():
    """The cli section allows no engine and no computing library; test_imports_follow_the_map holds the modules to it."""
    computing = BY_PACKAGE["forcenet.cli"].computing or []
    assert {"numpy", "sympy", "mpmath", "flint"} <= set(computing), "the cli section names the computing libraries"
    rules = _cli_rules()
    engines = [r for r in rules if r.startswith("forcenet") and r not in _FRONT_DOOR_RULES]
    assert not engines, f"the command line may import {engines}: reach them through the front door (forcenet.NAME)"
    libraries = [r for r in rules if _library(r) in computing]
    assert not libraries, f"the command line may import {libraries}: computation belongs next to its engine"


def _front_door_reads(tree: ast.AST) -> list[tuple[int, str]]:
    """``(line, name)`` of every name a module takes from the top of the package: ``from forcenet import name``
    and ``forcenet.name`` on the module imported as ``forcenet``."""
    reads = []
    top = {(a.asname or a.name) for node in ast.walk(tree) if isinstance(node, ast.Import)
           for a in node.names if a.name == "forcenet"}
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.module == "forcenet" and not node.level:
            reads += [(node.lineno, a.name) for a in node.names]
        elif isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name) and node.value.id in top:
            reads.append((node.lineno, node.attr))
    return reads


def test_the_front_door_check_sees_the_names():
    tree = ast.parse("import forcenet\nfrom forcenet import plan, testing\nx = forcenet.table(3)\n")
    assert sorted(_front_door_reads(tree)) == [(2, "plan"), (2, "testing"), (3, "table")]


@pytest.mark.parametrize("name, path", [m for m in MODULES if m[0].startswith("forcenet.cli")], ids=lambda x: str(x))
def test_the_command_line_takes_only_front_door_names(name, path):
    """What a cli module takes from ``forcenet`` is a front-door name (``forcenet.__all__``) or the toolkit."""
    import forcenet

    public = set(forcenet.__all__) | {"testing", "__version__"}
    bad = [(line, what) for line, what in _front_door_reads(ast.parse(path.read_text())) if what not in public]
    assert not bad, f"{name} takes {bad} from the top of the package, which are not front-door names"


# ------------------------------------------------------------------------------------- one copy of each rule


def _inline_dimension(node: ast.AST) -> bool:
    """``N * (N - 1) // 2`` (either factor order, any name): the number of free forces written by hand."""
    if not (isinstance(node, ast.BinOp) and isinstance(node.op, ast.FloorDiv)
            and isinstance(node.right, ast.Constant) and node.right.value == 2):
        return False
    product = node.left
    if not (isinstance(product, ast.BinOp) and isinstance(product.op, ast.Mult)):
        return False
    for a, b in ((product.left, product.right), (product.right, product.left)):
        if (isinstance(b, ast.BinOp) and isinstance(b.op, ast.Sub) and isinstance(b.right, ast.Constant)
                and b.right.value == 1 and ast.dump(b.left) == ast.dump(a)):
            return True
    return False


def test_the_dimension_check_sees_the_pattern():
    hits = [_inline_dimension(n) for n in ast.walk(ast.parse("a = N * (N - 1) // 2\nb = (k - 1) * k // 2\n"
                                                          "c = N * (N + 1) // 2\nd = dimension(N)"))]
    assert sum(hits) == 2


@pytest.mark.parametrize("name, path", [m for m in MODULES if m[0] != "forcenet.exact.triangle.staircase"
                                        and not m[0].startswith("forcenet.exact.reference")], ids=lambda x: str(x))
def test_dimension_is_written_in_one_place(name, path):
    """``d = N(N-1)/2`` (4.3) lives in staircase.dimension; the reference routes, which share no code, aside."""
    hits = [n.lineno for n in ast.walk(ast.parse(path.read_text())) if _inline_dimension(n)]
    assert not hits, f"{name} writes N*(N-1)//2 at lines {hits}: use forcenet.exact.triangle.staircase.dimension"


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


@pytest.mark.parametrize("name, path", [m for m in MODULES if m[0] != "forcenet.core.validation"], ids=lambda x: str(x))
def test_one_integer_check_for_the_whole_package(name, path):
    """Every integer argument is checked by forcenet.core.validation (one message format, one policy)."""
    hits = _integer_checks(ast.parse(path.read_text()))
    assert not hits, f"{name} checks integers by hand at {hits}; use forcenet.core.validation"


# ------------------------------------------------------------------------------------------ the remaining rules


@pytest.mark.parametrize("name, path", MODULES, ids=lambda x: str(x))
def test_no_generic_top_level_imports(name, path):
    """Inside the package everything is imported as forcenet.* (nothing generic at the top of site-packages)."""
    bad = [m for m in module_imports(path, name) if m.split(".")[0] in ("exact", "numeric")]
    assert not bad, f"{name} imports {bad}"


def test_no_test_or_benchmark_imports_the_folders_by_their_generic_names():
    """The checkout's root holds exact/ and numeric/; tests and benchmarks import them as forcenet.*."""
    bad = []
    for path in sorted((ROOT / "tests").glob("*.py")) + sorted((ROOT / "benchmarks").glob("*.py")):
        for node in ast.walk(ast.parse(path.read_text())):
            names = [a.name for a in node.names] if isinstance(node, ast.Import) else (
                [node.module or ""] if isinstance(node, ast.ImportFrom) and not node.level else [])
            bad += [(path.name, n) for n in names if n.split(".")[0] in ("exact", "numeric")]
    assert not bad, f"generic imports: {bad}"


def test_no_module_sets_a_global_precision():
    for name, path in MODULES:
        text = path.read_text()
        for pattern in ("mp.dps =", "mp.prec =", "ctx.dps =", "ctx.prec ="):
            assert pattern not in text, f"{name} sets a global precision ({pattern})"


def test_files_stay_readable():
    too_long = [(name, n) for name, path in MODULES if (n := len(path.read_text().splitlines())) > 600]
    assert not too_long, f"modules over 600 lines (split by job): {too_long}"


def _import_time_imports(path: Path) -> list[ast.Import | ast.ImportFrom]:
    """The import statements that run when the module is imported (not those inside functions)."""
    found: list[ast.Import | ast.ImportFrom] = []
    stack: list[ast.AST] = [ast.parse(path.read_text())]
    while stack:
        node = stack.pop()
        if isinstance(node, (ast.Import, ast.ImportFrom)):
            found.append(node)
        elif not isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda)):
            stack.extend(ast.iter_child_nodes(node))
    return found


def test_the_testing_toolkit_needs_hypothesis_only_for_its_strategies():
    """``import forcenet.testing`` does not import hypothesis (the strategies are imported on first use).

    Checked on the modules ``import forcenet.testing`` runs: their import-time imports, followed through
    forcenet (a package's parents included), reach no ``hypothesis``.
    """
    files = dict(MODULES)
    seen, todo, reached = set(), ["forcenet.testing"], set()
    while todo:
        name = todo.pop()
        if name in seen or name not in files:
            continue
        seen.add(name)
        todo += [".".join(name.split(".")[:k]) for k in range(2, name.count(".") + 1)]  # its parent packages
        for node in _import_time_imports(files[name]):
            for target in _resolve(node, files[name], name):
                reached.add(_library(target))
                todo.append(target)
    assert "forcenet.testing.strategies" not in seen and "hypothesis" not in reached, sorted(seen)


# ---------------------------------------------------------------- errors (notes/architecture.md, "Errors")

_BUILTIN_BASES = {"Exception", "ValueError", "TypeError"}  # only the family's module derives from these directly
_ERRORS_MODULE = "forcenet.core.errors"


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
    assert not raises, f"{name} raises builtins at {raises}: raise forcenet.core.errors.ArgumentError / ArgumentTypeError"
    assert not asserts, f"{name} has bare assert at lines {asserts}: raise an error instead (python -O strips asserts)"


def _errors_section() -> str:
    text = MAP.read_text()
    start = text.index("\n## Errors\n")
    end = text.find("\n## ", start + 1)
    return text[start:end if end > 0 else len(text)]


# the names the map allows outside the family ("Errors", rule 1), each with where it may be raised
OUTSIDE_THE_FAMILY = _names_after(" ".join(_errors_section().split()), "of these only:") or []


@functools.cache
def _exception_classes() -> dict[str, set[str]]:
    """``{class name: its bases' last names}`` for every class the installed package defines."""
    out: dict[str, set[str]] = {}
    for _, path in MODULES:
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ClassDef):
                out.setdefault(node.name, set()).update(ast.unparse(b).rsplit(".", 1)[-1] for b in node.bases)
    return out


def _derives_from(name: str, roots: set[str]) -> bool:
    classes, seen, todo = _exception_classes(), set(), [name]
    while todo:
        current = todo.pop()
        if current in roots:
            return True
        if current not in seen:
            seen.add(current)
            todo += classes.get(current, ())
    return False


@functools.cache
def _family() -> set[str]:
    tree = ast.parse(dict(MODULES)[_ERRORS_MODULE].read_text())
    defined = {n.name for n in tree.body if isinstance(n, ast.ClassDef)}
    return {n for n in defined if _derives_from(n, {"ForcenetError"})}


def raise_offenders(name: str, source: str) -> list[tuple[int, str]]:
    """``(line, what)`` of every ``raise`` in ``source`` outside the family and the map's allowed set."""
    tree = ast.parse(source)
    returns = {n.name: ast.unparse(n.returns).rsplit(".", 1)[-1] for n in ast.walk(tree)
               if isinstance(n, (ast.FunctionDef, ast.AsyncFunctionDef)) and n.returns is not None}
    family, outside = _family(), set(OUTSIDE_THE_FAMILY)
    bug_roots = {"ArithmeticError"} & outside
    where = {}  # the function around each raise (AttributeError: in __getattr__ only)
    for function in ast.walk(tree):
        if isinstance(function, (ast.FunctionDef, ast.AsyncFunctionDef)):
            for node in ast.walk(function):
                if isinstance(node, ast.Raise):
                    where[id(node)] = function.name  # walked outside in: the innermost function wins
    out = []
    for node in ast.walk(tree):
        if not isinstance(node, ast.Raise) or node.exc is None:
            continue  # a bare raise re-raises
        target = node.exc.func if isinstance(node.exc, ast.Call) else node.exc
        raised = ast.unparse(target)
        short = raised.rsplit(".", 1)[-1]
        if isinstance(node.exc, ast.Call) and short in returns and short not in _exception_classes():
            short = raised = returns[short]  # raise make_error(...): the class its annotation names
        if raised in outside:  # before the family: argparse.ArgumentTypeError is not forcenet's
            if raised == "AttributeError" and where.get(id(node)) != "__getattr__":
                out.append((node.lineno, f"{raised} outside a module's __getattr__"))
            elif raised.startswith("argparse.") and not name.startswith("forcenet.cli"):
                out.append((node.lineno, f"{raised} outside the command line"))
            continue
        if _derives_from(short, family) or (bug_roots and _derives_from(short, bug_roots)):
            continue
        out.append((node.lineno, raised))
    return out


def test_the_map_names_the_raises_allowed_outside_the_family():
    assert set(OUTSIDE_THE_FAMILY) == {"ArithmeticError", "KeyboardInterrupt", "AttributeError", "ImportError",
                                       "argparse.ArgumentTypeError"}, OUTSIDE_THE_FAMILY
    assert {"ForcenetError", "ArgumentError", "ArgumentTypeError", "ConvergenceError"} <= _family()


def test_the_raise_rule_sees_what_is_outside_the_family():
    """A control: the rule finds a builtin, a misplaced AttributeError and argparse's error, and passes the family."""
    source = (
        "import argparse\n"
        "from forcenet.core.errors import ArgumentError\n"
        "def _refuse(why) -> ArgumentError:\n    return ArgumentError(why)\n"
        "def f(x):\n"
        "    if x == 1: raise RuntimeError('no')\n"
        "    if x == 2: raise AttributeError(x)\n"
        "    if x == 3: raise argparse.ArgumentTypeError('x')\n"
        "    if x == 4: raise TimeoutError\n"
        "    if x == 5: raise ArgumentError('fine')\n"
        "    if x == 6: raise _refuse('fine')\n"
        "    if x == 7: raise ArithmeticError('a failed check: a bug')\n"
        "    raise\n"
        "def __getattr__(name):\n    raise AttributeError(name)\n"
    )
    found = raise_offenders("forcenet.exact.example", source)
    assert [line for line, _ in found] == [6, 7, 8, 9], found
    assert not raise_offenders("forcenet.cli.example", "import argparse\nraise argparse.ArgumentTypeError('x')\n")


@pytest.mark.parametrize("name, path", MODULES, ids=lambda x: str(x))
def test_every_raise_is_the_family_or_allowed_by_the_map(name, path):
    """Every ``raise``: the family, a re-raise, or one of the map's short list where the map allows it."""
    found = raise_offenders(name, path.read_text())
    assert not found, (f"{name} raises outside the exception family at {found}: raise a class of "
                       "forcenet.core.errors (notes/architecture.md, Errors)")


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
                "(forcenet.core.errors) if it is an expected failure")


def _handlers(function: ast.FunctionDef) -> list[str]:
    names = []
    for node in ast.walk(function):
        if isinstance(node, ast.ExceptHandler) and node.type is not None:
            kinds = node.type.elts if isinstance(node.type, ast.Tuple) else [node.type]
            names += [ast.unparse(k) for k in kinds]
    return names


def test_the_command_line_boundary_catches_only_the_family():
    """main(): the family, memory, interruption, a reader that left; any other exception (an OSError too) is the bug
    handler's: the file and stream operations raise the family themselves."""
    path = dict(MODULES)["forcenet.cli"]
    main = next(n for n in ast.parse(path.read_text()).body if isinstance(n, ast.FunctionDef) and n.name == "main")
    caught = _handlers(main)
    assert "ForcenetError" in caught
    assert caught[-1] == "Exception", "the last handler of main() is the bug handler (exit 1, internal error)"
    allowed_here = {"SystemExit", "ForcenetError", "MemoryError", "KeyboardInterrupt", "BrokenPipeError", "Exception"}
    assert set(caught) <= allowed_here, f"main() catches {sorted(set(caught) - allowed_here)}: a bug would pass as a usage error"


# ------------------------------------------------------ other libraries (notes/architecture.md, "Other libraries")

def _allowed_private_names() -> set[str]:
    """The backquoted names after "The allowed names" in the map's "Other libraries" section."""
    text = MAP.read_text()
    section = text[text.index("## Other libraries"):]
    section = " ".join(section[:section.index("\n## ", 1)].split())
    allowed = section[section.index("The allowed names"):]
    return {name.split(".")[-1].rstrip(")") for name in re.findall(r"`([A-Za-z_.]+)`", allowed)
            if name.split(".")[-1].startswith("_")}


@functools.cache
def _names_defined_by_forcenet() -> frozenset[str]:
    defined: set[str] = set()
    for _, path in MODULES:
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
                defined.add(node.name)
            elif isinstance(node, ast.Attribute) and isinstance(node.ctx, ast.Store):
                defined.add(node.attr)
            elif isinstance(node, ast.Name) and isinstance(node.ctx, ast.Store):
                defined.add(node.id)
            elif isinstance(node, ast.arg):
                defined.add(node.arg)
            elif isinstance(node, ast.alias):
                defined.add(node.asname or node.name.split(".")[-1])
    return frozenset(defined)


def _foreign_private_reads(tree: ast.AST, defined, allowed) -> list[str]:
    found = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Attribute) and node.attr.startswith("_") and not node.attr.startswith("__") \
                and node.attr not in defined and node.attr not in allowed:
            found.append(f"line {node.lineno}: {ast.unparse(node)}")
        elif isinstance(node, (ast.Import, ast.ImportFrom)):
            names = [a.name for a in node.names] if isinstance(node, ast.Import) else [node.module or ""]
            found += [f"line {node.lineno}: import {n}" for n in names if n == "numba.core" or
                      n.startswith("numba.core.")]
    return found


def test_the_private_attribute_check_sees_them():
    """A control: the reads issue 44 found, in a module that defines none of those names, are all seen."""
    source = ("def f(executor, pool, dispatcher):\n"
              "    from numba.core import caching\n"
              "    return executor._max_workers, pool._processes, executor._client, dispatcher._cache, os._exit\n")
    found = _foreign_private_reads(ast.parse(source), {"f", "executor", "pool", "dispatcher", "caching"}, {"_exit"})
    assert sorted(f.split(": ", 1)[1] for f in found) == ["dispatcher._cache", "executor._client",
                                                          "executor._max_workers", "import numba.core",
                                                          "pool._processes"], found
    assert _allowed_private_names() == {"_exit", "_actions", "_SubParsersAction", "_HelpAction", "_VersionAction",
                                       "_replace", "_asdict", "_fields"}


@pytest.mark.parametrize("name, path", MODULES, ids=lambda x: str(x))
def test_no_private_attribute_of_another_library(name, path):
    found = _foreign_private_reads(ast.parse(path.read_text()), _names_defined_by_forcenet(), _allowed_private_names())
    assert not found, (f"{name} reads private attributes of other libraries ({found}): use their public interface, "
                       "or keep the fact yourself (notes/architecture.md, \"Other libraries\")")
