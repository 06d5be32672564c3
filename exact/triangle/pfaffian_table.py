"""``forcenet table --method pfaffian``: the mean by free fermions, every higher moment by de Bruijn Pfaffians.

The table engine of the method ``pfaffian`` (the engine protocol of
:mod:`forcenet.exact.protocol`: :func:`table_plan`, :func:`table_run`)
dispatches on the highest moment, here and nowhere else: ``moments = 1`` is
the free-fermion route (:func:`.free_fermion.route.mean_plan`,
:func:`.free_fermion.route.survival_tables`: one-time, ``O(N^7 log N)``),
``moments >= 2`` the ``<W^s>`` tables from each layer's gap laws below.

``W_ij`` is a Dirichlet spacing given its rank gap ``g`` (``notes/force_distribution.md`` Sec. 1), so

    <W_ij^s> = E[g (g+1) ... (g+s-1)] / ((d+1)(d+2) ... (d+s)),

and the gap law of every load comes from a polynomial route: the floor's
(:func:`.de_bruijn.floor.floor_gap_laws`) and the other layers'
(:func:`.de_bruijn.layers.layer_gap_laws`), one two-dimensional grid of Pfaffians per
layer.  This is what ``forcenet table --method pfaffian --moments s`` runs
for ``s >= 2`` (the mean alone has the much cheaper one-time route).  The cost is polynomial but steep (``O(n^8)`` per prime,
:func:`moments_plan`): about an hour at N = 28 on 2 cores, where the
order-ideal DP stops near N = 24-28; ``notes/fluctuations.md`` Sec. 4 proves
that no evaluate-and-combine route needs fewer than ``~d^2/8`` nodes per layer.

Examples
--------
>>> tables = table_run(4, 2)
>>> [str(x) for x in tables[2][-1]]  # <W_{4,j}^2>
['1/28', '9/56', '9/56', '1/28']
>>> [str(x) for x in table_run(5)[1][-1]]  # the mean alone: free fermions
['1/11', '1/4', '7/22', '1/4', '1/11']
"""

from __future__ import annotations

from collections.abc import Callable
from concurrent.futures import Executor
from dataclasses import replace
from fractions import Fraction
from os import PathLike
from typing import Any

from forcenet.core.checkpoints import CheckpointStore, records_held
from forcenet.core.execution import as_executor
from forcenet.core.plan import Plan, combine
from forcenet.core.validation import check_int, check_layers, check_moments

from ..protocol import Progress, Table, TableEngine, TableRequest, check_table_request
from .de_bruijn.floor import MAX_FLOOR_N, floor_cost, floor_gap_laws
from .de_bruijn.layers import layer_cost, layer_gap_laws
from .free_fermion.route import MAX_N, mean_plan, survival_tables, table_from_survival
from .gap_counts import GapCounts, moment_from_gaps
from .prime_tasks import STARTUP_SECONDS, checkpoint_store

__all__ = ["MAX_N", "MAX_MOMENTS_N", "ENGINE", "checkpoint_for", "table_plan", "table_run",
           "moments_plan", "moments_run", "every_load_gap_law"]

MAX_MOMENTS_N = MAX_FLOOR_N

Checkpoint = str | PathLike | CheckpointStore | None


def checkpoint_for(directory: str | PathLike, N: int, moments: int = 1) -> Checkpoint:
    """The checkpoint of a table request in ``directory``: the mean's store (it counts what it reused), or for
    ``moments >= 2`` the directory itself (every layer keeps a request of its own).

    Examples
    --------
    >>> import tempfile
    >>> checkpoint_for(tempfile.gettempdir(), 12).request["route"]
    'pfaffian-table'
    """
    return checkpoint_store(directory, "table", N) if moments == 1 else directory


def table_plan(N: int, moments: int = 1, *, memory_bytes: int | None = None, executor: Executor | None = None,
               workers: int | None = None, checkpoint: Checkpoint = None) -> Plan:
    """The cost of :func:`table_run` (``forcenet table --method pfaffian``), the engine protocol's plan.

    Parameters
    ----------
    N : int
        Number of layers, ``>= 2`` (the mean reaches ``N <= 200``).
    moments : int
        Highest moment, ``>= 1`` (``>= 2``: every load's gap law, :func:`moments_plan`, ``N <= 128``).
    memory_bytes : int, optional
        Memory available to the run (None: not checked).
    executor : concurrent.futures.Executor or Dask Client, optional
        Runs the per-prime tasks; the plan counts its workers (and the
        scheduler's cost per task).  Default: a local process pool when the
        run pays for starting it.
    workers : int, optional
        Local worker processes (default: the cores when the run pays for them).
    checkpoint : str, os.PathLike or CheckpointStore, optional
        The plan counts only the primes not yet recorded there, and says so.

    Returns
    -------
    Plan

    Raises
    ------
    ArgumentError
        If ``N`` or ``moments`` is not an integer ``>= 2`` or ``>= 1``.

    Examples
    --------
    >>> plan = table_plan(32)
    >>> plan.runnable, plan.ticks, plan.unit
    (True, 55, 'prime')
    >>> table_plan(8, moments=2).what  # higher moments: every load's gap law
    "exact <W^s> tables s <= 2 N=8 (de Bruijn Pfaffians, every layer's gap laws)"
    >>> table_plan(201).refusal
    'N=201 is out of range for --method pfaffian: N must be an integer in 2..200'
    """
    return ENGINE.plan(check_table_request(N, moments, memory_bytes=memory_bytes, executor=executor, workers=workers,
                                     checkpoint=checkpoint))


