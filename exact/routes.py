"""The triangle's engines in the registry: ``forcenet table``'s methods, one row's routes, one load's laws.

=========  ==========================================================  ==========
method     engine                                                      reach
=========  ==========================================================  ==========
fast       order-ideal path sums (:mod:`.triangle.moments`)            N ~ 28-30
thesis     nested-matrix integration (:mod:`.thesis.nested_route`)     N <= 9
lambda     Lambda/Gamma recursions (:mod:`.thesis.lambda_route`)       N <= 12
maps       map counting of Sec. 4.6 (:mod:`.thesis.maps_route`)        N <= 9
pfaffian   Schur Pfaffians, minor summation (:mod:`.triangle.pfaffian_table`)  N ~ 64-100
auto       the fastest runnable of the five, by their plans (the default)
=========  ==========================================================  ==========

Every table method is an engine object (:class:`forcenet.exact.protocol.TableEngine`,
each module's ``ENGINE``) that owns its cost knowledge; this module registers
them, the row's routes (:mod:`.row_routes`) and the laws' routes
(:mod:`.law_registry`) in the one registry (:data:`forcenet.core.registry.REGISTRY`,
model ``"triangle"``, quantities ``"table"``, ``"row"``, ``"law"``), with the
policies of a row and a law; ``auto`` is the registry's choice by the plans.
A request is checked once (:func:`check_request`: ``N``, ``moments``,
``method``, ``row``, ``memory_bytes``), planned once (:func:`plan_request`,
:func:`plan_row`) and its plan checked before the run (:func:`run_request`,
:func:`run_row`); the engines take the request and trust it.

One row of the moment tables (``forcenet table --row i``, :func:`row_plan`,
:func:`row_run`) has routes of its own (:func:`choose_row`,
:mod:`.row_routes`): the one-time cover identity for the rows ``2``, ``3``,
``N - 1`` (``<W^2>`` for the price of the mean), the lattice route for row 2
(every moment), de Bruijn Pfaffians for one layer (every load, every moment),
or a whole table's row.

Examples
--------
>>> table_plan("fast", 9).runnable
True
>>> tables = table_run("lambda", 5)
>>> [str(x) for x in tables[1][-1]]
['1/11', '1/4', '7/22', '1/4', '1/11']
>>> choose(28).method, choose(12, moments=2).method  # the Pfaffian route wins, compiled or not
('pfaffian', 'fast')
>>> choose_row("pfaffian", 40, 39, 2).route  # layer N - 1: the cover identity
'covers'
>>> [str(x) for x in row_run("auto", 5, 4, 2)[2]]
['1/22', '4/33', '4/33', '1/22']
"""

from __future__ import annotations

from collections.abc import Sequence
from concurrent.futures import Executor
from dataclasses import replace
from fractions import Fraction
from typing import Any, NamedTuple

from forcenet.core.errors import ArgumentError
from forcenet.core.plan import Plan, duration_text
from forcenet.core.registry import REGISTRY, Engine
from forcenet.core.validation import MAX_MOMENTS

from .law_registry import (
    LAW_CONTACTS,
    LAW_DP_MAX_N,
    LAW_ENGINES,
    LAW_MAX_N,
    LAW_METHODS,
    LAW_PRIME_ROUTES,
    LAW_ROUTES,
    LawChoice,
    LawPieces,
    LawRequest,
    choose_law,
    law_checkpoint,
    law_policy,
    law_request,
    law_resumed,
    law_run,
)
from .protocol import Progress, Table, TableEngine, TableRequest, check_table_request
from .row_routes import ROW_ENGINES, ROW_LAYER_ROUTES, ROW_PRIME_ROUTES, ROW_ROUTES, row_policy
from .thesis import lambda_route, maps_route, nested_route
from .triangle import moments as ideal_moments
from .triangle import pfaffian_table as pfaffian_route

__all__ = ["ENGINES", "TABLE_ENGINES", "METHODS", "MAX_MOMENTS", "Choice", "Request", "check_request", "plan_request",
           "run_request", "choose", "table_plan", "table_run", "takes", "checkpoint_for", "over_primes",
           "over_primes_text", "ROW_ROUTES", "ROW_PRIME_ROUTES", "ROW_LAYER_ROUTES", "RowChoice", "plan_row", "run_row", "choose_row", "row_plan", "row_run",
           # the laws of one load (forcenet.law, forcenet dist): defined in .law_registry, this registry's names
           "LAW_METHODS", "LAW_MAX_N", "LAW_DP_MAX_N", "LAW_CONTACTS", "LAW_PRIME_ROUTES", "LAW_ROUTES", "LawRequest",
           "law_request", "LawChoice", "choose_law", "law_checkpoint", "law_resumed", "LawPieces", "law_run"]

