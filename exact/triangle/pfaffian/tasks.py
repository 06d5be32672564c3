"""The Pfaffian route's independent tasks: its primes, where they run, and their checkpoint records.

One task per word-size prime (:func:`forcenet.exact.triangle.pfaffian.engine.prime_residues`
and its siblings); the primes come from :func:`forcenet.exact.modular.primes_for_bound`
below the kernels' :func:`~.engine.prime_limit`, and the residues go back
through :func:`forcenet.exact.modular.crt_many`.  The tasks run on an
executor by :func:`forcenet.core.execution.run_tasks`: any
:class:`concurrent.futures.Executor`, else a local process pool when the run
pays for starting it (:data:`PARALLEL_MIN_SECONDS`), else this process.

Examples
--------
>>> route_primes(32, 10**15)
(33554393, 33554383)
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from concurrent.futures import Executor
from os import PathLike
from typing import Any

from forcenet.core.checkpoints import CheckpointStore
from forcenet.core.execution import as_executor, available_cores, executor_workers, run_tasks
from ...modular import primes_for_bound
from forcenet.core.validation import check_int
from ..staircase import dimension
from .engine import prime_limit

__all__ = ["PARALLEL_MIN_SECONDS", "ROUTES", "route_primes", "checkpoint_store", "run_primes", "workers_for"]

PARALLEL_MIN_SECONDS = 20.0  # below this, starting workers (numba import, ~3 s each) costs more than it saves
ROUTES = {"count": "pfaffian-count", "table": "pfaffian-table", "table2": "pfaffian-table-second",
          "lattice": "pfaffian-lattice",
          "floor": "pfaffian-floor", "floor-grains": "pfaffian-floor-grains",
          "layer": "pfaffian-layer", "layer-grains": "pfaffian-layer-grains"}  # checkpoint names (a layer's: + i)


def route_primes(N: int, bound: int) -> tuple[int, ...]:
    """The primes of the route for ``N`` layers whose product exceeds ``bound``, largest first.

    Below :func:`~.engine.prime_limit` (the kernels' word-size bound) and
    above ``max(2N + 3, d + 2)`` (the level points and the kernel's sizes
    must stay distinct modulo the prime).  A non-negative integer ``<= bound``
    is then determined by its residues (:func:`~forcenet.exact.modular.primes_for_bound`).

    Examples
    --------
    >>> route_primes(10, 33554393)
    (33554393, 33554383)
    """
    return primes_for_bound(bound, limit=prime_limit(max(N - 1, 1)), smallest=max(2 * N + 3, dimension(N) + 2))


def checkpoint_store(checkpoint: str | PathLike | CheckpointStore | None, route: str, N: int,
                     layer: int | None = None) -> CheckpointStore | None:
    """The checkpoint store of one request of ``route`` (a key of :data:`ROUTES`, with the ``layer`` of a layer's
    route): None, from a directory, or a given store (reused when it is this request's, else its directory and
    report).

    Examples
    --------
    >>> checkpoint_store(None, "table", 12) is None
    True
    """
    if checkpoint is None:
        return None
    name = ROUTES[route] + ("" if layer is None else f"{int(layer)}")
    if isinstance(checkpoint, CheckpointStore):
        if checkpoint.request["route"] == name and checkpoint.request["N"] == N:
            return checkpoint
        return CheckpointStore(checkpoint.directory, name, N, report=checkpoint.report)
    return CheckpointStore(checkpoint, name, N)


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
    if workers is None:
        workers = available_cores() if seconds >= PARALLEL_MIN_SECONDS else 1
    workers = check_int(workers, "workers", 1)
    return max(1, min(workers, tasks))
