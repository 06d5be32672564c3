"""The thesis's contact geometries as contact networks (:mod:`.model`), with exact data.

* :func:`triangle` -- the fully mobilized triangle of chapter 4 (Sec. 4.2):
  ``N`` layers, grain ``(i, j)`` resting on ``(i+1, j)`` and ``(i+1, j+1)``
  along normals at 60 degrees, an overload 1 on the top grain, the bottom
  layer on the floor, each layer pushed by the left wall with a prescribed
  ``p_h`` and held by a right-wall contact.  With ``p_h >= 2/sqrt(3)`` no
  lateral force can vanish (the lateral force of Eq. (3.2) is
  ``p_h + (2/sqrt 3) sum_k (q W)_{i,k} - (q W)_{i-1,k}``, which stays
  within ``2/sqrt 3`` of ``p_h``), so the polytope is the triangle's order
  polytope in the loads ``W`` (Eq. 4.3) and its means are ``forcenet.table``'s.
* :func:`hexagonal_packing` -- the N x P packing of Secs. 3.2-3.3 (top
  pressure ``p_v``, overload ``F``, lateral pressure ``p_h``, grain weight ``g``).

Every grain index is ``grain_index[(i, j)]`` of the returned network's
geometry (``Geometry.grain``).

Examples
--------
>>> geo = triangle(3)
>>> geo.network.grains, len(geo.network.contacts), geo.network.exact
(6, 15, True)
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import sympy

from forcenet.core.validation import check_int

from .model import ContactNetwork, contact_network, exact_number

__all__ = ["Geometry", "triangle", "hexagonal_packing", "rectangular_packing", "snooker", "SQRT3"]

SQRT3 = sympy.sqrt(3)
_DOWN_LEFT = (-sympy.Rational(1, 2), -SQRT3 / 2)  # the unit normal from (i, j) to (i+1, j), Fig. 3.1
_DOWN_RIGHT = (sympy.Rational(1, 2), -SQRT3 / 2)  # from (i, j) to (i+1, j+1)


@dataclass(frozen=True)
class Geometry:
    """A thesis geometry: the network and the names of its grains and contacts.

    Attributes
    ----------
    network : ContactNetwork
    grain : dict
        ``(i, j) -> grain number``.
    contact : dict
        ``(kind, i, j) -> contact number``; kinds ``"left"``, ``"right"`` (down to ``(i+1, j)`` and
        ``(i+1, j+1)``), ``"side"`` (to ``(i, j+1)``), ``"wall"`` (the right wall), ``"floor"``.
    """

    network: ContactNetwork
    grain: dict[tuple[int, int], int]
    contact: dict[tuple[str, int, int], int]


def triangle(N: Any, p_h: Any = "sqrt(3)") -> Geometry:
    """The fully mobilized triangle of ``N`` layers (chapter 4) as a contact network.

    Parameters
    ----------
    N : int
        Layers, ``>= 2``.
    p_h : number, optional
        The left wall's prescribed push on every layer (default ``sqrt(3)``, above the ``2/sqrt(3)`` that
        keeps every lateral force positive: the fully mobilized case).

    Returns
    -------
    Geometry
        The vertical load of grain ``(i, j)`` is ``W_ij = (sqrt(3)/2)(f_left + f_right)`` for ``i < N``, the floor
        force for ``i = N`` (Eqs. (3.2), (4.5)).

    Examples
    --------
    >>> geo = triangle(2)
    >>> sorted(geo.contact)
    [('floor', 2, 1), ('floor', 2, 2), ('left', 1, 1), ('right', 1, 1), ('side', 2, 1), ('wall', 1, 1), ('wall', 2, 2)]
    """
    N = check_int(N, "N", 2)
    push = exact_number(p_h, "p_h")
    grain: dict[tuple[int, int], int] = {}
    for i in range(1, N + 1):
        for j in range(1, i + 1):
            grain[(i, j)] = len(grain)
    contacts: list[list[Any]] = []
    contact: dict[tuple[str, int, int], int] = {}

    def add(kind: str, i: int, j: int, other: int | None, normal: tuple[Any, Any]) -> None:
        contact[(kind, i, j)] = len(contacts)
        contacts.append([grain[(i, j)], other, *normal])

    loads: list[list[Any]] = [[grain[(1, 1)], 0, -1]]  # the overload W_11 = 1
    for i in range(1, N + 1):
        for j in range(1, i + 1):
            if i < N:
                add("left", i, j, grain[(i + 1, j)], _DOWN_LEFT)
                add("right", i, j, grain[(i + 1, j + 1)], _DOWN_RIGHT)
            else:
                add("floor", i, j, None, (0, -1))
            if j < i:
                add("side", i, j, grain[(i, j + 1)], (1, 0))
        add("wall", i, i, None, (1, 0))
        loads.append([grain[(i, 1)], push, 0])
    return Geometry(contact_network(len(grain), contacts, loads), grain, contact)


def hexagonal_packing(N: Any, P: Any, *, F: Any = 1, j0: Any = None, p_v: Any = 0, p_h: Any = "sqrt(3)",
                      g: Any = 0) -> Geometry:
    """The N x P hexagonal packing of Secs. 3.2-3.3 (Fig. 3.1) as a contact network.

    ``N`` layers of ``P`` grains; grain ``(i, j)`` rests on ``(i+1, j)`` (left) and ``(i+1, j+1)`` (right); the
    right column has no lower-right neighbour; the top layer carries ``p_v`` per grain and the overload ``F``
    on ``(1, j0)``; every grain weighs ``g``; the left wall pushes every layer with ``p_h`` (a load), the right
    wall holds it (a contact); the floor carries the bottom layer (vertical contacts). The ``j``-th grain of
    layer ``i`` sits at ``x = j - 1 + (i - 1)/2`` in this reading of the thesis's indices (3.4), (3.9).

    Examples
    --------
    >>> geo = hexagonal_packing(2, 3)
    >>> geo.network.grains, len(geo.network.contacts)
    (6, 14)
    """
    N = check_int(N, "N", 2)
    P = check_int(P, "P", 2)
    j0 = (P + 1) // 2 if j0 is None else check_int(j0, "j0", 1, P)
    push, top, weight, overload = (exact_number(v, name) for v, name in ((p_h, "p_h"), (p_v, "p_v"), (g, "g"),
                                                                          (F, "F")))
    grain = {(i, j): (i - 1) * P + (j - 1) for i in range(1, N + 1) for j in range(1, P + 1)}
    contacts: list[list[Any]] = []
    contact: dict[tuple[str, int, int], int] = {}

    def add(kind: str, i: int, j: int, other: int | None, normal: tuple[Any, Any]) -> None:
        contact[(kind, i, j)] = len(contacts)
        contacts.append([grain[(i, j)], other, *normal])

    loads: list[list[Any]] = []
    for i in range(1, N + 1):
        for j in range(1, P + 1):
            fy = -weight - (top + (overload if j == j0 else 0) if i == 1 else 0)
            loads.append([grain[(i, j)], push if j == 1 else 0, fy])
            if i < N:
                add("left", i, j, grain[(i + 1, j)], _DOWN_LEFT)
                if j < P:
                    add("right", i, j, grain[(i + 1, j + 1)], _DOWN_RIGHT)
            else:
                add("floor", i, j, None, (0, -1))
            if j < P:
                add("side", i, j, grain[(i, j + 1)], (1, 0))
        add("wall", i, P, None, (1, 0))
    return Geometry(contact_network(N * P, contacts, loads), grain, contact)



def rectangular_packing(N: Any, P: Any, *, friction: Any = "1/2", F: Any = 1, j0: Any = None, p_v: Any = 0,
                        p_h: Any = 1, g: Any = 0) -> Geometry:
    """The rectangular packing of frictional grains of chapter 5 as a contact network.

    ``N`` rows of ``P`` grains of radius 1/2 on a square lattice: grain ``(i, j)`` touches ``(i+1, j)`` below
    (``"down"``) and ``(i, j+1)`` on its right (``"side"``); the floor carries row ``N`` (``"floor"``), the right
    wall holds every row (``"wall"``), the left wall pushes it with ``p_h`` (a load). Every contact has a normal
    and a tangential force with ``|t| <= mu f`` (Coulomb) and every grain balances force and torque (Sec. 5.1).
    Loads: ``p_v`` on every top grain, the overload ``F`` on ``(1, j0)``, the weight ``g`` of every grain.

    Examples
    --------
    >>> geo = rectangular_packing(2, 2)
    >>> geo.network.frictional, len(geo.network.contacts)
    (True, 8)
    """
    N = check_int(N, "N", 1)
    P = check_int(P, "P", 1)
    j0 = (P + 1) // 2 if j0 is None else check_int(j0, "j0", 1, P)
    push, top, weight, overload = (exact_number(v, name) for v, name in ((p_h, "p_h"), (p_v, "p_v"), (g, "g"),
                                                                          (F, "F")))
    grain = {(i, j): (i - 1) * P + (j - 1) for i in range(1, N + 1) for j in range(1, P + 1)}
    contacts: list[list[Any]] = []
    contact: dict[tuple[str, int, int], int] = {}

    def add(kind: str, i: int, j: int, other: int | None, normal: tuple[Any, Any]) -> None:
        contact[(kind, i, j)] = len(contacts)
        contacts.append([grain[(i, j)], other, *normal])

    loads: list[list[Any]] = []
    for i in range(1, N + 1):
        for j in range(1, P + 1):
            fy = -weight - ((top + (overload if j == j0 else 0)) if i == 1 else 0)
            loads.append([grain[(i, j)], push if j == 1 else 0, fy])
            add("down" if i < N else "floor", i, j, grain[(i + 1, j)] if i < N else None, (0, -1))
            if j < P:
                add("side", i, j, grain[(i, j + 1)], (1, 0))
        add("wall", i, P, None, (1, 0))
    network = contact_network(N * P, contacts, loads, friction=friction, radii=[sympy.Rational(1, 2)] * (N * P))
    return Geometry(network, grain, contact)


def snooker(N: Any, pressure: Any = 1) -> Geometry:
    """The snooker packing of Sec. 7.2.1 (Fig. 2.7): ``N`` layers of disks in an equilateral triangle.

    Hexagonal contacts as in :func:`triangle` (``"left"``, ``"right"`` down the lattice directions, ``"side"``
    within a layer); an isotropic ``pressure`` on the three sides: on the left side it is a prescribed load
    ``pressure * (sqrt(3)/2, -1/2)`` on each grain ``(i, 1)`` (the thesis's choice of the boundary whose forces
    are known), the right side (``"rightwall"``, normal ``(sqrt(3)/2, 1/2)``) and the floor (``"floor"``) are
    walls. The polytope has the thesis's dimension ``N(N-1)/2`` (Sec. 7.3). (The thesis calls the network of
    equal forces the centre of mass of the polytope; at the corners, where a grain meets two walls, equal
    forces do not balance, so this holds in the bulk only: the exact means say how far.)

    Examples
    --------
    >>> geo = snooker(3)
    >>> geo.network.grains, len(geo.network.contacts)
    (6, 15)
    """
    N = check_int(N, "N", 2)
    p = exact_number(pressure, "pressure")
    grain: dict[tuple[int, int], int] = {}
    for i in range(1, N + 1):
        for j in range(1, i + 1):
            grain[(i, j)] = len(grain)
    contacts: list[list[Any]] = []
    contact: dict[tuple[str, int, int], int] = {}

    def add(kind: str, i: int, j: int, other: int | None, normal: tuple[Any, Any]) -> None:
        contact[(kind, i, j)] = len(contacts)
        contacts.append([grain[(i, j)], other, *normal])

    loads: list[list[Any]] = []
    for i in range(1, N + 1):
        for j in range(1, i + 1):
            if i < N:
                add("left", i, j, grain[(i + 1, j)], _DOWN_LEFT)
                add("right", i, j, grain[(i + 1, j + 1)], _DOWN_RIGHT)
            else:
                add("floor", i, j, None, (0, -1))
            if j < i:
                add("side", i, j, grain[(i, j + 1)], (1, 0))
        add("rightwall", i, i, None, (SQRT3 / 2, sympy.Rational(1, 2)))
        loads.append([grain[(i, 1)], p * SQRT3 / 2, -p / 2])
    return Geometry(contact_network(len(grain), contacts, loads), grain, contact)
