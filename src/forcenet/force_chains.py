"""The front door of Part III: clusters of large forces and their finite-size scaling (thesis Chs. 6-7).

* :func:`clusters` — users' force networks (CSV files ``sample,i,j,f``, one
  file per system size, ``M`` = bonds per sample; or arrays / DataFrames with
  those four columns): every threshold's clusters in one pass
  (:mod:`forcenet.numeric.force_chains.newman_ziff`), then the finite-size
  scaling (:mod:`forcenet.numeric.force_chains.finite_size_scaling`), a
  bootstrap over samples.
* :func:`scaling` / :func:`scaling_plan` — a model's networks generated at
  several sizes and scaled: ``percolation`` (independent uniform forces,
  the control with exact exponents 43/48 and 4/3), ``q-independent`` and
  ``q-microcanonical`` (Sec. 7.3), the force network ensemble's ``snooker``,
  ``disordered`` and ``averaged`` (Sec. 7.2, hit-and-run along local
  self-stresses, :mod:`forcenet.numeric.force_chains.network_ensembles`),
  planned first, run in blocks of samples (local processes or a Dask
  cluster's executor, checkpointed).

Both return a :class:`~forcenet.force_chains_results.ForceChainScaling`.

Examples
--------
>>> import forcenet
>>> plan = forcenet.scaling_plan("percolation", sizes=(16, 24, 32, 48), samples=200, replicas=0)
>>> plan.runnable, plan.cost.ticks
(True, 128)
>>> r = plan.run()
>>> abs(r.fit.value["f_c"] - 0.5) < 0.02     # 1 - p_c of bond percolation on the square lattice
True
"""

from __future__ import annotations

import functools
import os
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from forcenet.core.atomic_files import check_directory
from forcenet.core.errors import ArgumentError, ArgumentTypeError
from forcenet.core.plan import Plan
from forcenet.core.validation import check_int, check_seed
from forcenet.force_chains_results import ForceChainScaling
from forcenet.front_door import _Costed
from forcenet.numeric.force_chains.engines import DEFAULTS, MODELS, ScalingRequest
from forcenet.numeric.force_chains.finite_size_scaling import SizeBlocks, analyse
from forcenet.numeric.force_chains.newman_ziff import LATTICES, size_distribution, sweep_samples
from forcenet.registry import REGISTRY

__all__ = ["ScalingPlan", "ForceChainScaling", "scaling", "scaling_plan", "clusters", "read_networks", "example"]

MAX_SIZE = 4096


@dataclass(frozen=True)
class ScalingPlan(_Costed):
    """A checked :func:`scaling` request with its cost (make it with :func:`scaling_plan`); :meth:`run` runs it.

    Parameters
    ----------
    request : forcenet.numeric.force_chains.engines.ScalingRequest
        The checked request (model, sizes, samples, seed, thresholds, blocks, ...).
    cost : forcenet.core.plan.Plan
        Its estimated seconds, bytes and progress ticks (one per block), or the refusal.

    Examples
    --------
    >>> import forcenet
    >>> plan = forcenet.scaling_plan("q-independent", sizes=(8, 12, 16), samples=64)
    >>> plan.request.blocks, plan.cost.unit, plan.cost_method
    (32, 'block', 'union-find')
    """

    request: ScalingRequest
    cost: Plan

    def run(self, *, progress: Callable[..., Any] | bool | None = None, executor: Any = None) -> ForceChainScaling:
        """Run as planned.

        Parameters
        ----------
        progress : callable or bool, optional
            A tick per finished block, or ``True`` for a bar.
        executor : Executor or Dask client, optional
            Where the blocks run (default: this process, or ``workers`` local processes).

        Returns
        -------
        ForceChainScaling
            The exponents with their errors, the curves, the figures.

        Examples
        --------
        >>> import forcenet
        >>> forcenet.scaling_plan("q-independent", sizes=(6, 8, 10), samples=16, replicas=0).run().model
        'q-independent'
        """
        engine = REGISTRY.engine(self.request.model, self.request.quantity, self.cost_method)
        with self._ticks(progress, self.request.model) as tick:
            outcome = engine.run(self.request, self.cost.check(), progress=tick, executor=executor)
        r = self.request
        details = {"sizes": list(r.sizes), "samples": list(r.samples), "seed": r.seed, "thresholds": r.thresholds,
                   "blocks": r.blocks, "method": engine.name, "checkpoint_records_reused": outcome.reused}
        if r.model == "percolation":
            details["lattice"] = r.lattice
        details.update(outcome.details)
        return ForceChainScaling(r.model, outcome.data, outcome.fit, outcome.seconds, details)

    @property
    def cost_method(self) -> str:
        """The engine chosen (``auto`` resolved).

        Examples
        --------
        >>> import forcenet
        >>> forcenet.scaling_plan("q-microcanonical", sizes=(8, 12, 16), samples=8).cost_method
        'heat-bath'
        """
        return REGISTRY.choose(self.request)[0].name


