"""The force-chain models as engines of the registry: force networks at several sizes, clusters, scaling.

Each model (``percolation``: independent uniform forces on a periodic
lattice, the control whose exponents are known exactly; ``q-independent``
and ``q-microcanonical``: Sec. 7.3) generates force networks at every size
in *blocks* of samples; a block is one task of
:func:`forcenet.core.execution.run_tasks` (a local pool, or a Dask cluster's
executor) and one record of the checkpoint store, seeded by its own
``SeedSequence(seed, spawn_key=(size, block))``, so the result depends on
the request alone, not on the workers or on what a checkpoint held.  A block
returns, at every threshold, the integer sums of its samples' cluster
statistics (:mod:`.newman_ziff`); the blocks are the bootstrap's units
(:mod:`.finite_size_scaling`).  For the Markov chain of the microcanonical
model each block is its own chain (burn-in included), so blocks are
independent too.

The thresholds are the quantiles (1 % to 99 %) of the pooled forces of two
pilot networks of the largest size, the same for every size.  The scaling
size ``S`` is ``M`` (percolation) or ``L_vert^2`` (q-models: the thesis
scales them in their vertical size, Sec. 7.3; with ``W = L`` grains per row
the two differ by a constant factor, which changes no exponent).

Examples
--------
>>> from forcenet.registry import REGISTRY
>>> request = ScalingRequest("percolation", sizes=(8, 12, 16), samples=(64, 64, 64), seed=1, replicas=0, blocks=8)
>>> engine, plan = REGISTRY.choose(request)
>>> engine.name, plan.runnable
('union-find', True)
>>> outcome = engine.run(request, plan)
>>> [d.label for d in outcome.data], abs(outcome.fit.value["f_c"] - 0.5) < 0.05
([8.0, 12.0, 16.0], True)
"""

from __future__ import annotations

import hashlib
import time
from abc import ABC, abstractmethod
from collections.abc import Callable
from concurrent.futures import Executor
from dataclasses import dataclass
from typing import Any

import numpy as np

from forcenet.core.checkpoints import CheckpointStore
from forcenet.core.execution import run_tasks
from forcenet.core.plan import Plan
from forcenet.core.registry import REGISTRY

from .finite_size_scaling import ScalingFit, SizeBlocks, analyse
from .newman_ziff import Lattice, periodic_lattice, sweep_lattice
from .q_models import independent_samples, microcanonical_chain, q_lattice

__all__ = ["ScalingRequest", "ScalingOutcome", "MODELS", "DEFAULTS", "UnionFindEngine", "HeatBathEngine",
           "block_task", "thresholds_for", "scaling_size"]

MODELS = ("percolation", "q-independent", "q-microcanonical")
# default sizes and samples per size: the whole default run of each model within ~2-5 minutes on one core
DEFAULTS: dict[str, tuple[tuple[int, ...], tuple[int, ...]]] = {
    "percolation": ((32, 48, 64, 96, 128, 192, 256), (3200, 2400, 1600, 1200, 800, 480, 400)),
    "q-independent": ((20, 28, 40, 56, 80, 112), (19200, 9600, 4800, 2400, 1200, 640)),
    "q-microcanonical": ((12, 16, 24, 32, 48, 64), (1280, 1280, 640, 640, 320, 192)),
}
# Remeasured 2026-12-06 (issue 53, notes/benchmarks.md "Estimates against the actual"): the blocks of the
# default runs took 1.0e-7 CPU s per bond (percolation 16.3 s, q-independent 8.0 s) since the counting sort,
# and the heat-bath blocks 0.2-0.27 of the old moves' model (4.9 s): the plans were 2-3x high.
BONDS_PER_SECOND = 1.2e7  # the cluster pass with wrapping, one core, thresholds grouped by a counting sort
GENERATE_PER_SECOND = 6.0e7  # uniform forces or q-model forces per second
MOVES_PER_SECOND = 2.2e8  # heat-bath moves per second, one core
ANALYSIS_SECONDS = 0.012  # the collapse and estimators: per bootstrap replica and per size (0.008-0.016 measured)


