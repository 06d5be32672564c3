"""The front door for one load's law: its exact density, CDF and moments (:func:`law`), and its plan (:func:`law_plan`).

``forcenet.law(N, (i, j))`` is what ``forcenet dist --N N --grain i,j``
computes, by the same route and to the same bytes: the exact
piecewise-polynomial density and distribution function of the vertical force
``W_ij`` on one grain (Eqs. (4.5)-(4.9)), of a contact force (``contact=``,
Eq. (3.8)), of layer ``i``'s pooled ``P(f)``, ``f = i W_ij`` (``layer=i``),
or of the ensemble's (neither: every grain of layers ``2..N``).
``forcenet.law_plan(...)`` takes the same request and answers what it will
cost, or why it cannot run and what would, without doing the work; a plan
runs as it was checked (:meth:`LawPlan.run`), so a request is validated and
planned once.

The routes and their limits live in the registry :mod:`forcenet.exact.routes`
(its laws section); this module names the request and keeps the answer
together (:class:`Law`), rendered as the command line renders it.

Examples
--------
>>> import forcenet
>>> law = forcenet.law(6, (6, 2))
>>> law.mean, law.method
(Fraction(413, 2288), 'ideals')
>>> p = forcenet.law_plan(40, layer=40)
>>> p.method, p.runnable
('floor', True)
"""

from __future__ import annotations

import os
from concurrent.futures import Executor
from dataclasses import dataclass, field, replace
from typing import Any

from forcenet.core.atomic_files import check_directory
from forcenet.core.checkpoints import run_distrusting
from forcenet.core.errors import ArgumentError
from forcenet.core.plan import Plan
from forcenet.core.validation import available_memory
from forcenet.costed_plans import CostedPlan, Progress
from forcenet.exact.routes import LAW_PRIME_ROUTES, LawRequest, law_checkpoint, law_request, law_resumed
from forcenet.law_results import Law, check_grid
from forcenet.registry import REGISTRY
from forcenet.sampled_comparison import SampledComparisonPlan, comparison_plan

__all__ = ["Law", "LawPlan", "law", "law_plan"]  # Law: forcenet.law_results



