"""Exact results for the force network ensemble of the fully mobilized triangle.

Everything here is exact: Python ``int``, :class:`fractions.Fraction` or sympy
``Rational``; nothing in this package uses floating point.

Examples
--------
>>> from exact import count, normalization, mean_W
>>> count(6)
286
>>> normalization(4)
Fraction(1, 360)
>>> [str(w) for w in mean_W(4)[-1]]
['1/7', '5/14', '5/14', '1/7']
"""

from .moments import (
    correlation,
    covariance,
    mean_W,
    mean_W_grain,
    moment,
    moment_table,
    variance_table,
)
from .staircase import count, count_by_hooks, dimension, normalization

__all__ = [
    "count",
    "count_by_hooks",
    "dimension",
    "normalization",
    "mean_W",
    "mean_W_grain",
    "moment",
    "moment_table",
    "correlation",
    "covariance",
    "variance_table",
]
