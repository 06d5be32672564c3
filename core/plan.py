"""What a long computation will cost, decided before it starts.

Every route of ``forcenet table`` (and every other long command) exposes a
*plan* and a *run*.  The plan is cheap: estimated seconds on the 2-core
reference machine, peak bytes, the number of progress ticks the run will
report, or a refusal with its reason (out of the route's range, or more
memory than the caller has).  The engines own their cost knowledge (measured
constants live next to the code they describe); the command line only asks,
announces, refuses or runs.

Examples
--------
>>> plan = Plan("exact table N=20", seconds=3.2, nbytes=2**28, ticks=4, unit="pass")
>>> plan.describe()
'~3 s, ~0.25 GiB'
>>> Plan("x", 0, refusal="N=40 is out of range").runnable
False
"""

from __future__ import annotations

import functools
import hashlib
import os
import signal
import struct
import sys
import threading
import time
from collections.abc import Callable, Iterable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass, replace
from importlib import metadata
from stat import S_ISREG
from types import FrameType
from typing import Any, cast

from .compiled import compile_features
from .errors import ArgumentError

__all__ = ["Plan", "duration_text", "combine", "combine_by_time", "phase_progress", "first_moment_only", "table_range", "chunks",
           "first_chunk", "CHUNK_SECONDS", "kernels_cached", "with_compilation",
           "interruptible_compilation"]

CHUNK_SECONDS = 0.15  # compiled work per call: Ctrl-C is seen within this, the calls' overhead stays far below 1 %


def duration_text(seconds: float) -> str:
    """``seconds`` as a readable duration: 40 s, 12 min, 3.5 h, 90 days.

    Examples
    --------
    >>> duration_text(40), duration_text(720), duration_text(12600), duration_text(8e6)
    ('40 s', '12 min', '3.5 h', '93 days')
    """
    if seconds < 120:
        return f"{seconds:.0f} s"
    if seconds < 7200:
        return f"{seconds / 60:.0f} min"
    if seconds < 2 * 86400:
        return f"{seconds / 3600:.1f} h"
    return f"{seconds / 86400:.0f} days"


@dataclass(frozen=True, repr=False)
class Plan:
    """The announced cost of a run.

    Its ``repr`` reads as the announcement does (``Plan(exact table N=100
    (Pfaffians): ~30 min, ~0.68 GiB, 866 primes)``; a refused plan says
    ``refused`` and why): the plan is the one source of every number a
    person reads about a run (issue 53).

    Attributes
    ----------
    what : str
        What will be computed, for the announcement.
    seconds : float
        Estimated wall time on the 2-core reference machine.
    nbytes : int
        Estimated peak memory.
    ticks : int
        Number of progress ticks the run reports (0: no progress bar).
    unit : str
        What one tick is (a grain, an ideal, a sample, ...).
    refusal : str or None
        Why the run cannot be done at all (range, memory); None if it can.
    compiling : tuple of (str, float)
        The kernel groups that will be compiled first (numba's cache does not
        hold them, :func:`with_compilation`) and their seconds, included in
        ``seconds``.
    """

    what: str
    seconds: float
    nbytes: int = 0
    ticks: int = 0
    unit: str = "step"
    refusal: str | None = None
    compiling: tuple = ()

    @property
    def runnable(self) -> bool:
        return self.refusal is None

    @property
    def compile_seconds(self) -> float:
        """The part of ``seconds`` spent compiling kernels (a first run, :func:`with_compilation`)."""
        return sum(seconds for _, seconds in self.compiling)

    def describe(self) -> str:
        """``'~12 min, ~3.2 GiB'``; with a cold cache ``'~40 s (compiling the kernels, once: ~25 s)'``; refused:
        ``'refused: <why>'`` (never a cost for a run that cannot be done).

        Examples
        --------
        >>> Plan("x", 40, compiling=(("sampler", 25.0),)).describe()
        '~40 s (compiling the kernels, once: ~25 s)'
        >>> Plan("x", 0, refusal="N=300 is out of range").describe()
        'refused: N=300 is out of range'
        """
        if self.refusal is not None:
            return f"refused: {self.refusal}"
        text = f"~{duration_text(self.seconds)}"
        if self.nbytes:
            text += f", ~{self.nbytes / 2**30:.2g} GiB"
        if self.compiling:
            text += f" (compiling the kernels, once: ~{duration_text(self.compile_seconds)})"
        return text

    def __repr__(self) -> str:
        """``Plan(what: ~30 min, ~0.68 GiB, 866 primes)`` or ``Plan(what: refused: why)``.

        Examples
        --------
        >>> Plan("exact table N=12 (order ideals)", 2.0, 2**20, ticks=2048, unit="ideal")
        Plan(exact table N=12 (order ideals): ~2 s, ~0.00098 GiB, 2048 ideals)
        >>> Plan("exact table N=300", 0, refusal="N must be an integer in 2..40")
        Plan(exact table N=300: refused: N must be an integer in 2..40)
        """
        what, _, why = self.what.partition("; ")
        ticks = f", {self.ticks} {self.unit}{'s' if self.ticks != 1 else ''}" if (
            self.ticks and self.runnable and self.unit != "s") else ""  # ticks in seconds: the estimate says it
        return f"Plan({what}: {self.describe()}{ticks}{'; ' + why if why else ''})"

    def refuse(self, reason: str) -> Plan:
        """The same plan, refused (the first reason wins)."""
        return self if self.refusal else replace(self, refusal=reason)

    def check(self) -> Plan:
        """The plan itself if it is runnable; else :class:`~forcenet.core.errors.ArgumentError` with its refusal.

        Raises
        ------
        ArgumentError
            If the plan is refused.

        Examples
        --------
        >>> Plan("x", 1).check().what
        'x'
        """
        if self.refusal is not None:
            raise ArgumentError(self.refusal)
        return self

    def within_memory(self, memory_bytes: int | None) -> Plan:
        """Refused if the peak memory exceeds ``memory_bytes`` (None: no check)."""
        if memory_bytes is None or self.nbytes <= memory_bytes:
            return self
        return self.refuse(
            f"{self.what} needs ~{self.nbytes / 2**30:.1f} GiB of memory but {memory_bytes / 2**30:.1f} GiB is available"
        )


