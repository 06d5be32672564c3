"""One contact force's exact density over the ensemble: a piecewise polynomial from the triangulation.

Derivation (``notes/contact_networks.md``, Sec. 3b).  The ensemble is the
uniform measure on the polytope (thesis Sec. 2.3.2); a contact force ``u`` is
affine on it.  Cut the polytope into simplices (Normaliz's triangulation,
:func:`~.triangulation_moments.triangulation`).  On one ``d``-simplex with
vertex values ``u_0..u_d`` the law of ``u`` under the uniform measure is the
B-spline with those knots (Curry and Schoenberg 1966: the density of a
linear function of a uniform point of a simplex)::

    M(t) = d [u_0, ..., u_d] (. - t)_+^(d-1)

(a divided difference in the dot).  Knots repeat (many vertices share a
force value, zero above all), so the divided difference is taken in its
confluent form: for each distinct knot ``tau`` of multiplicity ``m``,

    (1/(m-1)!) d^(m-1)/dx^(m-1) [ (x - t)^(d-1) / prod_(sigma != tau) (x - sigma)^(m_sigma) ]  at x = tau,

counted when ``tau > t`` (the truncated power vanishes below ``t``).  With
``h = x - tau`` and ``y = tau - t`` this is the coefficient of ``h^(m-1)``
in ``(h + y)^(d-1) prod (h + tau - sigma)^(-m_sigma)``: a polynomial in ``y``
whose coefficients are rationals of the knots alone.  Summing over the
simplices, weighted by their volumes, each knot ``tau`` of the whole
triangulation carries one polynomial ``Q_tau(tau - t)`` and the density is

    p(t) = sum_(tau > t) Q_tau(tau - t) / vol(P),

a polynomial of degree ``<= d - 1`` between consecutive knots.  Every number
is a Python ``Fraction``; the force's unit (``sqrt(3)`` for the hexagonal
lattice's rescaled forces) enters only at the end, in sympy.

Checks (``tests/test_contact_network_density.py``): it integrates to 1 and
its moments equal :func:`~.triangulation_moments.moments_by_triangulation`'s
and the volume route's; on the chapter-4 triangle it equals ``forcenet.law``'s
exact density (Eqs. (4.5)-(4.9), a route through sorted uniforms); at
single points it equals :func:`~.triangulation_moments.density_at` (slice
volumes).

Examples
--------
>>> from forcenet.exact.contact_network.model import contact_network
>>> from forcenet.exact.contact_network.polytope import exact_polytope
>>> net = contact_network(1, [[0, None, "-3/5", "-4/5"], [0, None, "3/5", "-4/5"], [0, None, 0, -1]], [[0, 0, -1]])
>>> [(str(p.lo), str(p.hi), str(p.poly.as_expr())) for p in force_density(exact_polytope(net), 2)]
[('0', '1', '1')]
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass
from fractions import Fraction
from math import comb
from typing import Any

import sympy

from forcenet.core.errors import ArgumentError

from .polytope import ExactPolytope
from .triangulation_moments import Triangulation, triangulation

__all__ = ["DensityPiece", "F", "knot_polynomials", "force_density", "force_densities", "integrate", "evaluate"]

F = sympy.Symbol("f")  # the force, in the network's units


@dataclass(frozen=True)
class DensityPiece:
    """The density on ``lo < f < hi``: ``poly`` (a sympy ``Poly`` in :data:`F`).

    Examples
    --------
    >>> DensityPiece(sympy.Integer(0), sympy.Integer(1), sympy.Poly(2 * F, F)).poly.eval(sympy.Rational(1, 2))
    1
    """

    lo: Any
    hi: Any
    poly: Any


def _series_inverse(a: Fraction, n: int, length: int) -> list[Fraction]:
    """Coefficients of ``(h + a)^(-n)`` in powers of ``h``, up to ``h^(length-1)``."""
    base = a ** (-n)
    return [base * (-1) ** j * comb(n + j - 1, j) / a**j for j in range(length)]


def _times(p: list[Fraction], q: list[Fraction], length: int) -> list[Fraction]:
    out = [Fraction(0)] * length
    for i, x in enumerate(p[:length]):
        if x:
            for j, y in enumerate(q[:length - i]):
                out[i + j] += x * y
    return out


def knot_polynomials(tri: Triangulation, k: int) -> dict[int, list[Fraction]]:
    """``Q_tau``: for every knot (an integer value of ``table[:, k]``) the coefficients ``q_p`` of
    ``sum_p q_p (tau - t)^p`` (module docstring), weighted by the simplices' volumes (not yet divided by their sum).

    Examples
    --------
    >>> from forcenet.exact.contact_network.geometries import triangle
    >>> from forcenet.exact.contact_network.polytope import exact_polytope
    >>> tri = triangulation(exact_polytope(triangle(3).network))
    >>> Q = knot_polynomials(tri, 0)
    >>> sum(q * tau**p for tau in Q for p, q in enumerate(Q[tau])) == 0  # below every knot (t = 0 < min): nothing
    True
    """
    d = tri.dimension
    Q: dict[int, list[Fraction]] = {}
    for key, w in zip(tri.simplices, tri.weights):
        knots = Counter(int(tri.table[v, k]) for v in key)
        if len(knots) == 1:
            raise ArgumentError(f"variable {k} is constant on a simplex of the polytope: it has no density")
        for tau, m in knots.items():
            series = [Fraction(1)] + [Fraction(0)] * (m - 1)
            for sigma, n in knots.items():
                if sigma != tau:
                    series = _times(series, _series_inverse(Fraction(tau - sigma), n, m), m)
            coefficients = Q.setdefault(tau, [Fraction(0)] * d)
            for j in range(min(m, d)):  # h^j from (h + y)^(d-1), h^(m-1-j) from the series: y^(d-1-j)
                coefficients[d - 1 - j] += w * d * comb(d - 1, j) * series[m - 1 - j]
    return Q


def _pieces(Q: dict[int, list[Fraction]], total: int, unit: Any) -> list[DensityPiece]:
    """The piecewise polynomial in the force ``f = unit * t`` from the knots' polynomials in ``t``."""
    t = sympy.Symbol("t")
    knots = sorted(Q)
    pieces = []
    running = sympy.Poly(0, t, domain="QQ")
    for lo, hi in reversed(list(zip(knots, knots[1:]))):  # p(t) on (lo, hi) = sum over tau >= hi
        running += sympy.Poly(sum(sympy.Rational(q.numerator, q.denominator) * (hi - t) ** p
                                  for p, q in enumerate(Q[hi])), t, domain="QQ")
        in_f = running.as_expr().subs(t, F / unit) / unit / total
        pieces.append(DensityPiece(sympy.radsimp(lo * unit), sympy.radsimp(hi * unit),
                                   sympy.Poly(sympy.expand(sympy.radsimp(in_f)), F)))
    merged: list[DensityPiece] = []
    for piece in reversed(pieces):
        if merged and merged[-1].poly == piece.poly:
            merged[-1] = DensityPiece(merged[-1].lo, piece.hi, piece.poly)
        else:
            merged.append(piece)
    return [p for p in merged if not p.poly.is_zero]


