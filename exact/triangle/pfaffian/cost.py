"""The Pfaffian route's cost model: CPU seconds per prime, the primes, the workers, the plan of a run.

Measured on the 2-core reference machine (numba 0.68, AVX-512) and fitted on
``N = 20, 100`` (``notes/benchmarks.md``): one prime of the table costs
``O(n^5)`` (``d/2`` level points, ``n + 1`` values of ``y``, an ``O(n^2)``
displacement elimination each), the lattice directions two eliminations per
level point; the client's Chinese remaindering is quadratic in the number of
primes.

Examples
--------
>>> prime_seconds(40) > edge_seconds(40) > 0
True
"""

from __future__ import annotations

from concurrent.futures import Executor
from math import ceil, log2

from forcenet.core.checkpoints import CheckpointStore
from forcenet.core.execution import as_executor, executor_label, wall_seconds
from forcenet.core.plan import Plan
from ..staircase import count, dimension
from .engine import level_points, prime_limit, with_kernels_compiled
from .tasks import route_primes, workers_for

__all__ = ["STARTUP_SECONDS", "WORKER_TASK_SECONDS", "CLIENT_TASK_SECONDS", "CRT_SECONDS", "prime_seconds", "edge_seconds", "primes_plan"]

# CPU seconds; notes/benchmarks.md
_SECONDS_PER_ROW = 1.14e-9  # per n^2 and y: the displacement elimination (n pivots of O(n) rows), fitted on N = 20, 100
_SECONDS_PER_PIVOT = 3.1e-8  # per n and y: a pivot's set-up (reading the pivot, the lanes' loop overhead)
# per s^3 of the kernel set-up (four solves with K(q), s = n + 1 or n + 2); 3.3e-10 with the Gauss-Jordan solve,
# scaled by 0.77, the measured ratio per prime of the lattice directions at N = 120 after the solve became an
# elimination with back substitution (2026-11-26, notes/benchmarks.md), and by 0.57, the measured ratio of the
# kernel set-up at N = 152 after K(c) got the skew-symmetric elimination (s^3/6) and one chain of powers
# (2026-11-27: 1.05 -> 0.59 ms per level point; per prime 6.6 -> 4.4 s, notes/benchmarks.md)
_SECONDS_PER_KERNEL = 1.43e-10
_SECONDS_PER_WEIGHT = 9e-9  # per M^2: the weights of the level functional, the sums over the points, the set-up
STARTUP_SECONDS = 1.5  # numba import and loading the cached kernels (first compilation ever: ~10 s more)
# a Dask cluster's cost per task on loopback (notes/benchmarks.md, `python benchmarks/cluster.py overhead 200`):
WORKER_TASK_SECONDS = 0.0102  # on the worker, in parallel with the other workers
CLIENT_TASK_SECONDS = 0.0075  # in the client, the scheduler and the nanny, one task after the other
CRT_SECONDS = 2.3e-9  # per reconstructed entry and prime^2: the client's Chinese remaindering (benchmarks)
WORKER_BASE_BYTES = 160 * 2**20  # a worker process: the interpreter, numpy and the loaded kernels


def worker_bytes(N: int, rows: int) -> int:
    """Peak bytes of one worker of a per-prime task: ``rows`` int64 rows of length ``n`` per paired level point.

    The table keeps ``n + 2`` rows per point (``y = 0..n`` and the two
    bordering ones), the lattice directions 2.

    Examples
    --------
    >>> worker_bytes(40, 2) < worker_bytes(40, 41) < 2 * WORKER_BASE_BYTES
    True
    """
    n = N - 1
    return level_points(dimension(N)) // 2 * rows * n * 8 + WORKER_BASE_BYTES


def prime_seconds(N: int) -> float:
    """CPU seconds of one prime of the table (:func:`~.engine.prime_residues`), ``N >= 2``.

    Examples
    --------
    >>> 0 < prime_seconds(20) < prime_seconds(40)
    True
    """
    n = N - 1
    return _per_point_seconds(N, 2 * ((n + 1) // 2))  # y = 0..n, paired


def edge_seconds(N: int) -> float:
    """CPU seconds of one prime of the lattice directions (:func:`~.engine.edge_residues`), ``N >= 2``.

    Examples
    --------
    >>> 0 < edge_seconds(20) < prime_seconds(20)
    True
    """
    return _per_point_seconds(N, 2)  # two eliminations per level point


def _per_point_seconds(N: int, eliminations: int) -> float:
    """``d/2`` level points, each ``eliminations`` displacement eliminations and one kernel set-up, then the weights."""
    n, d = N - 1, dimension(N)
    s = n + 1 + (n + 1) % 2
    per_y = _SECONDS_PER_PIVOT * n + _SECONDS_PER_ROW * n**2
    M = level_points(d)
    return M // 2 * (eliminations * per_y + _SECONDS_PER_KERNEL * s**3) + _SECONDS_PER_WEIGHT * M**2 + 1e-3


def primes_plan(what: str, N: int, per_prime: float, per_worker: int, workers: int | None, executor: Executor | None,
                store: CheckpointStore | None, memory_bytes: int | None, entries: int, lattice: bool,
                bound_factor: int = 1) -> Plan:
    """The plan of a run over the route's primes.

    ``per_prime`` CPU seconds each, spread over the workers (those of
    ``executor``, else local processes), the primes recorded in ``store`` not
    counted; then the client's Chinese remaindering of ``entries`` integers
    (quadratic in the number of primes; the integers are below ``bound_factor
    (d + 1) count``); compiling the kernels first when this
    machine's cache lacks them (a local run); refused beyond ``memory_bytes``.

    Examples
    --------
    >>> primes_plan("x", 12, 0.01, 2**20, 1, None, None, None, 121, False).unit
    'prime'
    """
    n, d = N - 1, dimension(N)
    bound = (d + 1) * count(N) * bound_factor  # the survival sums' bound: what the primes' product must exceed
    nprimes = ceil(bound.bit_length() / log2(prime_limit(max(n, 1)) * 0.999))
    reused = 0
    if store is not None:
        primes = route_primes(N, bound)
        nprimes, reused = len(primes), sum(store.holds(p) for p in primes)
    executor = as_executor(executor)
    nworkers = workers_for(workers, max(1, nprimes - reused), per_prime * (nprimes - reused), executor)
    overhead = WORKER_TASK_SECONDS if executor is not None else 0.0
    work = wall_seconds(per_prime, nprimes - reused, nworkers, overhead)
    if executor is not None:  # the scheduler's serial share bounds the run from below
        work = max(work, CLIENT_TASK_SECONDS * (nprimes - reused))
    seconds = (STARTUP_SECONDS * (1 + (nworkers > 1)) + work
               + CRT_SECONDS * entries * nprimes**2)
    if executor is not None:
        what += f" on {nworkers} worker{'s' if nworkers > 1 else ''} of {executor_label(executor)}"
    if store is not None:
        what += f"; checkpoints in {store.path}: {reused} of {nprimes} primes recorded"
    local = 1 if executor is not None else nworkers  # a cluster's workers hold their share on their own machines
    plan = Plan(what, seconds, local * per_worker, nprimes, "prime")
    if executor is None:  # the workers compile (or load) the kernels on their own machines
        plan = with_kernels_compiled(plan, lattice)
    return plan.within_memory(memory_bytes)
