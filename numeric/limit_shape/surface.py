"""The scaling limit of the response of the fully mobilized triangle.

A uniform standard tableau of the shifted staircase ``(n, ..., 1)`` has, as
``n -> infinity``, ``T(r, c) / d -> L(r/n, c/n)`` where ``L`` is the limit
surface of uniform *square* tableaux (Pittel and Romik 2007) restricted to
the half square ``x <= y`` (Linusson, Potka and Sulzgruber 2020).  In the
rotated coordinates ``u = x - y``, ``v = x + y`` the level curve ``L = a`` is
``v = h_a(u)`` with ``k = sqrt(4a(1-a) - u^2)`` and (Maslanka and Sniady 2022)

    h_a(u) = (2u/pi) arctan((1-2a) u / k) + (2/pi) arctan(k / (1-2a)),        a < 1/2,
    h_a(u) = 2 - (2u/pi) arctan((2a-1) u / k) - (2/pi) arctan(k / (2a-1)),    a > 1/2,

and ``h_{1/2} = 1``.  Since ``<W_{i,j}> = (E T(a) - E T(b)) / (d + 1)`` for the
diagonal neighbours ``a = (j, N-i+j)``, ``b = (j-1, N-i+j-1)``
(``notes/order_polytope.md``), with ``z = i/N`` and ``x = (2j - i - 1)/N``
(so that the lattice directions are ``|x| = z``):

* bulk: ``N <W> -> G(x, z) = 2 dL/dv`` at ``u = z - 1``, ``v = 1 + x``;
* lattice directions: ``<W_{i,1}> = <W_{i,i}> -> L`` at ``u = z - 1``, ``v = 1 - z``,
  on the edge of the square, where the level curve of ``a`` ends
  (``k = 0``): ``<W> -> (1 - sqrt(z (2 - z))) / 2``;
* bottom row (``z = 1``, the diagonal ``L(t, t) = sin^2(pi t / 2)``):
  ``G(x, 1) = (pi/2) cos(pi x / 2)``.

Derivation and checks against exact tables: ``notes/scaling_limit.md``.
Precision is a parameter: every function converts its inputs inside
``mpmath.workdps(dps + 10)`` (strings keep all their digits; :mod:`forcenet.core.precision`), computes with
those guard digits and returns an mpf rounded to ``dps`` digits; no global
precision is set, and points outside a function's domain raise
``ArgumentError`` (never a complex number).

Examples
--------
>>> import mpmath
>>> mpmath.nstr(bulk_response(0, 1, dps=30), 30)  # pi/2 at the bottom centre
'1.57079632679489661923132169164'
>>> mpmath.nstr(lattice_response("0.5", dps=20), 20)  # (1 - sqrt(3/4)) / 2
'0.066987298107780676618'
"""

from __future__ import annotations

from typing import Any

import mpmath

from forcenet.core.errors import ArgumentError
from forcenet.core.precision import GUARD, RealLike, guarded, to_mpf
from forcenet.core.validation import check_dps

__all__ = ["level_curve", "level_curve_slope", "limit_surface", "bulk_response", "lattice_response"]



def _in_interval(x: mpmath.mpf, name: str, low: float, high: float, low_open: bool = False,
                 high_open: bool = False) -> mpmath.mpf:
    bad = (x <= low if low_open else x < low) or (x >= high if high_open else x > high)
    if bad:
        lb, hb = "(" if low_open else "[", ")" if high_open else "]"
        raise ArgumentError(f"{name}={mpmath.nstr(x, 15)} is out of range: {name} must lie in {lb}{low}, {high}{hb}")
    return x


def _level_curve(a: mpmath.mpf, u: mpmath.mpf) -> mpmath.mpf:
    """``h_a(u)`` at the working precision (a, u already mpf and in range)."""
    b = 1 - 2 * a
    if b == 0:
        return mpmath.mpf(1)
    if b < 0:
        return 2 - _level_curve(1 - a, u)
    k = mpmath.sqrt(4 * a * (1 - a) - u * u)
    inner = mpmath.atan(b * u / k) if k else mpmath.sign(u) * mpmath.pi / 2
    return 2 * u / mpmath.pi * inner + 2 / mpmath.pi * mpmath.atan(k / b)


def _slope(a: mpmath.mpf, u: mpmath.mpf) -> mpmath.mpf:
    """``dh_a/da = k / (pi a (1 - a))`` at the working precision."""
    return mpmath.sqrt(4 * a * (1 - a) - u * u) / (mpmath.pi * a * (1 - a))


def _checked_level_point(a: Any, u: Any) -> tuple[mpmath.mpf, mpmath.mpf]:
    a = _in_interval(to_mpf(a, "a"), "a", 0, 1, True, True)
    u = to_mpf(u, "u")
    if 4 * a * (1 - a) - u * u < 0:
        raise ArgumentError(f"u={mpmath.nstr(u, 15)} is out of range: outside the level curve of a={mpmath.nstr(a, 15)} "
                         "(need u^2 <= 4a(1-a))")
    return a, u


