"""Exact means on a small N x P packing when every q is allowed (Secs. 3.2-3.3).

In the fully mobilized case (``p_h`` large; the thesis's gravity scene,
Sec. 3.3.2) the free ``q_{i,j}``, ``i < N``, ``j < P``, range over the unit
cube with density ``prod W_{i,j}(q)`` (Eq. 3.10), a polynomial; so

``<W_{k,l}> = int W_{k,l} prod W dq / int prod W dq``

is a ratio of integrals of polynomials over a cube: exact rationals for
rational loads.  Geometry and boundary as in :mod:`forcenet.numeric.packing` (right
column ``q = 1``).  Cost grows like the number of monomials; meant for
``(N-1)(P-1) <= 9`` as the exact reference of the Metropolis sampler.
"""

from __future__ import annotations

from fractions import Fraction
from functools import reduce
from typing import Any

import sympy

from forcenet.core.errors import ArgumentError
from forcenet.core.validation import check_int, check_rational

__all__ = ["mean_W_mobilized"]


def _rational(name: str, value: Any) -> Fraction:
    r = check_rational(value, name)  # an int, Fraction or string; a binary float only when exactly its decimal
    if r < 0:
        raise ArgumentError(f"{name}={value} is out of range: {name} must be >= 0")
    return r


def mean_W_mobilized(N: int, P: int, F: int | Fraction | str = 1, j0: int | None = None, pv: int | Fraction | str = 0,
                     mg: int | Fraction | str = 0) -> list[list[Fraction]]:
    """Exact ``<W_{i,j}>`` on the N x P packing with every q in [0, 1] allowed.

    Parameters
    ----------
    N, P : int
        Layers and grains per layer, ``N, P >= 2`` and ``(N-1)(P-1) <= 9``.
    F, pv, mg : int, Fraction or str
        Overload on grain ``(1, j0)``, top load per grain, grain weight (exact).
    j0 : int, optional
        Overload column ``1..P`` (default ``(P+1)//2``).

    Returns
    -------
    list of lists of Fraction
        Row ``i-1`` holds ``<W_{i,1..P}>``.

    Raises
    ------
    ArgumentError
        If a size is out of range, a load is negative, or the total load is zero.
    ArgumentTypeError
        If a load is not an exact number.

    Examples
    --------
    Gravity, two layers of two grains, overload 1 on the left grain:

    >>> mean_W_mobilized(2, 2, F=1, j0=1, mg=1)
    [[Fraction(2, 1), Fraction(1, 1)], [Fraction(2, 1), Fraction(3, 1)]]

    Every layer carries the whole load, ``F + i P mg`` (here 1 + 2i):

    >>> [sum(row) for row in mean_W_mobilized(3, 3, F=1, j0=2, mg=1)]
    [Fraction(4, 1), Fraction(7, 1), Fraction(10, 1)]
    """
    N, P = check_int(N, "N", 2), check_int(P, "P", 2)
    if (N - 1) * (P - 1) > 9:
        raise ArgumentError(f"(N-1)(P-1)={(N - 1) * (P - 1)} is out of range: at most 9 free q's for exact integration")
    j0 = (P + 1) // 2 if j0 is None else check_int(j0, "j0", 1, P)
    F, pv, mg = _rational("F", F), _rational("pv", pv), _rational("mg", mg)
    qs = [[sympy.Symbol(f"q_{i}_{j}") for j in range(1, P)] for i in range(1, N)]
    gens = [s for row in qs for s in row]
    one = sympy.Poly(1, *gens, domain="QQ")

    def const(r: Fraction) -> sympy.Poly:
        return one * sympy.Rational(r.numerator, r.denominator)

    q = [[one * s for s in row] + [one] for row in qs]  # right column: q = 1
    W = [[const(pv + mg + (F if j == j0 - 1 else 0)) for j in range(P)]]
    for i in range(1, N):  # Eq. (3.9)
        row = []
        for j in range(P):
            w = q[i - 1][j] * W[i - 1][j] + const(mg)
            if j > 0:
                w += (one - q[i - 1][j - 1]) * W[i - 1][j - 1]
            row.append(w)
        W.append(row)
    weight = reduce(lambda a, b: a * b, (W[i][j] for i in range(N - 1) for j in range(P - 1)), one)

    def integrate(poly: Any) -> Fraction:  # over the unit cube: x^e -> 1/(e+1)
        total = Fraction(0)
        for exps, c in poly.terms():
            den = 1
            for e in exps:
                den *= e + 1
            total += Fraction(int(c.p), int(c.q) * den)
        return total

    Z = integrate(weight)
    if Z == 0:
        raise ArgumentError("the total load is zero: nothing to average")
    return [[integrate(W[i][j] * weight) / Z for j in range(P)] for i in range(N)]
