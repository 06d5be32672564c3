"""Exact laws of rank gaps in a uniform random tableau: the spacings of the triangle.

A uniform point of the ensemble is a uniform random standard tableau ``T`` of
the shifted staircase together with ``d = N(N-1)/2`` sorted uniforms placed by
rank, ``S_x = U_(T(x))`` (``notes/order_polytope.md``).  Every force that is
the difference of two comparable partial sums is a *spacing*
``U_(T(a)) - U_(T(b))`` (``U_(0) = 0``, ``U_(d+1) = 1``), Beta(``g``,
``d + 1 - g``) given ``T`` with ``g = T(a) - T(b)`` the rank gap
(``notes/force_distribution.md``):

* the vertical load ``W_{i,j} = S_{i,j} - S_{i,j-1}`` (4.5): diagonal
  neighbours ``(j-1, c-1) -> (j, c)``, ``c = N - i + j``; a layer is a diagonal;
* the lower contacts ``(sqrt3/2) F5^{(i,j)} = q W = S_{i+1,j} - S_{i,j-1}``
  (vertical neighbours, a column) and ``(sqrt3/2) F6^{(i,j)} = (1 - q) W =
  S_{i,j} - S_{i+1,j}`` (horizontal neighbours, a row), by (3.8), (4.6) and
  the interlacing (4.8)-(4.9); the upper contacts follow by (3.4),
  ``F1^{(i,j)} = F6^{(i-1,j-1)}``, ``F2^{(i,j)} = F5^{(i-1,j)}``.

This module computes the exact law of the gap of every interval of a *chain*
of cells (a layer, a row or a column) in one forward pass over the
``2^(N-1)`` order ideals (:func:`chain_gap_counts`): the chain's cells cut
every maximal chain of ideals into runs, and the state of an ideal is the
level at which the current run began.  Arithmetic is modulo word-size primes
(numpy), reconstructed by the Chinese remainder theorem
(:mod:`forcenet.exact.modular`); results are Python integers.  Densities,
distribution functions and pooled ``P(f)`` are in :mod:`.distribution`, joint
laws of two gaps (for ``q``) in :mod:`.joint_gaps`.

Examples
--------
>>> gaps = grain_gap_counts(4, (4, 2))
>>> gaps.counts[:5], gaps.total
((0, 0, 1, 1, 0), 2)

References
----------
S. Ostojic, PhD thesis (2006), Eqs. (3.2)-(3.4), (3.8), (4.5)-(4.9).
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Sequence
from fractions import Fraction

import numpy as np

from forcenet.core.errors import ArgumentError
from forcenet.core.plan import Plan
from forcenet.core.validation import check_grain, check_int, check_layers

from ..modular import crt, primes_for_bound
from .gap_counts import GapCounts
from .ideal_dp import predecessor_moves
from .runs import check_chain, mulmod_sum, run_layout, transport
from .staircase import count, dimension, free_force_count, tableau_count

__all__ = [
    "gap_laws_cost",
    "contact_location",
    "GapCounts",
    "layer_chain",
    "row_chain",
    "column_chain",
    "chain_gap_counts",
    "estimate_chain_cost",
    "layer_gap_counts",
    "grain_gap_counts",
    "gap_distribution",
    "contact_gap_counts",
    "CONTACT_KINDS",
    "contact_spacing",
    "contact_gap_law",
    "gap_laws_plan",
    "chain_pass",
]


# ---------------------------------------------------------------- chains of cells


def layer_chain(N: int, i: int) -> list[tuple[int, int]]:
    """Cells of the free partial sums ``S_{i,1} < ... < S_{i,i-1}`` of layer ``i``.

    The chain's ``i`` intervals (``0 < S_{i,1}``, ..., ``S_{i,i-1} < 1``) are the
    gaps of ``W_{i,1}, ..., W_{i,i}``: the diagonal ``c - r = N - i``.

    Examples
    --------
    >>> layer_chain(5, 3)
    [(1, 3), (2, 4)]
    """
    N = check_layers(N)
    return _layer_cells(N, check_int(i, "i", 1, N))


def _layer_cells(N: int, i: int) -> list[tuple[int, int]]:
    return [(r, r + N - i) for r in range(1, i)]


def row_chain(N: int, r: int) -> list[tuple[int, int]]:
    """Row ``r`` of the staircase, ``(r, r) < (r, r+1) < ... < (r, N-1)``.

    Interval ``k >= 1`` (from ``(r, r+k-1)`` to ``(r, r+k)``, or to 1 for the
    last) is the lower-right contact ``(sqrt 3 / 2) F6^{(N-k, r)}``; interval 0
    is the partial sum ``S_{N,r}`` of the floor.

    Examples
    --------
    >>> row_chain(4, 2)
    [(2, 2), (2, 3)]
    """
    N = check_layers(N)
    return _row_cells(N, check_int(r, "r", 1, N - 1))


def _row_cells(N: int, r: int) -> list[tuple[int, int]]:
    return [(r, c) for c in range(r, N)]


def column_chain(N: int, c: int) -> list[tuple[int, int]]:
    """Column ``c`` of the staircase, ``(1, c) < (2, c) < ... < (c, c)``.

    Interval ``k <= c - 1`` (from ``(k, c)``, or 0 for ``k = 0``, to
    ``(k+1, c)``) is the lower-left contact ``(sqrt 3 / 2) F5^{(N-c+k, k+1)}``;
    the last interval is ``1 - S_{N,c}``.

    Examples
    --------
    >>> column_chain(4, 2)
    [(1, 2), (2, 2)]
    """
    N = check_layers(N)
    return _column_cells(N, check_int(c, "c", 1, N - 1))


def _column_cells(N: int, c: int) -> list[tuple[int, int]]:
    return [(r, c) for r in range(1, c + 1)]


# ---------------------------------------------------------------- the run-length DP


def _chain_residues(n: int, cells: Sequence[tuple[int, int]], primes: Sequence[int],
                    progress: Callable[[int], object] | None = None) -> np.ndarray:
    """``out[k, g, p]`` = (number of tableaux whose ``k``-th interval has gap ``g``) mod ``p``.

    Forward pass over the levels of the ideal lattice.  The state of an ideal
    ``M`` containing ``k`` chain cells is the vector over ``e`` (the level at
    which the ``k``-th chain cell was added, ``e >= |down(x_k)|``) of the number
    of chains from the empty ideal to ``M``.  A move that keeps ``k`` carries
    ``e`` along (a sparse 0/1 matrix per block); a move that adds ``x_{k+1}``
    at level ``L`` ends run ``k`` with gap ``L - e``, weighted by the number of
    chains from the new ideal to the top, ``f(complement)`` (complement lemma),
    and starts run ``k + 1`` with ``e = L`` and weight ``f(M)``.
    """
    d, pvec, h, f, full, lo, levels, pos = run_layout(n, cells, primes)
    K = len(cells)
    P = len(primes)
    out = np.zeros((K + 1, d + 2, P), dtype=np.int64)
    prev = {0: np.ones((1, 1, P), dtype=np.int64)}  # level 0: empty ideal, run 0 entered at 0
    for L in range(1, d + 1):
        cur = {}
        for k, block in levels[L].items():
            elo = 0 if k == 0 else lo[k]
            width = 1 if k == 0 else L - elo + 1
            acc = np.zeros((block.size, width, P), dtype=np.int64)
            moves = list(predecessor_moves(block, n))
            sel = np.concatenate([s for s, _ in moves])
            pred = np.concatenate([p for _, p in moves])
            add = h[pred] != k
            rows, cols = sel[~add], pos[pred[~add]]
            if rows.size:
                src = prev[k]
                acc[:, : src.shape[1]] = transport(rows, cols, block.size, src)
            add_rows, add_pred = sel[add], pred[add]
            if add_rows.size:  # the move adds x_k: run k-1 ends, run k starts at level L
                acc[add_rows, L - elo] += f[add_pred]
                X = prev[k - 1][pos[add_pred]]  # (a, width_{k-1}, P), e = elo_{k-1} + index
                u = f[full ^ block[add_rows]].astype(np.int64)
                Y = mulmod_sum(X, u, pvec)
                e = (0 if k == 1 else lo[k - 1]) + np.arange(Y.shape[0])
                out[k - 1, L - e] += Y
            cur[k] = acc % pvec
        prev = cur
        if progress is not None:
            progress(1)
    last = prev[K][0]  # the full ideal, run K entered at level e
    e = (0 if K == 0 else lo[K]) + np.arange(last.shape[0])
    out[K, d + 1 - e] += last
    return out % pvec


_BYTES_PER_STATE = 8 * 2  # int64 state and one transient copy (an upper bound in practice)


def _level_sizes(n: int) -> list[int]:
    """Ideals per level: the coefficients of ``prod_{k=1}^{n} (1 + x^k)`` (strict partitions, parts <= n)."""
    sizes = [1]
    for k in range(1, n + 1):
        sizes = [a + (sizes[m - k] if 0 <= m - k < len(sizes) else 0) for m, a in enumerate(sizes + [0] * k)]
    return sizes


def estimate_chain_cost(N: int, chain: Iterable[tuple[int, int]], n_primes: int | None = None) -> int:
    """Peak bytes of one pass of :func:`chain_gap_counts` (all primes at once), an upper bound.

    Measured: N = 20 about 0.25 GiB (estimate 0.32), N = 22 about 0.76 GiB
    (estimate 1.75) for the bottom layer.

    Examples
    --------
    >>> estimate_chain_cost(12, layer_chain(12, 12)) < 2**24
    True
    """
    return _chain_cost(check_layers(N), n_primes)


def _chain_cost(N: int, n_primes: int | None) -> int:
    """:func:`estimate_chain_cost` for ``N`` already checked (the cost does not depend on the chain)."""
    n, d = N - 1, free_force_count(N)
    if n_primes is None:
        n_primes = len(primes_for_bound(count(N)))
    width = max(_level_sizes(n))
    return width * (d + 1) * n_primes * _BYTES_PER_STATE + (1 << n) * (4 * n_primes + 16)


def chain_gap_counts(N: int, chain: Iterable[tuple[int, int]], *, memory_bytes: int = 4 * 2**30,
                     progress: Callable[[int], object] | None = None) -> list[GapCounts]:
    """Exact law of every interval of a chain of cells in a uniform tableau.

    For a chain ``x_1 < ... < x_K`` of the staircase poset and the conventions
    ``T(x_0) = 0``, ``T(x_{K+1}) = d + 1``, returns for ``k = 0..K`` the law of
    the gap ``T(x_{k+1}) - T(x_k)``.  One forward pass over the order ideals
    (rolling over levels, states = the level where the current run started)
    gives all ``K + 1`` laws.

    Parameters
    ----------
    N : int
        Number of layers.
    chain : sequence of (r, c)
        Cells ``1 <= r <= c <= N - 1``, strictly increasing in the poset.
    memory_bytes : int
        Budget; primes are processed in chunks that fit (:func:`estimate_chain_cost`).
    progress : callable, optional
        Called once per level and prime chunk.

    Returns
    -------
    list of GapCounts

    Examples
    --------
    >>> # S_{4,1} < S_{4,2}: the gaps of W_{4,1}, W_{4,2} and W_{4,3} + W_{4,4}
    >>> [g.counts for g in chain_gap_counts(4, [(1, 1), (2, 2)])]
    [(0, 2, 0, 0, 0, 0, 0, 0), (0, 0, 1, 1, 0, 0, 0, 0), (0, 0, 0, 1, 1, 0, 0, 0)]
    """
    N = check_layers(N)
    cells = check_chain(N, chain)
    return _chain_gap_counts(N, cells, memory_bytes, progress)


def _chain_gap_counts(N: int, cells: tuple[tuple[int, int], ...], memory_bytes: int = 4 * 2**30,
                      progress: Callable[[int], object] | None = None) -> list[GapCounts]:
    n, d = N - 1, dimension(N)
    total = count(N)
    if n == 0 or not cells:
        only = [0] * (d + 2)
        only[d + 1] = total
        return [GapCounts(tuple(only), total, d)]
    primes = primes_for_bound(total)
    per_prime = _chain_cost(N, 1)
    size = max(1, int(memory_bytes // per_prime))
    chunks = [primes[k : k + size] for k in range(0, len(primes), size)]
    out = np.concatenate([_chain_residues(n, cells, chunk, progress) for chunk in chunks], axis=2)
    # self-checks modulo every prime: each interval's law has total mass count(N), and the
    # K + 1 gaps of a tableau add up to d + 1
    pvec = np.asarray(primes, dtype=np.int64)
    tot = np.asarray([total % p for p in primes], dtype=np.int64)
    if not (out.sum(axis=1) % pvec == tot).all():
        raise ArithmeticError("a gap law does not sum to count(N)")
    g = np.arange(d + 2, dtype=np.int64)[None, :, None]
    if not ((out * g % pvec).sum(axis=(0, 1)) % pvec == (d + 1) * tot % pvec).all():
        raise ArithmeticError("the gaps of a chain do not add up to d + 1")
    result = []
    for k in range(len(cells) + 1):
        counts = tuple(crt(out[k, gg], primes) for gg in range(d + 2))
        if sum(counts) != total:
            raise ArithmeticError("CRT reconstruction of a gap law failed")
        result.append(GapCounts(counts, total, d))
    return result


_CACHE: dict[tuple[str, int, int], tuple[GapCounts, ...]] = {}  # (kind, N, index) -> laws of one chain pass; the most recent 64 are kept
_CACHE_SIZE = 64
_CHAIN_CELLS = {"layer": _layer_cells, "row": _row_cells, "column": _column_cells}


def chain_pass(kind: str, N: int, index: int, progress: Callable[[int], object] | None = None
                ) -> tuple[GapCounts, ...]:
    """The laws of every interval of one layer / row / column chain, cached; ``N`` and ``index`` already checked.

    The shared pass behind :func:`layer_gap_counts`, :func:`grain_gap_counts`,
    :func:`contact_gap_law` and the densities of :mod:`.distribution`, which
    check their arguments first.  ``progress`` ticks only when the pass runs.

    Examples
    --------
    >>> [g.counts for g in chain_pass("row", 3, 1)]
    [(0, 1, 0, 0, 0), (0, 1, 0, 0, 0), (0, 0, 1, 0, 0)]
    """
    key = (kind, N, index)
    if key not in _CACHE:
        chain = _CHAIN_CELLS[kind](N, index)
        laws = tuple(_chain_gap_counts(N, tuple(chain), progress=progress))
        if len(_CACHE) >= _CACHE_SIZE:
            _CACHE.pop(next(iter(_CACHE)))
        _CACHE[key] = laws
    return _CACHE[key]


def layer_gap_counts(N: int, i: int, progress: Callable[[int], object] | None = None) -> tuple[GapCounts, ...]:
    """Exact gap laws of ``W_{i,1}, ..., W_{i,i}`` (one pass over the ideals, cached).

    ``progress`` is called once per level of the ideal lattice (``d`` times) if
    the pass runs.

    Examples
    --------
    >>> [g.counts for g in layer_gap_counts(3, 3)]
    [(0, 1, 0, 0, 0), (0, 0, 1, 0, 0), (0, 1, 0, 0, 0)]
    """
    N = check_layers(N)
    i = check_int(i, "i", 1, N)
    return chain_pass("layer", N, i, progress)


def grain_gap_counts(N: int, grain: tuple[int, int], progress: Callable[[int], object] | None = None) -> GapCounts:
    """Exact law of the rank gap of ``W_{i,j}``.

    Examples
    --------
    >>> grain_gap_counts(5, (5, 3)).counts[:8], count(5)
    ((0, 0, 2, 4, 4, 2, 0, 0), 12)
    """
    N = check_layers(N)
    i, j = check_grain(N, grain)
    return chain_pass("layer", N, i, progress)[j - 1]


def gap_distribution(N: int, grain: tuple[int, int]) -> list[Fraction]:
    """``[P(gap = g) for g in 0..d+1]`` of ``W_{i,j}``, exact.

    Examples
    --------
    >>> [str(p) for p in gap_distribution(4, (4, 2))]
    ['0', '0', '1/2', '1/2', '0', '0', '0', '0']
    """
    return grain_gap_counts(N, grain).probabilities()


CONTACT_KINDS = ("F1", "F2", "F5", "F6")


def contact_spacing(N: int, grain: tuple[int, int], kind: str) -> tuple[str, int, int]:
    """Where the contact ``kind`` of ``grain`` lives: ``("row" | "column", index, interval)``.

    ``(sqrt3/2) F6^{(i,j)} = S_{i,j} - S_{i+1,j}`` is interval ``N - i`` of row
    ``j``; ``(sqrt3/2) F5^{(i,j)} = S_{i+1,j} - S_{i,j-1}`` is interval ``j - 1``
    of column ``N - i + j - 1`` (Eqs. (3.8), (4.6)); by (3.4)
    ``F1^{(i,j)} = F6^{(i-1,j-1)}`` and ``F2^{(i,j)} = F5^{(i-1,j)}``.  The
    contacts that are not random are refused: the overload on the top grain,
    the missing neighbours at the edges, and the bottom layer's lower contacts
    (the floor, not part of the network).

    Examples
    --------
    >>> contact_spacing(5, (3, 2), "F6"), contact_spacing(5, (3, 2), "F5"), contact_spacing(5, (4, 3), "F1")
    (('row', 2, 2), ('column', 3, 1), ('row', 2, 2))
    """
    N = check_layers(N)
    i, j = check_grain(N, grain)
    return contact_location(N, i, j, kind, grain)


def contact_location(N: int, i: int, j: int, kind: str, grain: object) -> tuple[str, int, int]:
    """:func:`contact_spacing` for a checked request's ``N`` and grain ``(i, j)`` (``grain`` as given, for the
    messages): the contacts that are not random are refused here.

    Examples
    --------
    >>> contact_location(5, 4, 3, "F1", (4, 3)) == contact_spacing(5, (4, 3), "F1")
    True
    """
    if kind not in CONTACT_KINDS:
        raise ArgumentError(f"kind={kind!r} is not a contact force that is a spacing: kind must be one of {', '.join(CONTACT_KINDS)} "
                         "(F3, F4 are lateral forces, p_h plus signed sums of spacings)")
    if kind in ("F1", "F2"):
        if i == 1:
            raise ArgumentError(f"grain={grain!r}: F1 = F2 = 1/sqrt3 on the top grain is the overload, not random")
        if (kind == "F1" and j == 1) or (kind == "F2" and j == i):
            raise ArgumentError(f"grain={grain!r}: {kind} is identically 0 there (no grain above on that side)")
        i, j, kind = (i - 1, j - 1, "F6") if kind == "F1" else (i - 1, j, "F5")
    elif i == N:
        raise ArgumentError(f"grain={grain!r}: the bottom layer's {kind} presses on the floor, outside the network; "
                         f"i must be an integer in 1..{N - 1} for {kind}")
    if kind == "F6":
        return "row", j, N - i
    return "column", N - i + j - 1, j - 1


def contact_gap_law(N: int, grain: tuple[int, int], kind: str, progress: Callable[[int], object] | None = None
                    ) -> GapCounts:
    """Exact law of the rank gap of the contact force ``kind`` of ``grain`` (one pass).

    The force is ``(2/sqrt3)`` times a spacing with this gap
    (:func:`contact_spacing`).

    Examples
    --------
    >>> contact_gap_law(4, (3, 2), "F6").counts[:5]
    (0, 1, 1, 0, 0)
    """
    N = check_layers(N)
    i, j = check_grain(N, grain)
    where, index, interval = contact_location(N, i, j, kind, grain)
    return chain_pass(where, N, index, progress)[interval]


def contact_gap_counts(N: int, mirror: bool = True, progress: Callable[[int], object] | None = None
                       ) -> dict[tuple[int, int, str], GapCounts]:
    """Gap laws of the lower contact forces of every grain of layers ``1..N-1``.

    Keys ``(i, j, 'F5')`` and ``(i, j, 'F6')``; the contact force is
    ``(2/sqrt3)`` times the spacing, ``F5 = (2/sqrt3)(S_{i+1,j} - S_{i,j-1})``
    (a column of the tableau) and ``F6 = (2/sqrt3)(S_{i,j} - S_{i+1,j})`` (a
    row).  By (3.4) the upper contacts are ``F1^{(i,j)} = F6^{(i-1,j-1)}``,
    ``F2^{(i,j)} = F5^{(i-1,j)}``.  With ``mirror=True`` (default) the
    ``N - 1`` row passes suffice: ``F5^{(i,j)}`` has the law of
    ``F6^{(i,i+1-j)}``, by the self-duality ``(r, c) -> (N - c, N - r)`` of the
    staircase (the left-right mirror of the triangle); ``mirror=False`` runs
    the ``N - 1`` column passes too (the tests check that both agree).

    Examples
    --------
    >>> c = contact_gap_counts(3)
    >>> c[(2, 1, 'F5')].counts, c[(2, 1, 'F6')].counts
    ((0, 1, 0, 0, 0), (0, 1, 0, 0, 0))
    """
    N = check_layers(N)
    out: dict[tuple[int, int, str], GapCounts] = {}
    for r in range(1, N):
        laws = chain_pass("row", N, r, progress)
        for k in range(1, len(laws)):
            out[(N - k, r, "F6")] = laws[k]
    if mirror:
        for i in range(1, N):
            for j in range(1, i + 1):
                out[(i, j, "F5")] = out[(i, i + 1 - j, "F6")]
        return out
    for c in range(1, N):
        laws = chain_pass("column", N, c, progress)
        for k in range(c):
            out[(N - c + k, k + 1, "F5")] = laws[k]
    return out


# ------------------------------------------------------------------- cost of a pass

# One pass costs about (ideals x entry levels x primes) states, 2^(N-1) d / 3 per
# prime, plus a fixed cost per level; measured on the 2-core machine for the floor
# pass (the costliest) at N = 12..20: 0.07 s, 0.31 s, 1.2 s, 5.8 s for N = 12, 16, 18, 20
# (load ~2.5; notes/benchmarks.md).
_SECONDS_PER_STATE = 1.4e-8
_SECONDS_PER_LEVEL = 1.0e-3


_AVERAGE_PASS = 0.6  # a layer / row pass averaged over the triangle, relative to the floor pass (N = 20: 63 s / 19 passes)


def _pass_seconds(N: int, average: bool = False) -> float:
    n, d = N - 1, free_force_count(N)
    primes = len(primes_for_bound(count(N)))
    states = _SECONDS_PER_STATE * (1 << n) * d / 3 * primes
    return states * (_AVERAGE_PASS if average else 1.0) + _SECONDS_PER_LEVEL * d


_MAX_LAYERS = 30  # 2^29 ideals: far beyond memory; the estimate is not even attempted


def gap_laws_plan(N: int, passes: int = 1, memory_bytes: int | None = None, what: str | None = None) -> Plan:
    """The cost of ``passes`` chain passes (:func:`chain_gap_counts`) at ``N`` layers.

    One pass gives every interval of one chain: a layer (all its grains'
    ``W``), a row or a column (contact forces).  All grains need ``N - 1``
    passes, all contacts ``N - 1`` more.  A single pass is priced as the
    floor pass (the costliest), several as the average over the triangle.

    Examples
    --------
    >>> gap_laws_plan(12, 11).seconds < 5
    True
    >>> gap_laws_plan(31).refusal
    'N=31 is out of range for exact gap laws: N must be an integer in 2..30'
    """
    return gap_laws_cost(check_layers(N), check_int(passes, "passes", 0), memory_bytes, what)


def gap_laws_cost(N: int, passes: int = 1, memory_bytes: int | None = None, what: str | None = None) -> Plan:
    """:func:`gap_laws_plan` of a checked request's ``N`` (and ``passes``): what the law and row engines plan with,
    nothing checked again.

    Examples
    --------
    >>> gap_laws_cost(12, 11) == gap_laws_plan(12, 11)
    True
    """
    what = what or f"exact gap laws N={N}, {passes} pass{'es' if passes != 1 else ''} over the ideals"
    if N > _MAX_LAYERS:
        return Plan(what, 0, refusal=f"N={N} is out of range for exact gap laws: N must be an integer in 2..{_MAX_LAYERS}")
    primes = len(primes_for_bound(tableau_count(N)))
    per_prime = _chain_cost(N, 1)
    chunk = max(1, min(primes, (4 * 2**30) // per_prime))  # primes per chunk, as chain_gap_counts does
    nbytes = _chain_cost(N, chunk) + 100 * 2**20
    plan = Plan(what, passes * _pass_seconds(N, average=passes > 1), nbytes, passes * free_force_count(N), "level")
    return plan.within_memory(memory_bytes)
