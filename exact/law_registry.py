"""The registry's laws: one load's law (``forcenet dist``, :func:`forcenet.law`), by target, N and method.

The exact density and distribution function of a grain's ``W_ij``, of a
contact force, of a layer's pooled ``P(f)`` or of the ensemble's.  Which
engine answers which target and N (the route functions beside the engines
compare their plans: the order-ideal DP against the Pfaffian routes), which
checkpoint a route keeps, and the limits the command line shows; the front
door (:mod:`forcenet.laws`) and the command line take them from here.  The
registry :mod:`forcenet.exact.routes` re-exports every name (its laws
section); the names live in this module to keep each under 600 lines.

The routes: ``ideals``, the order-ideal DP (:mod:`.triangle.gaps`, every
target, ``N <= 30``); ``pfaffian``, the Pfaffians of a lattice direction
(grains ``(i, 1)``, ``(i, i)``); ``floor`` and ``layers``, the de Bruijn
Pfaffians of the floor and of one layer (that layer, or its grains);
``pfaffians``, every layer's (the ensemble); the last four up to ``N = 128``.

Examples
--------
>>> request = law_request(40, layer=40)
>>> choice = choose_law(request)
>>> choice.route, choice.plan.runnable
('floor', True)
>>> law_run(law_request(4, (4, 2)), "ideals").extra["mean"]
Fraction(5, 14)
"""

from __future__ import annotations

import os
from concurrent.futures import Executor
from dataclasses import replace
from typing import Any, NamedTuple

from forcenet.core.checkpoints import resumed_plan
from forcenet.core.errors import ArgumentError, ArgumentTypeError
from forcenet.core.plan import Plan, duration_text
from forcenet.core.registry import Decision
from forcenet.core.validation import check_executor, check_grain, check_int, check_layers

from .protocol import Progress
from .triangle import distribution as D
from .triangle.distribution import distribution_plan
from .triangle.gaps import contact_gap_law, contact_location
from .triangle.law_routes import (
    ensemble_pieces,
    ensemble_route,
    grain_route,
    layer_gap_law,
    layer_route,
    single_grain_gap_law,
)
from .triangle.prime_tasks import STARTUP_SECONDS, checkpoint_store
from .triangle.staircase import dimension

__all__ = ["LAW_METHODS", "LAW_MAX_N", "LAW_DP_MAX_N", "LAW_CONTACTS", "LAW_PRIME_ROUTES", "LAW_ROUTES", "LawRequest",
           "law_request", "LawChoice", "choose_law", "law_policy", "law_checkpoint", "law_resumed", "LawPieces",
           "law_run", "LawEngine", "LAW_ENGINES"]

LAW_METHODS = ("auto", "ideals", "pfaffians")  # the faster by the plans; the order-ideal DP; the Pfaffian route
LAW_MAX_N = 128  # the Pfaffian routes' reach (fluctuations.MAX_LAW_N, layers.MAX_FLOOR_N; tested equal)
LAW_DP_MAX_N = 30  # the order-ideal DP's reach (gaps.gap_laws_plan refuses beyond; tested): the contacts' limit
LAW_CONTACTS = ("F1", "F2", "F5", "F6")  # the contact forces that are spacings (gaps.CONTACT_KINDS; tested equal)
LAW_PRIME_ROUTES = ("floor", "layers", "pfaffians")  # the law routes over primes: executor=, checkpoint=
LAW_ROUTES = {  # route -> what it is (the routes the route functions return, and the contacts' DP)
    "ideals": "the order-ideal DP (one pass over the 2^(N-1) order ideals per layer)",
    "pfaffian": "Pfaffians of a lattice direction (one-time)",
    "floor": "the floor's de Bruijn Pfaffians",
    "layers": "the layer's de Bruijn Pfaffians",
    "pfaffians": "every layer's de Bruijn Pfaffians",
}


