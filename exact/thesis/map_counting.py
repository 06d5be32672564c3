"""The maps of Sec. 4.6 (Eqs. 4.86-4.91): enumeration, the bijection with tableaux, the map route.

* :func:`maps`, :func:`is_map`, :func:`count_maps`, :func:`maps_by_bottom_row`:
  the maps ``h`` of (4.86)-(4.89), optionally with bounds raised on a defect
  line (the modified maps of (4.90), s-th order defects (4.80)-(4.85));
* :func:`map_from_tableau`, :func:`tableau_from_map`: a bijection between
  maps and standard shifted staircase tableaux (proof: ``notes/chapter4.md``);
* :func:`mean_W_thesis_maps`, :func:`moment_thesis_maps`: ``<W>`` and
  ``<W^s>`` from the thesis's map formulas (4.67), (4.90)-(4.91);
* :func:`moments_by_maps`, :func:`mean_W_by_maps`: every moment and
  correlation by averaging the Dirichlet spacings over all maps.

Enumerates maps one by one: ``Z_{N-2}`` of them (N = 8: 2.3e7).
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Iterable, Iterator
from fractions import Fraction
from functools import lru_cache

from forcenet.core.errors import ArgumentError
from forcenet.core.validation import check_grain, check_int, check_layers

from ..protocol import Progress
from ..triangle.spacings import rank_gap_moments, rising
from ..triangle.staircase import dimension
from .coefficients import defect_line, upper_bound
from .recursions import count_lambda, table_from_bulk

__all__ = ["is_map", "maps", "count_maps", "maps_by_bottom_row", "map_from_tableau", "tableau_from_map", "mean_W_thesis_maps", "moment_thesis_maps", "moments_by_maps", "mean_W_by_maps"]


def is_map(h: dict[int, tuple[int, ...]], p: int) -> bool:
    """True if ``h`` (row ``l`` -> tuple of length ``l``, ``l = 1..p``) is a map of Sec. 4.6.

    Conditions: ``h(1,1) = 1``; ``1 <= h(l,1) <= 2``; ``1 <= h(l,k) <= k + h(l,k-1)``
    (4.86); ``h(l,l) = 1`` (the ``delta`` of (4.87)); ``h(l-1,k) <= h(l,k+1)`` (4.89).

    Parameters
    ----------
    h : dict of int to tuple of int
        The candidate map, row ``l`` -> ``(h(l,1), ..., h(l,l))``.
    p : int
        Number of rows, ``p = N - 2``.

    Returns
    -------
    bool

    Examples
    --------
    >>> is_map({1: (1,), 2: (2, 1)}, 2), is_map({1: (1,), 2: (3, 1)}, 2)
    (True, False)
    """
    for l in range(1, p + 1):
        row = h.get(l)
        if row is None or len(row) != l:
            return False
        if any(not 1 <= row[k] <= upper_bound(k + 1, row[k - 1] if k else None) for k in range(l)):
            return False
        if row[-1] != 1:  # also h(1,1) = 1
            return False
        if l >= 2 and any(h[l - 1][k] > row[k + 1] for k in range(l - 1)):
            return False
    return True

def maps(N: int, relaxed: dict | None = None) -> Iterator[dict[int, tuple[int, ...]]]:
    """Generate all maps ``h`` for ``p = N - 2`` (rows ``l = 1..p``).

    ``relaxed`` maps a row ``l`` to a set of positions ``k`` whose upper bound
    in (4.86) is raised by one (the modified maps ``h(q, r)`` of Eq. (4.90)),
    or to a dict ``{k: amount}`` (s-th order defects, Eqs. (4.80)-(4.85)).

    Parameters
    ----------
    N : int
        Number of layers, ``N >= 3``.
    relaxed : dict, optional
        Row ``l`` -> set of positions, or ``{position: amount}``, whose
        bounds (4.86) are raised.

    Returns
    -------
    iterator of dict of int to tuple of int
        Each map as row ``l`` -> ``(h(l,1), ..., h(l,l))``.

    Raises
    ------
    ArgumentError
        If ``N`` is not an integer ``>= 3``.

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

    def extend(h: dict[int, tuple[int, ...]], l: int) -> Iterator[dict[int, tuple[int, ...]]]:
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
    raised = dict(raise_by)

    def extend(prefix: tuple[int, ...]) -> Iterator[tuple[int, ...]]:
        k = len(prefix) + 1
        if k > l:
            yield prefix
            return
        top = upper_bound(k, prefix[-1] if prefix else None, raised.get(k, 0))
        for v in range(1, top + 1):
            yield from extend(prefix + (v,))

    return [row for row in extend(()) if row[-1] == 1]  # h(l,l) = 1 (4.87), also h(1,1) = 1

