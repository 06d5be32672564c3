"""The triangle's table engines: the request they take (:class:`TableRequest`) and their base (:class:`TableEngine`).

Every table method (fast, thesis, lambda, maps, pfaffian) is an engine
object (:class:`forcenet.core.registry.Engine`) of model ``"triangle"`` for
the quantities ``"table"`` and ``"row"`` (a whole table, one row kept), made
from :class:`TableEngine` in its module (``ENGINE``) and registered by
:mod:`forcenet.exact.routes`.  An engine receives a request checked once
(:func:`check_table_request`, by the front door or the registry) and never checks it
again:

``plan(request) -> Plan``
    The cost of the run, or its refusal: out of the method's range
    (:func:`forcenet.core.plan.table_range`), or more memory than
    ``request.memory_bytes`` (every method honours it; None: not checked).
``run(request, plan, *, progress=None, executor=None) -> {s: table}``
    The exact ``<W^s>`` tables, ``s = 1..moments``, rows ``i = 1..N``,
    ``j = 1..i`` (Fractions), the plan made and checked by the caller (its
    ticks weigh the tasks); ``progress(k=1)`` is called with the plan's ticks.
    For a row request, ``{s: row}``.

Each engine module keeps a user's pair ``table_plan(N, moments=1, *,
memory_bytes=None, executor=None)`` and ``table_run(...)``: thin faces that
build the request (the one check) and ask the engine.

``executor`` runs the method's independent tasks (:func:`run_independent`):
any :class:`concurrent.futures.Executor` (a Dask client's
``get_executor()`` plugs in), or None for the method's default: the local
process pool where the run pays for it (the Pfaffian route's primes),
else this process.  Results never depend on it.  An engine may take more
keywords of its own (its ``options``; the Pfaffian route: ``workers``,
``checkpoint``), carried by the request.

Examples
--------
>>> def twice(x, progress=None):
...     return 2 * x
>>> run_independent([(twice, (1,), {}), (twice, (3,), {})], executor=None, progress=None)
[2, 6]
>>> check_table_request(12, 2).quantity, check_table_request(12, row=3).quantity
('table', 'row')
"""

from __future__ import annotations

import functools
from abc import ABC, abstractmethod
from collections.abc import Callable, Sequence
from concurrent.futures import Executor
from dataclasses import dataclass, field, replace
from fractions import Fraction
from typing import Any, ClassVar, ParamSpec

from forcenet.core.errors import ArgumentError, ArgumentTypeError
from forcenet.core.execution import run_tasks
from forcenet.core.plan import Plan
from forcenet.core.validation import check_executor, check_int, check_layers, check_moments

__all__ = ["BoundedTable", "Progress", "Table", "TableEngine", "TableRequest", "bounded_result", "run_independent",
           "check_table_request"]

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


@dataclass(frozen=True)
class TableRequest:
    """A request for the triangle's ``<W^s>`` tables (or one row), checked once (:func:`check_table_request`) and trusted
    after: ``options``, the engine options given; ``directory``, where each engine keeping checkpoints makes its
    store, once (``stores``)."""

    N: int
    moments: int = 1
    method: str = "auto"
    memory_bytes: int | None = None
    executor: Executor | None = None
    options: dict[str, Any] = field(default_factory=dict)
    row: int | None = None
    directory: str | None = None
    stores: dict[str, Any] = field(default_factory=dict, compare=False, repr=False)
    model: ClassVar[str] = "triangle"

    @property
    def quantity(self) -> str:
        """``"table"``, or ``"row"`` for one row's request."""
        return "table" if self.row is None else "row"


def check_table_request(N: Any, moments: Any = 1, method: Any = "auto", *, row: Any = None, memory_bytes: Any = None,
                  executor: Executor | None = None, methods: Sequence[str] | None = None,
                  **options: Any) -> TableRequest:
    """The one check of a table request: ``N >= 2``, ``moments`` in ``1..50``, ``method`` a string (one of
    ``methods`` when given: the registry's names), ``row`` in ``1..N``, ``memory_bytes >= 1`` (as ``law_request``, ``count_plan``); the options given
    (not None) kept.

    Raises
    ------
    ArgumentError, ArgumentTypeError
        Naming the argument out of range, or of the wrong type, and its range.

    Examples
    --------
    >>> check_table_request(12, 2).moments
    2
    >>> check_table_request(12, row=13)
    Traceback (most recent call last):
    ...
    forcenet.core.errors.ArgumentError: row=13 is out of range: row must be an integer in 1..12
    """
    N, moments = check_layers(N), check_moments(moments)
    choices = "the name of a method" if methods is None else f"one of {', '.join(methods)}"
    if not isinstance(method, str):
        raise ArgumentTypeError(f"method={method!r} is not a string: method must be {choices}")
    if methods is not None and method not in methods:
        raise ArgumentError(f"method={method!r} is out of range: method must be {choices}")
    row = None if row is None else check_int(row, "row", 1, N)
    memory_bytes = None if memory_bytes is None else check_int(memory_bytes, "memory_bytes", 1)
    given = {k: v for k, v in options.items() if v is not None}
    return TableRequest(N, moments, method, memory_bytes, check_executor(executor), given, row)


class TableEngine(ABC):
    """A table method of the triangle as an engine object (:class:`forcenet.core.registry.Engine`): its
    :meth:`table_plan` and :meth:`tables` for a whole table; :meth:`plan` and :meth:`run` serve a row too (the
    whole table, one row kept). ``options``: the keywords beyond the request it takes; ``min_plan_seconds``: the
    start-up every plan pays (``auto`` does not plan it when another plan runs within it)."""

    name: str
    model: str = "triangle"
    quantities: frozenset[str] = frozenset({"table", "row"})
    options: frozenset[str] = frozenset()
    min_plan_seconds: float = 0.0

    def __repr__(self) -> str:
        return f"<{self.model} engine {self.name!r}>"

    @abstractmethod
    def table_plan(self, request: TableRequest) -> Plan:
        """The cost of the whole table for the checked ``request`` (nothing is checked again)."""

    @abstractmethod
    def tables(self, request: TableRequest, plan: Plan, progress: Progress | None,
               executor: Executor | None) -> dict[int, Table]:
        """``{s: table}`` for the checked ``request`` and its checked runnable ``plan``."""

    def plan(self, request: TableRequest) -> Plan:
        """:meth:`table_plan`; for a row request, the whole table's plan named as that row's."""
        plan = self.table_plan(request)
        return plan if request.row is None else replace(plan, what=f"row {request.row} of the {plan.what}")

    def run(self, request: TableRequest, plan: Plan, *, progress: Progress | None = None,
            executor: Executor | None = None) -> Any:
        """:meth:`tables` (``executor``, else the request's); for a row request, ``{s: row}``."""
        tables = self.tables(request, plan, progress, executor if executor is not None else request.executor)
        if request.row is None:
            return tables
        return {s: table[request.row - 1] for s, table in tables.items()}


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