def combine(what: str, plans: Iterable[Plan], unit: str = "step") -> Plan:
    """One plan for several runs done one after the other (times and ticks add, memory is the peak).

    Examples
    --------
    >>> p = combine("both", [Plan("a", 2, 10, 3), Plan("b", 5, 30, 4)])
    >>> p.what, p.seconds, p.nbytes, p.ticks, p.unit, p.refusal, p.compiling
    ('both', 7, 30, 7, 'step', None, ())

    A kernel group compiled by several runs is compiled (and counted) once:

    >>> c = (("k", 4.0),)
    >>> combine("both", [Plan("a", 6, compiling=c), Plan("b", 5, compiling=c)]).seconds
    7.0
    """
    plans = list(plans)
    refusal = next((p.refusal for p in plans if p.refusal), None)
    compiling, repeated = {}, 0
    for plan in plans:
        for name, seconds in plan.compiling:
            if name in compiling:
                repeated += seconds
            else:
                compiling[name] = seconds
    return Plan(what, sum(p.seconds for p in plans) - repeated, max((p.nbytes for p in plans), default=0),
                sum(p.ticks for p in plans), unit, refusal, tuple(compiling.items()))


def combine_by_time(what: str, plans: Iterable[Plan]) -> Plan:
    """One plan for runs of different units (primes, samples) on one bar counted in estimated seconds.

    A phase's tick of ``k`` of its own units advances the bar by ``k`` times
    its seconds per unit (:func:`phase_progress`), so the bar's remaining time
    is right when the phases differ in speed.

    Examples
    --------
    >>> p = combine_by_time("both", [Plan("a", 20, 10, 4, "prime"), Plan("b", 5, 30, 1000, "sample")])
    >>> p.what, p.seconds, p.nbytes, p.ticks, p.unit, p.refusal, p.compiling
    ('both', 25, 30, 25, 's', None, ())
    """
    plans = list(plans)
    plan = combine(what, plans, "s")
    return replace(plan, ticks=max(1, round(plan.seconds)))


def phase_progress(progress: Callable[[float], object] | None, plan: Plan) -> Callable[..., None] | None:
    """``progress`` (of a :func:`combine_by_time` bar) in the units of one phase ``plan``; None stays None.

    Examples
    --------
    >>> seen = []
    >>> phase_progress(seen.append, Plan("a", 20, 10, 4, "prime"))(2)
    >>> seen
    [10.0]
    """
    if progress is None:
        return None
    rate = plan.seconds / plan.ticks if plan.ticks else 0.0

    def tick(k: float = 1) -> None:
        progress(k * rate)

    return tick