def scaling_plan(model: str, sizes: Sequence[int] | None = None, samples: int | Sequence[int] | None = None,
                 seed: int = 0, *, lattice: str = "square", thresholds: int = 600, replicas: int = 100,
                 blocks: int = 32, workers: int = 1, checkpoint: str | os.PathLike[str] | None = None,
                 method: str = "auto", average: int = 4) -> ScalingPlan:
    """Check a finite-size-scaling request once and say what it costs.

    Parameters
    ----------
    model : {"percolation", "q-independent", "q-microcanonical", "snooker", "disordered", "averaged"}
        The generator of force networks (Secs. 7.2-7.3; ``snooker``: the force network ensemble on the snooker
        triangle, ``disordered``: on soft-disk packings, ``averaged``: snooker networks each the average of
        ``average`` networks of the ensemble).
    sizes : sequence of int, optional
        Linear sizes ``L`` (at least 3; default: the model's, ``DEFAULTS``): the lattice's side, the snooker
        triangle's layers, ``sqrt`` of a disordered packing's disks.
    samples : int or sequence of int, optional
        Networks per size (one number: the same at every size).
    seed : int
        The seed (the result is a function of the request and the seed alone).
    lattice : {"square", "triangular", "honeycomb"}
        Percolation's periodic lattice.
    thresholds : int
        Number of thresholds (quantiles of pilot networks).
    replicas : int
        Bootstrap resamples.
    blocks : int
        Blocks of samples per size (the tasks, the bootstrap's units).
    workers : int
        Local processes when no executor is given.
    checkpoint : path, optional
        A directory keeping every finished block (a rerun reuses them).
    method : str
        The engine (``auto``: the registry's choice).
    average : int
        ``P`` of the ``averaged`` model (Sec. 7.2.3; 1..64).

    Returns
    -------
    ScalingPlan
        The request and its cost.

    Raises
    ------
    ArgumentError
        A model, lattice or number out of range, fewer than 3 sizes, samples not matching the sizes.
    ArgumentTypeError
        A size or number that is not an integer.

    Examples
    --------
    >>> import forcenet
    >>> forcenet.scaling_plan("q-microcanonical").request.sizes
    (12, 16, 24, 32, 48, 64)
    >>> forcenet.scaling_plan("ising")
    Traceback (most recent call last):
    ...
    forcenet.core.errors.ArgumentError: model='ising' is out of range: model must be one of percolation, q-independent, q-microcanonical, snooker, disordered, averaged
    """
    if model not in MODELS:
        raise ArgumentError(f"model={model!r} is out of range: model must be one of {', '.join(MODELS)}")
    if lattice not in LATTICES:
        raise ArgumentError(f"lattice={lattice!r} is out of range: lattice must be one of {', '.join(LATTICES)}")
    default_sizes, default_samples = DEFAULTS[model]
    if sizes is None:
        sizes_t = default_sizes
    else:
        if isinstance(sizes, str | bytes) or not isinstance(sizes, Sequence):
            raise ArgumentTypeError(f"sizes={sizes!r}: expected a sequence of integers, e.g. (16, 32, 64)")
        sizes_t = tuple(check_int(L, "sizes", 4, MAX_SIZE) for L in sizes)
    if len(sizes_t) < 3 or len(set(sizes_t)) != len(sizes_t):
        raise ArgumentError(f"sizes={list(sizes_t)} is out of range: give at least 3 different sizes")
    if samples is None:
        samples_t = default_samples if sizes is None else tuple([default_samples[-1]] * len(sizes_t))
    elif isinstance(samples, Sequence) and not isinstance(samples, str | bytes):
        samples_t = tuple(check_int(k, "samples", 2) for k in samples)
    else:
        samples_t = tuple([check_int(samples, "samples", 2)] * len(sizes_t))
    if len(samples_t) != len(sizes_t):
        raise ArgumentError(f"samples: {len(samples_t)} numbers for {len(sizes_t)} sizes; give one, or one per size")
    order = np.argsort(sizes_t)
    request = ScalingRequest(
        model, tuple(int(sizes_t[i]) for i in order), tuple(int(samples_t[i]) for i in order),
        seed=check_int(check_seed(seed), "seed", 0), lattice=lattice,
        thresholds=check_int(thresholds, "thresholds", 20, 20000), replicas=check_int(replicas, "replicas", 0, 10000),
        blocks=check_int(blocks, "blocks", 2, 10000), workers=check_int(workers, "workers", 1, 256),
        checkpoint=None if checkpoint is None else check_directory(checkpoint, "checkpoint"), method=str(method),
        average=check_int(average, "average", 1, 64))
    _, cost = REGISTRY.choose(request)
    return ScalingPlan(request, cost)