MODEL = "triangle"
TABLE_ENGINES: tuple[TableEngine, ...] = (ideal_moments.ENGINE, nested_route.ENGINE, lambda_route.ENGINE,
                                          maps_route.ENGINE, pfaffian_route.ENGINE)
ENGINES: tuple[Engine, ...] = (*TABLE_ENGINES, *ROW_ENGINES, *LAW_ENGINES)  # the triangle's, in the registry
METHODS = (*(engine.name for engine in TABLE_ENGINES), "auto")
Request = TableRequest  # a checked table (or row) request: forcenet.exact.protocol.TableRequest

for _one in ENGINES:
    REGISTRY.register(_one)
REGISTRY.set_policy(MODEL, "row", row_policy)
REGISTRY.set_policy(MODEL, "law", law_policy)


def check_request(N: int, moments: int = 1, method: str = "auto", *, row: int | None = None,
                  memory_bytes: int | None = None, executor: Executor | None = None, **options: Any) -> Request:
    """The one check of a table request: each argument once, at the entry; behind it everything trusts it.

    Parameters
    ----------
    N, moments, method, memory_bytes, executor, options
        As in :func:`table_plan`; ``row``, as in :func:`choose_row` (None: the whole table).

    Returns
    -------
    Request

    Raises
    ------
    ArgumentError, ArgumentTypeError
        Naming the argument out of range, or of the wrong type, and its range.

    Examples
    --------
    >>> check_request(12, 2, "fast").moments
    2
    >>> check_request(12, method="fastest")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    forcenet.core.errors.ArgumentError: method='fastest' is out of range: method must be one of fast, ...
    """
    return check_table_request(N, moments, method, row=row, memory_bytes=memory_bytes, executor=executor,
                         methods=METHODS, **options)


def _engine(method: str) -> TableEngine:
    return REGISTRY.engine(MODEL, "table", method)  # type: ignore[return-value]


def takes(method: str, option: str) -> bool:
    """Whether the engine of ``method`` takes the keyword ``option`` beyond the request's (its ``options``).

    Examples
    --------
    >>> takes("pfaffian", "checkpoint"), takes("fast", "checkpoint")
    (True, False)
    """
    return option in _engine(method).options


def checkpoint_for(method: str, directory: Any, N: int, moments: int = 1) -> Any:
    """The checkpoint the engine of ``method`` keeps for a table request in ``directory`` (its ``checkpoint_for``).

    Raises
    ------
    ArgumentError
        If the method keeps no checkpoints.
    """
    engine = _engine(method)
    if not takes(method, "checkpoint"):
        raise ArgumentError(f"checkpoint= applies to the routes over independent primes only, not to method={method!r}")
    return engine.checkpoint_for(directory, N, moments)  # type: ignore[attr-defined]


def _options(method: str, options: dict[str, Any]) -> dict[str, Any]:
    """The given (not None) engine options; refused for a method that does not take them."""
    given = {k: v for k, v in options.items() if v is not None}
    unknown = [k for k in given if not takes(method, k)]
    if unknown:
        able = [e.name for e in TABLE_ENGINES if all(k in e.options for k in unknown)]
        raise ArgumentError(f"{', '.join(f'{k}=' for k in unknown)} applies to method={' or '.join(map(repr, able))} "
                            "only (the routes over independent primes)")
    return given


def over_primes(method: str = "auto") -> str:
    """The table method a request with a cluster or a checkpoint is planned by before they are connected:
    ``method`` itself, or for ``auto`` the one method over independent primes (``auto`` among several).

    Examples
    --------
    >>> over_primes(), over_primes("fast")
    ('pfaffian', 'fast')
    """
    if method != "auto":
        return method
    able = [engine.name for engine in TABLE_ENGINES if "checkpoint" in engine.options]
    return able[0] if len(able) == 1 else "auto"


def over_primes_text() -> str:
    """The table methods over independent primes as the command line names them (its options' help and refusals).

    Examples
    --------
    >>> over_primes_text()
    '--method pfaffian'
    """
    return "--method " + " or ".join(engine.name for engine in TABLE_ENGINES if "checkpoint" in engine.options)


class Choice(NamedTuple):
    """What ``method="auto"`` chose: the method, its plan, and why (one line for the announcement)."""

    method: str
    plan: Plan
    why: str


