"""Second moments of every partial sum ``S_ij`` (and of every tableau entry) from the mean's own evaluations.

A partial sum ``S_ij = W_i1 + ... + W_ij`` is a single cell ``x`` of the
staircase (``notes/fluctuations.md`` Sec. 1): the order statistic of rank
``T(x)`` among ``d`` uniforms, ``T(x) = #{l : x not in I_l}`` along the chain of
ideals.  So ``E[S^2] = E[T(T+1)]/((d+1)(d+2))`` and, since ``x`` leaves the
ideals at the levels ``0..T-1``, ``T(T+1) = 2 sum_(l : x not in I_l) (l + 1)``:
a *one-time* quantity, the mean's level sums weighted by ``l + 1``,

    E[T(r, c)(T(r, c) + 1)] count = 2 sum_(k < r) S2[c - r + 1][k],
    S2[m][k] = sum_A (|A| + 1) w(A) [N_m(A) = k],

the functional ``q^l -> (l+1)! (d-l)!`` on the same Pfaffian evaluations as
``S`` (:func:`~.engine.prime_residues` with ``second=True``): the variance of
every partial sum for about the price of the mean table, to N = 100 and
beyond.  A load's ``<W^2>`` is not a single cell's, but three single cells
give it for every load of layer ``N - 1`` and of rows 2 and 3: a cell is
uniform between its covers (Sec. 3.1, :mod:`.covers`).  For the other
interior loads no one-time formula is known (Sec. 3 proves only that the
one-time marginals alone, valid for any measure on chains, do not fix it);
their route is one layer's de Bruijn grid (Sec. 6).  The bound
``0 <= S2 <= (d+1)(d+2)/2 count`` makes the Chinese remainders exact.  Checked against the order-ideal DP's moments and
correlations and the linear extensions (tests/test_partial_sums.py).

Examples
--------
>>> second = partial_sum_moments(4)[2]
>>> [str(x) for x in second[-1]]  # <S_{4,j}^2>, j = 1..4; S_{4,4} = 1
['1/28', '2/7', '3/4', '1']
"""

from __future__ import annotations

from collections.abc import Callable
from concurrent.futures import Executor
from fractions import Fraction
from os import PathLike
from typing import Any

from forcenet.core.checkpoints import CheckpointStore
from forcenet.core.execution import as_executor
from forcenet.core.plan import Plan
from forcenet.core.validation import check_layers

from ..prime_tasks import checkpoint_store
from ..staircase import dimension, free_force_count
from .cost import prime_seconds, worker_bytes
from .route import MAX_N, route_plan, survival_tables

__all__ = ["second_survival_tables", "entry_moments", "partial_sum_moments", "partial_sum_moments_plan",
           "partial_sum_moments_cost"]

Table = list[list[Fraction]]


def partial_sum_moments_plan(N: int, *, memory_bytes: int | None = None, workers: int | None = None,
                             executor: Executor | None = None,
                             checkpoint: str | PathLike | CheckpointStore | None = None) -> Plan:
    """The cost of :func:`partial_sum_moments`: the mean table's cost per prime, a few more primes.

    Parameters
    ----------
    N : int
        Number of layers, ``2..200``.
    memory_bytes : int, optional
        Memory available to the run (None: not checked); a plan over it is refused.
    workers : int, optional
        Local worker processes (default: the cores when the run pays for them).
    executor : concurrent.futures.Executor or Dask Client, optional
        Runs the per-prime tasks; the plan counts its workers.
    checkpoint : str, os.PathLike or CheckpointStore, optional
        The plan counts only the primes not yet recorded there.

    Returns
    -------
    Plan

    Raises
    ------
    ArgumentError
        If ``N`` is outside ``2..200``.
    ArgumentTypeError
        If ``N`` is not an integer.

    Examples
    --------
    >>> from forcenet.exact.triangle.free_fermion.route import mean_plan
    >>> plan = partial_sum_moments_plan(40)
    >>> plan.runnable, plan.unit, plan.ticks > mean_plan(40).ticks
    (True, 'prime', True)
    """
    return partial_sum_moments_cost(check_layers(N, maximum=MAX_N), memory_bytes=memory_bytes, workers=workers,
                                    executor=executor, checkpoint=checkpoint)