@dataclass(frozen=True, repr=False)  # the plan's own words: CostedPlan.__repr__
class LawPlan(CostedPlan):
    """A checked request for one load's law, with its route and cost: what :func:`law_plan` returns.

    Parameters
    ----------
    request : forcenet.exact.routes.LawRequest
        The validated target: ``N``, ``grain``, ``layer``, ``contact``.
    method : str
        The route that runs it (``"ideals"``, ``"pfaffian"``, ``"floor"``, ``"layers"``, ``"pfaffians"``).
    why : str
        Why ``auto`` chose it (empty for an explicit method).
    cost : forcenet.core.plan.Plan
        Estimated seconds, peak bytes, progress ticks, or the refusal.
    executor : concurrent.futures.Executor or Dask Client, optional
        Runs the route's independent primes.
    checkpoint : CheckpointStore or str, optional
        Where the route records finished primes (a directory for the ensemble: one request per layer).
    memory_bytes : int, optional
        The memory the plan was checked against (a cluster's plan is made again within it).

    Examples
    --------
    >>> import forcenet
    >>> p = forcenet.law_plan(12, (12, 6))
    >>> p.method, p.runnable, p.refusal
    ('ideals', True, None)
    """

    request: LawRequest
    method: str
    why: str
    cost: Plan
    executor: Executor | None = field(default=None, repr=False)
    checkpoint: Any = field(default=None, repr=False)
    memory_bytes: int | None = field(default=None, repr=False)  # the memory the plan was checked against

    @property
    def N(self) -> int:
        """Number of layers.

        Examples
        --------
        >>> import forcenet
        >>> forcenet.law_plan(9, layer=4).N
        9
        """
        return self.request.N

    @property
    def over_primes(self) -> bool:
        """True when the route runs over independent primes (it takes ``executor=`` and ``checkpoint=``).

        Examples
        --------
        >>> import forcenet
        >>> forcenet.law_plan(40, layer=40).over_primes, forcenet.law_plan(8, layer=8).over_primes
        (True, False)
        """
        return self.method in LAW_PRIME_ROUTES

    def check_grid(self, K: Any, name: str = "grid") -> int:
        """``K`` checked as the law's grid (:meth:`Law.grid`) before the law is computed: an integer in
        ``1..GRID_MAX`` whose ``K + 1`` exact evaluations, of the degree the request bounds (``d``, Eq. (4.3)),
        are planned within ``GRID_SECONDS``; else refused naming the ``K`` that fits.

        Parameters
        ----------
        K : int
            The grid's intervals (``forcenet dist --grid``), ``K + 1`` points.
        name : str
            How the refusal names ``K`` (``grid`` at the command line).

        Returns
        -------
        int
            The checked ``K``, unchanged.

        Raises
        ------
        ArgumentError
            A grid planned over ``GRID_SECONDS`` (naming the largest ``K`` within it), or ``K`` outside ``1..GRID_MAX``.

        Examples
        --------
        >>> import forcenet
        >>> forcenet.law_plan(6, layer=6).check_grid(50)
        50
        >>> forcenet.law_plan(120, layer=120).check_grid(100)  # doctest: +ELLIPSIS
        Traceback (most recent call last):
        ...
        forcenet.core.errors.ArgumentError: grid=100 is out of range here: 101 exact evaluations of degree 7140 ...
        """
        return check_grid(K, self.request.degree, name)

    def with_options(self, *, executor: Executor | None = None,
                     checkpoint: str | os.PathLike[str] | None = None) -> LawPlan:
        """This plan with a cluster's workers and a checkpoint directory; the route is not chosen again.

        Parameters
        ----------
        executor : concurrent.futures.Executor or Dask Client, optional
            Runs the route's independent primes.
        checkpoint : str or os.PathLike, optional
            A directory where the route records every finished prime (the ensemble: one request per layer).

        Returns
        -------
        LawPlan
            This plan, or a copy with the options (its cost counting the records a directory already holds).

        Raises
        ------
        ArgumentError
            If the route does not run over primes (the order-ideal DP, a lattice direction's Pfaffians).

        Examples
        --------
        >>> import forcenet, tempfile
        >>> p = forcenet.law_plan(40, layer=40).with_options(checkpoint=tempfile.mkdtemp())
        >>> p.checkpoint.request["route"]
        'pfaffian-floor'
        """
        if executor is None and checkpoint is None:
            return self
        if not self.over_primes:
            given = " and ".join(n for n, v in (("executor=", executor), ("checkpoint=", checkpoint)) if v is not None)
            raise ArgumentError(f"{given} applies to the law routes over primes ({', '.join(LAW_PRIME_ROUTES)}); "
                                f"this law runs by {self.method} ({self.describe()}): run it without")
        store = self.checkpoint
        cost = self.cost
        if executor is not None and executor is not self.executor:  # the route's plan on the executor's workers
            again = REGISTRY.decide(self.request._replace(method="auto", memory_bytes=self.memory_bytes,
                                                          executor=executor))
            if again.engine.name == self.method:  # (a cluster slower per task than this machine keeps its plan)
                cost = again.plan
        if checkpoint is not None:
            if self.checkpoint is not None:
                raise ArgumentError(f"checkpoint={checkpoint!r}: this plan keeps its checkpoint already; make the "
                                    "request again with forcenet.law_plan(..., checkpoint=...)")
            checkpoint = check_directory(checkpoint, "checkpoint")  # the one check, as --checkpoint's
            store = law_checkpoint(self.request, self.method, checkpoint)
            cost = law_resumed(cost, self.request, store)
        return replace(self, cost=cost, executor=executor if executor is not None else self.executor,
                       checkpoint=store)

    def run(self, progress: Progress | bool | None = None) -> Law:
        """Compute the law this plan describes (the plan is not made again).

        Parameters
        ----------
        progress : callable, bool or None
            ``progress(k)`` with the plan's ticks as the run goes; ``True``: a progress bar (tqdm).

        Returns
        -------
        Law

        Raises
        ------
        ArgumentError
            If the plan is refused.

        Examples
        --------
        >>> import forcenet
        >>> forcenet.law_plan(4, (4, 2)).run().mean
        Fraction(5, 14)
        """
        self.check()
        engine = REGISTRY.engine("triangle", "law", self.method)
        request = self.request._replace(executor=self.executor, checkpoint=self.checkpoint)
        with self._ticks(progress, f"law N={self.N}") as tick:  # a reused record that fails the route's exact
            found = run_distrusting(self.checkpoint, self.N,      # checks is named, dropped and recomputed
                                    lambda: engine.run(request, self.cost, progress=tick))
        kind = self.request.kind
        pool = "ensemble" if kind == "ensemble" else self.request.layer if kind == "layer" else None
        return Law(self.N, found.quantity, found.variable, found.density, found.cdf, self.method, self.why,
                   found.extra, pool)

    def with_sampled_comparison(self, samples: int = 20000, sweeps: int = 3000, bins: int = 40, f_max: float = 4.0,
                                seed: int = 0) -> SampledComparisonPlan[Law]:
        """This law and its comparison with the exact sampler's and Metropolis's histograms, planned as one run.

        What ``forcenet dist --plot`` announces and runs: the law's cost, then
        both samplers' (:meth:`Law.compare_with_samples`), one progress count.

        Parameters
        ----------
        samples : int
            Independent exact samples, ``>= 2``.
        sweeps : int
            Metropolis sweeps, ``>= 2`` (burn-in ``max(100, sweeps // 10)``).
        bins : int
            Equal bins of ``[0, f_max]``, ``1..1000``.
        f_max : float
            The histograms' range, a finite number ``> 0``.
        seed : int
            Both samplers' seed, ``>= 0``.

        Returns
        -------
        SampledComparisonPlan
            Its ``cost`` (the law's and the samplers'); ``run(progress)`` computes the law and the comparison.

        Raises
        ------
        ArgumentError
            If the law is a grain's or a contact's (not a pooled ``P(f)``), or an argument is out of range.

        Examples
        --------
        >>> import forcenet
        >>> p = forcenet.law_plan(8, layer=8).with_sampled_comparison(samples=1000, sweeps=1000)
        >>> p.cost.ticks == forcenet.law_plan(8, layer=8).cost.ticks + 2000
        True
        """
        kind = self.request.kind
        pool = "ensemble" if kind == "ensemble" else self.request.layer if kind == "layer" else None
        return comparison_plan(self.N, pool, samples=samples, sweeps=sweeps, bins=bins, f_max=f_max, seed=seed,
                               law_plan=self, memory_bytes=self.memory_bytes)