def choose(N: int, moments: int = 1, *, memory_bytes: int | None = None, executor: Executor | None = None,
           methods: Sequence[str] | None = None, **options: Any) -> Choice:
    """``method="auto"``: the fastest exact route for the request according to the plans.

    Every candidate method's plan is asked; among the runnable ones (in
    range, within ``memory_bytes``) the one of least estimated seconds wins
    (ties: the order of :data:`TABLE_ENGINES`).  A method whose engine states a
    ``min_plan_seconds`` (its start-up, e.g. loading compiled kernels) is
    not planned when another plan already runs within that time.  Engine options (``workers=``,
    ``checkpoint=``) restrict the candidates to the methods that take them.

    Parameters
    ----------
    N : int
        Number of layers, ``>= 2``.
    moments : int
        Highest moment ``s`` of ``W^s``, ``1..50``.
    memory_bytes : int, optional
        Memory available to the run (None: not checked).
    executor : concurrent.futures.Executor, optional
        Runs the chosen method's independent tasks (the plans count it).
    methods : sequence of str, optional
        The candidates (default: every method of :data:`TABLE_ENGINES`).
    **options
        ``workers=``, ``checkpoint=`` of the Pfaffian route.

    Returns
    -------
    Choice
        The method, its plan and the reason; when no candidate can run, the
        first candidate's plan refused with every candidate's reason.

    Raises
    ------
    ArgumentError
        If ``N``, ``moments`` or a method is out of range.

    Examples
    --------
    >>> choice = choose(28)  # fast ~7 min, pfaffian ~20 s (with compiling its kernels: ~21 s)
    >>> choice.method, choice.plan.runnable
    ('pfaffian', True)
    >>> choice.why  # doctest: +ELLIPSIS
    'auto chose pfaffian: the fastest by the plans (fast ~..., pfaffian ~...; thesis, lambda, maps out of range)'
    >>> choose(8, moments=2).method
    'fast'
    """
    return _choose(check_request(N, moments, memory_bytes=memory_bytes, executor=executor, **options), methods)


def _engine_options(method: str, request: Request) -> Request:
    """The request ``method``'s engine is given: its checkpoint store made once from ``request.directory``."""
    if request.directory is None:
        return request
    if method not in request.stores:
        request.stores[method] = checkpoint_for(method, request.directory, request.N, request.moments)
    return replace(request, options={**request.options, "checkpoint": request.stores[method]}, directory=None,
                   stores=request.stores)


def _choose(request: Request, methods: Sequence[str] | None = None) -> Choice:
    """:func:`choose` for a checked request: the registry's ``auto`` among ``methods`` (default: all)."""
    given = request.options
    candidates = tuple(m for m in (METHODS[:-1] if methods is None else methods) if all(takes(m, k) for k in given))
    if not candidates:
        raise ArgumentError(f"{', '.join(f'{k}=' for k in given)} applies to method='pfaffian' only "
                            "(the route over independent primes)")
    if request.directory is not None:  # the stores of the candidates keeping checkpoints, made once
        request = _engine_options("pfaffian", request) if "pfaffian" in candidates else request
    decision = REGISTRY.decide(replace(request, method="auto"), candidates)
    plans = decision.plans
    runnable = {m: p for m, p in plans.items() if p.runnable}
    if not runnable:  # every refusal, so the user sees each route's reach
        reasons = "; ".join(dict.fromkeys(p.refusal for p in plans.values() if p.refusal))
        return Choice(candidates[0], replace(plans[candidates[0]], refusal=f"no method can run it: {reasons}"), "")
    method = decision.engine.name
    slower = [f"{m} >= {duration_text(floor)}" for m, floor in decision.skipped.items()]
    costs = ", ".join([f"{m} ~{duration_text(p.seconds)}" for m, p in runnable.items()] + slower)
    refused = [m for m in plans if m not in runnable]
    out = f"; {', '.join(refused)} out of range" if refused else ""
    return Choice(method, runnable[method], f"auto chose {method}: the fastest by the plans ({costs}{out})")


