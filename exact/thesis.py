"""The thesis's own route (chapter 4): integer recursions and map counting.

Reconstructed from the extracted text of Ostojic (2006); every formula here is
checked against the exact core in ``tests/test_thesis.py`` and derived in
``notes/chapter4.md``.

* :func:`integral_I` and :func:`gamma_coefficient`: the centrepiece integral
  (4.14)-(4.15).
* :func:`index_tuples`: the index range (4.32): ``j_1 in {1, 2}``,
  ``1 <= j_l <= l + j_{l-1}``.
* :func:`lambda_table`: the integers ``Lambda^(p)`` of (4.2)/(4.50),
  ``Lambda^(2)_{j1 j2} = delta(j2, 1)``,
  ``Lambda^(p+1)_j = delta(j_{p+1}, 1) sum_k Lambda^(p)_k prod_{l<=p} theta(j_{l+1} - k_l)``.
* :func:`count_lambda`, :func:`normalization_lambda`: Eq. (4.51).
* :func:`boundary_mean_W`: ``<W_{N-q,1}>`` from Eq. (4.67)-(4.68).
* :func:`maps`, :func:`count_maps`, :func:`maps_by_bottom_row`: the maps ``h``
  of Sec. 4.6, Eqs. (4.86)-(4.89); :func:`map_from_tableau`: a bijection from
  standard shifted staircase tableaux onto them.
"""

from __future__ import annotations

from collections import Counter
from fractions import Fraction
from functools import lru_cache
from math import factorial

import numpy as np

from .staircase import check_layers

__all__ = [
    "gamma_coefficient",
    "integral_I",
    "index_tuples",
    "psi_fundamental",
    "right_vector",
    "normalization_fundamental",
    "lambda_table",
    "count_lambda",
    "normalization_lambda",
    "boundary_mean_W",
    "maps",
    "count_maps",
    "maps_by_bottom_row",
    "map_from_tableau",
    "tableau_from_map",
    "mean_W_by_maps",
    "moments_by_maps",
    "mean_W_thesis_maps",
    "moment_thesis_maps",
    "gamma_sums",
    "mean_W_gamma",
    "count_lambda_chain",
    "is_map",
]


def gamma_coefficient(m: int, n: int, k: int) -> Fraction:
    """``gamma^{m-k}_{m,n} = m! n! / ((n + k + 1)! (m - k)!)``, Eq. (4.15).

    Examples
    --------
    >>> gamma_coefficient(1, 1, 1)
    Fraction(1, 6)
    """
    if not 0 <= k <= m:
        raise ValueError(f"k={k}: need 0 <= k <= m={m}")
    return Fraction(factorial(m) * factorial(n), factorial(n + k + 1) * factorial(m - k))


def integral_I(m: int, n: int, a, b):
    """``I_mn(a, b) = int_a^b x^m (b - x)^n dx``, evaluated by Eq. (4.14).

    ``I_mn(a, b) = sum_{k=0}^{m} gamma^{m-k}_{m,n} (b - a)^{n+1+k} a^{m-k}``.
    ``a`` and ``b`` may be numbers or sympy expressions.

    Examples
    --------
    >>> integral_I(1, 1, 0, 1)
    Fraction(1, 6)
    >>> integral_I(2, 0, 1, 2)
    Fraction(7, 3)
    """
    total = 0
    for k in range(m + 1):
        total += gamma_coefficient(m, n, k) * (b - a) ** (n + 1 + k) * a ** (m - k)
    return total


def index_tuples(p: int):
    """All tuples ``(j_1, ..., j_p)`` in the range (4.32).

    Examples
    --------
    >>> list(index_tuples(2))
    [(1, 1), (1, 2), (1, 3), (2, 1), (2, 2), (2, 3), (2, 4)]
    """

    def extend(prefix):
        l = len(prefix) + 1
        if l > p:
            yield prefix
            return
        top = 2 if l == 1 else l + prefix[-1]
        for j in range(1, top + 1):
            yield from extend(prefix + (j,))

    yield from extend(())


def _psi_factor(f: int, s: int, e: int) -> Fraction:
    """``psi^f_{s,e} = gamma^f_{s,e}`` of (4.15), zero outside ``0 <= f <= s``, ``e >= 0``."""
    if f < 0 or s < 0 or e < 0 or f > s:
        return Fraction(0)
    return gamma_coefficient(s, e, s - f)


