"""The ``lambda`` engine of ``forcenet table`` (:mod:`forcenet.exact.protocol`): the integer recursions Lambda (4.50) and Gamma (4.73)-(4.77).

Its plan (measured costs) and its run, over the functions of :mod:`.recursions`.
"""

from __future__ import annotations

from concurrent.futures import Executor

from forcenet.core.plan import Plan, table_range

from ..protocol import Progress, Table, TableEngine, TableRequest, check_table_request, run_independent
from .recursions import mean_W_gamma

__all__ = ["table_plan", "table_run", "ENGINE"]

# ------------------------------------------------------ the table route: plan and run

# Measured per bulk grain of the Gamma route (seconds, peak bytes) on the 2-core machine
# (benchmarks/gamma_table.py); the table has (N-1)(N-2)/2 of them.  N = 12: one grain peaks
# at 20 GB; the normalization and the boundary (4.67) took 1083 s more there.
_GRAIN_COST = {10: (0.1, 1e8), 11: (2.5, 5e8), 12: (170.0, 2.2e10)}
_BOUNDARY_SECONDS = {11: 60.0, 12: 1083.0}
_MAX_N = 12  # the index boxes of (4.32) outgrow memory beyond


def table_plan(N: int, moments: int = 1, *, memory_bytes: int | None = None, executor: Executor | None = None) -> Plan:
    """The cost of :func:`table_run` (``--method lambda``): the ``<W>`` table by the Lambda/Gamma recursions.

    The engine protocol (:mod:`forcenet.exact.protocol`); one task (the
    table), on ``executor`` if given.

    Parameters
    ----------
    N : int
        Number of layers, ``>= 2`` (the route reaches ``N <= 12``).
    moments : int
        Highest moment, ``>= 1`` (the route computes ``<W>`` only: 1).
    memory_bytes : int, optional
        Memory available to the run (None: not checked).
    executor : concurrent.futures.Executor, optional
        Where the task runs (default: this process).

    Returns
    -------
    Plan

    Raises
    ------
    ArgumentError
        If ``N`` or ``moments`` is not an integer ``>= 2`` or ``>= 1``.

    Examples
    --------
    >>> table_plan(9).seconds < 5
    True
    >>> table_plan(9, moments=2).refusal
    'moments=2 is out of range for --method lambda: moments must be 1 (higher moments use --method fast, thesis or maps)'
    """
    return ENGINE.plan(check_table_request(N, moments, memory_bytes=memory_bytes, executor=executor))


class LambdaEngine(TableEngine):
    """The ``lambda`` table engine: the ``<W>`` table by the Lambda (4.50) and Gamma (4.73)-(4.77) recursions."""

    name = "lambda"

    def table_plan(self, request: TableRequest) -> Plan:
        """The plan of the whole table for the checked ``request`` (:meth:`TableEngine.table_plan`)."""
        N, moments, memory_bytes = request.N, request.moments, request.memory_bytes
        what = f"--method lambda N={N}, Gamma recursions"
        refusal = table_range(what, "lambda", N, moments, _MAX_N, why_N="the index boxes of (4.32) outgrow memory")
        if refusal is not None:
            return refusal
        per_grain, nbytes = _GRAIN_COST.get(N, (0.01, 0))
        grains = (N - 1) * (N - 2) // 2
        seconds = per_grain * grains + _BOUNDARY_SECONDS.get(N, 0.1)
        return Plan(what, seconds, int(nbytes), grains, "grain").within_memory(memory_bytes)

    def tables(self, request: TableRequest, plan: Plan, progress: Progress | None,
               executor: Executor | None) -> dict[int, Table]:
        """The tables of the checked ``request`` as its runnable ``plan`` says (:meth:`TableEngine.tables`)."""
        N = request.N
        (table,) = run_independent([(mean_W_gamma, (N,), {})], executor=executor, progress=progress, weights=[plan.ticks])
        return {1: table}


ENGINE = LambdaEngine()


def table_run(N: int, moments: int = 1, *, memory_bytes: int | None = None, progress: Progress | None = None,
              executor: Executor | None = None) -> dict[int, Table]:
    """``{1: <W> table}`` from the Lambda (4.67) and Gamma (4.77) integers; ``progress`` per bulk grain.

    The arguments are those of :func:`table_plan`.

    Returns
    -------
    dict of int to list of lists of Fraction

    Raises
    ------
    ArgumentError
        If the plan is refused (out of range, or more memory than ``memory_bytes``).

    Examples
    --------
    >>> [str(x) for x in table_run(5)[1][-1]]
    ['1/11', '1/4', '7/22', '1/4', '1/11']
    """
    request = check_table_request(N, moments, memory_bytes=memory_bytes, executor=executor)
    return ENGINE.run(request, ENGINE.plan(request).check(), progress=progress)


