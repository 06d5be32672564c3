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

May import: nothing of the package.

Examples
--------
>>> kernel_choice(None) in ("compiled", "python")
True
>>> kernel_choice("python")
'python'
"""

from __future__ import annotations

__all__ = ["HAVE_NUMBA", "njit", "kernel_choice"]

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
