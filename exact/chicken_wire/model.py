"""The chicken-wire vertex model of Sec. 7.4.1: exact counts on small lattices.

Lattice: the triangular lattice with sites ``(x, y)``; from a site the six
bond directions are ``0`` -> ``(x+1, y)``, ``60`` -> ``(x, y+1)``,
``120`` -> ``(x-1, y+1)`` and their opposites ``180, 240, 300``.  Every site
carries one of the six vertices of Fig. 7.7 (the set of its occupied bonds):

- ``"empty"``: no bond;
- ``"Y"`` and ``"inverted Y"`` (scattering): ``{0, 120, 240}``, ``{60, 180, 300}``;
- ``"H"``, ``"R"``, ``"L"`` (a particle passing straight): ``{0, 180}``,
  ``{60, 240}``, ``{120, 300}``; read upwards, ``R`` and ``L`` are the right-
  and left-moving particles and ``H`` the horizontally moving one (the
  "photon" that exchanges their states).

Occupied bonds then cover the plane by hexagonal cells with walls along the
three lattice directions (Fig. 7.8).

Row-to-row transfer matrix (upward, width ``L``, periodic): the state of a
row is what enters each site from below, ``D_x`` in ``{0, R, L}`` (a site has
at most one lower bond).  Given ``D``, each site has two choices, linked by
the horizontal bonds (periodic):

=========  ==========================  =======================
``D_x``    left bond, right bond, out  vertex
=========  ==========================  =======================
0          0, 0, none / 1, 1, none     empty / H
R (240)    0, 0, R / 0, 1, L           R / Y ``{0,120,240}``
L (300)    0, 0, L / 1, 0, R           L / inverted Y
=========  ==========================  =======================

An ``R`` leaving ``(x, y)`` enters ``(x, y+1)``; an ``L`` enters
``(x-1, y+1)``; two particles entering one site is forbidden.  Particle
number is conserved row to row; an ``R`` turns into ``L`` by emitting a
photon to its right that the next particle, an ``L``, absorbs.

Examples
--------
>>> count_torus(3, 3)
25
>>> count_torus(3, 3) == count_torus_by_enumeration(3, 3)
True
"""

from __future__ import annotations

from collections.abc import Iterator
from functools import cache
from itertools import product
from typing import TYPE_CHECKING

import sympy

from forcenet.core.errors import ArgumentError
from forcenet.core.validation import check_int

if TYPE_CHECKING:
    import sympy

__all__ = [
    "VERTICES",
    "row_transitions",
    "transfer_matrix",
    "count_torus",
    "count_torus_by_enumeration",
    "torus_configurations",
    "BOND_STEPS",
    "vertex_counts_torus",
    "EMPTY",
    "RIGHT",
    "LEFT",
    "SITE_CHOICES",
]

# the six vertices of Fig. 7.7 as sets of occupied bond directions (degrees)
VERTICES = {
    "empty": frozenset(),
    "Y": frozenset({0, 120, 240}),
    "inverted Y": frozenset({60, 180, 300}),
    "H": frozenset({0, 180}),
    "R": frozenset({60, 240}),
    "L": frozenset({120, 300}),
}

EMPTY, RIGHT, LEFT = _E, _R, _L = 0, 1, 2  # incoming/outgoing states: none, right-moving, left-moving
# the two choices of a site per incoming state: (left bond, right bond, outgoing, vertex name)
SITE_CHOICES = _CHOICES = {
    _E: ((0, 0, _E, "empty"), (1, 1, _E, "H")),
    _R: ((0, 0, _R, "R"), (0, 1, _L, "Y")),
    _L: ((0, 0, _L, "L"), (1, 0, _R, "inverted Y")),
}


def _next_row(out: tuple) -> tuple | None:
    """Incoming states of the next row from the outgoing ones (None on a collision)."""
    n = len(out)
    nxt = [_E] * n
    for x, o in enumerate(out):
        if o == _E:
            continue
        target = x if o == _R else (x - 1) % n
        if nxt[target] != _E:
            return None
        nxt[target] = o
    return tuple(nxt)


