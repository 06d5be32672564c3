"""The set-up of a forward pass over the order ideals that follows the runs of a chain of cells.

The exact gap laws (:mod:`.gaps`) and the joint laws of two gaps
(:mod:`.joint_gaps`) walk the ``2^(N-1)`` order ideals of the shifted
staircase level by level; a chain of cells cuts every maximal chain of ideals
into runs (``notes/force_distribution.md``).  Both passes share what is here:
the chain checked (:func:`check_chain`), the ideals grouped by level and by
the number of chain cells they contain (:func:`run_layout`), the carrying of
states along the moves (:func:`transport`) and the overflow-free modular
products (:func:`mulmod_sum`).  Arithmetic modulo word-size primes (numpy).
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from typing import NamedTuple

import numpy as np

from forcenet.core.errors import ArgumentError, ArgumentTypeError
from forcenet.core.validation import check_int

from .ideal_dp import forward_counts_mod, ideal_levels
from .staircase import dimension

__all__ = ["check_chain", "down_size", "RunLayout", "run_layout", "transport", "mulmod_sum"]


def check_chain(N: int, chain: Iterable[tuple[int, int]]) -> tuple[tuple[int, int], ...]:
    """The cells of ``chain``, checked: cells of the staircase of ``N`` layers, strictly increasing in the poset.

    ``N`` must be checked already (:func:`forcenet.core.validation.check_layers`).

    Raises
    ------
    ArgumentError
        If a cell is outside the staircase or the cells do not increase.
    ArgumentTypeError
        If ``chain`` is not a sequence of integer pairs.

    Examples
    --------
    >>> check_chain(4, [[1, 1], (2, 2)])
    ((1, 1), (2, 2))
    """
    n = N - 1
    try:
        cells = tuple((check_int(r, "chain row"), check_int(c, "chain column")) for r, c in chain)
    except (TypeError, ValueError) as exc:
        if isinstance(exc, ValueError) and "out of range" in str(exc):
            raise
        raise ArgumentTypeError(f"chain={chain!r}: need a sequence of cells (r, c) with integer r, c") from None
    for r, c in cells:
        if not 1 <= r <= c <= n:
            raise ArgumentError(f"cell {(r, c)} is not in the staircase of N={N}: need 1 <= r <= c <= {n}")
    for (r1, c1), (r2, c2) in zip(cells, cells[1:]):
        if not (r1 <= r2 and c1 <= c2 and (r1, c1) != (r2, c2)):
            raise ArgumentError(f"chain={list(cells)}: cells must increase strictly in the poset (r and c non-decreasing)")
    return cells


def down_size(r: int, c: int) -> int:
    """Number of cells ``<= (r, c)``: rows ``1..r``, columns ``r'..c``.

    Examples
    --------
    >>> down_size(2, 3)
    5
    """
    return sum(c - rr + 1 for rr in range(1, r + 1))


class RunLayout(NamedTuple):
    """The set-up of a forward pass over the order ideals that follows the runs of a chain of cells.

    Shared by the gap laws (:func:`chain_gap_counts`) and the joint laws
    (:func:`forcenet.exact.triangle.joint_gaps.joint_gap_counts`); built by :func:`run_layout`.
    """

    d: int  # the dimension N (N - 1) / 2
    pvec: np.ndarray  # the primes, int64
    h: np.ndarray  # h[mask]: how many chain cells the ideal mask contains
    f: np.ndarray  # f[mask, p]: chains of ideals from the empty one to mask, mod each prime
    full: int  # the mask of the full ideal
    lo: list[int]  # lo[k]: the earliest level at which run k can be entered (lo[0] = 0)
    levels: list[dict[int, np.ndarray]]  # levels[L][k]: the masks at level L containing k chain cells
    pos: np.ndarray  # pos[mask]: index of mask inside its group of levels


def run_layout(n: int, cells: Sequence[tuple[int, int]], primes: Sequence[int]) -> RunLayout:
    """The :class:`RunLayout` of the chain ``cells`` over the ideals of the staircase with ``n = N - 1`` (trusted).

    Examples
    --------
    >>> layout = run_layout(2, [(1, 1)], [101])
    >>> layout.d, layout.lo, layout.h.tolist()
    (3, [0, 1], [0, 1, 1, 1])
    """
    pvec = np.asarray(primes, dtype=np.int64)
    masks_all = np.arange(1 << n, dtype=np.int64)
    h = np.zeros(1 << n, dtype=np.int16)
    for r, c in cells:  # (r, c) in the ideal <=> at least r parts >= c - r + 1
        h += np.bitwise_count(masks_all >> (c - r)) >= r
    del masks_all
    f = forward_counts_mod(n, primes)
    lo = [0] + [down_size(r, c) for r, c in cells]  # earliest level of entering run k
    d = dimension(n + 1)
    levels, pos = _level_layout(n, h, d)
    return RunLayout(d, pvec, h, f, (1 << n) - 1, lo, levels, pos)


def transport(rows: np.ndarray, cols: np.ndarray, size: int, src: np.ndarray) -> np.ndarray:
    """``out[rows[t]] += src[cols[t]]`` for every move ``t``, as one sparse product; ``out`` has ``size`` rows.

    Examples
    --------
    >>> transport(np.array([0, 0, 1]), np.array([0, 1, 1]), 2, np.array([[1], [10]])).tolist()
    [[11], [10]]
    """

    from scipy.sparse import csr_matrix  # a second of start-up for every command otherwise (scipy.sparse is heavy)

    A = csr_matrix((np.ones(rows.size, dtype=np.int64), (rows, cols)), shape=(size, src.shape[0]))
    return (A @ src.reshape(src.shape[0], -1)).reshape((size,) + src.shape[1:])


def _level_layout(n: int, h: np.ndarray, d: int) -> tuple[list[dict[int, np.ndarray]], np.ndarray]:
    """Masks of each level grouped by ``h``; ``pos[mask]`` = index inside its group (``d`` levels above the empty one)."""
    order, bounds = ideal_levels(n)
    pos = np.empty(1 << n, dtype=np.int64)
    levels = []
    for L in range(d + 1):
        masks = order[bounds[L] : bounds[L + 1]].astype(np.int64)
        hm = h[masks]
        srt = np.argsort(hm, kind="stable")
        masks, hm = masks[srt], hm[srt]
        ks, starts = np.unique(hm, return_index=True)
        ends = list(starts[1:]) + [masks.size]
        groups: dict[int, np.ndarray] = {}
        for k, a, b in zip(ks.tolist(), starts.tolist(), ends):
            block = masks[a:b]
            pos[block] = np.arange(b - a)
            groups[k] = block
        levels.append(groups)
    return levels, pos


def mulmod_sum(X: np.ndarray, u: np.ndarray, pvec: np.ndarray) -> np.ndarray:
    """``sum_b X[b, e, p] * u[b, p] mod p`` without overflow (``X, u < 2**31``).

    ``u`` is split into 16-bit limbs so that every partial sum stays below
    ``2**63`` (at most ``2**15`` rows per block).

    Examples
    --------
    >>> X = np.array([[[3]], [[4]]]); u = np.array([[5], [6]])
    >>> mulmod_sum(X, u, np.array([7])).tolist()  # (15 + 24) mod 7
    [[4]]
    """
    out = np.zeros(X.shape[1:], dtype=np.int64)
    lo, hi = u & 0xFFFF, u >> 16
    for a in range(0, X.shape[0], 1 << 15):
        Xa = X[a : a + (1 << 15)]
        out += np.einsum("bep,bp->ep", Xa, lo[a : a + (1 << 15)]) % pvec
        out += (np.einsum("bep,bp->ep", Xa, hi[a : a + (1 << 15)]) % pvec << 16) % pvec
    return out % pvec
