"""Every module's doctests, run through the installed package names (forcenet.exact, forcenet.numeric, forcenet.cli)."""

import doctest
import importlib

import pytest
from installed import installed_modules


def _modules():
    # importing __main__ runs the command line
    return [name for name, _ in installed_modules() if not name.endswith("__main__")]


MODULES = _modules()
# the Bethe-ansatz modules' examples solve the equations at several sizes (~40 s and ~20 s): under -m slow
SLOW_DOCTESTS = {"forcenet.numeric.chicken_wire.bethe", "forcenet.numeric.chicken_wire.isotropic_bethe"}


def test_every_subpackage_is_walked():
    for name in ("forcenet.exact.triangle.staircase", "forcenet.numeric.chicken_wire.bethe", "forcenet.cli"):
        assert name in MODULES


@pytest.mark.parametrize("name", [pytest.param(m, marks=pytest.mark.slow) if m in SLOW_DOCTESTS else m for m in MODULES])
def test_doctests(name):
    module = importlib.import_module(name)
    finder = doctest.DocTestFinder(exclude_empty=True)
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    for test in finder.find(module, name, globs=dict(vars(module))):
        runner.run(test)
    result = runner.summarize(verbose=False)
    assert result.failed == 0, f"{result.failed} doctest failure(s) in {name} (details above)"
