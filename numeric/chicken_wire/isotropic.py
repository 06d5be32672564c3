"""The entropy of the chicken-wire model on the isotropic line, Eqs. (7.1)-(7.4), at any precision.

The closed forms are the exact sympy expressions of
:mod:`forcenet.exact.chicken_wire.closed_form` (reconstructed (7.1), (7.2),
their elimination ``v(Q)``, the tiling normalization, the corrected series
(7.3) and (7.4)), evaluated with mpmath: ``v(Q)``, ``mu`` and ``dmu/dQ`` are
compiled from the sympy expressions once (``sympy.lambdify``), never typed
again here.

Precision is a parameter.  Inputs (numbers, strings, Fractions) are
converted inside ``mpmath.workdps``; every quantity is computed at ``dps``
plus guard digits, and again with more, until two evaluations agree to
``dps + 3`` digits *relative* to the result (so cancellations near
``Q -> 0``, ``Q -> 1/3`` or in ``mu`` near the maximum cost precision, never
digits); the result is returned rounded to ``dps`` digits.  No global
precision is set; points outside ``0 <= Q <= 1/3`` (``|phi| <= pi/2``) raise
``ArgumentError``.  For tiny ``Q`` the exact series of ``v(Q)`` takes over
from the closed form where it is cheaper (both agree on their overlap; tests).

The Bethe-ansatz route, which knows nothing of these formulas, is
:mod:`.isotropic_bethe`.

Examples
--------
>>> mpmath.nstr(entropy(Q=Fraction(1, 6), dps=30), 30)
'0.0616159805393802359215413794767'
>>> mpmath.nstr(tiling_entropy(phi=0, dps=25), 25)  # log 108 - 2 sqrt3 log(2 + sqrt3)
'0.1200552493185416078336344'
>>> m = maximum(dps=20)
>>> mpmath.nstr(m.v_max, 20), mpmath.nstr(m.Q_max, 20)
('0.06278636828285688847', '0.184556497614421967')
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from dataclasses import dataclass
from fractions import Fraction
from functools import lru_cache
from typing import Any

import mpmath
import sympy

from forcenet.core.errors import ArgumentError, ArgumentTypeError
from forcenet.core.plan import Plan
from forcenet.core.precision import GUARD, RealLike, converged, to_mpf, within_pi
from forcenet.core.validation import check_dps, check_float_digits, check_int, is_binary_float
from forcenet.exact.chicken_wire.closed_form import EPS, entropy_Q, entropy_series_eps, series_coefficients

__all__ = [
    "phi_within_range",
    "leading_series_at",
    "density_Q",
    "density_Q_naive",
    "phi_of_density",
    "eps_of",
    "entropy",
    "chemical_potential",
    "empty_density",
    "tiling_entropy",
    "entropy_series_7_3",
    "entropy_per_grain",
    "Maximum",
    "maximum",
    "GUARD",
    "closed_form_plan",
]



def closed_form_plan(dps: int, maximum: bool = False) -> Plan:
    """The cost of every closed form at one point (or of :func:`maximum`, ``maximum=True``) to ``dps`` digits.

    Measured on the 2-core machine: one evaluation 0.02 s at 1000 digits,
    1.1 s at 9000 (eight of them at a point); the maximum 2.8 s at 1000
    digits, 15 s at 3000.

    Parameters
    ----------
    dps : int
        Decimal digits, 5..10000.
    maximum : bool
        The maxima instead of the quantities at a point.

    Returns
    -------
    Plan

    Raises
    ------
    ArgumentError
        If ``dps`` is out of range.

    Examples
    --------
    >>> round(closed_form_plan(1000).seconds, 6), round(closed_form_plan(1000, maximum=True).seconds, 6)
    (0.21, 3.1)
    """
    dps = check_dps(dps)
    seconds = 0.1 + 3.0 * (dps / 1000) ** 1.5 if maximum else 0.05 + 8 * 0.02 * (dps / 1000) ** 1.8
    return Plan(f"closed forms (7.1)-(7.4) to {dps} digits", seconds, 50 * 2**20)


# ----------------------------------------------------------------- conversions


def _exact(value: Any, name: str, dps: int) -> Any:
    """A binary float where digits matter meets the one rule (refused, or warned about when ``dps`` digits are
    within its reach: :func:`forcenet.core.validation.check_float_digits`), once at a public boundary."""
    return check_float_digits(value, name, dps, stacklevel=3) if is_binary_float(value) else value


def _point(phi: Any, Q: Any) -> tuple[mpmath.mpf, mpmath.mpf | None]:
    """``(Q, phi)`` at the current precision from exactly one of them (in range)."""
    if (phi is None) == (Q is None):
        raise ArgumentTypeError("give exactly one of phi= and Q=")
    if Q is not None:
        q = to_mpf(Q, "Q")
        if not 0 <= q <= mpmath.mpf(1) / 3:
            raise ArgumentError(f"Q={Q} is out of range: the density per direction Q must lie in [0, 1/3]")
        return q, None
    x = to_mpf(phi, "phi")
    if not abs(x) <= mpmath.pi / 2:
        raise ArgumentError(f"phi={phi} is out of range: phi must lie in [-pi/2, pi/2] (Q from 1/3 to 0)")
    return _Q_of_phi(x), x


def _Q_of_phi(x: mpmath.mpf) -> mpmath.mpf:
    """(7.2) without cancellation at either end: ``Q = 2 tan t / (sqrt3 (1 + sqrt3 tan t))``, ``t = (pi/2 - phi)/6``."""
    t = mpmath.tan((mpmath.pi / 2 - x) / 6)
    return 2 * t / (mpmath.sqrt(3) * (1 + mpmath.sqrt(3) * t))


# ------------------------------------------------------ closed forms, working precision


@lru_cache(maxsize=4)
def _series_rationals(order: int) -> tuple[Fraction, ...]:
    """``[a_3, ..., a_order]`` of :func:`forcenet.exact.chicken_wire.closed_form.entropy_series_Q` (rationals)."""

    coeffs = series_coefficients(order)
    return tuple(Fraction(int(c.p), int(c.q)) for c in coeffs[3:])


def _series_terms(q: mpmath.mpf, dps: int) -> int | None:
    """Number of series terms for ``dps`` digits at ``q``, or None if the closed form is cheaper."""
    if q == 0:
        return 3
    ratio = 3 * q  # the coefficients grow like 3^k / k^3
    if ratio >= mpmath.mpf(10) ** -2:
        return None
    terms = int(dps / -mpmath.log10(ratio)) + 3
    cancellation_digits = 2 * -mpmath.log10(q)  # what the closed form would spend
    return terms if terms < 60 and cancellation_digits > 20 else None


def _v_series(q: mpmath.mpf, terms: int) -> mpmath.mpf:
    """``-3 q^2 log q + (3 log 2 - 9/2) q^2 + sum_{k>=3} a_k q^k`` (exact coefficients)."""
    if q == 0:
        return mpmath.mpf(0)
    value = -3 * q**2 * mpmath.log(q) + (3 * mpmath.log(2) - mpmath.mpf(9) / 2) * q**2
    power = q**2
    for a in _series_rationals(terms + 2):
        power *= q
        value += (mpmath.mpf(a.numerator) / a.denominator) * power
    return value


@lru_cache(maxsize=3)
def _closed_form(derivative: int) -> Callable[[mpmath.mpf], mpmath.mpf]:
    """``v``, ``mu = -(1/3) v'`` or ``dmu/dQ`` (``derivative`` 0, 1, 2) of the exact ``v(Q)`` as an mpmath function.

    Derived from the sympy expression of :func:`forcenet.exact.chicken_wire.closed_form.entropy_Q`
    (the elimination of (7.1)-(7.2)) and compiled by ``sympy.lambdify`` to
    mpmath, once per process and each only when first asked for.  Every
    constant (``log 4``, ``1/3``) is evaluated at the precision of the call, so
    callers evaluate inside ``mpmath.workdps`` (:func:`converged`).  The
    symbol carries no assumptions: sympy then builds and differentiates the
    expression several times faster, and the expression is the same.
    """

    q = sympy.Symbol("q")
    expr = entropy_Q(q)
    for k in range(derivative):
        expr = sympy.diff(expr, q) / (-3 if k == 0 else 1)
    return sympy.lambdify(q, expr, "mpmath")


def _v(q: mpmath.mpf) -> mpmath.mpf:
    """The closed form ``v(Q)`` at the working precision (0 at both ends, where ``x^2 log x -> 0``)."""
    if q == 0 or q == mpmath.mpf(1) / 3:
        return mpmath.mpf(0)
    return _closed_form(0)(q)


def _mu(q: mpmath.mpf) -> mpmath.mpf:
    """``mu = -(1/3) dv/dQ`` at the working precision (``0 < Q < 1/3``)."""
    return _closed_form(1)(q)


def _dmu(q: mpmath.mpf) -> mpmath.mpf:
    """``d mu / dQ = -(1/3) v''(Q)`` (for Newton's method at the maximum)."""
    return _closed_form(2)(q)


# ------------------------------------------------------------------ public functions


def density_Q(phi: RealLike, dps: int = 50) -> mpmath.mpf:
    """Density of bonds per direction (of left-moving particles) per site, Eq. (7.2).

    ``Q = 1/2 - cos(phi/3) / (2 sqrt3 (1 - sin(phi/3)))``, evaluated in a
    cancellation-free form.  ``Q(-pi/2) = 1/3`` (the honeycomb of walls),
    ``Q(pi/2) = 0`` (empty lattice).

    Examples
    --------
    >>> mpmath.nstr(density_Q(0, dps=20), 20)  # 1/2 - 1/(2 sqrt 3)
    '0.21132486540518711775'
    >>> mpmath.nstr(density_Q("1.0", dps=30), 25)
    '0.09455495911710849789324424'
    """
    dps = check_dps(dps)
    phi = _exact(phi, "phi", dps)
    return converged(lambda: _point(phi, None)[0], dps)


def density_Q_naive(phi: RealLike, dps: int = 50) -> mpmath.mpf:
    """Eq. (7.2) as printed, ``1/2 - cos(phi/3)/(2 sqrt3 (1 - sin(phi/3)))``, for comparison.

    Evaluated at the working precision without guard digits, so that the
    cancellation ``1 - sin(phi/3) -> 0`` (at ``phi -> 3 pi/2``, outside the
    physical range) shows in the tests.
    """
    dps = check_dps(dps)
    phi = _exact(phi, "phi", dps)
    with mpmath.workdps(dps):
        x = to_mpf(phi, "phi")
        return mpmath.mpf(1) / 2 - mpmath.cos(x / 3) / (2 * mpmath.sqrt(3) * (1 - mpmath.sin(x / 3)))


def phi_of_density(Q: RealLike, dps: int = 50) -> mpmath.mpf:
    """Inverse of (7.2): ``phi = 6 atan(sqrt3 (1 - 2Q)) - 3 pi/2``, ``0 <= Q <= 1/3``.

    Examples
    --------
    >>> mpmath.nstr(phi_of_density(0), 20)  # pi/2
    '1.5707963267948966192'
    >>> mpmath.nstr(phi_of_density(Fraction(1, 6), dps=15), 15)
    '0.430042706716096'
    """
    dps = check_dps(dps)
    Q = _exact(Q, "Q", dps)

    def compute() -> mpmath.mpf:
        q, _ = _point(None, Q)
        return 6 * (mpmath.atan(mpmath.sqrt(3) * (1 - 2 * q)) - mpmath.pi / 4)

    return converged(compute, dps)


def phi_within_range(text: str, strict: bool = False) -> bool:
    """Whether the decimal ``text`` satisfies ``|phi| <= pi/2`` (``< pi/2`` if ``strict``), decided exactly.

    The comparison runs with more digits than ``text`` has, so a value that
    rounds to pi/2 is not taken for it.

    Examples
    --------
    >>> phi_within_range("1.5707963267948966"), phi_within_range("1.5707963267948967")
    (True, False)
    """
    return within_pi(text, Fraction(1, 2), strict=strict, name="phi")  # the generic check of forcenet.core


def leading_series_at(eps: mpmath.mpf, dps: int, Q: RealLike | None = None) -> mpmath.mpf:
    """The corrected leading term of (7.3), ``eps^2 (log(108/eps^2) - 3)/18``, at ``eps``.

    At the density ``Q = 1/3`` exactly, ``eps = pi`` is taken exactly (a
    rounded ``eps`` may exceed pi in its last digit).

    Examples
    --------
    >>> mpmath.nstr(leading_series_at(mpmath.mpf("0.1"), 15), 10)
    '0.00349294523'
    """

    dps = check_dps(dps)
    return _series_7_3(mpmath.pi if Q is not None and Q == Fraction(1, 3) else eps, 2, dps)  # order 2: no argument


def eps_of(*, phi: RealLike | None = None, Q: RealLike | None = None, dps: int = 50) -> mpmath.mpf:
    """``eps = pi/2 - phi``, the small parameter of (7.3), from ``phi`` or ``Q`` (relative digits kept).

    Examples
    --------
    >>> mpmath.nstr(eps_of(Q="1e-20", dps=15), 15)  # ~ 3 sqrt3 Q
    '5.19615242270663e-20'
    """
    dps = check_dps(dps)
    phi = _exact(phi, "phi", dps)
    Q = _exact(Q, "Q", dps)

    def compute() -> mpmath.mpf:
        q, x = _point(phi, Q)
        if x is not None:
            return mpmath.pi / 2 - x
        return 2 * mpmath.pi - 6 * mpmath.atan(mpmath.sqrt(3) * (1 - 2 * q))

    return converged(compute, dps)


def entropy(*, phi: RealLike | None = None, Q: RealLike | None = None, dps: int = 50) -> mpmath.mpf:
    """Entropy per chicken-wire site on the isotropic line, Eq. (7.1), at ``phi`` or at density ``Q``.

    Parameters
    ----------
    phi : number or str, optional
        The parameter of (7.1)-(7.2), ``-pi/2 <= phi <= pi/2``.
    Q : number, str or Fraction, optional
        The bond density per direction, ``0 <= Q <= 1/3`` (give one of the two).
    dps : int
        Decimal digits of the result (5..10000).

    Returns
    -------
    mpmath.mpf
        ``v`` per site, correct to ``dps`` relative digits.

    Raises
    ------
    ArgumentError
        If ``phi`` or ``Q`` is out of range, both or neither is given, or ``dps`` is out of range.
    ArgumentTypeError
        If ``phi`` or ``Q`` is a binary float whose digits do not reach ``dps`` (pass ``'1/6'`` or
        ``Fraction(1, 6)``); within its digits it is accepted with a :class:`~forcenet.PrecisionWarning`.

    Examples
    --------
    >>> mpmath.nstr(entropy(Q="0.1", dps=20), 20)
    '0.040351006159081691057'
    >>> mpmath.nstr(entropy(phi=0, dps=20), 20)  # half the square-triangle maximum
    '0.060027624659270803917'
    >>> mpmath.nstr(entropy(Q="1e-30", dps=10), 10)  # ~ -3 Q^2 log Q: the series takes over
    '2.048120999e-58'
    """
    dps = check_dps(dps)
    phi = _exact(phi, "phi", dps)
    Q = _exact(Q, "Q", dps)

    def compute() -> mpmath.mpf:
        q, _ = _point(phi, Q)
        terms = _series_terms(q, mpmath.mp.dps)
        return _v_series(q, terms) if terms else _v(q)

    return converged(compute, dps)


def chemical_potential(*, phi: RealLike | None = None, Q: RealLike | None = None, dps: int = 50) -> mpmath.mpf:
    """``mu = -(1/3) dv/dQ``: the log-fugacity of each bond direction at density ``Q`` (``0 < Q < 1/3``).

    ``mu < 0`` below the maximum ``Q*``, ``mu > 0`` above; near ``Q*`` the
    cancellation is paid in precision (relative digits are kept).

    Examples
    --------
    >>> mpmath.nstr(chemical_potential(Q=Fraction(1, 6), dps=20), 20)
    '-0.042985271999763969878'
    """
    dps = check_dps(dps)
    phi = _exact(phi, "phi", dps)
    Q = _exact(Q, "Q", dps)

    def compute() -> mpmath.mpf:
        q, _ = _point(phi, Q)
        if not 0 < q < mpmath.mpf(1) / 3:
            raise ArgumentError(f"Q={mpmath.nstr(q, 15)} is out of range: mu needs 0 < Q < 1/3 (it diverges at the ends)")
        return _mu(q)

    return converged(compute, dps)


def empty_density(*, phi: RealLike | None = None, Q: RealLike | None = None, dps: int = 50) -> mpmath.mpf:
    """Empty sites per site, ``e = 1 - 3Q + 3Q^2 = 1/(2 (1 - sin(phi/3)))``: the tiling vertices per site.

    Examples
    --------
    >>> empty_density(phi=0, dps=20)
    mpf('0.5')
    """
    dps = check_dps(dps)
    phi = _exact(phi, "phi", dps)
    Q = _exact(Q, "Q", dps)

    def compute() -> mpmath.mpf:
        q, _ = _point(phi, Q)
        return 1 - 3 * q + 3 * q * q

    return converged(compute, dps)


def tiling_entropy(*, phi: RealLike | None = None, Q: RealLike | None = None, dps: int = 50) -> mpmath.mpf:
    """Entropy per vertex of the square-triangle tiling, ``s = v / e = 2 (1 - sin(phi/3)) v(phi)``.

    Its maximum, at the twelvefold point ``phi = 0``, is
    ``log 108 - 2 sqrt3 log(2 + sqrt3) = 0.1200552493...`` (Kalugin 1994).

    Parameters
    ----------
    phi : number or str, optional
        The parameter of (7.1)-(7.2), ``-pi/2 <= phi <= pi/2``.
    Q : number, str or Fraction, optional
        The bond density per direction, ``0 <= Q <= 1/3`` (give one of the two).
    dps : int
        Decimal digits of the result (5..10000).

    Returns
    -------
    mpmath.mpf
        ``s`` per tiling vertex (empty site), correct to ``dps`` relative digits.

    Raises
    ------
    ArgumentError
        As :func:`entropy`.
    ArgumentTypeError
        As :func:`entropy` (a binary float short of ``dps`` digits).

    Examples
    --------
    >>> mpmath.nstr(tiling_entropy(phi="0.3", dps=20), 20)
    '0.11294704937043980697'
    """
    dps = check_dps(dps)
    phi = _exact(phi, "phi", dps)
    Q = _exact(Q, "Q", dps)

    def compute() -> mpmath.mpf:
        q, _ = _point(phi, Q)
        terms = _series_terms(q, mpmath.mp.dps)
        v = _v_series(q, terms) if terms else _v(q)
        return v / (1 - 3 * q + 3 * q * q)

    return converged(compute, dps)


def entropy_series_7_3(eps: RealLike, order: int = 2, dps: int = 50) -> mpmath.mpf:
    """Eq. (7.3), corrected, truncated at ``eps^order``: ``v ~ eps^2 (log(108/eps^2) - 3)/18 + ...``, ``phi = pi/2 - eps``.

    ``order = 2`` is the thesis's leading term (with the sign of ``3``
    restored); ``order = 3, 4`` add the next two orders (exact coefficients,
    :func:`forcenet.exact.chicken_wire.closed_form.entropy_series_eps`).  An
    approximation of :func:`entropy` for small ``eps``, not the entropy itself.

    Examples
    --------
    >>> mpmath.nstr(entropy_series_7_3("0.01", dps=20), 12)
    '6.05137311061e-5'
    """
    dps = check_dps(dps)
    return _series_7_3(_exact(eps, "eps", dps), check_int(order, "order", 2, 8), dps)


def _series_7_3(eps: Any, order: int, dps: int) -> mpmath.mpf:
    """:func:`entropy_series_7_3` with ``order`` and ``dps`` checked by the caller."""
    f = _series_eps_function(order)

    def compute() -> mpmath.mpf:
        e = to_mpf(eps, "eps")
        if not 0 < e <= mpmath.pi:
            raise ArgumentError(f"eps={eps} is out of range: eps = pi/2 - phi must lie in (0, pi]")
        return f(e)

    return converged(compute, dps)


@lru_cache(maxsize=8)
def _series_eps_function(order: int) -> Callable[[mpmath.mpf], mpmath.mpf]:
    """The exact series (7.3) to ``eps^order`` as an mpmath function (sympy, once per order)."""

    return sympy.lambdify(EPS, entropy_series_eps(order), "mpmath")


def entropy_per_grain(l: RealLike, dps: int = 50) -> mpmath.mpf:
    """Eq. (7.4), corrected: entropy per grain ``g = log(6 l) - 3/2`` for hexagons of side ``l`` (force scale).

    The limit of ``3 l^2 v`` at ``eps = sqrt3 / l -> 0`` (one degree of
    freedom per grain: ``g(l) - g(1) = log l``).

    Examples
    --------
    >>> mpmath.nstr(entropy_per_grain(1, dps=20), 20)
    '0.29175946922805500081'
    """
    dps = check_dps(dps)
    l = _exact(l, "l", dps)

    def compute() -> mpmath.mpf:
        x = to_mpf(l, "l")
        if not x > 0:
            raise ArgumentError(f"l={l} is out of range: the hexagon side (force scale) must be a finite number > 0")
        return mpmath.log(6 * x) - mpmath.mpf(3) / 2

    return converged(compute, dps)


@dataclass(frozen=True)
class Maximum:
    """The two maxima on the isotropic line (all mpf, rounded to ``dps`` digits).

    * per chicken-wire site: ``v_max = v(Q_max)`` where ``mu = 0`` (all fugacities 1);
    * per tiling vertex: ``s_max = log 108 - 2 sqrt3 log(2 + sqrt3)`` at the
      twelvefold point ``phi = 0``, ``Q0 = (3 - sqrt3)/6``, with its composition.
    """

    dps: int
    Q_max: mpmath.mpf
    phi_max: mpmath.mpf
    v_max: mpmath.mpf
    s_max: mpmath.mpf
    Q0: mpmath.mpf
    v_at_Q0: mpmath.mpf
    empty_per_site: mpmath.mpf  # tiling vertices per site at Q0 (1/2)
    y_per_site: mpmath.mpf  # Y vertices (one kind) per site at Q0, 3 Q0^2
    squares_per_vertex: mpmath.mpf
    triangles_per_vertex: mpmath.mpf
    squares_per_triangle: mpmath.mpf  # sqrt3/4

    def as_dict(self) -> dict:
        return {k: (mpmath.nstr(v, self.dps) if k != "dps" else v) for k, v in self.__dict__.items()}


def maximum(dps: int = 50) -> Maximum:
    """Both maxima of the isotropic line, to ``dps`` digits (Newton on ``mu(Q) = 0``; closed forms).

    Examples
    --------
    >>> m = maximum(dps=15)
    >>> mpmath.nstr(m.s_max, 15), mpmath.nstr(m.squares_per_triangle, 15)  # sqrt3/4 at the twelvefold point
    ('0.120055249318542', '0.433012701892219')
    """
    dps = check_dps(dps)

    def q_star() -> mpmath.mpf:
        q = mpmath.mpf("0.1845564976")
        for _ in range(200):
            step = _mu(q) / _dmu(q)
            q -= step
            if abs(step) < mpmath.eps * 8:
                break
        return q

    Q_max = converged(q_star, dps)
    with mpmath.workdps(dps + GUARD):
        Q_str = mpmath.nstr(Q_max, dps + GUARD)
    v_max = converged(lambda: _v(q_star()), dps)

    def composition() -> tuple[mpmath.mpf, ...]:
        q0 = (3 - mpmath.sqrt(3)) / 6
        e0 = 1 - 3 * q0 + 3 * q0 * q0
        y0 = 3 * q0 * q0
        squares = 3 * q0 - 3 * y0  # pass-through sites: 2 p + 3 (2 y) = 6 Q bond ends
        triangles = 2 * (e0 - squares)  # V = N_t/2 + N_s per vertex angle sum
        return q0, e0, y0, squares / e0, triangles / e0, squares / triangles

    parts = [converged(functools.partial(lambda k: composition()[k], k), dps) for k in range(6)]
    return Maximum(
        dps=dps, Q_max=Q_max, phi_max=phi_of_density(Q_str, dps), v_max=v_max,
        s_max=converged(lambda: mpmath.log(108) - 2 * mpmath.sqrt(3) * mpmath.log(2 + mpmath.sqrt(3)), dps),
        Q0=parts[0], v_at_Q0=entropy(phi=0, dps=dps), empty_per_site=parts[1], y_per_site=parts[2],
        squares_per_vertex=parts[3], triangles_per_vertex=parts[4], squares_per_triangle=parts[5],
    )
