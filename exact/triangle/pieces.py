"""Piecewise polynomial densities: pieces, their distribution functions and bin masses, exactly.

The pooled densities of :mod:`.distribution` (a layer's ``P_i(f)``, the
ensemble ``P(f)``, a contact pool) are polynomials on intervals; here they are
held as :class:`Piece` lists, summed, integrated and binned with exact
rationals (``notes/force_distribution.md``).
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from fractions import Fraction
from typing import Any, NamedTuple

import flint
import sympy

from forcenet.core.errors import ArgumentError, ArgumentTypeError

__all__ = ["Piece", "sum_pieces", "as_pieces", "piecewise_cdf", "bin_probabilities", "bernstein_to_monomial"]


class Piece(NamedTuple):
    """A polynomial ``poly`` of a piecewise density on ``[lo, hi]``."""

    lo: sympy.Rational
    hi: sympy.Rational
    poly: sympy.Poly


def sum_pieces(terms: Iterable[tuple[Any, sympy.Poly]], var: sympy.Symbol) -> list[Piece]:
    """Sum of ``(support end, poly)`` terms (each supported on ``[0, end]``) as pieces.

    Examples
    --------
    >>> f = sympy.Symbol("f")
    >>> [(p.lo, p.hi, p.poly.as_expr()) for p in sum_pieces([(1, sympy.Poly(1, f)), (2, sympy.Poly(f, f))], f)]
    [(0, 1, f + 1), (1, 2, f)]
    """
    terms = list(terms)
    breaks = sorted({b for b, _ in terms})
    pieces: list[Piece] = []
    lo = sympy.Integer(0)
    for hi in breaks:
        poly = sum((p for b, p in terms if b >= hi), sympy.Poly(0, var, domain="QQ"))
        pieces.append(Piece(lo, hi, poly))
        lo = hi
    return pieces


def as_pieces(density: sympy.Poly | Sequence[Piece], support: tuple[Any, Any] | None = None) -> list[Piece]:
    """A density as a list of :class:`Piece`: pieces pass through; one ``Poly`` needs its ``support`` ``(lo, hi)``.

    The single-polynomial densities live on different intervals (a grain's on
    ``[0, 1]``, a layer's ``P_i(f)`` on ``[0, i]``, a contact pool's on
    ``[0, 2i]``), so the interval is never guessed.

    Examples
    --------
    >>> from forcenet.exact.triangle.distribution import layer_force_density
    >>> as_pieces(layer_force_density(3, 3), (0, 3))[0][:2]
    (0, 3)
    """
    if isinstance(density, sympy.Poly):
        if support is None:
            raise ArgumentError("support: a single polynomial density needs its interval (lo, hi), "
                             "e.g. (0, 1) for a grain, (0, i) for layer i, (0, 2i) for the contacts below layer i")
        lo, hi = (sympy.Rational(str(Fraction(x))) for x in support)
        if not lo < hi:
            raise ArgumentError(f"support={support!r}: need lo < hi")
        return [Piece(lo, hi, density)]
    pieces = list(density)
    if not pieces or not all(isinstance(p, Piece) for p in pieces):
        raise ArgumentTypeError("density: need a sympy Poly (with support) or a list of Piece")
    return pieces


def piecewise_cdf(pieces: Sequence[Piece]) -> list[Piece]:
    """The distribution function of a piecewise density, as pieces on the same intervals.

    Examples
    --------
    >>> from forcenet.exact.triangle.distribution import triangle_force_density
    >>> [(p.lo, p.hi, p.poly.as_expr()) for p in piecewise_cdf(triangle_force_density(3))]
    [(0, 2, -f**3/10 + 7*f**2/30 + 2*f/5), (2, 3, -f**2/15 + 2*f/5 + 2/5)]
    """
    out, mass = [], sympy.Integer(0)
    for piece in pieces:
        F = piece.poly.integrate()
        F = F - F.eval(piece.lo) + mass
        out.append(Piece(piece.lo, piece.hi, F))
        mass = F.eval(piece.hi)
    return out


def bin_probabilities(pieces: sympy.Poly | Sequence[Piece], edges: Iterable[Any],
                      support: tuple[Any, Any] | None = None) -> list[Fraction]:
    """Exact ``int_{e_k}^{e_{k+1}} P(f) df`` of a piecewise density for consecutive ``edges``.

    ``pieces`` is a list of :class:`Piece`, or one ``Poly`` with its
    ``support`` (:func:`as_pieces`); ``edges`` are numbers
    :class:`fractions.Fraction` accepts (floats exactly).

    Examples
    --------
    >>> from forcenet.exact.triangle.distribution import contact_layer_force_density, triangle_force_density
    >>> [str(x) for x in bin_probabilities(triangle_force_density(3), [0, 1, 2, 3])]
    ['8/15', '2/5', '1/15']
    >>> [str(x) for x in bin_probabilities(contact_layer_force_density(3, 2), [0, 1, 4], support=(0, 4))]
    ['37/64', '27/64']
    """
    pieces = as_pieces(pieces, support)
    edges = [Fraction(e) for e in edges]
    if any(b <= a for a, b in zip(edges, edges[1:])):
        raise ArgumentError("edges must increase strictly")
    prims = [(Fraction(int(p.lo.p), int(p.lo.q)), Fraction(int(p.hi.p), int(p.hi.q)), p.poly.integrate()) for p in pieces]

    def mass(a: Fraction, b: Fraction) -> Fraction:
        total = Fraction(0)
        for lo, hi, F in prims:
            x, y = max(a, lo), min(b, hi)
            if x < y:
                v = F.eval(sympy.Rational(y.numerator, y.denominator)) - F.eval(sympy.Rational(x.numerator, x.denominator))
                total += Fraction(int(v.p), int(v.q))
        return total

    return [mass(a, b) for a, b in zip(edges, edges[1:])]


def bernstein_to_monomial(b: Sequence[int]) -> list[int]:
    """The coefficients of ``sum_k b[k] w^k (1 - w)^(n - k)`` (``n = len(b) - 1``) in powers of ``w``.

    ``sum_k b_k w^k (1-w)^(n-k) = w^n H(1/w)`` with ``H(t) = B(t - 1)`` and
    ``B(t) = sum_k b_k t^(n-k)``: a reversal, a Taylor shift by ``-1``
    (FLINT's integer polynomials) and a reversal, exact, in place of the
    ``O(n^2)`` binomial expansion (the Beta mixtures of
    :mod:`.distribution`: degree 2000, N = 64, in about a second).

    Parameters
    ----------
    b : sequence of int
        The weights of ``w^k (1 - w)^(n - k)``, ``k = 0..n``.

    Returns
    -------
    list of int
        ``a[m]``, the coefficient of ``w^m``, ``m = 0..n``.

    Examples
    --------
    >>> bernstein_to_monomial([0, 1, 0])  # w (1 - w) = w - w^2
    [0, 1, -1]
    >>> bernstein_to_monomial([1, 3, 3, 1])  # the Bernstein basis, binomials included, sums to 1
    [1, 0, 0, 0]
    """
    n = len(b) - 1
    shifted = flint.fmpz_poly([int(x) for x in reversed(b)])(flint.fmpz_poly([-1, 1]))
    h = [int(x) for x in shifted.coeffs()]
    h += [0] * (n + 1 - len(h))
    return h[::-1]
