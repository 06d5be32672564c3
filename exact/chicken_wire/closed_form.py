"""The entropy of the chicken-wire model on the isotropic line, Eqs. (7.1)-(7.4), as exact sympy expressions.

Reconstructed from the garbled extraction (notes/chicken_wire.md, Sec. 4 and 8)
and checked against the Bethe ansatz (tests/test_isotropic.py):

* (7.1), entropy per site at the parameter ``phi`` (``-pi/2 <= phi <= pi/2``)::

      v(phi) = [ log(6 sqrt3 / cos phi)
                 + cos(pi/6 + phi/3) log(tan(pi/4 + phi/6) tan(pi/12 + phi/6))
                 + cos(pi/6 - phi/3) log(tan(pi/4 - phi/6) tan(pi/12 - phi/6)) ] / (1 - sin(phi/3))

* (7.2), bond density per direction: ``Q = 1/2 - cos(phi/3) / (2 sqrt3 (1 - sin(phi/3)))``
  ``= 1/2 - tan(pi/4 + phi/6) / (2 sqrt3)``;
* eliminating ``phi`` (proved in tests with sympy), with ``e = 1 - 3Q + 3Q^2``::

      v(Q) = 6e log e + 2e log 4 - 3Q^2 log Q - 3(1-Q)^2 log(1-Q)
             - 3(1-2Q)^2 log(1-2Q) - (1-3Q)^2 log(1-3Q) - (2-3Q)^2 log(2-3Q);

* ``e(phi) = 1 / (2 (1 - sin(phi/3)))`` is the density of empty sites (the
  vertices of the square-triangle tiling), and ``s = v / e`` the entropy per
  tiling vertex; ``s(0) = log 108 - 2 sqrt3 log(2 + sqrt3)``, the maximal
  entropy of the square-triangle random tiling;
* (7.3) corrected: ``v = eps^2 (log(108/eps^2) - 3)/18 + O(eps^3 log eps)`` at
  ``phi = pi/2 - eps`` (the extraction lost the minus sign of ``3``);
* (7.4) corrected: entropy per grain ``g = 3 l^2 v -> log(6 l) - 3/2`` for
  hexagons of side ``l`` (``eps ~ sqrt3 / l``).

Everything here is exact (sympy); evaluation at any precision is
:mod:`forcenet.numeric.chicken_wire.isotropic`.

Examples
--------
>>> import sympy
>>> abs(sympy.N(entropy_phi(0) - tiling_entropy_maximum() / 2, 60)) < 1e-50
True
>>> sympy.limit(entropy_Q(), Q, sympy.Rational(1, 3)), sympy.limit(entropy_Q(), Q, 0)
(0, 0)
"""

from __future__ import annotations

from functools import lru_cache

import sympy

from forcenet.core.errors import ArgumentError

__all__ = [
    "PHI",
    "Q",
    "EPS",
    "density_Q",
    "phi_of_Q",
    "entropy_phi",
    "entropy_Q",
    "chemical_potential_Q",
    "empty_density_Q",
    "empty_density_phi",
    "tiling_entropy_phi",
    "tiling_entropy_maximum",
    "twelvefold_density",
    "series_coefficients",
    "entropy_series_Q",
    "entropy_series_eps",
    "per_grain_limit",
]

PHI = sympy.Symbol("phi", real=True)
Q = sympy.Symbol("Q", positive=True)
EPS = sympy.Symbol("epsilon", positive=True)
L_SIDE = sympy.Symbol("l", positive=True)  # the hexagon side of (7.4)
_pi, _sqrt3 = sympy.pi, sympy.sqrt(3)


def density_Q(phi: sympy.Expr = PHI) -> sympy.Expr:
    """Eq. (7.2): ``Q = 1/2 - tan(pi/4 + phi/6) / (2 sqrt3)`` (the printed ``cos/(1 - sin)`` form, simplified).

    Examples
    --------
    >>> density_Q(sympy.pi / 2), density_Q(-sympy.pi / 2)
    (0, 1/3)
    """
    return sympy.Rational(1, 2) - sympy.tan(_pi / 4 + phi / 6) / (2 * _sqrt3)


def phi_of_Q(q: sympy.Expr = Q) -> sympy.Expr:
    """The inverse of (7.2): ``phi = 6 atan(sqrt3 (1 - 2Q)) - 3 pi / 2``.

    Examples
    --------
    >>> phi_of_Q(0), phi_of_Q(sympy.Rational(1, 3))
    (pi/2, -pi/2)
    """
    return 6 * sympy.atan(_sqrt3 * (1 - 2 * q)) - 3 * _pi / 2