def first_moment_only(what: str, method: str, moments: int, why: str = "") -> Plan | None:
    """The refusal of a route that computes ``<W>`` only, or None when ``moments == 1``; ``why`` adds where else to look.

    Examples
    --------
    >>> first_moment_only("x", "lambda", 2).refusal
    'moments=2 is out of range for --method lambda: moments must be 1 (higher moments use --method fast, thesis or maps)'
    >>> first_moment_only("x", "lambda", 1) is None
    True
    """
    if moments == 1:
        return None
    return Plan(what, 0, refusal=f"moments={moments} is out of range for --method {method}: moments must be 1 "
                                 "(higher moments use --method fast, thesis or maps" + (f"; {why}" if why else "") + ")")


def table_range(what: str, method: str, N: int, moments: int, max_N: int, *, max_moments: int | None = 1,
                why_N: str = "", why_moments: str = "") -> Plan | None:
    """The prologue of every table route's plan: the refusal of a request out of the route's range, or None.

    ``N`` and ``moments`` are validated integers (``N >= 2``, ``moments >=
    1``); the route reaches ``N <= max_N`` and ``moments <= max_moments``
    (1: the first moment only, :func:`first_moment_only`; None: every
    moment).  The largest ``N`` is checked first; ``why_N`` and
    ``why_moments`` say, in parentheses, what stops the route there.

    Examples
    --------
    >>> table_range("x", "maps", 10, 1, 9, max_moments=None, why_N="too many maps").refusal
    'N=10 is out of range for --method maps: N must be an integer in 2..9 (too many maps)'
    >>> table_range("x", "thesis", 8, 4, 9, max_moments=3).refusal
    'moments=4 is out of range for --method thesis: moments must be an integer in 1..3'
    >>> table_range("x", "lambda", 8, 1, 12) is None
    True
    """
    if N > max_N:
        return Plan(what, 0, refusal=f"N={N} is out of range for --method {method}: N must be an integer in 2..{max_N}"
                                     + (f" ({why_N})" if why_N else ""))
    if max_moments == 1:
        return first_moment_only(what, method, moments, why_moments)
    if max_moments is not None and moments > max_moments:
        return Plan(what, 0, refusal=f"moments={moments} is out of range for --method {method}: moments must be an "
                                     f"integer in 1..{max_moments}" + (f" ({why_moments})" if why_moments else ""))
    return None


# ------------------------------------------------- compiled work in bounded calls


def chunks(total: int, first: int, seconds: float = CHUNK_SECONDS) -> Iterator[tuple[int, int]]:
    """Consecutive ranges ``(start, stop)`` covering ``0..total``, each taking about ``seconds``.

    The first range has ``first`` units (the caller's estimate of ``seconds``
    worth); every later one is sized from the measured time of the one before
    (the loop body between two ``yield``s: the compiled call, a progress tick),
    growing at most twofold, so a first call that also compiled or loaded the
    kernel is followed by short ranges that grow back.  The work done does not
    depend on the sizes: callers cut only where the state is complete.

    Examples
    --------
    >>> ranges = list(chunks(10, 4))
    >>> ranges[0], ranges[-1][1], all(a[1] == b[0] for a, b in zip(ranges, ranges[1:]))
    ((0, 4), 10, True)
    >>> list(chunks(0, 5))
    []
    """
    start, size = 0, max(1, int(first))
    while start < total:
        stop = min(total, start + size)
        t0 = time.perf_counter()
        yield start, stop
        elapsed = time.perf_counter() - t0
        grown = 2 * size
        size = grown if elapsed <= 0 else max(1, min(grown, int((stop - start) * seconds / elapsed)))
        start = stop


def first_chunk(seconds_per_unit: float, seconds: float = CHUNK_SECONDS) -> int:
    """The units of the first range of :func:`chunks`, from the model's cost of one unit.

    Examples
    --------
    >>> first_chunk(1e-3)
    150
    >>> first_chunk(10.0)
    1
    """
    return max(1, int(seconds / seconds_per_unit)) if seconds_per_unit > 0 else 1


# ------------------------------------------------- the first run: compiling the kernels

_INDEX_BYTES = 1 << 20  # numba's index: a few KiB of signatures


def kernels_cached(kernels: Iterable[Any], in_workers: bool = False) -> bool:
    """Whether numba holds machine code for every dispatcher of ``kernels`` without compiling.

    True when each is compiled in this process already (its public
    ``signatures``) or its on-disk cache (``cache=True``: the ``.nbi`` index in
    ``dispatcher.stats.cache_path``, under ``NUMBA_CACHE_DIR``) was written
    by this numba for the source as it is now (numba's own test: the source's
    content hash, so a reinstall of the same source keeps its cache) and holds
    code for the CPU features the run compiles for
    (:func:`~forcenet.core.compiled.compile_features`).  ``in_workers``: the
    run is in forcenet's worker processes, which compile with their own
    features (512-bit vectors on AVX-512) and load only from the disk.

    Examples
    --------
    >>> kernels_cached([])
    True
    """
    kernels = list(kernels)
    if not kernels:
        return True

    features = compile_features(workers=in_workers)
    return all((kernel.signatures and not in_workers) or _cache_index_is_fresh(kernel, features)
               for kernel in kernels)


