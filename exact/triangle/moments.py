"""Exact moments of the vertical forces W of the fully mobilized triangle.

A uniform point of the order polytope is a uniform random standard tableau
``T`` of the shifted staircase together with ``d`` sorted independent uniform
numbers placed by rank (``notes/order_polytope.md``).  Hence, with ``g`` the
number of gaps between the two partial sums that bound ``W[i][j]``,

* ``E[W] = E[g] / (d + 1)`` (order statistics),
* ``E[W**s] = E[g (g+1) ... (g+s-1)] / ((d+1) (d+2) ... (d+s))`` (a sum of
  ``g`` Dirichlet(1, ..., 1) spacings is Beta(g, d + 1 - g)),
* ``E[W W'] = E[g g' + |overlap|] / ((d+1) (d+2))``.

The expectations over tableaux are exact path sums over order ideals
(:mod:`forcenet.exact.triangle.ideal_dp`).  All results are :class:`fractions.Fraction`.

References
----------
S. Ostojic, PhD thesis (2006), Eqs. (4.3), (4.63)-(4.85).
"""

from __future__ import annotations

from collections.abc import Callable
from concurrent.futures import Executor
from fractions import Fraction
from functools import lru_cache
from math import comb, factorial
from typing import Any

import numpy as np

from forcenet.core.errors import ArgumentError
from forcenet.core.plan import Plan, combine
from forcenet.core.validation import check_grain, check_int, check_layers

from ..modular import crt, primes_for_bound
from ..protocol import Progress, Table, TableEngine, TableRequest, bounded_result, check_table_request, run_independent
from .ideal_dp import estimate_survival_cost, marked_chain_sums, parts_table, survival_counts
from .spacings import rising
from .staircase import free_force_count, tableau_count

__all__ = [
    "mean_W",
    "mean_W_grain",
    "moment",
    "moment_table",
    "correlation",
    "covariance",
    "variance_table",
    "mean_W_plan",
    "moment_table_plan",
    "table_plan",
    "table_run",
]


@lru_cache(maxsize=8)
def _survival(N: int) -> tuple[list[list[int]], int]:
    return survival_counts(N)


def _mean_numerator(N: int, i: int, j: int, C: list[list[int]]) -> int:
    """``total (d+1) E[W_ij]`` = survival weight of ideals between the bounds."""
    m = N - i + 1  # diagonal of row i
    upper = C[j - 1][m]
    lower = C[j][m] if j <= N - 1 else 0  # lambda_N = 0: no N-th part
    return upper - lower


@bounded_result(0, 1, "every W of the triangle lies in [0, 1]")
def mean_W(N: int, progress: Progress | None = None, memory_bytes: int | None = None) -> list[list[Fraction]]:
    """Exact table of ``<W_{i,j}>``, rows ``i = 1..N``, ``j = 1..i``.

    Parameters
    ----------
    N : int
        Number of layers, ``N >= 2``.
    progress : callable, optional
        Progress callback of :func:`forcenet.exact.triangle.ideal_dp.survival_counts`.
    memory_bytes : int, optional
        Budget for the residue tables (default 12 GiB); primes are processed
        in chunks that fit.

    Returns
    -------
    list of lists of Fraction
        ``table[i-1][j-1] = <W_{i,j}>``.

    Raises
    ------
    ArgumentError
        If ``N`` is not an integer ``>= 2`` or ``memory_bytes`` cannot hold one prime's tables.

    Examples
    --------
    >>> [str(x) for x in mean_W(5)[-1]]
    ['1/11', '1/4', '7/22', '1/4', '1/11']

    References
    ----------
    Ostojic (2006), Eqs. (4.63)-(4.77); Fig. 4.3 compares N = 11.
    """
    return _mean_table(_dp_layers(N, "mean_W", memory_bytes), progress, memory_bytes)


def _mean_table(N: int, progress: Progress | None = None, memory_bytes: int | None = None) -> Table:
    """:func:`mean_W` for ``N`` already checked (the engine's inside, :func:`table_run`)."""
    if progress is not None or memory_bytes is not None:
        C, total = survival_counts(N, progress, **({"memory_bytes": memory_bytes} if memory_bytes else {}))
    else:
        C, total = _survival(N)
    d = free_force_count(N)
    den = total * (d + 1)
    return [[Fraction(_mean_numerator(N, i, j, C), den) for j in range(1, i + 1)] for i in range(1, N + 1)]


