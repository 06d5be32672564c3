"""Compiled inner loops: numba if it is installed, and a clear fallback if not.

The samplers' compiled kernels (:mod:`forcenet.numeric.triangle.metropolis_kernel`, ``.slice_kernel``, ``.hook_walk``,
:mod:`forcenet.numeric.packing.kernels`) are written once as numba
``@njit(cache=True)`` functions.  numba is a declared dependency; without it
(``HAVE_NUMBA`` false) every sampler falls back to its pure-Python reference
kernel, which draws the same random numbers and gives the same chain, only
30-100 times slower.

The first call of a kernel in a fresh environment compiles it (a few
seconds, reported separately by ``benchmarks/bench_samplers.py``); numba
caches the machine code on disk (:mod:`forcenet.core.compiled`: under
``~/.cache/forcenet/numba``, never inside the installed package), so later
processes load it in well under a second.

A compiled call does not return to Python until it is done, and Python acts
on Ctrl-C (``KeyboardInterrupt``) only between bytecodes, so long compiled
work is cut into calls of about ``CHUNK_SECONDS`` each (:func:`chunks`, from
:mod:`forcenet.core.plan`, which the exact kernels use too):
the interrupt is then seen within a fraction of a second, and the state
between two calls is the state the one long call would have passed through
(the chains go on bit for bit).

Examples
--------
>>> kernel_choice(None) in ("compiled", "python")
True
>>> kernel_choice("python")
'python'
"""

from __future__ import annotations

import importlib.util
from collections.abc import Callable
from typing import Any

from forcenet.core.compiled import njit as compiled_njit
from forcenet.core.errors import ArgumentError
from forcenet.core.plan import CHUNK_SECONDS, chunks, first_chunk

__all__ = ["HAVE_NUMBA", "njit", "kernel_choice", "chunks", "first_chunk", "CHUNK_SECONDS"]

HAVE_NUMBA = importlib.util.find_spec("numba") is not None  # asked without importing it (a kernel's decoration does)

if HAVE_NUMBA:
    njit = compiled_njit  # cache=True by default, outside the package
else:  # pragma: no cover - numba is a declared dependency

    def njit(function: Callable[..., Any] | None = None, **options: Any) -> Any:
        """Without numba: the Python function itself (the reference kernels run instead)."""
        return (lambda f: f) if function is None else function


def kernel_choice(kernel: str | None) -> str:
    """``"compiled"`` or ``"python"``; ``None`` picks the compiled kernel when numba is available."""
    if kernel is None:
        return "compiled" if HAVE_NUMBA else "python"
    if kernel not in ("compiled", "python"):
        raise ArgumentError(f"kernel={kernel!r}: expected 'compiled', 'python' or None")
    if kernel == "compiled" and not HAVE_NUMBA:
        raise ArgumentError("kernel='compiled' needs numba (pip install numba); use kernel='python'")
    return kernel

