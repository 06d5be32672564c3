"""The free-fermion route's cost model and primes: CPU seconds per prime, bytes per worker, the primes.

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

from math import isqrt

from forcenet.core.validation import check_int

from ...modular import primes_for_bound
from ..prime_tasks import WORKER_BASE_BYTES
from ..staircase import dimension, free_force_count

__all__ = ["CRT_SECONDS", "prime_limit", "dense_prime_limit", "level_points", "route_primes", "prime_seconds",
           "edge_seconds", "worker_bytes"]

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
CRT_SECONDS = 2.3e-9  # per reconstructed entry and prime^2: the client's Chinese remaindering (benchmarks)


def prime_limit(n: int) -> int:
    """Bound on the primes of the route: ``p < 2^25``, so ``8 p^2 < 2^53`` (the displacement kernels' bound).

    ``n`` is accepted for the interface; the bound of the displacement
    elimination does not depend on it (that of the dense baseline does:
    :func:`dense_prime_limit`).

    Examples
    --------
    >>> prime_limit(31), prime_limit(99)
    (33554432, 33554432)
    """
    check_int(n, "n", 1)
    return 2**25


def dense_prime_limit(n: int) -> int:
    """Bound of the dense lazy elimination (the tests' dense baseline): ``p + 2 (n-1) p^2 < 2^53``, ``p < 2^23``.

    Examples
    --------
    >>> dense_prime_limit(31), dense_prime_limit(99)
    (8388608, 6744694)
    """
    n = check_int(n, "n", 1)
    return min(2**23, isqrt((2**53 - 2**24) // (2 * max(n, 1))))


def level_points(d: int) -> int:
    """Number ``M`` of level-fugacity points: the even one of ``d + 1`` and ``d + 2``.

    Examples
    --------
    >>> level_points(6), level_points(3)
    (8, 4)
    """
    return d + 1 if (d + 1) % 2 == 0 else d + 2


def route_primes(N: int, bound: int) -> tuple[int, ...]:
    """The primes of the route for ``N`` layers whose product exceeds ``bound``, largest first.

    Below :func:`prime_limit` (the kernels' word-size bound) and
    above ``max(2N + 3, d + 2)`` (the level points and the kernel's sizes
    must stay distinct modulo the prime).  A non-negative integer ``<= bound``
    is then determined by its residues (:func:`~forcenet.exact.modular.primes_for_bound`).

    Examples
    --------
    >>> route_primes(10, 33554393)
    (33554393, 33554383)
    """
    return primes_for_bound(bound, limit=prime_limit(max(N - 1, 1)), smallest=max(2 * N + 3, dimension(N) + 2))


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
    return level_points(free_force_count(N)) // 2 * rows * n * 8 + WORKER_BASE_BYTES


def prime_seconds(N: int) -> float:
    """CPU seconds of one prime of the table (:func:`.engine.prime_residues`), ``N >= 2``.

    Examples
    --------
    >>> 0 < prime_seconds(20) < prime_seconds(40)
    True
    """
    n = N - 1
    return _per_point_seconds(N, 2 * ((n + 1) // 2))  # y = 0..n, paired


def edge_seconds(N: int) -> float:
    """CPU seconds of one prime of the lattice directions (:func:`.engine.edge_residues`), ``N >= 2``.

    Examples
    --------
    >>> 0 < edge_seconds(20) < prime_seconds(20)
    True
    """
    return _per_point_seconds(N, 2)  # two eliminations per level point


def _per_point_seconds(N: int, eliminations: int) -> float:
    """``d/2`` level points, each ``eliminations`` displacement eliminations and one kernel set-up, then the weights."""
    n, d = N - 1, free_force_count(N)
    s = n + 1 + (n + 1) % 2
    per_y = _SECONDS_PER_PIVOT * n + _SECONDS_PER_ROW * n**2
    M = level_points(d)
    return M // 2 * (eliminations * per_y + _SECONDS_PER_KERNEL * s**3) + _SECONDS_PER_WEIGHT * M**2 + 1e-3
