"""The routes of ``forcenet table``: a plain table from method name to engine module, and ``auto``.

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

Every engine module has the same ``table_plan``/``table_run`` pair
(:class:`forcenet.exact.protocol.TableEngine`) and owns its cost knowledge;
this module only looks the method up, and for ``auto`` compares the plans.
It alone checks a request (:func:`check_request`: ``N``, ``moments``,
``method``, ``row``, ``memory_bytes``, once), plans it once
(:func:`plan_request`) and checks the plan before the run
(:func:`run_request`); the engines' trusted pair (``trusted_plan``,
``trusted_run``) receives the checked arguments.

One row of the moment tables (``forcenet table --row i``, :func:`row_plan`,
:func:`row_run`) has routes of its own (:func:`choose_row`): the one-time
cover identity for the rows ``2``, ``3``, ``N - 1`` (``<W^2>`` for the price
of the mean, :mod:`.triangle.free_fermion.covers`), the lattice route for row 2
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
from dataclasses import dataclass, field, replace
from fractions import Fraction
from typing import Any, NamedTuple

from forcenet.core.errors import ArgumentError, ArgumentTypeError
from forcenet.core.plan import Plan, duration_text
from forcenet.core.validation import MAX_MOMENTS, check_int, check_layers, check_moments

from .law_registry import (
    LAW_CONTACTS,
    LAW_DP_MAX_N,
    LAW_MAX_N,
    LAW_METHODS,
    LAW_PRIME_ROUTES,
    LAW_ROUTES,
    LawChoice,
    LawPieces,
    LawRequest,
    choose_law,
    law_checkpoint,
    law_request,
    law_resumed,
    law_run,
)
from .protocol import Progress, Table, TableEngine
from .thesis import lambda_route, maps_route, nested_route
from .triangle import moments as ideal_moments
from .triangle import pfaffian_table as pfaffian_route

__all__ = ["ENGINES", "METHODS", "MAX_MOMENTS", "Choice", "Request", "check_request", "plan_request", "run_request",
           "choose", "table_plan", "table_run", "takes", "checkpoint_for", "ROW_ROUTES", "ROW_PRIME_ROUTES", "RowChoice",
           "plan_row", "run_row", "choose_row", "row_plan", "row_run",
           # the laws of one load (forcenet.law, forcenet dist): defined in .law_registry, this registry's names
           "LAW_METHODS", "LAW_MAX_N", "LAW_DP_MAX_N", "LAW_CONTACTS", "LAW_PRIME_ROUTES", "LAW_ROUTES", "LawRequest",
           "law_request", "LawChoice", "choose_law", "law_checkpoint", "law_resumed", "LawPieces", "law_run"]

ENGINES: dict[str, TableEngine] = {
    "fast": ideal_moments,
    "thesis": nested_route,
    "lambda": lambda_route,
    "maps": maps_route,
    "pfaffian": pfaffian_route,
}
METHODS = (*ENGINES, "auto")


@dataclass(frozen=True)
class Request:
    """A checked table request (:func:`check_request` makes it), planned and run trusted: ``options``, the engine
    options given; ``directory``, where each engine keeping checkpoints makes its store, once (``stores``)."""

    N: int
    moments: int = 1
    method: str = "auto"
    memory_bytes: int | None = None
    executor: Executor | None = None
    options: dict[str, Any] = field(default_factory=dict)
    row: int | None = None
    directory: str | None = None
    stores: dict[str, Any] = field(default_factory=dict, compare=False, repr=False)


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
    N, moments = check_layers(N), check_moments(moments)
    if not isinstance(method, str):
        raise ArgumentTypeError(f"method={method!r} is not a string: method must be one of {', '.join(METHODS)}")
    if method != "auto":
        _engine(method)  # refuses an unknown name
    row = None if row is None else check_int(row, "row", 1, N)
    memory_bytes = None if memory_bytes is None else check_int(memory_bytes, "memory_bytes", 0)
    given = {k: v for k, v in options.items() if v is not None}
    return Request(N, moments, method, memory_bytes, executor, given, row)


def _engine(method: str) -> TableEngine:
    if method not in ENGINES:
        raise ArgumentError(f"method={method!r} is out of range: method must be one of {', '.join(METHODS)}")
    return ENGINES[method]


def takes(method: str, option: str) -> bool:
    """Whether the engine of ``method`` takes the keyword ``option`` beyond the protocol's (its ``OPTIONS``).

    Examples
    --------
    >>> takes("pfaffian", "checkpoint"), takes("fast", "checkpoint")
    (True, False)
    """
    return option in getattr(_engine(method), "OPTIONS", ())


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
        able = [m for m in ENGINES if all(takes(m, k) for k in unknown)]
        raise ArgumentError(f"{', '.join(f'{k}=' for k in unknown)} applies to method={' or '.join(map(repr, able))} "
                            "only (the routes over independent primes)")
    return given


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
    (ties: the order of :data:`ENGINES`).  A method whose module states a
    ``MIN_PLAN_SECONDS`` (its start-up, e.g. loading compiled kernels) is
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
        The candidates (default: every method of :data:`ENGINES`).
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


def _engine_options(method: str, request: Request) -> dict[str, Any]:
    """The options ``method``'s engine is given: the request's, with its checkpoint store made once from
    ``request.directory``."""
    if request.directory is None:
        return request.options
    if method not in request.stores:
        request.stores[method] = checkpoint_for(method, request.directory, request.N, request.moments)
    return {**request.options, "checkpoint": request.stores[method]}


def _plan(method: str, request: Request) -> Plan:
    """The engine's plan of a checked request (its trusted face: nothing is checked again)."""
    return ENGINES[method].trusted_plan(request.N, request.moments, memory_bytes=request.memory_bytes,
                                        executor=request.executor, **_engine_options(method, request))


