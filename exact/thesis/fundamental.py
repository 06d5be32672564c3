"""The fundamental relations of the nested integration, as printed (Eqs. 4.14-4.32, 4.46, 4.49).

* :func:`integral_I`: the central integral (4.14)-(4.15);
* :func:`index_tuples`: the index range (4.32);
* :func:`psi_fundamental`, :func:`right_vector`: the coefficients (4.29)-(4.31);
* :func:`normalization_fundamental`: the normalization ``L t(1) R`` (4.46).

The literal route, for small N (N = 7 in seconds); the layer-by-layer
engine is :mod:`.nested`.  Derivations: ``notes/chapter4.md``.
"""

from __future__ import annotations

from collections.abc import Iterator
from fractions import Fraction
from typing import Any

from forcenet.core.errors import ArgumentError
from forcenet.core.validation import check_layers

from .coefficients import gamma, gamma_coefficient, upper_bound

__all__ = ["integral_I", "index_tuples", "psi_fundamental", "right_vector", "normalization_fundamental"]


def integral_I(m: int, n: int, a: Any, b: Any) -> Any:
    """``I_mn(a, b) = int_a^b x^m (b - x)^n dx``, evaluated by Eq. (4.14).

    ``I_mn(a, b) = sum_{k=0}^{m} gamma^{m-k}_{m,n} (b - a)^{n+1+k} a^{m-k}``.
    ``a`` and ``b`` may be numbers or sympy expressions.

    Parameters
    ----------
    m, n : int
        The powers of ``x`` and ``b - x``, ``>= 0``.
    a, b : int, Fraction or sympy expression
        The limits of the integral.

    Returns
    -------
    Fraction or sympy expression
        Of the type that ``a`` and ``b`` combine to.

    Examples
    --------
    >>> integral_I(1, 1, 0, 1)
    Fraction(1, 6)
    >>> integral_I(2, 0, 1, 2)
    Fraction(7, 3)
    """
    total = 0
    for k in range(m + 1):
        total += gamma_coefficient(m, n, k) * (b - a) ** (n + 1 + k) * a ** (m - k)
    return total

def index_tuples(p: int) -> Iterator[tuple[int, ...]]:
    """All tuples ``(j_1, ..., j_p)`` in the range (4.32).

    Parameters
    ----------
    p : int
        Length of the tuples, ``>= 0``.

    Returns
    -------
    iterator of tuple of int
        In lexicographic order.

    Examples
    --------
    >>> list(index_tuples(2))
    [(1, 1), (1, 2), (1, 3), (2, 1), (2, 2), (2, 3), (2, 4)]
    """

    def extend(prefix: tuple[int, ...]) -> Iterator[tuple[int, ...]]:
        l = len(prefix) + 1
        if l > p:
            yield prefix
            return
        top = upper_bound(l, prefix[-1] if prefix else None)
        for j in range(1, top + 1):
            yield from extend(prefix + (j,))

    yield from extend(())

def psi_fundamental(i: tuple, j: tuple) -> Fraction:
    """The coefficient ``psi_{i1 j1, ..., ip jp}`` of the fundamental relations (4.29)-(4.30).

    ``psi_{i1 j1} = psi^{2-i1}_{1, 2-j1}`` and (4.30)

        psi_{..., ip jp} = psi_{..., i(p-1) j(p-1)} psi^{p + i(p-1) - ip}_{p + i(p-1) - j(p-1), p + j(p-1) - jp} theta(ip - j(p-1)),

    with ``psi^f_{s,e} = gamma^f_{s,e} = s! e! / ((e + s - f + 1)! f!)`` (4.15).
    The element of the nested matrix ``t`` (4.28) is ``psi W^{p + i_p - j_p}``
    (``p`` index pairs).  Read this way -- the first lower index is
    ``p + i(p-1) - j(p-1)``, the power of ``W`` in the previous level -- the
    printed relations give the normalization (4.46) and
    ``R = Lambda / prod factorials`` (4.49) exactly (tests, N <= 7).

    Parameters
    ----------
    i, j : tuple of int
        The index tuples ``(i_1, ..., i_p)`` and ``(j_1, ..., j_p)``.

    Returns
    -------
    Fraction

    Raises
    ------
    ArgumentError
        If ``i`` and ``j`` differ in length or are empty.

    Examples
    --------
    >>> psi_fundamental((2,), (2,)), psi_fundamental((2, 3), (1, 1))
    (Fraction(1, 2), Fraction(1, 60))
    """
    if len(i) != len(j) or not i:
        raise ArgumentError(f"i={i!r}, j={j!r}: need two index tuples of the same length >= 1")
    value = gamma(2 - i[0], 1, 2 - j[0])
    for l in range(2, len(i) + 1):
        il, jl, ip, jp = i[l - 1], j[l - 1], i[l - 2], j[l - 2]
        if value == 0 or il < jp:  # theta(i_l - j_{l-1})
            return Fraction(0)
        value *= gamma(l + ip - il, l + ip - jp, l + jp - jl)
    return value

def right_vector(p: int) -> dict[tuple[int, ...], Fraction]:
    """``R^{(p)}`` of (4.31): ``R^{(1)} = delta(i1, 1)``,
    ``R^{(p)}_i = delta(i_p, 1) sum_j psi_{i1 j1, ..., i(p-1) j(p-1)} R^{(p-1)}_j``.

    Nonzero entries only; exact Fractions.  (4.49): ``R^{(p)}_j =
    Lambda^{(p)}_j / prod_{l=2}^{p} (l + j(l-1) - j_l)!``.

    Parameters
    ----------
    p : int
        Level of the vector, ``>= 1``.

    Returns
    -------
    dict of tuple of int to Fraction
        The nonzero entries ``R^{(p)}_i``.

    Examples
    --------
    >>> right_vector(2)
    {(1, 1): Fraction(1, 2), (2, 1): Fraction(1, 6)}
    """
    R: dict[tuple[int, ...], Fraction] = {(1,): Fraction(1)}
    for q in range(2, p + 1):
        new = {}
        for i in index_tuples(q):
            if i[-1] != 1:
                continue
            value = sum((psi_fundamental(i[:-1], j) * r for j, r in R.items()), Fraction(0))
            if value:
                new[i] = value
        R = new
    return R

def normalization_fundamental(N: int) -> Fraction:
    """The normalization ``L t(W_{1,1} = 1) R`` (4.46) from the printed fundamental relations.

    ``L^{(p)}_i = prod_l delta(i_l, l(l+1)/2 + 1)`` (4.31) selects one row;
    ``t`` is (4.28) with ``W = 1`` and ``R`` is :func:`right_vector`.  The
    literal route: a sum over the index tuples (4.32) with ``psi`` products,
    so meant for small N (N = 7 in a few seconds).

    Parameters
    ----------
    N : int
        Number of layers, ``N >= 3``.

    Returns
    -------
    Fraction
        Equal to :func:`forcenet.exact.normalization`.

    Raises
    ------
    ArgumentError
        If ``N`` is not an integer ``>= 3``.

    Examples
    --------
    >>> normalization_fundamental(5)
    Fraction(1, 302400)
    """
    N = check_layers(N, minimum=3)
    p = N - 2
    R = right_vector(p)
    top = tuple(l * (l + 1) // 2 + 1 for l in range(1, p + 1))
    return sum((psi_fundamental(top, j) * r for j, r in R.items()), Fraction(0))
