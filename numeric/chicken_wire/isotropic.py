"""Entropy of the chicken-wire model on the isotropic line (Sec. 7.4.1, Eqs. 7.1-7.4).

Two kinds of functions:

* closed forms reconstructed from the garbled thesis text, at any precision
  (mpmath): the density (7.2) as a function of the parameter ``phi`` and its
  inverse, the small-parameter expansion (7.3) and the entropy per grain (7.4);
* the entropy per site ``v(Q)`` computed independently of (7.1), from the
  twisted Bethe equations (:mod:`forcenet.numeric.chicken_wire.bethe`): for a rational density
  ``Q = c/a`` the sectors ``(L, n, m) = k (a, 2c, c)`` at the photon fugacity
  that makes all three particle densities equal ``Q``, extrapolated to
  ``L -> oo``.  Between rationals, ``v`` is interpolated with its exact
  derivative ``dv/dQ = -3 mu`` (Legendre: each of the three densities has
  the chemical potential ``mu``).

(7.1) itself is not reconstructed (notes/chicken_wire.md, Sec. 4); these
functions are what replaces it.

Examples
--------
>>> import mpmath
>>> mpmath.nstr(density_Q(0), 20)  # 1/2 - 1/(2 sqrt 3)
'0.21132486540518711775'
>>> mpmath.nstr(phi_of_density(Fraction(1, 6)), 15)
'0.430042706716096'
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction

import mpmath
import numpy as np

from forcenet.exact.validation import check_dps

__all__ = [
    "density_Q",
    "density_Q_naive",
    "phi_of_density",
    "entropy_small_parameter",
    "entropy_per_grain",
    "extrapolate",
    "IsotropicLimit",
    "isotropic_limit",
    "isotropic_entropy",
    "entropy_maximum",
    "bracketing_fractions",
]


def _check_phi(phi):
    x = mpmath.mpf(phi)
    if not (abs(x) <= mpmath.pi / 2 * (1 + mpmath.mpf(10) ** -15)):  # a rounded pi/2 is accepted
        raise ValueError(f"phi={mpmath.nstr(x, 15)}: out of range, the isotropic line is -pi/2 <= phi <= pi/2 (Q from 1/3 to 0)")
    return x


_check_dps = check_dps


def density_Q(phi, dps: int = 50):
    """Density of left-moving particles per site, Eq. (7.2), in a cancellation-free form.

    ``Q = 1/2 - cos(phi/3) / (2 sqrt3 (1 - sin(phi/3))) = 1/2 - tan(pi/4 + phi/6) / (2 sqrt3)``
    (``cos x / (1 - sin x) = tan(pi/4 + x/2)``).  ``Q(-pi/2) = 1/3`` (the
    honeycomb of walls), ``Q(pi/2) = 0`` (empty lattice).

    Parameters
    ----------
    phi : number or str
        The parameter of (7.1), ``-pi/2 <= phi <= pi/2``.
    dps : int
        Decimal digits.

    Examples
    --------
    >>> with mpmath.workdps(40):  # phi itself must carry the digits
    ...     mpmath.nstr(density_Q(-mpmath.pi / 2, dps=30), 30)
    '0.333333333333333333333333333333'
    >>> mpmath.nstr(density_Q("1.0", dps=30), 25)
    '0.09455495911710849789324424'
    """
    with mpmath.workdps(_check_dps(dps) + 10):
        x = _check_phi(phi)
        q = mpmath.mpf(1) / 2 - mpmath.tan(mpmath.pi / 4 + x / 6) / (2 * mpmath.sqrt(3))
    with mpmath.workdps(dps):
        return mpmath.mpf(q)


def density_Q_naive(phi, dps: int = 50):
    """Eq. (7.2) as printed, ``1/2 - cos(phi/3)/(2 sqrt3 (1 - sin(phi/3)))``, for comparison.

    Evaluated at the working precision without guard digits, so that the
    cancellation ``1 - sin(phi/3) -> 0`` (at ``phi -> 3 pi/2``, outside the
    physical range) shows in the tests.
    """
    with mpmath.workdps(_check_dps(dps)):
        x = mpmath.mpf(phi)
        return mpmath.mpf(1) / 2 - mpmath.cos(x / 3) / (2 * mpmath.sqrt(3) * (1 - mpmath.sin(x / 3)))


def phi_of_density(Q, dps: int = 50):
    """Inverse of (7.2): ``phi = 6 (atan(sqrt3 (1 - 2Q)) - pi/4)``, ``0 <= Q <= 1/3``.

    Examples
    --------
    >>> mpmath.nstr(phi_of_density(0), 20)  # pi/2
    '1.5707963267948966192'
    """
    with mpmath.workdps(_check_dps(dps) + 10):
        q = mpmath.mpf(Fraction(Q).numerator) / Fraction(Q).denominator if isinstance(Q, Fraction) else mpmath.mpf(Q)
        if not (0 <= q <= mpmath.mpf(1) / 3):
            raise ValueError(f"Q={Q!r}: the density per direction lies in 0..1/3")
        phi = 6 * (mpmath.atan(mpmath.sqrt(3) * (1 - 2 * q)) - mpmath.pi / 4)
    with mpmath.workdps(dps):
        return mpmath.mpf(phi)


def entropy_small_parameter(eps, dps: int = 50):
    """Reconstructed Eq. (7.3): ``v ~ eps^2 (1/6 + log(6 sqrt3)/9 - log(eps)/9)``, ``phi = pi/2 - eps``.

    The coefficient of ``eps^2 log eps`` is fixed by counting degrees of
    freedom (one per hexagon, notes/chicken_wire.md); the constant is read
    from the garbled text and is **not** confirmed by the Bethe ansatz (see
    the notes: at the densities reachable here it is not).

    Examples
    --------
    >>> mpmath.nstr(entropy_small_parameter("0.01", dps=20), 12)
    '9.38470644394e-5'
    """
    with mpmath.workdps(_check_dps(dps) + 10):
        e = mpmath.mpf(eps)
        if not e > 0:
            raise ValueError(f"eps={eps!r}: must be > 0")
        v = e**2 * (mpmath.mpf(1) / 6 + mpmath.log(6 * mpmath.sqrt(3)) / 9 - mpmath.log(e) / 9)
    with mpmath.workdps(dps):
        return mpmath.mpf(v)


def entropy_per_grain(F, dps: int = 50):
    """Reconstructed Eq. (7.4): entropy per grain ``g = 3/2 + log(6 F)`` at force scale ``F``.

    Examples
    --------
    >>> mpmath.nstr(entropy_per_grain(1, dps=20), 15)
    '3.29175946922806'
    """
    with mpmath.workdps(_check_dps(dps) + 10):
        f = mpmath.mpf(F)
        if not f > 0:
            raise ValueError(f"F={F!r}: the force scale must be > 0")
        g = mpmath.mpf(3) / 2 + mpmath.log(6 * f)
    with mpmath.workdps(dps):
        return mpmath.mpf(g)


# ----------------------------------------------------------- the Bethe-ansatz route


def extrapolate(Ls, values, points: int = 8):
    """``(limit, error)`` of a finite-size sequence: fits ``c0 + c1/L^2 (+ c2/L^4)``.

    The limit is the three-term fit over the last ``points`` values; the
    error is its difference from the two-term fit.
    """
    Ls = np.asarray(Ls[-points:], dtype=float)
    values = np.asarray(values[-points:], dtype=float)
    if len(Ls) < 4:
        raise ValueError(f"need at least 4 system sizes to extrapolate, got {len(Ls)}")
    A2 = np.vstack([np.ones_like(Ls), Ls**-2.0]).T
    A4 = np.vstack([np.ones_like(Ls), Ls**-2.0, Ls**-4.0]).T
    c2 = np.linalg.lstsq(A2, values, rcond=None)[0][0]
    c4 = np.linalg.lstsq(A4, values, rcond=None)[0][0]
    return float(c4), float(abs(c4 - c2))


@dataclass
class IsotropicLimit:
    """``v`` and ``mu`` at density ``Q`` in the limit ``L -> oo``, with error estimates."""

    Q: Fraction
    v: float
    v_err: float
    mu: float
    mu_err: float
    L: list

    @property
    def phi(self) -> float:
        return float(phi_of_density(self.Q, dps=20))


def isotropic_limit(Q, L_max: int = 240, L_min: int = 60, progress=None) -> IsotropicLimit:
    """Entropy per site at the rational density ``Q = c/a`` on the isotropic line, ``L -> oo``.

    Sectors ``(L, n, m) = k (a, 2c, c)`` for ``L_min <= L <= L_max`` at the
    isotropic fugacity (:func:`forcenet.numeric.chicken_wire.bethe.isotropic_sequence`), then
    :func:`extrapolate`.  Raises ``RuntimeError`` where the continuation
    loses the ground state (reported, never silent).

    Examples
    --------
    >>> lim = isotropic_limit(Fraction(1, 6), L_max=120, L_min=48)
    >>> round(lim.v, 6), round(lim.mu, 3)
    (0.061616, -0.043)
    """
    from .bethe import isotropic_sequence

    Q = Fraction(Q)
    if not (0 < Q < Fraction(1, 3)):
        raise ValueError(f"Q={Q}: the Bethe route needs 0 < Q < 1/3")
    a, c = Q.denominator, Q.numerator
    ks = range(max(2, -(-L_min // a)), L_max // a + 1)
    if len(ks) < 4:
        raise ValueError(f"L_max={L_max}: need at least 4 widths that are multiples of {a} in [{L_min}, {L_max}]")
    pts = isotropic_sequence(ks, ratio=(a, 2 * c, c), progress=progress)
    Ls = [p.L for p in pts]
    v, v_err = extrapolate(Ls, [p.entropy_per_site for p in pts])
    mu, mu_err = extrapolate(Ls, [p.log_fugacity for p in pts])
    return IsotropicLimit(Q, v, v_err, mu, mu_err, Ls)


def _hermite(q0, q1, v0, v1, d0, d1, q):
    """Cubic Hermite interpolation of ``v`` with slopes ``d`` on ``[q0, q1]``."""
    h = q1 - q0
    t = (q - q0) / h
    h00, h10, h01, h11 = 2 * t**3 - 3 * t**2 + 1, t**3 - 2 * t**2 + t, -2 * t**3 + 3 * t**2, t**3 - t**2
    return h00 * v0 + h10 * h * d0 + h01 * v1 + h11 * h * d1


def bracketing_fractions(Q: float, max_denominator: int = 16):
    """The nearest fractions ``c/a <= Q <= c'/a'`` with ``a <= max_denominator``, inside ``(0, 1/3)``."""
    cands = sorted({Fraction(c, a) for a in range(3, max_denominator + 1) for c in range(1, a) if Fraction(c, a) < Fraction(1, 3)})
    lo = max((f for f in cands if f <= Q), default=None)
    hi = min((f for f in cands if f >= Q), default=None)
    if lo is None or hi is None:
        raise ValueError(f"Q={Q}: outside the fractions c/a <= 16 available to the Bethe route")
    return lo, hi


def isotropic_entropy(Q, L_max: int = 240, L_min: int = 60, max_denominator: int = 16, limits=None):
    """``v(Q)`` at any density by Hermite interpolation between two rational densities.

    Uses ``v`` and its exact slope ``-3 mu`` at the bracketing fractions.
    The error adds the extrapolation errors and the difference between the
    cubic and the quadratic interpolant (which ignores the slope at the right end).

    Returns ``(v, error, (lo, hi))`` with the two :class:`IsotropicLimit` used.
    """
    Q = float(Q)
    lo, hi = bracketing_fractions(Q, max_denominator)
    limits = dict(limits or {})
    for f in (lo, hi):
        if f not in limits:
            limits[f] = isotropic_limit(f, L_max, L_min)
    a, b = limits[lo], limits[hi]
    if lo == hi:
        return a.v, a.v_err, (a, b)
    v, err = _interpolate(a, b, Q)
    return v, err, (a, b)


def _interpolate(a: IsotropicLimit, b: IsotropicLimit, Q: float):
    q0, q1 = float(a.Q), float(b.Q)
    v = _hermite(q0, q1, a.v, b.v, -3 * a.mu, -3 * b.mu, Q)
    # quadratic through v0, v1 with the slope at q0 only: a bound on the interpolation error
    h, t = q1 - q0, (Q - q0) / (q1 - q0)
    quad = a.v + (-3 * a.mu) * h * t + (b.v - a.v - (-3 * a.mu) * h) * t**2
    err = max(a.v_err, b.v_err) + 3 * max(a.mu_err, b.mu_err) * h + abs(v - quad)
    return v, err


def entropy_maximum(densities=(Fraction(1, 7), Fraction(1, 6), Fraction(2, 11)), L_max: int = 240, L_min: int = 60, limits=None, progress=None):
    """Maximum of ``v(Q)`` on the isotropic line: where ``mu(Q) = 0`` (all fugacities 1).

    ``mu`` is known at the given rational densities (at least three); the
    quadratic through the last three gives the zero ``Q*`` and
    ``v* = v(Q_last) - 3 int_{Q_last}^{Q*} mu dQ``.  The error adds the
    extrapolation errors and the change when the linear fit through the last
    two points is used instead.  The default densities lie below the maximum
    (``mu < 0``), because the fugacity-1 continuation loses the ground state
    at higher densities (``Q = 1/5, 3/16``; notes/chicken_wire.md), so ``Q*``
    is a short extrapolation (``Q* - 2/11 ~ 0.003``).

    Returns ``(Q*, v*, error, limits)``.
    """
    densities = sorted(Fraction(d) for d in densities)
    if len(densities) < 3:
        raise ValueError(f"densities={densities}: need at least three")
    limits = dict(limits or {})
    for f in densities:
        if f not in limits:
            limits[f] = isotropic_limit(f, L_max, L_min)
            if progress is not None:
                progress(1)
    pts = [limits[f] for f in densities[-3:]]
    qs = np.array([float(p.Q) for p in pts])
    mus = np.array([p.mu for p in pts])
    quad = np.polyfit(qs, mus, 2)
    lin = np.polyfit(qs[-2:], mus[-2:], 1)
    roots = [r.real for r in np.roots(quad) if abs(r.imag) < 1e-12 and 0 < r.real < 1 / 3]
    if not roots:
        raise RuntimeError(f"mu(Q) has no zero near the densities {densities}")
    q_star = min(roots, key=lambda r: abs(r - qs[-1]))
    q_lin = -lin[1] / lin[0]
    last = pts[-1]

    def v_at(poly, q):
        integral = np.polyval(np.polyint(poly), q) - np.polyval(np.polyint(poly), qs[-1])
        return last.v - 3 * integral

    v_star = v_at(quad, q_star)
    err = last.v_err + 3 * max(p.mu_err for p in pts) * abs(q_star - qs[-1]) + abs(v_star - v_at(lin, q_lin))
    return float(q_star), float(v_star), float(err), limits
