"""The isotropic line of the chicken-wire model from the Bethe ansatz: the independent route.

For a rational density ``Q = c/a`` the sectors ``(L, n, m) = k (a, 2c, c)`` are
solved at the photon fugacity that makes all three bond densities equal
``Q`` (:func:`forcenet.numeric.chicken_wire.bethe.isotropic_sequence`), and
the entropy per site ``v`` and the log-fugacity ``mu`` are extrapolated to
``L -> oo`` (:func:`extrapolate`).  Between rationals, ``v`` is interpolated
with its exact slope ``dv/dQ = -3 mu`` (Legendre).  This route knows nothing
of the closed form (7.1) (:mod:`.isotropic`), which the tests check against it.

Examples
--------
>>> lim = isotropic_limit(Fraction(1, 6), L_max=120, L_min=48)
>>> round(lim.v, 6), round(lim.mu, 3)
(0.061616, -0.043)
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass
from fractions import Fraction
from typing import Any

import numpy as np

from forcenet.core.errors import ArgumentError, ConvergenceError
from forcenet.core.plan import Plan
from forcenet.core.validation import check_int, check_rational

from .bethe import isotropic_sequence

__all__ = [
    "extrapolate",
    "IsotropicLimit",
    "isotropic_limit",
    "bracketing_fractions",
    "bethe_entropy",
    "bethe_entropy_maximum",
    "bethe_plan",
    "DIRECT_DENOMINATOR",
    "MIN_L_MAX",
    "MAX_L_MAX",
    "isotropic_entropy_plan",
    "isotropic_entropy",
]


def extrapolate(Ls: Sequence[float], values: Sequence[float], points: int = 8) -> tuple[float, float]:
    """``(limit, error)`` of a finite-size sequence: fits ``c0 + c1/L^2 (+ c2/L^4)``.

    The limit is the three-term fit over the last ``points`` values; the
    error is its difference from the two-term fit.
    """
    x = np.asarray(Ls[-points:], dtype=float)
    y = np.asarray(values[-points:], dtype=float)
    if len(x) < 4:
        raise ArgumentError(f"need at least 4 system sizes to extrapolate, got {len(x)}")
    A2 = np.vstack([np.ones_like(x), x**-2.0]).T
    A4 = np.vstack([np.ones_like(x), x**-2.0, x**-4.0]).T
    c2 = np.linalg.lstsq(A2, y, rcond=None)[0][0]
    c4 = np.linalg.lstsq(A4, y, rcond=None)[0][0]
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


def isotropic_limit(Q: Fraction | int | str | float, L_max: int = 240, L_min: int = 60, progress: Callable[[int], object] | None = None) -> IsotropicLimit:
    """Entropy per site at the rational density ``Q = c/a`` on the isotropic line, ``L -> oo``.

    Sectors ``(L, n, m) = k (a, 2c, c)`` for ``L_min <= L <= L_max`` at the
    isotropic fugacity (:func:`forcenet.numeric.chicken_wire.bethe.isotropic_sequence`), then
    :func:`extrapolate`.  Raises :class:`~forcenet.core.errors.ConvergenceError` where the continuation
    loses the ground state (reported, never silent).

    """

    Q = check_rational(Q, "Q")  # a binary float is refused: the widths are multiples of Q's denominator
    if not (0 < Q < Fraction(1, 3)):
        raise ArgumentError(f"Q={Q}: the Bethe route needs 0 < Q < 1/3")
    a, c = Q.denominator, Q.numerator
    ks = range(max(2, -(-L_min // a)), L_max // a + 1)
    if len(ks) < 4:
        raise ArgumentError(f"L_max={L_max}: need at least 4 widths that are multiples of {a} in [{L_min}, {L_max}]")
    pts = isotropic_sequence(ks, ratio=(a, 2 * c, c), progress=progress)
    Ls = [p.L for p in pts]
    v, v_err = extrapolate(Ls, [p.entropy_per_site for p in pts])
    mu, mu_err = extrapolate(Ls, [p.log_fugacity for p in pts])
    return IsotropicLimit(Q, v, v_err, mu, mu_err, Ls)


def _hermite(q0: float, q1: float, v0: float, v1: float, d0: float, d1: float, q: float) -> float:
    """Cubic Hermite interpolation of ``v`` with slopes ``d`` on ``[q0, q1]``."""
    h = q1 - q0
    t = (q - q0) / h
    h00, h10, h01, h11 = 2 * t**3 - 3 * t**2 + 1, t**3 - 2 * t**2 + t, -2 * t**3 + 3 * t**2, t**3 - t**2
    return h00 * v0 + h10 * h * d0 + h01 * v1 + h11 * h * d1


def bracketing_fractions(Q: float, max_denominator: int = 16) -> tuple[Fraction, Fraction]:
    """The nearest fractions ``c/a <= Q <= c'/a'`` with ``a <= max_denominator``, inside ``(0, 1/3)``."""
    cands = sorted({Fraction(c, a) for a in range(3, max_denominator + 1) for c in range(1, a) if Fraction(c, a) < Fraction(1, 3)})
    lo = max((f for f in cands if f <= Q), default=None)
    hi = min((f for f in cands if f >= Q), default=None)
    if lo is None or hi is None:
        raise ArgumentError(f"Q={Q}: outside the fractions c/a <= 16 available to the Bethe route")
    return lo, hi


def bethe_entropy(Q: float, L_max: int = 240, L_min: int = 60, max_denominator: int = 16,
                  limits: dict[Fraction, IsotropicLimit] | None = None) -> tuple[float, float, tuple[IsotropicLimit, IsotropicLimit]]:
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


def _interpolate(a: IsotropicLimit, b: IsotropicLimit, Q: float) -> tuple[float, float]:
    q0, q1 = float(a.Q), float(b.Q)
    v = _hermite(q0, q1, a.v, b.v, -3 * a.mu, -3 * b.mu, Q)
    # quadratic through v0, v1 with the slope at q0 only: a bound on the interpolation error
    h, t = q1 - q0, (Q - q0) / (q1 - q0)
    quad = a.v + (-3 * a.mu) * h * t + (b.v - a.v - (-3 * a.mu) * h) * t**2
    err = max(a.v_err, b.v_err) + 3 * max(a.mu_err, b.mu_err) * h + abs(v - quad)
    return v, err


def bethe_entropy_maximum(densities: Iterable[Fraction] = (Fraction(1, 7), Fraction(1, 6), Fraction(2, 11)), L_max: int = 240,
                          L_min: int = 60, limits: dict[Fraction, IsotropicLimit] | None = None,
                          progress: Callable[[int], object] | None = None) -> tuple[float, float, float, dict[Fraction, IsotropicLimit]]:
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
        raise ArgumentError(f"densities={densities}: need at least three")
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
        raise ConvergenceError(f"mu(Q) has no zero near the densities {densities}")
    q_star = min(roots, key=lambda r: abs(r - qs[-1]))
    q_lin = -lin[1] / lin[0]
    last = pts[-1]

    def v_at(poly: np.ndarray, q: float) -> Any:
        integral = np.polyval(np.polyint(poly), q) - np.polyval(np.polyint(poly), qs[-1])
        return last.v - 3 * integral

    v_star = v_at(quad, q_star)
    err = last.v_err + 3 * max(p.mu_err for p in pts) * abs(q_star - qs[-1]) + abs(v_star - v_at(lin, q_lin))
    return float(q_star), float(v_star), float(err), limits


# seconds of one isotropic sequence to L_max in a fresh process on the 2-core machine, single-threaded BLAS
# (Q = 1/6: L <= 120 7.7 s, L <= 240 11 s, L <= 600 144 s; 2026-11-23)
def bethe_plan(sequences: int, L_max: int) -> Plan:
    """The cost of ``sequences`` isotropic Bethe sequences up to width ``L_max``.

    Parameters
    ----------
    sequences : int
        Number of rational densities whose sequences are solved.
    L_max : int
        Largest width.

    Returns
    -------
    Plan
        One tick per sequence.

    Examples
    --------
    >>> bethe_plan(1, 240).seconds < 60
    True
    """
    seconds = sequences * (3.0 + 9.0 * (L_max / 240) ** 2.8)
    return Plan(f"{sequences} Bethe-ansatz sequence(s) to L = {L_max}", seconds, 200 * 2**20, sequences, "sequence")


MIN_L_MAX, MAX_L_MAX = 60, 1200  # the widths' sequences: 1200 plans ~14 min (one sequence) to ~27 min (two)
DIRECT_DENOMINATOR = 60  # a density c/a with a <= 60 is solved directly (widths L = k a, k >= 2: 4 of them need
# L_max >= 5a, i.e. a <= 48 at the default 240; the plan names the L_max a larger a needs)


def _direct(Q: Fraction | float | None) -> bool:
    """Whether :func:`isotropic_entropy` solves ``Q`` itself (one sequence) rather than interpolating (two)."""
    return isinstance(Q, Fraction) and Q.denominator <= DIRECT_DENOMINATOR


def _check_density(Q: Fraction | float) -> None:
    if not 0 < Q < Fraction(1, 3):
        raise ArgumentError(f"Q={float(Q):g} is out of range: the Bethe route needs 0 < Q < 1/3")


def isotropic_entropy_plan(Q: Fraction | float | None, L_max: int) -> Plan:
    """The cost of :func:`isotropic_entropy` at ``Q`` (None: a density known only as a number, from ``phi``).

    Parameters
    ----------
    Q : Fraction, float or None
        The density; a Fraction with denominator at most
        :data:`DIRECT_DENOMINATOR` costs one sequence, anything else two.
    L_max : int
        Largest width, ``60..1200`` (:data:`MIN_L_MAX`, :data:`MAX_L_MAX`).

    Returns
    -------
    Plan
        Refused (naming ``Q``) outside ``0 < Q < 1/3``.

    Raises
    ------
    ArgumentError
        If ``L_max`` is out of range.

    Examples
    --------
    >>> isotropic_entropy_plan(Fraction(1, 6), 240).ticks, isotropic_entropy_plan(0.2, 240).ticks
    (1, 2)
    >>> isotropic_entropy_plan(Fraction(1, 3), 240).refusal
    'Q=0.333333 is out of range: the Bethe route needs 0 < Q < 1/3'
    """
    L_max = check_int(L_max, "L_max", MIN_L_MAX, MAX_L_MAX)
    plan = bethe_plan(1 if _direct(Q) else 2, L_max)
    if Q is not None:
        try:
            _check_density(Q)
        except ArgumentError as exc:
            return plan.refuse(str(exc))
    # the widths: every density solved needs 4 multiples of its denominator in [L_min, L_max] (isotropic_limit)
    if isinstance(Q, Fraction) and _direct(Q):
        denominators = [Q.denominator]
    elif Q is not None:
        try:
            denominators = [f.denominator for f in bracketing_fractions(float(Q))]
        except ArgumentError as exc:  # below 1/16 or above 5/16: no two fractions to interpolate between
            return plan.refuse(str(exc))
    else:  # a density known only once phi is solved: any bracketing denominator up to 16 may come
        denominators = list(range(3, 17))
    short = [a for a in denominators if _widths(a, L_max) < 4]
    if short:
        need = min(L for L in range(L_max, 100 * max(short)) if all(_widths(a, L) >= 4 for a in denominators))
        which = f"Q={Q}" if Q is not None else "a density given by --phi (a bracketing fraction c/a, a <= 16)"
        return plan.refuse(f"L_max={L_max} is out of range for {which}: the widths L = k a in "
                           f"[max(24, L_max/4), L_max] must give 4 for a = {', '.join(map(str, short))}; "
                           f"L_max must be at least {need}")
    return plan


def _widths(a: int, L_max: int) -> int:
    """How many widths ``L = k a`` (``k >= 2``) :func:`isotropic_entropy` takes in ``[max(24, L_max // 4), L_max]``."""
    L_min = max(24, L_max // 4)
    return len(range(max(2, -(-L_min // a)), L_max // a + 1))


def isotropic_entropy(Q: Fraction | float, L_max: int = 240) -> tuple[float, float, tuple[Fraction, ...]]:
    """``v(Q)`` from the Bethe ansatz alone, with its error and the rational densities solved.

    A Fraction with denominator at most :data:`DIRECT_DENOMINATOR` is solved
    directly (:func:`isotropic_limit`), any other density interpolated
    between two (:func:`bethe_entropy`); widths ``max(24, L_max / 4) <= L <= L_max``.

    Parameters
    ----------
    Q : Fraction or float
        The density, ``0 < Q < 1/3``.
    L_max : int
        Largest width, ``>= 60``.

    Returns
    -------
    tuple
        ``(v, error, densities)``.

    Raises
    ------
    ArgumentError
        If ``Q`` or ``L_max`` is out of range.
    ConvergenceError
        Where a continuation loses the ground state.

    Examples
    --------
    >>> v, err, densities = isotropic_entropy(Fraction(1, 6), L_max=120)
    >>> round(v, 6), densities
    (0.061616, (Fraction(1, 6),))
    """
    L_max = check_int(L_max, "L_max", 60)
    _check_density(Q)
    L_min = max(24, L_max // 4)
    if _direct(Q):
        lim = isotropic_limit(Q, L_max, L_min)
        return lim.v, lim.v_err, (lim.Q,)
    v, err, (a, b) = bethe_entropy(float(Q), L_max, L_min)
    return v, err, (a.Q, b.Q)