def _cache_index_is_fresh(kernel: Any, features: str) -> bool:
    """Whether numba's on-disk cache of ``kernel`` holds an index numba would load: this numba's, this source's.

    numba has no public "is it cached" query: its cache folder is public
    (``dispatcher.stats.cache_path``), the index's name is numba's file
    convention (``<file's stem>.<qualname>-<first line>.py<major><minor><abiflags>.nbi``,
    numba's ``_CacheImpl.get_filename_base``, the same from 0.4x to the
    versions pinned in pyproject.toml).  numba loads an index only when the
    numba version and the source stamp it holds are the current ones; the
    stamp is the SHA-256 of the source file's bytes from numba 0.68 (numba
    pull request 10659), ``(st_mtime, st_size)`` in 0.60-0.67 (its
    modification time is looked for then).  Both are looked for in the
    index's bytes, never unpickled: a reinstall of the same source (a new
    modification time) keeps its cache, an edited source does not.  numba
    keys each overload by the CPU ``features`` it was compiled for (its
    codegen's ``magic_tuple``): the index must hold ``features`` too.  Isolated
    here, read-only, so a changed convention costs at most a compile time
    counted twice.
    """
    try:
        folder = kernel.stats.cache_path
        function = kernel.py_func
        source_file = function.__code__.co_filename
        stem = os.path.splitext(os.path.basename(source_file))[0]  # numba names by the file, not the module path
        fullname = f"{stem}.{function.__qualname__}".replace("<", "").replace(">", "")
        name = "{}-{}.py{}{}{}.nbi".format(fullname,
                                           function.__code__.co_firstlineno, sys.version_info[0], sys.version_info[1],
                                           getattr(sys, "abiflags", ""))
        path = os.path.join(folder, name)
        if not S_ISREG(os.stat(path).st_mode):  # a FIFO or device in its place is never opened
            return False
        with open(path, "rb") as index:
            data = index.read(_INDEX_BYTES)
        stat = os.stat(source_file)
        mtime = stat.st_mtime
        digest = _source_digest(source_file, mtime, stat.st_size)
        version = _numba_version()
    except (AttributeError, OSError, TypeError, metadata.PackageNotFoundError):  # no cache, or unreadable: count the compilation
        return False
    # the pickled version string (SHORT_BINUNICODE: its length, then its bytes) opens the index
    same_numba = _pickled_text(version) in data[:64]
    same_source = digest in data or struct.pack(">d", mtime) in data
    return same_numba and same_source and _pickled_text(features.encode()) in data


@functools.lru_cache(maxsize=64)
def _source_digest(path: str, mtime: float, size: int) -> bytes:
    """The SHA-256 of a kernel's source, once per file as it is (numba's own memo: path, time, size)."""
    with open(path, "rb") as source:
        return hashlib.sha256(source.read()).digest()


@functools.lru_cache(maxsize=1)
def _numba_version() -> bytes:
    """The installed numba's version (``numba.__version__``), read once from its metadata."""
    return metadata.version("numba").encode()


def _pickled_text(text: bytes) -> bytes:
    """A str as pickle (protocol 4 and later, numba's) writes it: its opcode, its length, its UTF-8 bytes."""
    if len(text) < 256:
        return b"\x8c" + bytes([len(text)]) + text  # SHORT_BINUNICODE
    return b"X" + struct.pack("<I", len(text)) + text  # BINUNICODE


def with_compilation(plan: Plan, name: str, seconds: float, kernels: Iterable[Any], *,
                     in_workers: bool = False) -> Plan:
    """``plan`` plus ``seconds`` of compiling the kernel group ``name`` if numba's cache does not hold ``kernels``.

    ``kernels``: the group's entry points (numba dispatchers) the run will
    call; ``seconds``: their measured compile time on the reference machine
    (``benchmarks/compile_times.py``); ``in_workers``: the run is in
    forcenet's worker processes (:func:`kernels_cached`).  A refused plan, or
    one that counts ``name`` already, is returned as it is.

    Examples
    --------
    >>> with_compilation(Plan("x", 3), "none", 5.0, []).seconds  # nothing to compile
    3
    """
    if not plan.runnable or any(n == name for n, _ in plan.compiling) or kernels_cached(kernels, in_workers):
        return plan
    return replace(plan, seconds=plan.seconds + seconds, compiling=plan.compiling + ((name, seconds),))


