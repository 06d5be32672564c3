"""The nested-matrix integration of chapter 4 as sympy objects, layer by layer (small N).

The same recursion as :mod:`.nested` (literal engine), shown instead of
computed: after the layers below ``m`` are integrated, the integrand is the
matrix product (4.27)

    J_m = L t(W_{m,1}) t(W_{m,2}) ... t(W_{m,m}) R,

with ``t`` a matrix of monomials ``psi W^power`` (4.28)-(4.30) whose row and
column indices are nested tuples (Fig. 4.1b), ``L`` and ``R`` the boundary
vectors (4.31), (4.44)-(4.45).  :func:`nested_layers` returns every ``J_m``
as a :class:`NestedLayer` of sympy matrices in the symbols ``W_m_k``;
:func:`integrate_layer_step` does one step with the central integral (4.14):

* the bottom layer's integrand is 1 (``1 x 1`` matrices);
* integrating layer ``m`` turns each entry ``x^s`` of site ``k`` that meets
  ``u_k^e`` from the right into ``gamma^f_{s,e} Y_k^{e+1+s-f}`` at row
  ``(row, f)`` and column ``(col, e)``, ``gamma^f_{s,e} = s! e! / ((e+s-f+1)! f!)``
  (4.14)-(4.15), the last site becoming the new right vector (4.45) and
  ``a_1 = 0`` the new left vector (4.44);
* at the top, ``J_1`` at ``W_{1,1} = 1`` is the normalization (4.46).

Moments insert ``W^s`` at a grain before its layer is integrated (the
defects (4.57)-(4.61), (4.80)-(4.85)).  Meant for ``N <= 5`` (sympy matrices
of the nested bonds: 1, 2, 7, 37 entries wide).  Session:
``notes/symbolic_session.md``.

Examples
--------
>>> layers = nested_layers(3)
>>> [layer.m for layer in layers]
[3, 2, 1]
>>> layers[1].integrand()
W_2_1*W_2_2
>>> layers[2].normalization()
1/6
"""

from __future__ import annotations

from fractions import Fraction
from typing import Any, NamedTuple

import sympy

from forcenet.core.errors import ArgumentError
from forcenet.core.validation import check_layers

from .nested import check_powers, integrate_layer, multiply_site, prune_layer

__all__ = ["w_symbol", "NestedLayer", "nested_layers", "integrate_layer_step", "moment_symbolic"]

_MAX_N = 6


def w_symbol(i: int, j: int) -> sympy.Symbol:
    """The symbol ``W_i_j`` of the force on grain ``(i, j)``.

    Examples
    --------
    >>> w_symbol(4, 2)
    W_4_2
    """
    return sympy.Symbol(f"W_{i}_{j}")  # the names of forcenet.exact.reference.integration: the same symbols


def _rational(x: Fraction) -> sympy.Rational:
    return sympy.Rational(x.numerator, x.denominator)


class NestedLayer(NamedTuple):
    """``J_m = L t(W_{m,1}) ... t(W_{m,m}) R`` (4.27) after integrating the layers below ``m``.

    ``bonds[k]`` lists the nested index tuples labelling the ``k``-th bond
    (``bonds[0]``: the rows of ``t(W_{m,1})`` and the entries of ``L``;
    ``bonds[m]``: the entries of ``R``), in the order of the matrix rows.
    ``state`` is the raw (left, sites, right) of the literal engine.
    """

    m: int
    left: sympy.Matrix
    sites: tuple
    right: sympy.Matrix
    bonds: tuple
    state: tuple

    def integrand(self) -> sympy.Expr:
        """``J_m`` as a polynomial in the forces of layer ``m`` (4.27)."""
        product = self.left
        for t in self.sites:
            product = product * t
        return sympy.factor(sympy.expand((product * self.right)[0, 0]))

    def normalization(self) -> sympy.Rational:
        """``L t(1) ... t(1) R``: (4.46) at the top layer, ``W_{1,1} = 1``."""
        return sympy.expand(self.integrand().subs({w_symbol(self.m, k): 1 for k in range(1, self.m + 1)}))

    def bond_dimensions(self) -> tuple:
        """Widths of the bonds, left to right (the number of nested index tuples, Fig. 4.1b)."""
        return tuple(len(b) for b in self.bonds)


