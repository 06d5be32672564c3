"""``<W^2>`` of every load of layer ``N - 1`` for the price of the mean: a cell is uniform between its covers.

``notes/fluctuations.md`` Sec. 3.1 has the proof.  Under the uniform measure
on the order polytope a partial sum ``x`` is, given every other one,
uniform on ``[L, U]``, ``L`` the largest of the cells it must exceed (its
lower covers; ``0`` if none), ``U`` the smallest of those it must stay below
(``1`` if none).  So ``E[x^2] = E[L^2 + L U + U^2]/3`` and

    E[(U - L)^2] = 3 E[L^2] + 3 E[U^2] - 6 E[x^2].                              (C)

When ``L`` and ``U`` are single partial sums of one layer, consecutive,
``U - L`` is a load and (C) gives its second moment from three single-cell
second moments, which :func:`~.partial_sums.partial_sum_moments` computes
from the mean's own Pfaffian evaluations.  The floor cell ``S_(N,j)`` lies
between ``S_(N-1,j-1)`` and ``S_(N-1,j)`` (``S_(N-1,0) = 0``,
``S_(N-1,N-1) = 1``) and nothing else, so

    <W_(N-1,j)^2> = 3 (<S_(N-1,j-1)^2> + <S_(N-1,j)^2>) - 6 <S_(N,j)^2>,     j = 1..N-1;

the only other such cell is ``S_(2,1)``, between ``S_(3,1)`` and ``S_(3,2)``
(:func:`cover_spans` finds them from the covers).  With the ends
``W_(i,1) = S_(i,1)`` and ``W_(i,i) = 1 - S_(i,i-1)``, single cells too, rows
``2``, ``3`` and ``N - 1`` are one-time in full (:func:`one_time_rows`).
Checked exactly against the order-ideal DP (tests/test_covers.py).

Examples
--------
>>> rows = cover_row_moments(6, 5)  # layer N - 1 of N = 6
>>> [str(x) for x in rows[2]]
['3/136', '3/44', '69/748', '3/44', '3/136']
>>> from forcenet.exact.triangle.moments import moment_table
>>> rows[2] == moment_table(6, 2)[4]  # the order-ideal DP
True
"""

from __future__ import annotations

from concurrent.futures import Executor
from dataclasses import replace
from fractions import Fraction
from os import PathLike
from typing import Any

from forcenet.core.checkpoints import CheckpointStore
from forcenet.core.errors import ArgumentError
from forcenet.core.plan import Plan
from forcenet.core.validation import check_int, check_layers

from .partial_sums import partial_sum_moments, partial_sum_moments_cost
from .route import MAX_N

__all__ = ["covers", "cover_spans", "one_time_rows", "cover_row_moments", "cover_row_plan", "cover_row_cost"]

Cell = tuple[int, int]


def covers(N: int, cell: Cell) -> tuple[list[Cell], list[Cell]]:
    """The free partial sums a cell ``S_(i,j)`` must exceed and those it must stay below (its covers).

    The interlacing of Eqs. (4.8)-(4.9): ``S_(i-1,j-1) <= S_(i,j) <= S_(i-1,j)``
    and ``S_(i+1,j) <= S_(i,j) <= S_(i+1,j+1)``.  The constants ``S_(i,0) = 0``
    and ``S_(i,i) = 1`` are left out (they bound nothing a free cover does not).

    Parameters
    ----------
    N : int
        Number of layers, ``>= 2``.
    cell : (int, int)
        ``(i, j)``, ``2 <= i <= N``, ``1 <= j <= i - 1``.

    Returns
    -------
    (lower, upper) : (list of (int, int), list of (int, int))

    Raises
    ------
    ArgumentError
        If the cell is not a free partial sum of ``N`` layers.

    Examples
    --------
    >>> covers(5, (5, 2))  # a floor cell: one cover on each side
    ([(4, 1)], [(4, 2)])
    >>> covers(5, (3, 1))
    ([(4, 1)], [(2, 1), (4, 2)])
    """
    N = check_layers(N)
    i = check_int(cell[0], "i", 2, N)
    return _covers(N, i, check_int(cell[1], "j", 1, i - 1))