def law_plan(N: int, grain: tuple[int, int] | None = None, *, layer: int | None = None, contact: str | None = None,
             method: str = "auto", executor: Executor | None = None,
             checkpoint: str | os.PathLike[str] | None = None, memory_bytes: int | None = None) -> LawPlan:
    """What :func:`law` will cost for this request, or why it cannot run and what would; nothing is computed.

    Parameters
    ----------
    N : int
        Number of layers of the triangle, ``2..128`` (a contact force: ``2..30``).
    grain : (int, int), optional
        ``(i, j)``, ``2 <= i <= N``, ``1 <= j <= i``: the law of ``W_ij`` (or of its contact force).
    layer : int, optional
        ``i`` in ``2..N``: layer ``i``'s pooled ``P(f)``, ``f = i W_ij``.  Neither ``grain`` nor ``layer``:
        the ensemble's ``P(f)``, every grain of layers ``2..N``.
    contact : {"F1", "F2", "F5", "F6"}, optional
        With ``grain``: that contact force, in units of ``2/sqrt3`` (Eq. (3.8)).
    method : {"auto", "ideals", "pfaffians"}
        ``"auto"`` (the faster runnable route by the plans, the default), ``"ideals"`` (the order-ideal DP,
        ``N <= 30``) or ``"pfaffians"`` (the Pfaffian route: a lattice direction's Pfaffians, de Bruijn
        Pfaffians of the floor, of a layer, of every layer; planned where it is the faster).
    executor : concurrent.futures.Executor or Dask Client, optional
        Runs the de Bruijn routes' independent primes.
    checkpoint : str or os.PathLike, optional
        A directory where those routes record every finished prime; a rerun recomputes only what is missing.
    memory_bytes : int, optional
        Memory the run may use; default: what the machine has available now.

    Returns
    -------
    LawPlan
        The route, its estimated cost, or its refusal naming what would work.

    Raises
    ------
    ArgumentError
        If the request is out of range, or ``executor``/``checkpoint`` is given to a route without primes.

    Examples
    --------
    >>> import forcenet
    >>> forcenet.law_plan(64, (64, 1)).method  # a lattice direction: one-time Pfaffians
    'pfaffian'
    >>> print(forcenet.law_plan(12, (6, 3), contact="F5", method="pfaffians").refusal)  # doctest: +ELLIPSIS
    method='pfaffians' for this law at N=12: no Pfaffian route reaches a contact force; method='auto' runs it by ideals (~...)
    """
    request = law_request(N, grain, layer, contact, method=method, memory_bytes=memory_bytes, executor=executor)
    if request.memory_bytes is None:
        request = request._replace(memory_bytes=available_memory() or 16 * 2**30)
    decision = REGISTRY.decide(request)  # the law's policy: the faster runnable route by the plans
    plan = LawPlan(request, decision.engine.name, decision.why, decision.plan, memory_bytes=request.memory_bytes)
    if not plan.runnable or (executor is None and checkpoint is None):
        return plan
    if not plan.over_primes:
        return plan.with_options(executor=executor, checkpoint=checkpoint)  # refuses them, naming the route
    return replace(plan, executor=executor).with_options(checkpoint=checkpoint)  # planned on its workers above


