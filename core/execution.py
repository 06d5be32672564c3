"""Independent tasks on an executor: the one engine of every multi-modular route.

The per-prime tasks of the Pfaffian route (and the independent chains of
``forcenet sample``) are handed to a :class:`concurrent.futures.Executor`:
a local process pool by default (the standard library, nothing more), or
any executor the caller gives, e.g. Dask's ``Client.get_executor()`` for a
cluster.  No scheduler is written here; this module only

* submits the tasks a checkpoint store does not already hold,
* collects the results in the order of the tasks (the same result, hence
  the same bytes, for any number of workers and any completion order),
* reports progress per finished task and records each result in the store
  (:mod:`forcenet.core.checkpoints`) as it arrives,
* runs every task through :func:`worker_call`, which readies the process
  it lands in once: glibc's allocator back to its steady state when the
  environment fixed it (a Dask nanny starts its workers with
  ``MALLOC_TRIM_THRESHOLD_=65536``, which also freezes the threshold above
  which ``malloc`` maps fresh pages, so every kernel's work arrays of over
  128 KiB were mapped, page-faulted and unmapped again: 35 000 page faults
  and a sixth more CPU per prime at N = 64, ``notes/benchmarks.md``), and
  the BLAS/OpenMP pools to one thread (a task is one core's work);
* starts a local pool's workers without the caller's main module
  (:func:`~forcenet.core.lifetime.workers_without_main`), so a script
  without ``if __name__ == "__main__":``, stdin, ``python -c``, IPython
  and Jupyter all work;
* is interruptible: on ``KeyboardInterrupt`` (or a failed task) the pending
  futures are cancelled and the workers of a pool it started are terminated
  at once, so Ctrl-C ends the run within a second or two even while workers
  sit inside compiled kernels; the exception is then re-raised.

Examples
--------
>>> from operator import mul
>>> run_tasks(mul, [(2, 3), (4, 5)])
[6, 20]
>>> wall_seconds(per_task=2.0, tasks=10, workers=4, overhead=0.5)
7.5
"""

from __future__ import annotations

import multiprocessing
import multiprocessing.resource_tracker
import os
import signal
import sys
import time
import weakref
from collections.abc import Callable, Iterable
from concurrent.futures import FIRST_COMPLETED, BrokenExecutor, CancelledError, Executor, ProcessPoolExecutor, wait
from math import ceil
from typing import TYPE_CHECKING, Any

from forcenet.core.compiled import prefer_wide_vectors
from forcenet.core.errors import ArgumentError, ArgumentTypeError, ClusterError
from forcenet.core.lifetime import deaf_to_hangups, die_with_parent, quiet_broken_pools, workers_without_main
from forcenet.core.validation import check_int
from forcenet.core.worker_readiness import worker_call

if TYPE_CHECKING:
    from concurrent.futures import ProcessPoolExecutor


__all__ = ["ClusterError", "WORKERLESS_SECONDS", "PROBE_SECONDS", "available_cores", "local_pool", "as_executor",
           "declare_workers", "executor_workers", "executor_label", "check_cluster", "wall_seconds", "run_tasks"]

WORKERLESS_SECONDS = 10.0  # a Dask cluster without a worker (or its scheduler gone) that long fails the run
_POLL_SECONDS = 0.5  # how often a cluster run looks at its workers while no task finishes
PROBE_SECONDS = 10.0  # a cluster's workers answer the probe task (import forcenet, its version) within this

# Our own bookkeeping of the executors made here, never the private attributes of concurrent.futures or Dask:
# how many tasks each runs at once, the Dask client behind an executor, the worker pids of a local pool.
_WORKERS: weakref.WeakKeyDictionary[Any, int] = weakref.WeakKeyDictionary()
_CLIENTS: weakref.WeakKeyDictionary[Any, Any] = weakref.WeakKeyDictionary()
_PIDS: weakref.WeakKeyDictionary[Any, Any] = weakref.WeakKeyDictionary()  # a local pool: the queue its workers
# report their pid to (forcenet.core.lifetime.die_with_parent)
_PROBED: weakref.WeakSet[Any] = weakref.WeakSet()  # the Dask clients whose workers import forcenet
_SPAWNED: weakref.WeakKeyDictionary[Any, list[Any]] = weakref.WeakKeyDictionary()  # a local pool: the child
# processes its submit calls started (multiprocessing.active_children before and after), reported or not


def available_cores() -> int:
    """Cores this process may run on (its affinity), at least 1.

    Examples
    --------
    >>> available_cores() >= 1
    True
    """
    if hasattr(os, "sched_getaffinity"):
        return max(1, len(os.sched_getaffinity(0)))
    return os.cpu_count() or 1  # pragma: no cover - platforms without affinity