def psi_fundamental(i: tuple, j: tuple) -> Fraction:
    """The coefficient ``psi_{i1 j1, ..., ip jp}`` of the fundamental relations (4.29)-(4.30).

    ``psi_{i1 j1} = psi^{2-i1}_{1, 2-j1}`` and (4.30)

        psi_{..., ip jp} = psi_{..., i(p-1) j(p-1)} psi^{p + i(p-1) - ip}_{p + i(p-1) - j(p-1), p + j(p-1) - jp} theta(ip - j(p-1)),

    with ``psi^f_{s,e} = gamma^f_{s,e} = s! e! / ((e + s - f + 1)! f!)`` (4.15).
    The element of the nested matrix ``t`` (4.28) is ``psi W^{p + i_p - j_p}``
    (``p`` index pairs).  Read this way -- the first lower index is
    ``p + i(p-1) - j(p-1)``, the power of ``W`` in the previous level -- the
    printed relations give the normalization (4.46) and
    ``R = Lambda / prod factorials`` (4.49) exactly (tests, N <= 7).

    Examples
    --------
    >>> psi_fundamental((2,), (2,)), psi_fundamental((2, 3), (1, 1))
    (Fraction(1, 2), Fraction(1, 60))
    """
    if len(i) != len(j) or not i:
        raise ValueError(f"i={i!r}, j={j!r}: need two index tuples of the same length >= 1")
    value = _psi_factor(2 - i[0], 1, 2 - j[0])
    for l in range(2, len(i) + 1):
        il, jl, ip, jp = i[l - 1], j[l - 1], i[l - 2], j[l - 2]
        if value == 0 or il < jp:  # theta(i_l - j_{l-1})
            return Fraction(0)
        value *= _psi_factor(l + ip - il, l + ip - jp, l + jp - jl)
    return value


def right_vector(p: int) -> dict:
    """``R^{(p)}`` of (4.31): ``R^{(1)} = delta(i1, 1)``,
    ``R^{(p)}_i = delta(i_p, 1) sum_j psi_{i1 j1, ..., i(p-1) j(p-1)} R^{(p-1)}_j``.

    Nonzero entries only; exact Fractions.  (4.49): ``R^{(p)}_j =
    Lambda^{(p)}_j / prod_{l=2}^{p} (l + j(l-1) - j_l)!``.

    Examples
    --------
    >>> right_vector(2)
    {(1, 1): Fraction(1, 2), (2, 1): Fraction(1, 6)}
    """
    R = {(1,): Fraction(1)}
    for q in range(2, p + 1):
        new = {}
        for i in index_tuples(q):
            if i[-1] != 1:
                continue
            value = sum((psi_fundamental(i[:-1], j) * r for j, r in R.items()), Fraction(0))
            if value:
                new[i] = value
        R = new
    return R