def scaling(model: str, sizes: Sequence[int] | None = None, samples: int | Sequence[int] | None = None,
            seed: int = 0, *, progress: Callable[..., Any] | bool | None = None, executor: Any = None,
            **options: Any) -> ForceChainScaling:
    """A model's force networks at several sizes, their clusters and the finite-size scaling (Eqs. 6.8, 6.12).

    Parameters
    ----------
    model : str
        As :func:`scaling_plan`.
    sizes : sequence of int, optional
        As :func:`scaling_plan`.
    samples : int or sequence of int, optional
        As :func:`scaling_plan`.
    seed : int
        As :func:`scaling_plan`.
    progress : callable or bool, optional
        A tick per block, or ``True`` for a bar.
    executor : Executor, optional
        Where the blocks run.
    **options
        The other keyword arguments of :func:`scaling_plan` (``lattice``, ``thresholds``, ``replicas``,
        ``blocks``, ``workers``, ``checkpoint``, ``method``).

    Returns
    -------
    ForceChainScaling
        ``f_c``, ``nu``, ``gamma_2`` with errors, the curves, the figures.

    Examples
    --------
    >>> import forcenet
    >>> r = forcenet.scaling("percolation", sizes=(8, 12, 16), samples=64, replicas=0, blocks=8)
    >>> r.fit.value["f_c"] > 0.4
    True
    """
    return scaling_plan(model, sizes, samples, seed, **options).run(progress=progress, executor=executor)


