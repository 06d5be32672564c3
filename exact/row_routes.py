"""One row of the triangle's moment tables (``forcenet table --row i``): the row's own engines and its policy.

A row request (:class:`~forcenet.exact.protocol.TableRequest` with ``row``)
has routes of its own, each an engine of model ``"triangle"`` and quantity
``"row"``: ``apex`` (row 1, ``W_11 = 1``), ``covers`` (the one-time cover
identity for the rows ``2``, ``3``, ``N - 1``: ``<W^2>`` for the price of
the mean, :mod:`.triangle.free_fermion.covers`), ``lattice`` (row 2, both
loads lattice directions: every moment), ``layers`` / ``floor`` (every load
of one layer by de Bruijn Pfaffians, every moment); beside them every table
method's whole table, one row kept (the table engines serve ``"row"`` too).

:func:`row_policy` is the registry's choice for a row (registered by
:mod:`forcenet.exact.routes`): ``method="pfaffian"`` (or ``"auto"``) lets the
row's routes compete by their plans, ``auto`` adding the fastest other
method's whole table; any other method computes its whole table and keeps
the row.

Examples
--------
>>> from forcenet.exact.protocol import check_table_request
>>> COVERS.plan(check_table_request(40, 2, row=39)).runnable
True
>>> [str(x) for x in LAYERS.run(check_table_request(5, 2, row=4), LAYERS.plan(check_table_request(5, 2, row=4)))[2]]
['1/22', '4/33', '4/33', '1/22']
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from concurrent.futures import Executor
from dataclasses import replace
from fractions import Fraction
from typing import Any, ClassVar

from forcenet.core.plan import Plan
from forcenet.core.registry import Decision, Registry

from .protocol import Progress, TableRequest
from .triangle.de_bruijn.floor import MAX_FLOOR_N, floor_cost
from .triangle.de_bruijn.layers import layer_cost
from .triangle.distribution import moment_from_gaps
from .triangle.free_fermion.covers import cover_row_cost, cover_row_moments, one_time_rows
from .triangle.free_fermion.fluctuations import grain_gap_law, lattice_gap_laws_cost
from .triangle.pfaffian_table import every_load_gap_law

__all__ = ["ROW_ROUTES", "ROW_PRIME_ROUTES", "ROW_LAYER_ROUTES", "RowEngine", "APEX", "COVERS", "LATTICE", "LAYERS", "FLOOR",
           "ROW_ENGINES", "row_policy"]

ROW_ROUTES = ("apex", "covers", "lattice", "layers", "floor")  # beside them, a table method's whole table
ROW_PRIME_ROUTES = ("covers", "layers", "floor", "pfaffian")  # the row's routes over primes: executor=, checkpoint=
ROW_LAYER_ROUTES = ("layers", "floor")  # a checkpoint directory holds one request per layer

Rows = dict[int, list[Fraction]]


def _what(request: TableRequest) -> str:
    return f"row {request.row} of <W^s>, s <= {request.moments}, N={request.N}"


class RowEngine(ABC):
    """A route to one row of the ``<W^s>`` tables (an engine of model ``"triangle"``, quantity ``"row"``); the
    request is checked (its ``row`` in ``1..N``) and trusted."""

    name: str
    model: str = "triangle"
    quantities: frozenset[str] = frozenset({"row"})
    options: frozenset[str] = frozenset({"workers", "checkpoint"})

    def __repr__(self) -> str:
        return f"<triangle row engine {self.name!r}>"

    @abstractmethod
    def plan(self, request: TableRequest) -> Plan:
        """The route's cost for the request's row (or its refusal)."""

    @abstractmethod
    def run(self, request: TableRequest, plan: Plan, *, progress: Progress | None = None,
            executor: Executor | None = None) -> Rows:
        """``{s: [<W_(row,j)^s>, j = 1..row]}`` for ``s = 1..moments``, exact."""


class _Apex(RowEngine):
    name = "apex"

    def plan(self, request: TableRequest) -> Plan:
        return Plan(f"{_what(request)} (the apex: W_11 = 1)", 0.0)

    def run(self, request: TableRequest, plan: Plan, *, progress: Progress | None = None,
            executor: Executor | None = None) -> Rows:
        return {s: [Fraction(1)] for s in range(1, request.moments + 1)}


class _Covers(RowEngine):
    name = "covers"

    def plan(self, request: TableRequest) -> Plan:
        options = request.options
        return cover_row_cost(request.N, request.row or 1, memory_bytes=request.memory_bytes,
                              workers=options.get("workers"), executor=request.executor,
                              checkpoint=options.get("checkpoint"))

    def run(self, request: TableRequest, plan: Plan, *, progress: Progress | None = None,
            executor: Executor | None = None) -> Rows:
        found = cover_row_moments(request.N, request.row or 1, progress=progress,
                                  executor=executor or request.executor, **request.options)
        return {s: found[s] for s in range(1, request.moments + 1)}


class _Lattice(RowEngine):
    name = "lattice"
    options = frozenset({"workers"})

    def plan(self, request: TableRequest) -> Plan:
        law = lattice_gap_laws_cost(request.N, request.memory_bytes, request.options.get("workers"), layers=1)
        return replace(law, what=f"{_what(request)} (one-time: the lattice directions' law, Pfaffians)")

    def run(self, request: TableRequest, plan: Plan, *, progress: Progress | None = None,
            executor: Executor | None = None) -> Rows:
        law = grain_gap_law(request.N, (request.row or 1, 1), progress=progress, **request.options)
        return {s: [moment_from_gaps(law, s)] * 2 for s in range(1, request.moments + 1)}


class _Layer(RowEngine):
    """One layer's every load by de Bruijn Pfaffians: ``layers`` above the floor, ``floor`` for row ``N``."""

    floor: ClassVar[bool]

    def plan(self, request: TableRequest) -> Plan:
        N, row, memory_bytes, workers = request.N, request.row or 1, request.memory_bytes, request.options.get("workers")
        if N <= MAX_FLOOR_N:
            plan = floor_cost(N, True, memory_bytes, workers) if self.floor else layer_cost(N, row, True, memory_bytes,
                                                                                             workers)
        else:
            plan = Plan(_what(request), 0, refusal=f"N={N} is out of range for one layer's de Bruijn Pfaffians: N "
                                                   f"must be an integer in 2..{MAX_FLOOR_N}")
        return replace(plan, what=f"{_what(request)} (two-time: layer {row}'s gap laws, de Bruijn Pfaffians)")

    def run(self, request: TableRequest, plan: Plan, *, progress: Progress | None = None,
            executor: Executor | None = None) -> Rows:
        row = request.row or 1
        laws = every_load_gap_law(request.N, row, progress=progress, executor=executor or request.executor,
                                  **request.options)
        return {s: [moment_from_gaps(laws[j], s) for j in range(1, row + 1)] for s in range(1, request.moments + 1)}


