"""Worker processes that never outlive their parent and never run the caller's script.

:func:`die_with_parent` is the initializer of every local pool of the
package; :func:`workers_without_main` is the context in which a pool starts
its workers.

A module of the standard library alone: a spawned worker imports it (to run
the initializer) within a fraction of a second, long before the seconds it
takes to import a route's modules, so the window in which a parent's death
goes unnoticed is as short as the interpreter's start.

Examples
--------
>>> import os
>>> from concurrent.futures import ProcessPoolExecutor
>>> with ProcessPoolExecutor(1, initializer=die_with_parent, initargs=(os.getpid(),)) as pool:
...     pool.submit(abs, -3).result()
3
"""

from __future__ import annotations

import ctypes
import os
import signal
import sys
import threading
import time
import types
from collections.abc import Callable, Iterator
from concurrent.futures import InvalidStateError
from contextlib import contextmanager
from typing import Any

__all__ = ["deaf_to_hangups", "die_with_parent", "interrupts_held", "quiet_broken_pools", "workers_without_main"]

_PR_SET_PDEATHSIG = 1  # <linux/prctl.h>
_WATCH_SECONDS = 0.5  # elsewhere: how often a worker's watchdog looks for its parent


def die_with_parent(parent: int, started: Any = None) -> None:
    """End this worker process when its parent ``parent`` ends, however it ends (SIGKILL included).

    Linux: the parent-death signal (``prctl(PR_SET_PDEATHSIG, SIGKILL)``),
    then the parent's pid checked once more, for a parent that died between
    this process's start and the ``prctl`` call (the kernel sends nothing
    then; the worker has been re-parented and exits at once). Elsewhere: a
    daemon thread that polls the parent's pid.

    Parameters
    ----------
    parent : int
        The pid of the process that started the pool.
    started : multiprocessing queue, optional
        Receives this worker's pid once armed: the pool's owner stops its
        workers by that list (``forcenet.core.execution``), not by a
        private attribute of the pool.

    Examples
    --------
    >>> import os, subprocess, sys
    >>> code = f"from forcenet.core.lifetime import die_with_parent; die_with_parent({os.getpid()} + 10**7)"
    >>> subprocess.run([sys.executable, "-c", code], check=False).returncode  # its parent is not that pid
    1
    """
    armed = False
    if sys.platform.startswith("linux"):
        try:
            armed = ctypes.CDLL(None, use_errno=True).prctl(_PR_SET_PDEATHSIG, int(signal.SIGKILL), 0, 0, 0) == 0
        except (OSError, AttributeError):  # pragma: no cover - no prctl
            armed = False
    if os.getppid() != parent:  # the parent is gone already (this process was re-parented)
        os._exit(1)
    if not armed:  # pragma: no cover - not Linux

        def watch() -> None:
            while os.getppid() == parent:
                time.sleep(_WATCH_SECONDS)
            os._exit(1)

        threading.Thread(target=watch, name="forcenet-parent-watch", daemon=True).start()
    if started is not None:
        started.put(os.getpid())


_MAIN_LOCK = threading.Lock()  # one pool at a time starts its workers without the caller's main module


@contextmanager
def workers_without_main() -> Iterator[None]:
    """While a pool starts its workers, ``sys.modules["__main__"]`` is a bare module: no worker runs the script.

    A spawned (or forkserver) worker of :mod:`multiprocessing` first rebuilds
    the parent's ``__main__`` from that module's ``__spec__`` or ``__file__``
    (``multiprocessing.spawn.get_preparation_data``): it runs the caller's
    script again, so a script without ``if __name__ == "__main__":`` ran its
    top level in every worker and crashed (issue 53), and a script read from
    stdin (``__file__ == "<stdin>"``) could not start a worker at all. A
    module with neither is not rebuilt, as for ``python -c``. forcenet's
    workers run forcenet's own module-level functions only, which they import
    by name, so they need nothing of the caller's script. The swap lasts while
    the pool starts processes (its ``submit`` calls: milliseconds per worker),
    under a lock; forked workers copy the parent as it is.

    Yields
    ------
    None

    Examples
    --------
    >>> import sys
    >>> main = sys.modules["__main__"]
    >>> with workers_without_main():
    ...     hasattr(sys.modules["__main__"], "__file__")
    False
    >>> sys.modules["__main__"] is main
    True
    """
    with _MAIN_LOCK, interrupts_held():
        main = sys.modules.get("__main__")
        sys.modules["__main__"] = types.ModuleType("__main__")
        try:
            yield
        finally:
            if main is None:  # pragma: no cover - an interpreter always has a __main__
                sys.modules.pop("__main__", None)
            else:
                sys.modules["__main__"] = main