def _to_sympy(m: int, state: Any) -> NestedLayer:
    left, sites, right = state
    bonds = [sorted(left, key=repr)]
    for site in sites:
        bonds.append(sorted({col for (_, col) in site}, key=repr))
    if set(bonds[-1]) != set(right):  # columns of the last site = entries of R
        bonds[-1] = sorted(set(bonds[-1]) | set(right), key=repr)
    index = [{key: n for n, key in enumerate(b)} for b in bonds]
    L = sympy.zeros(1, len(bonds[0]))
    for key, c in left.items():
        L[0, index[0][key]] = _rational(c)
    mats = []
    for k, site in enumerate(sites, start=1):
        W = w_symbol(m, k)
        t = sympy.zeros(len(bonds[k - 1]), len(bonds[k]))
        for (row, col), poly in site.items():
            t[index[k - 1][row], index[k][col]] += sum((_rational(c) * W**p for p, c in poly.items()), sympy.Integer(0))
        mats.append(t)
    R = sympy.zeros(len(bonds[-1]), 1)
    for key, c in right.items():
        R[index[-1][key], 0] = _rational(c)
    return NestedLayer(m, L, tuple(mats), R, tuple(tuple(b) for b in bonds), state)


def integrate_layer_step(layer: NestedLayer, powers: dict | None = None) -> NestedLayer:
    """Integrate the forces of layer ``m`` with (4.14): ``J_m`` -> ``J_{m-1}`` (4.28)-(4.31), (4.44)-(4.45).

    ``powers`` (``{(m, k): s}``) multiplies ``t(W_{m,k})`` by ``W_{m,k}^s``
    first (a defect, (4.57)-(4.61)).

    Parameters
    ----------
    layer : NestedLayer
        The integrand ``J_m`` of layer ``m >= 2``.
    powers : dict, optional
        ``{(m, k): s}``: the power of each force of this layer.

    Returns
    -------
    NestedLayer
        ``J_{m-1}``.

    Raises
    ------
    ArgumentError
        If ``layer`` is the top layer ``m = 1``.

    Examples
    --------
    >>> bottom = nested_layers(3)[0]
    >>> integrate_layer_step(bottom).integrand()
    W_2_1*W_2_2
    """
    if layer.m < 2:
        raise ArgumentError(f"layer m={layer.m}: the top layer W_11 = 1 is not integrated; use normalization()")
    powers = powers or {}
    left, sites, right = layer.state
    sites = [multiply_site(site, powers.get((layer.m, k), 0)) for k, site in enumerate(sites, start=1)]
    return _to_sympy(layer.m - 1, prune_layer(*integrate_layer(left, sites, right)))


def nested_layers(N: int, powers: dict | None = None) -> list[NestedLayer]:
    """``[J_N, J_{N-1}, ..., J_1]`` as sympy matrix products (4.27), from the bottom layer up.

    ``J_N = 1``; ``J_{N-1} = prod_j W_{N-1,j}`` (4.16); ``J_1`` at
    ``W_{1,1} = 1`` is the normalization (4.46), or the unnormalized moment
    when ``powers`` (``{(i, j): s}``) inserts forces.

    Parameters
    ----------
    N : int
        Number of layers, ``2 <= N <= 6``.
    powers : dict, optional
        ``{(i, j): s}``: the power of each grain's force.

    Returns
    -------
    list of NestedLayer
        ``N`` layers, ``J_N`` first.

    Raises
    ------
    ArgumentError
        If ``N`` is out of range, a key of ``powers`` is not a grain or a
        power is negative.

    Examples
    --------
    >>> [layer.bond_dimensions() for layer in nested_layers(4)]
    [(1, 1, 1, 1, 1), (1, 1, 1, 1), (1, 2, 1), (1, 2)]
    >>> nested_layers(4)[-1].normalization()
    1/360
    """
    N = check_layers(N, maximum=_MAX_N)
    powers = check_powers(N, powers)
    one = {0: Fraction(1)}
    state = ({(): Fraction(1)}, [{((), ()): dict(one)} for _ in range(N)], {(): Fraction(1)})
    layers = [_to_sympy(N, state)]
    while layers[-1].m > 1:
        layers.append(integrate_layer_step(layers[-1], powers))
    return layers


def moment_symbolic(N: int, grain: tuple[int, int], s: int = 1) -> sympy.Rational:
    """``<W_{i,j}^s>`` = (J_1 with the defect) / (J_1 without), both at ``W_{1,1} = 1``, Eqs. (4.57)-(4.61).

    Parameters
    ----------
    N : int
        Number of layers, ``2 <= N <= 6``.
    grain : tuple of int
        ``(i, j)`` with ``1 <= j <= i <= N``.
    s : int
        The power, ``s >= 0``.

    Returns
    -------
    sympy.Rational

    Raises
    ------
    ArgumentError
        If ``N``, ``grain`` or ``s`` is out of range.

    Examples
    --------
    >>> moment_symbolic(3, (3, 1)), moment_symbolic(4, (4, 2), 2)
    (1/4, 9/56)
    """
    N = check_layers(N, maximum=_MAX_N)
    (grain, s), = check_powers(N, {grain: s}).items() or [((1, 1), 0)]
    if grain == (1, 1):  # W_11 = 1
        return sympy.Integer(1)
    return nested_layers(N, {grain: s})[-1].normalization() / nested_layers(N)[-1].normalization()
