"""Reference route: the moments averaged over all linear extensions (networkx).

:func:`linear_extension_moments` enumerates the linear extensions of the
poset of partial sums with :func:`networkx.all_topological_sorts` and
averages the order-statistic (Dirichlet spacing) formulas over them: given
the ranks, ``<W^s>`` is the rising factorial of the rank gap over
``(d+1) ... (d+s)`` and ``<W W'> = (|I| |J| + |I & J|) / ((d+1)(d+2))``.

Independence: this module shares no code with the routes it checks (the
exact core and the thesis's map route have their own spacing code in
:mod:`forcenet.exact.triangle.spacings`).  It may import only
:mod:`forcenet.core.validation`, networkx, sympy and the standard library.
"""

from __future__ import annotations

from collections.abc import Iterable
from fractions import Fraction
from typing import Any

import networkx as nx
from sympy import rf

from forcenet.core.validation import check_int, check_layers

__all__ = ["partial_sum_poset", "linear_extension_moments"]


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


def linear_extension_moments(N: int, s_max: int = 2, pairs: Iterable[tuple[tuple[int, int], tuple[int, int]]] = ()
                             ) -> tuple[int, dict[int, dict[tuple[int, int], Fraction]], dict[Any, Fraction]]:
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
    s_max = check_int(s_max, "s_max", 1)
    d = N * (N - 1) // 2  # written out: this route uses nothing of the core
    grains = [(i, j) for i in range(1, N + 1) for j in range(1, i + 1)]
    pairs = list(dict.fromkeys(pairs))
    sums = {(s, g): 0 for s in range(1, s_max + 1) for g in grains}
    pair_sums = {p: 0 for p in pairs}
    number = 0
    def interval(rank: dict, g: tuple[int, int]) -> tuple[int, int]:
        """Ranks of ``S_{i,j-1}`` and ``S_{i,j}``, with ``S_{i,0} = 0`` and ``S_{i,i} = 1``."""
        i, j = g
        return (0 if j == 1 else rank[(i, j - 1)]), (d + 1 if j == i else rank[(i, j)])

    for extension in nx.all_topological_sorts(partial_sum_poset(N)) if d else [[]]:
        number += 1
        rank = {v: k + 1 for k, v in enumerate(extension)}
        for g in grains:
            lo, hi = interval(rank, g)
            for s in range(1, s_max + 1):
                sums[(s, g)] += int(rf(hi - lo, s))
        for g1, g2 in pairs:
            (a1, b1), (a2, b2) = interval(rank, g1), interval(rank, g2)
            pair_sums[(g1, g2)] += (b1 - a1) * (b2 - a2) + max(0, min(b1, b2) - max(a1, a2))
    moments = {s: {g: Fraction(sums[(s, g)], number * int(rf(d + 1, s))) for g in grains} for s in range(1, s_max + 1)}
    correlations = {p: Fraction(v, number * (d + 1) * (d + 2)) for p, v in pair_sums.items()}
    return number, moments, correlations