def entropy_phi(phi: sympy.Expr = PHI) -> sympy.Expr:
    """Eq. (7.1): the entropy per site ``v(phi)`` as reconstructed (module docstring).

    Examples
    --------
    >>> sympy.N(entropy_phi(sympy.Rational(3, 10)), 15)
    0.0627367486525136
    """
    plus = sympy.cos(_pi / 6 + phi / 3) * sympy.log(sympy.tan(_pi / 4 + phi / 6) * sympy.tan(_pi / 12 + phi / 6))
    minus = sympy.cos(_pi / 6 - phi / 3) * sympy.log(sympy.tan(_pi / 4 - phi / 6) * sympy.tan(_pi / 12 - phi / 6))
    return (sympy.log(6 * _sqrt3 / sympy.cos(phi)) + plus + minus) / (1 - sympy.sin(phi / 3))


def _xlog(x: sympy.Expr) -> sympy.Expr:
    return x**2 * sympy.log(x)


def entropy_Q(q: sympy.Expr = Q) -> sympy.Expr:
    """The entropy per site as an algebraic-logarithmic function of the density ``Q`` (``0 < Q < 1/3``).

    Examples
    --------
    >>> sympy.N(entropy_Q(sympy.Rational(1, 6)), 12)
    0.0616159805394
    """
    e = 1 - 3 * q + 3 * q**2
    return (6 * e * sympy.log(e) + 2 * e * sympy.log(4) - 3 * _xlog(q) - 3 * _xlog(1 - q)
            - 3 * _xlog(1 - 2 * q) - _xlog(1 - 3 * q) - _xlog(2 - 3 * q))


def chemical_potential_Q(q: sympy.Expr = Q) -> sympy.Expr:
    """``mu = -(1/3) dv/dQ``: the log-fugacity of each of the three bond directions at density ``Q``.

    Examples
    --------
    >>> sympy.N(chemical_potential_Q(sympy.Rational(1, 6)), 10)
    -0.04298527200
    """
    return sympy.expand(-sympy.diff(entropy_Q(Q), Q) / 3).subs(Q, q)


def empty_density_Q(q: sympy.Expr = Q) -> sympy.Expr:
    """``e = 1 - 3Q + 3Q^2``: empty sites per site (= tiling vertices per site, Sec. 8 of the notes).

    Examples
    --------
    >>> empty_density_Q(sympy.Rational(1, 6))
    7/12
    """
    return 1 - 3 * q + 3 * q**2


def empty_density_phi(phi: sympy.Expr = PHI) -> sympy.Expr:
    """``e(phi) = 1 / (2 (1 - sin(phi/3)))``, equal to ``empty_density_Q(density_Q(phi))``.

    Examples
    --------
    >>> empty_density_phi(0)
    1/2
    """
    return 1 / (2 * (1 - sympy.sin(phi / 3)))


def tiling_entropy_phi(phi: sympy.Expr = PHI) -> sympy.Expr:
    """``s(phi) = v / e = 2 (1 - sin(phi/3)) v(phi)``: the entropy per tiling vertex (even in ``phi``).

    Examples
    --------
    >>> sympy.N(tiling_entropy_phi(0), 15)
    0.120055249318542
    """
    return 2 * (1 - sympy.sin(phi / 3)) * entropy_phi(phi)


def tiling_entropy_maximum() -> sympy.Expr:
    """``log 108 - 2 sqrt3 log(2 + sqrt3)``: the maximal entropy per vertex of the square-triangle tiling.

    Examples
    --------
    >>> sympy.N(tiling_entropy_maximum(), 20)
    0.12005524931854160783
    """
    return sympy.log(108) - 2 * _sqrt3 * sympy.log(2 + _sqrt3)


def twelvefold_density() -> sympy.Expr:
    """``Q0 = Q(phi = 0) = (3 - sqrt3)/6``: the density of the twelvefold point.

    Examples
    --------
    >>> sympy.simplify(twelvefold_density() - density_Q(0))
    0
    """
    return (3 - _sqrt3) / 6


