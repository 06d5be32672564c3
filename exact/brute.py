"""Independent routes for small N: symbolic integration and linear extensions.

These implement the definitions directly and share no code with
:mod:`exact.ideal_dp`, so the tests can compare the two.

* :func:`integrate_moment` integrates a monomial in the W's over the polytope
  ``a_ij <= W_ij <= b_ij`` of Eqs. (4.8)-(4.9) with sympy, layer by layer from
  the bottom as in Sec. 4.3, and divides by the volume (4.1).
* :func:`linear_extension_moments` enumerates the linear extensions of the
  poset of partial sums with :func:`networkx.all_topological_sorts` and
  averages the order-statistic / Dirichlet formulas over them.
"""

from __future__ import annotations

from fractions import Fraction
from functools import lru_cache
from math import prod

import networkx as nx
import sympy

from .staircase import check_layers

__all__ = [
    "w_symbols",
    "polytope_bounds",
    "integrate_moment",
    "partial_sum_poset",
    "linear_extension_moments",
    "rank_gap_moments",
]


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


def polytope_bounds(N: int, W=None) -> dict[tuple[int, int], tuple[sympy.Expr, sympy.Expr]]:
    """Bounds ``(a_ij, b_ij)`` of Eq. (4.9) for each free ``W_ij``.

    ``a_ij = sum_{k<j} (W_{i-1,k} - W_{i,k})`` and ``b_ij = W_{i-1,j} + a_ij``.

    Examples
    --------
    >>> polytope_bounds(3)[(3, 2)]
    (W_2_1 - W_3_1, 1 - W_3_1)
    """
    W = W or w_symbols(N)
    out = {}
    for i in range(2, N + 1):
        for j in range(1, i):
            a = sum((W[(i - 1, k)] - W[(i, k)] for k in range(1, j)), sympy.Integer(0))
            out[(i, j)] = (sympy.expand(a), sympy.expand(W[(i - 1, j)] + a))
    return out


@lru_cache(maxsize=None)
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


def partial_sum_poset(N: int) -> nx.DiGraph:
    """DAG on the partial sums ``S_ij``, an edge ``u -> v`` meaning ``S_u <= S_v``.

    Interlacing of Eqs. (4.8)-(4.9): ``S_{i-1,j-1} <= S_{i,j} <= S_{i-1,j}``
    (only between free partial sums, ``1 <= j <= i - 1``).

    Examples
    --------
    >>> sorted(partial_sum_poset(3).edges())
    [((2, 1), (3, 2)), ((3, 1), (2, 1))]
    """
    G = nx.DiGraph()
    for i in range(2, N + 1):
        for j in range(1, i):
            G.add_node((i, j))
            if j <= i - 2:
                G.add_edge((i, j), (i - 1, j))
            if j >= 2:
                G.add_edge((i - 1, j - 1), (i, j))
    return G


def _rising(x, s):
    return prod(range(x, x + s))


def rank_gap_moments(N: int, rankings, s_max: int = 2, pairs=()):
    """Moments of the W's averaged over linear extensions given by their ranks.

    A uniform point of the order polytope of the partial sums is, given its
    linear extension, ``d`` sorted uniforms; the ``d + 1`` spacings are
    Dirichlet(1, ..., 1).  ``W_{i,j}`` is the sum of the spacings between the
    ranks of ``S_{i,j-1}`` and ``S_{i,j}``, so ``<W^s>`` is the rising
    factorial of the rank gap over ``(d+1)...(d+s)``, and
    ``<W W'> = (|I| |J| + |I & J|) / ((d+1)(d+2))`` for rank intervals ``I, J``.

    ``rankings`` yields dicts ``(i, j) -> rank`` of the free partial sums
    ``S_{i,j}``, ``1 <= j <= i - 1`` (ranks ``1..d``).  Returns
    ``(count, moments, correlations)`` as :func:`linear_extension_moments`.
    """
    d = N * (N - 1) // 2
    grains = [(i, j) for i in range(1, N + 1) for j in range(1, i + 1)]
    acc = {s: {g: 0 for g in grains} for s in range(1, s_max + 1)}
    pairs = list(dict.fromkeys(pairs))  # a repeated pair is counted once
    acc_pairs = {p: 0 for p in pairs}
    number = 0
    for rank in rankings:
        number += 1

        def gap_interval(g):
            i, j = g
            lo = 0 if j == 1 else rank[(i, j - 1)]
            hi = d + 1 if j == i else rank[(i, j)]
            return lo, hi

        for g in grains:
            lo, hi = gap_interval(g)
            for s in acc:
                acc[s][g] += _rising(hi - lo, s)
        for g1, g2 in pairs:
            (a1, b1), (a2, b2) = gap_interval(g1), gap_interval(g2)
            overlap = max(0, min(b1, b2) - max(a1, a2))
            acc_pairs[(g1, g2)] += (b1 - a1) * (b2 - a2) + overlap
    moments = {s: {g: Fraction(v, number * _rising(d + 1, s)) for g, v in acc[s].items()} for s in acc}
    correlations = {p: Fraction(v, number * (d + 1) * (d + 2)) for p, v in acc_pairs.items()}
    return number, moments, correlations


def linear_extension_moments(N: int, s_max: int = 2, pairs=()):
    """Moments averaged over all linear extensions (networkx enumeration).

    Returns ``(count, moments, correlations)`` where ``moments[s][(i, j)]`` is
    ``<W_ij^s>`` for ``s = 1..s_max`` and ``correlations[(g1, g2)]`` is
    ``<W_g1 W_g2>`` for each requested pair.

    Examples
    --------
    >>> c, mom, _ = linear_extension_moments(4)
    >>> c, mom[1][(4, 1)], mom[2][(4, 1)]
    (2, Fraction(1, 7), Fraction(1, 28))
    """
    N = check_layers(N)
    d = N * (N - 1) // 2
    G = partial_sum_poset(N)
    rankings = (
        {v: k + 1 for k, v in enumerate(ext)} for ext in (nx.all_topological_sorts(G) if d else [[]])
    )
    return rank_gap_moments(N, rankings, s_max, pairs)
