"""Exact means and second moments of every force over the ensemble's polytope, through Normaliz.

Two exact routes over :class:`~.polytope.ExactPolytope` (kernel coordinates
``x``, inequalities ``H x + h >= 0``), both on Normaliz (Bruns, Ichim,
Soeger et al., https://www.normaliz.uni-osnabrueck.de; the ``PyNormaliz``
package):

* :func:`moments_by_triangulation` -- Normaliz triangulates the polytope
  (its vertices as generators); a uniform point of a simplex with vertices
  ``v_0..v_d`` has ``E[x] = (sum v_i)/(d+1)`` and
  ``E[x x^T] = (sum v_i v_i^T + (sum v_i)(sum v_i)^T)/((d+1)(d+2))``, and the
  polytope's moments are the simplices' weighted by their volumes (Normaliz's
  multiplicities, all in one lattice).  Every force is affine in ``x``, so its
  moments follow.  The cost grows with the number of simplices.
* :func:`moments_by_volumes` -- for a force ``u(x) >= 0``:
  ``int_P u = vol{(x, t): x in P, 0 <= t <= u(x)}`` and
  ``int_P u^2 = 2 vol{(x, t, s): 0 <= s <= t <= u(x)}``, so each moment is a
  ratio of two Normaliz volumes (normalized volumes ``(d+k)! vol``), which
  Normaliz computes without listing the simplices (fast on the triangle's
  order polytope, where a triangulation has ``23178480`` simplices at N = 7).

The routes share only the polytope; each is the other's check, and both are
checked against :mod:`forcenet.exact.reference.polytope_moments` (vertex
enumeration and a pulling triangulation in plain fractions).

Examples
--------
>>> from forcenet.exact.contact_network.model import contact_network
>>> from forcenet.exact.contact_network.polytope import exact_polytope
>>> net = contact_network(1, [[0, None, "-3/5", "-4/5"], [0, None, "3/5", "-4/5"], [0, None, 0, -1]], [[0, 0, -1]])
>>> poly = exact_polytope(net)
>>> m = moments_by_triangulation(poly)
>>> [str(x) for x in m.mean], [str(x) for x in m.second]
(['5/16', '5/16', '1/2'], ['25/192', '25/192', '1/3'])
>>> moments_by_volumes(poly).mean == m.mean
True
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from fractions import Fraction
from typing import Any

import numpy as np
import sympy

from forcenet.core.errors import ArgumentError

from .polytope import ExactPolytope

__all__ = ["Moments", "Triangulation", "triangulation", "normaliz_rows", "normaliz_cone", "moments_by_triangulation", "moments_by_volumes", "polytope_facts",
           "density_at"]


@dataclass(frozen=True)
class Moments:
    """Exact moments of every variable (contact force) of the ensemble.

    Attributes
    ----------
    mean, second : tuple of sympy numbers
        ``<z_k>`` and ``<z_k^2>`` in the network's units (``second`` empty when not asked).
    dimension : int
        The polytope's dimension (``dim Ker A`` less any inequality that holds with equality everywhere).
    pieces : int
        Simplices of the triangulation, or Normaliz volume computations.
    densities : dict or None
        Exact one-force densities by variable (:mod:`~.marginal_density`), when asked for.
    """

    mean: tuple[Any, ...]
    second: tuple[Any, ...]
    dimension: int
    pieces: int
    densities: dict[int, Any] | None = None


def _integer_row(row: list[Fraction]) -> list[int]:
    common = math.lcm(*(x.denominator for x in row)) if row else 1
    ints = [int(x * common) for x in row]
    divisor = math.gcd(*ints) or 1
    return [v // divisor for v in ints]


def normaliz_rows(poly: ExactPolytope, extra: list[tuple[list[Fraction], Fraction]] = ()) -> list[list[int]]:  # type: ignore[assignment]
    """The polytope as Normaliz's ``inhom_inequalities`` (integer rows ``[a_1..a_d, c]``: ``a . x + c >= 0``).

    ``extra`` appends inequalities ``(a, c)`` in the same coordinates (longer ``a`` lifts the polytope).

    Examples
    --------
    >>> from forcenet.exact.contact_network.model import contact_network
    >>> from forcenet.exact.contact_network.polytope import exact_polytope
    >>> normaliz_rows(exact_polytope(contact_network(1, [[0, None, 0, -1], [0, None, 0, -1]], [[0, 0, -1]])))
    [[-1, 1], [1, 0]]
    """
    width = max([poly.dimension] + [len(a) for a, _ in extra])
    rows = []
    for a, c in [*zip(poly.H, poly.h), *extra]:
        row = list(a) + [Fraction(0)] * (width - len(a)) + [c]
        if any(row[:-1]):
            rows.append(_integer_row(row))
        elif c < 0:
            rows.append([0] * width + [-1])  # an inequality 0 >= -c > 0 that no point meets: empty
    return rows


def normaliz_cone(rows: list[list[Any]], number_field: list[str] | None = None) -> Any:
    """Normaliz's cone of the polytope ``rows`` (``inhom_inequalities``), over a number field when given.

    Examples
    --------
    >>> normaliz_cone([[1, 0], [-1, 1]]).VerticesOfPolyhedron()
    [[0, 1], [1, 1]]
    """
    from PyNormaliz import Cone  # optional dependency: the "networks" extra

    if number_field is None:
        return Cone(inhom_inequalities=rows)
    return Cone(number_field=number_field, inhom_inequalities=rows)


def _cone(rows: list[list[int]]) -> Any:
    return normaliz_cone(rows)


def polytope_facts(poly: ExactPolytope) -> tuple[int, int, int]:
    """``(dimension, vertices, facets)`` of the polytope, exactly (Normaliz); refuses an empty or unbounded one.

    Examples
    --------
    >>> from forcenet.exact.contact_network.geometries import triangle
    >>> from forcenet.exact.contact_network.polytope import exact_polytope
    >>> polytope_facts(exact_polytope(triangle(3).network))
    (3, 4, 4)
    """
    if poly.dimension == 0:
        if any(c < 0 for c in poly.h):
            raise _empty()
        return 0, 1, 0
    cone = _cone(normaliz_rows(poly))
    vertices = cone.VerticesOfPolyhedron()
    if not vertices:
        raise _empty()
    if cone.RecessionRank() > 0:
        raise ArgumentError("unbounded: the forces can grow without bound (a self-stress); there is no uniform "
                            "ensemble")
    return int(cone.AffineDim()), len(vertices), len(cone.SupportHyperplanes())


def _empty() -> ArgumentError:
    return ArgumentError("infeasible: no network of repulsive contact forces balances these loads exactly")


def _point_moments(poly: ExactPolytope, moments: int) -> Moments:
    z = [poly.scale[k] * sympy.Rational(poly.z0[k]) for k in range(len(poly.z0))]
    return Moments(tuple(z), tuple(v * v for v in z) if moments >= 2 else (), 0, 1)


def _vertex_values(poly: ExactPolytope, generators: list[list[int]]) -> tuple[np.ndarray, int]:
    """The scaled variables ``z'`` at every generator (vertex ``g[:-1]/g[-1]``) as integers over one denominator."""
    q = math.lcm(*(x.denominator for x in poly.z0), *(x.denominator for row in poly.K for x in row))
    z0 = [int(x * q) for x in poly.z0]
    K = [[int(x * q) for x in row] for row in poly.K]
    common = math.lcm(*(int(g[-1]) for g in generators))
    rows = []
    for g in generators:
        h, coords = int(g[-1]), [int(v) for v in g[:-1]]
        factor = common // h
        rows.append([(z0[k] * h + sum(a * x for a, x in zip(K[k], coords))) * factor for k in range(len(z0))])
    return np.array(rows, dtype=object), q * common