def law(N: int, grain: tuple[int, int] | None = None, *, layer: int | None = None, contact: str | None = None,
        method: str = "auto", executor: Executor | None = None, checkpoint: str | os.PathLike[str] | None = None,
        progress: Progress | bool | None = None, memory_bytes: int | None = None) -> Law:
    """One load's exact law, as ``forcenet dist`` computes it: density, CDF and moments as exact polynomials.

    The force network ensemble of the fully mobilized triangle (Sec. 4.2) makes
    every force a spacing of sorted uniforms: a grain's ``W_ij`` has a Beta
    mixture density on ``[0, 1]`` (Eqs. (4.5)-(4.9)), a pooled ``P(f)`` a
    piecewise polynomial.  ``method="auto"`` runs the faster route by the
    plans (:func:`law_plan`), the same choice and bytes as the command line.

    Parameters
    ----------
    N : int
        Number of layers, ``2..128`` (a contact force: ``2..30``).
    grain : (int, int), optional
        ``(i, j)``: the law of ``W_ij``, ``i >= 2`` (or, with ``contact``, of its contact force).
    layer : int, optional
        Layer ``i``'s pooled ``P(f)``, ``f = i W_ij``; neither ``grain`` nor ``layer``: the ensemble's.
    contact : {"F1", "F2", "F5", "F6"}, optional
        With ``grain``: that contact force, in units of ``2/sqrt3``.
    method : {"auto", "ideals", "pfaffians"}
        As in :func:`law_plan`.
    executor : concurrent.futures.Executor or Dask Client, optional
        Runs the de Bruijn routes' independent primes.
    checkpoint : str or os.PathLike, optional
        A directory recording every finished prime (resumable runs).
    progress : callable, bool or None
        ``progress(k)`` with the plan's ticks; ``True``: a progress bar.
    memory_bytes : int, optional
        Memory the run may use; default: what the machine has available now.

    Returns
    -------
    Law
        Exact pieces of the density and the CDF, the route used and why.

    Raises
    ------
    ArgumentError
        If the request is out of range, or its plan is refused (the message names the route that would run it).

    Examples
    --------
    >>> import forcenet
    >>> w = forcenet.law(5, (5, 3))
    >>> w.moment(2) == forcenet.table(5, moments=2).moment(2)[4][2]
    True
    >>> forcenet.law(7, layer=7).cdf_at(7)
    Fraction(1, 1)
    >>> forcenet.law(5).quantity
    'P(f), f = i W_{i,j} over layers 2..N (ensemble)'
    >>> forcenet.law(40, layer=40, method="ideals")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    forcenet.core.errors.ArgumentError: N=40 is out of range for exact gap laws: ...; method='auto' runs it by floor (~...)
    """
    return law_plan(N, grain, layer=layer, contact=contact, method=method, executor=executor, checkpoint=checkpoint,
                    memory_bytes=memory_bytes).check().run(progress)
