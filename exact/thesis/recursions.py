"""The thesis's integer recursions: Lambda (4.2)/(4.50)-(4.51), the boundary (4.67), Gamma (4.73)-(4.77).

* :func:`lambda_table`, :func:`count_lambda`, :func:`normalization_lambda`:
  the integers ``Lambda^(p)`` and the normalization (4.51);
* :func:`boundary_mean_W`: ``<W>`` on the left boundary, (4.67)-(4.68);
* :func:`gamma_sums`, :func:`gamma_bulk_integer`, :func:`mean_W_gamma`: the
  bulk ``<W>`` from the Gamma recursion (4.73)-(4.77).

Every recursion is a row-by-row transfer of dense numpy boxes indexed by one
row of a map (Sec. 4.6): the nested sum of (4.50) is a dominance prefix sum
(:func:`_transfer`), and the last row is never built (:func:`_last_row_chain`).
Multi-modular (int64 residues, CRT) beyond a few layers: N = 12 reaches.
Derivations: ``notes/chapter4.md``.
"""

from __future__ import annotations

from collections.abc import Callable
from fractions import Fraction
from functools import lru_cache
from math import factorial
from typing import Any

import numpy as np

from forcenet.core.validation import check_int, check_layers

from ..modular import crt, primes_for_bound
from ..protocol import Progress
from ..triangle.staircase import count, dimension
from .coefficients import defect_line, upper_bound

Reduce = Callable[..., np.ndarray]  # an array to canonical values (% prime, or the identity)

__all__ = ["lambda_table", "count_lambda", "count_lambda_chain", "normalization_lambda", "boundary_mean_W", "gamma_sums", "gamma_bulk_integer", "mean_W_gamma", "table_from_bulk"]


def _lambda_boxes(p: int, dtype: Any, reduce: Reduce) -> np.ndarray:
    """``Lambda^(p)`` on the box of its first ``p - 1`` indices (the last is 1).

    ``reduce`` maps an array to canonical values (``% prime`` or identity).
    The nested sum of (4.50) is a dominance prefix sum: one row step of the
    map recursion (:func:`_transfer`) with no raised bounds per level.
    """
    L = np.ones((), dtype=dtype)  # Lambda^(1)_{(1)} = 1: an empty box
    for q in range(1, p):  # Lambda^(q) -> Lambda^(q+1)
        L = _transfer(L, q, frozenset(), reduce)
    return L

@lru_cache(maxsize=16)
def lambda_table(p: int) -> dict[tuple[int, ...], int]:
    """Non-zero ``Lambda^(p)_{j_1..j_p}`` of Eqs. (4.2)/(4.50), ``p >= 1``, exact.

    ``Lambda^(1)_{(1)} = 1`` starts the recursion (it reproduces
    ``Lambda^(2)_{j1 j2} = delta(j2, 1)``).  Entries vanish unless ``j_p = 1``;
    the nested sum over ``k`` is evaluated as a dominance prefix sum
    (:func:`_lambda_boxes`), with Python integers (object arrays).  Meant for
    ``p <= 8``; :func:`count_lambda` uses modular arithmetic beyond.

    Parameters
    ----------
    p : int
        Level of the recursion, ``p >= 1`` (``p = N - 2``).

    Returns
    -------
    dict of tuple of int to int
        ``(j_1, ..., j_p)`` -> ``Lambda^(p)_{j_1..j_p}``, nonzero entries only.

    Raises
    ------
    ArgumentError
        If ``p`` is not an integer ``>= 1``.

    Examples
    --------
    >>> lambda_table(2)
    {(1, 1): 1, (2, 1): 1}
    >>> sum(lambda_table(4).values())
    286
    """
    p = check_int(p, "p", 1)
    L = _lambda_boxes(p, object, lambda a: a)
    if L.ndim == 0:
        return {(1,): int(L)}
    return {tuple(int(x) + 1 for x in idx) + (1,): int(L[idx]) for idx in zip(*np.nonzero(L))}