def as_executor(executor: Any) -> Executor | None:
    """``executor`` as a :class:`concurrent.futures.Executor`: a Dask ``Client`` gives its ``get_executor()``.

    Parameters
    ----------
    executor : Executor, object with ``get_executor()``, or None

    Returns
    -------
    Executor or None

    Raises
    ------
    ArgumentTypeError
        If ``executor`` is neither.

    Examples
    --------
    >>> as_executor(None) is None
    True
    >>> as_executor(3)
    Traceback (most recent call last):
    ...
    forcenet.core.errors.ArgumentTypeError: executor=3 is not a concurrent.futures.Executor (nor a Dask Client)
    """
    if executor is None or isinstance(executor, Executor):
        return executor
    if callable(getattr(executor, "get_executor", None)):
        made = executor.get_executor()
        _CLIENTS[made] = executor  # the client is ours to know (Client.get_executor() keeps it private)
        return made
    raise ArgumentTypeError(f"executor={executor!r} is not a concurrent.futures.Executor (nor a Dask Client)")


def declare_workers(executor: Executor, workers: int) -> Executor:
    """Tell forcenet how many tasks ``executor`` runs at once (its plans divide the work by it); returns it.

    The pools made here (:func:`local_pool`) and Dask clients are known
    already; a pool of your own is otherwise planned as one worker.

    Examples
    --------
    >>> from concurrent.futures import ThreadPoolExecutor
    >>> with declare_workers(ThreadPoolExecutor(3), 3) as pool:
    ...     executor_workers(pool)
    3
    """
    _WORKERS[executor] = check_int(workers, "workers", 1)
    return executor


def _dask_client(executor: Any) -> Any:
    """The Dask client behind ``executor``: the one :func:`as_executor` made it from, else, for an executor of
    Dask's own (``client.get_executor()`` given directly), Dask's current client (``distributed.get_client``)."""
    client = _CLIENTS.get(executor)
    if client is not None or not type(executor).__module__.startswith("distributed"):
        return client
    try:
        from distributed import get_client

        return get_client()
    except (ImportError, ValueError):  # no client in this process: treated as any executor
        return None


def executor_workers(executor: Any) -> int | None:
    """How many tasks ``executor`` runs at once: a pool's workers, a Dask cluster's threads; None if unknown.

    Known for the pools made by :func:`local_pool`, the executors given to
    :func:`declare_workers` and Dask clients (their threads, asked of the
    scheduler); None for any other executor.

    Examples
    --------
    >>> with local_pool(2) as pool:
    ...     executor_workers(pool)
    2
    >>> from concurrent.futures import ThreadPoolExecutor
    >>> with ThreadPoolExecutor(3) as pool:
    ...     executor_workers(pool) is None
    True
    """
    executor = as_executor(executor)
    client = _dask_client(executor)
    if client is not None:
        try:
            threads = client.nthreads()
        except Exception as exc:  # the scheduler gone since the client connected
            raise ClusterError(f"the Dask cluster cannot be reached ({type(exc).__name__}): its scheduler went away; "
                               "rerun (finished primes are kept with --checkpoint)") from None
        return max(1, sum(threads.values()))
    return _WORKERS.get(executor)


def executor_label(executor: Any) -> str:
    """Where an executor runs its tasks, for announcements: ``"Dask scheduler tcp://..."`` or its class name.

    Examples
    --------
    >>> from concurrent.futures import ThreadPoolExecutor
    >>> with ThreadPoolExecutor(1) as pool:
    ...     executor_label(pool)
    'ThreadPoolExecutor'
    """
    executor = as_executor(executor)
    address = getattr(getattr(_dask_client(executor), "scheduler", None), "address", None)
    if address:
        return f"Dask scheduler {address}"
    # Dask's own executor class (ClientExecutor) is internal: name the cluster instead
    return "a Dask cluster" if type(executor).__module__.startswith("distributed") else type(executor).__name__


# The probe: a builtin (``eval``, unpickled by any Python) evaluating an import of forcenet on the worker. A task
# of forcenet's own code cannot be the probe: a worker without forcenet fails to unpickle it while reading the
# scheduler's message and leaves the cluster (Dask 2026.8), so the client would only see its workers vanish.
_PROBE = "__import__('forcenet').__version__"


