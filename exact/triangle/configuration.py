"""The fully mobilized triangle: W, q and lateral-force coordinates, exactly.

Grains are ``(i, j)``, ``i = 1..N`` (layer, top to bottom), ``j = 1..i``; grain
``(i, j)`` rests on ``(i+1, j)`` (lower left) and ``(i+1, j+1)`` (lower right).
``W[i][j]`` is the vertical force grain ``(i, j)`` transmits downwards, the
overload is ``W_{1,1} = 1`` and gravity is absent, so every row sums to 1.

Coordinates (Ostojic 2006):

* ``q_{i,j}`` (3.8): the fraction of ``W_{i,j}`` sent to the lower-left
  neighbour; ``W_{i+1,j} = (1 - q_{i,j-1}) W_{i,j-1} + q_{i,j} W_{i,j}`` (4.5);
  inverse (4.6): ``q_{i,j} = (S_{i+1,j} - S_{i,j-1}) / W_{i,j}`` with partial
  sums ``S_{i,j} = W_{i,1} + ... + W_{i,j}``.
* bounds (4.8)-(4.9): ``a_{i,j} <= W_{i,j} <= b_{i,j}``,
  ``a_{i,j} = sum_{k<j} (W_{i-1,k} - W_{i,k})``, ``b_{i,j} = W_{i-1,j} + a_{i,j}``;
  equivalently ``S_{i-1,j-1} <= S_{i,j} <= S_{i-1,j}`` (interlacing).
* contact forces (3.2) with ``g = 0``: ``F5 = F2 + (F4 - F3)``,
  ``F6 = F1 - (F4 - F3)``, ``F5 = (2/sqrt 3) q W``, ``F6 = (2/sqrt 3)(1-q) W``,
  so the lateral force to the right of grain ``(i, j)`` is
  ``F4^{(i,j)} = p_h + (2/sqrt 3) sum_{k<=j} (q_{i,k} W_{i,k} - q_{i-1,k} W_{i-1,k})``.

Everything is exact: :class:`fractions.Fraction` for W, q, S and sympy for
the lateral forces, which carry ``sqrt(3)``.

Examples
--------
>>> from fractions import Fraction as F
>>> W = W_from_q({(1, 1): F(1, 3), (2, 1): F(1, 2), (2, 2): F(1, 4)}, 3)
>>> [[str(x) for x in row] for row in W]
[['1'], ['1/3', '2/3'], ['1/6', '1/3', '1/2']]
>>> q_from_W(W)[(2, 2)]
Fraction(1, 4)
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from fractions import Fraction
from typing import Any

import sympy

from forcenet.core.errors import ArgumentError
from forcenet.core.validation import check_layers

__all__ = [
    "W_from_q",
    "q_from_W",
    "partial_sums",
    "W_from_partial_sums",
    "bounds",
    "in_ensemble",
    "contact_forces",
    "P_H_SYMBOL",
]

P_H_SYMBOL = sympy.Symbol("p_h", positive=True)  # the side pressure p_h, symbolic by default


def _rows(W: Iterable[Iterable[Any]]) -> list[list[Fraction]]:
    rows = [[Fraction(x) for x in row] for row in W]
    for i, row in enumerate(rows, start=1):
        if len(row) != i:
            raise ArgumentError(f"W: row {i} has {len(row)} entries, expected {i}")
    return rows


def W_from_q(q: Mapping[tuple[int, int], Any], N: int) -> list[list[Fraction]]:
    """Forces ``W`` from the q-coordinates, Eq. (4.5), with ``W_{1,1} = 1``.

    Parameters
    ----------
    q : mapping
        ``(i, j) -> q_{i,j}`` for ``1 <= i <= N-1``, ``1 <= j <= i``, values in ``[0, 1]``.
    N : int
        Number of layers.

    Returns
    -------
    list of list of Fraction
        Row ``i - 1`` holds ``W_{i,1}, ..., W_{i,i}``.

    Raises
    ------
    ArgumentError
        If ``N`` is out of range or a ``q`` is outside ``[0, 1]``.

    Examples
    --------
    >>> W_from_q({(1, 1): Fraction(1, 4)}, 2)
    [[Fraction(1, 1)], [Fraction(1, 4), Fraction(3, 4)]]
    """
    N = check_layers(N)
    for (i, j), value in q.items():
        if not (0 <= Fraction(value) <= 1):
            raise ArgumentError(f"q[{i}, {j}]={value}: q must lie in [0, 1]")
    W = [[Fraction(1)]]
    for i in range(1, N):
        prev = W[-1]
        row: list[Fraction] = []
        for j in range(1, i + 2):
            left = (1 - Fraction(q[(i, j - 1)])) * prev[j - 2] if j >= 2 else Fraction(0)
            right = Fraction(q[(i, j)]) * prev[j - 1] if j <= i else Fraction(0)
            row.append(left + right)
        W.append(row)
    return W


def partial_sums(W: Iterable[Iterable[Any]]) -> list[list[Fraction]]:
    """``S[i-1][j] = W_{i,1} + ... + W_{i,j}`` for ``j = 0..i``.

    Parameters
    ----------
    W : sequence of sequences
        Row ``i`` holds ``W_{i,1}, ..., W_{i,i}`` (numbers :class:`fractions.Fraction` accepts).

    Returns
    -------
    list of list of Fraction
        Row ``i - 1`` holds ``S_{i,0} = 0, ..., S_{i,i}``.

    Raises
    ------
    ArgumentError
        If a row of ``W`` does not have ``i`` entries.

    Examples
    --------
    >>> partial_sums([[1], [Fraction(1, 4), Fraction(3, 4)]])[1]
    [Fraction(0, 1), Fraction(1, 4), Fraction(1, 1)]
    """
    out = []
    for row in _rows(W):
        acc, sums = Fraction(0), [Fraction(0)]
        for x in row:
            acc += x
            sums.append(acc)
        out.append(sums)
    return out


def W_from_partial_sums(S: Iterable[Sequence[Any]]) -> list[list[Fraction]]:
    """Inverse of :func:`partial_sums`."""
    return [[Fraction(b) - Fraction(a) for a, b in zip(row, row[1:])] for row in S]


def q_from_W(W: Iterable[Iterable[Any]]) -> dict[tuple[int, int], Fraction | None]:
    """q-coordinates from forces, Eq. (4.6); ``None`` where ``W_{i,j} = 0``.

    ``q_{i,j} = (S_{i+1,j} - S_{i,j-1}) / W_{i,j}``.

    Parameters
    ----------
    W : sequence of sequences
        Row ``i`` holds ``W_{i,1}, ..., W_{i,i}`` (numbers :class:`fractions.Fraction` accepts).

    Returns
    -------
    dict
        ``(i, j) -> q_{i,j}`` (a Fraction, or None where ``W_{i,j} = 0``) for ``i = 1..N-1``.

    Raises
    ------
    ArgumentError
        If a row of ``W`` does not have ``i`` entries.

    Examples
    --------
    >>> q_from_W([[1], [Fraction(1, 4), Fraction(3, 4)]])
    {(1, 1): Fraction(1, 4)}
    """
    rows = _rows(W)
    S = partial_sums(rows)
    q: dict[tuple[int, int], Fraction | None] = {}
    for i in range(1, len(rows)):
        for j in range(1, i + 1):
            w = rows[i - 1][j - 1]
            q[(i, j)] = None if w == 0 else (S[i][j] - S[i - 1][j - 1]) / w
    return q


def bounds(W: Iterable[Iterable[Any]], i: int, j: int) -> tuple[Fraction, Fraction]:
    """``(a_{i,j}, b_{i,j})`` of Eq. (4.9) for a free force ``W_{i,j}``, ``j < i``.

    Examples
    --------
    >>> bounds([[1], [Fraction(1, 2), Fraction(1, 2)], [Fraction(1, 4), Fraction(1, 2), Fraction(1, 4)]], 3, 2)
    (Fraction(1, 4), Fraction(3, 4))
    """
    rows = _rows(W)
    if not (2 <= i <= len(rows) and 1 <= j <= i - 1):
        raise ArgumentError(f"(i, j)=({i}, {j}): need 2 <= i <= N={len(rows)} and 1 <= j <= i - 1")
    a = sum((rows[i - 2][k - 1] - rows[i - 1][k - 1] for k in range(1, j)), Fraction(0))
    return a, rows[i - 2][j - 1] + a


def in_ensemble(W: Iterable[Iterable[Any]]) -> bool:
    """True if ``W`` is a force network of the fully mobilized triangle.

    Rows sum to 1, ``W_{1,1} = 1``, and every free force obeys Eq. (4.8).

    Parameters
    ----------
    W : sequence of sequences
        Row ``i`` holds ``W_{i,1}, ..., W_{i,i}`` (numbers :class:`fractions.Fraction` accepts).

    Returns
    -------
    bool

    Raises
    ------
    ArgumentError
        If a row of ``W`` does not have ``i`` entries.

    Examples
    --------
    >>> in_ensemble([[1], [Fraction(1, 4), Fraction(3, 4)]]), in_ensemble([[1], [Fraction(1, 2), Fraction(1, 4)]])
    (True, False)
    """
    rows = _rows(W)
    if rows[0][0] != 1 or any(sum(row) != 1 for row in rows):
        return False
    if any(x < 0 for row in rows for x in row):
        return False
    return all(
        bounds(rows, i, j)[0] <= rows[i - 1][j - 1] <= bounds(rows, i, j)[1]
        for i in range(2, len(rows) + 1)
        for j in range(1, i)
    )


def contact_forces(W: Iterable[Iterable[Any]], p_h: Any = P_H_SYMBOL) -> dict[tuple[int, int], tuple[Any, ...]]:
    """All six contact forces of every grain above the bottom layer, exact.

    Returns ``{(i, j): (F1, F2, F3, F4, F5, F6)}`` as sympy expressions for
    ``i = 1..N-1`` (Fig. 3.2 numbering: 1 upper left, 2 upper right, 3 left,
    4 right, 5 lower left, 6 lower right); on the top grain the overload
    appears as ``F1 = F2 = 1/sqrt 3`` (a vertical unit force).  The side force entering the
    triangle on the left of each layer is ``p_h``; the one on the right closes
    the horizontal balance and is ``p_h`` plus a term bounded by the overload,
    which is why the thesis needs ``(2/sqrt 3) p_h > F`` (Sec. 4.1).

    Parameters
    ----------
    W : sequence of sequences
        Row ``i`` holds ``W_{i,1}, ..., W_{i,i}`` (numbers :class:`fractions.Fraction` accepts).
    p_h : sympy expression or number, optional
        The side force, :data:`P_H_SYMBOL` (symbolic) by default.

    Returns
    -------
    dict
        ``(i, j) -> (F1, F2, F3, F4, F5, F6)``, sympy expressions.

    Raises
    ------
    ArgumentError
        If a row of ``W`` does not have ``i`` entries.

    Examples
    --------
    >>> forces = contact_forces([[1], [Fraction(1, 4), Fraction(3, 4)]])
    >>> forces[(1, 1)]
    (sqrt(3)/3, sqrt(3)/3, p_h, p_h - sqrt(3)/6, sqrt(3)/6, sqrt(3)/2)
    """
    rows = _rows(W)
    q = q_from_W(rows)
    c = 2 / sympy.sqrt(3)
    N = len(rows)
    out: dict[tuple[int, int], tuple[Any, ...]] = {}
    for i in range(1, N):
        F3 = sympy.sympify(p_h)
        for j in range(1, i + 1):
            w = rows[i - 1][j - 1]
            given = q[(i, j)]
            qq = given if given is not None else Fraction(0)
            F5 = c * sympy.Rational(qq * w)
            F6 = c * sympy.Rational((1 - qq) * w)
            if i == 1:  # the vertical overload W_ext = 1, split evenly as in (3.1)
                F1 = F2 = 1 / sympy.sqrt(3)
            else:  # (3.4); zero from grains outside the triangle
                F1 = out[(i - 1, j - 1)][5] if (i - 1, j - 1) in out else sympy.Integer(0)
                F2 = out[(i - 1, j)][4] if (i - 1, j) in out else sympy.Integer(0)
            F4 = sympy.expand(F3 + F5 - F2)  # (3.2) with g = 0
            out[(i, j)] = (F1, F2, F3, F4, F5, F6)
            F3 = F4  # (3.4): F3^{(i,j+1)} = F4^{(i,j)}
    return out
