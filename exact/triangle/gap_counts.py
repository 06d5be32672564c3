"""A rank-gap law as exact integer counts, shared by the order-ideal DP and the Pfaffian routes.

``GapCounts`` holds ``P(gap = g) = counts[g] / total``; the DP
(:mod:`.gaps`), the free-fermion lattice laws and the de Bruijn routes all
return it.  Given the gap ``g``, a spacing is Beta(``g``, ``d + 1 - g``)
(``notes/force_distribution.md``), so its moments are exact rationals
(:func:`moment_from_gaps`); laws with the same ``d`` and ``total`` pool by
adding counts (:func:`pool_gaps`).

Examples
--------
>>> law = GapCounts((0, 1, 0, 0), 1, 2)  # the smaller of two uniforms: gap 1 of d = 2
>>> law.mean(), moment_from_gaps(law, 1)
(Fraction(1, 1), Fraction(1, 3))
"""

from __future__ import annotations

from collections.abc import Iterable
from fractions import Fraction
from typing import NamedTuple

from forcenet.core.errors import ArgumentError
from forcenet.core.validation import check_int

from .spacings import rising

__all__ = ["GapCounts", "pool_gaps", "moment_from_gaps"]


class GapCounts(NamedTuple):
    """Integer law of a rank gap: ``P(gap = g) = counts[g] / total``.

    ``counts`` has length ``d + 2`` (``g = 0 .. d + 1``); ``total`` is the number
    of tableaux ``count(N)`` (or a multiple of it for pooled laws); ``d`` is the
    dimension ``N (N - 1) / 2``.
    """

    counts: tuple
    total: int
    d: int

    def probabilities(self) -> list[Fraction]:
        """``[P(gap = g) for g in 0..d+1]`` as Fractions.

        Examples
        --------
        >>> [str(p) for p in GapCounts((0, 0, 1, 0, 0), 1, 3).probabilities()]  # W_(3,2) for N = 3
        ['0', '0', '1', '0', '0']
        """
        return [Fraction(c, self.total) for c in self.counts]

    def mean(self) -> Fraction:
        """``E[gap]``.

        Examples
        --------
        >>> GapCounts((0, 0, 1, 1, 0, 0, 0, 0), 2, 6).mean()  # W_(4,2) for N = 4
        Fraction(5, 2)
        """
        return Fraction(sum(g * c for g, c in enumerate(self.counts)), self.total)


def moment_from_gaps(gaps: GapCounts, s: int) -> Fraction:
    """``E[X^s] = E[g (g+1) ... (g+s-1)] / ((d+1) ... (d+s))``, exact.

    Examples
    --------
    >>> moment_from_gaps(GapCounts((0, 1, 0, 0), 1, 2), 2)  # U_(1) of two uniforms: E[U^2] = 1/6
    Fraction(1, 6)
    """
    s = check_int(s, "s", 0)
    num = sum(c * rising(g, s) for g, c in enumerate(gaps.counts) if c)
    return Fraction(num, gaps.total * rising(gaps.d + 1, s))


def pool_gaps(laws: Iterable[GapCounts]) -> GapCounts:
    """Mixture of gap laws with equal weights (same ``d`` and ``total``).

    Examples
    --------
    >>> pool_gaps([GapCounts((0, 1, 0, 0), 1, 2), GapCounts((0, 0, 1, 0), 1, 2)])
    GapCounts(counts=(0, 1, 1, 0), total=2, d=2)
    """
    laws = list(laws)
    if not laws:
        raise ArgumentError("pool_gaps: need at least one gap law")
    d, total = laws[0].d, laws[0].total
    if any(g.d != d or g.total != total for g in laws):
        raise ArgumentError("pool_gaps: all laws must have the same d and total")
    counts = tuple(sum(col) for col in zip(*(g.counts for g in laws)))
    return GapCounts(counts, total * len(laws), d)