class LawRequest(NamedTuple):
    """One load's law, validated (:func:`law_request`): a grain's ``W_ij``, its contact force, a layer or the
    ensemble; the ``method`` asked, the memory the plan is checked against, the ``executor`` and ``checkpoint`` of
    the routes over primes. The registry's request (model ``"triangle"``, quantity ``"law"``)."""

    N: int
    grain: tuple[int, int] | None = None
    layer: int | None = None
    contact: str | None = None
    method: str = "auto"
    memory_bytes: int | None = None
    executor: Executor | None = None
    checkpoint: Any = None

    @property
    def model(self) -> str:
        """``"triangle"``."""
        return "triangle"

    @property
    def quantity(self) -> str:
        """``"law"``."""
        return "law"

    @property
    def degree(self) -> int:
        """A bound on the degree of the law's polynomial pieces, known before the law is computed: ``d``, the free
        forces (Eq. (4.3)); the CDF of a linear function of the forces on the ``d``-dimensional force space
        (Eq. (4.1)) is piecewise polynomial of degree at most ``d`` (``Law.grid``'s cost is planned by it).

        Examples
        --------
        >>> law_request(6, (5, 3), contact="F1").degree
        15
        """
        return dimension(self.N)

    @property
    def kind(self) -> str:
        """``"contact"``, ``"grain"``, ``"layer"`` or ``"ensemble"``."""
        if self.contact is not None:
            return "contact"
        return "grain" if self.grain is not None else "layer" if self.layer is not None else "ensemble"


def law_request(N: int, grain: Any = None, layer: Any = None, contact: Any = None, *, method: Any = "auto",
                memory_bytes: Any = None, executor: Executor | None = None) -> LawRequest:
    """Validate one load's law once: ``grain=(i, j)`` (with ``contact``, its contact force), ``layer=i``, or neither
    (the ensemble, every grain of layers ``2..N`` pooled); ``memory_bytes >= 1``; ``method`` one of
    :data:`LAW_METHODS`.

    Raises
    ------
    ArgumentError, ArgumentTypeError
        If ``N`` is not in ``2..LAW_MAX_N``, the grain or layer is out of range, ``W_11`` (the overload) is asked,
        a contact is not random there, the arguments do not name one target, or ``memory_bytes`` or ``method`` is
        out of range.

    Examples
    --------
    >>> law_request(12, (12, 6)).kind, law_request(12, layer=3).kind, law_request(12).kind
    ('grain', 'layer', 'ensemble')
    >>> law_request(6, (1, 1))
    Traceback (most recent call last):
    ...
    forcenet.core.errors.ArgumentError: grain=(1, 1): W_11 = 1 is the overload, it has no density; i must be in 2..6
    """
    N = check_layers(N, maximum=LAW_MAX_N)
    if grain is not None and layer is not None:
        raise ArgumentError(f"grain={grain!r} and layer={layer!r}: give one (a grain's W_ij, or layer i's pooled "
                            "P(f)); neither is the ensemble")
    if contact is not None:
        if not isinstance(contact, str):
            raise ArgumentTypeError(f"contact={contact!r} is not a string: contact must be one of "
                                    f"{', '.join(LAW_CONTACTS)}")
        if contact not in LAW_CONTACTS:
            raise ArgumentError(f"contact={contact!r} is out of range: contact must be one of {', '.join(LAW_CONTACTS)}"
                                " (F3, F4 are lateral forces, not spacings)")
        if grain is None:
            raise ArgumentError(f"contact={contact!r} needs grain=(i, j): the grain whose contact force is wanted")
    if grain is not None:
        i, j = check_grain(N, grain)
        if contact is None and i == 1:
            raise ArgumentError(f"grain=({i}, {j}): W_11 = 1 is the overload, it has no density; i must be in 2..{N}")
        if contact is not None:
            contact_location(N, i, j, contact, grain)  # refuses the contacts that are not random
        target = LawRequest(N, (i, j), None, contact)
    elif layer is not None:
        target = LawRequest(N, None, check_int(layer, "layer", 2, N))
    else:
        target = LawRequest(N)
    memory = None if memory_bytes is None else check_int(memory_bytes, "memory_bytes", 1)
    return target._replace(method=_check_method(method), memory_bytes=memory, executor=check_executor(executor))


def _check_method(method: Any) -> str:
    if not isinstance(method, str):
        raise ArgumentTypeError(f"method={method!r} is not a string: method must be one of {', '.join(LAW_METHODS)}")
    if method not in LAW_METHODS:
        raise ArgumentError(f"method={method!r} is out of range: method must be one of {', '.join(LAW_METHODS)}")
    return method


class LawChoice(NamedTuple):
    """The route to a law, its plan, and why (empty for an explicit method)."""

    route: str
    plan: Plan
    why: str


