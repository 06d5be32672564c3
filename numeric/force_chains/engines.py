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
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from forcenet.core.checkpoints import CheckpointStore
from forcenet.core.execution import run_tasks
from forcenet.core.plan import Plan
from forcenet.core.registry import REGISTRY

from . import network_ensembles
from .finite_size_scaling import ScalingFit, SizeBlocks, analyse
from .newman_ziff import Lattice, periodic_lattice, sweep_lattice
from .q_models import independent_samples, microcanonical_chain, q_lattice

__all__ = ["analysis_seconds", "ScalingRequest", "ScalingOutcome", "MODELS", "DEFAULTS", "UnionFindEngine",
           "HeatBathEngine", "block_task", "thresholds_for", "scaling_size", "LocalHitAndRunEngine"]

MODELS = ("percolation", "q-independent", "q-microcanonical") + network_ensembles.NETWORK_MODELS
# default sizes and samples per size: the whole default run of each model within ~2-5 minutes on one core
DEFAULTS: dict[str, tuple[tuple[int, ...], tuple[int, ...]]] = {
    "percolation": ((32, 48, 64, 96, 128, 192, 256), (3200, 2400, 1600, 1200, 800, 480, 400)),
    "q-independent": ((20, 28, 40, 56, 80, 112), (19200, 9600, 4800, 2400, 1200, 640)),
    "q-microcanonical": ((12, 16, 24, 32, 48, 64), (1280, 1280, 640, 640, 320, 192)),
    # Sec. 7.2: L = layers of the snooker triangle (M = 3L(L-1)/2 + 2L contacts), L^2 disks when disordered;
    # planned under the command line's minute (no --force needed)
    "snooker": ((8, 12, 16, 20, 28), (3200, 2400, 1600, 1280, 800)),
    "disordered": ((5, 6, 7, 8, 10), (960, 960, 640, 640, 640)),
    "averaged": ((8, 12, 16, 20, 28), (1200, 800, 480, 320, 200)),
}
# the cost model: CPU seconds of forcenet.scaling measured on one core (each model's default run, and L = 8..512;
# notes/benchmarks.md):
BONDS_PER_SECOND = 1.3e7  # the cluster pass with wrapping, sorting included (1.3e7 at L <= 128, 0.8e7 at L = 512)
GENERATE_PER_SECOND = 3.0e7  # uniform forces or q-model forces per second
MOVES_PER_SECOND = 2.4e8  # heat-bath moves per second (2.4-2.5e8 at L = 16..64; 5e7 before: 4-5x high)
FIT_SECONDS = (0.6, 0.1)  # the collapse fit (Eq. 6.12) from its starting points: a constant and a share per size
REPLICA_SECONDS = (0.02, 0.003)  # one bootstrap replica's refit: a constant and a share per size
WORKER_START_SECONDS = 2.0  # local workers start in parallel: interpreter, numpy, cached kernels (2.3 CPU s under load)


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
    average: int = 4

    def key(self) -> str:
        """A digest of what determines the numbers (not the workers, nor the checkpoint's place)."""
        text = repr((self.model, self.sizes, self.samples, self.seed, self.lattice, self.thresholds, self.blocks))
        if self.model == "averaged":  # P, the networks averaged into one (Sec. 7.2.3)
            text += f"average={self.average}"
        return hashlib.sha256(text.encode()).hexdigest()[:16]


@dataclass(frozen=True)
class ScalingOutcome:
    """What an engine returns: every size's blocks, the fit, the wall seconds and the checkpoint records reused."""

    request: ScalingRequest
    data: list[SizeBlocks]
    fit: ScalingFit
    seconds: float
    reused: int = 0
    details: dict[str, Any] = field(default_factory=dict)


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


