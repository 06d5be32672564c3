"""Every moment of every load by de Bruijn Pfaffians: the ``<W^s>`` tables from each layer's gap laws.

``W_ij`` is a Dirichlet spacing given its rank gap ``g`` (``notes/force_distribution.md`` Sec. 1), so

    <W_ij^s> = E[g (g+1) ... (g+s-1)] / ((d+1)(d+2) ... (d+s)),

and the gap law of every load comes from a polynomial route: the floor's
(:func:`.floor.floor_gap_laws`) and the other layers'
(:func:`.layers.layer_gap_laws`), one two-dimensional grid of Pfaffians per
layer.  This is what ``forcenet table --method pfaffian --moments s`` runs
for ``s >= 2`` (the mean alone has the much cheaper one-time route,
:mod:`.route`).  The cost is polynomial but steep (``O(n^8)`` per prime,
:func:`moments_plan`): about an hour at N = 28 on 2 cores, where the
order-ideal DP stops near N = 24-28; ``notes/fluctuations.md`` Sec. 4 proves
that no evaluate-and-combine route needs fewer than ``~d^2/8`` nodes per layer.

Examples
--------
>>> tables = moments_run(4, 2)
>>> [str(x) for x in tables[2][-1]]  # <W_{4,j}^2>
['1/28', '9/56', '9/56', '1/28']
"""

from __future__ import annotations

from collections.abc import Callable
from concurrent.futures import Executor
from dataclasses import replace
from fractions import Fraction
from os import PathLike
from typing import Any

from forcenet.core.plan import Plan, combine
from forcenet.core.validation import check_int, check_layers, check_moments
from forcenet.core.checkpoints import CheckpointStore
from ...protocol import Table
from ..distribution import moment_from_gaps
from ..gaps import GapCounts
from .cost import STARTUP_SECONDS
from .floor import MAX_FLOOR_N, floor_gap_laws, floor_plan
from .layers import layer_gap_laws, layer_plan

__all__ = ["MAX_MOMENTS_N", "moments_plan", "moments_run", "every_load_gap_law"]

MAX_MOMENTS_N = MAX_FLOOR_N


def moments_plan(N: int, moments: int = 2, *, memory_bytes: int | None = None,
                 workers: int | None = None) -> Plan:
    """The cost of :func:`moments_run`: every layer's every-load plan, one tick per prime and layer.

    Examples
    --------
    >>> plan = moments_plan(20)
    >>> plan.runnable, plan.unit, plan.ticks == 19 * floor_plan(20).ticks
    (True, 'prime', True)
    >>> moments_plan(129).refusal
    'N=129 is out of range for --method pfaffian --moments 2: N must be an integer in 2..128'
    """
    N, moments = check_layers(N), check_moments(moments)
    what = f"exact <W^s> tables s <= {moments} N={N} (de Bruijn Pfaffians, every layer's gap laws)"
    if N > MAX_MOMENTS_N:
        return Plan(what, 0, refusal=f"N={N} is out of range for --method pfaffian --moments {moments}: N must be an "
                                     f"integer in 2..{MAX_MOMENTS_N}")
    plans = [layer_plan(N, i, True, memory_bytes, workers) for i in range(2, N)]
    plans.append(floor_plan(N, True, memory_bytes, workers))
    plan = combine(what, plans, "prime")
    return replace(plan, seconds=plan.seconds - (len(plans) - 1) * STARTUP_SECONDS)  # one process starts once


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
        moments_plan(N, moments, memory_bytes=memory_bytes, workers=workers).check()
    options: dict[str, Any] = {"workers": workers, "progress": progress, "executor": executor,
                               "checkpoint": checkpoint}
    tables: dict[int, Table] = {s: [[Fraction(1)]] for s in range(1, moments + 1)}
    for i in range(2, N + 1):
        laws = every_load_gap_law(N, i, **options)
        for s in range(1, moments + 1):
            tables[s].append([moment_from_gaps(laws[j], s) for j in range(1, i + 1)])
    return tables