@dataclass(frozen=True)
class ScalingRequest:
    """A checked request for the finite-size scaling of one model (built once by the front door).

    ``samples[i]`` networks at size ``sizes[i]`` (the linear size ``L``), cut into ``blocks`` blocks each;
    ``thresholds`` thresholds; ``replicas`` bootstrap resamples; ``lattice`` (percolation);
    ``checkpoint`` a directory or None; ``workers`` local processes when no executor is given."""

    model: str
    sizes: tuple[int, ...]
    samples: tuple[int, ...]
    seed: int = 0
    lattice: str = "square"
    thresholds: int = 600
    replicas: int = 100
    blocks: int = 32
    checkpoint: str | None = None
    workers: int = 1
    method: str = "auto"
    quantity: str = "scaling"

    def key(self) -> str:
        """A digest of what determines the numbers (not the workers, nor the checkpoint's place)."""
        text = repr((self.model, self.sizes, self.samples, self.seed, self.lattice, self.thresholds, self.blocks))
        return hashlib.sha256(text.encode()).hexdigest()[:16]


@dataclass(frozen=True)
class ScalingOutcome:
    """What an engine returns: every size's blocks, the fit, the wall seconds and the checkpoint records reused."""

    request: ScalingRequest
    data: list[SizeBlocks]
    fit: ScalingFit
    seconds: float
    reused: int = 0


def lattice_for(model: str, lattice: str, L: int) -> Lattice:
    """The bond list of ``model`` at linear size ``L`` (``W = L`` grains per row for the q-models).

    Examples
    --------
    >>> lattice_for("q-independent", "square", 4).bonds, lattice_for("percolation", "honeycomb", 4).bonds
    (32, 48)
    """
    return periodic_lattice(lattice, L) if model == "percolation" else q_lattice(L, L)


def scaling_size(model: str, lattice: Lattice) -> float:
    """``S``: the bonds ``M`` (isotropic), ``L_vert^2`` for the anisotropic q-models (Sec. 7.3).

    Examples
    --------
    >>> scaling_size("percolation", periodic_lattice("square", 4)), scaling_size("q-independent", q_lattice(4, 4))
    (32.0, 16.0)
    """
    return float(lattice.bonds) if model == "percolation" else float(lattice.L) ** 2


