"""The ``thesis`` engine of ``forcenet table`` (:mod:`forcenet.exact.protocol`): the nested-matrix integration of Secs. 4.3-4.5.

Its plan (measured costs) and its run, over the functions of :mod:`.nested`.
"""

from __future__ import annotations

from concurrent.futures import Executor

from forcenet.core.plan import Plan, table_range

from ..protocol import Progress, Table, TableEngine, TableRequest, check_table_request, run_independent
from .nested import integrate_layers, moment_table_nested

__all__ = ["table_plan", "table_run", "ENGINE"]

# ------------------------------------------------------ the table route: plan and run

# Measured seconds and peak bytes of one integration (modular engine, 2-core machine);
# a table needs N(N+1)/2 + 1 of them.  N = 10 would need bonds of ~4e5 index tuples
# (about 1e10 matrix entries): out of reach (killed at 24 GB).
_TABLE_COST = {2: (0.01, 5e7), 3: (0.01, 5e7), 4: (0.01, 5e7), 5: (0.01, 5e7), 6: (0.01, 6e7),
               7: (0.01, 1e8), 8: (0.13, 3e8), 9: (15.0, 2e9)}  # N = 9: 6-48 s, 1.2-1.9 GB per grain
_MAX_ORDER = 3  # the s-th order defects grow fast: N = 9, s = 3 needs 12 GB
# cost of s = 1, 2, 3 relative to s = 1 at the costliest grain (N, 3):
# N = 8 time x2.4, x4.8; N = 9 time x3.2, x8.0; memory x2.6, x6.5
_TIME_FACTOR = {8: (1.0, 2.4, 4.8), 9: (1.0, 3.2, 8.0)}
_MEMORY_FACTOR = (1.0, 2.6, 6.5)


def table_plan(N: int, moments: int = 1, *, memory_bytes: int | None = None, executor: Executor | None = None) -> Plan:
    """The cost of :func:`table_run` (``--method thesis``): ``<W^s>`` tables, ``s = 1..moments``, by nested integration.

    The engine protocol (:mod:`forcenet.exact.protocol`); one independent
    task per order ``s`` (on ``executor`` if given), the normalization
    integrated once before them.

    Parameters
    ----------
    N : int
        Number of layers, ``>= 2`` (the route reaches ``N <= 9``).
    moments : int
        Highest moment, ``1..3``.
    memory_bytes : int, optional
        Memory available to the run (None: not checked).
    executor : concurrent.futures.Executor, optional
        Where the orders run (default: this process).

    Returns
    -------
    Plan

    Raises
    ------
    ArgumentError
        If ``N`` or ``moments`` is not an integer ``>= 2`` or ``>= 1``.

    Examples
    --------
    >>> table_plan(8).seconds < 60
    True
    >>> table_plan(10).refusal
    'N=10 is out of range for --method thesis: N must be an integer in 2..9 (the nested bonds outgrow memory at N = 10)'
    """
    return ENGINE.plan(check_table_request(N, moments, memory_bytes=memory_bytes, executor=executor))


class NestedEngine(TableEngine):
    """The ``thesis`` table engine: ``<W^s>`` by nested-matrix integration (Secs. 4.3-4.5)."""

    name = "thesis"

    def table_plan(self, request: TableRequest) -> Plan:
        """The plan of the whole table for the checked ``request`` (:meth:`TableEngine.table_plan`)."""
        N, moments, memory_bytes = request.N, request.moments, request.memory_bytes
        what = f"--method thesis N={N}, nested integrations"
        refusal = table_range(what, "thesis", N, moments, max(_TABLE_COST), max_moments=_MAX_ORDER,
                              why_N="the nested bonds outgrow memory at N = 10",
                              why_moments="the s-th order defects grow fast: N = 9, s = 3 needs 12 GB")
        if refusal is not None:
            return refusal
        per_run, nbytes = _TABLE_COST[N]
        runs = N * (N + 1) // 2
        factor = _TIME_FACTOR.get(N, _TIME_FACTOR[8])
        seconds = per_run * (1 + runs * sum(factor[:moments]))
        plan = Plan(what, seconds, int(nbytes * _MEMORY_FACTOR[moments - 1]), runs * moments, "grain")
        return plan.within_memory(memory_bytes)

    def tables(self, request: TableRequest, plan: Plan, progress: Progress | None,
               executor: Executor | None) -> dict[int, Table]:
        """The tables of the checked ``request`` as its runnable ``plan`` says (:meth:`TableEngine.tables`)."""
        N, moments = request.N, request.moments
        volume = integrate_layers(N)  # once for every s
        calls = [(moment_table_nested, (N, s), {"volume": volume}) for s in range(1, moments + 1)]
        tables = run_independent(calls, executor=executor, progress=progress, weights=[plan.ticks / moments] * moments)
        return dict(enumerate(tables, start=1))


ENGINE = NestedEngine()


def table_run(N: int, moments: int = 1, *, memory_bytes: int | None = None, progress: Progress | None = None,
              executor: Executor | None = None) -> dict[int, Table]:
    """``{s: <W^s> table}`` for ``s = 1..moments``; the normalization is integrated once.

    The arguments are those of :func:`table_plan`; ``progress`` is called
    once per grain and order.

    Returns
    -------
    dict of int to list of lists of Fraction

    Raises
    ------
    ArgumentError
        If the plan is refused (out of range, or more memory than ``memory_bytes``).

    Examples
    --------
    >>> tables = table_run(4, 2)
    >>> [str(x) for x in tables[2][-1]]
    ['1/28', '9/56', '9/56', '1/28']
    """
    request = check_table_request(N, moments, memory_bytes=memory_bytes, executor=executor)
    return ENGINE.run(request, ENGINE.plan(request).check(), progress=progress)


