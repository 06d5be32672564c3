"""forcenet: exact enumeration and Monte Carlo for the force network ensemble of static granular matter.

* :mod:`forcenet.exact` — exact results (int, Fraction, sympy), one subpackage per model;
* :mod:`forcenet.numeric` — samplers, floating point and arbitrary precision;
* :mod:`forcenet.cli` — the command line ``forcenet``.

The map of the package is ``notes/architecture.md``.

Examples
--------
>>> import forcenet
>>> from importlib.metadata import version
>>> forcenet.__version__ == version("forcenet")
True
"""

from importlib.metadata import PackageNotFoundError, version

try:
    __version__: str = version("forcenet")  # one source: pyproject.toml, through the installed metadata
except PackageNotFoundError:  # imported from a tree that was never installed (not a supported way to run)
    __version__ = "0+unknown"
