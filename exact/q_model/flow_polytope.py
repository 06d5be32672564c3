"""The microcanonical q-model's polytope of vertical force networks, exactly (thesis Sec. 7.3.2).

On the tilted rectangular lattice (``L`` rows of ``W`` grains, periodic
horizontally; grain ``(i, j)`` rests on ``(i + 1, j)`` by its left bond and
on ``(i + 1, j + 1 mod W)`` by its right bond, the last row on the floor), a
vertical force network is fixed by the left forces ``F_l(i, j)``, with
``0 <= F_l(i, j) <= W_ij``, where the loads are ``W_0j = 1`` (a uniform unit
pressure on the top) and ``W_ij = F_r(i-1, j-1) + F_l(i-1, j)``,
``F_r = W - F_l``.  The microcanonical q-model is the uniform law on this
polytope (Lebesgue measure in the ``F_l``; in the ``q = F_l / W`` it is
``prod W_ij dq_ij``, the thesis's weight).

Its volume and the mean of every bond force are exact rationals here: the
rows are integrated from the bottom up, each ``F_l(i, j)`` over
``[0, W_ij]`` with ``W_ij`` a linear form in the rows above, so every step is
the integral of a polynomial (sympy, exact).  The independent route is the
volume of the same polytope by Normaliz (``tests/test_force_chains_models.py``),
and the heat-bath sampler of :mod:`forcenet.numeric.force_chains.q_models`
is checked against :func:`mean_forces`.

Examples
--------
>>> volume(1, 3)          # one row: each F_l in [0, 1] independently
Fraction(1, 1)
>>> volume(2, 2)
Fraction(5, 6)
"""

from __future__ import annotations

from fractions import Fraction

import sympy

from forcenet.core.validation import check_int

__all__ = ["volume", "mean_forces", "force_moments", "integrate_polytope"]


def _symbols(L: int, W: int) -> list[list[sympy.Symbol]]:
    return [[sympy.Symbol(f"F_{i}_{j}") for j in range(W)] for i in range(L)]


def _loads(F: list[list[sympy.Symbol]], L: int, W: int) -> list[list[sympy.Expr]]:
    """``W_ij`` as linear forms in the ``F_l`` of the rows above."""
    loads: list[list[sympy.Expr]] = [[sympy.Integer(1)] * W]
    for i in range(1, L):
        above = loads[-1]
        loads.append([(above[(j - 1) % W] - F[i - 1][(j - 1) % W]) + F[i - 1][j] for j in range(W)])
    return loads


def integrate_polytope(L: int, W: int, integrand: sympy.Expr | None = None) -> Fraction:
    """The integral of a polynomial in the ``F_l`` (symbols ``F_i_j``) over the polytope (default: its volume).

    Parameters
    ----------
    L, W : int
        Rows (``1..4``) and grains per row (``2..4``): the polynomials grow fast.
    integrand : sympy expression, optional
        A polynomial in the symbols ``F_i_j``.

    Returns
    -------
    Fraction
        The exact integral.

    Examples
    --------
    >>> import sympy
    >>> integrate_polytope(1, 2, sympy.Symbol("F_0_0"))   # the mean of F_l(0, 0) is 1/2
    Fraction(1, 2)
    """
    L, W = check_int(L, "L", 1, 4), check_int(W, "W", 2, 4)
    F = _symbols(L, W)
    loads = _loads(F, L, W)
    expr = sympy.Integer(1) if integrand is None else sympy.sympify(integrand)
    for i in reversed(range(L)):  # the bottom row first: its limits depend only on the rows above
        for j in range(W):
            expr = sympy.expand(sympy.integrate(expr, (F[i][j], 0, loads[i][j])))
    value = sympy.Rational(expr)
    return Fraction(int(value.p), int(value.q))


def volume(L: int, W: int) -> Fraction:
    """The volume of the microcanonical q-model's polytope in the ``F_l`` coordinates.

    Examples
    --------
    >>> volume(3, 2)
    Fraction(61, 90)
    """
    return integrate_polytope(L, W)


def force_moments(L: int, W: int, power: int = 1) -> list[Fraction]:
    """The exact ``<F^power>`` of every bond force, in the bond order of
    :func:`forcenet.numeric.force_chains.q_models.q_lattice` (grain ``(i, j)``'s left bond, then its right bond,
    row by row).

    Examples
    --------
    >>> force_moments(1, 2)                       # F_l uniform in [0, 1]: mean 1/2
    [Fraction(1, 2), Fraction(1, 2), Fraction(1, 2), Fraction(1, 2)]
    >>> [str(m) for m in force_moments(1, 2, 2)][:2]
    ['1/3', '1/3']
    """
    L, W = check_int(L, "L", 1, 4), check_int(W, "W", 2, 4)
    power = check_int(power, "power", 1, 4)
    F = _symbols(L, W)
    loads = _loads(F, L, W)
    total = volume(L, W)
    out = []
    for i in range(L):
        for j in range(W):
            out += [integrate_polytope(L, W, F[i][j] ** power) / total,
                    integrate_polytope(L, W, (loads[i][j] - F[i][j]) ** power) / total]
    return out


def mean_forces(L: int, W: int) -> list[Fraction]:
    """The exact mean of every bond force (:func:`force_moments` with ``power=1``; ``1/2`` on the top row, and by
    the lattice's reflection and translation symmetries everywhere: the second moments are the real check).

    Examples
    --------
    >>> [str(m) for m in mean_forces(2, 2)][4:6]
    ['1/2', '1/2']
    """
    return force_moments(L, W, 1)