def force_densities(poly: ExactPolytope, variables: list[int],
                    tri: Triangulation | None = None) -> dict[int, list[DensityPiece]]:
    """The exact densities of several variables from one triangulation (:func:`force_density` each; ``tri``:
    the polytope's triangulation when made already, e.g. for the moments).

    Examples
    --------
    >>> from forcenet.exact.contact_network.geometries import triangle
    >>> from forcenet.exact.contact_network.polytope import exact_polytope
    >>> geo = triangle(3)
    >>> d = force_densities(exact_polytope(geo.network), [geo.contact[("floor", 3, 1)]])
    >>> [str(p.poly.as_expr()) for p in d[geo.contact[("floor", 3, 1)]]]  # W_31: the smallest of three spacings
    ['3*f**2 - 6*f + 3']
    """
    for k in variables:
        if poly.dimension == 0 or not any(poly.K[k]):
            raise ArgumentError(f"{poly.labels[k]} is fixed by balance alone: it has no density (a point mass at "
                                "its mean)")
    tri = triangulation(poly) if tri is None else tri
    return {k: _pieces(knot_polynomials(tri, k), tri.weight, poly.scale[k] / tri.denominator) for k in variables}


def force_density(poly: ExactPolytope, k: int) -> list[DensityPiece]:
    """Variable ``k``'s exact density as pieces ``(lo, hi, polynomial in f)``, in the network's units.

    Parameters
    ----------
    poly : ExactPolytope
    k : int
        The variable (``f{c}``: contact ``c``'s normal force).

    Returns
    -------
    list of DensityPiece
        Consecutive pieces on the force's range (zero outside).

    Raises
    ------
    ArgumentError
        A force that balance fixes (a point mass).

    Examples
    --------
    >>> from forcenet.exact.contact_network.geometries import triangle
    >>> from forcenet.exact.contact_network.polytope import exact_polytope
    >>> geo = triangle(4)
    >>> pieces = force_density(exact_polytope(geo.network), geo.contact[("floor", 4, 2)])
    >>> [str(p.poly.eval(sympy.Rational(1, 3))) for p in pieces]  # forcenet.law(4, (4, 2)).density_at(1/3)
    ['160/81']
    """
    return force_densities(poly, [k])[k]


def evaluate(pieces: list[DensityPiece], value: Any) -> Any:
    """The density at ``value`` (0 outside the pieces; at a knot, the piece on its right).

    Examples
    --------
    >>> evaluate([DensityPiece(0, 1, sympy.Poly(2 * F, F))], sympy.Rational(1, 4))
    1/2
    """
    for piece in pieces:
        if piece.lo <= value < piece.hi:
            return piece.poly.eval(value)
    return sympy.Integer(0)


def integrate(pieces: list[DensityPiece], power: int = 0) -> Any:
    """``int f^power p(f) df`` over the pieces, exactly (``power = 0``: the normalization).

    Examples
    --------
    >>> integrate([DensityPiece(0, 1, sympy.Poly(2 * F, F))], 1)
    2/3
    """
    total = sympy.Integer(0)
    for piece in pieces:
        antiderivative = sympy.Poly(piece.poly.as_expr() * F**power, F).integrate()
        total += antiderivative.eval(piece.hi) - antiderivative.eval(piece.lo)
    return sympy.radsimp(sympy.expand(total))