def choose_law(request: LawRequest, method: str | None = None, memory_bytes: int | None = None, *,
               executor: Executor | None = None) -> LawChoice:
    """The route to ``request``'s law by ``method`` (default: the request's) and its plan; a refused plan names what
    would run it.  :func:`law_policy` (the registry's choice for a law) as a function.

    ``auto`` takes the route function's choice beside the engines (the faster runnable plan of the order-ideal
    DP and the Pfaffian route: :func:`~forcenet.exact.triangle.law_routes.grain_route`,
    :func:`~forcenet.exact.triangle.law_routes.layer_route`,
    :func:`~forcenet.exact.triangle.law_routes.ensemble_route`; a contact force has the DP only), each
    called once.  ``ideals`` is the DP; ``pfaffians`` the Pfaffian route, planned where it is the faster.
    ``executor`` (a cluster's workers) belongs to the routes over primes, :data:`LAW_PRIME_ROUTES`.

    Examples
    --------
    >>> choose_law(law_request(12, (12, 6))).route, choose_law(law_request(40, layer=40)).route
    ('ideals', 'floor')
    >>> print(choose_law(law_request(40, layer=40), "ideals").plan.refusal)  # doctest: +ELLIPSIS
    N=40 is out of range for exact gap laws: ...; method='auto' runs it by floor (~...)
    """
    if method is not None:
        request = request._replace(method=_check_method(method))
    if memory_bytes is not None:
        request = request._replace(memory_bytes=memory_bytes)
    if executor is not None:
        request = request._replace(executor=executor)
    return _decide(request)


def law_policy(registry: Any, request: LawRequest) -> Decision:
    """The registry's choice for a checked law request (:func:`choose_law`): the route's engine, its plan, why.

    Examples
    --------
    >>> law_policy(None, law_request(40, layer=40)).engine.name
    'floor'
    """
    route, plan, why = _decide(request)
    return Decision(LAW_ENGINES_BY_ROUTE[route], plan, {route: plan}, {}, why)


def _decide(request: LawRequest) -> LawChoice:
    """The route, plan and reason for a checked law request (the body of :func:`choose_law`)."""
    method, memory_bytes, executor = request.method, request.memory_bytes, request.executor
    N, kind = request.N, request.kind
    options: dict[str, Any] = {"executor": executor}  # the plans over primes count a cluster's workers
    if request.contact is not None:  # a contact force: the DP over the ideals of its row or column
        route, plan = "ideals", distribution_plan(N, "contact", memory_bytes)
    elif request.grain is not None:
        route, plan = grain_route(N, request.grain, memory_bytes, **options)
    elif request.layer is not None:
        route, plan = layer_route(N, request.layer, memory_bytes, **options)
    else:
        route, plan = ensemble_route(N, memory_bytes, **options)
    auto = f"method='auto' runs it by {route} (~{duration_text(plan.seconds)})" if plan.runnable else ""
    if method == "auto":
        if not plan.runnable and kind == "contact" and N > LAW_DP_MAX_N:
            plan = replace(plan, refusal=f"{plan.refusal}; a contact force has the order-ideal DP only (N <= "
                                         f"{LAW_DP_MAX_N}); a grain's W_ij, a layer or the ensemble run up to "
                                         f"N={LAW_MAX_N}")
        why = f"auto: {route}, {LAW_ROUTES[route]}, the faster runnable route by the plans"
        return LawChoice(route, plan, why if plan.runnable else "")
    if method == "ideals" and route != "ideals":
        dp = distribution_plan(N, kind, memory_bytes)
        if not dp.runnable and auto:
            dp = replace(dp, refusal=f"{dp.refusal}; {auto}")
        return LawChoice("ideals", dp, "")
    if method == "pfaffians" and route == "ideals":
        why = ("no Pfaffian route reaches a contact force" if kind == "contact" else
               "the Pfaffian route is planned where it is the faster, and here the order-ideal DP is")
        refusal = f"method='pfaffians' for this law at N={N}: {why}; {auto or 'no route runs it'}"
        return LawChoice("pfaffians", Plan(plan.what, 0, refusal=refusal), "")
    return LawChoice(route, plan, "")


def law_checkpoint(request: LawRequest, route: str, directory: Any) -> Any:
    """The checkpoint ``route`` keeps for ``request`` in ``directory``: a store, or for the ensemble (one request
    per layer) the directory itself.

    Raises
    ------
    ArgumentError
        If the route keeps no checkpoints (only :data:`LAW_PRIME_ROUTES` do).

    Examples
    --------
    >>> import tempfile
    >>> d = tempfile.mkdtemp()
    >>> law_checkpoint(law_request(40, layer=40), "floor", d).request["route"]
    'pfaffian-floor'
    >>> law_checkpoint(law_request(40), "pfaffians", d) == d
    True
    """
    if route not in LAW_PRIME_ROUTES:
        raise ArgumentError(f"checkpoint= applies to the law routes over primes ({', '.join(LAW_PRIME_ROUTES)}), "
                            f"not to route={route!r}: run it without a checkpoint")
    if route == "pfaffians":
        return os.fspath(directory)
    key = {"floor": "floor", "layers": "layer"}[route] + ("-grains" if request.kind == "grain" else "")
    layer = request.grain[0] if request.grain is not None else request.layer
    return checkpoint_store(directory, key, request.N, layer=layer if route == "layers" else None)