def mean_W_grain(N: int, i: int, j: int) -> Fraction:
    """Exact ``<W_{i,j}>`` of one grain, Eqs. (4.63)-(4.77).

    Parameters
    ----------
    N : int
        Number of layers, ``N >= 2``.
    i, j : int
        The grain, row ``i`` and position ``j``, ``1 <= j <= i <= N``.

    Returns
    -------
    Fraction

    Raises
    ------
    ArgumentError
        If ``N`` is not an integer ``>= 2`` or the grain is not ``1 <= j <= i <= N``.

    Examples
    --------
    >>> mean_W_grain(6, 6, 2)
    Fraction(413, 2288)
    """
    N = _dp_layers(N, "mean_W_grain")
    i, j = check_grain(N, (i, j))
    C, total = _survival(N)
    d = free_force_count(N)
    return Fraction(_mean_numerator(N, i, j, C), total * (d + 1))


def _eligible(lam: np.ndarray, N: int, i: int, j: int) -> np.ndarray:
    """Ideals lying between the partial sums that bound ``W_ij`` (bool per mask)."""
    m = N - i + 1
    return (lam[:, j - 1] >= m) & (lam[:, j] < m)


_STATE_BUDGET = 8 * 2**30  # bytes of one marked-chain DP (states x primes x ideals)
_MEAN_MAX_N = 40  # 2^39 ideals: beyond any machine, the estimate itself is skipped
_RESIDUE_CAP = 12 * 2**30  # mean_W's residue tables, at most
_MOMENT_BATCH_BYTES = 4 * 2**30  # moment_table's batch of grains, at most
_SECONDS_PER_STATE = 6.5e-8  # moment_table per ideal x grain x state x prime, measured N = 14..17 (2 cores)


def mean_W_plan(N: int, memory_bytes: int | None = None) -> Plan:
    """The cost of :func:`mean_W` for ``N`` layers: a :class:`~forcenet.core.plan.Plan`.

    ``memory_bytes`` is the memory available to the run (None: not
    checked); the residue tables are chunked to 3/4 of it, at most 12 GiB
    (None: 12 GiB).

    Examples
    --------
    >>> mean_W_plan(12).seconds < 1
    True
    >>> mean_W_plan(41).refusal
    'N=41 is out of range for the exact table: N must be an integer in 2..40'
    """
    return _mean_plan(check_layers(N), memory_bytes)


def _mean_plan(N: int, memory_bytes: int | None) -> Plan:
    what = f"exact table N={N} (order ideals)"
    if N > _MEAN_MAX_N:
        return Plan(what, 0, refusal=f"N={N} is out of range for the exact table: N must be an integer in 2..{_MEAN_MAX_N}")
    budget = _budget(memory_bytes, _RESIDUE_CAP)
    est = estimate_survival_cost(N, budget)
    plan = Plan(what, est.seconds, est.nbytes, est.ticks, "ideal")
    if est.nbytes > budget:
        fits = [M for M in range(2, N) if estimate_survival_cost(M, budget).nbytes <= budget]
        where = f"N must be an integer in 2..{fits[-1]} here" if fits else "no N fits it: give more memory_bytes"
        return plan.refuse(f"N={N} is out of range for the exact table here: it needs ~{est.nbytes / 2**30:.1f} GiB "
                           f"but {budget / 2**30:.1f} GiB is available; {where}")
    return plan


_BEYOND_DP = ("beyond the order-ideal DP's wall, forcenet.exact.triangle.pfaffian_table reaches N = 200 in time polynomial "
              "in N: mean_W(N) (N = 64 ~1.6 min, N = 100 ~36 min on 2 cores), moments_run(N, s) for <W^s> to N = 128 "
              "(forcenet table --N N --method pfaffian [--moments s])")


