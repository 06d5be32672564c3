"""forcenet: exact enumeration and Monte Carlo for the force network ensemble of static granular matter.

* :mod:`forcenet.exact` — exact results (int, Fraction, sympy), one subpackage per model;
* :mod:`forcenet.numeric` — samplers, floating point and arbitrary precision;
* :mod:`forcenet.cli` — the command line ``forcenet``.

The map of the package is ``notes/architecture.md``.
"""

__version__ = "0.1.0"