def _covers(N: int, i: int, j: int) -> tuple[list[Cell], list[Cell]]:
    """:func:`covers` of a checked cell (every cell of :func:`cover_spans`'s loop): Eqs. (4.8)-(4.9)."""
    lower = ([(i - 1, j - 1)] if j >= 2 else []) + ([(i + 1, j)] if i < N else [])
    upper = ([(i - 1, j)] if j <= i - 2 else []) + ([(i + 1, j + 1)] if i < N else [])
    return lower, upper


def cover_spans(N: int) -> dict[Cell, tuple[Cell, ...]]:
    """``{load (i, j): cells}``: every load ``W_ij = S_ij - S_(i,j-1)`` that is the span ``U - L`` of a cell.

    A cell with at most one free cover on each side has ``L`` and ``U`` single
    partial sums (or the constants ``0``, ``1``); when they are consecutive in
    one layer, (C) of the module docstring gives the load's second moment.
    Found from :func:`covers`: the floor cells ``(N, j)`` span the loads
    ``(N - 1, j)``, and ``(2, 1)`` spans ``(3, 2)``; no other cell spans a load
    (at ``N = 4`` two cells span ``W_(3,2)``).

    Parameters
    ----------
    N : int
        Number of layers, ``>= 2``.

    Returns
    -------
    dict of (int, int) to tuple of (int, int)
        The loads, sorted, each with the cells that span it.

    Examples
    --------
    >>> cover_spans(5)
    {(3, 2): ((2, 1),), (4, 1): ((5, 1),), (4, 2): ((5, 2),), (4, 3): ((5, 3),), (4, 4): ((5, 4),)}
    """
    return _cover_spans(check_layers(N))


def _cover_spans(N: int) -> dict[Cell, tuple[Cell, ...]]:
    """:func:`cover_spans` of a checked ``N``."""
    spans: dict[Cell, tuple[Cell, ...]] = {}
    for i in range(2, N + 1):
        for j in range(1, i):
            lower, upper = _covers(N, i, j)
            if len(lower) > 1 or len(upper) > 1:
                continue
            if lower and upper:  # S_(a,b) and S_(a,b+1)
                (a, b), (c, e) = lower[0], upper[0]
                load = (a, e) if a == c and e == b + 1 else None
            elif upper:  # 0 = S_(c,0) and S_(c,1)
                c, e = upper[0]
                load = (c, 1) if e == 1 else None
            elif lower:  # S_(a,a-1) and 1 = S_(a,a)
                a, b = lower[0]
                load = (a, a) if b == a - 1 else None
            else:  # N = 2: the floor cell between 0 and 1 spans the apex
                load = (1, 1)
            if load is not None:
                spans[load] = spans.get(load, ()) + ((i, j),)
    return dict(sorted(spans.items()))


def one_time_rows(N: int) -> list[int]:
    """The rows ``i`` whose every load has a one-time ``<W^2>``: spanned by a cell, or an end ``j = 1``, ``j = i``.

    Examples
    --------
    >>> one_time_rows(12)
    [1, 2, 3, 11]
    """
    return _one_time_rows(check_layers(N))


def _one_time_rows(N: int) -> list[int]:
    """:func:`one_time_rows` of a checked ``N``."""
    spans = _cover_spans(N)
    return [i for i in range(1, N + 1) if all(j in (1, i) or (i, j) in spans for j in range(1, i + 1))]


def _row_refusal(N: int, i: int) -> str | None:
    """Why the cover identity does not give row ``i`` (a checked ``1 <= i <= N``), or None."""
    rows = _one_time_rows(N)
    if i in rows:
        return None
    return (f"row={i} is out of range for the cover identity: it closes the rows {', '.join(map(str, rows))} of "
            f"N={N} (the loads of other rows need two-time routes)")


def _check_row(N: int, i: int) -> int:
    i = check_int(i, "row", 1, N)
    refusal = _row_refusal(N, i)
    if refusal is not None:
        raise ArgumentError(refusal)
    return i