@cache
def row_transitions(L: int) -> dict:
    """All transitions of one chicken-wire row (Sec. 7.4.1): ``{D: [(D_next, vertex counts), ...]}``.

    ``vertex counts`` is a tuple of the numbers of
    ``(empty, Y, inverted Y, H, R, L)`` vertices in the row.

    Parameters
    ----------
    L : int
        Row width (periodic), ``>= 2``.

    Returns
    -------
    dict of tuple to list of (tuple, tuple)
        For every incoming row state ``D`` (a tuple of ``EMPTY``, ``RIGHT``,
        ``LEFT`` per site), the allowed ``(D_next, vertex counts)`` pairs.

    Raises
    ------
    ArgumentError
        If ``L < 2``.
    ArgumentTypeError
        If ``L`` is not an integer.

    Examples
    --------
    >>> sorted(row_transitions(2)[(0, 0)])
    [((0, 0), (0, 0, 0, 2, 0, 0)), ((0, 0), (2, 0, 0, 0, 0, 0))]
    """
    L = check_int(L, "L", 2)
    names = list(VERTICES)
    table = {}
    for D in product((_E, _R, _L), repeat=L):
        moves = []
        for pick in product((0, 1), repeat=L):
            chosen = [_CHOICES[d][p] for d, p in zip(D, pick)]
            if any(chosen[x][1] != chosen[(x + 1) % L][0] for x in range(L)):
                continue  # a horizontal bond must be seen by both of its sites
            nxt = _next_row(tuple(c[2] for c in chosen))
            if nxt is None:
                continue
            counts = [0] * 6
            for c in chosen:
                counts[names.index(c[3])] += 1
            moves.append((nxt, tuple(counts)))
        table[D] = moves
    return table


def transfer_matrix(L: int, weights: dict[str, object] | None = None) -> sympy.Matrix:
    """The chicken-wire row-to-row transfer matrix (Sec. 7.4.1), exact sympy; states in ``product`` order.

    ``weights`` maps vertex names to sympy/int weights (default 1 each);
    entry ``[D_next, D]`` is the sum over the row's configurations of the
    product of their vertex weights.

    Parameters
    ----------
    L : int
        Row width (periodic), ``>= 2``.
    weights : dict of str to number or sympy expression, optional
        Weight per vertex name of :data:`VERTICES`; missing names weigh 1.

    Returns
    -------
    sympy.Matrix
        The ``3^L x 3^L`` matrix, entry ``[D_next, D]``.

    Raises
    ------
    ArgumentError
        If ``weights`` names an unknown vertex, or ``L < 2``.
    ArgumentTypeError
        If ``L`` is not an integer.

    Examples
    --------
    >>> transfer_matrix(2).shape
    (9, 9)
    >>> transfer_matrix(2).trace()  # torus of 2 x 1 sites (with the skew of the lattice)
    6
    """

    w: dict[str, object] = {name: 1 for name in VERTICES}
    if weights is not None:
        unknown = set(weights) - set(VERTICES)
        if unknown:
            raise ArgumentError(f"weights: unknown vertex names {sorted(unknown)}; allowed {list(VERTICES)}")
        w.update(weights)
    names = list(VERTICES)
    states = list(product((_E, _R, _L), repeat=L))
    index = {s: k for k, s in enumerate(states)}
    T = sympy.zeros(len(states), len(states))
    for D, moves in row_transitions(L).items():
        for nxt, counts in moves:
            term = sympy.Integer(1)
            for name, c in zip(names, counts):
                term *= sympy.sympify(w[name]) ** c
            T[index[nxt], index[D]] += term
    return T


def count_torus(L: int, M: int) -> int:
    """Number of chicken-wire configurations (Sec. 7.4.1, Fig. 7.8) on the ``L x M`` torus (transfer matrix, exact).

    ``Tr T^M`` with integer arithmetic on the sparse transitions.

    Parameters
    ----------
    L : int
        Width of the torus, ``>= 2``.
    M : int
        Height of the torus (rows), ``>= 1``.

    Returns
    -------
    int
        ``Tr T^M``, a Python int.

    Raises
    ------
    ArgumentError
        If ``L < 2`` or ``M < 1``.
    ArgumentTypeError
        If ``L`` or ``M`` is not an integer.

    Examples
    --------
    >>> [count_torus(2, M) for M in (1, 2, 3)]
    [6, 10, 12]
    """
    L = check_int(L, "L", 2)
    M = check_int(M, "M", 1)
    return sum(vertex_counts_torus(L, M).values())


