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
    "edge_density_coefficient",
    "kesten_mckay_edge_coefficient",
    "edge_scale",
    "bulk_edge_coefficient",
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


def edge_density_coefficient(z: sympy.Expr) -> sympy.Expr:
    """``A(z)``: layer ``zN`` holds ``(N A(z) / pi) sqrt(s - e(z)) ds`` partial sums just above its lowest one (the edge).

    From the level curves: row ``i = zN`` has ``j = N (h_s(z - 1) - 1 + z) / 2`` partial
    sums below the level ``s``, so ``dj/ds = (N/2) dh_s/ds = N k / (2 pi s (1 - s))``
    with ``k^2 = 4 s (1 - s) - (1 - z)^2 ~ 4 (1 - 2 e) (s - e)`` at the end
    ``e = (1 - sqrt(z (2 - z)))/2`` of the level curves (``notes/scaling_limit.md`` Sec. 5).

    Parameters
    ----------
    z : sympy.Expr
        Depth ``z = i/N``, ``0 < z < 1`` (a number or a symbol).

    Returns
    -------
    sympy.Expr

    Examples
    --------
    >>> edge_density_coefficient(sympy.Rational(1, 2))
    8*sqrt(2)*3**(1/4)
    """
    return 4 * (z * (2 - z)) ** sympy.Rational(1, 4) / (1 - z) ** 2


def kesten_mckay_edge_coefficient(z: sympy.Expr) -> sympy.Expr:
    """``A(z)`` by a second route: the floor's arcsine law compressed freely to the fraction ``z`` (Kesten-McKay).

    Given the floor, the rows above are the corners of ``U diag(floor) U*``
    (``notes/scaling_limit.md`` Sec. 5).  The floor's limit law is the arcsine law
    on ``[0, 1]``, ``(1 + B + B') / 2`` with ``B, B'`` free symmetric Bernoulli
    (``+-1/2``); the corner of relative size ``z`` has the law of
    ``1/2 + (z / 4) X``, ``X`` Kesten-McKay with ``t = 2/z``: density
    ``t sqrt(4 (t - 1) - x^2) / (2 pi (t^2 - x^2))``.  Its square-root vanishing at
    the lower edge ``x_0 = -2 sqrt(t - 1)``, times ``zN`` sums per unit ``x``, gives ``A``.

    Parameters
    ----------
    z : sympy.Expr
        Depth ``z = i/N``, ``0 < z < 1``.

    Returns
    -------
    sympy.Expr
        ``lim (counting density) / (N sqrt(s - e) / pi)`` at the lower edge.

    Examples
    --------
    >>> z = sympy.Rational(1, 3)
    >>> sympy.simplify(kesten_mckay_edge_coefficient(z) - edge_density_coefficient(z))
    0
    """
    t = 2 / z
    x0 = 2 * sympy.sqrt(t - 1)
    # density ~ t sqrt(2 x0 w) / (2 pi (t - 2)^2) at x = -x0 + w, w = (4/z) (s - e); zN sums, dx/ds = 4/z
    return sympy.pi * z * (4 / z) * t * sympy.sqrt(2 * x0 * 4 / z) / (2 * sympy.pi * (t - 2) ** 2)


def edge_scale(z: sympy.Expr) -> sympy.Expr:
    """``c(z)`` of the edge scale ``sigma_N = c(z) N^(-2/3)`` of the lowest partial sum of layer ``zN``.

    ``c = A^(-2/3)`` with ``A`` of :func:`edge_density_coefficient`: the Airy-kernel
    matching of a density ``(N A / pi) sqrt(y)``, ``y = s - e``
    (``notes/scaling_limit.md`` Sec. 5); then
    ``<W_(i,1)> = e(z) + |E chi| c(z) N^(-2/3) + O(1/N)``,
    ``sd(W_(i,1)) ~ sd(chi) c(z) N^(-2/3)``, ``chi`` Tracy-Widom GUE.

    Parameters
    ----------
    z : sympy.Expr
        Depth ``z = i/N``, ``0 < z < 1``.

    Returns
    -------
    sympy.Expr
        ``(1 - z)^(4/3) / (2^(4/3) (z (2 - z))^(1/6))``.

    Examples
    --------
    >>> edge_scale(sympy.Rational(1, 2))
    2**(2/3)*3**(5/6)/24
    """
    return (1 - z) ** sympy.Rational(4, 3) / (2 ** sympy.Rational(4, 3) * (z * (2 - z)) ** sympy.Rational(1, 6))


def bulk_edge_coefficient(z: sympy.Expr) -> sympy.Expr:
    """``C(z)`` of the divergence ``G(x, z) ~ C(z) (z - |x|)^(-1/3)`` of the bulk response at the lattice directions.

    At fixed ``u = z - 1`` the level curve near its end is
    ``h_a(u) - |u| = k^3 / (6 pi r e (1 - e)) + O(k^5)`` with ``r = 1 - 2e = sqrt(z (2 - z))``,
    ``e (1 - e) = (1 - z)^2 / 4``; with ``G = 2 pi a (1 - a) / k`` and ``z - |x| = h_a(u) - |u|``
    this is ``C = 2 pi e (1 - e) (6 pi r e (1 - e))^(-1/3)`` (``notes/scaling_limit.md`` Sec. 1).

    Parameters
    ----------
    z : sympy.Expr
        Depth ``z = i/N``, ``0 < z < 1``.

    Returns
    -------
    sympy.Expr

    Examples
    --------
    >>> sympy.nsimplify(bulk_edge_coefficient(sympy.Rational(1, 2)) ** 3 / sympy.pi**2)
    sqrt(3)/288
    """
    q = (1 - z) ** 2 / 4
    r = sympy.sqrt(z * (2 - z))
    return 2 * sympy.pi * q / (6 * sympy.pi * r * q) ** sympy.Rational(1, 3)