def table_plan(method: str, N: int, moments: int = 1, memory_bytes: int | None = None, *,
               executor: Executor | None = None, **options: Any) -> Plan:
    """What ``forcenet table --method METHOD --N N --moments MOMENTS`` will cost.

    Parameters
    ----------
    method : {"auto", "fast", "thesis", "lambda", "maps", "pfaffian"}
        ``auto``: :func:`choose`.
    N : int
        Number of layers, ``>= 2``.
    moments : int
        Highest moment ``s`` of ``W^s``, ``1..50``.
    memory_bytes : int, optional
        Memory available to the run; a plan that needs more is refused.
    executor : concurrent.futures.Executor, optional
        Runs the method's independent tasks (default: the method's own,
        :mod:`forcenet.exact.protocol`).
    **options
        ``workers=``, ``checkpoint=`` of the Pfaffian route.

    Returns
    -------
    :class:`~forcenet.core.plan.Plan`

    Raises
    ------
    ArgumentError
        If ``method``, ``N`` or ``moments`` is out of range, or an option
        does not apply to the method.

    Examples
    --------
    >>> table_plan("lambda", 13).refusal
    'N=13 is out of range for --method lambda: N must be an integer in 2..12 (the index boxes of (4.32) outgrow memory)'
    """
    choice = plan_request(check_request(N, moments, method, memory_bytes=memory_bytes, executor=executor, **options))
    return replace(choice.plan, what=f"{choice.plan.what}; {choice.why}") if choice.why else choice.plan


def table_run(method: str, N: int, moments: int = 1, progress: Progress | None = None,
              memory_bytes: int | None = None, *, executor: Executor | None = None,
              **options: Any) -> dict[int, Table]:
    """``{s: table of <W_{i,j}^s>}`` for ``s = 1..moments`` by the chosen route (exact Fractions).

    Parameters
    ----------
    method, N, moments, memory_bytes, executor, options
        As in :func:`table_plan`.
    progress : callable, optional
        ``progress(k=1)`` with the plan's ticks.

    Returns
    -------
    dict of int to list of lists of Fraction

    Raises
    ------
    ArgumentError
        As :func:`table_plan`, and if the plan is refused.

    Examples
    --------
    >>> table_run("auto", 4, 2)[2][-1] == table_run("thesis", 4, 2)[2][-1]
    True
    """
    request = check_request(N, moments, method, memory_bytes=memory_bytes, executor=executor, **options)
    return run_request(request, plan_request(request), progress)


def plan_request(request: Request, methods: Sequence[str] | None = None) -> Choice:
    """The plan of a checked request, made once: ``auto``'s choice among ``methods`` (default: all), or the method's.

    >>> plan_request(check_request(9, method="fast")).plan.runnable
    True
    """
    if request.method == "auto":
        return _choose(request, methods)
    _options(request.method, request.options)  # refuses an option the method does not take
    return Choice(request.method, _engine(request.method).plan(_engine_options(request.method, request)), "")


def run_request(request: Request, choice: Choice, progress: Progress | None = None) -> dict[int, Table]:
    """Run the plan :func:`plan_request` made (not made again); the one place a run checks its plan: a refused
    plan raises ArgumentError before any work.

    >>> request = check_request(5, method="lambda")
    >>> [str(x) for x in run_request(request, plan_request(request))[1][-1]]
    ['1/11', '1/4', '7/22', '1/4', '1/11']
    """
    choice.plan.check()
    return _engine(choice.method).run(_engine_options(choice.method, request), choice.plan,  # type: ignore[no-any-return]
                                      progress=progress)


# ------------------------------------------------------------------ one row: forcenet table --row i


class RowChoice(NamedTuple):
    """The route to one row: a name of :data:`ROW_ROUTES` or a table method, its plan, and why (one line)."""

    route: str
    plan: Plan
    why: str


def choose_row(method: str, N: int, row: int, moments: int = 2, *, memory_bytes: int | None = None,
               executor: Executor | None = None, **options: Any) -> RowChoice:
    """The fastest exact route to row ``row`` of the ``<W^s>`` tables, ``s <= moments``, by the plans.

    With ``method="pfaffian"`` (or ``"auto"``) the row's own routes compete:
    ``covers`` (``moments = 2``, rows 2, 3, ``N - 1``: one-time, the price of
    the mean; :mod:`.triangle.free_fermion.covers`), ``lattice`` (row 2, every
    moment), ``layers`` / ``floor`` (every load of one layer by de Bruijn
    Pfaffians, ``N <= 128``), for ``moments = 1`` the mean table by
    Pfaffians; ``auto`` adds the fastest other method's whole table (the
    order-ideal DP for small ``N``).  Any other method computes its whole
    table and keeps the row.

    Parameters
    ----------
    method : {"auto", "fast", "thesis", "lambda", "maps", "pfaffian"}
        As for :func:`table_plan`.
    N : int
        Number of layers, ``>= 2``.
    row : int
        The row (layer) ``i``, ``1..N``.
    moments : int
        Highest moment ``s``, ``1..50``.
    memory_bytes : int, optional
        Memory available to the run.
    executor : concurrent.futures.Executor, optional
        Runs the route's independent tasks (the routes over primes take it).
    **options
        ``workers=``, ``checkpoint=`` (a directory: a layer's route keeps one request per layer).

    Returns
    -------
    RowChoice
        The route, its plan (refused with every route's reason when none can run) and the reason.

    Raises
    ------
    ArgumentError
        If ``method``, ``N``, ``row`` or ``moments`` is out of range.

    Examples
    --------
    >>> choose_row("pfaffian", 40, 20, 2).route, choose_row("auto", 10, 5, 2).route
    ('layers', 'fast')
    >>> choose_row("pfaffian", 40, 39, 2).why  # doctest: +ELLIPSIS
    'row 39: covers, the fastest by the plans (covers ~..., layers ~...)'
    """
    return plan_row(check_request(N, moments, method, row=row, memory_bytes=memory_bytes, executor=executor, **options))


