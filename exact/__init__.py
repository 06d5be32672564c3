"""Exact results for the force network ensemble (``forcenet.exact``).

Everything here is exact: Python ``int``, :class:`fractions.Fraction` or sympy
``Rational``; no result is a float.  One subpackage per model:

* :mod:`.triangle`: the fully mobilized triangle (the exact core);
* :mod:`.thesis`: the thesis's own routes of chapter 4;
* :mod:`.packing`: the N x P packing when every q is allowed;
* :mod:`.chicken_wire`: the chicken-wire vertex model of Sec. 7.4;
* :mod:`.limit_shape`: closed forms of the scaling limit;
* :mod:`.reference`: independent routes used to check the others.

The most used functions are re-exported here.

Examples
--------
>>> from forcenet.exact import count, normalization, mean_W
>>> count(6)
286
>>> normalization(4)
Fraction(1, 360)
>>> [str(w) for w in mean_W(4)[-1]]
['1/7', '5/14', '5/14', '1/7']
"""

from .triangle.moments import (
    correlation,
    covariance,
    mean_W,
    mean_W_grain,
    moment,
    moment_table,
    variance_table,
)
from .triangle.staircase import count, count_by_hooks, dimension, normalization

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
