"""Path sums over the lattice of order ideals of the shifted staircase.

An order ideal of the shifted staircase ``(n, ..., 1)`` is a strict partition
with parts ``<= n``, stored as a bit mask (bit ``p`` set <=> part ``p + 1``
present).  Adding a cell moves a part ``p`` to ``p + 1`` (bit ``p-1`` -> bit
``p``) or creates a part 1 (sets bit 0); both increase the mask, so numeric
order is a topological order, and the level of a mask is the sum of its parts.
A standard tableau is a maximal chain ``0 = I_0 < I_1 < ... < I_d = full``.

Two facts make everything below work (``notes/order_polytope.md``):

* ``f(mask)``, the number of chains from the empty ideal to ``mask``, is the
  number of standard shifted tableaux of that shape;
* the number of chains from ``mask`` to the full staircase is
  ``f(~mask)`` (the complement of an ideal, rotated by 180 degrees, is the
  ideal of the complementary set of parts).

So the number of tableaux whose chain passes through ``mask`` is
``w(mask) = f(mask) * f(~mask)``, and survival sums
``sum_mask w(mask) [cell not in mask]`` give expected entries (Eq. (4.63)
equivalents).  Everything is computed modulo word-size primes with numpy and
reconstructed exactly by CRT (:mod:`forcenet.exact.modular`), so results are Python
integers.

An engine's inside: ``N`` and ``n`` arrive checked by the public functions
of :mod:`.moments`, :mod:`.gaps` and :mod:`.distribution`, and are trusted
here (issue 25: validate at the boundary, trust inside).
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Sequence
from functools import cache, lru_cache
from typing import NamedTuple, TypeAlias

import numpy as np

from forcenet.core.errors import ArgumentError

from ..modular import crt, primes_for_bound
from .staircase import free_force_count, tableau_count

Progress: TypeAlias = Callable[..., object] | None  # progress(k): k more ticks done

__all__ = [
    "ideal_levels",
    "forward_counts_mod",
    "survival_counts",
    "MemoryEstimate",
    "estimate_survival_cost",
    "survival_primes",
    "parts_table",
    "marked_chain_sums",
    "predecessor_moves",
]


class MemoryEstimate(NamedTuple):
    """Peak bytes, seconds and progress ticks of a DP run, announced before it starts (a resource estimate)."""

    nbytes: int
    seconds: float
    ticks: int = 0

    def __str__(self) -> str:
        return f"~{self.nbytes / 2**30:.2f} GiB, ~{self.seconds:.0f} s"


@lru_cache(maxsize=4)
def ideal_levels(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Masks sorted by level (sum of parts) and the level boundaries.

    Returns ``(order, bounds)`` with ``order[bounds[k]:bounds[k+1]]`` the masks
    of level ``k``, ``k = 0..n(n+1)/2``.

    Examples
    --------
    >>> order, bounds = ideal_levels(3)
    >>> [order[bounds[k]:bounds[k + 1]].tolist() for k in range(7)]
    [[0], [1], [2], [3, 4], [5], [6], [7]]
    """
    level = np.zeros(1, dtype=np.int16)
    for p in range(n):
        level = np.concatenate([level, level + (p + 1)])
    order = np.argsort(level, kind="stable").astype(np.uint32 if n < 32 else np.int64)
    d = free_force_count(n + 1)
    bounds = np.concatenate([[0], np.cumsum(np.bincount(level, minlength=d + 1))])
    return order, bounds


def predecessor_moves(masks: np.ndarray, n: int) -> Iterator[tuple[np.ndarray, np.ndarray]]:
    """Yield ``(positions, predecessor_masks)`` for each kind of removal of one cell from the ideals ``masks``.

    An ideal is a set of distinct parts in ``1..n`` (bit ``a - 1`` of the mask);
    removing a cell takes a part 1 away or lowers a part ``q + 1`` to ``q``.

    Examples
    --------
    >>> [(s.tolist(), p.tolist()) for s, p in predecessor_moves(np.array([1, 2, 3]), 2)]
    [([0, 2], [0, 2]), ([1], [1])]
    """
    sel = np.flatnonzero(masks & 1)  # remove part 1
    if sel.size:
        yield sel, masks[sel] - 1
    for q in range(1, n):  # part q+1 -> q
        sel = np.flatnonzero(((masks >> q) & 1) & ~(masks >> (q - 1)) & 1)
        if sel.size:
            yield sel, masks[sel] - (1 << (q - 1))


