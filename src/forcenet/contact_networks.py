"""The front door for any contact network: :func:`network` and its plan :func:`network_plan` (thesis Sec. 2.3).

``forcenet.network(source, exact=True, moments=2)`` computes what
``forcenet network FILE --exact --moments 2`` prints: the exact mean and
second moment of every contact force of the force network ensemble on the
user's contact network (the uniform measure on the polytope of balanced,
repulsive force networks), through Normaliz; ``samples=K, seed=S`` samples
the same ensemble by hit-and-run and gives means with error bars from the
integrated autocorrelation time.  ``source`` is a
:class:`~forcenet.exact.contact_network.model.ContactNetwork` (see
:func:`contact_network`, ``from_networkx``, ``read_csv``), a JSON file's path or
the JSON document as a dict.

The request is checked once, when it is built (:func:`network_plan`): the
network's own refusals (not balanced, infeasible, unbounded: one line each,
by linear programming) come first, before any work; the engines of the
``"contact-network"`` model in :data:`forcenet.registry.REGISTRY` plan it
(``auto``: the faster exact route) and run it as planned.

Examples
--------
>>> import forcenet
>>> net = forcenet.contact_network(1, [[0, None, "-3/5", "-4/5"], [0, None, "3/5", "-4/5"], [0, None, 0, -1]],
...                                [[0, 0, -1]])
>>> p = forcenet.network_plan(net, exact=True, moments=2)
>>> p.runnable, p.methods
(True, ('triangulation',))
>>> [str(x) for x in p.run().exact_second]
['25/192', '25/192', '1/3']
"""

from __future__ import annotations

import json
import os
from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path
from typing import Any, ClassVar

from forcenet.contact_network_results import NetworkResult
from forcenet.core.atomic_files import check_directory
from forcenet.core.errors import ArgumentError, ArgumentTypeError
from forcenet.core.plan import Plan, combine
from forcenet.core.validation import check_int, check_seed
from forcenet.costed_plans import CostedPlan, Progress
from forcenet.exact.contact_network import polytope as polytope_module
from forcenet.exact.contact_network import triangulation_moments
from forcenet.exact.contact_network.model import ContactNetwork, contact_network, parse_json, read_json
from forcenet.exact.contact_network.number_field import NO_DENSITY_IN_FIELD, in_number_field
from forcenet.registry import REGISTRY

__all__ = ["network", "network_plan", "NetworkPlan", "NetworkRequest", "NetworkResult", "ContactNetwork",
           "contact_network", "network_response"]

EXACT_METHODS = ("auto", "triangulation", "volumes")


@dataclass(frozen=True)
class NetworkRequest:
    """One checked request on a contact network (immutable; the engines trust it).

    Attributes
    ----------
    network : ContactNetwork
    quantity : {"exact-moments", "sampled-moments"}
    moments : int
        1 (means) or 2 (and second moments).
    samples : int
        Recorded sweeps of the sampler (0 for the exact route).
    seed : int or None
    burn_in : int or None
    thin : int
        Sweeps between two recorded samples.
    chains : int
        Independent chains (run in worker processes, or on ``executor``), pooled.
    method : str
        An engine's name or ``"auto"``.
    checkpoint : str or None
        A checked directory recording the sampler's finished blocks (one chain) or chains (several).
    density : tuple of int
        Variables whose exact density the exact route computes too (piecewise polynomials).
    """

    network: ContactNetwork
    quantity: str
    moments: int = 1
    samples: int = 0
    seed: int | None = None
    burn_in: int | None = None
    method: str = "auto"
    thin: int = 1
    chains: int = 1
    checkpoint: str | None = None
    density: tuple[int, ...] = ()
    model: ClassVar[str] = "contact-network"

    @cached_property
    def balance(self) -> Any:
        """The balance equations (:func:`forcenet.exact.contact_network.polytope.balance`), made once."""
        return polytope_module.balance(self.network)

    @cached_property
    def polytope(self) -> Any:
        """The exact polytope (:func:`forcenet.exact.contact_network.polytope.exact_polytope`), made once."""
        return polytope_module.exact_polytope(self.network, self.balance)

    @cached_property
    def facts(self) -> tuple[int, int, int]:
        """``(dimension, vertices, facets)`` of the polytope (Normaliz), made once."""
        return triangulation_moments.polytope_facts(self.polytope)


