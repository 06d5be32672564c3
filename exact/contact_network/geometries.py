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
* :func:`rectangular_packing` -- chapter 5's packing of frictional grains (Figs. 5.1-5.2): every grain on two
  grains below at the angle ``alpha``, periodic sideways, pressure ``p`` and overload ``F`` on the top layer
  (:func:`square_packing`: a square lattice with walls, a small frictional test network, not the thesis's).
* :func:`hexagonal_torus` -- the periodic hexagonal packing of Sec. 8.2 (no
  loads: the macroscopic stress is imposed by :mod:`.shear_stress`).

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

from forcenet.core.errors import ArgumentError, ArgumentTypeError
from forcenet.core.validation import check_int

from .model import ContactNetwork, contact_network, exact_number

__all__ = ["Geometry", "triangle", "hexagonal_packing", "rectangular_packing", "snooker", "SQRT3", "hexagonal_torus",
           "TORUS_DIRECTIONS", "square_packing", "contact_angle"]

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


class _Builder:
    """The lists :func:`contact_network` takes, with names: grains ``(i, j)`` numbered in order, contacts
    ``(kind, i, j)``, loads."""

    def __init__(self, cells: list[tuple[int, int]]) -> None:
        self.grain = {cell: k for k, cell in enumerate(cells)}
        self.contacts: list[list[Any]] = []
        self.contact: dict[tuple[str, int, int], int] = {}
        self.loads: list[list[Any]] = []

    def add(self, kind: str, i: int, j: int, other: tuple[int, int] | None, normal: tuple[Any, Any]) -> None:
        """The contact of grain ``(i, j)`` with grain ``other`` (None: a wall) along ``normal``."""
        self.contact[(kind, i, j)] = len(self.contacts)
        self.contacts.append([self.grain[(i, j)], None if other is None else self.grain[other], *normal])

    def geometry(self, **options: Any) -> Geometry:
        """The network made of the lists, with the names."""
        network = contact_network(len(self.grain), self.contacts, self.loads, **options)
        return Geometry(network, self.grain, self.contact)


def _triangle_of_disks(N: int, wall: str, wall_normal: tuple[Any, Any]) -> _Builder:
    """``N`` layers of disks in a triangle, hexagonal contacts (Fig. 2.7): down the two lattice directions, within
    a layer, the floor under layer ``N`` and the right-hand ``wall`` of every layer; no loads yet."""
    b = _Builder([(i, j) for i in range(1, N + 1) for j in range(1, i + 1)])
    for i in range(1, N + 1):
        for j in range(1, i + 1):
            if i < N:
                b.add("left", i, j, (i + 1, j), _DOWN_LEFT)
                b.add("right", i, j, (i + 1, j + 1), _DOWN_RIGHT)
            else:
                b.add("floor", i, j, None, (0, -1))
            if j < i:
                b.add("side", i, j, (i, j + 1), (1, 0))
        b.add(wall, i, i, None, wall_normal)
    return b


def _rows_of_grains(N: Any, P: Any, j0: Any, loads: tuple[Any, Any, Any, Any]) -> tuple[int, int, _Builder]:
    """``N`` rows of ``P`` grains and their loads ``(p_h, p_v, g, F)``: a push on the left column, a load on the
    top row, the weight of every grain, the overload on ``(1, j0)``; no contacts yet."""
    N = check_int(N, "N", 1)
    P = check_int(P, "P", 1)
    j0 = (P + 1) // 2 if j0 is None else check_int(j0, "j0", 1, P)
    push, top, weight, overload = (exact_number(v, name) for v, name in zip(loads, ("p_h", "p_v", "g", "F")))
    b = _Builder([(i, j) for i in range(1, N + 1) for j in range(1, P + 1)])
    for i in range(1, N + 1):
        for j in range(1, P + 1):
            fy = -weight - ((top + (overload if j == j0 else 0)) if i == 1 else 0)
            b.loads.append([b.grain[(i, j)], push if j == 1 else 0, fy])
    return N, P, b


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
    b = _triangle_of_disks(N, "wall", (1, 0))
    b.loads.append([b.grain[(1, 1)], 0, -1])  # the overload W_11 = 1
    b.loads += [[b.grain[(i, 1)], push, 0] for i in range(1, N + 1)]
    return b.geometry()


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
    check_int(N, "N", 2)
    check_int(P, "P", 2)
    N, P, b = _rows_of_grains(N, P, j0, (p_h, p_v, g, F))
    for i in range(1, N + 1):
        for j in range(1, P + 1):
            if i < N:
                b.add("left", i, j, (i + 1, j), _DOWN_LEFT)
                if j < P:
                    b.add("right", i, j, (i + 1, j + 1), _DOWN_RIGHT)
            else:
                b.add("floor", i, j, None, (0, -1))
            if j < P:
                b.add("side", i, j, (i, j + 1), (1, 0))
        b.add("wall", i, P, None, (1, 0))
    return b.geometry()



def square_packing(N: Any, P: Any, *, friction: Any = "1/2", F: Any = 1, j0: Any = None, p_v: Any = 0,
                   p_h: Any = 1, g: Any = 0) -> Geometry:
    """A small frictional test network: ``N`` rows of ``P`` grains on a square lattice (not a thesis geometry).

    Grains of radius 1/2; grain ``(i, j)`` touches ``(i+1, j)`` below (``"down"``) and ``(i, j+1)`` on its right
    (``"side"``); the floor carries row ``N`` (``"floor"``), the right wall holds every row (``"wall"``), the left
    wall pushes it with ``p_h`` (a load). Every contact has a normal and a tangential force with ``|t| <= mu f``
    (Coulomb) and every grain balances force and torque (the frictional ensemble of Sec. 5.1 on another lattice;
    chapter 5's own packing is :func:`rectangular_packing`). Loads: ``p_v`` on every top grain, the overload ``F``
    on ``(1, j0)``, the weight ``g`` of every grain. Its walls and vertical contacts give a small polytope with
    tangential forces of both signs (the density tests and the local sampler's refusal use it).

    Examples
    --------
    >>> geo = square_packing(2, 2)
    >>> geo.network.frictional, len(geo.network.contacts)
    (True, 8)
    """
    N, P, b = _rows_of_grains(N, P, j0, (p_h, p_v, g, F))
    for i in range(1, N + 1):
        for j in range(1, P + 1):
            b.add("down" if i < N else "floor", i, j, (i + 1, j) if i < N else None, (0, -1))
            if j < P:
                b.add("side", i, j, (i, j + 1), (1, 0))
        b.add("wall", i, P, None, (1, 0))
    return b.geometry(friction=friction, radii=[sympy.Rational(1, 2)] * (N * P))


def contact_angle(cosine: Any) -> tuple[Any, Any]:
    """``(cos alpha, sin alpha)`` of chapter 5's contact angle, exact, from its cosine (Fig. 5.1: ``alpha``
    between 30 and 60 degrees, i.e. ``1/2 <= cos alpha <= sqrt(3)/2``).

    Parameters
    ----------
    cosine : int, Fraction, str or sympy number
        ``cos alpha`` exactly: ``"3/5"`` (then ``sin alpha = 4/5``), ``"1/2"`` (``sqrt(3)/2``), ``"sqrt(2)/2"``.

    Returns
    -------
    (sympy number, sympy number)

    Raises
    ------
    ArgumentTypeError
        A float (the lattice's numbers would not be exact).
    ArgumentError
        A cosine outside ``[1/2, sqrt(3)/2]``.

    Examples
    --------
    >>> contact_angle("3/5"), contact_angle("1/2")
    ((3/5, 4/5), (1/2, sqrt(3)/2))
    >>> contact_angle("9/10")
    Traceback (most recent call last):
    ...
    forcenet.core.errors.ArgumentError: angle='9/10' is out of range: the cosine of the contact angle must lie in [1/2, sqrt(3)/2] (alpha between 30 and 60 degrees, Fig. 5.1), e.g. '3/5'
    """
    if isinstance(cosine, float):
        raise ArgumentTypeError(f"angle={cosine!r} is a float: give the cosine of the contact angle exactly, e.g. "
                                "'3/5' (sin 4/5) or 'sqrt(2)/2'")
    c = exact_number(cosine, "angle")
    if not bool(sympy.Rational(1, 2) <= c) or not bool(c <= SQRT3 / 2):
        raise ArgumentError(f"angle={cosine!r} is out of range: the cosine of the contact angle must lie in "
                            "[1/2, sqrt(3)/2] (alpha between 30 and 60 degrees, Fig. 5.1), e.g. '3/5'",
                            argument="angle")
    return c, sympy.sqrt(1 - c * c)


def rectangular_packing(N: Any, P: Any, *, friction: Any = "1/2", F: Any = 3, j0: Any = None, p: Any = 1,
                        angle: Any = "3/5") -> Geometry:
    """Chapter 5's rectangular packing of frictional grains (Figs. 5.1-5.2) as a contact network.

    ``N`` layers of ``P`` grains of radius 1/2; grain ``(i, j)`` rests on ``(i+1, j)`` (``"left"``, normal
    ``(-cos alpha, -sin alpha)``) and ``(i+1, j+1)`` (``"right"``, ``(cos alpha, -sin alpha)``): four contacts
    per grain, two below and two above, as in the action-reaction identities (5.3)
    (``N1(i, j) = N4(i-1, j-1)``, ``N2(i, j) = N3(i-1, j)``). Sideways the packing is periodic (``j`` modulo
    ``P``); the bottom layer rests on fixed supports along the same two directions (its ``"left"`` and
    ``"right"`` contacts are wall contacts), so that every grain has four contacts and the polytope has one
    dimension per grain (Sec. 5.2.1: the vector ``T4`` of ``N P`` components); ``notes/contact_networks.md``,
    Sec. 4d, on this reading. Every contact has a normal and a tangential force with ``|t| <= mu f`` (Eq. (5.4))
    and every grain balances force and torque (Eq. (5.2)). Loads: the pressure ``p`` on every top grain and the
    overload ``F`` on ``(1, j0)`` (Fig. 5.1). The vertical force grain ``(i, j)`` passes down is Eq. (5.1),
    ``W = sin alpha (N_L + N_R) + cos alpha (T_L - T_R)``, its two down contacts' normal and tangential forces.

    Parameters
    ----------
    N : int
        Layers, ``>= 1``.
    P : int
        Grains per layer (periodic), ``>= 2``.
    friction : number, optional
        ``mu`` (default ``1/2``; 0: frictionless, the forces fixed by balance, Sec. 5.1).
    F : number, optional
        The overload on the top grain ``j0`` (default 3, the thesis's smallest, Fig. 5.3).
    j0 : int, optional
        Its column, ``1 .. P`` (default the middle one).
    p : number, optional
        The confining pressure on every top grain (default 1, Fig. 5.1).
    angle : number, optional
        ``cos alpha``, exact, in ``[1/2, sqrt(3)/2]`` (default ``3/5``: ``sin alpha = 4/5``, every number
        rational; the thesis: the angle "does not influence the results").

    Returns
    -------
    Geometry
        Contacts named ``("left", i, j)`` and ``("right", i, j)`` for every grain.

    Examples
    --------
    >>> geo = rectangular_packing(2, 3)
    >>> geo.network.frictional, geo.network.grains, len(geo.network.contacts)
    (True, 6, 12)
    >>> geo.network.contacts[geo.contact[("right", 1, 3)]]  # periodic: (1, 3) rests on (2, 1)
    (2, 3, 3/5, -4/5)
    """
    c, s = contact_angle(angle)
    check_int(P, "P", 2)
    N, P, b = _rows_of_grains(N, P, j0, (0, exact_number(p, "p"), 0, F))  # named p in a refusal
    for i in range(1, N + 1):
        for j in range(1, P + 1):
            below = i < N  # the last layer rests on the fixed supports (wall contacts)
            b.add("left", i, j, (i + 1, j) if below else None, (-c, -s))
            b.add("right", i, j, (i + 1, j % P + 1) if below else None, (c, -s))
    return b.geometry(friction=friction, radii=[sympy.Rational(1, 2)] * (N * P))


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
    b = _triangle_of_disks(N, "rightwall", (SQRT3 / 2, sympy.Rational(1, 2)))
    b.loads += [[b.grain[(i, 1)], p * SQRT3 / 2, -p / 2] for i in range(1, N + 1)]
    return b.geometry()


TORUS_DIRECTIONS = ((sympy.Integer(1), sympy.Integer(0)), (sympy.Rational(1, 2), SQRT3 / 2),
                    (-sympy.Rational(1, 2), SQRT3 / 2))
"""The three bond directions of the hexagonal torus: ``"side"``, ``"up"``, ``"upleft"`` (contact ``3 g + k``)."""


def hexagonal_torus(L: Any) -> Geometry:
    """The periodic hexagonal packing of Sec. 8.2: ``L x L`` monodisperse disks of diameter 1 on a torus.

    Grain ``(i, j)`` (``1 <= i, j <= L``) sits at ``(i + j/2, j sqrt(3)/2)`` and touches ``(i+1, j)``
    (``"side"``, normal ``(1, 0)``), ``(i, j+1)`` (``"up"``, ``(1/2, sqrt(3)/2)``) and ``(i-1, j+1)``
    (``"upleft"``, ``(-1/2, sqrt(3)/2)``), indices modulo ``L``: six contacts per grain, ``3 L^2`` in all,
    contact ``3 g + k`` the ``k``-th kind of grain ``g`` (:data:`TORUS_DIRECTIONS`). No loads and no walls: on its
    own the polytope is a cone (self-stresses); the macroscopic stress of Eq. (8.1), imposed by
    :func:`forcenet.exact.contact_network.shear_stress.sheared_balance`, bounds it.

    Parameters
    ----------
    L : int
        Grains per period, ``>= 3`` (with ``L = 2`` two grains would touch twice).

    Returns
    -------
    Geometry

    Examples
    --------
    >>> geo = hexagonal_torus(3)
    >>> geo.network.grains, len(geo.network.contacts), geo.contact[("upleft", 1, 1)]
    (9, 27, 2)
    """
    L = check_int(L, "L", 3)
    b = _Builder([(i, j) for j in range(1, L + 1) for i in range(1, L + 1)])
    for j in range(1, L + 1):
        for i in range(1, L + 1):
            right, up, left = i % L + 1, j % L + 1, (i - 2) % L + 1  # the torus' indices
            for kind, other, normal in zip(("side", "up", "upleft"), ((right, j), (i, up), (left, up)),
                                           TORUS_DIRECTIONS):
                b.add(kind, i, j, other, normal)
    positions = [(i + sympy.Rational(j, 2), j * SQRT3 / 2) for j in range(1, L + 1) for i in range(1, L + 1)]
    return b.geometry(positions=positions)
