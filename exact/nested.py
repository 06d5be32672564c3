"""Layer-by-layer nested-matrix integration (thesis Secs. 4.3-4.5), exactly.

The thesis integrates the uniform measure over the W's layer by layer from
the bottom, and finds that after each layer the remaining integrand is a
matrix product ``L t(W_{m,1}) t(W_{m,2}) ... t(W_{m,m}) R`` over the grains of
the current layer ``m`` (Eqs. 4.4, 4.27), whose matrix indices are nested
tuples (Fig. 4.1b).  This module implements that recursion directly.

One integration step (layer ``m`` -> ``m-1``): write ``X_k = W_{m,k}``,
``Y_k = W_{m-1,k}``, ``u_k = b_{m,k} - X_k``.  By (4.9)-(4.11),
``b_k - a_k = Y_k``, ``a_k = u_{k-1}`` (``a_1 = 0``) and ``X_m = u_{m-1}``.
Sweeping ``k = m-1, ..., 1`` and integrating ``X_k`` with the central
integral (4.14),

    int_{a}^{b} x^s (b - x)^e dx = sum_f gamma^{f}_{s,e} (b - a)^{e + 1 + s - f} a^f,
    gamma^{f}_{s,e} = s! e! / ((e + s - f + 1)! f!),

turns each matrix entry ``x^s`` of site ``k`` into entries ``Y_k^{e+1+s-f}``
of a new matrix whose column index is the pair (old column, ``e``) and whose
row index is (old row, ``f``): the nesting of indices of Eqs. (4.28)-(4.30).
The last site gives the new right vector (4.31)/(4.45), ``a_1 = 0`` the new
left vector (4.44).  At the top ``W_{1,1} = 1`` and ``J_1 = L t(1) R`` is the
normalization (4.46).

Moments and correlations multiply the matrix of a grain by ``x^s`` before its
layer is integrated: the thesis's defects of type I and II (4.57)-(4.61),
(4.80)-(4.85) are what this does to the recursion.

Everything is exact (:class:`fractions.Fraction`).  The bond dimension grows
like the number of index tuples (4.32), so this route is meant for small N
(the thesis stopped at N = 11 with the integer form).

Examples
--------
>>> normalization_nested(4)
Fraction(1, 360)
>>> moment_nested(5, {(5, 1): 1})
Fraction(1, 11)
"""

from __future__ import annotations

from collections import defaultdict
from fractions import Fraction
from math import factorial

from .staircase import check_layers

__all__ = ["integrate_layers", "normalization_nested", "moment_nested"]


def _gamma(s: int, e: int, f: int) -> Fraction:
    """``gamma^{f}_{s,e} = s! e! / ((e + s - f + 1)! f!)`` (Eq. 4.15 with ``m - k = f``)."""
    return Fraction(factorial(s) * factorial(e), factorial(e + s - f + 1) * factorial(f))


def _multiply_site(site: dict, power: int) -> dict:
    """Multiply every entry of a site matrix by ``x**power``."""
    return {key: {p + power: c for p, c in poly.items()} for key, poly in site.items()}


def _integrate_layer(left: dict, sites: list, right: dict):
    """Integrate one layer: ``(L, [T_1..T_m], R)`` -> ``(L', [T'_1..T'_{m-1}], R')``."""
    m = len(sites)
    # new right vector: X_m = u_{m-1}, so site m's powers become exponents of u
    new_right = defaultdict(Fraction)
    for (row, col), poly in sites[m - 1].items():
        if col in right:
            for power, c in poly.items():
                new_right[(row, power)] += c * right[col]
    # exponents e of u_k that reach site k from the right: the rows' powers of site k+1
    reach = [None] * m
    reach[m - 1] = defaultdict(set)
    for (row, power) in new_right:
        reach[m - 1][row].add(power)
    new_sites = [None] * (m - 1)
    for k in range(m - 2, -1, -1):  # site k+1 (1-based) integrated; sweep right to left
        exps = reach[k + 1]
        table = defaultdict(lambda: defaultdict(Fraction))
        for (row, col), poly in sites[k].items():
            for e in exps.get(col, ()):
                for s, c in poly.items():
                    for f in range(s + 1):  # a_k^f with a_k = u_{k-1}; Y_k^{e+1+s-f}
                        table[((row, f), (col, e))][e + 1 + s - f] += c * _gamma(s, e, f)
        new_sites[k] = {key: dict(poly) for key, poly in table.items()}
        reach[k] = defaultdict(set)
        for (row, f), _col in new_sites[k]:
            reach[k][row].add(f)
    new_left = {(row, 0): c for row, c in left.items()}  # a_1 = 0: only f = 0 survives
    return new_left, new_sites, dict(new_right)


def _prune(left: dict, sites: list, right: dict):
    """Drop matrix entries no path from ``L`` to ``R`` uses (exact: they never contribute)."""
    m = len(sites)
    alive = set(left)
    forward = []
    for site in sites:  # column bonds reachable from the left vector
        forward.append(alive)
        alive = {col for (row, col) in site if row in alive}
    alive = set(right)
    kept = [None] * m
    for k in range(m - 1, -1, -1):  # keep entries on a path left -> right
        kept[k] = {key: poly for key, poly in sites[k].items() if key[0] in forward[k] and key[1] in alive}
        alive = {row for (row, col) in kept[k]}
    left = {row: c for row, c in left.items() if row in alive}
    return left, kept, right


def integrate_layers(N: int, powers: dict | None = None) -> Fraction:
    """``int prod dW  prod_{(i,j)} W_{i,j}^{powers[(i,j)]}`` over the ensemble (unnormalized).

    Examples
    --------
    >>> integrate_layers(3)
    Fraction(1, 6)
    """
    N = check_layers(N)
    powers = {tuple(g): int(e) for g, e in (powers or {}).items() if e}
    for (i, j), e in powers.items():
        if not (1 <= i <= N and 1 <= j <= i) or e < 0:
            raise ValueError(f"powers[{(i, j)}]={e}: need a grain 1 <= j <= i <= N and a power >= 0")
    one = {0: Fraction(1)}
    left, right = {(): Fraction(1)}, {(): Fraction(1)}
    sites = [{((), ()): dict(one)} for _ in range(N)]  # the bottom layer's integrand is 1
    for m in range(N, 1, -1):
        sites = [_multiply_site(site, powers.get((m, k), 0)) for k, site in enumerate(sites, start=1)]
        left, sites, right = _prune(*_integrate_layer(left, sites, right))
    # layer 1: W_{1,1} = 1 (a power of W_{1,1} changes nothing)
    total = Fraction(0)
    for (row, col), poly in sites[0].items():
        if row in left and col in right:
            total += left[row] * sum(poly.values()) * right[col]
    return total


def normalization_nested(N: int) -> Fraction:
    """The normalization (4.46)/(4.51) by nested-matrix integration.

    Examples
    --------
    >>> normalization_nested(5)
    Fraction(1, 302400)
    """
    return integrate_layers(N)


def moment_nested(N: int, powers: dict) -> Fraction:
    """``< prod W_{i,j}^{e_{ij}} >`` by nested-matrix integration (Secs. 4.4-4.5).

    Examples
    --------
    >>> moment_nested(4, {(4, 2): 2})
    Fraction(9, 56)
    """
    return integrate_layers(N, powers) / integrate_layers(N)
