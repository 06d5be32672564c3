"""Independent chains (or batches of exact samples) in parallel processes, pooled into one estimate.

What ``forcenet sample --workers K`` runs. **Exact samples** come in
streams of at most :data:`STREAM_SAMPLES` (``ceil(samples / STREAM_SAMPLES)``
streams, differing by at most one sample; stream ``i`` drawn from
``SeedSequence(seed).spawn(streams)[i]``, the seed itself for one stream),
whatever the number of workers: the ``K`` workers share the streams, and the
raw sums of ``W`` and ``W^2`` are pooled in stream order, so the result is
the same, bit for bit, for any ``K`` (issue 53). **Markov chains** are one
chain per worker (``K`` shares of the sweeps, ``SeedSequence(seed).spawn(K)``),
pooled by :func:`forcenet.numeric.autocorr.pool_chains` (each chain's error
bar from its integrated autocorrelation time): their result is a function
of the arguments, the seed and ``K`` (``K`` chains each burn in). The tasks run through
:func:`forcenet.core.execution.run_tasks`, which returns them in task order
whatever the completion order, and whose Ctrl-C terminates the workers at
once (every worker dies with its parent).

Examples
--------
>>> result = sample_in_parallel("exact", 4, 200, seed=1, workers=1)
>>> result.mean.shape, result.extra["effective_samples"]
((4, 4), 200.0)
"""

from __future__ import annotations

import multiprocessing
import os
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from forcenet.core.execution import run_tasks
from forcenet.core.plan import Plan
from forcenet.core.validation import is_integer
from forcenet.numeric.autocorr import mean_and_stderr, pool_chains, pool_means
from forcenet.numeric.packing.metropolis import PackingMetropolis
from forcenet.numeric.packing.metropolis import response as packing_response
from forcenet.numeric.triangle.exact_sampler import ExactSampler, mean_and_error
from forcenet.numeric.triangle.metropolis import TriangleMetropolis

from .autocorr import AutocorrError

__all__ = ["ChainsResult", "shares", "seeds", "parallel_plan", "sample_in_parallel"]

STREAM_SAMPLES = 10_000  # exact samples per random stream (stream i: SeedSequence(seed).spawn(streams)[i])
WORKER_BYTES = 100 * 2**20  # each further worker process: its interpreter, numpy and the compiled kernels


@dataclass(frozen=True)
class ChainsResult:
    """The pooled estimate of :func:`sample_in_parallel`.

    Parameters
    ----------
    mean : numpy.ndarray
        The mean of every ``W`` (the sampler's shape).
    stderr : numpy.ndarray
        Its standard error (from the integrated autocorrelation time for a Markov chain).
    extra : dict
        ``effective_samples``, ``kernel``, and for Markov chains ``burn_in``, ``move``, ``acceptance``,
        ``tau_max``, ``std_W`` (and ``G``, ``stderr_G`` with a response; the scene's parameters for a packing).

    Examples
    --------
    >>> import numpy as np
    >>> r = ChainsResult(np.array([0.5]), np.array([0.01]), {"effective_samples": 2500})
    >>> r.mean.tolist(), r.extra["effective_samples"]
    ([0.5], 2500)
    """

    mean: np.ndarray
    stderr: np.ndarray
    extra: dict[str, Any]