@lru_cache(maxsize=16)
def _lambda_weighted_sums(N: int) -> list[int]:
    """Exact ``sum_j Lambda^(N-2)_j`` and ``sum_j j_a Lambda^(N-2)_j`` for every axis ``a``.

    Multi-modular with CRT, through the chain of :func:`_lambda_sum_mod`
    (``N >= 5``), which never builds the last Lambda table.
    """
    if N < 5:
        return _lambda_weighted_sums_box(N)
    d = dimension(N)
    primes = primes_for_bound(d * d * count(N))
    p = N - 2
    rows = []
    for prime in primes:  # one Lambda^(p-1) box per prime, one chain per weight
        reduce = _mod_reducer(prime)
        box = _lambda_boxes(p - 1, np.int64, reduce)
        rows.append([_last_row_chain(box, p, frozenset(), reduce, k) % prime for k in [None] + list(range(1, p))])
        del box
    return [crt(col, primes) for col in zip(*rows)]

def _lambda_weighted_sums_box(N: int) -> list[int]:
    """The same sums from the whole last table (dense box): the reference for the chain."""
    p = N - 2
    d = dimension(N)
    primes = primes_for_bound(d * d * count(N))
    per_prime = []
    for prime in primes:
        L = _lambda_boxes(p, np.int64, lambda a, prime=prime: a % prime)
        total = int(L.sum() % prime)
        moments = []
        for axis in range(L.ndim):
            marginal = L.sum(axis=tuple(ax for ax in range(L.ndim) if ax != axis)) % prime
            moments.append(int((marginal * np.arange(1, marginal.size + 1)).sum() % prime))
        per_prime.append([total] + moments)
    columns = list(zip(*per_prime))
    return [crt(col, primes) for col in columns]

def count_lambda(N: int) -> int:
    """``sum_j Lambda^(N-2)_j``, the integer of Eq. (4.1)/(4.51).

    Computed by the chain of :func:`_lambda_sum_mod` (N = 12 in about 3 min).

    Parameters
    ----------
    N : int
        Number of layers, ``N >= 2``.

    Returns
    -------
    int
        Equal to :func:`forcenet.exact.count`.

    Raises
    ------
    ArgumentError
        If ``N`` is not an integer ``>= 2``.

    Examples
    --------
    >>> [count_lambda(N) for N in range(3, 8)]
    [1, 2, 12, 286, 33592]
    """
    N = check_layers(N)
    if N <= 3:
        return 1
    if N == 4:
        return _lambda_weighted_sums_box(N)[0]
    return count_lambda_chain(N)

def normalization_lambda(N: int) -> Fraction:
    """Eq. (4.51): ``normalization = sum Lambda^(N-2) / (N(N-1)/2)!``.

    Parameters
    ----------
    N : int
        Number of layers, ``N >= 2``.

    Returns
    -------
    Fraction
        Equal to :func:`forcenet.exact.normalization`.

    Raises
    ------
    ArgumentError
        If ``N`` is not an integer ``>= 2``.

    Examples
    --------
    >>> normalization_lambda(5)
    Fraction(1, 302400)
    """
    N = check_layers(N)
    return Fraction(count_lambda(N), factorial(dimension(N)))