def _network(source: Any) -> ContactNetwork:
    if isinstance(source, ContactNetwork):
        return source
    if isinstance(source, (str, os.PathLike)):
        return read_json(Path(source))
    if isinstance(source, dict):
        return parse_json(json.dumps(source, default=str), "the network")
    raise ArgumentTypeError(f"network={type(source).__name__}: give a ContactNetwork (forcenet.contact_network), "
                            "a JSON file's path or its dict")


@dataclass(frozen=True)
class NetworkPlan(CostedPlan):
    """A checked request on a contact network with its engines and cost: what :func:`network_plan` returns.

    Parameters
    ----------
    exact, sampled : NetworkRequest or None
        The exact and the sampled request (None: not asked for).
    engines : tuple
        The engines that will run, exact first (``forcenet.core.registry.Engine`` objects).
    plans : tuple of Plan
        Each engine's plan.
    cost : Plan
        The whole run's cost (or its refusal).
    start : optional
        The sampler's starting point (a strictly feasible force network), found with the refusals.
    executor : concurrent.futures.Executor, optional
        Where independent chains run.

    Examples
    --------
    >>> import forcenet
    >>> from forcenet.exact.contact_network.geometries import triangle
    >>> p = forcenet.network_plan(triangle(4).network, exact=True, samples=200, seed=1)
    >>> p.methods, p.runnable
    (('triangulation', 'hit-and-run'), True)
    """

    exact: NetworkRequest | None
    sampled: NetworkRequest | None
    engines: tuple[Any, ...]
    plans: tuple[Plan, ...]
    cost: Plan
    start: Any = field(default=None, repr=False)
    executor: Any = field(default=None, repr=False)

    @property
    def methods(self) -> tuple[str, ...]:
        """The engines that will run, in order (exact first).

        Examples
        --------
        >>> import forcenet
        >>> from forcenet.exact.contact_network.geometries import triangle
        >>> forcenet.network_plan(triangle(3).network, exact=True).methods
        ('triangulation',)
        """
        return tuple(engine.name for engine in self.engines)

    def check(self) -> NetworkPlan:
        """The plan itself when it runs; else :class:`~forcenet.core.errors.ArgumentError` with its refusal.

        Returns
        -------
        NetworkPlan
            This plan.

        Raises
        ------
        ArgumentError
            The plan's refusal.

        Examples
        --------
        >>> import forcenet
        >>> from forcenet.exact.contact_network.geometries import triangle
        >>> forcenet.network_plan(triangle(3).network, exact=True).check().runnable
        True
        """
        self.cost.check()
        return self

    def run(self, progress: Progress | bool | None = None) -> NetworkResult:
        """Compute as planned (the plan is not made again).

        Parameters
        ----------
        progress : callable, bool or None
            ``progress(k)`` per recorded sweep; ``True``: a progress bar.

        Returns
        -------
        NetworkResult

        Examples
        --------
        >>> import forcenet
        >>> net = forcenet.contact_network(1, [[0, None, 0, -1]], [[0, 0, -1]])
        >>> forcenet.network_plan(net).run().exact_mean
        (1,)
        """
        self.check()
        result: dict[str, Any] = {}
        dimension = 0
        with self._ticks(progress, "network") as tick:
            for engine, plan, request in zip(self.engines, self.plans, (r for r in (self.exact, self.sampled) if r)):
                if request.quantity == "exact-moments":
                    moments = engine.run(request, plan, progress=None)
                    dimension = moments.dimension
                    result["exact_mean"] = moments.mean
                    result["exact_second"] = moments.second or None
                    if moments.densities is not None:
                        result["exact_density"] = tuple(moments.densities.items())
                else:
                    chain, dimension = engine.run(request, plan, progress=tick, executor=self.executor)
                    mean, error, tau = chain.statistics()
                    result.update(sampled_mean=mean, sampled_error=error, tau=tau, samples=chain.samples)
                    if request.moments >= 2:
                        result["sampled_second"], result["second_error"] = chain.second_moments()
        network = (self.exact or self.sampled).network  # type: ignore[union-attr]
        labels = (self.exact or self.sampled).balance.labels  # type: ignore[union-attr]
        return NetworkResult(network, labels, dimension, methods=self.methods, **result)


