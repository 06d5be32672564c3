"""A plain dictionary-based dynamic program over order ideals (Python ints).

The straightforward algorithm, kept as the benchmark baseline and as a second
algorithm for the tests: forward and backward chain counts in dictionaries
keyed by strict partitions, then the rank of every cell averaged over the
edges of the ideal lattice,
``E[T(x)] = sum_{I -> I+x} (|I| + 1) f(I) b(I + x) / count``.
It uses neither the complement symmetry nor modular arithmetic of
:mod:`forcenet.exact.triangle.ideal_dp`.

Independence: this module shares no code with the routes it checks.  It may
import only :mod:`forcenet.core.validation` and the standard library.
"""

from __future__ import annotations

from collections.abc import Iterator
from fractions import Fraction

from forcenet.core.validation import check_layers

__all__ = ["addable_cells", "chain_counts", "mean_W_dictionary"]


def addable_cells(shape: tuple[int, ...], n: int) -> Iterator[tuple[tuple[int, ...], tuple[int, int]]]:
    """Cells that can be added to a shifted shape inside the staircase.

    Yields ``(new_shape, (r, c))``.

    Examples
    --------
    >>> list(addable_cells((2,), 2))
    [((2, 1), (2, 2))]
    """
    for r, part in enumerate(shape):
        if part < n and (r == 0 or shape[r - 1] > part + 1):
            yield shape[:r] + (part + 1,) + shape[r + 1 :], (r + 1, r + 1 + part)
    if not shape or shape[-1] > 1:
        r = len(shape) + 1
        yield shape + (1,), (r, r)


def chain_counts(n: int) -> tuple[dict[tuple[int, ...], int], dict[tuple[int, ...], int]]:
    """Forward and backward chain counts of all shifted shapes in the staircase.

    Examples
    --------
    >>> f, b = chain_counts(2)
    >>> f[(2, 1)], b[()]
    (1, 1)
    """
    levels: list[list[tuple[int, ...]]] = [[()]]
    forward: dict[tuple[int, ...], int] = {(): 1}
    d = n * (n + 1) // 2  # written out: this route uses nothing of the core
    for _ in range(d):
        nxt: dict[tuple[int, ...], int] = {}
        for shape in levels[-1]:
            for new, _cell in addable_cells(shape, n):
                nxt[new] = nxt.get(new, 0) + forward[shape]
        forward.update(nxt)
        levels.append(list(nxt))
    backward = {tuple(range(n, 0, -1)): 1}
    for level in reversed(levels[:-1]):
        for shape in level:
            backward[shape] = sum(backward[new] for new, _ in addable_cells(shape, n))
    return forward, backward


def mean_W_dictionary(N: int) -> list[list[Fraction]]:
    """``<W_ij>`` table from expected tableau entries (edge sums, Python ints).

    Examples
    --------
    >>> [str(x) for x in mean_W_dictionary(5)[-1]]
    ['1/11', '1/4', '7/22', '1/4', '1/11']
    """
    N = check_layers(N)
    n, d = N - 1, N * (N - 1) // 2  # written out: this route uses nothing of the core
    forward, backward = chain_counts(n)
    total = forward[tuple(range(n, 0, -1))] if n else 1
    rank_sum: dict[tuple[int, int], int] = {}
    for shape, f in forward.items():
        size = sum(shape)
        for new, cell in addable_cells(shape, n):
            rank_sum[cell] = rank_sum.get(cell, 0) + (size + 1) * f * backward[new]

    def mean_rank(i: int, j: int) -> Fraction:  # rank of S_ij; S_i0 = 0 and S_ii = 1 are ranks 0, d+1
        if j == 0:
            return Fraction(0)
        if j == i:
            return Fraction(d + 1)
        return Fraction(rank_sum[(j, N - i + j)], total)

    return [
        [(mean_rank(i, j) - mean_rank(i, j - 1)) / (d + 1) for j in range(1, i + 1)]
        for i in range(1, N + 1)
    ]
