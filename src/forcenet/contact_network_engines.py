"""The contact-network model's engines (:class:`forcenet.core.registry.Engine`), registered in ``REGISTRY``.

Model ``"contact-network"``; quantities ``"exact-moments"`` (every force's
exact ``<f>`` and ``<f^2>``: ``triangulation``, ``volumes``, both through
Normaliz, :mod:`forcenet.exact.contact_network.triangulation_moments`; a
network in ``Q(sqrt(3))`` that no rescaling makes rational goes to the
triangulation over that number field,
:mod:`forcenet.exact.contact_network.number_field`) and
``"sampled-moments"`` (``hit-and-run``, the uniform sampler of
:mod:`forcenet.numeric.contact_network.hit_and_run`).  Imported by the
registry on the first request for the model (``REGISTRY.add_loader``).

The cost models are measured on the 2-core reference machine: Normaliz's
triangulation of the triangle's polytope (d = 21, 77 forces) with the
moments takes about 1 s, d = 15 about 0.1 s; a volume about 0.1 s at
d = 21. Beyond ``MAX_EXACT_DIMENSION`` the exact routes refuse and name
``--samples``.

Examples
--------
>>> from forcenet.registry import REGISTRY
>>> REGISTRY.methods("contact-network", "exact-moments")
('triangulation', 'volumes')
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Callable
from concurrent.futures import Executor
from dataclasses import replace
from functools import lru_cache
from typing import Any

from forcenet.core.errors import ArgumentError
from forcenet.core.plan import Plan, with_compilation
from forcenet.exact.contact_network.marginal_density import force_densities
from forcenet.exact.contact_network.number_field import (
    NO_DENSITY_IN_FIELD,
    FieldPolytope,
    field_facts,
    field_polytope,
    in_number_field,
    moments_in_number_field,
    number_field_seconds,
)
from forcenet.exact.contact_network.polytope import IrrationalDataError
from forcenet.exact.contact_network.triangulation_moments import (
    moments_by_triangulation,
    moments_by_volumes,
    triangulation,
)
from forcenet.numeric.contact_network.hit_and_run import (
    BASIS_COPIES,
    HitAndRun,
    hit_and_run_sweeps,
    rounding_seconds,
    route_for,
    run_chains,
    setup_seconds,
    sweep_seconds,
)
from forcenet.registry import REGISTRY

__all__ = ["MODEL", "MAX_EXACT_DIMENSION", "TriangulationEngine", "VolumesEngine", "HitAndRunEngine",
           "triangulation_seconds", "volume_seconds", "exact_or_field_polytope"]

MODEL = "contact-network"
MAX_EXACT_DIMENSION = 26  # beyond it a triangulation's size is out of reach (sampling has no such limit)
COMPILE_SECONDS = 3.0  # the hit-and-run kernel's first compilation (measured: 2-3 s)
# seconds of one call of the compiled sweeps from Python (numba's dispatch: typing the arguments, the Generator's
# the dearest): 1.3e-5 CPU s measured on the triangle N = 5 when it was called per recorded sample (200000
# samples in 2.9 s); now once per chunk, except on the sparse route (per recorded sample and batch)
KERNEL_CALL_SECONDS = 1.2e-5
_FIX = "sample it instead (--samples K, or samples=K)"


def triangulation_seconds(dimension: int, variables: int, vertices: int = 0) -> float:
    """Estimated seconds of the triangulation route: a rough model of two measured families, the triangle's
    order polytopes (few vertices: d = 21, 64 vertices, 77 forces, ~1 s) and the snooker's (many: d = 6, 68
    vertices, 0.04 s; d = 10, 1505 vertices, Normaliz not done after 2 minutes), ``~ 2^(0.55 d)`` per force plus
    ``~ vertices^3``.

    Examples
    --------
    >>> triangulation_seconds(21, 77, 64) < 5, triangulation_seconds(10, 75, 1505) > 60
    (True, True)
    """
    return 0.05 + 3e-6 * variables * 2 ** (0.55 * dimension) + 1e-7 * vertices**3


def volume_seconds(dimension: int, variables: int, moments: int, vertices: int = 0) -> float:
    """Estimated seconds of the volume route (``1 + moments * variables`` Normaliz volumes; one volume of the
    snooker's d = 10 polytope with 1505 vertices took 60 s on the loaded machine).

    Examples
    --------
    >>> volume_seconds(21, 77, 2, 64) > triangulation_seconds(21, 77, 64)
    True
    """
    return (1 + moments * variables) * (0.01 + 3e-5 * 2 ** (0.5 * dimension) + 2e-8 * vertices**3)


@lru_cache(maxsize=8)
def _field_polytope(network: Any) -> FieldPolytope:
    """The network's polytope over ``Q(sqrt(3))``, made once for the plan and the run."""
    return field_polytope(network)


def exact_or_field_polytope(request: Any) -> Any:
    """The request's exact polytope: rational after rescaling (:func:`~forcenet.exact.contact_network.polytope.
    exact_polytope`), else, when every number of its balance lies in ``Q(sqrt(3))``, over that number field
    (:mod:`forcenet.exact.contact_network.number_field`); otherwise the rational route's refusal (naming
    ``--samples``).

    Examples
    --------
    >>> import forcenet
    >>> net = forcenet.contact_network(1, [[0, None, "-1/2", "-sqrt(3)/2"], [0, None, "3/5", "-4/5"],
    ...                                    [0, None, 0, -1]], [[0, 0, -1]])
    >>> type(exact_or_field_polytope(forcenet.network_plan(net).exact)).__name__
    'FieldPolytope'
    """
    try:
        return request.polytope
    except IrrationalDataError:  # only this refusal: unbalanced loads, say, stay refused as they are
        if not request.network.exact or not in_number_field(request.balance):
            raise
    least = request.balance.variables - request.balance.rows  # dim Ker A >= unknowns - equations
    if least > MAX_EXACT_DIMENSION:  # before the field's row reduction (sympy: 5 s at 1161 unknowns, ~n^2)
        raise ArgumentError(f"the polytope has dimension at least {least}, beyond the exact route's "
                            f"{MAX_EXACT_DIMENSION}: {_FIX}")
    return _field_polytope(request.network)


def _exact_plan(request: Any, name: str) -> tuple[Any, Plan | None]:
    """The exact polytope of the request (rational, or over ``Q(sqrt(3))``), or a refused plan (floats,
    irrational mixtures outside ``Q(sqrt(3))``, too large)."""
    what = f"exact moments of {request.network.grains} grains ({name})"
    try:
        import PyNormaliz  # noqa: F401  (its presence is the question)
    except ImportError:
        return None, Plan(what, 0, refusal="the exact route needs Normaliz: pip install 'forcenet[networks]' "
                                           f"(pynormaliz); or {_FIX}")
    try:
        poly = exact_or_field_polytope(request)
    except ArgumentError as exc:
        return None, Plan(what, 0, refusal=str(exc))
    if poly.dimension > MAX_EXACT_DIMENSION:
        return None, Plan(what, 0, refusal=f"the polytope has dimension {poly.dimension}, beyond the exact "
                                           f"route's {MAX_EXACT_DIMENSION}: {_FIX}")
    return poly, None


def _vertices(request: Any, poly: Any) -> int:
    """The polytope's vertex count (Normaliz, exact; refuses an empty or unbounded polytope), asked once."""
    if isinstance(poly, FieldPolytope):
        return field_facts(poly)[1]
    return int(request.facts[1])


class _ExactMomentsEngine(ABC):
    """What the two exact engines share: the model, the quantity, and the plan's refusals before the cost (no
    Normaliz, no exact polytope, a dimension beyond the route) and the vertex count the cost is priced by."""

    name = ""
    model = MODEL
    quantities = frozenset({"exact-moments"})

    def plan(self, request: Any) -> Plan:
        poly, refused = _exact_plan(request, self.name)
        if refused is not None:
            return refused
        return self._refusal(request, poly) or self._cost(request, poly, _vertices(request, poly))

    def _refusal(self, request: Any, poly: Any) -> Plan | None:
        """A refusal of this engine's own, decided before Normaliz is asked for the vertices (None: none)."""
        return None

    @abstractmethod
    def _cost(self, request: Any, poly: Any, vertices: int) -> Plan:
        """The engine's plan for the checked polytope with ``vertices`` vertices: each prices its own algorithm."""


class TriangulationEngine(_ExactMomentsEngine):
    """Exact moments from Normaliz's triangulation and the simplex formulas (every force, one pass).

    Examples
    --------
    >>> TriangulationEngine().name
    'triangulation'
    """

    name = "triangulation"

    def _refusal(self, request: Any, poly: Any) -> Plan | None:
        if not request.density or not isinstance(poly, FieldPolytope):
            return None
        return Plan("exact moments (triangulation)", 0, refusal=NO_DENSITY_IN_FIELD + _FIX)

    def _cost(self, request: Any, poly: Any, vertices: int) -> Plan:
        if isinstance(poly, FieldPolytope):  # no rescaling makes it rational: Normaliz over Q(sqrt(3))
            return Plan(f"exact moments, dimension {poly.dimension}, {vertices} vertices (Normaliz triangulation "
                        "over Q(sqrt(3)))", number_field_seconds(len(poly.z0), vertices), ticks=0, unit="simplex")
        seconds = triangulation_seconds(poly.dimension, len(poly.z0), vertices)
        return Plan(f"exact moments, dimension {poly.dimension}, {vertices} vertices (Normaliz triangulation)",
                    seconds, ticks=0, unit="simplex")

    def run(self, request: Any, plan: Plan, *, progress: Callable[..., Any] | None = None,
            executor: Executor | None = None) -> Any:
        poly = exact_or_field_polytope(request)
        if isinstance(poly, FieldPolytope):
            return moments_in_number_field(request.network, request.moments, poly)
        if not request.density:
            return moments_by_triangulation(request.polytope, request.moments)
        # one triangulation for the moments and the densities (piecewise polynomials, marginal_density)
        tri = triangulation(request.polytope)
        densities = force_densities(request.polytope, list(request.density), tri)
        return replace(moments_by_triangulation(request.polytope, request.moments, tri=tri), densities=densities)


class VolumesEngine(_ExactMomentsEngine):
    """Exact moments as ratios of Normaliz volumes of lifted polytopes (normal forces only).

    Examples
    --------
    >>> VolumesEngine().quantities
    frozenset({'exact-moments'})
    """

    name = "volumes"

    def _refusal(self, request: Any, poly: Any) -> Plan | None:
        if isinstance(poly, FieldPolytope):
            return Plan("exact moments (volumes)", 0, refusal="method='volumes' needs data that are rational once "
                        "rescaled (Normaliz computes no volume over Q(sqrt(3))): use method='triangulation'")
        if request.density:
            return Plan("exact moments (volumes)", 0, refusal="the exact density (--density) is read off the "
                        "triangulation: use method='triangulation' (--method triangulation)")
        if not request.network.frictional:
            return None
        return Plan("exact moments (volumes)", 0, refusal="method='volumes' needs forces that are never "
                    "negative; a tangential force is not: use method='triangulation'")

    def _cost(self, request: Any, poly: Any, vertices: int) -> Plan:
        seconds = volume_seconds(poly.dimension, len(poly.z0), request.moments, vertices)
        return Plan(f"exact moments, dimension {poly.dimension}, {vertices} vertices (Normaliz volumes)", seconds,
                    ticks=len(poly.z0), unit="force")

    def run(self, request: Any, plan: Plan, *, progress: Callable[..., Any] | None = None,
            executor: Executor | None = None) -> Any:
        return moments_by_volumes(request.polytope, request.moments, progress=progress)


class HitAndRunEngine:
    """Uniform samples by coordinate hit-and-run (compiled), error bars from autocorrelation times.

    Examples
    --------
    >>> HitAndRunEngine().quantities
    frozenset({'sampled-moments'})
    """

    name = "hit-and-run"
    model = MODEL
    quantities = frozenset({"sampled-moments"})

    def plan(self, request: Any) -> Plan:
        bal = request.balance
        rows, m = bal.rows, bal.variables
        dimension = max(1, m - min(rows, m))  # a bound; the walk computes the kernel exactly
        recorded = request.samples * request.thin
        sweeps = recorded + (request.burn_in if request.burn_in is not None else max(100, recorded // 10))
        inequalities = bal.inequalities if request.network.frictional else 0
        parallel = min(request.chains, 2)  # the reference machine's cores
        route = route_for(m, dimension)
        per = sweep_seconds(dimension, m, inequalities, route == "sparse")
        setup = setup_seconds(rows, m, dimension)  # this process's walk, and each chain's when chains > 1
        # every chain rounds its own basis during its burn-in (not on the sparse route: no basis to round)
        rounding = 0.0 if route == "sparse" else request.chains * rounding_seconds(dimension, m, per)
        # the compiled sweeps are called once per chunk of recorded samples; the sparse route calls them per
        # recorded sample and batch of directions (twice when thinned)
        calls = request.samples * (1 if request.thin == 1 else 2) if route == "sparse" else 0
        seconds = (setup * (1 if request.chains == 1 else 2)
                   + (rounding + sweeps * per + calls * KERNEL_CALL_SECONDS) / parallel)
        basis = 0 if route == "sparse" else BASIS_COPIES * dimension  # the walk's basis-sized arrays at the peak
        nbytes = 8 * m * (request.samples * 4 + basis + rows)
        plan = Plan(f"{sweeps} hit-and-run sweeps on {request.network.grains} grains", seconds, nbytes,
                    ticks=request.samples, unit="sample")
        return with_compilation(plan, "hit-and-run", COMPILE_SECONDS, [hit_and_run_sweeps])

    def run(self, request: Any, plan: Plan, *, progress: Callable[..., Any] | None = None,
            executor: Executor | None = None) -> Any:
        walk = HitAndRun(request.network, request.balance)
        if request.chains == 1 and executor is None:
            chain = walk.run(request.samples, request.seed, request.burn_in, progress=progress, thin=request.thin,
                             checkpoint=request.checkpoint)
        else:  # independent chains in worker processes (or on a Dask cluster), pooled
            chain = run_chains(request.network, request.samples, request.seed, request.burn_in, request.thin,
                               request.chains, executor, progress, checkpoint=request.checkpoint, fixed=walk.fixed)
        return chain, walk.dimension


REGISTRY.register(TriangulationEngine())
REGISTRY.register(VolumesEngine())
REGISTRY.register(HitAndRunEngine())