def network_plan(source: Any, *, exact: bool | None = None, moments: int = 1, samples: int | None = None,
                 seed: int | None = None, burn_in: int | None = None, method: str = "auto",
                 thin: int = 1, chains: int = 1, executor: Any = None,
                 checkpoint: str | os.PathLike[str] | None = None, density: Any = None) -> NetworkPlan:
    """Check a request on a contact network once and plan it (the exact route, the sampler, or both).

    Parameters
    ----------
    source : ContactNetwork, path or dict
        The network (a JSON file's path or document: ``{"grains": n, "contacts": [[i, j, "nx", "ny"], ...],
        "loads": [[g, "fx", "fy"], ...]}``).
    exact : bool, optional
        The exact moments through Normaliz (default: True unless ``samples`` is given).
    moments : int
        1 (means) or 2 (and second moments).
    samples : int, optional
        Recorded hit-and-run sweeps (``>= 2``).
    seed : int, optional
        The sampler's seed.
    burn_in : int, optional
        Sweeps discarded first (default ``max(100, samples / 10)``).
    method : {"auto", "triangulation", "volumes"}
        The exact route.
    thin : int
        Sweeps between two recorded samples (default 1; large networks: memory is ``samples * contacts``).
    chains : int
        Independent chains sharing the samples (default 1), each in a worker process (or on ``executor``);
        their statistics are pooled.
    executor : concurrent.futures.Executor or Dask Client, optional
        Where the chains run (default: a local process pool when ``chains > 1``).
    checkpoint : str or os.PathLike, optional
        A directory recording the sampler's finished blocks (or chains, with ``chains > 1``); the same request
        run again (after Ctrl-C, a crash) resumes there and gives the same samples as an uninterrupted run.
    density : bool or list of int, optional
        With the exact route: the exact density of these contacts' normal forces (``True``: every contact whose
        force is not fixed by balance alone), a piecewise polynomial read off the triangulation.

    Returns
    -------
    NetworkPlan

    Raises
    ------
    ArgumentError
        A bad network (one line: not balanced, infeasible, unbounded, ...) or argument.

    Examples
    --------
    >>> import forcenet
    >>> net = forcenet.contact_network(1, [[0, None, 0, 1]], [[0, 0, -1]])
    >>> forcenet.network_plan(net)
    Traceback (most recent call last):
    ...
    forcenet.core.errors.ArgumentError: infeasible: no network of repulsive contact forces balances these loads (a load pulls a grain away from its contacts, i.e. a tensile load?); the sampler and the exact route need one
    """
    net = _network(source)
    moments = check_int(moments, "moments", 1, 2)
    if samples is not None:
        samples = check_int(samples, "samples", 2)
    if burn_in is not None:
        burn_in = check_int(burn_in, "burn_in", 0)
    thin = check_int(thin, "thin", 1)
    chains = check_int(chains, "chains", 1, samples if samples is not None else 1)
    seed = None if seed is None else int(check_seed(seed))
    directory = None if checkpoint is None else check_directory(checkpoint, "checkpoint")
    if method not in EXACT_METHODS:
        raise ArgumentError(f"method={method!r} is out of range: method must be one of {', '.join(EXACT_METHODS)}",
                            argument="method")
    exact = samples is None if exact is None else bool(exact)
    if not exact and samples is None:
        raise ArgumentError("nothing to compute: ask for the exact moments (exact=True, --exact) or samples "
                            "(samples=K, --samples K)")
    start, _ = polytope_module.check_polytope(net)  # the network's refusals, before any work
    variables = _density_variables(net, density, exact)
    requests = []
    if exact:
        requests.append(NetworkRequest(net, "exact-moments", moments, method=method, density=variables))
    if samples is not None:
        requests.append(NetworkRequest(net, "sampled-moments", moments, samples, seed, burn_in, thin=thin,
                                       chains=chains, checkpoint=directory))
    chosen = [REGISTRY.choose(request) for request in requests]
    engines = tuple(engine for engine, _ in chosen)
    plans = tuple(plan for _, plan in chosen)
    cost = combine("; ".join(plan.what for plan in plans), plans, plans[-1].unit)
    return NetworkPlan(requests[0] if exact else None, requests[-1] if samples is not None else None, engines, plans,
                       cost, start, executor)