def level_curve(a: RealLike, u: RealLike, dps: int = 30) -> mpmath.mpf:
    """``h_a(u)``: the ``v = x + y`` of the level curve ``L = a`` at ``u = x - y`` (scaling limit, Sec. 4.8).

    Defined for ``0 < a < 1`` and ``u^2 <= 4a(1-a)``; raises ``ArgumentError`` outside.

    Parameters
    ----------
    a : int, float, str, Fraction or mpmath.mpf
        The level, ``0 < a < 1``.
    u : int, float, str, Fraction or mpmath.mpf
        Rotated coordinate, ``u^2 <= 4a(1-a)``.
    dps : int
        Decimal digits of the result, ``5..10000``; the work runs with guard digits.

    Returns
    -------
    mpmath.mpf

    Raises
    ------
    ArgumentError
        If ``a`` or ``u`` is out of range, or ``dps`` outside ``5..10000``.

    Examples
    --------
    >>> level_curve(0.5, 0.3)
    mpf('1.0')
    >>> mpmath.nstr(level_curve("0.2", "0.1", dps=30), 30)
    '0.592728925371743062936460766685'
    """
    dps = check_dps(dps)
    return guarded(lambda: _level_curve(*_checked_level_point(a, u)), dps)


def level_curve_slope(a: RealLike, u: RealLike, dps: int = 30) -> mpmath.mpf:
    """``dh_a(u)/da = k / (pi a (1 - a))``, ``k = sqrt(4a(1-a) - u^2)`` (derived in the notes).

    Defined where :func:`level_curve` is; raises ``ArgumentError`` outside (never a complex number).

    Parameters
    ----------
    a : int, float, str, Fraction or mpmath.mpf
        The level, ``0 < a < 1``.
    u : int, float, str, Fraction or mpmath.mpf
        Rotated coordinate, ``u^2 <= 4a(1-a)``.
    dps : int
        Decimal digits of the result, ``5..10000``; the work runs with guard digits.

    Returns
    -------
    mpmath.mpf

    Raises
    ------
    ArgumentError
        If ``a`` or ``u`` is out of range, or ``dps`` outside ``5..10000``.

    Examples
    --------
    >>> mpmath.nstr(level_curve_slope("0.5", 0, dps=20), 20)  # 4/pi
    '1.2732395447351626862'
    >>> level_curve_slope(0.1, 0.9)
    Traceback (most recent call last):
    ...
    forcenet.core.errors.ArgumentError: u=0.9 is out of range: outside the level curve of a=0.1 (need u^2 <= 4a(1-a))
    """
    dps = check_dps(dps)
    return guarded(lambda: _slope(*_checked_level_point(a, u)), dps)