def check_cluster(client: Any, seconds: float | None = None) -> str:
    """Run one tiny task on the cluster of ``client`` that imports forcenet; the workers' forcenet version.

    The task is Python's ``eval`` of an import of forcenet (nothing of
    forcenet to unpickle), so a worker without forcenet fails it at once
    with the import's error, and the run is refused in seconds, naming the
    cause, instead of waiting for workers that leave the cluster when a
    task of forcenet's code cannot be unpickled.  Done once per client (a
    run over a client probes on its first tasks).

    Parameters
    ----------
    client : distributed.Client
        The cluster's client.
    seconds : float, optional
        The bound on the probe (default :data:`PROBE_SECONDS`).

    Returns
    -------
    str
        The version of forcenet on the worker that ran the probe.

    Raises
    ------
    ClusterError
        One line: the workers cannot import forcenet (the import's error
        named), or run another version, or no worker answers in time.

    Examples
    --------
    >>> class Inline:  # a stand-in for a client: runs the task here
    ...     def submit(self, f, *args, pure=True):
    ...         from concurrent.futures import Future
    ...         future = Future(); future.set_result(f(*args)); return future
    >>> import forcenet
    >>> check_cluster(Inline()) == forcenet.__version__
    True
    """
    seconds = PROBE_SECONDS if seconds is None else seconds
    future = client.submit(eval, _PROBE, {}, pure=False)
    try:
        version = future.result(timeout=seconds)
    except ImportError as exc:  # unpickling the probe on the worker imported forcenet, and failed
        raise ClusterError(f"the cluster's workers cannot import forcenet ({type(exc).__name__}: "
                           f"{str(exc).splitlines()[0] if str(exc) else ''}): install forcenet on every worker"
                           ) from None
    except TimeoutError:
        raise ClusterError(f"no worker of the cluster ran a first tiny task within {seconds:g} s (its workers are "
                           "busy, stuck or gone): start workers with forcenet installed and rerun") from None
    except CancelledError:
        raise ClusterError("the cluster cancelled its first task: its scheduler went away; rerun") from None
    except OSError as exc:
        if type(exc).__module__.startswith("distributed"):  # CommClosedError and its kind
            raise ClusterError(f"the cluster lost the connection ({type(exc).__name__}); rerun") from None
        raise
    finally:
        try:
            future.cancel()
        except Exception:  # the scheduler gone: the failure being raised is the one to report
            pass
    ours = sys.modules["forcenet"].__version__  # imported with this module (its package's parent)
    if version != ours:
        raise ClusterError(f"the cluster's workers run forcenet {version}, this process {ours}: "
                           "install the same version on every worker")
    _PROBED.add(client)
    return version


def wall_seconds(per_task: float, tasks: int, workers: int, overhead: float = 0.0) -> float:
    """Wall time of ``tasks`` equal tasks on ``workers``: ``ceil(tasks / workers)`` rounds of ``per_task + overhead``.

    ``overhead`` is the scheduler's cost per task (submission, transfer of
    the result), measured in ``notes/benchmarks.md``.
    """
    return ceil(tasks / max(1, workers)) * (per_task + overhead)


def local_pool(workers: int, start_method: str = "spawn") -> ProcessPoolExecutor:
    """A local :class:`~concurrent.futures.ProcessPoolExecutor` whose workers die with this process.

    Every worker runs :func:`~forcenet.core.lifetime.die_with_parent` first
    (a module of the standard library alone, so a spawned worker arms it
    within a fraction of a second, before the seconds of importing the
    route's modules), and a parent killed by SIGKILL, the OOM killer or a
    time limit leaves no worker computing.  On an AVX-512 machine the
    workers compile the kernels with 512-bit vectors, as the command line
    does (:func:`_start_worker`); this process is left as it is.

    Parameters
    ----------
    workers : int
        Worker processes.
    start_method : str
        ``"spawn"``, ``"fork"`` or ``"forkserver"`` (:mod:`multiprocessing`).

    Returns
    -------
    concurrent.futures.ProcessPoolExecutor

    Examples
    --------
    >>> with local_pool(1) as pool:
    ...     pool.submit(abs, -3).result()
    3
    """

    deaf_to_hangups(multiprocessing.resource_tracker.ensure_running)
    context = multiprocessing.get_context(start_method)
    started = context.SimpleQueue()  # each worker's pid, put by its initializer: the workers we stop
    pool = ProcessPoolExecutor(workers, mp_context=context, initializer=_start_worker,
                               initargs=(os.getpid(), started))
    _WORKERS[pool] = workers
    _PIDS[pool] = started
    return pool