def vertex_counts_torus(L: int, M: int) -> dict:
    """Number of chicken-wire configurations on the ``L x M`` torus by vertex content (the six vertices of Fig. 7.7).

    Returns ``{(n_empty, n_Y, n_invY, n_H, n_R, n_L): count}``; the transfer
    matrix route with polynomial bookkeeping.

    Parameters
    ----------
    L : int
        Width of the torus, ``>= 2``.
    M : int
        Height of the torus (rows), ``>= 1``.

    Returns
    -------
    dict of tuple to int
        ``{(n_empty, n_Y, n_invY, n_H, n_R, n_L): count}``.

    Raises
    ------
    ArgumentError
        If ``L < 2`` or ``M < 1``.
    ArgumentTypeError
        If ``L`` or ``M`` is not an integer.

    Examples
    --------
    >>> vertex_counts_torus(2, 1)[(2, 0, 0, 0, 0, 0)]  # the empty torus
    1
    """
    L = check_int(L, "L", 2)
    M = check_int(M, "M", 1)
    moves = row_transitions(L)
    total: dict[tuple[int, ...], int] = {}
    for start in moves:
        layer: dict[tuple[object, tuple[int, ...]], int] = {(start, (0,) * 6): 1}
        for _ in range(M):
            new: dict[tuple[object, tuple[int, ...]], int] = {}
            for (D, acc), c in layer.items():
                for nxt, counts in moves[D]:
                    key = (nxt, tuple(a + b for a, b in zip(acc, counts)))
                    new[key] = new.get(key, 0) + c
            layer = new
        for (D, acc), c in layer.items():
            if D == start:
                total[acc] = total.get(acc, 0) + c
    return total


def count_torus_by_enumeration(L: int, M: int) -> int:
    """The chicken-wire count (Sec. 7.4.1) by backtracking over vertex assignments (independent of the transfer matrix).

    Each site gets one of the six vertices; a bond is occupied for both of
    its ends or for neither.  Exponential; for ``L * M <= 20``.

    Parameters
    ----------
    L : int
        Width of the torus, ``>= 2``.
    M : int
        Height of the torus (rows), ``>= 1``.

    Returns
    -------
    int
        The number of configurations, equal to :func:`count_torus`.

    Raises
    ------
    ArgumentError
        If ``L < 2`` or ``M < 1``, or ``L * M > 20``.
    ArgumentTypeError
        If ``L`` or ``M`` is not an integer.

    Examples
    --------
    >>> count_torus_by_enumeration(2, 2)
    10
    """
    L = check_int(L, "L", 2)
    M = check_int(M, "M", 1)
    if L * M > 20:
        raise ArgumentError(f"L*M={L * M} is out of range: enumeration is for at most 20 sites")
    return sum(1 for _ in torus_configurations(L, M))


BOND_STEPS = {0: (1, 0), 60: (0, 1), 120: (-1, 1), 180: (-1, 0), 240: (0, -1), 300: (1, -1)}


def torus_configurations(L: int, M: int) -> Iterator[dict[tuple[int, int], frozenset[int]]]:
    """Every configuration of the ``L x M`` torus as ``{(x, y): frozenset of bond directions}``.

    Backtracking over the six vertices per site with bond consistency (a bond
    is occupied for both of its ends or for neither), independent of the
    transfer matrix.

    Examples
    --------
    >>> sum(1 for _ in torus_configurations(3, 3))
    25
    """
    L = check_int(L, "L", 1)
    M = check_int(M, "M", 1)
    sites = [(x, y) for y in range(M) for x in range(L)]
    vertices = list(VERTICES.values())
    assign: dict[tuple[int, int], frozenset[int]] = {}

    def consistent(site: tuple[int, int]) -> bool:
        x, y = site
        v = assign[site]
        for d, (dx, dy) in BOND_STEPS.items():
            other = ((x + dx) % L, (y + dy) % M)
            if other in assign and ((d in v) != ((d + 180) % 360 in assign[other])):
                return False
        return True

    def place(k: int) -> Iterator[dict[tuple[int, int], frozenset[int]]]:
        if k == len(sites):
            yield dict(assign)
            return
        for v in vertices:
            assign[sites[k]] = v
            if consistent(sites[k]):
                yield from place(k + 1)
            del assign[sites[k]]

    yield from place(0)