_HELD = ("SIGINT", "SIGTERM", "SIGHUP")


@contextmanager
def interrupts_held() -> Iterator[None]:
    """Ctrl-C (SIGINT), SIGTERM and SIGHUP held while the block runs, and the first delivered when it ends.

    A pool's ``submit`` spawns its workers: an interrupt raised inside ``Process.start`` left a child reading
    a half-written start-up from its parent, which then printed ``EOFError`` or ``OSError: Bad file
    descriptor`` after the parent's "interrupted" (measured: 1 run in 6 interrupted at once, under load).
    Held for the milliseconds of the spawns, the interrupt comes right after them, where the pool knows its
    processes and stops them. Only in the main thread (the only one signals reach); an ignored signal stays
    ignored.

    Yields
    ------
    None

    Examples
    --------
    >>> seen = []
    >>> previous = signal.signal(signal.SIGTERM, lambda *_: seen.append("delivered"))
    >>> with interrupts_held():
    ...     signal.raise_signal(signal.SIGTERM)  # held
    ...     seen.append("the block ends")
    >>> seen
    ['the block ends', 'delivered']
    >>> _ = signal.signal(signal.SIGTERM, previous)
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    held: list[int] = []
    previous: dict[int, Any] = {}
    for name in _HELD:
        number = getattr(signal, name, None)
        if number is None:
            continue
        handler = signal.getsignal(number)
        if handler is signal.SIG_IGN or handler is None:  # ignored (nohup's SIGHUP), or not set from Python
            continue
        previous[number] = handler
        signal.signal(number, lambda signum, frame: held.append(signum))
    try:
        yield
    finally:
        for number, handler in previous.items():
            signal.signal(number, handler)
        if held:
            signal.raise_signal(held[0])


def deaf_to_hangups(start: Callable[[], None]) -> None:
    """``start()`` (multiprocessing's resource tracker) with SIGHUP ignored, which the child keeps: the tracker
    shares this process group, and a closed terminal's SIGHUP would kill it, then this process's shutdown would
    unregister its semaphores with a relaunched tracker, printing a ``KeyError`` traceback for each.  Its
    "leaked semaphore" warnings (after a SIGKILL of this process, it cleans them up) are not printed.

    Examples
    --------
    >>> before, seen = signal.getsignal(signal.SIGHUP), []
    >>> deaf_to_hangups(lambda: seen.append(signal.getsignal(signal.SIGHUP)))
    >>> seen == [signal.SIG_IGN], signal.getsignal(signal.SIGHUP) == before  # (before: SIG_IGN under nohup)
    (True, True)
    """
    hangup = getattr(signal, "SIGHUP", None)
    changed, previous = False, None
    if hangup is not None:
        try:
            previous, changed = signal.signal(hangup, signal.SIG_IGN), True
        except ValueError:  # not the main thread: signals cannot be changed here
            pass
    quiet = "ignore:resource_tracker:UserWarning"  # passed on to the tracker (its -W): after a SIGKILL of this
    added = quiet not in sys.warnoptions  # process it cleans the semaphores up, without a "leaked" warning line
    if added:
        sys.warnoptions.append(quiet)
    try:
        start()
    finally:
        if added:
            sys.warnoptions.remove(quiet)
        if changed and hangup is not None:  # a handler not set from Python reads None: the default is restored
            signal.signal(hangup, signal.SIG_DFL if previous is None else previous)


def quiet_broken_pools() -> None:
    """``threading.excepthook`` without the ``InvalidStateError`` that CPython's process pool manager raises when
    the pool's workers are terminated with cancelled futures pending (``terminate_broken`` sets an exception on a
    cancelled future): a traceback printed after "interrupted" that tells the user nothing. Installed once; every
    other thread's exception goes to the hook there was.

    Examples
    --------
    >>> quiet_broken_pools(); quiet_broken_pools()
    >>> getattr(threading.excepthook, "forcenet_quiet", False)
    True
    """
    if getattr(threading.excepthook, "forcenet_quiet", False):
        return
    hook = threading.excepthook

    def quiet(args: Any) -> object:
        if issubclass(args.exc_type, InvalidStateError) and type(args.thread).__name__ == "_ExecutorManagerThread":
            return None
        return hook(args)

    quiet.forcenet_quiet = True  # type: ignore[attr-defined]
    threading.excepthook = quiet