def normalization_fundamental(N: int) -> Fraction:
    """The normalization ``L t(W_{1,1} = 1) R`` (4.46) from the printed fundamental relations.

    ``L^{(p)}_i = prod_l delta(i_l, l(l+1)/2 + 1)`` (4.31) selects one row;
    ``t`` is (4.28) with ``W = 1`` and ``R`` is :func:`right_vector`.  The
    literal route: a sum over the index tuples (4.32) with ``psi`` products,
    so meant for small N (N = 7 in a few seconds).

    Examples
    --------
    >>> normalization_fundamental(5)
    Fraction(1, 302400)
    """
    N = check_layers(N, minimum=3)
    p = N - 2
    R = right_vector(p)
    top = tuple(l * (l + 1) // 2 + 1 for l in range(1, p + 1))
    return sum((psi_fundamental(top, j) * r for j, r in R.items()), Fraction(0))


def _lambda_boxes(p: int, dtype, reduce):
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

    Examples
    --------
    >>> lambda_table(2)
    {(1, 1): 1, (2, 1): 1}
    >>> sum(lambda_table(4).values())
    286
    """
    if p < 1:
        raise ValueError(f"p={p}: need p >= 1")
    L = _lambda_boxes(p, object, lambda a: a)
    if L.ndim == 0:
        return {(1,): int(L)}
    return {tuple(int(x) + 1 for x in idx) + (1,): int(L[idx]) for idx in zip(*np.nonzero(L))}


@lru_cache(maxsize=16)
def _lambda_weighted_sums(N: int):
    """Exact ``sum_j Lambda^(N-2)_j`` and ``sum_j j_a Lambda^(N-2)_j`` for every axis ``a``.

    Multi-modular with CRT, through the chain of :func:`_lambda_sum_mod`
    (``N >= 5``), which never builds the last Lambda table.
    """
    if N < 5:
        return _lambda_weighted_sums_box(N)
    from .modular import crt, primes_for_bound
    from .staircase import count

    d = N * (N - 1) // 2
    primes = primes_for_bound(d * d * count(N))
    p = N - 2
    rows = []
    for prime in primes:  # one Lambda^(p-1) box per prime, one chain per weight
        reduce = _mod_reducer(prime)
        box = _lambda_boxes(p - 1, np.int64, reduce)
        rows.append([_last_row_chain(box, p, frozenset(), reduce, k) % prime for k in [None] + list(range(1, p))])
        del box
    return [crt(col, primes) for col in zip(*rows)]


def _lambda_weighted_sums_box(N: int):
    """The same sums from the whole last table (dense box): the reference for the chain."""
    from .modular import crt, primes_for_bound
    from .staircase import count

    p = N - 2
    d = N * (N - 1) // 2
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

    Examples
    --------
    >>> normalization_lambda(5)
    Fraction(1, 302400)
    """
    N = check_layers(N)
    return Fraction(count_lambda(N), factorial(N * (N - 1) // 2))


def boundary_mean_W(N: int, q: int) -> Fraction:
    """``<W_{N-q,1}>`` on the left boundary, Eqs. (4.67)-(4.68).

    ``<W_{N-q,1}> = sum_j (q(q+1)/2 + 2 - j_{q-1}) Lambda^(N-2)_j / ((d+1) sum_j Lambda^(N-2)_j)``
    for ``1 <= q <= N-2`` with ``j_0 = 1``; ``<W_{N,1}> = <W_{N-1,1}> / 2``;
    ``W_{1,1} = 1``.

    Examples
    --------
    >>> [boundary_mean_W(5, q) for q in range(5)]
    [Fraction(1, 11), Fraction(2, 11), Fraction(41, 132), Fraction(1, 2), Fraction(1, 1)]
    """
    N = check_layers(N)
    if not 0 <= q <= N - 1:
        raise ValueError(f"q={q} is out of range: q must be in 0..N-1={N - 1}")
    if q == N - 1:
        return Fraction(1)
    if q == 0:
        return boundary_mean_W(N, 1) / 2
    d = N * (N - 1) // 2
    sums = _lambda_weighted_sums(N)  # [sum Lambda, sum j_1 Lambda, sum j_2 Lambda, ...]
    total = sums[0]
    j_sum = total if q == 1 else sums[q - 1]  # j_0 = 1
    return Fraction((q * (q + 1) // 2 + 2) * total - j_sum, (d + 1) * total)


# ---------------------------------------------------------------- maps (4.86)-(4.89)


def is_map(h: dict[int, tuple[int, ...]], p: int) -> bool:
    """True if ``h`` (row ``l`` -> tuple of length ``l``, ``l = 1..p``) is a map of Sec. 4.6.

    Conditions: ``h(1,1) = 1``; ``1 <= h(l,1) <= 2``; ``1 <= h(l,k) <= k + h(l,k-1)``
    (4.86); ``h(l,l) = 1`` (the ``delta`` of (4.87)); ``h(l-1,k) <= h(l,k+1)`` (4.89).
    """
    for l in range(1, p + 1):
        row = h.get(l)
        if row is None or len(row) != l:
            return False
        if not 1 <= row[0] <= (1 if l == 1 else 2):
            return False
        if any(not 1 <= row[k] <= (k + 1) + row[k - 1] for k in range(1, l)):
            return False
        if row[-1] != 1:
            return False
        if l >= 2 and any(h[l - 1][k] > row[k + 1] for k in range(l - 1)):
            return False
    return True


def maps(N: int, relaxed: dict | None = None):
    """Generate all maps ``h`` for ``p = N - 2`` (rows ``l = 1..p``).

    ``relaxed`` maps a row ``l`` to a set of positions ``k`` whose upper bound
    in (4.86) is raised by one (the modified maps ``h(q, r)`` of Eq. (4.90)),
    or to a dict ``{k: amount}`` (s-th order defects, Eqs. (4.80)-(4.85)).

    Examples
    --------
    >>> [m for m in maps(4)]
    [{1: (1,), 2: (1, 1)}, {1: (1,), 2: (2, 1)}]
    """
    N = check_layers(N, minimum=3)
    p = N - 2
    relaxed = relaxed or {}
    rows = {}
    for l in range(1, p + 1):
        raise_by = relaxed.get(l, {})
        if not isinstance(raise_by, dict):
            raise_by = {k: 1 for k in raise_by}
        rows[l] = _map_rows(l, tuple(sorted(raise_by.items())))

    def extend(h, l):
        if l > p:
            yield dict(h)
            return
        for row in rows[l]:
            if l == 1 or all(h[l - 1][k] <= row[k + 1] for k in range(l - 1)):
                h[l] = row
                yield from extend(h, l + 1)
        h.pop(l, None)

    yield from extend({}, 1)


@lru_cache(maxsize=256)
def _map_rows(l: int, raise_by: tuple) -> list[tuple[int, ...]]:
    """Row ``l`` of a map: (4.86) with bounds raised by ``amount`` at each ``(k, amount)``, last entry 1."""
    raise_by = dict(raise_by)

    def extend(prefix):
        k = len(prefix) + 1
        if k > l:
            yield prefix
            return
        top = (1 if l == 1 else 2) if k == 1 else k + prefix[-1]
        top += raise_by.get(k, 0)
        for v in range(1, top + 1):
            yield from extend(prefix + (v,))

    return [row for row in extend(()) if row[-1] == 1]


def _defect_line(N: int, q: int, r: int, amount: int = 1) -> dict:
    """Rows ``l`` -> ``{k: amount}`` on the defect line ``(N-r+t, q+t)``, ``0 <= t <= r-2`` (Eq. 4.90)."""
    line = {}
    for t in range(r - 1):
        l, k = N - r + t, q + t
        if 1 <= l <= N - 2:
            line.setdefault(l, {})[k] = amount
    return line


def _entry(h, l: int, k: int) -> int:
    """``h(l, k)`` with the conventions ``h(l, 0) = h(0, k) = 1`` of (4.67) and (4.91)."""
    return 1 if (l == 0 or k == 0) else h[l][k - 1]


def _table_from_bulk(N: int, bulk) -> list[list[Fraction]]:
    """Assemble a ``<W>`` table: (4.67) on the left boundary, ``bulk(q, r) / ((d+1) Z)``
    for ``r >= 2`` (Eq. 4.91 or 4.77), the bottom layer from the layer above."""
    if N <= 3:
        return mean_W_by_maps(N)
    d = N * (N - 1) // 2
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


def mean_W_thesis_maps(N: int, progress=None) -> list[list[Fraction]]:
    """``<W>`` table from the thesis's map formulas, Eqs. (4.67) and (4.90)-(4.91).

    * ``r = 1`` (left boundary): Eq. (4.67) with the Lambda integers;
    * ``1 <= q``, ``2 <= r <= N - q``:
      ``<W_{N-q,r}> = sum_{h(q,r)} [q + 1 + h(N-r, q-1) - h(N-r-1, q-1)] / ((d+1) Z_{N-2})``,
      over the maps whose bounds (4.86) are raised by one on the line
      ``(l, k) = (N-r+j, q+j)``, ``0 <= j <= r-2``, with ``h(l, 0) = h(0, k) = 1``;
    * ``q = 0`` (bottom layer): ``<W_{N,r}> = (<W_{N-1,r-1}> + <W_{N-1,r}>)/2``,
      because the last layer's q's do not enter the weight (3.10) and are
      uniform and independent of the layers above (generalizing the thesis's
      ``<W_{N,1}> = <W_{N-1,1}>/2``).

    Enumerates maps, so meant for ``N <= 8`` (N = 8: 23,178,480 maps and more
    modified ones per grain, 34 min for the table; N = 9 would visit 1.1e11
    maps per grain).  ``progress`` is called once per bulk grain.

    Examples
    --------
    >>> [str(x) for x in mean_W_thesis_maps(5)[-1]]
    ['1/11', '1/4', '7/22', '1/4', '1/11']
    """
    N = check_layers(N)

    def bulk(q, r):
        line = _defect_line(N, q, r)
        value = sum(q + 1 + _entry(h, N - r, q - 1) - _entry(h, N - r - 1, q - 1) for h in maps(N, line))
        if progress is not None:
            progress()
        return value

    return _table_from_bulk(N, bulk)


def moment_thesis_maps(N: int, grain, s: int) -> Fraction:
    """``<W_{i,j}^s>`` from map counting with s-th order defects, ``i <= N - 1``.

    Reconstructed (4.80)-(4.85) in map form: with ``q = N - i``, ``r = j >= 2``,

        (d+1)...(d+s) Z <W^s> = sum over maps with bounds raised by ``s`` on the
        line ``(N-r+t, q+t)``, ``0 <= t <= r-2``, of
        (q + s + h(N-r, q-1) - h(N-r-1, q-1)) (...) (q + 1 + h(N-r, q-1) - h(N-r-1, q-1)),

    the falling product of (4.82); on the left boundary ``r = 1`` the rank
    ``T = q(q+1)/2 + 2 - h(N-2, q-1)`` of (4.67) gives
    ``<W^s> = E[T (T+1) ... (T+s-1)] / ((d+1) ... (d+s))``.  The bottom layer
    needs two-grain moments and is not covered (use :func:`exact.moment`).

    Examples
    --------
    >>> moment_thesis_maps(5, (4, 2), 2)
    Fraction(4, 33)
    """
    N = check_layers(N, minimum=3)
    i, j = grain
    if not (1 <= i <= N - 1 and 1 <= j <= i):
        raise ValueError(f"grain={grain!r}: need 1 <= j <= i <= N - 1 = {N - 1} (the bottom layer needs two-grain moments)")
    if isinstance(s, bool) or not isinstance(s, int) or s < 1:
        raise ValueError(f"s={s!r}: must be an integer >= 1")
    d, p, q, r = N * (N - 1) // 2, N - 2, N - i, j
    Z = count_lambda(N)
    rising = 1
    for t in range(1, s + 1):
        rising *= d + t
    if q == N - 1:  # W_{1,1} = 1
        return Fraction(1)
    if r == 1:
        total = 0
        for h in maps(N):
            T = q * (q + 1) // 2 + 2 - (1 if q == 1 else h[p][q - 2])
            value = 1
            for t in range(s):
                value *= T + t
            total += value
        return Fraction(total, Z * rising)
    total = 0
    for h in maps(N, _defect_line(N, q, r, s)):
        top = q + s + _entry(h, N - r, q - 1) - _entry(h, N - r - 1, q - 1)
        value = 1
        for t in range(s):
            value *= top - t
        total += value
    return Fraction(total, Z * rising)


def count_maps(N: int) -> int:
    """``Z_{N-2}``: the number of maps (Sec. 4.6), by enumeration.

    Examples
    --------
    >>> count_maps(6)
    286
    """
    return sum(1 for _ in maps(N))


def maps_by_bottom_row(N: int) -> Counter:
    """Number of maps for each value of the last row ``h(N-2, .)`` (= ``Lambda^(N-2)``, Eq. 4.88).

    Examples
    --------
    >>> sorted(maps_by_bottom_row(4).items())
    [((1, 1), 1), ((2, 1), 1)]
    """
    N = check_layers(N, minimum=3)
    return Counter(h[N - 2] for h in maps(N))


def map_from_tableau(N: int, T: dict[tuple[int, int], int]) -> dict[int, tuple[int, ...]]:
    """The map ``h`` of a standard shifted staircase tableau (a bijection).

    ``T`` maps cells ``(r, c)``, ``1 <= r <= c <= N-1``, to entries ``1..d``.
    Row ``l`` of ``h`` describes tableau row ``r = N - 1 - l``:
    ``h(l, k) = 1 + #{cells (r', c') : r' >= r, c' < c, T(r', c') > T(r, c)}``
    with ``c = r + 1 + k``, and ``h(l, l) = 1``.  On the first tableau row this
    is Eq. (4.67)'s ``T(1, q+1) = q(q+1)/2 + 2 - h(N-2, q-1)``.

    Examples
    --------
    >>> T = {(1, 1): 1, (1, 2): 2, (1, 3): 3, (2, 2): 4, (2, 3): 5, (3, 3): 6}
    >>> map_from_tableau(4, T)
    {1: (1,), 2: (2, 1)}
    """
    N = check_layers(N, minimum=3)
    n, p = N - 1, N - 2
    h = {}
    for l in range(1, p + 1):
        r = n - l
        row = []
        for k in range(1, l):
            c = r + 1 + k
            later = sum(
                1 for (r2, c2), t in T.items() if r2 >= r and c2 < c and t > T[(r, c)]
            )
            row.append(1 + later)
        h[l] = tuple(row) + (1,)
    return h


def tableau_from_map(N: int, h: dict[int, tuple[int, ...]]) -> dict[tuple[int, int], int]:
    """Inverse of :func:`map_from_tableau`: the tableau of a map.

    Builds the order of the cells row by row from the bottom of the
    staircase: ``(r, r)`` and ``(r, r+1)`` precede every cell below them;
    ``(r, c)``, ``c >= r + 2``, precedes every cell of the rows below in
    columns ``>= c`` and exactly ``h(l, k) - 1`` of those in columns ``< c``
    (``l = N - 1 - r``, ``k = c - r - 1``).

    Examples
    --------
    >>> tableau_from_map(4, {1: (1,), 2: (2, 1)})[(2, 2)]
    4
    """
    N = check_layers(N, minimum=3)
    if not is_map(h, N - 2):
        raise ValueError(f"h={h!r} is not a map of Sec. 4.6 for N={N} (Eqs. 4.86-4.89)")
    n = N - 1
    order = [(n, n)]
    for r in range(n - 1, 0, -1):
        l = n - r
        row = [(r, r), (r, r + 1)] if r + 1 <= n else [(r, r)]
        merged = row + order
        for c in range(r + 2, n + 1):
            later = h[l][c - r - 2] - 1  # cells of lower rows, columns < c, filled after (r, c)
            # scan positions right after (r, c-1): count lower cells with column < c behind each position
            start = merged.index((r, c - 1)) + 1
            behind = sum(1 for (r2, c2) in merged[start:] if r2 > r and c2 < c)
            pos = start
            while behind > later:
                cell = merged[pos]
                if cell[0] > r and cell[1] < c:
                    behind -= 1
                pos += 1
            if behind != later or any(r2 > r and c2 >= c for (r2, c2) in merged[start:pos]):
                raise ValueError(f"h is not a map: row {l} entry {c - r - 1} cannot be placed")
            merged.insert(pos, (r, c))
        order = merged
    return {cell: k + 1 for k, cell in enumerate(order)}


def _map_rankings(N: int):
    """Ranks of the partial sums ``S_{i,j}`` for every map, through its tableau.

    Tableau cell ``(r, c)`` holds the rank of ``S_{N-c+r, r}``.
    """
    if N == 2:  # no map rows: the one-cell staircase
        yield {(2, 1): 1}
        return
    for h in maps(N):
        T = tableau_from_map(N, h)
        yield {(N - c + r, r): t for (r, c), t in T.items()}


def moments_by_maps(N: int, s_max: int = 1, pairs=()):
    """Moments and two-point functions of the W's by counting maps (Sec. 4.6).

    Every map ``h`` of (4.86)-(4.89) is turned into its staircase tableau
    (:func:`tableau_from_map`), i.e. a linear extension of the partial sums.
    Given it, the ``d + 1`` spacings of the partial sums are Dirichlet(1, ..., 1),
    so with the rank gap ``g`` of a grain,
    ``<W^s> = E[g (g+1) ... (g+s-1)] / ((d+1) ... (d+s))`` (the map form of the
    s-th order defects (4.80)-(4.85)), and for two grains with rank intervals
    ``I, J``: ``<W W'> = E[|I| |J| + |I & J|] / ((d+1)(d+2))`` (Sec. 4.5.2).
    This covers every grain, the bottom layer included.  Enumerates
    ``Z_{N-2}`` maps: ``N <= 7``.

    Parameters
    ----------
    N : int
        Number of layers, ``2 <= N``.
    s_max : int
        Highest moment ``s`` of ``W^s``.
    pairs : iterable of (grain, grain)
        Two-point functions ``<W_g W_g'>`` to compute.

    Returns
    -------
    (count, moments, correlations)
        ``count = Z_{N-2}``, ``moments[s][(i, j)] = <W_{i,j}^s>``,
        ``correlations[(g, g')] = <W_g W_g'>``, all exact Fractions.

    Examples
    --------
    >>> Z, mom, cor = moments_by_maps(4, s_max=2, pairs=[((4, 1), (4, 4))])
    >>> Z, mom[2][(4, 1)], cor[((4, 1), (4, 4))]
    (2, Fraction(1, 28), Fraction(1, 56))
    """
    from .brute import rank_gap_moments
    from .moments import check_grain

    N = check_layers(N)
    if isinstance(s_max, bool) or not isinstance(s_max, int) or s_max < 1:
        raise ValueError(f"s_max={s_max!r}: must be an integer >= 1")
    pairs = [(check_grain(N, a, "pairs"), check_grain(N, b, "pairs")) for a, b in pairs]
    return rank_gap_moments(N, _map_rankings(N), s_max, pairs)


def mean_W_by_maps(N: int) -> list[list[Fraction]]:
    """``<W>`` table as an average over all maps (Sec. 4.6), through the bijection.

    Each map is turned into its tableau (:func:`tableau_from_map`) and the
    grain's gap of ranks averaged: ``<W_ij> = E[T(j, N-i+j) - T(j-1, N-i+j-1)] / (d+1)``.
    Enumerates ``Z_{N-2}`` maps, so meant for ``N <= 7``.

    Examples
    --------
    >>> [str(x) for x in mean_W_by_maps(5)[-1]]
    ['1/11', '1/4', '7/22', '1/4', '1/11']
    """
    _, moments, _ = moments_by_maps(N, 1)
    return [[moments[1][(i, j)] for j in range(1, i + 1)] for i in range(1, N + 1)]


# ---------------------------------------------------------------- Gamma: (4.73)-(4.77)


def _row_maxima(l: int, relaxed: frozenset) -> tuple[int, ...]:
    """Largest values of ``h(l, 1..l-1)`` under (4.86) with bounds raised at ``relaxed``."""
    out = []
    for k in range(1, l):
        top = (2 if k == 1 else k + out[-1]) + (k in relaxed)
        out.append(top)
    return tuple(out)


def _row_mask(l: int, relaxed: frozenset) -> np.ndarray:
    """Valid ``(h(l,1), ..., h(l,l-1))`` (0-based box) under the raised bounds."""
    shape = _row_maxima(l, relaxed)
    mask = np.ones(shape, dtype=bool)
    m = len(shape)
    for k in range(2, m + 1):  # h(l,k) <= k + h(l,k-1) (+1 if relaxed); 0-based b <= k + a (+1)
        a = np.arange(shape[k - 2]).reshape([-1 if ax == k - 2 else 1 for ax in range(m)])
        b = np.arange(shape[k - 1]).reshape([-1 if ax == k - 1 else 1 for ax in range(m)])
        mask &= b <= k + a + (k in relaxed)
    return mask


def _transfer(box: np.ndarray, l: int, relaxed_next: frozenset, reduce) -> np.ndarray:
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


def _dominance(box: np.ndarray, reduce) -> np.ndarray:
    """Cumulative sums along every axis (a new array; ``box`` is left alone)."""
    D = np.array(box, copy=True)
    for axis in range(D.ndim):
        np.cumsum(D, axis=axis, dtype=D.dtype, out=D)
        D = _reduce_inplace(D, reduce)
    return D


def _times_index(box: np.ndarray, axis: int, reduce) -> np.ndarray:
    """Multiply ``box`` by the 1-based value of its index along ``axis`` (a map entry ``h``)."""
    values = np.arange(1, box.shape[axis] + 1, dtype=np.int64)
    return reduce(box * values.reshape([-1 if ax == axis % box.ndim else 1 for ax in range(box.ndim)]))


def _reduce_inplace(a: np.ndarray, reduce) -> np.ndarray:
    modulus = getattr(reduce, "modulus", None)
    if modulus is not None and a.dtype != object:
        np.remainder(a, modulus, out=a)
        return a
    return reduce(a)


def gamma_sums(N: int, q: int, r: int, dtype=object, reduce=lambda a: a):
    """Integer sums over the modified maps ``h(q, r)`` of Eq. (4.90), via row recursions.

    Returns ``(Z', S1, S0)``: the number of modified maps and the sums of
    ``h(N-r, q-1)`` and ``h(N-r-1, q-1)`` over them.  The recursion over rows is
    the Lambda recursion (4.50) with the bounds raised by one on the line of
    (4.73)/(4.75) -- the thesis's Gamma integers are its intermediate tables.
    """
    p = N - 2
    relaxed = {l: frozenset(ks) for l, ks in _defect_line(N, q, r).items()}

    def weighted(row_l: int | None):
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


def mean_W_gamma(N: int, progress=None) -> list[list[Fraction]]:
    """``<W>`` table from the integer recursions: Lambda for ``r = 1`` (4.67), Gamma in the bulk (4.77).

    ``(d+1) Z <W_{N-q,r}> = (q + 1) Z' + S1 - S0`` (:func:`gamma_bulk_integer`,
    multi-modular, the last row of each recursion summed as a chain); the
    bottom layer from the layer above (see :func:`mean_W_thesis_maps`).
    Reaches N = 12: about 3 min and 6-20 GB per grain there, 55 grains.
    ``progress`` is called once per bulk grain.

    Examples
    --------
    >>> [str(x) for x in mean_W_gamma(5)[-1]]
    ['1/11', '1/4', '7/22', '1/4', '1/11']
    """
    N = check_layers(N)

    def bulk(q, r):
        value = gamma_bulk_integer(N, q, r)
        if progress is not None:
            progress()
        return value

    return _table_from_bulk(N, bulk)


# ------------------------------------------- Lambda sums without the last table (N = 12)


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
    """``sum_j Lambda^(N-2)_j`` by :func:`_lambda_sum_mod` and CRT (reaches N = 12).

    Examples
    --------
    >>> [count_lambda_chain(N) for N in range(5, 10)]
    [12, 286, 33592, 23178480, 108995910720]
    """
    from .modular import crt, primes_for_bound
    from .staircase import count

    N = check_layers(N, minimum=5)
    primes = primes_for_bound(count(N) * N * N)
    return crt([_lambda_sum_mod(N, p) for p in primes], primes)


# ------------------------------------- Gamma sums without the last table (bulk at N = 12)


def _last_row_chain(box: np.ndarray, p: int, relaxed: frozenset, reduce, weight_index: int | None = None) -> int:
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

    def weigh(G, k):  # G's last axis is h_k, unclipped
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
            bound = min(k + t + raise_k, C.shape[-1])
            if k - 1 >= 2:  # h_{k-1} is an axis of D, clipped to its length
                slices.append(C[..., min(t, shape[k - 3]) - 1, bound - 1])
            else:
                slices.append(C[..., bound - 1])
        del C
        G = np.stack(slices, axis=-1)
    G = weigh(G, 1)
    return int(G.sum())  # at most three residues: the callers reduce


def _mod_reducer(prime: int):
    def reduce(a):
        return a % prime

    reduce.modulus = prime
    return reduce


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
    relaxed = {l: frozenset(ks) for l, ks in _defect_line(N, q, r).items()}
    k = q - 1  # the weight h(row, q-1); h(l, 0) = h(0, k) = 1

    def weight(box, row):
        return _times_index(box, k - 1, reduce) if 1 <= k < row else box

    plus_row, minus_row = N - r, N - r - 1
    B = np.ones((), dtype=np.int64)
    X = np.full((), (q + 1) % prime, dtype=np.int64)
    if minus_row < 1:  # S0 = Z': h(0, k) = 1
        X = reduce(X - B)
    for l in range(1, p):
        if l > 1:
            X = _transfer(X, l - 1, relaxed.get(l, frozenset()), reduce)
            if B is not None:
                B = _transfer(B, l - 1, relaxed.get(l, frozenset()), reduce)
        if l == minus_row:
            X = reduce(X - weight(B, l))
        if l == plus_row:
            X = reduce(X + weight(B, l))
            B = None
    last = relaxed.get(p, frozenset())
    total = _last_row_chain(X, p, last, reduce)
    if plus_row == p:  # r = 2: the + weight sits on the last row itself
        total += _last_row_chain(B, p, last, reduce, weight_index=k if 1 <= k < p else None)
    return total % prime


def gamma_bulk_integer(N: int, q: int, r: int) -> int:
    """The integer ``(q+1) Z'(q,r) + S1 - S0 = (d+1) Z <W_{N-q,r}>`` of Eq. (4.77), by CRT.

    Multi-modular version of :func:`gamma_sums` that never builds the last
    row of the recursion (:func:`_last_row_chain`); reaches N = 12.

    Examples
    --------
    >>> Z, S1, S0 = gamma_sums(7, 2, 3)
    >>> gamma_bulk_integer(7, 2, 3) == 3 * Z + S1 - S0
    True
    """
    from .modular import crt, primes_for_bound
    from .staircase import count

    N = check_layers(N, minimum=4)
    if not (1 <= q <= N - 2 and 2 <= r <= N - q):
        raise ValueError(f"(q, r) = ({q}, {r}): need 1 <= q <= N-2 = {N - 2} and 2 <= r <= N-q = {N - q}")
    d = N * (N - 1) // 2
    primes = primes_for_bound((d + 2) * (d + 1) * count(N))
    return crt([_gamma_combined_mod(N, q, r, prime) for prime in primes], primes)