def _exact(poly: ExactPolytope, k: int, value: Fraction, power: int) -> Any:
    return sympy.radsimp(poly.scale[k] ** power * sympy.Rational(value.numerator, value.denominator))


@dataclass(frozen=True)
class Triangulation:
    """Normaliz's triangulation of the polytope with every variable's value at its vertices.

    Attributes
    ----------
    simplices : list of tuple of int
        Each simplex's vertices (indices into ``table``'s rows).
    table : numpy.ndarray of int (object)
        ``table[v, k] / denominator`` is the scaled variable ``z'_k`` at vertex ``v``.
    denominator : int
    weights : list of int
        Each simplex's volume, all in one unit (their sum is ``weight``).
    weight : int
    dimension : int
        The polytope's dimension (each simplex has ``dimension + 1`` vertices).
    """

    simplices: list[tuple[int, ...]]
    table: Any
    denominator: int
    weights: list[int]
    weight: int
    dimension: int


def triangulation(poly: ExactPolytope) -> Triangulation:
    """The triangulation (Normaliz) of a polytope of dimension ``>= 1``, weighted in one unit.

    Examples
    --------
    >>> from forcenet.exact.contact_network.geometries import triangle
    >>> from forcenet.exact.contact_network.polytope import exact_polytope
    >>> tri = triangulation(exact_polytope(triangle(3).network))
    >>> len(tri.simplices), tri.dimension, len(tri.simplices[0])
    (1, 3, 4)
    """
    polytope_facts(poly)
    cone = _cone(normaliz_rows(poly))
    simplices, generators = cone.Triangulation()
    table, denominator = _vertex_values(poly, generators)
    degrees = [int(g[-1]) for g in generators]
    # Normaliz's multiplicity is |det| of the homogenized integer generators (v_i h_i, h_i): the simplex's
    # normalized volume times the product of the degrees h_i; all weights are brought to one denominator
    products = [math.prod(degrees[v] for v in key) for key, *_ in simplices]
    common = math.lcm(*products)
    weights = [int(m) * (common // p) for (key, m, *_), p in zip(simplices, products)]
    return Triangulation([tuple(int(v) for v in key) for key, *_ in simplices], table, denominator, weights,
                         sum(weights), int(cone.AffineDim()))


def moments_by_triangulation(poly: ExactPolytope, moments: int = 2,
                             progress: Callable[..., Any] | None = None, tri: Triangulation | None = None) -> Moments:
    """Every variable's exact ``<z>`` (and ``<z^2>``) from Normaliz's triangulation and the simplex formulas.

    Parameters
    ----------
    poly : ExactPolytope
    moments : int
        1 (means) or 2 (means and second moments).
    progress : callable, optional
        Called with the number of simplices done, every 1000.
    tri : Triangulation, optional
        The polytope's :func:`triangulation` when made already (e.g. for densities).

    Returns
    -------
    Moments

    Examples
    --------
    >>> from forcenet.exact.contact_network.geometries import triangle
    >>> from forcenet.exact.contact_network.polytope import exact_polytope
    >>> geo = triangle(3)
    >>> m = moments_by_triangulation(exact_polytope(geo.network))
    >>> [str(m.mean[geo.contact[("floor", 3, j)]]) for j in (1, 2, 3)]  # <W_3j>, table(3)'s last row
    ['1/4', '1/2', '1/4']
    """
    if poly.dimension == 0:
        polytope_facts(poly)
        return _point_moments(poly, moments)
    tri = triangulation(poly) if tri is None else tri
    simplices, table, denominator, weights, weight, dimension = (tri.simplices, tri.table, tri.denominator,
                                                                tri.weights, tri.weight, tri.dimension)
    n = table.shape[1]
    # sum_s w_s sum_{u,v in s} t_u t_v = sum_{u,v} C_uv t_u t_v with C_uv = sum_{s contains u, v} w_s (one pass
    # over the simplices with small integers; machine integers when they cannot overflow)
    count = table.shape[0]
    kind: Any = np.int64 if weight < 2**62 else object
    pairs = np.zeros((count, count), dtype=kind)
    for done, (key, w) in enumerate(zip(simplices, weights), start=1):
        index = np.asarray(key)
        pairs[np.ix_(index, index)] += w
        if progress is not None and done % 1000 == 0:
            progress(1000)
    pairs = pairs.astype(object)
    singles = pairs.diagonal().copy()
    first = singles @ table
    second = (singles @ (table * table) + ((pairs @ table) * table).sum(axis=0)) if moments >= 2 else first
    k1 = (dimension + 1) * weight * denominator
    k2 = (dimension + 1) * (dimension + 2) * weight * denominator * denominator
    mean = tuple(_exact(poly, k, Fraction(int(first[k]), k1), 1) for k in range(n))
    seconds = tuple(_exact(poly, k, Fraction(int(second[k]), k2), 2) for k in range(n)) if moments >= 2 else ()
    return Moments(mean, seconds, dimension, len(simplices))


def _volume(rows: list[list[int]]) -> Fraction:
    volume = _cone(rows).Volume()
    return Fraction(str(volume))


def moments_by_volumes(poly: ExactPolytope, moments: int = 2, variables: list[int] | None = None,
                       progress: Callable[..., Any] | None = None) -> Moments:
    """``<z_k>`` (and ``<z_k^2>``) as ratios of Normaliz volumes of lifted polytopes (needs ``z_k >= 0``).

    ``E[u] = (d+1)! vol(P_u) / ((d+1) d! vol(P))`` with ``P_u = {(x, t): 0 <= t <= u(x)}``, and
    ``E[u^2] = 2 (d+2)! vol(P_uu) / ((d+2)(d+1) d! vol(P))`` with ``P_uu = {0 <= s <= t <= u(x)}``; Normaliz's
    ``Volume`` is the normalized one, ``(dim)! vol``, in one lattice for all of them.

    Parameters
    ----------
    poly : ExactPolytope
    moments : int
        1 or 2.
    variables : list of int, optional
        Which variables (default all); the others are ``None``.
    progress : callable, optional
        Called with 1 after each volume.

    Returns
    -------
    Moments

    Raises
    ------
    ArgumentError
        If a variable can be negative on the polytope (a tangential force): use the triangulation.

    Examples
    --------
    >>> from forcenet.exact.contact_network.geometries import triangle
    >>> from forcenet.exact.contact_network.polytope import exact_polytope
    >>> geo = triangle(3)
    >>> m = moments_by_volumes(exact_polytope(geo.network), 2, [geo.contact[("floor", 3, 1)]])
    >>> [str(x) for x in m.mean if x is not None], [str(x) for x in m.second if x is not None]
    (['1/4'], ['1/10'])
    """
    if poly.dimension == 0:
        polytope_facts(poly)
        return _point_moments(poly, moments)
    dimension = polytope_facts(poly)[0]
    n, d = len(poly.z0), poly.dimension
    chosen = list(range(n)) if variables is None else variables
    if any(not label.startswith("f") for k, label in enumerate(poly.labels) if k in chosen):
        raise ArgumentError("the volume route needs forces that are never negative; a tangential force is not: "
                            "use the triangulation route")
    base = _volume(normaliz_rows(poly))
    done = 1
    mean: list[Any] = [None] * n
    second: list[Any] = [None] * n
    for k in chosen:
        a = list(poly.K[k])  # u(x) = z0_k + K_k . x  (scaled variable z'_k >= 0)
        lift1 = [([Fraction(0)] * d + [Fraction(1)], Fraction(0)),
                 ([*a, Fraction(-1)], poly.z0[k])]
        v1 = _volume(normaliz_rows(poly, lift1))
        mean[k] = _exact(poly, k, v1 / ((dimension + 1) * base), 1)
        done += 1
        if moments >= 2:
            lift2 = [([Fraction(0)] * (d + 1) + [Fraction(1)], Fraction(0)),
                     ([Fraction(0)] * d + [Fraction(1), Fraction(-1)], Fraction(0)),
                     ([*a, Fraction(-1), Fraction(0)], poly.z0[k])]
            v2 = _volume(normaliz_rows(poly, lift2))
            second[k] = _exact(poly, k, 2 * v2 / ((dimension + 2) * (dimension + 1) * base), 2)
            done += 1
        if progress is not None:
            progress(1)
    return Moments(tuple(mean), tuple(second) if moments >= 2 else (), dimension, done)


def density_at(poly: ExactPolytope, k: int, values: list[Any]) -> list[Any]:
    """The exact density of variable ``k`` (a contact force) at each of ``values``, by Normaliz slice volumes.

    The density of an affine ``u(x)`` over the uniform polytope is the ``(d-1)``-volume of the slice
    ``{u = s}`` over ``|grad u| vol(P)``; with ``u = (g/L) a.x + c`` (``a`` primitive integer), Normaliz's
    normalized volumes give ``density(s) = d * NV(slice) / NV(P) * L / g``: the lattice covolume ``|a|`` of
    the slice cancels the gradient's norm. Each value costs one Normaliz volume of dimension ``d - 1``.

    Parameters
    ----------
    poly : ExactPolytope
    k : int
        The variable (``f{c}`` of contact ``c`` is variable ``c`` without friction).
    values : list
        Points, exact (int, Fraction, sympy numbers in the variable's units).

    Returns
    -------
    list
        Exact densities (sympy numbers).

    Examples
    --------
    >>> from forcenet.exact.contact_network.geometries import triangle
    >>> from forcenet.exact.contact_network.polytope import exact_polytope
    >>> geo = triangle(4)
    >>> density_at(exact_polytope(geo.network), geo.contact[("floor", 4, 2)], [Fraction(1, 3)])  # forcenet.law
    [160/81]
    """
    d = poly.dimension
    a = list(poly.K[k])
    if d == 0 or not any(a):
        raise ArgumentError(f"variable {k} is constant on the polytope: it has no density (a point mass)")
    base = _volume(normaliz_rows(poly))
    common = math.lcm(*(x.denominator for x in a))
    divisor = math.gcd(*(int(x * common) for x in a))
    out = []
    for value in values:
        scaled = sympy.radsimp(sympy.sympify(value) / poly.scale[k])
        if not scaled.is_Rational:
            raise ArgumentError(f"the density at {value} needs a point that is rational in the force's unit "
                                f"({poly.scale[k]})")
        s = Fraction(int(scaled.p), int(scaled.q))
        equation = _integer_row([*a, poly.z0[k] - s])
        from PyNormaliz import Cone  # optional dependency: the "networks" extra

        cone = Cone(inhom_inequalities=normaliz_rows(poly), inhom_equations=[equation])
        slice_volume = Fraction(str(cone.Volume())) if cone.AffineDim() == d - 1 else Fraction(0)
        density = slice_volume * d / base * Fraction(common, divisor)
        out.append(sympy.radsimp(sympy.Rational(density.numerator, density.denominator) / poly.scale[k]))
    return out
