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
    """``h_a(u)`` for ``a < 1/2`` (Pittel-Romik surface, rotated coordinates): the limit Sec. 4.8 leaves open.

    ``a > 1/2`` follows from the symmetry ``h_{1-a}(u) = 2 - h_a(u)``.

    Parameters
    ----------
    a : sympy.Expr
        Level of the surface, ``0 < a < 1/2`` (a number or a symbol).
    u : sympy.Expr
        Rotated coordinate ``u = x_T - y_T``, ``u^2 <= 4 a (1 - a)``.

    Returns
    -------
    sympy.Expr
        ``v = x_T + y_T`` on the level curve ``L = a``.

    Examples
    --------
    >>> a, u = sympy.symbols("a u", positive=True)
    >>> sympy.simplify(level_curve_expr(a, 0).subs(a, sympy.Rational(1, 4)))
    2/3
    """
    k = sympy.sqrt(4 * a * (1 - a) - u**2)
    return 2 * u / sympy.pi * sympy.atan((1 - 2 * a) * u / k) + 2 / sympy.pi * sympy.atan(k / (1 - 2 * a))


def diagonal_limit(t: sympy.Expr) -> sympy.Expr:
    """``L(t, t) = sin^2(pi t / 2)``: the limit surface on the diagonal (the scaling limit of Sec. 4.8).

    Parameters
    ----------
    t : sympy.Expr
        Position on the diagonal, ``0 <= t <= 1`` (a number or a symbol).

    Returns
    -------
    sympy.Expr

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

    Parameters
    ----------
    y : sympy.Expr
        Position along the edge, ``0 <= y <= 1`` (a number or a symbol).

    Returns
    -------
    sympy.Expr

    Examples
    --------
    >>> edge_profile(sympy.Integer(1))
    1/2
    """
    return (1 - sympy.sqrt(1 - y**2)) / 2


def lattice_direction_limit(z: sympy.Expr) -> sympy.Expr:
    """Limit of ``<W_{i,1}> = <W_{i,i}>`` at depth ``z``: ``L(0, 1 - z)`` (N-independent, Sec. 4.8, Fig. 3.5).

    Parameters
    ----------
    z : sympy.Expr
        Depth ``z = i/N``, ``0 <= z <= 1`` (a number or a symbol).

    Returns
    -------
    sympy.Expr

    Examples
    --------
    >>> lattice_direction_limit(sympy.Integer(1))
    0
    """
    return sympy.Rational(1, 2) - sympy.sqrt(z * (2 - z)) / 2


def bottom_row_limit(x: sympy.Expr) -> sympy.Expr:
    """Limit of ``N <W_{N,j}>``: ``(pi/2) cos(pi x / 2)``, from the diagonal (the 1/N bulk of Sec. 4.8, Fig. 3.5).

    Parameters
    ----------
    x : sympy.Expr
        Horizontal position ``x = (2j - N - 1)/N``, ``|x| <= 1`` (a number or a symbol).

    Returns
    -------
    sympy.Expr

    Examples
    --------
    >>> bottom_row_limit(sympy.Integer(1))
    0
    """
    return sympy.pi / 2 * sympy.cos(sympy.pi * x / 2)