def _density_variables(net: ContactNetwork, density: Any, exact: bool) -> tuple[int, ...]:
    """The variables (normal forces ``f{c}``) whose exact density is asked for, checked once."""
    if density is None or density is False:
        return ()
    if not exact:
        raise ArgumentError("density needs the exact route: exact=True (--exact) with density (--density)",
                            argument="density")
    bal = polytope_module.balance(net)
    labels = bal.labels
    if density is True:
        try:
            poly = polytope_module.exact_polytope(net)
        except polytope_module.IrrationalDataError:
            if not net.exact or not in_number_field(bal):
                raise
            raise ArgumentError(NO_DENSITY_IN_FIELD + "sample it (--samples K)", argument="density") from None
        return tuple(labels.index(f"f{c}") for c in range(len(net.contacts))
                     if poly.dimension and any(poly.K[labels.index(f"f{c}")]))
    if isinstance(density, (str, bytes)) or not hasattr(density, "__iter__"):
        raise ArgumentTypeError(f"density={density!r}: give True or a list of contact indices")
    return tuple(labels.index(f"f{check_int(c, 'density', 0, len(net.contacts) - 1)}") for c in density)


def network(source: Any, *, exact: bool | None = None, moments: int = 1, samples: int | None = None,
            seed: int | None = None, burn_in: int | None = None, method: str = "auto", thin: int = 1,
            chains: int = 1, executor: Any = None, checkpoint: str | os.PathLike[str] | None = None,
            density: Any = None, progress: Progress | bool | None = None) -> NetworkResult:
    """Every contact force's moments over the force network ensemble of a contact network (Sec. 2.3).

    ``network_plan(...)`` then ``.run(progress)``.

    Parameters
    ----------
    source : ContactNetwork, path or dict
        The network.
    exact, moments, samples, seed, burn_in, method, thin, chains, executor, checkpoint, density
        As :func:`network_plan`.
    progress : callable, bool or None
        ``progress(k)`` per recorded sweep; ``True``: a progress bar.

    Returns
    -------
    NetworkResult
        Exact values (sympy numbers), sampled ones with error bars, renderings (``to_json``, ``to_csv``,
        ``to_text``), ``force_distribution``.

    Raises
    ------
    ArgumentError
        As :func:`network_plan`, or a refused plan.

    Examples
    --------
    >>> import forcenet
    >>> from forcenet.exact.contact_network.geometries import triangle
    >>> r = forcenet.network(triangle(3).network, exact=True)
    >>> r.dimension, str(r.exact_mean[0])
    (3, 'sqrt(3)/3')
    """
    return network_plan(source, exact=exact, moments=moments, samples=samples, seed=seed, burn_in=burn_in,
                        method=method, thin=thin, chains=chains, executor=executor,
                        checkpoint=checkpoint, density=density).run(progress)


def network_response(source: Any, grain: int, load: tuple[Any, Any] = (0, -1), **options: Any) -> tuple[Any, ...]:
    """The response: every force's mean with an extra load on ``grain`` minus without (thesis Ch. 3, Sec. 5.3).

    Parameters
    ----------
    source : ContactNetwork, path or dict
    grain : int
        The grain that carries the overload.
    load : (fx, fy)
        The overload (default ``(0, -1)``, a unit downward force).
    **options
        As :func:`network` (``exact=True``, or ``samples=K, seed=S``).

    Returns
    -------
    tuple
        Per variable the difference of the means (exact, or floats for samples).

    Raises
    ------
    ArgumentError
        A grain out of range, or either network refused (see :func:`network_plan`).

    Examples
    --------
    >>> import forcenet
    >>> net = forcenet.contact_network(1, [[0, None, "-3/5", "-4/5"], [0, None, "3/5", "-4/5"]], [[0, 0, -1]])
    >>> [str(x) for x in network_response(net, 0, (0, -1), exact=True)]
    ['5/8', '5/8']
    """
    net = _network(source)
    check_int(grain, "grain", 0, net.grains - 1)
    loads = [[g, *load_g] for g, load_g in enumerate(net.loads)] + [[grain, load[0], load[1], 0]]
    loaded = contact_network(net.grains, net.contacts, loads, friction=net.friction, radii=net.radii,
                             positions=net.positions)
    with_load = network(loaded, **options)
    without = network(net, **options)
    if with_load.exact_mean is not None and without.exact_mean is not None:
        return tuple(a - b for a, b in zip(with_load.exact_mean, without.exact_mean))
    return tuple(float(a - b) for a, b in zip(with_load.sampled_mean, without.sampled_mean))  # type: ignore[arg-type]