def _start_worker(parent: int, started: Any) -> None:
    """A local pool's worker: Ctrl-C is its parent's to handle (the parent stops its workers), and it dies with it.

    Before numba is imported, the worker takes 512-bit vectors on an AVX-512 machine
    (:func:`~forcenet.core.compiled.prefer_wide_vectors`), as the command line's processes do: a table from
    Python costs what ``forcenet table`` costs, and the caller's own process and numba are left as they are.
    """
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    die_with_parent(parent, started)
    prefer_wide_vectors()  # nothing when the caller chose NUMBA_CPU_FEATURES / NUMBA_CPU_NAME, or numba is loaded


def _terminate(pool: Any) -> None:
    """Stop a local process pool now: pending work cancelled, worker processes terminated (then killed).

    The workers are the children of this process (``multiprocessing.active_children``) whose pid the pool's
    initializer reported, and those its ``submit`` calls started that had not reported yet (:func:`_submit_local`):
    a worker still unpickling its start-up when this process has gone prints a traceback (a semaphore or a pipe
    already closed) after "interrupted".
    """

    started = _PIDS.get(pool)
    pids = set()
    while started is not None and not started.empty():
        pids.add(started.get())
    processes = [p for p in multiprocessing.active_children() if p.pid in pids]
    processes += [p for p in _SPAWNED.get(pool, ()) if p.pid not in pids]
    quiet_broken_pools()
    pool.shutdown(wait=False, cancel_futures=True)
    for process in processes:
        if process.is_alive():
            process.terminate()
    for process in processes:
        process.join(1.0)
        if process.is_alive():  # pragma: no cover - a worker ignoring SIGTERM
            process.kill()
            process.join(1.0)


def _submit_local(pool: Executor, calls: list[tuple[Any, ...]]) -> list[Any]:
    """``pool.submit(*call)`` for each call of a local pool (:func:`local_pool`), every one inside
    :func:`~forcenet.core.lifetime.workers_without_main` (the workers start in these calls: without the caller's
    script, interrupts held until they have), and the child processes they started recorded for
    :func:`_terminate` (reported or not)."""
    with workers_without_main():
        before = set(multiprocessing.active_children())
        try:
            return [pool.submit(*call) for call in calls]
        finally:
            _SPAWNED[pool] = [p for p in multiprocessing.active_children() if p not in before]


def _cluster_workers(client: Any) -> int | None:
    """The workers a Dask client knows of (its scheduler's last report, no round trip); 0 once it is closed."""
    if getattr(client, "status", "running") in ("closed", "closing", "failed"):
        return 0
    try:
        return len(client.scheduler_info().get("workers", {}))
    except Exception:  # the scheduler gone: counted as no worker
        return 0


def _cluster_result(future: Any, label: str) -> Any:
    """A cluster task's result; the cluster's own failures as :class:`ClusterError`, a task's error as it is."""
    try:
        return future.result()
    except CancelledError:
        raise ClusterError(f"{label} cancelled the run's tasks: its scheduler went away or closed the connection; "
                           "rerun (finished primes are kept with --checkpoint)") from None
    except ImportError as exc:  # the task could not be unpickled or run on the worker
        raise ClusterError(f"a worker of {label} cannot import forcenet ({type(exc).__name__}: {exc}): install "
                           "forcenet, the same version, on every worker") from None
    except OSError as exc:
        if type(exc).__module__.startswith("distributed"):  # CommClosedError and its kind
            raise ClusterError(f"{label} lost the connection ({type(exc).__name__}); rerun") from None
        raise


def _collect_from_cluster(futures: dict, finish: Callable[[int, Any], object], client: Any) -> None:
    """``finish(i, result)`` per finished task of a Dask cluster, bounded: a run whose cluster has no worker (or no
    scheduler) for :data:`WORKERLESS_SECONDS` fails with :class:`ClusterError` instead of waiting for ever."""
    label = executor_label(client.get_executor()) if callable(getattr(client, "get_executor", None)) else "the cluster"
    waiting = set(futures)
    idle_since: float | None = None
    while waiting:
        done, waiting = wait(waiting, timeout=_POLL_SECONDS, return_when=FIRST_COMPLETED)
        for future in done:
            finish(futures[future], _cluster_result(future, label))
        if done or _cluster_workers(client):
            idle_since = None
            continue
        now = time.monotonic()
        idle_since = now if idle_since is None else idle_since
        if now - idle_since > WORKERLESS_SECONDS:
            raise ClusterError(f"{label} has had no worker for {WORKERLESS_SECONDS:g} s (its workers died or left, "
                               "or the scheduler is gone); start workers and rerun")