# Python code that native code calls back (ctypes callbacks) swallows exceptions: a KeyboardInterrupt raised
# there is printed as "Exception ignored" and lost. LLVM calls back into llvmlite's object cache while numba
# finalizes machine code, so these call sites are where Ctrl-C must wait (function name, file path suffix).
NATIVE_CALL_SITES = [("__call__", os.path.join("llvmlite", "binding", "ffi.py")),
                     ("__call__", os.sep + "weakref.py")]  # weakref.finalize's callbacks, run by the collector


def _where_exceptions_are_swallowed(frame: FrameType) -> bool:
    """Whether ``frame`` runs below one of ``NATIVE_CALL_SITES`` (a callback, a finalizer) or in a ``__del__``."""
    if frame.f_code.co_name == "__del__":
        return True
    caller = frame.f_back  # ``frame`` itself at a call site: between its own bytecodes raising is safe
    while caller is not None:
        code = caller.f_code
        if code.co_name == "__del__" or any(code.co_name == name and code.co_filename.endswith(path)
                                            for name, path in NATIVE_CALL_SITES):
            return True
        caller = caller.f_back
    return False


@contextmanager
def interruptible_compilation(retry_seconds: float = 0.02) -> Iterator[None]:
    """Make Ctrl-C end the run even when it arrives while numba compiles.

    Python's own SIGINT handler raises ``KeyboardInterrupt`` wherever the
    main thread is; inside a callback from native code (LLVM's object cache
    calling llvmlite while numba finalizes a kernel) the exception is
    swallowed, and the run then goes on to the end or fails on a half-built
    library; so it is in a finalizer (``__del__``, e.g. llvmlite disposing
    of a module).  Within this context SIGINT raises ``KeyboardInterrupt`` as
    before, except inside such a callback or finalizer, where it is asked
    again ``retry_seconds`` later (it has returned by then), to the main
    thread, so that a blocking wait there ends at once.  A deferred
    interrupt still pending when the block ends is dropped if the block ran
    to its end (the work it would have stopped is done) and raised there
    otherwise.  Outside the main thread, or when SIGINT already has a handler
    of the caller's, the block runs unchanged.

    Parameters
    ----------
    retry_seconds : float, optional
        The delay before an interrupt that arrived inside a callback is
        delivered again.

    Yields
    ------
    None

    Raises
    ------
    KeyboardInterrupt
        On Ctrl-C, outside native callbacks.

    Examples
    --------
    >>> with interruptible_compilation():
    ...     sum(range(10))
    45
    """
    if (threading.current_thread() is not threading.main_thread()
            or signal.getsignal(signal.SIGINT) is not signal.default_int_handler):
        yield
        return
    state, timers = {"pending": False, "closed": False}, []
    main_thread = cast(int, threading.main_thread().ident)  # the main thread has started: its ident is set

    def again() -> None:
        if not state["closed"]:
            if hasattr(signal, "pthread_kill"):  # to the main thread: it may be blocked in a wait
                signal.pthread_kill(main_thread, signal.SIGINT)
            else:  # pragma: no cover - Windows
                signal.raise_signal(signal.SIGINT)

    def handler(signum: int, frame: FrameType | None) -> None:
        if frame is not None and _where_exceptions_are_swallowed(frame):
            state["pending"] = True
            timer = threading.Timer(retry_seconds, again)
            timer.daemon = True
            timer.start()
            timers.append(timer)  # only started timers: a nested call may run between these lines
            return
        state["pending"] = False
        raise KeyboardInterrupt

    def record(signum: int, frame: FrameType | None) -> None:  # while the block ends: note the interrupt, raise nothing yet
        state["pending"] = True

    signal.signal(signal.SIGINT, handler)
    completed = False
    try:
        yield
        completed = True
    finally:
        while signal.getsignal(signal.SIGINT) is not record:
            try:
                signal.signal(signal.SIGINT, record)
            except KeyboardInterrupt:  # a Ctrl-C just before: kept for the end
                state["pending"] = True
        state["closed"] = True
        for timer in list(timers):  # no thread of ours outlives the block
            timer.cancel()
            timer.join()
        signal.signal(signal.SIGINT, signal.default_int_handler)
    if state["pending"] and not completed:
        raise KeyboardInterrupt
