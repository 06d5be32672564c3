"""Dirichlet spacings: moments of the forces given the ranks of the partial sums.

Given the linear extension (a standard tableau) of the partial sums, a
uniform point of the order polytope is ``d`` sorted uniforms placed by rank;
the ``d + 1`` spacings are Dirichlet(1, ..., 1) (``notes/order_polytope.md``).
``W_{i,j}`` is the sum of the spacings between the ranks of ``S_{i,j-1}``
and ``S_{i,j}`` (rank gap ``g``), so

* ``<W^s | T> = g (g+1) ... (g+s-1) / ((d+1) ... (d+s))``;
* ``<W W' | T> = (|I| |J| + |I & J|) / ((d+1)(d+2))`` for rank intervals ``I, J``.

Used by the exact core (:mod:`.moments`) and by the thesis's map route
(:mod:`forcenet.exact.thesis.map_counting`); the reference routes
(:mod:`forcenet.exact.reference`) have their own code for independence.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from fractions import Fraction
from math import perm, prod

from .staircase import dimension

__all__ = ["rising", "rank_gap_moments"]


def rising(x: int, s: int) -> int:
    """Rising factorial ``x (x+1) ... (x+s-1)`` (1 for ``s = 0``).

    Examples
    --------
    >>> rising(3, 2), rising(5, 0), rising(0, 3), rising(-2, 1)
    (12, 1, 0, -2)
    """
    if x >= 1:
        return perm(x + s - 1, s)
    return prod(range(x, x + s))


Grain = tuple[int, int]


def rank_gap_moments(N: int, rankings: Iterable[Mapping[Grain, int]], s_max: int = 2,
                     pairs: Iterable[tuple[Grain, Grain]] = ()
                     ) -> tuple[int, dict[int, dict[Grain, Fraction]], dict[tuple[Grain, Grain], Fraction]]:
    """Moments of the W's averaged over linear extensions given by their ranks.

    ``rankings`` yields dicts ``(i, j) -> rank`` of the free partial sums
    ``S_{i,j}``, ``1 <= j <= i - 1`` (ranks ``1..d``), one per linear
    extension, each counted once.

    Returns
    -------
    (count, moments, correlations)
        the number of extensions, ``moments[s][(i, j)] = <W_{i,j}^s>`` for
        ``s = 1..s_max`` and ``correlations[(g, g')] = <W_g W_g'>``.

    Examples
    --------
    >>> ranks = [{(2, 1): 1, (3, 1): 2, (3, 2): 3}, {(2, 1): 1, (3, 1): 3, (3, 2): 2}]
    >>> c, mom, _ = rank_gap_moments(3, ranks[:1], s_max=1)
    >>> c, mom[1][(3, 1)]
    (1, Fraction(1, 2))
    """
    d = dimension(N)
    grains = [(i, j) for i in range(1, N + 1) for j in range(1, i + 1)]
    acc = {s: {g: 0 for g in grains} for s in range(1, s_max + 1)}
    unique_pairs = list(dict.fromkeys(pairs))  # a repeated pair is counted once
    acc_pairs = {p: 0 for p in unique_pairs}
    number = 0
    def gap_interval(rank: Mapping[Grain, int], g: Grain) -> tuple[int, int]:
        i, j = g
        lo = 0 if j == 1 else rank[(i, j - 1)]
        hi = d + 1 if j == i else rank[(i, j)]
        return lo, hi

    for rank in rankings:
        number += 1
        for g in grains:
            lo, hi = gap_interval(rank, g)
            for s in acc:
                acc[s][g] += rising(hi - lo, s)
        for g1, g2 in unique_pairs:
            (a1, b1), (a2, b2) = gap_interval(rank, g1), gap_interval(rank, g2)
            overlap = max(0, min(b1, b2) - max(a1, a2))
            acc_pairs[(g1, g2)] += (b1 - a1) * (b2 - a2) + overlap
    moments = {s: {g: Fraction(v, number * rising(d + 1, s)) for g, v in acc[s].items()} for s in acc}
    correlations = {p: Fraction(v, number * (d + 1) * (d + 2)) for p, v in acc_pairs.items()}
    return number, moments, correlations