def _limit_surface(u: mpmath.mpf, v: mpmath.mpf, dps: int) -> mpmath.mpf:
    """``L(u, v)`` at the working precision (u, v in the square)."""
    lo = (1 - mpmath.sqrt(1 - u * u)) / 2  # the level curve of lo ends on the edge at u
    hi = 1 - lo
    if v <= abs(u):  # lower edges of the square: h_lo(u) = |u|
        return lo
    if v >= 2 - abs(u):
        return hi
    eps = (hi - lo) * mpmath.mpf(10) ** (-(dps + GUARD // 2))  # relative to the bracket (narrow at small depth)
    def f(a: mpmath.mpf) -> mpmath.mpf:  # increasing in a
        return _level_curve(a, u) - v

    a = mpmath.findroot(f, (lo + eps, hi - eps), solver="anderson", tol=eps)
    for _ in range(4):  # Newton polish with dh/da = k / (pi a (1 - a))
        a -= f(a) / _slope(a, u)
    return a


def limit_surface(u: RealLike, v: RealLike, dps: int = 30) -> mpmath.mpf:
    """The limit surface ``L`` (Sec. 4.8) at rotated coordinates ``(u, v)``, ``|u| + |v - 1| <= 1``, by root finding.

    Parameters
    ----------
    u : int, float, str, Fraction or mpmath.mpf
        Rotated coordinate ``u = z - 1``.
    v : int, float, str, Fraction or mpmath.mpf
        Rotated coordinate ``v = 1 + x``.
    dps : int
        Decimal digits of the result, ``5..10000``; the work runs with guard digits.

    Returns
    -------
    mpmath.mpf
        The level ``a`` whose curve passes through ``(u, v)``.

    Raises
    ------
    ArgumentError
        If ``(u, v)`` is outside the square, or ``dps`` outside ``5..10000``.

    Examples
    --------
    >>> limit_surface(0, 1)
    mpf('0.5')
    >>> mpmath.nstr(limit_surface(0, "0.5", dps=20), 20)  # the diagonal: sin(pi/8)^2
    '0.1464466094067262378'
    """
    dps = check_dps(dps)

    def compute() -> mpmath.mpf:
        x, y = to_mpf(u, "u"), to_mpf(v, "v")
        if abs(x) + abs(y - 1) > 1:
            raise ArgumentError(f"(u, v)=({mpmath.nstr(x, 15)}, {mpmath.nstr(y, 15)}) is out of range: "
                             "outside the square |u| + |v - 1| <= 1")
        return _limit_surface(x, y, dps)

    return guarded(compute, dps)


def _depth_digits(depth: mpmath.mpf) -> int:
    """Extra working digits at a small depth ``z``: ``u = z - 1`` and ``v = 1 + x`` keep every digit of ``z`` and ``x``."""
    return max(0, -int(mpmath.floor(mpmath.log10(depth))))


def lattice_response(z: RealLike, dps: int = 30) -> mpmath.mpf:
    """Limit of ``<W_{i,1}> = <W_{i,i}>`` at depth ``z = i/N``, ``0 <= z <= 1`` (N-independent; Sec. 4.8).

    Parameters
    ----------
    z : int, float, str, Fraction or mpmath.mpf
        Depth ``z = i/N``, ``0 <= z <= 1``.
    dps : int
        Decimal digits of the result, ``5..10000``; the work runs with guard digits.

    Returns
    -------
    mpmath.mpf

    Raises
    ------
    ArgumentError
        If ``z`` is outside ``[0, 1]``, or ``dps`` outside ``5..10000``.

    Examples
    --------
    >>> lattice_response(1)
    mpf('0.0')
    """
    dps = check_dps(dps)

    def compute() -> mpmath.mpf:
        depth = _in_interval(to_mpf(z, "z"), "z", 0, 1)
        if depth == 0:
            return mpmath.mpf(1)
        with mpmath.workdps(mpmath.mp.dps + _depth_digits(depth)):
            depth = to_mpf(z, "z")
            return _limit_surface(depth - 1, 1 - depth, dps)

    return guarded(compute, dps)


def bulk_response(x: RealLike, z: RealLike, dps: int = 30) -> mpmath.mpf:
    """Limit of ``N <W>`` at ``(x, z)``, ``|x| < z <= 1``: ``2 dL/dv`` (the 1/N bulk of Sec. 4.8, Fig. 3.5).

    Computed as ``2 / (dh_a/da) = 2 pi a (1 - a) / sqrt(4a(1-a) - u^2)`` at
    ``a = L(u, v)`` (the level curves are graphs over ``u``).  On the lattice
    directions ``|x| = z < 1`` the bulk density diverges (``<W>`` itself tends
    to :func:`lattice_response` there): ``ArgumentError``.  At the bottom corners
    ``|x| = z = 1`` it vanishes.

    Parameters
    ----------
    x : int, float, str, Fraction or mpmath.mpf
        Horizontal position ``x = (2j - i - 1)/N``, ``|x| < z`` (or ``|x| = z = 1``).
    z : int, float, str, Fraction or mpmath.mpf
        Depth ``z = i/N``, ``0 < z <= 1``.
    dps : int
        Decimal digits of the result, ``5..10000``; the work runs with guard digits.

    Returns
    -------
    mpmath.mpf

    Raises
    ------
    ArgumentError
        If ``(x, z)`` is outside the triangle or on a lattice direction ``|x| = z < 1``,
        or ``dps`` outside ``5..10000``.

    Examples
    --------
    >>> mpmath.nstr(bulk_response("0.5", 1, dps=20), 20)  # (pi/2) cos(pi/4) on the bottom row
    '1.1107207345395915618'
    >>> mpmath.nstr(bulk_response("0.2", "0.6", dps=40), 40)
    '1.633495169743023600221082837945243056984'
    """
    dps = check_dps(dps)

    def compute() -> mpmath.mpf:
        depth, h = _in_interval(to_mpf(z, "z"), "z", 0, 1, low_open=True), to_mpf(x, "x")
        if abs(h) > depth or (abs(h) == depth and depth < 1):  # at the bottom corners (|x| = z = 1) it vanishes
            raise ArgumentError(f"x={mpmath.nstr(h, 15)} is out of range: the bulk response needs |x| < z = "
                             f"{mpmath.nstr(depth, 15)} (on the lattice directions |x| = z < 1 it diverges; use lattice_response)")
        with mpmath.workdps(mpmath.mp.dps + _depth_digits(depth)):
            u, v = to_mpf(z, "z") - 1, 1 + to_mpf(x, "x")
            a = _limit_surface(u, v, dps)
            return mpmath.mpf(0) if a in (0, 1) else 2 / _slope(a, u)

    return guarded(compute, dps)
