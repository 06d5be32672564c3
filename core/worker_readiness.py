"""What every task's process does around its tasks: glibc's allocator thresholds, BLAS pools of one thread.

A local pool's process or a Dask worker runs each task as :func:`worker_call`
(``forcenet.core.execution.run_tasks`` submits every task in that form): before
its first task, once, glibc's ``malloc`` gets back the dynamic thresholds that a
frozen ``MALLOC_TRIM_THRESHOLD_`` (Dask's nanny sets one) turns off, and every
BLAS/OpenMP pool is pinned to one thread (the tasks are the parallelism); after
the first task once more, for the pools of libraries it loaded.

Examples
--------
>>> import os
>>> worker_call(os.getpid(), abs, -3)  # the client's own process: the call alone
3
"""

from __future__ import annotations

import ctypes
import ctypes.util
import os
from collections.abc import Callable
from typing import Any, TypeVar

from threadpoolctl import threadpool_info, threadpool_limits

__all__ = ["worker_call"]

T = TypeVar("T")

# glibc's mallopt parameters (<malloc.h>) and the ceiling of its own dynamic mmap threshold on 64-bit
# (DEFAULT_MMAP_THRESHOLD_MAX = 32 MiB); the trim threshold is then twice it, as glibc sets it itself.
_M_TRIM_THRESHOLD, _M_MMAP_THRESHOLD = -1, -3
_MMAP_THRESHOLD = 32 * 2**20
_READY: dict[str, Any] = {}


def _steady_allocator() -> bool:
    """Give glibc's ``malloc`` back the thresholds it reaches by itself, if the environment froze them.

    Setting ``MALLOC_TRIM_THRESHOLD_`` (Dask's nanny does, to 64 KiB) turns
    off glibc's dynamic mmap threshold: every block over 128 KiB is then
    mapped on ``malloc`` and unmapped on ``free``, fresh zeroed pages each
    time.  A user's own ``MALLOC_MMAP_THRESHOLD_`` is respected.
    """
    if "MALLOC_TRIM_THRESHOLD_" not in os.environ or "MALLOC_MMAP_THRESHOLD_" in os.environ:
        return False
    try:
        mallopt = ctypes.CDLL(ctypes.util.find_library("c")).mallopt
    except (OSError, AttributeError, TypeError):  # pragma: no cover - not glibc
        return False
    return bool(mallopt(_M_MMAP_THRESHOLD, _MMAP_THRESHOLD)) and bool(mallopt(_M_TRIM_THRESHOLD, 2 * _MMAP_THRESHOLD))


def _ready_worker() -> dict:
    """Ready this process for tasks: glibc's allocator thresholds (once), BLAS/OpenMP pools of one thread.

    Called by :func:`worker_call` before the first task a process runs (a
    local pool's process or a Dask worker) and once after it (pinning the
    pools of libraries the first task loaded).

    Returns
    -------
    dict
        ``{"allocator": bool, "threads": int, "pinned": int}``: whether the
        allocator's thresholds were restored, the most threads any
        BLAS/OpenMP pool of the process keeps, and how often the pools were
        pinned.
    """

    if "allocator" not in _READY:
        _READY["allocator"] = _steady_allocator()
    threadpool_limits(1)
    _READY["threads"] = max([pool["num_threads"] for pool in threadpool_info()] or [1])
    _READY["pinned"] = _READY.get("pinned", 0) + 1
    return dict(_READY)


def worker_call(client_pid: int, function: Callable[..., T], *args: Any) -> T:
    """``function(*args)``, in a process readied by :func:`_ready_worker` unless it is the client's own (an
    executor of threads): the form every task is submitted in.

    Examples
    --------
    >>> import os
    >>> worker_call(os.getpid(), abs, -3)  # the client's own process (threads): not readied
    3
    """
    if os.getpid() == client_pid:
        return function(*args)
    if _READY.get("pinned", 0) < 2:
        _ready_worker()
    result = function(*args)
    if _READY["pinned"] < 2:
        _ready_worker()
    return result
