"""Per-prime tasks, shared by the free-fermion and the de Bruijn routes: where they run, their checkpoint records,
and the one plan of a run over primes with its constants.

Both Pfaffian routes compute modulo word-size primes, one independent task
per prime, and rebuild the exact integers by Chinese remaindering
(:func:`forcenet.exact.modular.crt_many`).  The tasks run on an executor by
:func:`forcenet.core.execution.run_tasks`: any
:class:`concurrent.futures.Executor` (a Dask cluster's included), else a
local process pool when the run pays for starting it
(:data:`PARALLEL_MIN_SECONDS`), else this process.  :func:`primes_plan` is
the plan of such a run, the executor's workers counted; each route supplies
its CPU seconds per prime, its bytes per worker and its compiled kernels.

Examples
--------
>>> plan = primes_plan("x", 2.0, 10, 2**20, workers=2)
>>> plan.ticks, plan.unit, plan.seconds == 2 * STARTUP_SECONDS + 5 * 2.0
(10, 'prime', True)
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from concurrent.futures import Executor
from os import PathLike
from typing import Any

from forcenet.core.checkpoints import CheckpointStore
from forcenet.core.execution import (
    as_executor,
    available_cores,
    executor_label,
    executor_workers,
    run_tasks,
    wall_seconds,
)
from forcenet.core.plan import Plan
from forcenet.core.validation import check_int

__all__ = ["STARTUP_SECONDS", "WORKER_BASE_BYTES", "WORKER_TASK_SECONDS", "CLIENT_TASK_SECONDS",
           "PARALLEL_MIN_SECONDS", "ROUTES", "record_shape", "checkpoint_store", "run_primes", "workers_for", "primes_plan"]

STARTUP_SECONDS = 1.5  # numba import and loading the cached kernels (first compilation ever: ~10 s more)
WORKER_BASE_BYTES = 160 * 2**20  # a worker process: the interpreter, numpy and the loaded kernels
# a Dask cluster's cost per task on loopback (notes/benchmarks.md, `python benchmarks/cluster.py overhead 200`):
WORKER_TASK_SECONDS = 0.0102  # on the worker, in parallel with the other workers
CLIENT_TASK_SECONDS = 0.0075  # in the client, the scheduler and the nanny, one task after the other
# parallel from here: the workers start at once (each ~STARTUP_SECONDS), so 2 workers pay once half the work
# exceeds a start-up; on a 2-core host, table N = 34 (1.7 s) in 2 workers 0.76x the wall, N = 40 (5.4 s) 0.56x
# (notes/benchmarks.md); 20 s before, which left N = 40-48 on one core
PARALLEL_MIN_SECONDS = 2 * STARTUP_SECONDS
ROUTES = {"count": "pfaffian-count", "table": "pfaffian-table", "table2": "pfaffian-table-second",
          "lattice": "pfaffian-lattice",
          "floor": "pfaffian-floor", "floor-grains": "pfaffian-floor-grains",
          "layer": "pfaffian-layer", "layer-grains": "pfaffian-layer-grains"}  # checkpoint names (a layer's: + i)


def record_shape(route: str, N: int) -> tuple[int, ...] | None:
    """The shape of every checkpoint record of the free-fermion ``route`` (a key of :data:`ROUTES`) at ``N``: one
    prime's residues as its task returns them; None for the de Bruijn routes, whose stores are given their
    shape by their callers (``floor.py``, ``layers.py``: a gap law of ``d + 2`` gaps per row).

    ``count``: one residue; ``table``: ``S[m][k] mod p``, ``m, k = 0..n``
    (Eqs. (4.63)-(4.77)); ``table2``: that and the second level; ``lattice``:
    the first column.  A record of another shape (a valid checksum on the
    wrong content) is named and recomputed
    (:class:`~forcenet.core.checkpoints.CheckpointStore`).

    Examples
    --------
    >>> record_shape("table", 5), record_shape("table2", 5), record_shape("lattice", 5), record_shape("floor", 5)
    ((5, 5), (2, 5, 5), (5,), None)
    """
    return {"count": (), "table": (N, N), "table2": (2, N, N), "lattice": (N,)}.get(route)


def checkpoint_store(checkpoint: str | PathLike | CheckpointStore | None, route: str, N: int,
                     layer: int | None = None, shape: tuple[int, ...] | None = None) -> CheckpointStore | None:
    """The checkpoint store of one request of ``route`` (a key of :data:`ROUTES`, with the ``layer`` of a layer's
    route): None, from a directory, or a given store (reused when it is this request's, else its directory and
    report); its records' ``shape`` is the route's (:func:`record_shape`) unless given.

    Examples
    --------
    >>> checkpoint_store(None, "table", 12) is None
    True
    """
    if checkpoint is None:
        return None
    name = ROUTES[route] + ("" if layer is None else f"{int(layer)}")
    shape = record_shape(route, N) if shape is None else shape
    if isinstance(checkpoint, CheckpointStore):
        if checkpoint.request["route"] == name and checkpoint.request["N"] == N:
            if shape is not None:
                checkpoint.shape = tuple(shape)
            return checkpoint
        return CheckpointStore(checkpoint.directory, name, N, report=checkpoint.report, shape=shape)
    return CheckpointStore(checkpoint, name, N, shape=shape)


def run_primes(function: Callable[..., Any], tasks: Sequence[tuple], executor: Executor | None, nworkers: int,
               progress: Callable[..., Any] | None, store: CheckpointStore | None) -> list:
    """``[function(*task)]`` over the tasks (``task[1]`` is the prime, the checkpoint key), in task order.

    On ``executor``, else in ``nworkers`` local processes (spawn: the parent
    may hold threads, the children load the cached kernels).

    Examples
    --------
    >>> from operator import mul
    >>> run_primes(mul, [(2, 3), (2, 5)], None, 1, None, None)
    [6, 10]
    """
    return run_tasks(function, tasks, executor=executor, workers=nworkers, progress=progress, store=store,
                     keys=[task[1] for task in tasks])


def workers_for(workers: int | None, tasks: int, seconds: float, executor: Executor | None = None) -> int:
    """Tasks run at once: the executor's workers, else ``workers`` local processes (default: the available cores
    when ``seconds`` of CPU pay for starting them, else 1), never more than ``tasks``.

    Examples
    --------
    >>> workers_for(None, 40, 1.0)
    1
    >>> workers_for(3, 2, 100.0)
    2
    """
    if executor is not None:
        return max(1, executor_workers(as_executor(executor)) or 1)
    if workers is None:  # the default: no user's number to check
        return max(1, min(available_cores() if seconds >= PARALLEL_MIN_SECONDS else 1, tasks))
    return max(1, min(check_int(workers, "workers", 1), tasks))


def primes_plan(what: str, per_prime: float, nprimes: int, per_worker: int, *, workers: int | None = None,
                executor: Executor | None = None, store: CheckpointStore | None = None, reused: int = 0,
                crt_seconds: float = 0.0, memory_bytes: int | None = None,
                compile: Callable[[Plan, bool], Plan] | None = None) -> Plan:
    """The plan of a run over ``nprimes`` primes, one tick per prime: the one formula of every route over primes.

    ``per_prime`` CPU seconds each, the ``reused`` primes (recorded in
    ``store``) not counted, spread over the workers (:func:`workers_for`:
    those of ``executor``, else local processes) in rounds
    (:func:`~forcenet.core.execution.wall_seconds`, with the scheduler's
    cost per task on an executor, whose serial share in the client bounds
    the run from below); the start-up of this process and of the workers;
    then ``crt_seconds`` in the client (the Chinese remaindering).  Memory:
    ``per_worker`` bytes per local worker (a cluster's workers hold their
    share on their own machines); ``compile`` adds compiling the kernels when
    the run is local (a cluster's workers compile on their own machines);
    refused beyond ``memory_bytes``.

    Parameters
    ----------
    what : str
        What the plan computes (its announcement).
    per_prime : float
        CPU seconds of one prime on the reference machine.
    nprimes : int
        Primes of the run.
    per_worker : int
        Peak bytes of one worker.
    workers : int, optional
        Local worker processes (default: the cores when the run pays for them).
    executor : concurrent.futures.Executor or Dask Client, optional
        Runs the tasks; the plan counts its workers.
    store : CheckpointStore, optional
        The run's checkpoints (named in the announcement).
    reused : int
        Primes already recorded in ``store``.
    crt_seconds : float
        The client's seconds after the primes.
    memory_bytes : int, optional
        Memory available to the run (None: not checked).
    compile : callable, optional
        ``compile(plan, in_workers)``: the plan plus compiling the route's kernels (a local run only;
        ``in_workers``: in local worker processes, which compile for their own CPU features).

    Returns
    -------
    Plan

    Examples
    --------
    >>> from concurrent.futures import ThreadPoolExecutor
    >>> from forcenet.core.execution import declare_workers
    >>> with declare_workers(ThreadPoolExecutor(max_workers=4), 4) as pool:
    ...     on_four = primes_plan("x", 10.0, 8, 2**20, executor=pool)
    >>> primes_plan("x", 10.0, 8, 2**20, workers=1).seconds > on_four.seconds
    True
    """
    todo = nprimes - reused
    executor = as_executor(executor)
    nworkers = workers_for(workers, max(1, todo), per_prime * todo, executor)
    overhead = WORKER_TASK_SECONDS if executor is not None else 0.0
    work = wall_seconds(per_prime, todo, nworkers, overhead)
    if executor is not None:  # the scheduler's serial share bounds the run from below
        work = max(work, CLIENT_TASK_SECONDS * todo)
    seconds = STARTUP_SECONDS * (1 + (nworkers > 1)) + work + crt_seconds
    if executor is not None:
        what += f" on {nworkers} worker{'s' if nworkers > 1 else ''} of {executor_label(executor)}"
    if store is not None:
        what += f"; checkpoints in {store.path}: {reused} of {nprimes} primes recorded"
    local = 1 if executor is not None else nworkers  # a cluster's workers hold their share on their own machines
    plan = Plan(what, seconds, local * per_worker, nprimes, "prime").within_memory(memory_bytes)
    if executor is None and compile is not None:  # a cluster's workers compile (or load) on their own machines
        plan = compile(plan, nworkers > 1)  # local workers compile for their own CPU features
    return plan