def _choose(request: Request, methods: Sequence[str] | None = None) -> Choice:
    """:func:`choose` for a checked request."""
    given = request.options
    candidates = [m for m in (ENGINES if methods is None else methods)
                  if all(takes(m, k) for k in given)]
    if not candidates:
        raise ArgumentError(f"{', '.join(f'{k}=' for k in given)} applies to method='pfaffian' only "
                            "(the route over independent primes)")
    plans: dict[str, Plan] = {}
    slower: list[str] = []  # not planned: their start-up alone exceeds a runnable plan's whole time
    for m in sorted(candidates, key=lambda m: getattr(ENGINES[m], "MIN_PLAN_SECONDS", 0.0)):
        floor = getattr(ENGINES[m], "MIN_PLAN_SECONDS", 0.0)
        if floor and any(p.runnable and p.seconds <= floor for p in plans.values()):
            slower.append(f"{m} >= {duration_text(floor)}")
            continue
        plans[m] = _plan(m, request)
    runnable = {m: p for m, p in plans.items() if p.runnable}
    if not runnable:  # every refusal, so the user sees each route's reach
        reasons = "; ".join(dict.fromkeys(p.refusal for p in plans.values() if p.refusal))
        return Choice(candidates[0], replace(plans[candidates[0]], refusal=f"no method can run it: {reasons}"), "")
    method = min(runnable, key=lambda m: (runnable[m].seconds, candidates.index(m)))
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
    return Choice(request.method, _plan(request.method, request), "")


def run_request(request: Request, choice: Choice, progress: Progress | None = None) -> dict[int, Table]:
    """Run the plan :func:`plan_request` made (not made again); the one place a run checks its plan: a refused
    plan raises ArgumentError before any work.

    >>> request = check_request(5, method="lambda")
    >>> [str(x) for x in run_request(request, plan_request(request))[1][-1]]
    ['1/11', '1/4', '7/22', '1/4', '1/11']
    """
    choice.plan.check()
    return ENGINES[choice.method].trusted_run(
        request.N, request.moments, choice.plan, memory_bytes=request.memory_bytes, progress=progress,
        executor=request.executor, **_engine_options(choice.method, request))


# ------------------------------------------------------------------ one row: forcenet table --row i

ROW_ROUTES = ("apex", "covers", "lattice", "layers", "floor")  # beside them, a table method's whole table
ROW_PRIME_ROUTES = ("covers", "layers", "floor", "pfaffian")  # the row's routes over primes: executor=, checkpoint=


class RowChoice(NamedTuple):
    """The route to one row: a name of :data:`ROW_ROUTES` or a table method, its plan, and why (one line)."""

    route: str
    plan: Plan
    why: str


