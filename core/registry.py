"""The model seam: engines as objects, one registry keyed by model, quantity and method.

A *request* is an immutable value that was checked once, when it was built
(by the front door or the command line); it names its ``model`` (the
triangle, a contact network, a q-model, ...), its ``quantity`` (a table, a
row, a law, moments, samples, clusters, ...) and its ``method`` (an engine's
name, or ``"auto"``).  An *engine* serves one model and some quantities:
``plan(request)`` is cheap and returns a :class:`~forcenet.core.plan.Plan`
(the cost, or the refusal), ``run(request, plan, progress=, executor=)``
computes as planned and trusts the request (it never checks it again).

A new model enters by registering its engines (:meth:`Registry.register`,
or a loader named in :meth:`Registry.add_loader` that registers them on
first use, so ``import forcenet`` stays light: the module registers them
itself, or lists them in its ``ENGINES``); nothing else of the house
changes.  ``method="auto"`` chooses the fastest runnable engine by the
engines' own plans (:meth:`Registry.decide`); an engine may state its
``options`` (the keywords beyond the request it takes: ``auto`` then
chooses among the engines taking the options given) and its
``min_plan_seconds`` (its start-up: not planned when another plan already
runs within it).  A model whose choice is more than "the fastest plan"
(one quantity's engines choosing among routes of their own) registers its
policy for that quantity (:meth:`Registry.set_policy`).

Examples
--------
>>> from dataclasses import dataclass
>>> from forcenet.core.plan import Plan
>>> @dataclass(frozen=True)
... class Square:
...     n: int
...     method: str = "auto"
...     model = "toy"
...     quantity = "square"
>>> class Multiply:
...     name, model, quantities = "multiply", "toy", frozenset({"square"})
...     def plan(self, request): return Plan(f"{request.n}^2", seconds=2.0)
...     def run(self, request, plan, *, progress=None, executor=None): return request.n * request.n
>>> class Add:
...     name, model, quantities = "add", "toy", frozenset({"square"})
...     def plan(self, request): return Plan(f"{request.n}^2", seconds=1.0 * request.n)
...     def run(self, request, plan, *, progress=None, executor=None): return sum([request.n] * request.n)
>>> registry = Registry()
>>> _ = registry.register(Multiply()); _ = registry.register(Add())
>>> registry.methods("toy", "square")
('multiply', 'add')
>>> registry.choose(Square(1))[0].name, registry.choose(Square(7))[0].name  # auto: the faster plan
('add', 'multiply')
>>> registry.run(Square(7))
49
"""

from __future__ import annotations

import importlib
from collections.abc import Callable
from concurrent.futures import Executor
from typing import Any, NamedTuple, Protocol, runtime_checkable

from .errors import ArgumentError, ArgumentTypeError
from .plan import Plan

__all__ = ["Engine", "Registry", "Decision", "Policy", "AUTO", "REGISTRY"]

AUTO = "auto"


class Decision(NamedTuple):
    """The registry's answer to a request: the ``engine`` that runs it, its ``plan`` (possibly refused), ``plans``
    (every candidate's plan, by name, in registration order: ``auto``'s comparison) and ``skipped`` (candidates
    not planned: their ``min_plan_seconds`` alone exceeds a runnable plan's time); ``why``, a policy's reason."""

    engine: Engine
    plan: Plan
    plans: dict[str, Plan]
    skipped: dict[str, float]
    why: str = ""


Policy = Callable[["Registry", Any], Decision]  # a model's own choice for one quantity (set_policy)


@runtime_checkable
class Engine(Protocol):
    """One algorithm for one model: its ``name`` (the method users pass), the ``model`` it serves, the
    ``quantities`` it computes, its cost (``plan``) and its computation (``run``, trusting the request)."""

    name: str
    model: str
    quantities: frozenset[str]

    def plan(self, request: Any) -> Plan: ...

    def run(self, request: Any, plan: Plan, *, progress: Callable[..., Any] | None = None,
            executor: Executor | None = None) -> Any: ...