def cover_row_plan(N: int, i: int, *, memory_bytes: int | None = None, workers: int | None = None,
                   executor: Executor | None = None,
                   checkpoint: str | PathLike | CheckpointStore | None = None) -> Plan:
    """The cost of :func:`cover_row_moments`: :func:`~.partial_sums.partial_sum_moments_plan`, any row.

    Refused for a row the identity does not close (:func:`one_time_rows`) and beyond ``N = 200``.

    Examples
    --------
    >>> plan = cover_row_plan(40, 39)
    >>> plan.runnable, plan.unit
    (True, 'prime')
    >>> cover_row_plan(40, 20).refusal
    'row=20 is out of range for the cover identity: it closes the rows 1, 2, 3, 39 of N=40 (the loads of other rows need two-time routes)'
    """
    N = check_layers(N)
    what = f"row {i} of <W>, <W^2> N={N} (one-time: each cell uniform between its covers; partial sums by Pfaffians)"
    if N > MAX_N:
        return Plan(what, 0, refusal=f"N={N} is out of range for the cover identity: N must be an integer in 2..{MAX_N}")
    try:
        i = check_int(i, "row", 1, N)
    except ArgumentError as error:
        return Plan(what, 0, refusal=str(error))
    return cover_row_cost(N, i, memory_bytes=memory_bytes, workers=workers, executor=executor, checkpoint=checkpoint)


def cover_row_cost(N: int, i: int, *, memory_bytes: int | None = None, workers: int | None = None,
                   executor: Executor | None = None,
                   checkpoint: str | PathLike | CheckpointStore | None = None) -> Plan:
    """:func:`cover_row_plan` of a checked request's ``N`` and row (``1 <= i <= N``): what the row's engine plans
    with, nothing checked again.

    Examples
    --------
    >>> cover_row_cost(40, 39) == cover_row_plan(40, 39)
    True
    """
    what = f"row {i} of <W>, <W^2> N={N} (one-time: each cell uniform between its covers; partial sums by Pfaffians)"
    if N > MAX_N:
        return Plan(what, 0, refusal=f"N={N} is out of range for the cover identity: N must be an integer in 2..{MAX_N}")
    refusal = _row_refusal(N, i)
    if refusal is not None:
        return Plan(what, 0, refusal=refusal)
    plan = partial_sum_moments_cost(N, memory_bytes=memory_bytes, workers=workers, executor=executor,
                                    checkpoint=checkpoint)
    return replace(plan, what=what)


def cover_row_moments(N: int, i: int, **kwargs: Any) -> dict[int, list[Fraction]]:
    """``{1: <W_(i,j)>, 2: <W_(i,j)^2>}``, ``j = 1..i``, of a one-time row, exact (module docstring).

    Parameters
    ----------
    N : int
        Number of layers, ``2..200``.
    i : int
        A row of :func:`one_time_rows`: ``1``, ``2``, ``3`` or ``N - 1``.
    **kwargs
        ``workers``, ``progress``, ``executor``, ``checkpoint`` of
        :func:`~.partial_sums.partial_sum_moments` (results do not depend on them).

    Returns
    -------
    dict of int to list of Fraction

    Raises
    ------
    ArgumentError
        If ``N`` is out of range or the identity does not close row ``i``.

    Examples
    --------
    >>> cover_row_moments(5, 3)[2]  # row 3: W_(3,2) from the cell S_(2,1), the ends are S_(3,1), 1 - S_(3,2)
    [Fraction(23, 198), Fraction(1, 6), Fraction(23, 198)]
    """
    N = check_layers(N, maximum=MAX_N)
    i = _check_row(N, i)
    if i == 1:
        return {1: [Fraction(1)], 2: [Fraction(1)]}
    moments = partial_sum_moments(N, **kwargs)
    first, second = moments[1], moments[2]

    def cell(s: int, a: int, b: int) -> Fraction:
        """``<S_(a,b)^s>`` with the constants ``S_(a,0) = 0``, ``S_(a,a) = 1``."""
        return Fraction(b > 0) if b in (0, a) else (first, second)[s - 1][a - 1][b - 1]

    spans = cover_spans(N)
    mean = [cell(1, i, j) - cell(1, i, j - 1) for j in range(1, i + 1)]
    square = []
    for j in range(1, i + 1):
        if (i, j) in spans:  # (C): U = S_(i,j), L = S_(i,j-1)
            x = spans[i, j][-1]  # the floor cell for layer N - 1
            square.append(3 * (cell(2, i, j - 1) + cell(2, i, j)) - 6 * cell(2, *x))
        elif j == 1:  # W_(i,1) = S_(i,1)
            square.append(cell(2, i, 1))
        else:  # W_(i,i) = 1 - S_(i,i-1)
            square.append(1 - 2 * cell(1, i, i - 1) + cell(2, i, i - 1))
    return {1: mean, 2: square}
