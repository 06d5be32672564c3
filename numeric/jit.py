"""Compiled inner loops: numba if it is installed, and a clear fallback if not.

The samplers' compiled kernels (:mod:`forcenet.numeric.triangle.kernels`,
:mod:`forcenet.numeric.packing.kernels`) are written once as numba
``@njit(cache=True)`` functions.  numba is a declared dependency; without it
(``HAVE_NUMBA`` false) every sampler falls back to its pure-Python reference
kernel, which draws the same random numbers and gives the same chain, only
30-100 times slower.

The first call of a kernel in a fresh environment compiles it (a few
seconds, reported separately by ``benchmarks/bench_samplers.py``); numba
caches the machine code next to the module (``__pycache__``), so later
processes load it in well under a second.

A compiled call does not return to Python until it is done, and Python acts
on Ctrl-C (``KeyboardInterrupt``) only between bytecodes, so long compiled
work is cut into calls of about :data:`CHUNK_SECONDS` each (:func:`chunks`):
the interrupt is then seen within a fraction of a second, and the state
between two calls is the state the one long call would have passed through
(the chains go on bit for bit).

May import: nothing of the package.

Examples
--------
>>> kernel_choice(None) in ("compiled", "python")
True
>>> kernel_choice("python")
'python'
"""

from __future__ import annotations

import time

__all__ = ["HAVE_NUMBA", "njit", "kernel_choice", "chunks", "first_chunk", "CHUNK_SECONDS"]

CHUNK_SECONDS = 0.15  # compiled work per call: Ctrl-C is seen within this, the calls' overhead stays far below 1 %

try:  # pragma: no branch
    import numba

    HAVE_NUMBA = True

    def njit(*args, **kwargs):
        """``numba.njit`` with the machine code cached on disk (``cache=True``)."""
        kwargs.setdefault("cache", True)
        return numba.njit(*args, **kwargs)

except ImportError:  # pragma: no cover - numba is a declared dependency
    HAVE_NUMBA = False

    def njit(*args, **kwargs):
        if args and callable(args[0]):
            return args[0]
        return lambda f: f


def kernel_choice(kernel) -> str:
    """``"compiled"`` or ``"python"``; ``None`` picks the compiled kernel when numba is available."""
    if kernel is None:
        return "compiled" if HAVE_NUMBA else "python"
    if kernel not in ("compiled", "python"):
        raise ValueError(f"kernel={kernel!r}: expected 'compiled', 'python' or None")
    if kernel == "compiled" and not HAVE_NUMBA:
        raise ValueError("kernel='compiled' needs numba (pip install numba); use kernel='python'")
    return kernel


def chunks(total: int, first: int, seconds: float = CHUNK_SECONDS):
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