def analysis_seconds(sizes: int, replicas: int) -> float:
    """Seconds of the finite-size scaling after the blocks, in this process: the collapse fit (Eq. 6.12) and its
    bootstrap ``replicas``, for ``sizes`` sizes (measured at 3-6 sizes, 100-2000 thresholds, 0-100 replicas:
    0.5-1.4 s for the fit, 0.023-0.043 s a replica).

    Examples
    --------
    >>> round(analysis_seconds(3, 0), 2), round(analysis_seconds(6, 100), 2)
    (0.9, 5.0)
    """
    return FIT_SECONDS[0] + FIT_SECONDS[1] * sizes + replicas * (REPLICA_SECONDS[0] + REPLICA_SECONDS[1] * sizes)


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
                    seconds=self.seconds(request) / workers + analysis_seconds(len(request.sizes), request.replicas)
                    + (WORKER_START_SECONDS if workers > 1 else 0.0),
                    nbytes=16 * biggest * workers + 64 * 2**20, ticks=tasks, unit="block")

    def thresholds(self, request: ScalingRequest) -> np.ndarray:
        """The thresholds of the request (:func:`thresholds_for`)."""
        return thresholds_for(request)

    def task(self, request: ScalingRequest, L: int, count: int, index: int, block: int,
             thresholds: np.ndarray) -> tuple[Callable[..., np.ndarray], tuple[Any, ...]]:
        """One block's function and arguments."""
        return block_task, (request.model, request.lattice, L, count, request.seed, index, block, thresholds)

    def size_blocks(self, request: ScalingRequest, L: int, rows: np.ndarray, thresholds: np.ndarray) -> SizeBlocks:
        """One size's blocks from the rows its tasks returned."""
        T = thresholds.size
        rows = rows.astype(np.float64)
        lattice = lattice_for(request.model, request.lattice, L)
        return SizeBlocks(scaling_size(request.model, lattice), lattice.bonds, thresholds, rows[:, :T],
                          rows[:, T:2 * T], rows[:, 2 * T:3 * T], rows[:, -1], label=float(L),
                          has_wraps=request.model == "percolation")

    def run(self, request: ScalingRequest, plan: Plan, *, progress: Callable[..., Any] | None = None,
            executor: Executor | None = None) -> ScalingOutcome:
        started = time.perf_counter()
        thresholds = self.thresholds(request)
        tasks, owners = [], []
        function: Callable[..., np.ndarray] = block_task
        for index, (L, k) in enumerate(zip(request.sizes, request.samples, strict=True)):
            for block, count in enumerate(_split(k, request.blocks)):
                function, arguments = self.task(request, L, count, index, block, thresholds)
                tasks.append(arguments)
                owners.append(index)
        store = None
        if request.checkpoint is not None:
            store = CheckpointStore(request.checkpoint, f"scaling-{request.model}-{request.key()}", max(request.sizes),
                                    shape=self.record_shape(thresholds))  # a record of another shape is recomputed
        results = run_tasks(function, tasks, executor=executor, workers=request.workers, progress=progress,
                            store=store, keys=list(range(len(tasks))) if store is not None else None)
        data, per_size = [], []
        for index, L in enumerate(request.sizes):
            rows = np.array([r for r, o in zip(results, owners, strict=True) if o == index])
            data.append(self.size_blocks(request, L, rows, thresholds))
            per_size.append(rows)
        fit = analyse(data, replicas=request.replicas, seed=request.seed)
        return ScalingOutcome(request, data, fit, time.perf_counter() - started,
                              store.reused if store is not None else 0, self.details(request, per_size, thresholds))

    def details(self, request: ScalingRequest, rows: list[np.ndarray], thresholds: np.ndarray) -> dict[str, Any]:
        """What the engine adds to the result's details (nothing by default)."""
        return {}

    def record_shape(self, thresholds: np.ndarray) -> tuple[int]:
        """A block's checkpoint record: the three sums over every threshold and the count (:func:`block_task`)."""
        return (3 * thresholds.size + 1,)


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


def _floats(rows: np.ndarray) -> np.ndarray:
    """A block's float64 numbers from the int64 bits its task returned."""
    return np.ascontiguousarray(rows, dtype=np.int64).view(np.float64)


class LocalHitAndRunEngine(_ScalingEngine):
    """The force network ensemble's models (Sec. 7.2: ``snooker``, ``disordered``, ``averaged``): one chain of
    hit-and-run along local self-stresses per block (:mod:`.network_ensembles`, :mod:`.local_hit_and_run`).

    A block's row holds ``total / M`` (each network's own ``M``), multiplied back by the size's mean ``M`` so that
    ``<s^2>`` is the mean over networks of ``sum s^2 / M``; ``S = M`` (the thesis's scaling size, all contacts).
    The details name the thinning (sweeps) and the largest integrated autocorrelation time of a block's recorded
    networks (their mean squared force, in recorded networks: ~1 means decorrelated).
    """

    name = "local-hit-and-run"

    def __init__(self, model: str) -> None:
        self.model = model

    def seconds(self, request: ScalingRequest) -> float:
        setup = sum(network_ensembles.setup_seconds(request.model, L) for L in request.sizes)
        return setup * min(request.workers, request.blocks) + sum(  # each process builds its own samplers
            network_ensembles.block_seconds(request.model, L, c, request.average)
            for L, k in zip(request.sizes, request.samples, strict=True) for c in _split(k, request.blocks))

    def thresholds(self, request: ScalingRequest) -> np.ndarray:
        return network_ensembles.pilot_thresholds(request.model, request.sizes, request.seed, request.thresholds,
                                                  request.average)

    def task(self, request: ScalingRequest, L: int, count: int, index: int, block: int,
             thresholds: np.ndarray) -> tuple[Callable[..., np.ndarray], tuple[Any, ...]]:
        return network_ensembles.block_task, (request.model, L, count, request.seed, index, block, thresholds,
                                              request.average)

    def size_blocks(self, request: ScalingRequest, L: int, rows: np.ndarray, thresholds: np.ndarray) -> SizeBlocks:
        T = thresholds.size
        rows = _floats(rows)
        count, contacts = rows[:, 3 * T], rows[:, 3 * T + 1]
        M = int(round(float(contacts @ count / count.sum())))  # sums of s^2 / M_block, times M: <s^2>/M exactly
        return SizeBlocks(float(M), M, thresholds, rows[:, :T] * M, rows[:, T:2 * T] * M, rows[:, 2 * T:3 * T],
                          count, label=float(L))

    def record_shape(self, thresholds: np.ndarray) -> tuple[int]:
        """A block's record: the three sums, the count, the contacts ``M`` and the autocorrelation time, as bits."""
        return (3 * thresholds.size + 3,)

    def details(self, request: ScalingRequest, rows: list[np.ndarray], thresholds: np.ndarray) -> dict[str, Any]:
        T = thresholds.size
        return {"thin_sweeps": [network_ensembles.THIN_PER_LAYER * L for L in request.sizes],
                "tau_recorded": [round(float(_floats(r)[:, 3 * T + 2].max()), 2) for r in rows],
                "average": request.average if request.model == "averaged" else 1}


def _register() -> None:
    """Register the models' engines (this module is the registry's loader for them)."""
    REGISTRY.register(UnionFindEngine("percolation"))
    REGISTRY.register(UnionFindEngine("q-independent"))
    REGISTRY.register(HeatBathEngine())
    for model in network_ensembles.NETWORK_MODELS:
        REGISTRY.register(LocalHitAndRunEngine(model))


_register()