def plan_row(request: Request) -> RowChoice:
    """:func:`choose_row` for a checked request with its ``row`` (:func:`check_request`): nothing checked again.

    >>> plan_row(check_request(40, 2, "pfaffian", row=39)).route
    'covers'
    """
    if request.method not in ("auto", "pfaffian"):
        _options(request.method, request.options)  # refuses an option the method does not take
    decision = REGISTRY.decide(request)
    plans, row, route = decision.plans, request.row, decision.engine.name
    if not decision.plan.runnable:
        reasons = "; ".join(dict.fromkeys(p.refusal for p in plans.values() if p.refusal))
        first = next(iter(plans))
        return RowChoice(first, replace(plans[first], refusal=f"no route can give row {row}: {reasons}"), "")
    if len(plans) == 1:
        return RowChoice(route, decision.plan, "")
    runnable = {name: plan for name, plan in plans.items() if plan.runnable}
    costs = ", ".join(f"{name} ~{duration_text(plan.seconds)}" for name, plan in runnable.items())
    refused = [name for name in plans if name not in runnable]
    out = f"; {', '.join(refused)} out of range" if refused else ""
    return RowChoice(route, decision.plan, f"row {row}: {route}, the fastest by the plans ({costs}{out})")


def row_plan(method: str, N: int, row: int, moments: int = 2, memory_bytes: int | None = None, *,
             executor: Executor | None = None, **options: Any) -> Plan:
    """What ``forcenet table --N N --row ROW --moments MOMENTS --method METHOD`` will cost (:func:`choose_row`).

    Examples
    --------
    >>> row_plan("pfaffian", 40, 39).what  # doctest: +ELLIPSIS
    'row 39 of <W>, <W^2> N=40 (one-time: each cell uniform between its covers; ...); row 39: covers, ...'
    """
    choice = choose_row(method, N, row, moments, memory_bytes=memory_bytes, executor=executor, **options)
    return replace(choice.plan, what=f"{choice.plan.what}; {choice.why}") if choice.why else choice.plan


def row_run(method: str, N: int, row: int, moments: int = 2, progress: Progress | None = None,
            memory_bytes: int | None = None, *, route: str | None = None, executor: Executor | None = None,
            **options: Any) -> dict[int, list[Fraction]]:
    """``{s: [<W_(row,j)^s>, j = 1..row]}`` for ``s = 1..moments``, exact, by the route :func:`choose_row` takes.

    Parameters
    ----------
    method, N, row, moments, memory_bytes, executor, options
        As in :func:`choose_row`.
    progress : callable, optional
        ``progress(k=1)`` with the plan's ticks.
    route : str, optional
        The route already chosen (:attr:`RowChoice.route`), else chosen here.

    Returns
    -------
    dict of int to list of Fraction

    Raises
    ------
    ArgumentError
        As :func:`choose_row`, and if no route can run the request.

    Examples
    --------
    >>> row_run("pfaffian", 7, 6, 2) == {s: t[5] for s, t in table_run("fast", 7, 2).items()}
    True
    """
    request = check_request(N, moments, method, row=row, memory_bytes=memory_bytes, executor=executor, **options)
    choice = plan_row(request)
    return run_row(request, choice if route is None else choice._replace(route=route), progress)


def run_row(request: Request, choice: RowChoice, progress: Progress | None = None) -> dict[int, list[Fraction]]:
    """Run the row route :func:`plan_row` chose for a checked request (not chosen again); its plan is checked here,
    as in :func:`run_request`.

    >>> request = check_request(5, 2, "auto", row=4)
    >>> [str(x) for x in run_row(request, choose_row("auto", 5, 4, 2))[2]]
    ['1/22', '4/33', '4/33', '1/22']
    """
    choice.plan.check()
    engine = REGISTRY.engine(MODEL, "row", choice.route)
    return engine.run(request, choice.plan, progress=progress)  # type: ignore[no-any-return]