def shares(total: int, workers: int) -> list[int]:
    """``total`` split into ``workers`` shares differing by at most one (the first ones larger).

    Examples
    --------
    >>> shares(10, 3)
    [4, 3, 3]
    """
    return [total // workers + (k < total % workers) for k in range(workers)]


def seeds(seed: int, workers: int) -> list[Any]:
    """One seed per worker: the seed itself for one worker, else ``SeedSequence(seed).spawn(workers)``.

    Examples
    --------
    >>> seeds(7, 1)
    [7]
    >>> [s.spawn_key for s in seeds(7, 2)]
    [(0,), (1,)]
    """
    return [seed] if workers == 1 else np.random.SeedSequence(seed).spawn(workers)


def parallel_plan(plan: Plan, workers: int, memory: int | None, cores: int | None = None) -> Plan:
    """``plan`` of the whole run on one core, spread over ``workers`` processes on the machine's cores.

    The seconds divided by the cores used (plus a second of starting the
    processes), each further process's interpreter and kernels counted in
    its bytes, and the memory checked again.

    Parameters
    ----------
    plan : Plan
        The sampler's plan for all the samples in one process.
    workers : int
        Processes.
    memory : int or None
        Available bytes (:meth:`Plan.within_memory`).
    cores : int, optional
        The machine's cores (default ``os.cpu_count()``).

    Returns
    -------
    Plan

    Examples
    --------
    >>> p = parallel_plan(Plan("x", 10.0, 2**20), 2, None, cores=2)
    >>> p.what, p.seconds
    ('x, 2 workers', 6.0)
    """

    if workers == 1 or not plan.runnable:
        return plan
    used = max(1, min(workers, cores if cores is not None else os.cpu_count() or 1))
    plan = replace(plan, what=f"{plan.what}, {workers} workers", seconds=plan.seconds / used + 1.0,
                   nbytes=plan.nbytes + (workers - 1) * WORKER_BYTES)
    return plan.within_memory(memory)


def _exact_task(N: int, samples: int, seed: Any, progress: Callable[[int], None] | None = None
                ) -> tuple[Any, str]:
    """Worker: raw sums of W and W^2 over ``samples`` exact draws, and the kernel used."""

    sampler = ExactSampler(N, seed=np.random.default_rng(seed))
    return sampler.moment_sums(samples, (1,), progress)[1], sampler.kernel


def _metropolis_task(N: int, F: float, ph: float | None, scene: Any, sweeps: int, burn: int, seed: Any,
                     response: bool, move: str = "metropolis", progress: Callable[[int], None] | None = None
                     ) -> dict[str, Any]:
    """Worker: one chain; its mean, error bars (integrated autocorrelation time) and counts.

    Returns a dict, or ``{"error": message}`` when the chain is too short to trust.
    """

    rng = np.random.default_rng(seed)
    out: dict[str, Any] = {}
    try:
        if scene is None:
            sampler: Any = TriangleMetropolis(N, seed=rng, ph=None if ph is None else ph / F, move=move)
            chain = sampler.run(sweeps, burn_in=burn, progress=progress)  # in units of F (scaled at the end)
        else:
            sampler = PackingMetropolis(scene, seed=rng, move=move)
            chain = sampler.run(sweeps, burn_in=burn, progress=progress)
        mean, stderr, tau = mean_and_stderr(chain)
        if response:
            # the response's two chains: seeded from the same integer as before (one worker), else from a child
            child = seed if is_integer(seed) else seed.spawn(1)[0]
            out["G"], out["stderr_G"], _ = packing_response(scene, sweeps, burn, seed=child, progress=progress,
                                                              move=move)
    except AutocorrError as exc:
        return {"error": str(exc)}  # a plain dict: AutocorrError itself does not pickle back
    out.update({"n": sweeps, "mean": mean, "stderr": stderr, "tau": tau, "std": chain.std(axis=0, ddof=1),
                "accepted": sampler.accepted, "attempted": sampler.attempted, "kernel": sampler.kernel})
    return out


def _combine_chains(parts: Sequence[dict[str, Any]]) -> tuple[np.ndarray, np.ndarray, dict[str, Any]]:
    """Means, error bars, spread and effective sample size of independent chains (:func:`pool_chains`)."""

    n = [p["n"] for p in parts]
    pooled = pool_chains(n, *([p[k] for p in parts] for k in ("mean", "stderr", "std", "tau")))
    extra: dict[str, Any] = {
        "acceptance": sum(p["accepted"] for p in parts) / sum(p["attempted"] for p in parts),
        "tau_max": float(max(p["tau"].max() for p in parts)),
        "effective_samples": float(pooled.effective_samples.min()),  # min over the grains of sum_k n_k / tau_k
        "std_W": pooled.std,
    }
    if "G" in parts[0]:
        extra["G"], extra["stderr_G"] = pool_means(n, [p["G"] for p in parts], [p["stderr_G"] for p in parts])
    return pooled.mean, pooled.stderr, extra


def _run(func: Callable[..., Any], tasks: list[tuple[Any, ...]], workers: int, weights: list[int],
         progress: Callable[[int], None] | None) -> list[Any]:
    """``func(*task)`` for every task: in this process for one worker, else in ``workers`` processes."""
    if workers == 1:
        return [func(*task, progress=progress) for task in tasks]

    method = "fork" if "fork" in multiprocessing.get_all_start_methods() else "spawn"
    return run_tasks(func, tasks, workers=workers, progress=progress, weights=weights, start_method=method)


def sample_in_parallel(sampler: str, N: int, samples: int, *, seed: int, workers: int = 1, F: float = 1.0,
                       ph: float | None = None, scene: Any = None, burn_in: int = 0, response: bool = False,
                       move: str = "metropolis", progress: Callable[[int], None] | None = None) -> ChainsResult:
    """``samples`` exact samples, or sweeps of Markov chains, drawn by ``workers`` processes and pooled.

    The estimator of ``<W_ij>`` (Eqs. (3.8)-(3.10) for the chains' moves)
    with its standard error: for the exact sampler the raw sums of every
    share pooled (``samples`` effective samples), for Metropolis the chains
    pooled with their integrated autocorrelation times
    (:func:`forcenet.numeric.autocorr.pool_chains`).

    Parameters
    ----------
    sampler : {"exact", "metropolis"}
        Independent uniform tableaux, or the thesis's Markov chain.
    N : int
        Layers of the triangle (or of the packing ``scene``).
    samples : int
        Samples (exact) or recorded sweeps (metropolis), over all workers.
    seed : int
        The seed; the result depends on it and on ``workers`` only.
    workers : int
        Processes (one: this process).
    F : float
        The overload (the triangle's chains run in units of ``F``; scaled last).
    ph : float, optional
        Side pressure of the triangle's chain (None: fully mobilized).
    scene : forcenet.numeric.packing.scene.Scene, optional
        The N x P packing (metropolis only); None for the triangle.
    burn_in : int
        Sweeps discarded by each chain before it records.
    response : bool
        Also ``G(i, j)`` from a second chain per worker (packing only).
    move : {"metropolis", "slice"}
        The chains' move.
    progress : callable, optional
        ``progress(k)`` per ``k`` samples or sweeps done.

    Returns
    -------
    ChainsResult
        ``mean``, ``stderr`` and ``extra`` (effective samples, kernel, chain statistics).

    Raises
    ------
    AutocorrError
        A chain too short to trust its autocorrelation time (run more sweeps).

    Examples
    --------
    >>> a = sample_in_parallel("metropolis", 3, 2000, seed=5, burn_in=100)
    >>> a.mean.shape, a.extra["move"], a.extra["burn_in"]
    ((3, 3), 'metropolis', 100)
    >>> b = sample_in_parallel("metropolis", 3, 2000, seed=5, burn_in=100)
    >>> bool((a.mean == b.mean).all())  # the seed alone decides
    True
    """
    parts_seeds = seeds(seed, workers)
    split = shares(samples, workers)
    if sampler == "exact":  # streams of the seed and their index, whatever the workers: the same samples
        streams = -(-samples // STREAM_SAMPLES)
        tasks: list[tuple[Any, ...]] = [(N, k, s) for k, s in zip(shares(samples, streams), seeds(seed, streams))]
        parts = _run(_exact_task, tasks, min(workers, streams), [t[1] for t in tasks], progress)

        mean, stderr = mean_and_error(sum(p[0][0] for p in parts), sum(p[0][1] for p in parts), samples)
        return ChainsResult(mean * F, stderr * F, {"kernel": parts[0][1], "effective_samples": float(samples)})
    tasks = [(N, F, ph, scene, k, burn_in, s, response, move) for k, s in zip(split, parts_seeds)]
    chains = _run(_metropolis_task, tasks, workers, [t[4] * (2 if t[7] else 1) for t in tasks], progress)
    for part in chains:
        if "error" in part:
            raise AutocorrError(part["error"], np.array([]))
    mean, stderr, extra = _combine_chains(chains)
    if scene is None:  # the triangle's statistics in units of F, scaled last: any finite F
        mean, stderr, extra["std_W"] = mean * F, stderr * F, extra["std_W"] * F
    else:
        extra = {"scene": scene.name, "P": scene.P, "F": scene.F, "j0": scene.j0,
                 "pv": scene.pv, "mg": scene.mg, "ph": scene.ph, **extra}
    extra = {"burn_in": burn_in, "kernel": chains[0]["kernel"], "move": move, **extra}
    return ChainsResult(mean, stderr, extra)
