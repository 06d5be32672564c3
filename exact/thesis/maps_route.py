"""The ``maps`` engine of ``forcenet table`` (:mod:`forcenet.exact.protocol`): the map counting of Sec. 4.6, (4.67), (4.90)-(4.91).

Its plan (measured costs) and its run, over the functions of :mod:`.map_counting`.
"""

from __future__ import annotations

from concurrent.futures import Executor
from decimal import Decimal

from forcenet.core.plan import Plan, combine, table_range

from ..protocol import Progress, Table, TableEngine, TableRequest, check_table_request, run_independent
from ..triangle.staircase import free_force_count, tableau_count
from .map_counting import mean_W_thesis_maps, moments_by_maps

__all__ = ["table_plan", "table_run", "ENGINE"]

# ------------------------------------------------------ the table route: plan and run

_MAX_N = 9  # N = 9 visits 1.1e11 maps per grain; N = 10 is out of reach
_COUNTED_N = 40  # a refusal counts the maps exactly up to here (a millisecond), beyond it bounds them
_SECONDS_PER_MAP_GRAIN = 5.2e-6  # mean_W_thesis_maps per map and grain, measured N = 6, 7 (2 cores)
_SECONDS_PER_MAP_CELL2 = 2.5e-7  # moments_by_maps per map and d^2 (tableau of each map), measured N = 7


def table_plan(N: int, moments: int = 1, *, memory_bytes: int | None = None, executor: Executor | None = None) -> Plan:
    """The cost of :func:`table_run` (``--method maps``): ``<W>`` by the map formulas, ``<W^s>`` by averaging over all maps.

    The engine protocol (:mod:`forcenet.exact.protocol`).  Both passes
    enumerate maps one by one, independent tasks on ``executor`` if given:
    the first once per bulk grain (the modified maps of (4.90)), the second,
    for ``moments >= 2``, once through the bijection with tableaux.  Memory:
    one map at a time, the plan never refuses for it.

    Parameters
    ----------
    N : int
        Number of layers, ``>= 2`` (the route reaches ``N <= 9``).
    moments : int
        Highest moment, ``>= 1``.
    memory_bytes : int, optional
        Memory available to the run (None: not checked).
    executor : concurrent.futures.Executor, optional
        Where the two passes run (default: this process).

    Returns
    -------
    Plan

    Raises
    ------
    ArgumentError
        If ``N`` or ``moments`` is not an integer ``>= 2`` or ``>= 1``.

    Examples
    --------
    >>> table_plan(7, 3).seconds < 30
    True
    >>> table_plan(10).refusal
    'N=10 is out of range for --method maps: N must be an integer in 2..9 (N = 10 would enumerate 3.97e+15 maps per grain)'
    """
    return ENGINE.plan(check_table_request(N, moments, memory_bytes=memory_bytes, executor=executor))


class MapsEngine(TableEngine):
    """The ``maps`` table engine: ``<W>`` by map counting (Sec. 4.6, (4.67), (4.90)-(4.91)), ``<W^s>`` over every map."""

    name = "maps"

    def table_plan(self, request: TableRequest) -> Plan:
        """The plan of the whole table for the checked ``request`` (:meth:`TableEngine.table_plan`)."""
        N, moments, memory_bytes = request.N, request.moments, request.memory_bytes
        what = f"--method maps N={N}"
        refusal = table_range(what, "maps", N, moments, _MAX_N, max_moments=None, why_N=_too_many(N))
        if refusal is not None:
            return refusal
        plans = _pass_plans(N, moments)
        what = plans[0].what if len(plans) == 1 else f"{what}, map sums and every map's tableau"
        return combine(what, plans, "grain").within_memory(memory_bytes)

    def tables(self, request: TableRequest, plan: Plan, progress: Progress | None,
               executor: Executor | None) -> dict[int, Table]:
        """The tables of the checked ``request`` as its runnable ``plan`` says (:meth:`TableEngine.tables`)."""
        N, moments = request.N, request.moments
        calls: list = [(mean_W_thesis_maps, (N,), {})]
        if moments >= 2:
            calls.append((_higher_moment_tables, (N, moments), {}))
        results = run_independent(calls, executor=executor, progress=progress,
                                  weights=[plan.ticks for plan in _pass_plans(N, moments)])
        tables = {1: results[0]}
        if moments >= 2:
            tables.update(results[1])
        return tables


ENGINE = MapsEngine()


def _too_many(N: int) -> str:
    """Why ``N`` is out of reach: its maps per grain, counted exactly up to ``_COUNTED_N`` (the count is a big
    integer of ~N^2 log N digits: at N = 2000 it took minutes), beyond as a lower bound (the count grows with N)."""
    if N <= _MAX_N:
        return ""
    if N <= _COUNTED_N:
        return f"N = {N} would enumerate {Decimal(tableau_count(N)):.3g} maps per grain"
    return f"N = {N} would enumerate more than {Decimal(tableau_count(_COUNTED_N)):.3g} maps per grain"


def _pass_plans(N: int, moments: int) -> list[Plan]:
    what = f"--method maps N={N}"
    grains = (N - 1) * (N - 2) // 2
    d, maps = free_force_count(N), tableau_count(N)
    plans = [Plan(f"{what}, map sums per grain ({maps} maps each)", maps * d * _SECONDS_PER_MAP_GRAIN,
                  0, grains, "grain")]
    if moments >= 2:
        plans.append(Plan(f"{what}, every map's tableau for <W^s>", maps * d * d * _SECONDS_PER_MAP_CELL2,
                          0, 1, "grain"))
    return plans


def _higher_moment_tables(N: int, moments: int, progress: Progress | None = None) -> dict[int, Table]:
    """``{s: <W^s> table}`` for ``s = 2..moments`` by map counting through the tableau bijection; one tick."""
    _, mom, _ = moments_by_maps(N, moments)
    if progress is not None:
        progress()
    return {s: [[mom[s][(i, j)] for j in range(1, i + 1)] for i in range(1, N + 1)] for s in range(2, moments + 1)}


def table_run(N: int, moments: int = 1, *, memory_bytes: int | None = None, progress: Progress | None = None,
              executor: Executor | None = None) -> dict[int, Table]:
    """``{s: <W^s> table}``: ``s = 1`` from (4.67), (4.90)-(4.91), ``s >= 2`` averaged over all maps.

    The arguments are those of :func:`table_plan`; ``progress`` is called
    once per bulk grain and once for the moment pass.

    Returns
    -------
    dict of int to list of lists of Fraction

    Raises
    ------
    ArgumentError
        If the plan is refused (out of range, or more memory than ``memory_bytes``).

    Examples
    --------
    >>> tables = table_run(5, 2)
    >>> [str(x) for x in tables[2][-1]]
    ['1/66', '65/792', '25/198', '65/792', '1/66']
    """
    request = check_table_request(N, moments, memory_bytes=memory_bytes, executor=executor)
    return ENGINE.run(request, ENGINE.plan(request).check(), progress=progress)


