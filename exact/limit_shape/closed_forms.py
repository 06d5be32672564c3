"""Closed forms of the scaling limit of the response, as exact sympy expressions.

See :mod:`forcenet.numeric.limit_shape.surface` for evaluation at any precision and
``notes/scaling_limit.md`` for the derivation.  Coordinates: depth
``z = i/N``, horizontal ``x = (2j - i - 1)/N`` (lattice directions ``|x| = z``);
rotated tableau coordinates ``u = x_T - y_T``, ``v = x_T + y_T`` with
``u = z - 1``, ``v = 1 + x``.

Examples
--------
>>> import sympy
>>> z = sympy.Symbol("z")
>>> lattice_direction_limit(z)
1/2 - sqrt(z*(2 - z))/2
>>> bottom_row_limit(sympy.Integer(0))
pi/2
"""

from __future__ import annotations

import sympy

__all__ = [
    "level_curve_expr",
    "diagonal_limit",
    "lattice_direction_limit",
    "bottom_row_limit",
    "edge_profile",
]


def level_curve_expr(a: sympy.Expr, u: sympy.Expr) -> sympy.Expr:
    """``h_a(u)`` for ``a < 1/2`` (Pittel-Romik surface in rotated coordinates).

    ``a > 1/2`` follows from the symmetry ``h_{1-a}(u) = 2 - h_a(u)``.

    Examples
    --------
    >>> a, u = sympy.symbols("a u", positive=True)
    >>> sympy.simplify(level_curve_expr(a, 0).subs(a, sympy.Rational(1, 4)))
    2/3
    """
    k = sympy.sqrt(4 * a * (1 - a) - u**2)
    return 2 * u / sympy.pi * sympy.atan((1 - 2 * a) * u / k) + 2 / sympy.pi * sympy.atan(k / (1 - 2 * a))


def diagonal_limit(t: sympy.Expr) -> sympy.Expr:
    """``L(t, t) = sin^2(pi t / 2)``: the limit surface on the diagonal.

    Examples
    --------
    >>> diagonal_limit(sympy.Rational(1, 2))
    1/2
    """
    return sympy.sin(sympy.pi * t / 2) ** 2


def edge_profile(y: sympy.Expr) -> sympy.Expr:
    """``L(0, y) = (1 - sqrt(1 - y^2)) / 2``: the limit surface on the edge of the square.

    On the edge the level curve of ``a`` ends (``k = 0`` in ``h_a``), at
    ``y^2 = 4 a (1 - a)``.

    Examples
    --------
    >>> edge_profile(sympy.Integer(1))
    1/2
    """
    return (1 - sympy.sqrt(1 - y**2)) / 2


def lattice_direction_limit(z: sympy.Expr) -> sympy.Expr:
    """Limit of ``<W_{i,1}> = <W_{i,i}>`` at depth ``z``: ``L(0, 1 - z)``.

    Examples
    --------
    >>> lattice_direction_limit(sympy.Integer(1))
    0
    """
    return sympy.Rational(1, 2) - sympy.sqrt(z * (2 - z)) / 2


def bottom_row_limit(x: sympy.Expr) -> sympy.Expr:
    """Limit of ``N <W_{N,j}>``: ``(pi/2) cos(pi x / 2)``, from the diagonal.

    Examples
    --------
    >>> bottom_row_limit(sympy.Integer(1))
    0
    """
    return sympy.pi / 2 * sympy.cos(sympy.pi * x / 2)