def _entry(h: dict[int, tuple[int, ...]], l: int, k: int) -> int:
    """``h(l, k)`` with the conventions ``h(l, 0) = h(0, k) = 1`` of (4.67) and (4.91)."""
    return 1 if (l == 0 or k == 0) else h[l][k - 1]

def mean_W_thesis_maps(N: int, progress: Progress | None = None) -> list[list[Fraction]]:
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
    >>> [str(x) for x in mean_W_thesis_maps(5)[-1]]
    ['1/11', '1/4', '7/22', '1/4', '1/11']
    """
    N = check_layers(N)

    def bulk(q: int, r: int) -> int:
        line = defect_line(N, q, r)
        value = sum(q + 1 + _entry(h, N - r, q - 1) - _entry(h, N - r - 1, q - 1) for h in maps(N, line))
        if progress is not None:
            progress()
        return value

    return table_from_bulk(N, bulk)

def moment_thesis_maps(N: int, grain: tuple[int, int], s: int) -> Fraction:
    """``<W_{i,j}^s>`` from map counting with s-th order defects, ``i <= N - 1``.

    Reconstructed (4.80)-(4.85) in map form: with ``q = N - i``, ``r = j >= 2``,

        (d+1)...(d+s) Z <W^s> = sum over maps with bounds raised by ``s`` on the
        line ``(N-r+t, q+t)``, ``0 <= t <= r-2``, of
        (q + s + h(N-r, q-1) - h(N-r-1, q-1)) (...) (q + 1 + h(N-r, q-1) - h(N-r-1, q-1)),

    the falling product of (4.82); on the left boundary ``r = 1`` the rank
    ``T = q(q+1)/2 + 2 - h(N-2, q-1)`` of (4.67) gives
    ``<W^s> = E[T (T+1) ... (T+s-1)] / ((d+1) ... (d+s))``.  The bottom layer
    needs two-grain moments and is not covered (use :func:`exact.moment`).

    Parameters
    ----------
    N : int
        Number of layers, ``N >= 3``.
    grain : tuple of int
        ``(i, j)`` with ``1 <= j <= i <= N - 1``.
    s : int
        Order of the moment, ``s >= 1``.

    Returns
    -------
    Fraction

    Raises
    ------
    ArgumentError
        If ``N``, ``grain`` or ``s`` is out of range (the bottom layer ``i = N``
        included).

    Examples
    --------
    >>> moment_thesis_maps(5, (4, 2), 2)
    Fraction(4, 33)
    """
    N = check_layers(N, minimum=3)
    i, j = check_grain(N, grain)
    if i == N:
        raise ArgumentError(f"grain={grain!r} is out of range: the map formulas need 1 <= i <= N-1={N - 1} "
                         "(the bottom layer needs two-grain moments: use forcenet.exact.moment)")
    s = check_int(s, "s", 1)
    d, p, q, r = dimension(N), N - 2, N - i, j
    Z = count_lambda(N)
    if q == N - 1:  # W_{1,1} = 1
        return Fraction(1)
    if r == 1:
        total = 0
        for h in maps(N):
            T = q * (q + 1) // 2 + 2 - (1 if q == 1 else h[p][q - 2])
            total += rising(T, s)
        return Fraction(total, Z * rising(d + 1, s))
    total = 0
    for h in maps(N, defect_line(N, q, r, s)):
        top = q + s + _entry(h, N - r, q - 1) - _entry(h, N - r - 1, q - 1)
        total += rising(top - s + 1, s)  # the falling product top (top-1) ... (top-s+1)
    return Fraction(total, Z * rising(d + 1, s))

def count_maps(N: int) -> int:
    """``Z_{N-2}``: the number of maps (Sec. 4.6, Eqs. 4.86-4.89), by enumeration.

    Parameters
    ----------
    N : int
        Number of layers, ``N >= 3``.

    Returns
    -------
    int
        Equal to :func:`forcenet.exact.count`.

    Examples
    --------
    >>> count_maps(6)
    286
    """
    return sum(1 for _ in maps(N))

def maps_by_bottom_row(N: int) -> Counter:
    """Number of maps for each value of the last row ``h(N-2, .)`` (= ``Lambda^(N-2)``, Eq. 4.88).

    Parameters
    ----------
    N : int
        Number of layers, ``N >= 3``.

    Returns
    -------
    collections.Counter
        Last row (a tuple) -> number of maps.

    Raises
    ------
    ArgumentError
        If ``N`` is not an integer ``>= 3``.

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

    Parameters
    ----------
    N : int
        Number of layers, ``N >= 3``.
    T : dict of (int, int) to int
        The tableau, cell ``(r, c)`` -> entry.

    Returns
    -------
    dict of int to tuple of int
        The map, row ``l`` -> ``(h(l,1), ..., h(l,l))``.

    Raises
    ------
    ArgumentError
        If ``N`` is not an integer ``>= 3``.

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
    """Inverse of :func:`map_from_tableau`: the tableau of a map of Eqs. (4.86)-(4.89).

    Builds the order of the cells row by row from the bottom of the
    staircase: ``(r, r)`` and ``(r, r+1)`` precede every cell below them;
    ``(r, c)``, ``c >= r + 2``, precedes every cell of the rows below in
    columns ``>= c`` and exactly ``h(l, k) - 1`` of those in columns ``< c``
    (``l = N - 1 - r``, ``k = c - r - 1``).

    Parameters
    ----------
    N : int
        Number of layers, ``N >= 3``.
    h : dict of int to tuple of int
        The map, row ``l`` -> ``(h(l,1), ..., h(l,l))``.

    Returns
    -------
    dict of (int, int) to int
        The tableau, cell ``(r, c)`` -> entry ``1..d``.

    Raises
    ------
    ArgumentError
        If ``N`` is not an integer ``>= 3`` or ``h`` is not a map.

    Examples
    --------
    >>> tableau_from_map(4, {1: (1,), 2: (2, 1)})[(2, 2)]
    4
    """
    N = check_layers(N, minimum=3)
    if not is_map(h, N - 2):
        raise ArgumentError(f"h={h!r} is not a map of Sec. 4.6 for N={N} (Eqs. 4.86-4.89)")
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
                raise ArgumentError(f"h is not a map: row {l} entry {c - r - 1} cannot be placed")
            merged.insert(pos, (r, c))
        order = merged
    return {cell: k + 1 for k, cell in enumerate(order)}

