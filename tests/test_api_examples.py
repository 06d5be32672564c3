"""Every public name has a runnable example, checked without Sphinx (seconds, not the site's minutes).

The public names: everything in ``forcenet.__all__`` and ``forcenet.testing.__all__`` (the strategies
module's names too), every entry of the API reference's autosummary lists (docs/api/*.rst), and the
public methods and properties of each class among them. Each needs a numpydoc ``Examples`` section with
a ``>>>`` line, in a module that tests/test_doctests.py runs; where numpydoc is installed (the docs
extra), each also passes the checks docs/conf.py asks of the site's build, with nothing excluded but
dunder and private names, so the build's -W cannot fail on them.
"""

from __future__ import annotations

import ast
import importlib
import inspect
import re
from pathlib import Path

import pytest
from installed import installed_modules

import forcenet
import forcenet.testing

DOCS = Path(__file__).resolve().parents[1] / "docs"
_AUTOSUMMARY_ENTRY = re.compile(r"^\s+~?([A-Za-z_][\w.]*)\s*$")


def _resolve(name: str) -> object:
    """The object of a dotted name: the longest importable module short of the name, then attributes.

    A package's attribute wins over its submodule of the same name (``forcenet.testing.cross_check`` is the
    function), as on the rendered page.
    """
    parts = name.split(".")
    for n in range(len(parts) - 1, 0, -1):
        try:
            obj: object = importlib.import_module(".".join(parts[:n]))
        except ImportError:
            continue
        for part in parts[n:]:
            obj = getattr(obj, part)
        return obj
    raise LookupError(name)


def _reference_entries() -> list[str]:
    """The dotted names the API reference's autosummary lists render (under their ``currentmodule``)."""
    names = []
    for page in sorted((DOCS / "api").glob("*.rst")):
        module, listing = None, False
        for line in page.read_text(encoding="utf-8").splitlines():
            if line.startswith(".. currentmodule::"):
                module = line.split("::", 1)[1].strip()
            elif line.startswith(".. autosummary::"):
                listing = True
            elif listing and line and not line.startswith(" "):
                listing = False
            elif listing and (m := _AUTOSUMMARY_ENTRY.match(line)) and not line.strip().startswith(":"):
                names.append(f"{module}.{m.group(1)}")
    return names


def public_names() -> dict[str, object]:
    """Dotted name -> object for every public name (see the module docstring)."""
    found: dict[str, object] = {}
    for module in (forcenet, forcenet.testing, forcenet.testing.strategies):
        for name in module.__all__:
            obj = getattr(module, name)
            if inspect.isclass(obj) or inspect.isfunction(obj):
                found[f"{module.__name__}.{name}"] = obj
    for name in _reference_entries():
        found[name] = _resolve(name)
    for name, obj in list(found.items()):
        if inspect.isclass(obj):
            for member in dir(obj):
                raw = inspect.getattr_static(obj, member)
                if member.startswith("_"):
                    continue
                if isinstance(raw, (staticmethod, classmethod)):
                    raw = raw.__func__
                target = raw.fget if isinstance(raw, property) else raw
                if inspect.isfunction(target) and target.__module__.startswith("forcenet"):
                    found[f"{name}.{member}"] = raw
    return found


PUBLIC = public_names()


def _examples(doc: str) -> str:
    """The text of a numpydoc ``Examples`` section ('' if none)."""
    match = re.search(r"^Examples\n-{8,}\n(.*?)(?=^\w[\w ]*\n-{3,}\n|\Z)", doc, re.M | re.S)
    return match.group(1) if match else ""


def _defining_module(obj: object) -> str:
    target = obj.fget if isinstance(obj, property) else obj
    return getattr(inspect.unwrap(target), "__module__", "")  # type: ignore[arg-type]


def test_the_public_surface_is_found():
    # the front door, a testing class's method, a property, a strategy and a name only the reference lists
    for name in ("forcenet.table", "forcenet.testing.TableAgreement.summary", "forcenet.Scene.top_load",
                 "forcenet.testing.strategies.seeds", "forcenet.numeric.triangle.force_distribution.histogram_edges"):
        assert name in PUBLIC
    assert len(PUBLIC) > 250


def test_a_missing_example_is_seen():
    def documented():
        """Say it.

        Examples
        --------
        >>> 1 + 1
        2

        Notes
        -----
        None.
        """

    def undocumented():
        """Say it, with ``>>>`` in prose but no section.

        Notes
        -----
        >>> not an example
        """

    assert ">>>" in _examples(inspect.getdoc(documented))
    assert _examples(inspect.getdoc(undocumented)) == ""


@pytest.mark.parametrize("name", sorted(PUBLIC))
def test_every_public_name_has_a_runnable_example(name):
    obj = PUBLIC[name]
    doc = inspect.getdoc(obj.fget if isinstance(obj, property) else obj) or ""
    assert ">>>" in _examples(doc), f"{name}: no numpydoc Examples section with a >>> line"


def test_the_examples_run_as_doctests():
    walked = {module for module, _ in installed_modules()}
    outside = sorted({module for obj in PUBLIC.values() if (module := _defining_module(obj)) not in walked})
    assert not outside, f"public names defined where tests/test_doctests.py does not look: {outside}"


def test_the_site_excludes_nothing_public_from_validation():
    tree = ast.parse((DOCS / "conf.py").read_text(encoding="utf-8"))
    assigned = {target.id: node.value for node in tree.body if isinstance(node, ast.Assign)
                for target in node.targets if isinstance(target, ast.Name)}
    assert "NEEDS_WORK" not in assigned
    patterns = ast.literal_eval(assigned["numpydoc_validation_exclude"])
    assert patterns == {r"\.__\w+__$", r"\._\w+$"}


def test_the_reference_passes_the_sites_numpydoc_checks():
    validate = pytest.importorskip("numpydoc.validate", reason="the docs extra (pip install '.[docs]')").validate
    tree = ast.parse((DOCS / "conf.py").read_text(encoding="utf-8"))
    checks = next(ast.literal_eval(node.value) for node in tree.body if isinstance(node, ast.Assign)
                  and any(getattr(t, "id", None) == "numpydoc_validation_checks" for t in node.targets))
    failures = []
    for name in sorted(PUBLIC):
        try:
            report = validate(name)
        except AttributeError:  # a name reached only through a re-export: validate where it is defined
            obj = PUBLIC[name]
            target = obj.fget if isinstance(obj, property) else obj
            report = validate(f"{target.__module__}.{target.__qualname__}")
        found = [f"{code} {message}" for code, message in report["errors"] if code in checks]
        if found:
            failures.append(f"{name}: {'; '.join(found)}")
    assert not failures, "\n".join(failures)
