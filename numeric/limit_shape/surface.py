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
Everything is evaluated with mpmath at ``dps`` decimal digits.

Examples
--------
>>> import mpmath
>>> float(bulk_response(0, 1, dps=30))  # pi/2 at the bottom centre
1.5707963267948966
>>> round(float(lattice_response(0.5, dps=20)), 12)  # (1 - sqrt(3/4)) / 2
0.066987298108
"""

from __future__ import annotations

import mpmath

__all__ = ["level_curve", "level_curve_slope", "limit_surface", "bulk_response", "lattice_response"]


def _check_unit(name, value, low=0, high=1):
    value = mpmath.mpf(value)
    if not low <= value <= high:
        raise ValueError(f"{name}={value}: must lie in [{low}, {high}]")
    return value


def level_curve(a, u, dps: int = 30):
    """``h_a(u)``: the ``v = x + y`` of the level curve ``L = a`` at ``u = x - y``.

    Defined for ``u^2 <= 4a(1-a)``.

    Examples
    --------
    >>> float(level_curve(0.5, 0.3))
    1.0
    """
    with mpmath.workdps(dps + 10):
        a, u = mpmath.mpf(a), mpmath.mpf(u)
        if not 0 < a < 1:
            raise ValueError(f"a={a}: must lie in (0, 1)")
        k2 = 4 * a * (1 - a) - u * u
        if k2 < 0:
            raise ValueError(f"u={u}: outside the level curve of a={a} (need u^2 <= 4a(1-a))")
        k = mpmath.sqrt(k2)
        if a == mpmath.mpf(1) / 2:
            return mpmath.mpf(1)
        b = 1 - 2 * a
        if a > mpmath.mpf(1) / 2:
            return 2 - level_curve(1 - a, u, dps)
        inner = mpmath.atan(b * u / k) if k else mpmath.sign(u) * mpmath.pi / 2
        return +(2 * u / mpmath.pi * inner + 2 / mpmath.pi * mpmath.atan(k / b))


def level_curve_slope(a, u, dps: int = 30):
    """``dh_a(u)/da = k / (pi a (1 - a))``, ``k = sqrt(4a(1-a) - u^2)`` (derived in the notes).

    Examples
    --------
    >>> float(level_curve_slope(0.5, 0)) == float(4 / mpmath.pi)
    True
    """
    with mpmath.workdps(dps + 10):
        a, u = mpmath.mpf(a), mpmath.mpf(u)
        k = mpmath.sqrt(4 * a * (1 - a) - u * u)
        return +(k / (mpmath.pi * a * (1 - a)))


def limit_surface(u, v, dps: int = 30):
    """``L`` at rotated coordinates ``(u, v)``, ``|u| + |v - 1| <= 1``, by root finding.

    Examples
    --------
    >>> float(limit_surface(0, 1))
    0.5
    >>> float(limit_surface(0, 0.5, dps=20)) == float(mpmath.sin(mpmath.pi / 8) ** 2)
    True
    """
    with mpmath.workdps(dps + 10):
        u, v = mpmath.mpf(u), mpmath.mpf(v)
        if abs(u) + abs(v - 1) > 1 + mpmath.mpf(10) ** (-dps):
            raise ValueError(f"(u, v)=({u}, {v}): outside the square |u| + |v - 1| <= 1")
        lo = (1 - mpmath.sqrt(1 - u * u)) / 2  # the level curve of lo ends on the edge at u
        hi = 1 - lo
        if v <= abs(u):  # lower edges of the square: h_lo(u) = |u|
            return lo
        if v >= 2 - abs(u):
            return hi
        eps = mpmath.mpf(10) ** (-(dps + 5))
        f = lambda a: level_curve(a, u, dps + 10) - v  # increasing in a
        a = mpmath.findroot(f, (lo + eps, hi - eps), solver="anderson", tol=eps)
        for _ in range(4):  # Newton polish with dh/da = k / (pi a (1 - a))
            a -= f(a) / level_curve_slope(a, u, dps + 10)
        return +a


def lattice_response(z, dps: int = 30):
    """Limit of ``<W_{i,1}> = <W_{i,i}>`` at depth ``z = i/N`` (independent of N).

    Examples
    --------
    >>> float(lattice_response(1))
    0.0
    """
    z = _check_unit("z", z)
    with mpmath.workdps(dps + 10):
        if z == 0:
            return mpmath.mpf(1)
        return +limit_surface(z - 1, 1 - z, dps)


def bulk_response(x, z, dps: int = 30):
    """Limit of ``N <W>`` at ``(x, z)``, ``|x| < z <= 1``: ``2 dL/dv``.

    Computed as ``2 / (dh_a/da) = 2 pi a (1 - a) / sqrt(4a(1-a) - u^2)`` at
    ``a = L(u, v)`` (the level curves are graphs over ``u``).

    Examples
    --------
    >>> float(bulk_response(0.5, 1, dps=20)) == float(mpmath.pi / 2 * mpmath.cos(mpmath.pi / 4))
    True
    """
    z = _check_unit("z", z)
    x = _check_unit("x", x, -z, z)
    with mpmath.workdps(dps + 10):
        u, v = z - 1, 1 + x
        a = limit_surface(u, v, dps + 10)
        if a in (0, 1):
            return mpmath.mpf(0)
        return +(2 / level_curve_slope(a, u, dps + 10))
