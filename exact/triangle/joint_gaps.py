"""Joint law of two consecutive rank gaps: the law of ``q_{i,j}`` (Eqs. 3.8, 4.6).

``q_{i,j} = F5 / (F5 + F6)`` is the ratio of two adjacent spacings,
``S_{i+1,j} - S_{i,j-1}`` and ``S_{i,j} - S_{i+1,j}``.  Given the tableau,
``(F5, F6, rest)`` is Dirichlet(``g5``, ``g6``, ``d + 1 - g5 - g6``) up to the
factor ``2/sqrt3``, so by aggregation and neutrality ``q`` is
Beta(``g5``, ``g6``), independent of ``W_{i,j}`` (``notes/force_distribution.md``).
Its density (:func:`forcenet.exact.triangle.distribution.q_density`) needs the
joint law of the two gaps, which one forward pass over the order ideals gives
when the state in the second run is the pair (first gap, level where the
second run began) (:func:`joint_gap_counts`).  ``O(d)`` times the cost of a
single-gap pass (:mod:`.gaps`); meant for ``N <= 16``.

Examples
--------
>>> counts, total = q_gap_counts(3, (2, 1))
>>> [(a, b, c) for a, row in enumerate(counts) for b, c in enumerate(row) if c], total
([(1, 1, 1)], 1)
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence

import numpy as np

from forcenet.core.errors import ArgumentError
from forcenet.core.validation import check_grain, check_int, check_layers

from ..modular import crt, primes_for_bound
from .ideal_dp import predecessor_moves
from .runs import check_chain, mulmod_sum, run_layout, transport
from .staircase import count, dimension

__all__ = ["joint_gap_counts", "q_gap_counts"]


def _joint_residues(n: int, cells: tuple[tuple[int, int], ...], k: int, primes: Sequence[int]) -> np.ndarray:
    """``out[g1, g2, p]``: tableaux with gaps ``(g1, g2)`` in intervals ``k``, ``k + 1``, mod ``p``.

    Like :func:`forcenet.exact.triangle.gaps.chain_gap_counts`' pass (the same set-up,
    :func:`~forcenet.exact.triangle.runs.run_layout`), but the state in run ``k + 1`` is the pair
    (gap of run ``k``, level where run ``k + 1`` started).
    """
    d, pvec, h, f, full, lo, levels, pos = run_layout(n, cells, primes)
    K = len(cells)
    P = len(primes)
    out = np.zeros((d + 2, d + 2, P), dtype=np.int64)
    G = d + 2  # range of the first gap
    prev: dict[int, np.ndarray] = {}
    if k == 0:
        prev[0] = np.ones((1, 1, P), dtype=np.int64)  # run 0 entered at level 0
    for L in range(1, d + 1):
        cur = {}
        for hk, block in levels[L].items():
            if hk not in (k, k + 1):
                continue
            moves = list(predecessor_moves(block, n))
            sel = np.concatenate([s for s, _ in moves])
            pred = np.concatenate([p for _, p in moves])
            same = h[pred] == hk
            if hk == k:
                elo = lo[k]
                acc = np.zeros((block.size, L - elo + 1, P), dtype=np.int64)
                if same.any():
                    src = prev[k]
                    acc[:, : src.shape[1]] = transport(sel[same], pos[pred[same]], block.size, src)
                if (~same).any():  # run k starts here: all chains to the predecessor
                    np.add.at(acc[:, L - elo], sel[~same], f[pred[~same]].astype(np.int64))
            else:
                elo = lo[k + 1]
                acc = np.zeros((block.size, G, L - elo + 1, P), dtype=np.int64)
                if same.any():
                    src = prev[k + 1]
                    acc[:, :, : src.shape[2]] = transport(sel[same], pos[pred[same]], block.size, src)
                if (~same).any():  # run k ends (gap L - e1), run k + 1 starts at L
                    s2, p2 = sel[~same], pred[~same]
                    X = prev[k][pos[p2]]  # (a, w1, P), e1 = lo[k] + index
                    g1 = L - (lo[k] + np.arange(X.shape[1]))
                    for t, g in enumerate(g1):
                        np.add.at(acc[:, g, L - elo], s2, X[:, t])
            cur[hk] = acc % pvec
            # run k + 1 ends when x_{k+2} is added: emit with the number of completions
        if k + 2 <= K and k + 2 in levels[L] and (k + 1) in prev:
            block = levels[L][k + 2]
            moves = list(predecessor_moves(block, n))
            sel = np.concatenate([s for s, _ in moves])
            pred = np.concatenate([p for _, p in moves])
            add = h[pred] == k + 1
            if add.any():
                s2, p2 = sel[add], pred[add]
                X = prev[k + 1][pos[p2]]  # (a, G, w2, P)
                u = f[full ^ block[s2]].astype(np.int64)
                Y = mulmod_sum(X.reshape(X.shape[0], -1, P), u, pvec).reshape(G, -1, P)
                e2 = lo[k + 1] + np.arange(Y.shape[1])
                out[:, L - e2] += Y
        prev = cur
    if k + 1 == K:  # the last run ends at the top, rank d + 1
        last = prev[K][0]  # (G, w2, P)
        e2 = lo[K] + np.arange(last.shape[1])
        out[:, d + 1 - e2] += last
    return out % pvec


def joint_gap_counts(N: int, chain: Iterable[tuple[int, int]], k: int) -> tuple[list[list[int]], int]:
    """Exact joint law of the gaps of intervals ``k`` and ``k + 1`` of a chain.

    Returns ``(counts, total)`` with ``counts[g1][g2]`` the number of tableaux.
    Memory and time grow like ``d`` times those of :func:`chain_gap_counts`;
    meant for ``N <= 14``.

    Examples
    --------
    >>> counts, total = joint_gap_counts(4, [(1, 2), (2, 3)], 0)
    >>> total, [(g1, g2, c) for g1, row in enumerate(counts) for g2, c in enumerate(row) if c]
    (2, [(2, 3, 2)])
    """
    N = check_layers(N)
    cells = check_chain(N, chain)
    return _joint_gap_counts(N, cells, check_int(k, "k", 0, len(cells) - 1))


def _joint_gap_counts(N: int, cells: tuple[tuple[int, int], ...], k: int) -> tuple[list[list[int]], int]:
    """:func:`joint_gap_counts` for arguments already checked."""
    total = count(N)
    primes = primes_for_bound(total)
    out = _joint_residues(N - 1, cells, k, primes)
    pvec = np.asarray(primes, dtype=np.int64)
    if not (out.sum(axis=(0, 1)) % pvec == np.asarray([total % p for p in primes])).all():
        raise ArithmeticError("the joint gap law does not sum to count(N)")
    d = dimension(N)
    counts = [[crt(out[a, b], primes) for b in range(d + 2)] for a in range(d + 2)]
    if sum(map(sum, counts)) != total:
        raise ArithmeticError("CRT reconstruction of the joint gap law failed")
    return counts, total


def q_gap_counts(N: int, grain: tuple[int, int]) -> tuple[list[list[int]], int]:
    """Joint law of the gaps ``(g5, g6)`` of ``F5`` and ``F6`` of grain ``(i, j)``, ``i < N``.

    ``q_{i,j} = F5 / (F5 + F6)`` is, given the tableau, Beta(``g5``, ``g6``) and
    independent of ``W_{i,j}`` (Dirichlet aggregation), so the law of ``q``
    follows from this table (:func:`q_density`).

    Examples
    --------
    >>> counts, total = q_gap_counts(3, (2, 1))
    >>> [(a, b, c) for a, row in enumerate(counts) for b, c in enumerate(row) if c], total
    ([(1, 1, 1)], 1)
    """
    N = check_layers(N)
    i, j = check_grain(N, grain)
    if i == N:
        raise ArgumentError(f"grain={grain!r}: the bottom layer has no q (no grains below); i must be an integer in 1..{N - 1}")
    c = N - i + j
    chain: list[tuple[int, int]] = []
    k = 0
    if j >= 2:
        chain.append((j - 1, c - 1))  # S_{i,j-1}
        k = 1
    chain.append((j, c - 1))  # S_{i+1,j}
    if j <= i - 1:
        chain.append((j, c))  # S_{i,j}
    return _joint_gap_counts(N, tuple(chain), k)


