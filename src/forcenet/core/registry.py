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
first use, so ``import forcenet`` stays light); nothing else of the house
changes.  ``method="auto"`` chooses the fastest runnable engine by the
engines' own plans (:meth:`Registry.choose`).

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
from typing import Any, Protocol, runtime_checkable

from .errors import ArgumentError, ArgumentTypeError
from .plan import Plan

__all__ = ["Engine", "Registry", "AUTO"]

AUTO = "auto"


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

    def _load(self, model: str) -> None:
        for module in self._loaders.pop(model, []):
            importlib.import_module(module)

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

    def choose(self, request: Any) -> tuple[Engine, Plan]:
        """The engine and its plan for a checked ``request`` (``model``, ``quantity``, ``method``).

        ``method="auto"``: every engine's plan, the fastest runnable one; if none runs, the first refusal
        (the engines' registration order) with the others' reasons. A named method: its plan as it is
        (possibly refused: the caller decides whether to raise or announce).
        """
        if request.method != AUTO:
            engine = self.engine(request.model, request.quantity, request.method)
            return engine, engine.plan(request)
        names = self.methods(request.model, request.quantity)
        if not names:
            raise ArgumentError(f"no engine computes {request.quantity!r} for model {request.model!r}")
        engines = self._engines[(request.model, request.quantity)]
        plans = [(engines[name], engines[name].plan(request)) for name in names]
        runnable = [pair for pair in plans if pair[1].runnable]
        if runnable:
            return min(runnable, key=lambda pair: pair[1].seconds)
        return plans[0]

    def run(self, request: Any, *, progress: Callable[..., Any] | None = None,
            executor: Executor | None = None) -> Any:
        """Choose, check the plan (:meth:`~forcenet.core.plan.Plan.check`) and run."""
        engine, plan = self.choose(request)
        return engine.run(request, plan.check(), progress=progress, executor=executor)