class _Layers(_Layer):
    name, floor = "layers", False


class _Floor(_Layer):
    name, floor = "floor", True


APEX, COVERS, LATTICE, LAYERS, FLOOR = _Apex(), _Covers(), _Lattice(), _Layers(), _Floor()
ROW_ENGINES: tuple[RowEngine, ...] = (APEX, COVERS, LATTICE, LAYERS, FLOOR)


def _candidates(registry: Registry, request: TableRequest) -> dict[str, tuple[Any, Plan]]:
    """Every route's engine and plan for the request's row (``auto``: the row's routes and the other tables)."""
    N, moments, row, options = request.N, request.moments, request.row or 1, request.options
    if row == 1:
        return {"apex": (APEX, APEX.plan(request))}
    found: dict[str, tuple[Any, Plan]] = {}
    if moments == 1:  # the mean: one row of the one-time mean table
        pfaffian = registry.engine("triangle", "table", "pfaffian")
        found["pfaffian"] = (pfaffian, pfaffian.table_plan(request))  # type: ignore[attr-defined]
    elif moments == 2 and row in one_time_rows(N):
        found["covers"] = (COVERS, COVERS.plan(request))
    if row == 2 and request.executor is None and options.get("checkpoint") is None:  # both loads: lattice directions
        found["lattice"] = (LATTICE, LATTICE.plan(request))
    layer = FLOOR if row == N else LAYERS
    found[layer.name] = (layer, layer.plan(request))
    if request.method == "auto" and not options:  # the other methods' whole tables, the fastest of them
        others = tuple(m for m in registry.methods("triangle", "table") if m != "pfaffian")
        best = registry.fastest(replace(request, row=None), others)
        if best.plan.runnable:
            found[best.engine.name] = (best.engine, replace(best.plan, what=f"row {row} of the {best.plan.what}"))
    return found


def row_policy(registry: Registry, request: TableRequest) -> Decision:
    """The registry's choice for a checked row request: the fastest runnable route by the plans (ties: the order
    above), or the first route's plan (refused) when none runs; a table method other than ``pfaffian`` is its
    whole table's row.

    Examples
    --------
    >>> from forcenet.registry import REGISTRY
    >>> from forcenet.exact.routes import check_request
    >>> decision = row_policy(REGISTRY, check_request(40, 2, "pfaffian", row=20))
    >>> decision.engine.name, list(decision.plans)
    ('layers', ['layers'])
    """
    if request.method not in ("auto", "pfaffian"):
        engine = registry.engine("triangle", "row", request.method)
        plan = engine.plan(request)
        return Decision(engine, plan, {engine.name: plan}, {})
    found = _candidates(registry, request)
    plans = {name: plan for name, (_, plan) in found.items()}
    runnable = [name for name, plan in plans.items() if plan.runnable]
    best = min(runnable, key=lambda name: plans[name].seconds) if runnable else next(iter(plans))
    return Decision(found[best][0], plans[best], plans, {})