def forward_counts_mod(n: int, primes: Sequence[int], progress: Progress = None) -> np.ndarray:
    """``f(mask) mod p`` for all ``2**n`` masks and each prime, shape ``(2**n, P)``.

    Residues are stored as ``uint32`` (primes are below ``2**31``).

    Examples
    --------
    >>> f = forward_counts_mod(3, (97,))
    >>> f[:, 0].tolist()  # shapes {}, (1), (2), (2,1), (3), (3,1), (3,2), (3,2,1)
    [1, 1, 1, 1, 1, 2, 2, 2]
    """
    order, bounds = ideal_levels(n)
    P = len(primes)
    pvec = np.asarray(primes, dtype=np.int64)
    f = np.zeros((1 << n, P), dtype=np.uint32)
    f[0] = 1
    d = free_force_count(n + 1)
    for k in range(1, d + 1):
        masks = order[bounds[k] : bounds[k + 1]].astype(np.int64)
        acc = np.zeros((masks.size, P), dtype=np.int64)
        for sel, pred in predecessor_moves(masks, n):
            acc[sel] += f[pred]
        f[masks] = acc % pvec
        if progress is not None:
            progress(masks.size)
    return f


_BYTES_PER_RESIDUE = 4  # the uint32 residue table
_BYTES_PER_MASK = 16  # level order (uint32) and its argsort transient
_SECONDS_PER_RESIDUE = 8.5e-8  # measured on the 2-core machine, N = 24