class PfaffianEngine(TableEngine):
    """The ``pfaffian`` table engine: ``<W>`` by free fermions (Schur Pfaffians, minor summation), ``<W^s>`` from
    every load's gap law by de Bruijn Pfaffians; over independent primes (``workers``, ``checkpoint``)."""

    name = "pfaffian"
    options = frozenset({"workers", "checkpoint"})
    min_plan_seconds = STARTUP_SECONDS  # every plan of the route pays the start-up

    def checkpoint_for(self, directory: str | PathLike, N: int, moments: int = 1) -> Checkpoint:
        """The checkpoint this engine keeps for a table request in ``directory`` (:func:`checkpoint_for`)."""
        return checkpoint_for(directory, N, moments)

    def table_plan(self, request: TableRequest) -> Plan:
        """The plan of the whole table for the checked ``request`` (:meth:`TableEngine.table_plan`)."""
        N, moments, memory_bytes, executor = request.N, request.moments, request.memory_bytes, request.executor
        workers, checkpoint = request.options.get("workers"), request.options.get("checkpoint")
        if moments > 1:  # every load's gap law, layer by layer (de Bruijn Pfaffians)
            return _moments_plan(N, moments, memory_bytes, workers, executor, checkpoint)
        return mean_plan(N, memory_bytes=memory_bytes, executor=executor, workers=workers, checkpoint=checkpoint)

    def tables(self, request: TableRequest, plan: Plan, progress: Progress | None,
               executor: Executor | None) -> dict[int, Table]:
        """The tables of the checked ``request`` as its runnable ``plan`` says (:meth:`TableEngine.tables`)."""
        N, moments = request.N, request.moments
        workers, checkpoint = request.options.get("workers"), request.options.get("checkpoint")
        if moments > 1:
            return _moments_run(N, moments, progress=progress, executor=executor, workers=workers,
                                checkpoint=checkpoint)
        (S,), total = survival_tables(N, workers, progress, as_executor(executor), checkpoint)
        return {1: table_from_survival(N, S, total)}


ENGINE = PfaffianEngine()


def table_run(N: int, moments: int = 1, *, memory_bytes: int | None = None, progress: Progress | None = None,
              executor: Executor | None = None, workers: int | None = None,
              checkpoint: Checkpoint = None) -> dict[int, Table]:
    """``{1: <W> table}`` by free fermions (``{s: <W^s> table}`` for ``moments >= 2`` by de Bruijn Pfaffians), the
    engine protocol's run; ``progress(1)`` per prime.

    The arguments are those of :func:`table_plan`; a request the plan refuses
    (out of range, or more memory than ``memory_bytes``) raises before any
    prime starts.

    Parameters
    ----------
    N : int
        Number of layers, ``2..200``.
    moments : int
        Highest moment; ``>= 2`` runs :func:`moments_run`.
    memory_bytes : int, optional
        Memory available to the run (None: not checked).
    progress : callable, optional
        Called as ``progress(1)`` after each prime.
    executor : concurrent.futures.Executor or Dask Client, optional
        Runs the per-prime tasks (default: a local process pool when it pays).
    workers : int, optional
        Local worker processes (default: the cores when the run pays for them).
    checkpoint : str, os.PathLike or CheckpointStore, optional
        Finished primes are recorded there and not recomputed.

    Returns
    -------
    dict of int to list of lists of Fraction

    Raises
    ------
    ArgumentError
        If the plan is refused.

    Examples
    --------
    >>> [str(x) for x in table_run(5)[1][-1]]
    ['1/11', '1/4', '7/22', '1/4', '1/11']
    """
    request = check_table_request(N, moments, memory_bytes=memory_bytes, executor=executor, workers=workers,
                            checkpoint=checkpoint)
    return ENGINE.run(request, ENGINE.plan(request).check(), progress=progress)


def moments_plan(N: int, moments: int = 2, *, memory_bytes: int | None = None,
                 workers: int | None = None, executor: Executor | None = None) -> Plan:
    """The cost of :func:`moments_run`: every layer's every-load plan, one tick per prime and layer.

    Examples
    --------
    >>> plan = moments_plan(20)
    >>> plan.runnable, plan.unit, plan.ticks == 19 * floor_cost(20).ticks
    (True, 'prime', True)
    >>> moments_plan(129).refusal
    'N=129 is out of range for --method pfaffian --moments 2: N must be an integer in 2..128'
    """
    N, moments = check_layers(N), check_moments(moments)
    return _moments_plan(N, moments, memory_bytes, workers, executor)