def _table(source: Any) -> np.ndarray:
    """Columns ``sample, i, j, f`` of a CSV path, an array or a DataFrame, as float64 ``(n, 4)``."""
    if isinstance(source, str | os.PathLike):
        path = os.fspath(source)
        try:
            with open(path, encoding="utf-8") as handle:
                text = handle.read()
        except OSError as exc:
            raise ArgumentError(f"{path}: cannot read it ({exc.strerror})") from exc
        first, _, rest = text.partition("\n")
        body = rest if first.replace(" ", "").lower().startswith("sample,") else text
        try:
            values = np.array(body.replace(",", " ").split(), dtype=np.float64)
        except ValueError as exc:
            raise ArgumentError(f"{path}: not a CSV of numbers with columns sample,i,j,f ({exc})") from exc
        if values.size % 4:
            raise ArgumentError(f"{path}: expected 4 columns sample,i,j,f on every line")
        return values.reshape(-1, 4)
    if hasattr(source, "columns") and hasattr(source, "to_numpy"):  # a DataFrame: by column names
        try:
            return np.asarray(source[["sample", "i", "j", "f"]].to_numpy(), dtype=np.float64)
        except KeyError as exc:
            raise ArgumentError("a DataFrame needs the columns sample, i, j, f") from exc
    array = np.asarray(source, dtype=np.float64)
    if array.ndim != 2 or array.shape[1] != 4:
        raise ArgumentError(f"an array of force networks must have shape (bonds, 4): sample, i, j, f; got {array.shape}")
    return array