def _dp_layers(N: Any, what: str, memory_bytes: int | None = None) -> int:
    """``N`` checked, and refused where the order-ideal DP (``2^(N-1)`` ideals) cannot run: before any work,
    naming the Pfaffian route that reaches that ``N`` and its cost."""
    N = check_layers(N)
    plan = _mean_plan(N, memory_bytes)
    if not plan.runnable:
        raise ArgumentError(f"{what}(N={N}): {plan.refusal} (the DP over the 2^(N-1) order ideals); {_BEYOND_DP}")
    return N


def _budget(memory_bytes: int | None, cap: int) -> int:
    """Bytes of the residue or state tables: 3/4 of the available memory, at most ``cap`` (None: ``cap``)."""
    return cap if memory_bytes is None else min(memory_bytes * 3 // 4, cap)


def moment_table_plan(N: int, s: int, memory_bytes: int | None = None) -> Plan:
    """The cost of :func:`moment_table` for ``N`` layers and order ``s``.

    One forward pass over the ``2^(N-1)`` ideals per batch of grains, each
    grain carrying ``s + 1`` states per prime (calibrated at N = 14..17 on 2
    cores; N = 18, s = 2: ~40 s announced, 34 s measured).

    Examples
    --------
    >>> moment_table_plan(12, 2).seconds < 2
    True
    """
    return _moment_plan(check_layers(N), check_int(s, "s", 1), memory_bytes)


def _moment_plan(N: int, s: int, memory_bytes: int | None) -> Plan:
    n, d = N - 1, free_force_count(N)
    grains = N * (N + 1) // 2
    what = f"<W^{s}> table N={N}"
    if N > 24:
        return Plan(what, 0, refusal=f"N={N} is out of range for --moments {s}: N must be an integer in 2..24")
    primes = len(primes_for_bound(tableau_count(N) * comb(d + s, s)))
    per_grain = (1 << n) * (s + 1) * primes * 8 * 3
    batch = max(1, min(grains, _budget(memory_bytes, _MOMENT_BATCH_BYTES) // per_grain))
    passes = -(-grains // batch)
    seconds = _SECONDS_PER_STATE * (1 << n) * grains * (s + 1) * primes + 0.5
    nbytes = int(0.55 * batch * per_grain) + 150 * 2**20
    plan = Plan(what, seconds, nbytes, passes * ((1 << n) - 1), "ideal")
    state = (1 << n) * (s + 1) * primes * 8 * 2
    if state > _STATE_BUDGET:
        plan = plan.refuse(f"N={N} is out of range for --moments {s}: one grain's path-sum table needs "
                           f"~{state / 2**30:.0f} GiB (limit {_STATE_BUDGET / 2**30:.0f} GiB)")
    return plan.within_memory(memory_bytes)


def _check_state_memory(N: int, n_states: int, n_primes: int) -> None:
    nbytes = (1 << (N - 1)) * n_states * n_primes * 8 * 2
    if nbytes > _STATE_BUDGET:
        raise ArgumentError(
            f"N={N} is out of range for this moment: its path-sum table needs ~{nbytes / 2**30:.0f} GiB "
            f"(budget {_STATE_BUDGET / 2**30:.0f} GiB); use a smaller N (about N <= 20 for s = 2)"
        )


@bounded_result(0, 1, "every W^s of the triangle lies in [0, 1]")
def moment_table(N: int, s: int = 2, *, memory_bytes: int | None = None, progress: Progress | None = None) -> Table:
    """Exact ``<W_{i,j}^s>`` for every grain.

    One forward pass over the ideal lattice per batch of grains; the state of a
    grain counts multisets of ``s`` ideals between its bounding partial sums,
    so ``E[g^(s rising)] = s! * F[full][s] / count``.  The batches of grains
    fill 3/4 of ``memory_bytes``, at most 4 GiB (None: 4 GiB), as
    :func:`moment_table_plan` counts them.  Eq. (4.3) with the Beta moments of
    the order statistics.

    Parameters
    ----------
    N : int
        Number of layers, ``N >= 2``.
    s : int
        Order of the moment, ``s >= 1``.
    memory_bytes : int, optional
        Memory for the batches of grains (None: 4 GiB).
    progress : callable, optional
        Progress callback, one tick per ideal-lattice layer.

    Returns
    -------
    list of lists of Fraction
        ``table[i-1][j-1] = <W_{i,j}^s>``.

    Raises
    ------
    ArgumentError
        If ``N`` or ``s`` is out of range, or one grain's path-sum table
        exceeds the memory budget.

    Examples
    --------
    >>> [str(x) for x in moment_table(4, 2)[-1]]
    ['1/28', '9/56', '9/56', '1/28']
    """
    return _moment_table(_dp_layers(N, "moment_table", memory_bytes), check_int(s, "s", 1), memory_bytes, progress)


def _moment_table(N: int, s: int, memory_bytes: int | None = None, progress: Progress | None = None) -> Table:
    """:func:`moment_table` for ``N`` and ``s`` already checked (the engine's inside, :func:`table_run`)."""
    n, d = N - 1, free_force_count(N)
    total = tableau_count(N)
    grains = [(i, j) for i in range(1, N + 1) for j in range(1, i + 1)]
    if n == 0:
        return [[Fraction(1)]]
    primes = primes_for_bound(total * comb(d + s, s))
    _check_state_memory(N, s + 1, len(primes))
    lam = parts_table(n)
    per_grain = (1 << n) * (s + 1) * len(primes) * 8 * 3  # state table and temporaries
    batch = max(1, min(len(grains), _budget(memory_bytes, _MOMENT_BATCH_BYTES) // per_grain))
    values = {}
    for start in range(0, len(grains), batch):
        chunk = grains[start : start + batch]
        elig = np.stack([_eligible(lam, N, i, j) for i, j in chunk], axis=1)  # (masks, B)

        size = len(chunk)

        def update(masks: np.ndarray, acc: np.ndarray, elig: np.ndarray = elig, B: int = size) -> np.ndarray:
            acc = acc.reshape(acc.shape[0], B, s + 1, -1)
            cum = np.cumsum(acc, axis=2)
            out = np.where(elig[masks][:, :, None, None], cum, acc)
            return out.reshape(acc.shape[0], B * (s + 1), -1)

        initial = ([1] + [0] * s) * len(chunk)
        final = marked_chain_sums(n, primes, initial, update, progress)
        final = final.reshape(len(chunk), s + 1, -1)
        for b, grain in enumerate(chunk):
            multisets = crt(final[b, s], primes)
            values[grain] = Fraction(factorial(s) * multisets, total * rising(d + 1, s))
    return [[values[(i, j)] for j in range(1, i + 1)] for i in range(1, N + 1)]


def moment(N: int, grain: tuple[int, int], s: int) -> Fraction:
    """Exact ``<W_{i,j}^s>`` for one grain and any order ``s >= 1``, Eq. (4.3).

    Parameters
    ----------
    N : int
        Number of layers, ``N >= 2``.
    grain : tuple of int
        ``(i, j)`` with ``1 <= j <= i <= N``.
    s : int
        Order of the moment, ``s >= 1``.

    Returns
    -------
    Fraction

    Raises
    ------
    ArgumentError
        If ``N``, ``grain`` or ``s`` is out of range, or the path-sum table
        exceeds its memory budget.

    Examples
    --------
    >>> moment(5, (5, 1), 1)
    Fraction(1, 11)
    >>> moment(5, (5, 1), 2)
    Fraction(1, 66)
    """
    N = _dp_layers(N, "moment")
    i, j = check_grain(N, grain)
    s = check_int(s, "s", 1)
    if s == 1:
        return mean_W_grain(N, i, j)
    return _single_moment(N, i, j, s)


@lru_cache(maxsize=256)
def _single_moment(N: int, i: int, j: int, s: int) -> Fraction:
    n, d = N - 1, free_force_count(N)
    total = tableau_count(N)
    primes = primes_for_bound(total * comb(d + s, s))
    _check_state_memory(N, s + 1, len(primes))
    lam = parts_table(n)
    elig = _eligible(lam, N, i, j)

    def update(masks: np.ndarray, acc: np.ndarray) -> np.ndarray:
        return np.where(elig[masks][:, None, None], np.cumsum(acc, axis=1), acc)

    final = marked_chain_sums(n, primes, [1] + [0] * s, update)
    return Fraction(factorial(s) * crt(final[s], primes), total * rising(d + 1, s))


def correlation(N: int, grain1: tuple[int, int], grain2: tuple[int, int]) -> Fraction:
    """Exact two-point function ``<W_{i,j} W_{k,l}>``, Sec. 4.5.2.

    Parameters
    ----------
    N : int
        Number of layers, ``N >= 2``.
    grain1, grain2 : tuple of int
        The grains ``(i, j)`` and ``(k, l)``, each inside the triangle.

    Returns
    -------
    Fraction

    Raises
    ------
    ArgumentError
        If ``N`` or a grain is out of range, or the path-sum table exceeds
        its memory budget.

    Examples
    --------
    >>> correlation(4, (4, 1), (4, 4))
    Fraction(1, 56)
    >>> correlation(4, (4, 2), (4, 2)) == moment(4, (4, 2), 2)
    True

    References
    ----------
    Ostojic (2006), Sec. 4.5.2.
    """
    N = _dp_layers(N, "correlation")
    g1 = check_grain(N, grain1, "grain1")
    g2 = check_grain(N, grain2, "grain2")
    return _correlation(N, *sorted([g1, g2]))


@lru_cache(maxsize=256)
def _correlation(N: int, g1: tuple[int, int], g2: tuple[int, int]) -> Fraction:
    n, d = N - 1, free_force_count(N)
    total = tableau_count(N)
    primes = primes_for_bound(total * (d + 1) * (d + 2))
    _check_state_memory(N, 4, len(primes))
    lam = parts_table(n)
    e1 = _eligible(lam, N, *g1)
    e2 = _eligible(lam, N, *g2)

    def update(masks: np.ndarray, acc: np.ndarray) -> np.ndarray:
        a, b = e1[masks][:, None], e2[masks][:, None]
        s00, s10, s01, s11 = acc[:, 0], acc[:, 1], acc[:, 2], acc[:, 3]
        return np.stack(
            [s00, s10 + a * s00, s01 + b * s00, s11 + a * s01 + b * s10 + 2 * (a & b) * s00],
            axis=1,
        )

    final = marked_chain_sums(n, primes, [1, 0, 0, 0], update)
    return Fraction(crt(final[3], primes), total * (d + 1) * (d + 2))


def covariance(N: int, grain1: tuple[int, int], grain2: tuple[int, int]) -> Fraction:
    """``<W W'> - <W><W'>``, exact (Sec. 4.5.2).

    Parameters
    ----------
    N : int
        Number of layers, ``N >= 2``.
    grain1, grain2 : tuple of int
        The grains ``(i, j)`` and ``(k, l)``, each inside the triangle.

    Returns
    -------
    Fraction

    Raises
    ------
    ArgumentError
        If ``N`` or a grain is out of range.

    Examples
    --------
    >>> covariance(4, (4, 1), (4, 4))
    Fraction(-1, 392)
    """
    N = _dp_layers(N, "covariance")
    g1 = check_grain(N, grain1, "grain1")
    g2 = check_grain(N, grain2, "grain2")
    return correlation(N, g1, g2) - mean_W_grain(N, *g1) * mean_W_grain(N, *g2)


def variance_table(N: int) -> list[list[Fraction]]:
    """Exact ``Var W_{i,j} = <W^2> - <W>^2`` for every grain, Eq. (4.3).

    Parameters
    ----------
    N : int
        Number of layers, ``N >= 2``.

    Returns
    -------
    list of lists of Fraction
        ``table[i-1][j-1] = Var W_{i,j}``.

    Examples
    --------
    >>> [str(x) for x in variance_table(4)[-1]]
    ['3/196', '13/392', '13/392', '3/196']
    """
    means = mean_W(N)
    second = moment_table(N, 2)
    return [[m2 - m * m for m, m2 in zip(r1, r2)] for r1, r2 in zip(means, second)]


# ------------------------------------------------------ the table route (--method fast): plan and run


def table_plan(N: int, moments: int = 1, *, memory_bytes: int | None = None, executor: Executor | None = None) -> Plan:
    """The cost of :func:`table_run` (``forcenet table --method fast``): the order-ideal DP.

    The engine protocol (:mod:`forcenet.exact.protocol`): ``<W>`` by one pass
    of survival counts, each ``<W^s>`` by its own passes (independent tasks
    on ``executor``); refused beyond ``memory_bytes``.

    Parameters
    ----------
    N : int
        Number of layers, ``>= 2``.
    moments : int
        Highest moment ``s`` of ``W^s``, ``>= 1``.
    memory_bytes : int, optional
        Memory available to the run (None: not checked).
    executor : concurrent.futures.Executor, optional
        Where the independent passes run (default: this process).

    Returns
    -------
    Plan

    Raises
    ------
    ArgumentError
        If ``N`` or ``moments`` is out of range.

    Examples
    --------
    >>> table_plan(9).runnable, table_plan(9, 2).what
    (True, 'exact tables N=9, <W^s> for s = 1..2 (order ideals)')
    >>> table_plan(20, memory_bytes=2**20).runnable
    False
    """
    return ENGINE.plan(check_table_request(N, moments, memory_bytes=memory_bytes, executor=executor))


class IdealEngine(TableEngine):
    """The ``fast`` table engine: ``<W^s>`` by the order-ideal path sums (the default up to N ~ 28-30)."""

    name = "fast"

    def table_plan(self, request: TableRequest) -> Plan:
        """The plan of the whole table for the checked ``request`` (:meth:`TableEngine.table_plan`)."""
        N, moments, memory_bytes = request.N, request.moments, request.memory_bytes
        plans = _pass_plans(N, moments, memory_bytes)
        what = plans[0].what if moments == 1 else f"exact tables N={N}, <W^s> for s = 1..{moments} (order ideals)"
        return combine(what, plans, "ideal")

    def tables(self, request: TableRequest, plan: Plan, progress: Progress | None,
               executor: Executor | None) -> dict[int, Table]:
        """The tables of the checked ``request`` as its runnable ``plan`` says (:meth:`TableEngine.tables`)."""
        N, moments, memory_bytes = request.N, request.moments, request.memory_bytes
        weights = None if executor is None else [p.ticks for p in _pass_plans(N, moments, memory_bytes)]
        calls: list[tuple[Callable[..., Any], tuple, dict]] = [(_mean_table, (N,), {"memory_bytes": _budget(memory_bytes, _RESIDUE_CAP)})]
        calls += [(_moment_table, (N, s), {"memory_bytes": memory_bytes}) for s in range(2, moments + 1)]
        tables = run_independent(calls, executor=executor, progress=progress, weights=weights)
        return dict(enumerate(tables, start=1))


ENGINE = IdealEngine()


def _pass_plans(N: int, moments: int, memory_bytes: int | None) -> list[Plan]:
    """The plans of the run's independent passes: ``<W>``, then ``<W^s>`` for ``s = 2..moments``."""
    return [_mean_plan(N, memory_bytes)] + [_moment_plan(N, s, memory_bytes) for s in range(2, moments + 1)]


def table_run(N: int, moments: int = 1, *, memory_bytes: int | None = None, progress: Progress | None = None,
              executor: Executor | None = None) -> dict[int, Table]:
    """``{s: <W^s> table}`` for ``s = 1..moments`` by the order-ideal DP (exact Fractions).

    Parameters
    ----------
    N, moments, memory_bytes, executor
        As in :func:`table_plan`.
    progress : callable, optional
        ``progress(k=1)`` with the plan's ticks (ideals).

    Returns
    -------
    dict of int to list of lists of Fraction

    Raises
    ------
    ArgumentError
        If the arguments are out of range or the plan needs more than ``memory_bytes``.

    Examples
    --------
    >>> [str(x) for x in table_run(5, 2)[2][-1]]
    ['1/66', '65/792', '25/198', '65/792', '1/66']
    """
    request = check_table_request(N, moments, memory_bytes=memory_bytes, executor=executor)
    return ENGINE.run(request, ENGINE.plan(request).check(), progress=progress)