def _moments_plan(N: int, moments: int, memory_bytes: int | None, workers: int | None,
                  executor: Executor | None, checkpoint: Checkpoint = None) -> Plan:
    """:func:`moments_plan` of checked arguments: every layer's every-load plan (Sec. 5-6 of
    ``notes/fluctuations.md``), each layer's start-up paid once.

    A resumed run (``checkpoint``, the directory of one request per layer) counts each layer's own held primes:
    a layer wholly recorded costs nothing, a layer begun pays its workers' start-up and its remaining primes at
    its own cost per prime (the layers run in order and cost more with ``i``: the held records are the cheap
    ones, so discounting the whole plan by the share of primes held was ~1.4x low at half of N = 40).
    """
    what = f"exact <W^s> tables s <= {moments} N={N} (de Bruijn Pfaffians, every layer's gap laws)"
    if N > MAX_MOMENTS_N:
        return Plan(what, 0, refusal=f"N={N} is out of range for --method pfaffian --moments {moments}: N must be an "
                                     f"integer in 2..{MAX_MOMENTS_N}")
    directory = checkpoint.directory if isinstance(checkpoint, CheckpointStore) else checkpoint
    plans = [layer_cost(N, i, True, memory_bytes, workers, executor=executor,
                        store=checkpoint_store(directory, "layer-grains", N, layer=i)) for i in range(2, N)]
    plans.append(floor_cost(N, True, memory_bytes, workers, executor=executor,
                            store=checkpoint_store(directory, "floor-grains", N)))
    plan = combine(what, plans, "prime")
    plan = replace(plan, seconds=plan.seconds - (len(plans) - 1) * STARTUP_SECONDS)  # one process starts once
    held = records_held(directory, N, ("pfaffian-layer-grains", "pfaffian-floor-grains")) if directory else 0
    if held:
        plan = replace(plan, what=f"{what}; {held} of {plan.ticks} primes recorded in {directory}")
    return plan


def every_load_gap_law(N: int, i: int, **options: Any) -> dict[int, GapCounts]:
    """The gap law of every load of layer ``i`` (``2..N``) by its de Bruijn route: ``{j: GapCounts}``.

    Examples
    --------
    >>> every_load_gap_law(4, 4)[1].counts[:2]  # the floor's corner: Beta(1, d)
    (0, 2)
    """
    N = check_layers(N, maximum=MAX_MOMENTS_N)
    i = check_int(i, "i", 2, N)
    return floor_gap_laws(N, **options) if i == N else layer_gap_laws(N, i, **options)


def moments_run(N: int, moments: int = 2, *, memory_bytes: int | None = None,
                progress: Callable[..., Any] | None = None, executor: Executor | None = None,
                workers: int | None = None,
                checkpoint: str | PathLike | CheckpointStore | None = None) -> dict[int, Table]:
    """``{s: <W^s> table}`` for ``s = 1..moments``, exact, from every load's gap law by de Bruijn Pfaffians.

    Parameters
    ----------
    N : int
        Number of layers, ``2..128``.
    moments : int
        Highest moment ``s``.
    memory_bytes : int, optional
        Memory available to the run: a plan over it is refused before any work.
    progress : callable, optional
        ``progress(1)`` after each prime of each layer.
    executor : concurrent.futures.Executor or dask Client, optional
        Where the per-prime tasks run.
    workers : int, optional
        Local worker processes.
    checkpoint : path or CheckpointStore, optional
        Every finished prime of every layer is kept there (one request per layer); a rerun reuses them.

    Returns
    -------
    dict of int to list of lists of Fraction
        Row ``i - 1`` holds ``<W_ij^s>``, ``j = 1..i``; ``W_11 = 1``.

    Examples
    --------
    >>> moments_run(3, 3)[3]  # doctest: +NORMALIZE_WHITESPACE
    [[Fraction(1, 1)], [Fraction(1, 5), Fraction(1, 5)], [Fraction(1, 20), Fraction(1, 5), Fraction(1, 20)]]
    """
    N, moments = check_layers(N), check_moments(moments)
    if N > MAX_MOMENTS_N or memory_bytes is not None:
        moments_plan(N, moments, memory_bytes=memory_bytes, workers=workers, executor=executor).check()
    return _moments_run(N, moments, progress=progress, executor=executor, workers=workers, checkpoint=checkpoint)


def _moments_run(N: int, moments: int, *, progress: Callable[..., Any] | None, executor: Executor | None,
                 workers: int | None, checkpoint: str | PathLike | CheckpointStore | None) -> dict[int, Table]:
    """:func:`moments_run` for checked arguments whose plan was checked."""
    options: dict[str, Any] = {"workers": workers, "progress": progress, "executor": executor,
                               "checkpoint": checkpoint}
    tables: dict[int, Table] = {s: [[Fraction(1)]] for s in range(1, moments + 1)}
    for i in range(2, N + 1):
        laws = every_load_gap_law(N, i, **options)
        for s in range(1, moments + 1):
            tables[s].append([moment_from_gaps(laws[j], s) for j in range(1, i + 1)])
    return tables
