"""Imports at the top of modules (issue 51): the graph is visible to readers and tools, and ``import forcenet`` light.

An import inside a function hides an edge of the module graph; the ones left are lazy on purpose (an optional or
heavy library: numba, scipy's submodules, matplotlib, distributed, tqdm) or not yet moved. The count may only go
down (issue 51's goal: at most 40; 243 before the seam). The package's one lazy loader is its top
(``forcenet.__getattr__``): ``import forcenet`` loads neither numpy nor sympy; a front-door name loads its own
engines (imported at the top of its module) and no other model's.
"""

from __future__ import annotations

import ast
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
MOST = 39  # imports inside functions now, each lazy on purpose: optional extras (PyNormaliz, distributed), matplotlib,
# tqdm's notebook probe, numba and the kernels whose decoration imports it, the command line after the environment
# check, and what every command's start-up would otherwise pay for one command (scipy.stats, .optimize, .sparse,
# asyncio, ssl)


def _count(source: str) -> int:
    """Import statements inside functions (nested ones included, each once)."""
    count = 0

    def visit(node: ast.AST, inside: bool) -> None:
        nonlocal count
        for child in ast.iter_child_nodes(node):
            if isinstance(child, (ast.Import, ast.ImportFrom)) and inside:
                count += 1
            visit(child, inside or isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef)))

    visit(ast.parse(source), False)
    return count


def _inner_imports() -> dict[str, int]:
    found = {str(path.relative_to(ROOT)): _count(path.read_text())
             for folder in ("src/forcenet", "core", "exact", "numeric") for path in sorted((ROOT / folder).rglob("*.py"))}
    return {name: n for name, n in found.items() if n}


def test_the_counter_sees_imports_inside_functions_only():
    source = ("import os\nif os:\n    import json\nclass C:\n    def m(self):\n        import sys\n"
              "def f():\n    def g():\n        from json import dumps\n    async def h():\n        import io\n")
    assert _count(source) == 3


def test_imports_inside_functions_only_go_down():
    found = _inner_imports()
    total = sum(found.values())
    assert 0 < total <= MOST, sorted(found.items(), key=lambda kv: -kv[1])[:15]
    assert "exact/routes.py" not in found and "exact/law_registry.py" not in found and "exact/row_routes.py" not in found


@pytest.mark.parametrize("name, heavy", [
    (None, ("numpy", "sympy", "numba", "forcenet.exact")),  # import forcenet alone: the one lazy loader
    # a front door loads its own engines, not others' (the triangle's samplers count with its exact staircase, whose
    # package brings sympy)
    ("sample_plan", ("numba", "forcenet.exact.routes")),
    ("count_plan", ("numba", "forcenet.exact.routes")),
    ("isotropic_point_plan", ("numba", "forcenet.exact.routes")),
    ("limit_shape", ("numba", "forcenet.exact.routes")),
    ("maps", ("numba", "forcenet.exact.routes")),
])
def test_a_front_door_name_loads_its_own_engines_only(name, heavy):
    code = "import sys, forcenet\n" + (f"forcenet.{name}\n" if name else "") + \
        "print(' '.join(m for m in sys.modules if m.split('.')[0] in ('numpy', 'sympy', 'numba') or m.startswith('forcenet.exact')))"
    loaded = set(subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.split())
    assert not loaded & set(heavy), loaded