@lru_cache(maxsize=8)
def series_coefficients(order: int) -> tuple[sympy.Expr, ...]:
    """Exact Taylor coefficients ``a_2..a_order`` of ``v(Q) + 3 Q^2 log Q`` (an analytic function at 0).

    Every term of :func:`entropy_Q` but ``-3 Q^2 log Q`` is analytic at ``Q = 0``;
    ``(1 - cQ)^2 log(1 - cQ)`` has the coefficients ``-c``, ``3c^2/2`` and
    ``-2 c^k / (k (k-1) (k-2))`` for ``k >= 3``, and ``log e = log(1 - Q/r) + log(1 - Q/rbar)``
    with ``1/r = sqrt3 exp(-i pi/6)``, so ``[Q^n] log e = -2 * 3^(n/2) cos(n pi/6) / n``.
    """
    def square_log(c: sympy.Expr | int, k: int) -> sympy.Expr:  # [Q^k] (1 - cQ)^2 log(1 - cQ)
        c = sympy.sympify(c)
        if k == 0:
            return sympy.Integer(0)
        if k == 1:
            return -c
        if k == 2:
            return sympy.Rational(3, 2) * c**2
        return -2 * c**k / (k * (k - 1) * (k - 2))

    def log_e(n: int) -> sympy.Expr:  # [Q^n] log(1 - 3Q + 3Q^2)
        if n == 0:
            return sympy.Integer(0)
        return sympy.Rational(-2, n) * sympy.expand(sympy.sqrt(3) ** n * sympy.cos(n * _pi / 6))  # a rational

    log2 = sympy.log(2)
    coeffs = []
    for k in range(order + 1):
        e_log_e = log_e(k) - 3 * (log_e(k - 1) if k >= 1 else 0) + 3 * (log_e(k - 2) if k >= 2 else 0)
        e_k = {0: 1, 1: -3, 2: 3}.get(k, 0)
        # (2 - 3Q)^2 log(2 - 3Q) = 4 (1 - 3Q/2)^2 (log 2 + log(1 - 3Q/2))
        two = 4 * ({0: 1, 1: -3, 2: sympy.Rational(9, 4)}.get(k, 0) * log2 + square_log(sympy.Rational(3, 2), k))
        a = (6 * e_log_e + 2 * e_k * 2 * log2 - 3 * square_log(1, k) - 3 * square_log(2, k) - square_log(3, k) - two)
        coeffs.append(sympy.expand(a))
    return tuple(coeffs)


def entropy_series_Q(order: int = 6, q: sympy.Expr = Q) -> sympy.Expr:
    """``v(Q) = -3 Q^2 log Q + sum_{k=2}^{order} a_k Q^k + O(Q^{order+1})``, exact coefficients.

    The series converges for ``|Q| < 1/3`` (the singularity of ``log(1 - 3Q)``).

    Examples
    --------
    >>> entropy_series_Q(3)
    -9*Q**3/2 - 3*Q**2*log(Q) + Q**2*(-9/2 + 3*log(2))
    """
    if order < 2:
        raise ArgumentError(f"order={order} is out of range: order must be an integer >= 2")
    coeffs = series_coefficients(order)
    return -3 * q**2 * sympy.log(q) + sum(coeffs[k] * q**k for k in range(2, order + 1))


def entropy_series_eps(order: int = 4, eps: sympy.Expr = EPS) -> sympy.Expr:
    """Eq. (7.3) corrected and extended: ``v`` at ``phi = pi/2 - eps`` to ``O(eps^(order+1) log eps)``.

    ``v = eps^2 (log(108/eps^2) - 3)/18 + sqrt3 eps^3 (2 log eps - log 108 + 3)/54 + ...``;
    derived here by substituting the series of (7.2) into :func:`entropy_Q`.

    Examples
    --------
    >>> v2 = entropy_series_eps(2)
    >>> sympy.simplify(v2 - EPS**2 * (sympy.log(108 / EPS**2) - 3) / 18)
    0
    """
    if order < 2:
        raise ArgumentError(f"order={order} is out of range: order must be an integer >= 2")
    q_eps = sympy.series(density_Q(_pi / 2 - EPS), EPS, 0, order + 1).removeO()
    series = sympy.expand(sympy.series(entropy_series_Q(order, q_eps), EPS, 0, order + 1).removeO())
    series = sympy.expand(sympy.expand_log(series, force=True))
    return sympy.collect(series, [EPS**k for k in range(order, 1, -1)]).subs(EPS, eps)


def per_grain_limit(l: sympy.Expr = L_SIDE) -> sympy.Expr:
    """Eq. (7.4) corrected: the entropy per grain ``g = 3 l^2 v -> log(6 l) - 3/2`` (hexagon side ``l``).

    Examples
    --------
    >>> per_grain_limit(1)
    -3/2 + log(6)
    """
    return sympy.log(6 * l) - sympy.Rational(3, 2)