# a local pool's worker that died: killed (the OOM killer, a signal), or it could not start (its workers never
# import the caller's script: workers_without_main)
LOST_WORKER = ("a worker process of the local pool ended abruptly: killed (out of memory, or by a signal), or "
               "it could not start; rerun with fewer workers (workers=1 runs in this process)")


def run_tasks(function: Callable[..., Any], tasks: Iterable[Any], *, executor: Any = None, workers: int = 1,
              progress: Callable[[Any], object] | None = None, weights: Iterable[float] | None = None,
              store: Any = None, keys: Any = None, start_method: str = "spawn") -> list:
    """``[function(*task) for task in tasks]``, the tasks run independently on an executor.

    Parameters
    ----------
    function : callable
        A module-level function (it is pickled to the workers).
    tasks : sequence of tuples
        The arguments of each call.
    executor : concurrent.futures.Executor or Dask Client, optional
        Where the tasks run (it is not shut down here).  Default: this
        process when ``workers == 1``, else a local process pool of
        ``workers`` processes started with ``start_method``.
    workers : int
        Processes of the local pool (ignored when ``executor`` is given).
    progress : callable, optional
        Called as ``progress(weight)`` once per task when its result is
        available; the results taken from ``store`` in one call, at once
        (a rate measured from the first call on counts only work done).
    weights : sequence, optional
        The progress weight of each task (default 1 each).
    store : object with ``load(key)`` and ``save(key, value)``, optional
        A checkpoint store (:class:`forcenet.core.checkpoints.CheckpointStore`):
        results it holds are not recomputed, new ones are saved as they arrive.
    keys : sequence, optional
        The store's key of each task (required with ``store``).

    Returns
    -------
    list
        The results, in the order of ``tasks`` whatever the completion order.

    Raises
    ------
    KeyboardInterrupt
        Re-raised after cancelling the pending tasks and terminating the
        local pool's workers.
    Exception
        The first failed task's exception, after the same clean-up.

    Examples
    --------
    >>> from operator import add
    >>> run_tasks(add, [(1, 2), (3, 4), (5, 6)], progress=lambda k: None)
    [3, 7, 11]
    """
    tasks = list(tasks)
    workers = check_int(workers, "workers", 1)
    if store is not None and (keys is None or len(keys) != len(tasks)):
        raise ArgumentError("keys must give one store key per task when a store is given")
    weights = [1] * len(tasks) if weights is None else list(weights)
    results: list = [None] * len(tasks)
    pending: list[int] = []
    reused: float = 0
    for i in range(len(tasks)):
        value = store.load(keys[i]) if store is not None else None
        if value is None:
            pending.append(i)
            continue
        results[i] = value
        reused += weights[i]
    if progress is not None and reused:  # one tick for every record reused: no rate is measured on them
        progress(reused)

    def finish(i: int, value: Any) -> None:
        results[i] = value
        if store is not None:
            store.save(keys[i], value)
        if progress is not None:
            progress(weights[i])

    executor = as_executor(executor)
    if executor is None and (workers <= 1 or len(pending) <= 1):
        for i in pending:
            finish(i, function(*tasks[i]))
        return results
    own = executor is None
    client = None if own else _dask_client(executor)
    if client is not None and client not in _PROBED:
        check_cluster(client)  # workers that cannot import forcenet: said in seconds, by name
    pool = local_pool(min(workers, len(pending)), start_method) if own else executor
    futures = {}
    try:
        calls = [(worker_call, os.getpid(), function, *tasks[i]) for i in pending]
        if own:  # (an interrupt held during the submits comes after them: _terminate stops what they started)
            futures = dict(zip(_submit_local(pool, calls), pending))
        else:
            for call, i in zip(calls, pending):  # a cluster's futures kept as they are made, to cancel them
                futures[pool.submit(*call)] = i
        client = _dask_client(pool)  # a Dask cluster's executor
        if client is None:
            waiting = set(futures)
            while waiting:  # bounded waits: a Ctrl-C the kernel hands to a pool thread is raised within a poll
                done, waiting = wait(waiting, timeout=_POLL_SECONDS, return_when=FIRST_COMPLETED)
                for future in done:
                    finish(futures[future], future.result())
        else:
            _collect_from_cluster(futures, finish, client)
    except BaseException:
        for future in futures:
            try:
                future.cancel()  # a cluster's future cancels its task on the scheduler, if it can still reach it
            except Exception:  # the scheduler gone: the failure being raised is the one to report
                pass
        if own:
            _terminate(pool)
            broken = sys.exc_info()[1]
            if isinstance(broken, BrokenExecutor):
                raise ClusterError(LOST_WORKER) from broken
        raise
    if own:
        pool.shutdown(wait=True)
    return results