def boundary_mean_W(N: int, q: int) -> Fraction:
    """``<W_{N-q,1}>`` on the left boundary, Eqs. (4.67)-(4.68).

    ``<W_{N-q,1}> = sum_j (q(q+1)/2 + 2 - j_{q-1}) Lambda^(N-2)_j / ((d+1) sum_j Lambda^(N-2)_j)``
    for ``1 <= q <= N-2`` with ``j_0 = 1``; ``<W_{N,1}> = <W_{N-1,1}> / 2``;
    ``W_{1,1} = 1``.

    Parameters
    ----------
    N : int
        Number of layers, ``N >= 2``.
    q : int
        Layers above the bottom, ``0 <= q <= N - 1`` (the grain is ``(N - q, 1)``).

    Returns
    -------
    Fraction

    Raises
    ------
    ArgumentError
        If ``N`` or ``q`` is out of range.

    Examples
    --------
    >>> [boundary_mean_W(5, q) for q in range(5)]
    [Fraction(1, 11), Fraction(2, 11), Fraction(41, 132), Fraction(1, 2), Fraction(1, 1)]
    """
    N = check_layers(N)
    q = check_int(q, "q", 0, N - 1)
    if q == N - 1:
        return Fraction(1)
    if q == 0:
        return boundary_mean_W(N, 1) / 2
    d = dimension(N)
    sums = _lambda_weighted_sums(N)  # [sum Lambda, sum j_1 Lambda, sum j_2 Lambda, ...]
    total = sums[0]
    j_sum = total if q == 1 else sums[q - 1]  # j_0 = 1
    return Fraction((q * (q + 1) // 2 + 2) * total - j_sum, (d + 1) * total)

def table_from_bulk(N: int, bulk: Callable[[int, int], int]) -> list[list[Fraction]]:
    """Assemble a ``<W>`` table: (4.67) on the left boundary, ``bulk(q, r) / ((d+1) Z)``
    for ``r >= 2`` (Eq. 4.91 or 4.77), the bottom layer from the layer above.

    Every ``N >= 2``: at ``N = 2`` only the apex and the bottom layer remain.

    Examples
    --------
    >>> [str(x) for x in table_from_bulk(2, lambda q, r: 0)[-1]]
    ['1/2', '1/2']
    """
    d = dimension(N)
    Z = count_lambda(N)
    table = {(1, 1): Fraction(1)}
    for q in range(1, N - 1):  # layer i = N - q
        i = N - q
        table[(i, 1)] = boundary_mean_W(N, q)  # (4.67)
        for r in range(2, i + 1):
            table[(i, r)] = Fraction(bulk(q, r), (d + 1) * Z)
    for r in range(1, N + 1):  # bottom layer: last-layer q's are independent uniforms
        table[(N, r)] = (table.get((N - 1, r - 1), Fraction(0)) + table.get((N - 1, r), Fraction(0))) / 2
    return [[table[(i, j)] for j in range(1, i + 1)] for i in range(1, N + 1)]

def _row_maxima(l: int, relaxed: frozenset) -> tuple[int, ...]:
    """Largest values of ``h(l, 1..l-1)`` under (4.86) with bounds raised at ``relaxed``."""
    out: list[int] = []
    for k in range(1, l):
        out.append(upper_bound(k, out[-1] if out else None, k in relaxed))
    return tuple(out)

def _row_mask(l: int, relaxed: frozenset) -> np.ndarray:
    """Valid ``(h(l,1), ..., h(l,l-1))`` (0-based box) under the raised bounds."""
    shape = _row_maxima(l, relaxed)
    mask = np.ones(shape, dtype=bool)
    m = len(shape)
    for k in range(2, m + 1):  # the values h(l,k-1), h(l,k) are the 0-based indices + 1
        a = np.arange(1, shape[k - 2] + 1).reshape([-1 if ax == k - 2 else 1 for ax in range(m)])
        b = np.arange(1, shape[k - 1] + 1).reshape([-1 if ax == k - 1 else 1 for ax in range(m)])
        mask &= b <= upper_bound(k, a, k in relaxed)
    return mask

def _transfer(box: np.ndarray, l: int, relaxed_next: frozenset, reduce: Reduce) -> np.ndarray:
    """Row ``l`` -> row ``l + 1`` of the map recursion (4.87): a dominance prefix sum (4.89)."""
    D = _dominance(box, reduce)
    target = _row_maxima(l + 1, relaxed_next)
    if D.ndim:
        pad = [(0, max(t - s, 0)) for s, t in zip(D.shape, target[1:])]
        D = np.pad(D, pad, mode="edge")[tuple(slice(0, t) for t in target[1:])]
    out = np.empty(target, dtype=D.dtype)  # in place from here: the boxes reach 1e9 cells at N = 12
    np.copyto(out, np.broadcast_to(D, target))
    del D
    np.multiply(out, _row_mask(l + 1, relaxed_next), out=out)
    return out

def _dominance(box: np.ndarray, reduce: Reduce) -> np.ndarray:
    """Cumulative sums along every axis (a new array; ``box`` is left alone)."""
    D = np.array(box, copy=True)
    for axis in range(D.ndim):
        np.cumsum(D, axis=axis, dtype=D.dtype, out=D)
        D = _reduce_inplace(D, reduce)
    return D

def _times_index(box: np.ndarray, axis: int, reduce: Reduce) -> np.ndarray:
    """Multiply ``box`` by the 1-based value of its index along ``axis`` (a map entry ``h``)."""
    values = np.arange(1, box.shape[axis] + 1, dtype=np.int64)
    return reduce(box * values.reshape([-1 if ax == axis % box.ndim else 1 for ax in range(box.ndim)]))

def _reduce_inplace(a: np.ndarray, reduce: Reduce) -> np.ndarray:
    modulus = getattr(reduce, "modulus", None)
    if modulus is not None and a.dtype != object:
        np.remainder(a, modulus, out=a)
        return a
    return reduce(a)

def gamma_sums(
    N: int, q: int, r: int, dtype: Any = object, reduce: Callable[[np.ndarray], np.ndarray] = lambda a: a
) -> tuple[Any, Any, Any]:
    """Integer sums over the modified maps ``h(q, r)`` of Eq. (4.90), via row recursions.

    Returns ``(Z', S1, S0)``: the number of modified maps and the sums of
    ``h(N-r, q-1)`` and ``h(N-r-1, q-1)`` over them.  The recursion over rows is
    the Lambda recursion (4.50) with the bounds raised by one on the line of
    (4.73)/(4.75) -- the thesis's Gamma integers are its intermediate tables.

    Parameters
    ----------
    N : int
        Number of layers, ``N >= 3``.
    q, r : int
        The grain ``(N - q, r)``, ``1 <= q <= N - 2``, ``2 <= r <= N - q``.
    dtype : numpy dtype
        Of the tables: ``object`` (default) for exact Python integers, or
        ``np.int64`` with a modular ``reduce``.
    reduce : callable
        Applied to every table after each step (default: none; a reduction
        modulo a prime for the multi-modular route).

    Returns
    -------
    tuple
        ``(Z', S1, S0)``, Python integers for ``dtype=object``, residues
        otherwise.

    Examples
    --------
    >>> from fractions import Fraction
    >>> from forcenet.exact import count, mean_W
    >>> Z, S1, S0 = gamma_sums(7, 2, 3)
    >>> Z, S1, S0
    (61024, 92120, 90952)
    >>> Fraction(3 * Z + S1 - S0, 22 * count(7)) == mean_W(7)[4][2]  # Eq. (4.77), d + 1 = 22
    True
    """
    p = N - 2
    relaxed = {l: frozenset(ks) for l, ks in defect_line(N, q, r).items()}

    def weighted(row_l: int | None) -> Any:
        box = np.ones((), dtype=dtype)  # row 1: h(1,1) = 1
        for l in range(1, p + 1):
            if l > 1:
                box = _transfer(box, l - 1, relaxed.get(l, frozenset()), reduce)
            if row_l == l and q - 1 >= 1 and q - 1 < l:  # multiply by the value h(l, q-1)
                box = _times_index(box, q - 2, reduce)
        return box.sum()

    Z = weighted(None)
    S1 = weighted(N - r) if (q - 1 >= 1 and q - 1 < N - r) else Z
    S0 = weighted(N - r - 1) if (N - r - 1 >= 1 and q - 1 >= 1 and q - 1 < N - r - 1) else Z
    return Z, S1, S0

def mean_W_gamma(N: int, progress: Progress | None = None) -> list[list[Fraction]]:
    """``<W>`` table from the integer recursions: Lambda for ``r = 1`` (4.67), Gamma in the bulk (4.77).

    ``(d+1) Z <W_{N-q,r}> = (q + 1) Z' + S1 - S0`` (:func:`gamma_bulk_integer`,
    multi-modular, the last row of each recursion summed as a chain); the
    bottom layer from the layer above (see :func:`mean_W_thesis_maps`).
    Reaches N = 12: about 3 min and 6-20 GB per grain there, 55 grains.
    ``progress`` is called once per bulk grain.

    Parameters
    ----------
    N : int
        Number of layers, ``N >= 2``.
    progress : callable, optional
        Called with no argument after each bulk grain.

    Returns
    -------
    list of lists of Fraction
        ``table[i-1][j-1] = <W_{i,j}>``.

    Raises
    ------
    ArgumentError
        If ``N`` is not an integer ``>= 2``.

    Examples
    --------
    >>> [str(x) for x in mean_W_gamma(5)[-1]]
    ['1/11', '1/4', '7/22', '1/4', '1/11']
    """
    N = check_layers(N)

    def bulk(q: int, r: int) -> int:
        if N >= 4:
            value = gamma_bulk_integer(N, q, r)
        else:  # N = 3, one bulk grain: the exact sums themselves (the chain needs a row below the grain's)
            Z, S1, S0 = gamma_sums(N, q, r)
            value = (q + 1) * Z + S1 - S0
        if progress is not None:
            progress()
        return value

    return table_from_bulk(N, bulk)

def _lambda_sum_mod(N: int, prime: int, weight_index: int | None = None) -> int:
    """``sum_j w(j) Lambda^(N-2)_j mod prime`` without building the last table.

    ``Lambda^(p)`` at ``(j_1, ..., j_{p-1}, 1)`` is the dominance sum of
    ``Lambda^(p-1)`` read at ``(j_2, ..., j_{p-1})`` clipped to its box (4.50);
    its sum over the index range (4.32) is the chain of :func:`_last_row_chain`
    (no raised bounds).  N = 12 needs the 2.3e8-cell box of ``Lambda^(9)``
    instead of the 9.4e9-cell box of ``Lambda^(10)``.  ``weight_index = k``
    weights each tuple by ``j_k`` (for Eq. 4.67).
    """
    p = N - 2
    reduce = _mod_reducer(prime)
    box = _lambda_boxes(p - 1, np.int64, reduce)
    return _last_row_chain(box, p, frozenset(), reduce, weight_index) % prime

def count_lambda_chain(N: int) -> int:
    """``sum_j Lambda^(N-2)_j`` of Eq. (4.51) by :func:`_lambda_sum_mod` and CRT (reaches N = 12).

    Parameters
    ----------
    N : int
        Number of layers, ``N >= 5``.

    Returns
    -------
    int
        Equal to :func:`forcenet.exact.count`.

    Raises
    ------
    ArgumentError
        If ``N`` is not an integer ``>= 5``.

    Examples
    --------
    >>> [count_lambda_chain(N) for N in range(5, 10)]
    [12, 286, 33592, 23178480, 108995910720]
    """
    N = check_layers(N, minimum=5)
    primes = primes_for_bound(count(N) * N * N)
    return crt([_lambda_sum_mod(N, p) for p in primes], primes)

def _last_row_chain(box: np.ndarray, p: int, relaxed: frozenset, reduce: Reduce, weight_index: int | None = None) -> int:
    """``sum`` over row ``p`` of the map recursion without building it (the chain of (4.50)).

    ``box`` is row ``p - 1`` (axes ``h(p-1, 1..p-2)``).  Row ``p`` at
    ``(h_1, ..., h_{p-1})`` is the dominance sum ``D`` of ``box`` read at
    ``(h_2, ..., h_{p-1})`` clipped to its shape (4.89), on the range
    ``h_1 <= 2``, ``h_k <= k + h_{k-1}``, each bound raised by one at the
    ``relaxed`` positions (the Gamma defect line, 4.73).  The sum over that
    range is taken one coordinate at a time, innermost first: a cumulative sum
    along one axis read at the bound set by the next coordinate.  The largest
    array is ``D``.  ``weight_index = k`` weighs each tuple by ``h_k``.
    """
    D = _dominance(box, reduce)
    M = _row_maxima(p, relaxed)  # M[k-1]: largest h_k on row p
    if p == 2:  # row 2 has one entry h_1 and no dependence on the box
        w = np.arange(1, M[0] + 1, dtype=np.int64) if weight_index == 1 else np.ones(M[0], dtype=np.int64)
        return int(reduce(w * D).sum())
    shape = D.shape  # axis a <-> clip(h_{a+2}), a = 0..p-3

    def weigh(G: np.ndarray, k: int) -> np.ndarray:  # G's last axis is h_k, unclipped
        return _times_index(G, -1, reduce) if weight_index == k else G

    # innermost coordinate h_{p-1}: extend D's last axis by saturation to M_{p-1}
    top = M[p - 2]
    G = D
    if top > shape[-1]:
        G = np.concatenate([D, np.broadcast_to(D[..., -1:], shape[:-1] + (top - shape[-1],))], axis=-1)
    del D
    G = G[..., :top]
    for k in range(p - 1, 1, -1):  # sum over h_k, bound k + h_{k-1} (+1 if relaxed)
        G = weigh(G, k)
        C = G  # ours: a fresh array or a view of one
        np.cumsum(C, axis=-1, dtype=C.dtype, out=C)
        C = _reduce_inplace(C, reduce)
        del G
        raise_k = 1 if k in relaxed else 0
        slices = []
        for t in range(1, M[k - 2] + 1):  # t = h_{k-1}, unclipped
            bound = min(upper_bound(k, t, raise_k), C.shape[-1])
            if k - 1 >= 2:  # h_{k-1} is an axis of D, clipped to its length
                slices.append(C[..., min(t, shape[k - 3]) - 1, bound - 1])
            else:
                slices.append(C[..., bound - 1])
        del C
        G = np.stack(slices, axis=-1)
    G = weigh(G, 1)
    return int(G.sum())  # at most three residues: the callers reduce

class _ModReducer:
    """``a % prime`` (numpy arrays or ints), with the prime at hand as ``modulus``."""

    def __init__(self, prime: int) -> None:
        self.modulus = prime

    def __call__(self, a: np.ndarray) -> np.ndarray:
        return a % self.modulus


def _mod_reducer(prime: int) -> _ModReducer:
    return _ModReducer(prime)

def _gamma_combined_mod(N: int, q: int, r: int, prime: int) -> int:
    """``(q+1) Z'(q, r) + S1 - S0 mod prime`` of Eq. (4.77) in one pass, last row by the chain.

    The three sums of :func:`gamma_sums` are one linear recursion with a
    weight inserted at row ``N - r`` (``+h(N-r, q-1)``) or ``N - r - 1``
    (``-h(N-r-1, q-1)``).  Carrying the unweighted box ``B`` and the combination
    ``X`` together until row ``N - r``, then ``X`` alone, gives the integer of
    (4.77) for the price of one recursion.
    """
    p = N - 2
    reduce = _mod_reducer(prime)
    relaxed = {l: frozenset(ks) for l, ks in defect_line(N, q, r).items()}
    k = q - 1  # the weight h(row, q-1); h(l, 0) = h(0, k) = 1

    def weight(box: np.ndarray, row: int) -> np.ndarray:
        return _times_index(box, k - 1, reduce) if 1 <= k < row else box

    plus_row, minus_row = N - r, N - r - 1
    B = np.ones((), dtype=np.int64)
    carrying = True  # B is carried along until the + row
    X = np.full((), (q + 1) % prime, dtype=np.int64)
    if minus_row < 1:  # S0 = Z': h(0, k) = 1
        X = reduce(X - B)
    for l in range(1, p):
        if l > 1:
            X = _transfer(X, l - 1, relaxed.get(l, frozenset()), reduce)
            if carrying:
                B = _transfer(B, l - 1, relaxed.get(l, frozenset()), reduce)
        if l == minus_row:
            X = reduce(X - weight(B, l))
        if l == plus_row:
            X = reduce(X + weight(B, l))
            carrying = False
    last = relaxed.get(p, frozenset())
    total = _last_row_chain(X, p, last, reduce)
    if plus_row == p:  # r = 2: the + weight sits on the last row itself
        total += _last_row_chain(B, p, last, reduce, weight_index=k if 1 <= k < p else None)
    return total % prime

def gamma_bulk_integer(N: int, q: int, r: int) -> int:
    """The integer ``(q+1) Z'(q,r) + S1 - S0 = (d+1) Z <W_{N-q,r}>`` of Eq. (4.77), by CRT.

    Multi-modular version of :func:`gamma_sums` that never builds the last
    row of the recursion (:func:`_last_row_chain`); reaches N = 12.

    Parameters
    ----------
    N : int
        Number of layers, ``N >= 4``.
    q, r : int
        The grain ``(N - q, r)``, ``1 <= q <= N - 2``, ``2 <= r <= N - q``.

    Returns
    -------
    int

    Raises
    ------
    ArgumentError
        If ``N``, ``q`` or ``r`` is out of range.

    Examples
    --------
    >>> Z, S1, S0 = gamma_sums(7, 2, 3)
    >>> gamma_bulk_integer(7, 2, 3) == 3 * Z + S1 - S0
    True
    """
    N = check_layers(N, minimum=4)
    q = check_int(q, "q", 1, N - 2)
    r = check_int(r, "r", 2, N - q)
    d = dimension(N)
    primes = primes_for_bound((d + 2) * (d + 1) * count(N))
    return crt([_gamma_combined_mod(N, q, r, prime) for prime in primes], primes)