def law_resumed(plan: Plan, request: LawRequest, checkpoint: Any) -> Plan:
    """``plan`` with the records a checkpoint directory already holds counted (the ensemble's one request per
    layer); a store's own plan is unchanged.

    Examples
    --------
    >>> import tempfile
    >>> plan = choose_law(law_request(8)).plan
    >>> law_resumed(plan, law_request(8), tempfile.mkdtemp()).seconds == plan.seconds
    True
    """
    if not isinstance(checkpoint, str):
        return plan
    # the process's start-up is paid whatever the records (the layers' pooled laws cost about alike per prime)
    return resumed_plan(plan, checkpoint, request.N, ("pfaffian-layer", "pfaffian-floor"), fixed=STARTUP_SECONDS)


class LawPieces(NamedTuple):
    """A law as the engines give it: its title, variable, density and CDF pieces (sympy ``Poly`` over ``QQ``) and
    extra exact fields (a grain's mean and second moment)."""

    quantity: str
    variable: str
    density: list[Any]
    cdf: list[Any]
    extra: dict[str, Any]


def law_run(request: LawRequest, route: str, progress: Progress | None = None, **options: Any) -> LawPieces:
    """``request``'s exact law by ``route`` (:func:`choose_law`); ``options``: ``executor``, ``checkpoint`` (the
    routes over primes).

    Examples
    --------
    >>> law = law_run(law_request(3, (3, 2)), "ideals")
    >>> law.quantity, law.density[0].poly.as_expr(), law.extra["mean"]
    ('W_{3,2}', -6*w**2 + 6*w, Fraction(1, 2))
    """
    N = request.N
    if request.grain is not None:
        i, j = request.grain
        contact = request.contact
        gaps = (single_grain_gap_law(N, (i, j), route, progress, **options) if contact is None
                else contact_gap_law(N, (i, j), contact, progress))
        name = f"W_{{{i},{j}}}" if contact is None else f"(sqrt3/2) {contact}^{{({i},{j})}}"
        extra = {"mean": D.moment_from_gaps(gaps, 1), "second_moment": D.moment_from_gaps(gaps, 2)}
        return LawPieces(name, "w", *D.grain_pieces(gaps), extra)
    if request.layer is not None:
        i = request.layer
        gaps = layer_gap_law(N, i, route, progress, **options)
        return LawPieces(f"P(f), f = {i} W_{{{i},j}} (layer {i})", "f", *D.layer_pieces_from_gaps(gaps, i), {})
    pieces = ensemble_pieces(N, route, progress, **options)
    return LawPieces("P(f), f = i W_{i,j} over layers 2..N (ensemble)", "f", pieces, D.piecewise_cdf(pieces), {})


class LawEngine:
    """One route to a load's law as an engine (model ``"triangle"``, quantity ``"law"``): its ``name`` is the route
    (:data:`LAW_ROUTES`); the law's policy (:func:`law_policy`) chooses among them, so its plan is the policy's
    when the policy takes this route, else refused naming the route that serves the law."""

    model = "triangle"
    quantities = frozenset({"law"})

    def __init__(self, name: str) -> None:
        self.name = name
        self.options = frozenset({"checkpoint"}) if name in LAW_PRIME_ROUTES else frozenset()

    def __repr__(self) -> str:
        return f"<triangle law engine {self.name!r}>"

    def plan(self, request: LawRequest) -> Plan:
        """The policy's plan if it takes this route; else a refusal naming the route that does."""
        route, plan, _ = _decide(request)
        if route == self.name:
            return plan
        return Plan(plan.what, 0, refusal=f"route {self.name!r} does not serve this law at N={request.N}: {route} does")

    def run(self, request: LawRequest, plan: Plan, *, progress: Progress | None = None,
            executor: Executor | None = None) -> LawPieces:
        """:func:`law_run` by this route, with the request's ``executor`` (or ``executor``) and ``checkpoint``."""
        options = {k: v for k, v in (("executor", executor or request.executor), ("checkpoint", request.checkpoint))
                   if v is not None}
        return law_run(request, self.name, progress, **options)


LAW_ENGINES: tuple[LawEngine, ...] = tuple(LawEngine(route) for route in LAW_ROUTES)
LAW_ENGINES_BY_ROUTE = {engine.name: engine for engine in LAW_ENGINES}