def _networks(model: str, L: int, count: int, rng: np.random.Generator, bonds: int) -> np.ndarray:
    if model == "percolation":
        return rng.random((count, bonds))
    if model == "q-independent":
        return independent_samples(L, L, count, rng)
    return microcanonical_chain(L, L, count, max(1, L * L // 16), L * L, rng)


def _rng(seed: int, *key: int) -> np.random.Generator:
    return np.random.default_rng(np.random.SeedSequence(seed, spawn_key=key))


def thresholds_for(request: ScalingRequest) -> np.ndarray:
    """The thresholds: quantiles 1 %..99 % of two pilot networks of the largest size (increasing, distinct).

    Examples
    --------
    >>> t = thresholds_for(ScalingRequest("percolation", (8, 16, 32), (8, 8, 8), thresholds=5))
    >>> [round(float(v), 1) for v in t]
    [0.0, 0.3, 0.5, 0.7, 1.0]
    """
    L = max(request.sizes)
    lattice = lattice_for(request.model, request.lattice, L)
    pilot = _networks(request.model, L, 2, _rng(request.seed, 2**31 - 1), lattice.bonds).ravel()
    return np.unique(np.quantile(pilot, np.linspace(0.01, 0.99, request.thresholds)))


def block_task(model: str, lattice_name: str, L: int, count: int, seed: int, size_index: int, block: int,
               thresholds: np.ndarray) -> np.ndarray:
    """One block: ``count`` networks at size ``L``, their cluster statistics summed per threshold.

    Returns
    -------
    ndarray of int64, shape (3 T + 1,)
        The sums of ``total``, ``largest``, ``wraps`` (T each) and the block's sample count.

    Examples
    --------
    >>> import numpy as np
    >>> block_task("percolation", "square", 4, 3, 0, 0, 0, np.array([0.5])).tolist()[-1]
    3
    """
    lattice = lattice_for(model, lattice_name, L)
    forces = _networks(model, L, count, _rng(seed, size_index, block), lattice.bonds)
    stats = sweep_lattice(lattice, forces, thresholds)
    return np.concatenate([stats.total.sum(0), stats.largest.sum(0), stats.wraps.sum(0), [count]]).astype(np.int64)


def _split(samples: int, blocks: int) -> list[int]:
    blocks = max(1, min(blocks, samples))
    return [samples // blocks + (1 if b < samples % blocks else 0) for b in range(blocks)]


class _ScalingEngine(ABC):
    """The shared plan and run: generators differ by model (:func:`_networks`), the cost by the engine."""

    name = ""
    model = ""
    quantities = frozenset({"scaling"})

    @abstractmethod
    def seconds(self, request: ScalingRequest) -> float:
        """Estimated seconds on one core."""

    def plan(self, request: ScalingRequest) -> Plan:
        tasks = sum(len(_split(k, request.blocks)) for k in request.samples)
        biggest = max(lattice_for(request.model, request.lattice, L).bonds * max(_split(k, request.blocks))
                      for L, k in zip(request.sizes, request.samples, strict=True))
        workers = max(1, request.workers)
        return Plan(f"{request.model} finite-size scaling at L = {', '.join(map(str, request.sizes))}",
                    seconds=self.seconds(request) / workers + ANALYSIS_SECONDS * request.replicas * len(request.sizes),
                    nbytes=16 * biggest * workers + 64 * 2**20, ticks=tasks, unit="block")

    def run(self, request: ScalingRequest, plan: Plan, *, progress: Callable[..., Any] | None = None,
            executor: Executor | None = None) -> ScalingOutcome:
        started = time.perf_counter()
        thresholds = thresholds_for(request)
        tasks, owners = [], []
        for index, (L, k) in enumerate(zip(request.sizes, request.samples, strict=True)):
            for block, count in enumerate(_split(k, request.blocks)):
                tasks.append((request.model, request.lattice, L, count, request.seed, index, block, thresholds))
                owners.append(index)
        store = None
        if request.checkpoint is not None:
            store = CheckpointStore(request.checkpoint, f"scaling-{request.model}-{request.key()}", max(request.sizes))
        results = run_tasks(block_task, tasks, executor=executor, workers=request.workers, progress=progress,
                            store=store, keys=list(range(len(tasks))) if store is not None else None)
        T = thresholds.size
        data = []
        for index, L in enumerate(request.sizes):
            rows = np.array([r for r, o in zip(results, owners, strict=True) if o == index], dtype=np.float64)
            lattice = lattice_for(request.model, request.lattice, L)
            data.append(SizeBlocks(scaling_size(request.model, lattice), lattice.bonds, thresholds, rows[:, :T],
                                   rows[:, T:2 * T], rows[:, 2 * T:3 * T], rows[:, -1], label=float(L),
                                   has_wraps=request.model == "percolation"))
        fit = analyse(data, replicas=request.replicas, seed=request.seed)
        return ScalingOutcome(request, data, fit, time.perf_counter() - started,
                              store.reused if store is not None else 0)


class UnionFindEngine(_ScalingEngine):
    """Independent networks (percolation, the independent q-model): generated and swept block by block."""

    name = "union-find"

    def __init__(self, model: str) -> None:
        self.model = model

    def seconds(self, request: ScalingRequest) -> float:
        bonds = sum(lattice_for(request.model, request.lattice, L).bonds * k
                    for L, k in zip(request.sizes, request.samples, strict=True))
        return bonds / BONDS_PER_SECOND + bonds / GENERATE_PER_SECOND


class HeatBathEngine(_ScalingEngine):
    """The microcanonical q-model: heat-bath chains on the flow polytope, one per block."""

    name = "heat-bath"
    model = "q-microcanonical"

    def seconds(self, request: ScalingRequest) -> float:
        total = 0.0
        for L, k in zip(request.sizes, request.samples, strict=True):
            moves = L * L
            sweeps = k * max(1, L * L // 16) + len(_split(k, request.blocks)) * L * L
            total += sweeps * moves / MOVES_PER_SECOND + 2 * L * L * k / BONDS_PER_SECOND
        return total


def _register() -> None:
    """Register the three models' engines (this module is the registry's loader for them)."""
    REGISTRY.register(UnionFindEngine("percolation"))
    REGISTRY.register(UnionFindEngine("q-independent"))
    REGISTRY.register(HeatBathEngine())


_register()