def _map_rankings(N: int) -> Iterator[dict[tuple[int, int], int]]:
    """Ranks of the partial sums ``S_{i,j}`` for every map, through its tableau.

    Tableau cell ``(r, c)`` holds the rank of ``S_{N-c+r, r}``.
    """
    if N == 2:  # no map rows: the one-cell staircase
        yield {(2, 1): 1}
        return
    for h in maps(N):
        T = tableau_from_map(N, h)
        yield {(N - c + r, r): t for (r, c), t in T.items()}

def moments_by_maps(
    N: int, s_max: int = 1, pairs: Iterable[tuple[tuple[int, int], tuple[int, int]]] = ()
) -> tuple[int, dict[int, dict[tuple[int, int], Fraction]], dict[tuple[tuple[int, int], tuple[int, int]], Fraction]]:
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

    Raises
    ------
    ArgumentError
        If ``N``, ``s_max`` or a grain of ``pairs`` is out of range.

    Examples
    --------
    >>> Z, mom, cor = moments_by_maps(4, s_max=2, pairs=[((4, 1), (4, 4))])
    >>> Z, mom[2][(4, 1)], cor[((4, 1), (4, 4))]
    (2, Fraction(1, 28), Fraction(1, 56))
    """
    N = check_layers(N)
    s_max = check_int(s_max, "s_max", 1)
    pairs = [(check_grain(N, a, "pairs"), check_grain(N, b, "pairs")) for a, b in pairs]
    return rank_gap_moments(N, _map_rankings(N), s_max, pairs)

def mean_W_by_maps(N: int) -> list[list[Fraction]]:
    """``<W>`` table as an average over all maps (Sec. 4.6), through the bijection.

    Each map is turned into its tableau (:func:`tableau_from_map`) and the
    grain's gap of ranks averaged: ``<W_ij> = E[T(j, N-i+j) - T(j-1, N-i+j-1)] / (d+1)``.
    Enumerates ``Z_{N-2}`` maps, so meant for ``N <= 7``.

    Parameters
    ----------
    N : int
        Number of layers, ``N >= 2``.

    Returns
    -------
    list of lists of Fraction
        ``table[i-1][j-1] = <W_{i,j}>``.

    Examples
    --------
    >>> [str(x) for x in mean_W_by_maps(5)[-1]]
    ['1/11', '1/4', '7/22', '1/4', '1/11']
    """
    _, moments, _ = moments_by_maps(N, 1)
    return [[moments[1][(i, j)] for j in range(1, i + 1)] for i in range(1, N + 1)]