def _prime_chunks(n: int, primes: Sequence[int], memory_bytes: int) -> list[Sequence[int]]:
    masks = 1 << n
    size = max(1, int((memory_bytes - masks * _BYTES_PER_MASK) // (masks * _BYTES_PER_RESIDUE)))
    return [primes[k : k + size] for k in range(0, len(primes), size)]


def survival_primes(N: int) -> tuple[int, ...]:
    """Primes whose product bounds every survival sum for ``N`` layers."""
    return primes_for_bound((free_force_count(N) + 1) * tableau_count(N))


def estimate_survival_cost(N: int, memory_bytes: int = 12 * 2**30) -> MemoryEstimate:
    """Peak memory and time estimate of :func:`survival_counts` for ``N`` layers.

    Calibrated on a 2-core machine (``notes/benchmarks.md``).  Each prime
    needs ``12`` bytes per ideal (``2**(N-1)`` ideals); primes are processed in
    chunks that fit ``memory_bytes``, but at least one prime is needed.

    Examples
    --------
    >>> est = estimate_survival_cost(12)
    >>> est.nbytes < 2**20, est.seconds < 1
    (True, True)
    """
    n = N - 1
    masks = 1 << n
    primes = survival_primes(N)
    chunks = _prime_chunks(n, primes, memory_bytes)
    biggest = max(len(c) for c in chunks)
    nbytes = masks * (biggest * _BYTES_PER_RESIDUE + _BYTES_PER_MASK)
    seconds = masks * (len(primes) * _SECONDS_PER_RESIDUE + len(chunks) * 2e-7)
    return MemoryEstimate(int(nbytes), seconds, len(chunks) * masks)


_BLOCK_BITS = 18


@cache
def _popcount_groups(bits: int) -> tuple[np.ndarray, np.ndarray]:
    """Integers ``0..2**bits-1`` sorted by popcount, and the group starts."""
    pc = np.bitwise_count(np.arange(1 << bits, dtype=np.uint64)).astype(np.int64)
    order = np.argsort(pc, kind="stable")
    starts = np.concatenate([[0], np.cumsum(np.bincount(pc, minlength=bits + 1))[:-1]])
    return order, starts


def _survival_residues(n: int, primes: Sequence[int], progress: Progress = None) -> np.ndarray:
    """``A[r, m] = sum_mask w(mask) [lambda_r == m]`` modulo each prime.

    Memory: the ``uint32`` residue table of :func:`forward_counts_mod` is
    reused in place; everything else is done in blocks of ``2**18`` masks.
    """
    P = len(primes)
    pvec = np.asarray(primes, dtype=np.int64)
    G = forward_counts_mod(n, primes, progress)
    size = 1 << n
    # w(mask) = f(mask) f(~mask) is complement-symmetric; fill in place, blockwise
    half, block = size // 2, 1 << _BLOCK_BITS
    for lo in range(0, half, block):
        hi = min(lo + block, half)
        w = G[lo:hi].astype(np.int64) * G[size - hi : size - lo][::-1] % pvec
        G[lo:hi] = w
        G[size - hi : size - lo] = w[::-1]
    A = np.zeros((n + 2, n + 1, P), dtype=np.int64)
    for pos in range(n):
        k = n - pos - 1  # bits above pos; G is indexed by mask >> pos
        G2 = G[: 2 << k].reshape(-1, 2, P)
        bits = min(k, _BLOCK_BITS)
        order, starts = _popcount_groups(bits)
        for h0 in range(0, 1 << k, 1 << bits):
            h1 = h0 + (1 << bits)
            # masks with part pos+1, grouped by the number of larger parts
            H = G2[h0:h1, 1, :].astype(np.int64)
            sums = np.add.reduceat(H[order], starts, axis=0) % pvec
            shift = int(h0).bit_count()
            A[1 + shift : 2 + shift + bits, pos + 1] += sums
            # sum over the bit pos, in place: G[h] <- G[2h] + G[2h+1]
            G[h0:h1] = (G2[h0:h1, 0, :].astype(np.int64) + H) % pvec
        A[:, pos + 1] %= pvec
    A[0, 0] = G[0]  # grand total, sum of all w
    return A


def survival_counts(N: int, progress: Progress = None, memory_bytes: int = 12 * 2**30) -> tuple[list[list[int]], int]:
    """Exact ``C[r][m] = sum_mask w(mask) [lambda_r >= m]`` for the triangle.

    ``lambda_r`` is the ``r``-th largest part of the ideal (0 if absent),
    ``r = 0..n`` (``lambda_0`` = infinity), ``m = 1..n+1``.  With ``T(x)`` the
    entry of cell ``x = (r, c)`` in a uniform random tableau,
    ``E[T(x)] = (count * (d + 1) - C[r][c - r + 1]) / count``.

    Parameters
    ----------
    N : int
        Number of layers.
    progress : callable, optional
        Called with the number of masks finished, ``len(primes_chunks) * 2**n``
        in all.
    memory_bytes : int
        Budget for the residue tables; primes are processed in chunks.

    Returns
    -------
    (C, total) : (list of lists of int, int)
        ``C[r][m]`` (index ``m = 0`` unused) and ``total = count(N)``.

    Examples
    --------
    >>> C, total = survival_counts(3)
    >>> total, C[0][1], C[1][1], C[1][2], C[2][1]
    (1, 4, 3, 2, 1)
    """
    n = N - 1
    d = free_force_count(n + 1)
    one_prime = (1 << n) * (_BYTES_PER_RESIDUE + _BYTES_PER_MASK)
    if one_prime > max(memory_bytes, 2**32):
        raise ArgumentError(
            f"N={N} is out of range for the exact table: one prime's residues over the 2^{n} ideals "
            f"need {one_prime / 2**30:.0f} GiB, more than memory_bytes={memory_bytes}; N must be at most about 30"
        )
    total = tableau_count(N)
    primes = survival_primes(N)
    A = np.concatenate(
        [_survival_residues(n, chunk, progress) for chunk in _prime_chunks(n, primes, memory_bytes)],
        axis=2,
    )
    # self-check: the weights of all ideals add up to (d + 1) * count
    if crt(A[0, 0], primes) != (d + 1) * total:
        raise ArithmeticError("sum of chain weights is not (d+1) * count(N)")
    C = [[0] * (n + 2) for _ in range(n + 1)]
    C[0][1:] = [(d + 1) * total] * (n + 1)
    for r in range(1, n + 1):
        for m in range(n, 0, -1):
            C[r][m] = C[r][m + 1] + crt(A[r, m], primes)
    return C, total


@lru_cache(maxsize=4)
def parts_table(n: int) -> np.ndarray:
    """``lam[mask, r]``: the ``r``-th largest part of ``mask`` for ``r = 0..n+1``.

    Column 0 holds ``n + 1`` (standing for infinity), absent parts are 0.

    Examples
    --------
    >>> parts_table(3)[0b101].tolist()
    [4, 3, 1, 0, 0]
    """
    masks = np.arange(1 << n, dtype=np.int64)
    lam = np.zeros((1 << n, n + 2), dtype=np.int16)
    lam[:, 0] = n + 1
    filled = np.zeros(1 << n, dtype=np.int64)
    for part in range(n, 0, -1):
        rows = np.flatnonzero((masks >> (part - 1)) & 1)
        lam[rows, filled[rows] + 1] = part
        filled[rows] += 1
    return lam


def marked_chain_sums(n: int, primes: Sequence[int], initial: Sequence[int] | np.ndarray,
                      update: Callable[[np.ndarray, np.ndarray], np.ndarray], progress: Progress = None) -> np.ndarray:
    """Forward DP over chains with a per-ideal linear update of a state vector.

    ``F[mask]`` (shape ``(K, P)`` residues) is first the sum of ``F`` over the
    predecessors of ``mask``; then ``update(masks, F_in)`` returns the new
    state of a whole level at once.  ``F[empty]`` starts as the integer vector
    ``initial`` (length ``K``) before its own update.  Returns ``F[full]``.

    This counts chains of ideals together with marks placed on them, e.g. a
    multiset of ``s`` ideals eligible for a grain (moment ``s``) or one ideal
    for each of two grains (a correlation).
    """
    order, bounds = ideal_levels(n)
    P = len(primes)
    pvec = np.asarray(primes, dtype=np.int64)
    n_states = len(initial)
    F = np.zeros((1 << n, n_states, P), dtype=np.int64)
    start = np.zeros((1, n_states, P), dtype=np.int64)
    start[0, :, :] = np.asarray(initial, dtype=np.int64)[:, None]
    F[0] = update(np.zeros(1, dtype=np.int64), start)[0] % pvec
    d = free_force_count(n + 1)
    for k in range(1, d + 1):
        masks = order[bounds[k] : bounds[k + 1]].astype(np.int64)
        acc = np.zeros((masks.size, n_states, P), dtype=np.int64)
        for sel, pred in predecessor_moves(masks, n):
            acc[sel] += F[pred]
        acc %= pvec
        F[masks] = update(masks, acc) % pvec
        if progress is not None:
            progress(masks.size)
    return F[-1]


