"""Reference route: the moments by exact symbolic integration over the polytope (sympy).

:func:`integrate_moment` integrates a monomial in the W's over the polytope
``a_ij <= W_ij <= b_ij`` of Eqs. (4.8)-(4.9), layer by layer from the bottom
as in Sec. 4.3, and divides by the volume (4.1).  It implements the
definition directly, for small N (N <= 5).

Independence: this module shares no code with the routes it checks.  It may
import only :mod:`forcenet.core.validation` (argument checks), sympy and the
standard library.
"""

from __future__ import annotations

from fractions import Fraction
from functools import cache

import sympy

from forcenet.core.validation import check_layers

__all__ = ["w_symbols", "polytope_bounds", "integrate_moment"]


def w_symbols(N: int) -> dict[tuple[int, int], sympy.Expr]:
    """Free symbols ``W_i_j`` (``j < i``) and the dependent ``W_i_i = 1 - sum``.

    Examples
    --------
    >>> w_symbols(2)[(2, 2)]
    1 - W_2_1
    """
    W = {(1, 1): sympy.Integer(1)}
    for i in range(2, N + 1):
        row = [sympy.Symbol(f"W_{i}_{j}") for j in range(1, i)]
        for j, sym in enumerate(row, start=1):
            W[(i, j)] = sym
        W[(i, i)] = 1 - sum(row)
    return W


def polytope_bounds(N: int, W: dict[tuple[int, int], sympy.Expr] | None = None) -> dict[tuple[int, int], tuple[sympy.Expr, sympy.Expr]]:
    """Bounds ``(a_ij, b_ij)`` of Eq. (4.9) for each free ``W_ij``.

    ``a_ij = sum_{k<j} (W_{i-1,k} - W_{i,k})`` and ``b_ij = W_{i-1,j} + a_ij``.

    Examples
    --------
    >>> polytope_bounds(3)[(3, 2)]
    (W_2_1 - W_3_1, 1 - W_3_1)
    """
    W = W or w_symbols(N)
    out: dict[tuple[int, int], tuple[sympy.Expr, sympy.Expr]] = {}
    for i in range(2, N + 1):
        for j in range(1, i):
            a = sum((W[(i - 1, k)] - W[(i, k)] for k in range(1, j)), sympy.Integer(0))
            out[(i, j)] = (sympy.expand(a), sympy.expand(W[(i - 1, j)] + a))
    return out


@cache
def _integrate(N: int, exponents: tuple) -> sympy.Rational:
    W = w_symbols(N)
    bounds = polytope_bounds(N, W)
    expr = sympy.Integer(1)
    for (i, j), e in exponents:
        expr *= W[(i, j)] ** e
    expr = sympy.expand(expr)
    # innermost: bottom layer, decreasing j (Sec. 4.3)
    for i in range(N, 1, -1):
        for j in range(i - 1, 0, -1):
            x = W[(i, j)]
            a, b = bounds[(i, j)]
            antiderivative = sympy.Poly(expr, x).integrate().as_expr()
            expr = sympy.expand(antiderivative.subs(x, b) - antiderivative.subs(x, a))
    return sympy.Rational(expr)


def integrate_moment(N: int, powers: dict[tuple[int, int], int] | None = None) -> Fraction:
    """``< prod W_ij^{e_ij} >`` by exact symbolic integration over the polytope.

    With ``powers`` empty or ``None``, returns the normalization (4.1) itself.

    Examples
    --------
    >>> integrate_moment(4)
    Fraction(1, 360)
    >>> integrate_moment(4, {(4, 1): 1})
    Fraction(1, 7)
    """
    N = check_layers(N)
    volume = _integrate(N, ())
    if not powers:
        return Fraction(int(volume.p), int(volume.q))
    key = tuple(sorted((tuple(g), int(e)) for g, e in powers.items() if e))
    value = _integrate(N, key) / volume
    return Fraction(int(value.p), int(value.q))