def read_networks(source: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """One system size's networks as the flat arrays of the cluster pass: ``starts``, ``sites``, ``head``,
    ``tail``, ``force`` (each sample's grain labels renumbered from 0).

    Parameters
    ----------
    source : path, array or DataFrame
        Rows ``sample, i, j, f``: a bond between grains ``i`` and ``j`` of sample ``sample`` carrying ``f``.

    Returns
    -------
    tuple of ndarray

    Examples
    --------
    >>> import numpy as np
    >>> starts, sites, head, tail, force = read_networks(np.array([[0, 7, 9, 1.0], [1, 3, 4, 2.0], [1, 4, 5, 0.5]]))
    >>> starts.tolist(), sites.tolist(), head.tolist(), tail.tolist()
    ([0, 1, 3], [2, 3], [0, 0, 1], [1, 1, 2])
    """
    table = _table(source)
    if table.shape[0] == 0 or not np.all(np.isfinite(table)):
        raise ArgumentError("force networks: no bonds, or a value that is not a finite number")
    if np.any(table[:, :3] != np.round(table[:, :3])):
        raise ArgumentError("force networks: sample, i and j must be integers")
    table = table[np.argsort(table[:, 0], kind="stable")]
    labels, starts = np.unique(table[:, 0], return_index=True)
    starts = np.append(starts, table.shape[0])
    head = np.empty(table.shape[0], np.int64)
    tail = np.empty(table.shape[0], np.int64)
    sites = np.empty(labels.size, np.int64)
    for r in range(labels.size):
        lo, hi = starts[r], starts[r + 1]
        _, inverse = np.unique(table[lo:hi, 1:3], return_inverse=True)
        inverse = inverse.reshape(-1, 2)
        head[lo:hi], tail[lo:hi] = inverse[:, 0], inverse[:, 1]
        sites[r] = int(inverse.max()) + 1
    return starts.astype(np.int64), sites, head, tail, table[:, 3].copy()


def clusters(sources: Sequence[Any], *, thresholds: int = 600, replicas: int = 100, seed: int = 0,
             labels: Sequence[float] | None = None) -> ForceChainScaling:
    """The clusters of large forces of users' force networks and their finite-size scaling (Sec. 6.5, Eq. 6.12).

    Parameters
    ----------
    sources : sequence
        One entry per system size (at least 3): a CSV path (header ``sample,i,j,f``), an array with those four
        columns, or a DataFrame with those columns.  ``M`` is the mean number of bonds per sample.
    thresholds : int
        Thresholds: quantiles 1 %..99 % of all the forces given.
    replicas : int
        Bootstrap resamples (over samples).
    seed : int
        The bootstrap's seed.
    labels : sequence of float, optional
        A label per size (e.g. the linear size ``L``; default none).

    Returns
    -------
    ForceChainScaling
        The scaling size is ``S = M``; ``wrapping`` is not known (no geometry).  ``details["n_s_at_f_c"]``:
        per size, the clusters per bond of ``s`` bonds at the ``f_c`` found, in bins ``[2^k, 2^(k+1))``.

    Raises
    ------
    ArgumentError
        Fewer than 3 sizes or 2 samples of a size, a file that cannot be read or is not ``sample,i,j,f``.
    ConvergenceError
        If no collapse is found (the forces' range leaves no window covered by every size).

    Examples
    --------
    >>> import numpy as np, forcenet
    >>> from forcenet.numeric.force_chains.newman_ziff import periodic_lattice
    >>> rng = np.random.default_rng(0)
    >>> def networks(L, K):                                   # independent uniform forces: percolation
    ...     lat = periodic_lattice("square", L)
    ...     return np.concatenate([np.column_stack([np.full(lat.bonds, k), lat.head, lat.tail, rng.random(lat.bonds)])
    ...                            for k in range(K)])
    >>> r = forcenet.clusters([networks(12, 300), networks(16, 200), networks(24, 120), networks(32, 80)], replicas=0)
    >>> abs(r.fit.value["f_c"] - 0.5) < 0.05, r.summary()["sizes"][0]["M"]
    (True, 288)
    """
    if isinstance(sources, str | bytes) or not isinstance(sources, Sequence):
        raise ArgumentTypeError("sources: expected a list of CSV paths, arrays or DataFrames, one per system size")
    if len(sources) < 3:
        raise ArgumentError(f"sources: finite-size scaling needs at least 3 system sizes, got {len(sources)}")
    thresholds = check_int(thresholds, "thresholds", 20, 20000)
    replicas = check_int(replicas, "replicas", 0, 10000)
    seed = check_int(seed, "seed", 0)
    started = time.perf_counter()
    rng = np.random.default_rng(seed)
    pooled = []
    for source in sources:  # pass 1: the thresholds, from up to 2^17 forces of every size (one size in memory)
        force = read_networks(source)[4]
        pooled.append(force if force.size <= 2**17 else rng.choice(force, 2**17, replace=False))
    levels = np.unique(np.quantile(np.concatenate(pooled), np.linspace(0.01, 0.99, thresholds)))
    del pooled
    data = []
    for index, source in enumerate(sources):  # pass 2: one size at a time
        starts, sites, head, tail, force = read_networks(source)
        stats = sweep_samples(starts, sites, head, tail, force, levels)
        K = sites.size
        if K < 2:
            raise ArgumentError(f"sources[{index}]: the bootstrap needs at least 2 samples, got {K}")
        M = float(force.size) / K
        label = float(labels[index]) if labels is not None else 0.0
        data.append(SizeBlocks(M, int(round(M)), levels, stats.total.astype(np.float64),
                               stats.largest.astype(np.float64), stats.wraps.astype(np.float64), np.ones(K),
                               label=label))
        del starts, sites, head, tail, force, stats
    fit = analyse(data, replicas=replicas, seed=seed)
    n_s = []
    for source in sources:  # pass 3: the cluster numbers n_s at the f_c found (Eq. 6.1)
        lower, density = size_distribution(*read_networks(source), fit.value["f_c"])
        n_s.append({"s": lower.tolist(), "n_s": [float(f"{x:.6g}") for x in density]})
    details = {"sources": [os.fspath(s) if isinstance(s, str | os.PathLike) else f"<{type(s).__name__}>"
                           for s in sources], "thresholds": int(levels.size),
               "n_s_at_f_c": n_s}
    return ForceChainScaling("data", sorted(data, key=lambda d: d.S), fit, time.perf_counter() - started, details)


@functools.cache
def example() -> ForceChainScaling:
    """A small result to try the renderings on: bond percolation on periodic square lattices ``L = 8..24``
    (64 samples each, no bootstrap), made once per session.

    Examples
    --------
    >>> example().model
    'percolation'
    """
    return scaling("percolation", sizes=(8, 12, 16, 24), samples=64, replicas=0, blocks=8)