class Registry:
    """Engines keyed by ``(model, quantity, method)``; ``auto`` picks the fastest runnable plan.

    Engines register directly (:meth:`register`) or through a loader (:meth:`add_loader`): a module
    path whose import registers a model's engines, imported the first time that model is asked for.
    """

    def __init__(self) -> None:
        self._engines: dict[tuple[str, str], dict[str, Engine]] = {}
        self._loaders: dict[str, list[str]] = {}
        self._policies: dict[tuple[str, str], Policy] = {}

    def add_loader(self, model: str, module: str) -> None:
        """Import ``module`` (which registers ``model``'s engines) the first time ``model`` is asked for."""
        self._loaders.setdefault(model, []).append(module)

    def register(self, engine: Engine) -> Engine:
        """Add ``engine`` under its model, each of its quantities and its name; returns it (usable as a decorator
        on an instance). A second engine of the same model, quantity and name is a programming error."""
        if not isinstance(engine, Engine):
            raise ArgumentTypeError(f"{engine!r} is not an Engine (name, model, quantities, plan, run)")
        if engine.name == AUTO:
            raise ArgumentError("'auto' is the registry's choice, not an engine's name")
        for quantity in engine.quantities:
            slot = self._engines.setdefault((engine.model, quantity), {})
            if engine.name in slot and slot[engine.name] is not engine:
                raise ArgumentError(f"engine {engine.name!r} is registered twice for {engine.model}/{quantity}")
            slot[engine.name] = engine
        return engine

    def set_policy(self, model: str, quantity: str, policy: Policy) -> None:
        """``policy(registry, request) -> Decision`` decides every request of ``model`` and ``quantity`` (a named
        method included), instead of :meth:`decide`'s fastest plan."""
        self._policies[(model, quantity)] = policy

    def _load(self, model: str) -> None:
        for module in self._loaders.pop(model, []):
            for engine in getattr(importlib.import_module(module), "ENGINES", ()):
                self.register(engine)

    def models(self) -> tuple[str, ...]:
        """Every model registered or loadable."""
        return tuple(dict.fromkeys([*(m for m, _ in self._engines), *self._loaders]))

    def methods(self, model: str, quantity: str) -> tuple[str, ...]:
        """The engines' names for ``model`` and ``quantity``, in registration order (``auto`` not included)."""
        self._load(model)
        return tuple(self._engines.get((model, quantity), {}))

    def engine(self, model: str, quantity: str, method: str) -> Engine:
        """The engine named ``method``; :class:`~forcenet.core.errors.ArgumentError` naming the choices if none."""
        names = self.methods(model, quantity)
        if not names:
            raise ArgumentError(f"no engine computes {quantity!r} for model {model!r}")
        if method not in names:
            raise ArgumentError(f"method={method!r} is out of range: method must be one of "
                                f"{', '.join((*names, AUTO))}")
        return self._engines[(model, quantity)][method]

    def takes(self, model: str, quantity: str, method: str, option: str) -> bool:
        """Whether engine ``method`` takes the keyword ``option`` beyond the request (its ``options``)."""
        return option in getattr(self.engine(model, quantity, method), "options", ())

    def choose(self, request: Any) -> tuple[Engine, Plan]:
        """The engine and its plan for a checked ``request`` (:meth:`decide`)."""
        decision = self.decide(request)
        return decision.engine, decision.plan

    def decide(self, request: Any, candidates: tuple[str, ...] | None = None) -> Decision:
        """The engine and its plan for a checked ``request`` (``model``, ``quantity``, ``method``).

        The model's policy for the quantity if it set one (:meth:`set_policy`); else, a named method: its plan
        as it is (possibly refused: the caller decides whether to raise or announce); ``method="auto"``: among
        ``candidates`` (default: every engine; those taking the request's ``options``), every plan, the
        fastest runnable one (ties: registration order); an engine whose ``min_plan_seconds`` a runnable plan
        already beats is not planned. If none runs, the first candidate's refusal (the caller may join the
        others' from ``plans``).
        """
        self._load(request.model)
        policy = self._policies.get((request.model, request.quantity))
        if policy is not None and candidates is None:
            return policy(self, request)
        if request.method != AUTO:
            engine = self.engine(request.model, request.quantity, request.method)
            plan = engine.plan(request)
            return Decision(engine, plan, {engine.name: plan}, {})
        return self.fastest(request, candidates)

    def fastest(self, request: Any, candidates: tuple[str, ...] | None = None) -> Decision:
        """``auto`` by the plans alone (:meth:`decide` without a policy): the fastest runnable candidate."""
        names = self.methods(request.model, request.quantity)
        if not names:
            raise ArgumentError(f"no engine computes {request.quantity!r} for model {request.model!r}")
        engines = self._engines[(request.model, request.quantity)]
        given = tuple(getattr(request, "options", None) or ())
        names = tuple(n for n in (names if candidates is None else candidates)
                      if all(k in getattr(engines[n], "options", ()) for k in given))
        if not names:
            raise ArgumentError(f"{', '.join(f'{k}=' for k in given)} applies to no engine of {request.quantity!r} "
                                f"for model {request.model!r}")
        plans: dict[str, Plan] = {}
        skipped: dict[str, float] = {}
        for name in sorted(names, key=lambda n: getattr(engines[n], "min_plan_seconds", 0.0)):
            floor = getattr(engines[name], "min_plan_seconds", 0.0)
            if floor and any(p.runnable and p.seconds <= floor for p in plans.values()):
                skipped[name] = floor
                continue
            plans[name] = engines[name].plan(request)
        plans = {n: plans[n] for n in names if n in plans}
        runnable = [n for n in plans if plans[n].runnable]
        best = min(runnable, key=lambda n: plans[n].seconds) if runnable else names[0]
        return Decision(engines[best], plans[best], plans, skipped)

    def run(self, request: Any, *, progress: Callable[..., Any] | None = None,
            executor: Executor | None = None) -> Any:
        """Choose, check the plan (:meth:`~forcenet.core.plan.Plan.check`) and run."""
        engine, plan = self.choose(request)
        return engine.run(request, plan.check(), progress=progress, executor=executor)


REGISTRY = Registry()  # the one instance (named for users by forcenet.registry; the models' engines register in it)