def _row_candidates(request: Request) -> dict[str, Plan]:
    """Every route's plan for the checked request's row (``auto``: the row routes and the other tables)."""
    from .triangle.de_bruijn.floor import MAX_FLOOR_N, floor_plan
    from .triangle.de_bruijn.layers import layer_plan
    from .triangle.free_fermion.covers import cover_row_plan, one_time_rows
    from .triangle.free_fermion.fluctuations import lattice_gap_laws_plan

    method, N, moments, memory_bytes, executor = (request.method, request.N, request.moments, request.memory_bytes,
                                                  request.executor)
    row, options = request.row or 1, request.options  # a row's request has its row (check_request)
    if method not in ("auto", "pfaffian"):  # a table method: its whole table, one row kept
        plan = _plan(method, request)
        return {method: replace(plan, what=f"row {row} of the {plan.what}")}
    what = f"row {row} of <W^s>, s <= {moments}, N={N}"
    if row == 1:
        return {"apex": Plan(f"{what} (the apex: W_11 = 1)", 0.0)}
    plans: dict[str, Plan] = {}
    workers, checkpoint = options.get("workers"), options.get("checkpoint")
    if moments == 1:  # the mean: one row of the one-time mean table
        plans["pfaffian"] = _plan("pfaffian", request)
    elif moments == 2 and row in one_time_rows(N):
        plans["covers"] = cover_row_plan(N, row, memory_bytes=memory_bytes, workers=workers, executor=executor,
                                         checkpoint=checkpoint)
    if row == 2 and executor is None and checkpoint is None:  # both loads are lattice directions: every moment
        law = lattice_gap_laws_plan(N, memory_bytes, workers, layers=1)
        plans["lattice"] = replace(law, what=f"{what} (one-time: the lattice directions' law, Pfaffians)")
    name = "floor" if row == N else "layers"
    if N <= MAX_FLOOR_N:
        plan = floor_plan(N, True, memory_bytes, workers) if row == N else layer_plan(N, row, True, memory_bytes, workers)
    else:
        plan = Plan(what, 0, refusal=f"N={N} is out of range for one layer's de Bruijn Pfaffians: N must be an "
                                     f"integer in 2..{MAX_FLOOR_N}")
    plans[name] = replace(plan, what=f"{what} (two-time: layer {row}'s gap laws, de Bruijn Pfaffians)")
    if method == "auto" and not options:  # the other methods' whole tables
        others = [m for m in ENGINES if m != "pfaffian"]
        choice = _choose(request, others)
        if choice.plan.runnable:
            plans[choice.method] = replace(choice.plan, what=f"row {row} of the {choice.plan.what}")
    return plans


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
    plans = _row_candidates(request)
    row = request.row
    runnable = {name: plan for name, plan in plans.items() if plan.runnable}
    if not runnable:
        first = next(iter(plans))
        reasons = "; ".join(dict.fromkeys(p.refusal for p in plans.values() if p.refusal))
        return RowChoice(first, replace(plans[first], refusal=f"no route can give row {row}: {reasons}"), "")
    names = list(plans)
    route = min(runnable, key=lambda name: (runnable[name].seconds, names.index(name)))
    if len(plans) == 1:
        return RowChoice(route, runnable[route], "")
    costs = ", ".join(f"{name} ~{duration_text(plan.seconds)}" for name, plan in runnable.items())
    refused = [name for name in plans if name not in runnable]
    out = f"; {', '.join(refused)} out of range" if refused else ""
    return RowChoice(route, runnable[route], f"row {row}: {route}, the fastest by the plans ({costs}{out})")


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
    from .triangle.distribution import moment_from_gaps
    from .triangle.free_fermion.covers import cover_row_moments
    from .triangle.free_fermion.fluctuations import grain_gap_law
    from .triangle.pfaffian_table import every_load_gap_law

    choice.plan.check()
    N, row, moments, route, executor = request.N, request.row or 1, request.moments, choice.route, request.executor
    given = request.options
    if route == "apex":
        return {s: [Fraction(1)] for s in range(1, moments + 1)}
    if route == "covers":
        found = cover_row_moments(N, row, progress=progress, executor=executor, **given)
        return {s: found[s] for s in range(1, moments + 1)}
    if route == "lattice":
        law = grain_gap_law(N, (row, 1), progress=progress, **given)
        return {s: [moment_from_gaps(law, s)] * 2 for s in range(1, moments + 1)}
    if route in ("layers", "floor"):
        laws = every_load_gap_law(N, row, progress=progress, executor=executor, **given)
        return {s: [moment_from_gaps(laws[j], s) for j in range(1, row + 1)] for s in range(1, moments + 1)}
    tables = run_request(replace(request, method=route), Choice(route, choice.plan, ""), progress)
    return {s: table[row - 1] for s, table in tables.items()}