def partial_sum_moments_cost(N: int, *, memory_bytes: int | None = None, workers: int | None = None,
                             executor: Executor | None = None,
                             checkpoint: str | PathLike | CheckpointStore | None = None) -> Plan:
    """:func:`partial_sum_moments_plan` of a checked ``N`` (``2..200``), nothing checked again.

    Examples
    --------
    >>> partial_sum_moments_cost(40) == partial_sum_moments_plan(40)
    True
    """
    n, d = N - 1, free_force_count(N)
    what = f"exact <S_ij^2> N={N} (Pfaffians: the mean's evaluations, a second level functional)"
    per_worker = worker_bytes(N, n + 2)
    return route_plan(what, N, prime_seconds(N), per_worker, workers, as_executor(executor),
                      checkpoint_store(checkpoint, "table2", N), memory_bytes, entries=2 * n * n, lattice=False,
                      bound_factor=(d + 2) // 2 + 1)


def second_survival_tables(N: int, *, workers: int | None = None, progress: Callable[[int], object] | None = None,
                           executor: Executor | None = None,
                           checkpoint: str | PathLike | CheckpointStore | None = None
                           ) -> tuple[list[list[int]], list[list[int]], int]:
    """Exact ``S[m][k]``, ``S2[m][k] = sum_A (|A| + 1) w(A) [N_m(A) = k]`` and ``count(N)``.

    Parameters
    ----------
    N : int
        Number of layers, ``2..200``.
    workers, progress, executor, checkpoint
        As in :func:`forcenet.exact.triangle.free_fermion.route.survival_table` (results do not depend on them).

    Returns
    -------
    (S, S2, total) : (list of lists of int, list of lists of int, int)
        Rows ``m = 1..n`` (row 0 unused), columns ``k = 0..n``; the rows of
        ``S`` sum to ``(d + 1) count``, those of ``S2`` to ``(d + 1)(d + 2)/2 count``.

    Raises
    ------
    ArgumentError
        If ``N`` is outside ``2..200``.

    Examples
    --------
    >>> S, S2, total = second_survival_tables(4)
    >>> total, S[3], S2[3]
    (2, [7, 7, 0, 0], [16, 40, 0, 0])
    """
    N = check_layers(N, maximum=MAX_N)
    (S, S2), total = survival_tables(N, workers, progress, as_executor(executor), checkpoint, second=True)
    return S, S2, total


def entry_moments(N: int, **kwargs: Any) -> dict[tuple[int, int], tuple[Fraction, Fraction]]:
    """``(E[T(r, c)], E[T(r, c)^2])`` of a uniform tableau of the staircase, every cell (exact).

    ``E[T] count = sum_(k<r) S[c-r+1][k]`` and ``E[T(T+1)] count = 2 sum_(k<r) S2[c-r+1][k]``.

    Parameters
    ----------
    N : int
        Number of layers, ``2..200``.
    **kwargs
        ``workers``, ``progress``, ``executor``, ``checkpoint`` of :func:`second_survival_tables`.

    Returns
    -------
    dict of (int, int) to (Fraction, Fraction)
        For ``1 <= r <= c <= N - 1``.

    Raises
    ------
    ArgumentError
        If ``N`` is outside ``2..200``.

    Examples
    --------
    >>> entry_moments(3)[(1, 2)]  # T(1, 2) is 2 in the one tableau of N = 3
    (Fraction(2, 1), Fraction(4, 1))
    """
    N = check_layers(N, maximum=MAX_N)
    n = N - 1
    S, S2, total = second_survival_tables(N, **kwargs)
    out = {}
    for r in range(1, n + 1):
        for c in range(r, n + 1):
            m = c - r + 1
            first = Fraction(sum(S[m][:r]), total)
            out[(r, c)] = first, Fraction(2 * sum(S2[m][:r]), total) - first
    return out


def partial_sum_moments(N: int, **kwargs: Any) -> dict[int, Table]:
    """``{1: <S_ij>, 2: <S_ij^2>}`` for every partial sum ``S_ij = W_i1 + ... + W_ij``, exact.

    Row ``i - 1`` holds ``j = 1..i`` (``S_ii = 1``, the load of a layer), the
    layout of the ``<W>`` tables.  ``Var S_ij`` is the variance of the force
    carried by the first ``j`` grains of layer ``i``.

    Parameters
    ----------
    N : int
        Number of layers, ``2..200``.
    **kwargs
        ``workers``, ``progress``, ``executor``, ``checkpoint`` of :func:`second_survival_tables`.

    Returns
    -------
    dict of int to list of lists of Fraction

    Raises
    ------
    ArgumentError
        If ``N`` is outside ``2..200``.

    Examples
    --------
    >>> moments = partial_sum_moments(3)
    >>> moments[1][2], moments[2][2]  # S_{3,1} = W_{3,1}: Beta(1, 3); S_{3,2} = 1 - W_{3,3}
    ([Fraction(1, 4), Fraction(3, 4), Fraction(1, 1)], [Fraction(1, 10), Fraction(3, 5), Fraction(1, 1)])
    """
    N = check_layers(N, maximum=MAX_N)
    d = dimension(N)
    S, S2, total = second_survival_tables(N, **kwargs)
    first: Table = [[Fraction(1)]]
    second: Table = [[Fraction(1)]]
    for i in range(2, N + 1):
        m = N - i + 1  # S_ij is the cell (j, m + j - 1): r = j, c - r + 1 = m
        first.append([Fraction(sum(S[m][:j]), (d + 1) * total) for j in range(1, i)] + [Fraction(1)])
        second.append([Fraction(2 * sum(S2[m][:j]), (d + 1) * (d + 2) * total) for j in range(1, i)] + [Fraction(1)])
    return {1: first, 2: second}
