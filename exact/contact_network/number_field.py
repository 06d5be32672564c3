"""Exact moments over the number field Q(sqrt(3)), without rescaling to rationals: Normaliz's algebraic polytopes.

The hexagonal lattice's normals ``(+-1/2, +-sqrt(3)/2)`` make the balance
equations live in ``Q(sqrt(3))``.  :func:`~.polytope.exact_polytope` removes
the ``sqrt(3)`` by rescaling equations and forces (possible for the thesis's
lattices, not for every network with these numbers).  This route keeps them:
the kernel coordinates are found by exact row reduction over the field
(sympy's ``DomainMatrix`` over ``QQ<sqrt(3)>``), the polytope is handed to
Normaliz as an algebraic polytope (its e-antic number field,
``number_field=["a^2-3", "a", "1.732+/-0.01"]``: the real root near 1.732),
and the moments follow from Normaliz's triangulation by the simplex formulas
of :func:`~.triangulation_moments.moments_by_triangulation`, every sum in the
field: a uniform point of a simplex with vertices ``v_0..v_d`` has
``E[u] = sum u(v_i) / (d+1)`` and ``E[u^2] = (sum u(v_i)^2 + (sum u(v_i))^2) /
((d+1)(d+2))`` (thesis Sec. 2.3.2's uniform measure; the simplices weighted by
Normaliz's multiplicities, divided by the product of the generators' degrees
as for rational polytopes).

What Normaliz's number field does and does not do here
(``notes/contact_networks.md``, Sec. 3c): ``Volume()`` is refused for an
algebraic polytope ("use getRenfVolume()"), ``RenfVolume()`` and
``Triangulation()`` work and return field elements as strings in ``a``.

Examples
--------
>>> from forcenet.exact.contact_network.geometries import triangle
>>> m = moments_in_number_field(triangle(3).network)
>>> [str(x) for x in m.mean[:3]]
['sqrt(3)/3', 'sqrt(3)/3', 'sqrt(3)']
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from typing import Any

import sympy
from sympy.polys.matrices import DomainMatrix
from sympy.polys.polyerrors import CoercionFailed

from forcenet.core.errors import ArgumentError

from .model import ContactNetwork
from .polytope import Balance, balance
from .triangulation_moments import Moments, normaliz_cone

__all__ = ["FIELD", "NORMALIZ_FIELD", "FieldPolytope", "field_polytope", "moments_in_number_field", "in_number_field",
           "field_facts", "number_field_seconds", "NO_DENSITY_IN_FIELD"]

# the refusal of an exact density over the field (the front door's and the engine's), followed by the fix
NO_DENSITY_IN_FIELD = ("the exact density (--density) needs data that are rational once rescaled; this network's "
                       "lie in Q(sqrt(3)) only (its moments are exact without --density): drop --density, or ")
FIELD = sympy.QQ.algebraic_field(sympy.sqrt(3))
NORMALIZ_FIELD = ["a^2-3", "a", "1.732+/-0.01"]  # e-antic: the root of a^2 - 3 near 1.732, i.e. sqrt(3)


@dataclass(frozen=True)
class FieldPolytope:
    """The ensemble's polytope with field entries: ``z = z0 + K x``, ``H x + h >= 0`` (elements of :data:`FIELD`).

    Attributes
    ----------
    z0, K, H, h : tuples of field elements
    free : tuple of int
        The forces that are the coordinates ``x``.
    labels : tuple of str
    """

    z0: tuple[Any, ...]
    K: tuple[tuple[Any, ...], ...]
    H: tuple[tuple[Any, ...], ...]
    h: tuple[Any, ...]
    free: tuple[int, ...]
    labels: tuple[str, ...]

    @property
    def dimension(self) -> int:
        """``dim Ker A``: the number of free coordinates, as :attr:`.polytope.ExactPolytope.dimension`.

        Examples
        --------
        >>> from forcenet.exact.contact_network.geometries import triangle
        >>> field_polytope(triangle(3).network).dimension
        3
        """
        return len(self.free)


@lru_cache(maxsize=4096)
def _element(value: Any) -> Any:
    """``value`` as an element of :data:`FIELD` (cached: a lattice repeats a few numbers many times)."""
    try:
        return FIELD.from_sympy(sympy.nsimplify(sympy.sympify(value)))
    except (CoercionFailed, TypeError, ValueError):
        raise ArgumentError(f"{value} is not in Q(sqrt(3)): the number-field route takes networks whose data are "
                            "rationals and sqrt(3) (the hexagonal lattice); use the default exact route or "
                            "--samples") from None


def in_number_field(bal: Balance) -> bool:
    """Whether every number of the balance equations and the Coulomb cones lies in ``Q(sqrt(3))``.

    Parameters
    ----------
    bal : Balance
        :func:`~.polytope.balance` of an exact network.

    Returns
    -------
    bool

    Examples
    --------
    >>> from forcenet.exact.contact_network.model import contact_network
    >>> in_number_field(balance(contact_network(1, [[0, None, "-1/2", "-sqrt(3)/2"], [0, None, "3/5", "-4/5"]],
    ...                                          [[0, "-1/10", -1]])))
    True
    >>> in_number_field(balance(contact_network(1, [[0, None, "-sqrt(2)/2", "-sqrt(2)/2"], [0, None, 0, -1]],
    ...                                          [[0, 0, -1]])))
    False
    """
    numbers = {v for _, _, v in bal.A} | set(bal.b) | {v for _, _, v in bal.G}
    try:
        for value in numbers:
            _element(value)
    except ArgumentError:
        return False
    return True


def field_polytope(net: ContactNetwork) -> FieldPolytope:
    """The polytope of ``net`` over ``Q(sqrt(3))`` by exact row reduction of ``[A | b]`` in the field.

    Raises
    ------
    ArgumentError
        Data outside ``Q(sqrt(3))`` (floats, other roots), or loads no forces balance.

    Examples
    --------
    >>> from forcenet.exact.contact_network.geometries import triangle
    >>> len(field_polytope(triangle(3).network).free)
    3
    """
    if not net.exact:
        raise ArgumentError("the number-field route needs exact data; this network has floats: use --samples")
    bal = balance(net)
    m = bal.variables
    rows = [[FIELD.zero] * (m + 1) for _ in range(bal.rows)]
    for r, c, v in bal.A:
        rows[r][c] = _element(v)
    for r in range(bal.rows):
        rows[r][m] = _element(bal.b[r])
    reduced, pivots = DomainMatrix(rows, (bal.rows, m + 1), FIELD).rref()
    if m in pivots:
        raise ArgumentError("the loads are not balanced: no contact forces at all balance them exactly")
    table = reduced.to_list()
    free = tuple(k for k in range(m) if k not in pivots)
    z0 = [FIELD.zero] * m
    K = [[FIELD.one if k == f else FIELD.zero for f in free] for k in range(m)]
    for row, p in zip(table, pivots):
        z0[p] = row[m]
        K[p] = [-row[f] for f in free]
    G: dict[int, list[tuple[int, Any]]] = {}
    for r, c, v in bal.G:
        G.setdefault(r, []).append((c, _element(v)))
    H, h = [], []
    for r in range(bal.inequalities):
        items = G.get(r, [])
        H.append(tuple(sum((q * K[c][i] for c, q in items), FIELD.zero) for i in range(len(free))))
        h.append(sum((q * z0[c] for c, q in items), FIELD.zero))
    return FieldPolytope(tuple(z0), tuple(tuple(row) for row in K), tuple(H), tuple(h), free, bal.labels)


def _text(element: Any) -> str:
    """A field element as Normaliz reads it: ``p*a+q``."""
    coefficients = [sympy.QQ.to_sympy(c) for c in element.to_list()]  # highest power first: [p, q] or [q]
    if not coefficients:
        return "0"
    if len(coefficients) == 1:
        return str(coefficients[0])
    p, q = coefficients
    return f"{p}*a" + (f"+{q}" if q > 0 else f"{q}" if q < 0 else "")


def _parse(text: str) -> Any:
    return FIELD.from_sympy(sympy.sympify(text.replace("^", "**"), locals={"a": sympy.sqrt(3)}))


def _field_cone(poly: FieldPolytope) -> Any:
    """Normaliz's cone of the polytope over e-antic's ``Q(sqrt(3))``, refusing an unbounded one."""
    rows = [[_text(a) for a in H] + [_text(c)] for H, c in zip(poly.H, poly.h) if any(H)]
    cone = normaliz_cone(rows, NORMALIZ_FIELD)
    if cone.RecessionRank() > 0:
        raise ArgumentError("unbounded: the forces can grow without bound (a self-stress)")
    return cone


def field_facts(poly: FieldPolytope) -> tuple[int, int, int]:
    """``(dimension, vertices, facets)`` of the polytope over ``Q(sqrt(3))`` (Normaliz), as
    :func:`~.triangulation_moments.polytope_facts` for rational ones; refuses an empty or unbounded polytope.

    Examples
    --------
    >>> from forcenet.exact.contact_network.geometries import triangle
    >>> field_facts(field_polytope(triangle(3).network))
    (3, 4, 4)
    """
    if poly.dimension == 0:
        if any(FIELD.to_sympy(c) < 0 for c in poly.h):
            raise ArgumentError("infeasible: no network of repulsive contact forces balances these loads exactly")
        return 0, 1, 0
    cone = _field_cone(poly)
    vertices = cone.VerticesOfPolyhedron()
    if not vertices:
        raise ArgumentError("infeasible: no network of repulsive contact forces balances these loads exactly")
    return int(cone.AffineDim()), len(vertices), len(cone.SupportHyperplanes())


def number_field_seconds(variables: int, vertices: int) -> float:
    """Estimated seconds of :func:`moments_in_number_field`: the row reduction over the field (``~ variables^2``)
    and the sums over the simplices in field arithmetic (``~ variables * vertices^1.7``, the simplices' count
    growing faster than the vertices'). Measured on the loaded 2-core machine (moments 2): the triangle N = 4
    (26 forces, 8 vertices) 0.17 s, N = 5 (40, 16) 0.5 s, the snooker N = 3 (15, 10) 0.04 s, N = 4 (26, 68,
    1256 simplices) 6.3 s; 2 to 90 times the rational route's time (the model: 0.27, 1.0, 0.16, 5.2 s).

    Examples
    --------
    >>> 0.1 < number_field_seconds(40, 16) < 2, 3 < number_field_seconds(26, 68) < 10
    (True, True)
    """
    return 2e-4 * variables**2 + 1.5e-4 * variables * vertices**1.7


def moments_in_number_field(net: ContactNetwork, moments: int = 2, poly: FieldPolytope | None = None) -> Moments:
    """Every force's exact ``<z>`` (and ``<z^2>``) from Normaliz's triangulation over ``Q(sqrt(3))``.

    Parameters
    ----------
    net : ContactNetwork
        Exact data in ``Q(sqrt(3))``.
    moments : int
        1 or 2.
    poly : FieldPolytope, optional
        ``field_polytope(net)`` when already made.

    Returns
    -------
    Moments
        Sympy numbers (``a + b*sqrt(3)``).

    Examples
    --------
    >>> from forcenet.exact.contact_network.geometries import triangle
    >>> m = moments_in_number_field(triangle(3).network, 1)
    >>> m.dimension, m.pieces
    (3, 1)
    """
    poly = field_polytope(net) if poly is None else poly
    d, n = len(poly.free), len(poly.z0)
    if d == 0:
        z = [FIELD.to_sympy(v) for v in poly.z0]
        return Moments(tuple(z), tuple(sympy.expand(v * v) for v in z) if moments >= 2 else (), 0, 1)
    cone = _field_cone(poly)
    simplices, generators = cone.Triangulation()
    dimension = int(cone.AffineDim())
    points = []
    for g in generators:
        degree = _parse(g[-1])
        points.append(([_parse(x) / degree for x in g[:-1]], degree))
    values = [[poly.z0[k] + sum((a * x for a, x in zip(poly.K[k], coords)), FIELD.zero) for k in range(n)]
              for coords, _ in points]
    first, second, total = [FIELD.zero] * n, [FIELD.zero] * n, FIELD.zero
    for key, multiplicity, *_ in simplices:
        weight = _parse(multiplicity)
        for v in key:
            weight = weight / points[v][1]
        total += weight
        for k in range(n):
            s = sum((values[v][k] for v in key), FIELD.zero)
            first[k] += weight * s
            if moments >= 2:
                second[k] += weight * (sum((values[v][k] ** 2 for v in key), FIELD.zero) + s * s)
    mean = tuple(sympy.radsimp(FIELD.to_sympy(first[k] / (total * (dimension + 1)))) for k in range(n))
    seconds = tuple(sympy.radsimp(FIELD.to_sympy(second[k] / (total * (dimension + 1) * (dimension + 2))))
                    for k in range(n)) if moments >= 2 else ()
    return Moments(mean, seconds, dimension, len(simplices))
