"""Every module's doctests, run through the installed package names (forcenet.exact, forcenet.numeric, forcenet.cli)."""

import doctest
import importlib
import pkgutil

import pytest

import forcenet


def _modules():
    names = ["forcenet"]
    for info in pkgutil.walk_packages(forcenet.__path__, prefix="forcenet."):
        if not info.name.endswith("__main__"):  # importing it runs the command line
            names.append(info.name)
    return sorted(names)


MODULES = _modules()


def test_every_subpackage_is_walked():
    for name in ("forcenet.exact.triangle.staircase", "forcenet.numeric.chicken_wire.bethe", "forcenet.cli"):
        assert name in MODULES


@pytest.mark.parametrize("name", MODULES)
def test_doctests(name):
    module = importlib.import_module(name)
    finder = doctest.DocTestFinder(exclude_empty=True)
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    for test in finder.find(module, name, globs=dict(vars(module))):
        runner.run(test)
    result = runner.summarize(verbose=False)
    assert result.failed == 0, f"{result.failed} doctest failure(s) in {name} (details above)"
