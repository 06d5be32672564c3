"""The engine protocol of ``forcenet table``: one ``table_plan``/``table_run`` pair per method.

Every table method (fast, thesis, lambda, maps, pfaffian) is a module with
the same two functions and the same arguments (:class:`TableEngine`):

``table_plan(N, moments=1, *, memory_bytes=None, executor=None) -> Plan``
    The cost of the run, or its refusal: out of the method's range
    (:func:`forcenet.core.plan.table_range`), or more memory than
    ``memory_bytes`` (every method honours it; None: not checked).
``table_run(N, moments=1, *, memory_bytes=None, progress=None, executor=None) -> {s: table}``
    The exact ``<W^s>`` tables, ``s = 1..moments``, rows ``i = 1..N``,
    ``j = 1..i`` (Fractions).  ``progress(k=1)`` is called with the plan's
    ticks; a run whose plan ``memory_bytes`` refuses raises
    :class:`~forcenet.core.errors.ArgumentError` before it starts.

Behind them, the trusted pair the registry (:mod:`forcenet.exact.routes`)
calls, once it has checked the request (:func:`~forcenet.exact.routes.check_request`)
and the plan:

``trusted_plan(N, moments, *, memory_bytes=None, executor=None) -> Plan``
    :func:`table_plan` without the argument checks.
``trusted_run(N, moments, plan, *, memory_bytes=None, progress=None, executor=None) -> {s: table}``
    :func:`table_run` without the argument checks, the plan made and
    checked by the caller (its ticks weigh the tasks).

The public pair is a thin validating face over the trusted one: it checks
``N`` and ``moments``, plans, checks the plan, and runs (so a user calling
an engine alone is refused as before), while a request through the registry
is checked and planned once.

``executor`` runs the method's independent tasks (:func:`run_independent`):
any :class:`concurrent.futures.Executor` (a Dask client's
``get_executor()`` plugs in), or None for the method's default: the local
process pool where the run pays for it (the Pfaffian route's primes),
else this process.  Results never depend on it.  A method may take more
keywords of its own (the Pfaffian route: ``workers``, ``checkpoint``).

Examples
--------
>>> def twice(x, progress=None):
...     return 2 * x
>>> run_independent([(twice, (1,), {}), (twice, (3,), {})], executor=None, progress=None)
[2, 6]
"""

from __future__ import annotations

import functools
from collections.abc import Callable, Sequence
from concurrent.futures import Executor
from fractions import Fraction
from typing import Any, ParamSpec, Protocol

from forcenet.core.execution import run_tasks
from forcenet.core.plan import Plan

__all__ = ["BoundedTable", "Progress", "Table", "TableEngine", "bounded_result", "run_independent"]

Progress = Callable[..., Any]  # progress(k=1): k more ticks of the plan done
Table = list[list[Fraction]]  # rows i = 1..N, entries j = 1..i
_P = ParamSpec("_P")


class BoundedTable(list):
    """An exact table (a list of rows) that knows where every sample of its values lies.

    ``bounds = (lo, hi)``: numbers, or tables shaped like this one;
    ``observable`` says what is bounded and why. A plain ``list`` in every
    other respect (equal to the same rows, JSON-serializable).
    :func:`forcenet.testing.compare` uses the bounds when it is given none:
    the bounded test, whose level holds at every number of samples.

    Examples
    --------
    >>> from forcenet.exact import mean_W
    >>> table = mean_W(3)
    >>> table.bounds, table == [[1], [0.5, 0.5], [0.25, 0.5, 0.25]]
    ((0, 1), True)
    """

    def __init__(self, rows: Any = (), bounds: tuple[Any, Any] = (0, 1), observable: str = "") -> None:
        super().__init__(rows)
        self.bounds = bounds
        self.observable = observable


def bounded_result(lo: Any, hi: Any, observable: str) -> Callable[[Callable[_P, Table]], Callable[_P, BoundedTable]]:
    """Decorate a table function: its result becomes a :class:`BoundedTable` with ``bounds = (lo, hi)``.

    Examples
    --------
    >>> @bounded_result(0, 1, "a probability")
    ... def half(n):
    ...     return [[Fraction(1, 2)] * n]
    >>> half(2).bounds, half(2).observable
    ((0, 1), 'a probability')
    """
    def decorate(function: Callable[_P, Table]) -> Callable[_P, BoundedTable]:
        @functools.wraps(function)
        def table(*args: _P.args, **kwargs: _P.kwargs) -> BoundedTable:
            return BoundedTable(function(*args, **kwargs), (lo, hi), observable)
        return table
    return decorate


class TableEngine(Protocol):
    """What every module of :data:`forcenet.exact.routes.ENGINES` provides (a module satisfies it)."""

    def table_plan(self, N: int, moments: int = 1, *, memory_bytes: int | None = None,
                   executor: Executor | None = None) -> Plan: ...

    def table_run(self, N: int, moments: int = 1, *, memory_bytes: int | None = None, progress: Progress | None = None,
                  executor: Executor | None = None) -> dict[int, Table]: ...

    def trusted_plan(self, N: int, moments: int, *, memory_bytes: int | None = None,
                     executor: Executor | None = None) -> Plan: ...

    def trusted_run(self, N: int, moments: int, plan: Plan, *, memory_bytes: int | None = None,
                    progress: Progress | None = None, executor: Executor | None = None) -> dict[int, Table]: ...


def _call(function: Callable[..., Any], args: tuple, kwargs: dict) -> Any:
    return function(*args, **kwargs)


def run_independent(calls: Sequence[tuple[Callable[..., Any], tuple, dict]], *, executor: Executor | None,
                    progress: Progress | None, weights: Sequence[float] | None = None) -> list:
    """``[function(*args, **kwargs) for function, args, kwargs in calls]``: independent tasks of one run.

    Parameters
    ----------
    calls : sequence of (callable, tuple, dict)
        Module-level functions (they are pickled to an executor's workers)
        with their arguments.
    executor : concurrent.futures.Executor or None
        Where the tasks run; None: in this process, one after the other.
    progress : callable or None
        In this process, passed on as ``progress=`` to each call (the
        functions tick as they go); on an executor, called as
        ``progress(weight)`` once per finished task.
    weights : sequence of float, optional
        The ticks of each task on an executor (default 1 each): the plan's
        ticks of that task, so the bar ends where the plan said.

    Returns
    -------
    list
        The results, in the order of ``calls``.

    Examples
    --------
    >>> from concurrent.futures import ThreadPoolExecutor
    >>> with ThreadPoolExecutor(2) as pool:
    ...     run_independent([(divmod, (7, 3), {}), (divmod, (9, 4), {})], executor=pool, progress=None)
    [(2, 1), (2, 1)]
    """
    if executor is None:
        return [function(*args, **kwargs, progress=progress) for function, args, kwargs in calls]
    return run_tasks(_call, list(calls), executor=executor, progress=progress, weights=weights)
