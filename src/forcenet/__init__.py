"""forcenet: exact enumeration and Monte Carlo for the force network ensemble of static granular matter.

* :mod:`forcenet.exact` — exact results (int, Fraction, sympy), one subpackage per model;
* :mod:`forcenet.numeric` — samplers, floating point and arbitrary precision;
* :mod:`forcenet.cli` — the command line ``forcenet``.

The exception family (:mod:`forcenet.core.errors`) is exported here:
:class:`ForcenetError`, the base of every expected failure, and the argument
errors :class:`ArgumentError` (also a ``ValueError``) and
:class:`ArgumentTypeError` (also a ``TypeError``), and :class:`ConvergenceError`
(also a ``RuntimeError``), and the warning :class:`PrecisionWarning` (a binary
float accepted where an exact number was expected).  They are loaded on first
use, so ``import forcenet`` stays cheap.

The map of the package is ``notes/architecture.md``.

Examples
--------
>>> import forcenet
>>> from importlib.metadata import version
>>> forcenet.__version__ == version("forcenet")
True
>>> issubclass(forcenet.ArgumentError, forcenet.ForcenetError), issubclass(forcenet.ArgumentError, ValueError)
(True, True)
"""

from __future__ import annotations

from importlib.metadata import PackageNotFoundError, version
from typing import TYPE_CHECKING

if TYPE_CHECKING:  # the type checker sees the names; at run time __getattr__ loads them on first use
    from forcenet.core.errors import ArgumentError, ArgumentTypeError, ConvergenceError, ForcenetError, PrecisionWarning

__all__ = ["ForcenetError", "ArgumentError", "ArgumentTypeError", "ConvergenceError", "PrecisionWarning", "__version__"]

_ERRORS = frozenset({"ForcenetError", "ArgumentError", "ArgumentTypeError", "ConvergenceError", "PrecisionWarning"})

try:
    __version__: str = version("forcenet")  # one source: pyproject.toml, through the installed metadata
except PackageNotFoundError:  # imported from a tree that was never installed (not a supported way to run)
    __version__ = "0+unknown"


def __getattr__(name: str) -> type[Exception]:
    """The exception family (and PrecisionWarning), imported on first use (``forcenet.exact`` costs about a second to import)."""
    if name in _ERRORS:
        from forcenet.core import errors

        return getattr(errors, name)
    raise AttributeError(f"module 'forcenet' has no attribute {name!r}")
