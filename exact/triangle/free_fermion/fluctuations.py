"""Beyond the mean by Pfaffians: exact gap laws of the lattice-direction grains in polynomial time.

``notes/fluctuations.md`` has the derivations.  The force ``W_{i,1}`` is the
partial sum ``S_{i,1}``, a *single* tableau entry: its rank gap is
``g = T(x)`` for the cell ``x = (1, m)``, ``m = N - i + 1``, and
``T(x) > l`` exactly when the ideal ``I_l`` at level ``l`` has no part
``>= m`` (``N_m(I_l) = 0``).  So

    count * P(g > l) = E[m][l] := sum_{|A| = l} w(A) [N_m(A) = 0],

one level at a time: the coefficient of ``q^l`` of the level polynomial the
mean's route already evaluates (``notes/free_fermions.md`` Sec. 3-4), times
``l! (d - l)!``.  The mean sums these coefficients with weight one; the law
needs them one by one, i.e. the polynomial interpolated instead of a
functional applied: one ``M x M`` Lagrange matrix per prime, the same
Pfaffian evaluations (two eliminations per level point,
:func:`~.kernels.edge_values`).  By the mirror symmetry ``W_{i,i}`` has the
same law.  Densities, CDFs and every moment follow from the Beta mixture
(:mod:`forcenet.exact.triangle.distribution`).

Interior grains ``1 < j < i`` are a different matter: their gap is the
difference of two entries, a *two-time* quantity of the chain of ideals,
which the one-time marginals alone do not fix (for an arbitrary measure on
chains; ``notes/fluctuations.md`` Sec. 3-4, with the proof and the cost of
the two-time route).  Their law comes from one layer's de Bruijn grid
(:mod:`forcenet.exact.triangle.de_bruijn.layers`); for layer ``N - 1`` the second moment is one-time after
all, by a property of the uniform measure (Sec. 3.1, :mod:`.covers`).

Cost: the lattice directions' Pfaffian work (``O(n^4)`` per prime) plus the
interpolation, ``O(M^2 n)`` per prime with ``M ~ d``: ``O(n^5)``; primes
``~ log2(count) / 25``.  Memory ``O(M^2)`` (the Lagrange matrix: 0.2 GB at
N = 100).

Examples
--------
>>> law = lattice_gap_laws(5)[3]  # W_{3,1} for N = 5: g = T(1, 3) is 3 or 4
>>> law.counts, law.total
((0, 0, 0, 7, 5, 0, 0, 0, 0, 0, 0, 0), 12)
>>> from forcenet.exact.triangle.gap_counts import moment_from_gaps
>>> moment_from_gaps(law, 2)  # <W_{3,1}^2>
Fraction(23, 198)
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Sequence
from concurrent.futures import Executor
from fractions import Fraction
from math import ceil, log2
from typing import Any

import numpy as np

from forcenet.core.errors import ArgumentError
from forcenet.core.plan import Plan
from forcenet.core.validation import check_grain, check_int, check_layers

from ...modular import crt_many
from ..gap_counts import GapCounts
from ..prime_tasks import WORKER_BASE_BYTES, primes_plan, run_primes, workers_for
from ..staircase import dimension, free_force_count, tableau_count
from .cost import edge_seconds, level_points, prime_limit, route_primes
from .engine import (
    MAX_POINT_FAILURES,
    PointFailureError,
    check_prime,
    constants,
    kernel_module,
    pair_points,
    setup_matrices,
)
from .route import count

__all__ = ["MAX_LAW_N", "lattice_gap_laws_cost", "edge_level_residues", "lattice_level_sums", "lattice_gap_laws", "lattice_mean_W2",
           "grain_gap_law", "lattice_gap_laws_plan", "law_prime_seconds"]

MAX_LAW_N = 128  # the interpolation's exact float64 products need M < 2^13
# CPU seconds on the reference machine.  Measured on 2026-11-25 on the loaded 2-core machine at N = 40 and scaled by
# the ratio (8x) of the lattice directions' measured time to their model (route.edge_seconds) in the same run.
# per M^2: the Lagrange matrix.  Re-measured on 2026-11-26: one prime, one window, N = 48-120, 0.149 ... 5.35 s
# beyond the lattice directions' evaluations, 0.9-1.2e-7 per M^2, on a machine that ran the route's own primes
# (cost.prime_seconds, edge_seconds) 1.6-1.9x slower than their reference model in the same session; so 5.5e-8
# on the reference machine.  The constant of 2026-11-25 (1e-8) was 5x low.
_SECONDS_PER_LAGRANGE = 5.5e-8
_SECONDS_PER_INTERPOLATION = 5.4e-10  # per M^2 (n + 2): the two BLAS products and the assembly
_SECONDS_PER_CRT = 3e-7  # per value and prime: the Chinese remainders, in the parent process


def _matmul_mod(A: np.ndarray, B: np.ndarray, p: int) -> np.ndarray:
    """``A @ B mod p`` for residues below ``2^25`` and inner size below ``2^13``, by two exact float64 products.

    ``A = A1 2^13 + A0`` with ``0 <= A0, A1 < 2^13`` (``A1 < 2^12``): every
    partial product is below ``2^38`` and a sum of ``k < 2^13`` of them below
    ``2^51``, so the BLAS products are exact integers.
    """
    if A.shape[1] >= 1 << 13:
        raise ArgumentError(f"inner size {A.shape[1]} is out of range: it must be below 8192 (N <= 128)")
    A = A.astype(np.int64)
    A1, A0 = (A >> 13).astype(np.float64), (A & 8191).astype(np.float64)
    B = np.asarray(B, dtype=np.float64)
    high = np.fmod(A1 @ B, p).astype(np.int64)
    low = np.fmod(A0 @ B, p).astype(np.int64)
    return (high * 8192 + low) % p


def edge_level_residues(N: int, p: int, windows: Sequence[int] | None = None) -> np.ndarray:
    """``E[m][l] = sum_{|A| = l} w(A) [N_m(A) = 0] mod p``, ``m = 1..n`` (row 0 unused), ``l = 0..d``.

    ``F_m(q) = Z(q) P_q(no part >= m) = sum_l q^l E[m][l] / (l! (d - l)!)`` is
    evaluated at the ``M`` level points of the mean's route (the window's top
    coefficient at ``c`` and its value at ``y = 0`` for the partner ``1/c``,
    :func:`~.kernels.edge_values`) and interpolated; the coefficients of
    degree above ``d`` must vanish (checked), ``E[m][0] = count`` (the empty
    ideal) and ``E[m][d] = 0`` (the full one).

    Parameters
    ----------
    N : int
        Number of layers, ``N >= 2``.
    p : int
        A prime of the route (:func:`.cost.route_primes`).
    windows : sequence of int, optional
        The ``m`` to interpolate (default: all of ``1..n``); the other rows stay 0.

    Returns
    -------
    numpy.ndarray of int64, shape ``(n + 1, d + 1)``

    Raises
    ------
    ArithmeticError
        If a coefficient above the degree ``d`` does not vanish (inconsistent residues).

    Examples
    --------
    >>> edge_level_residues(4, 8388593)[3].tolist()  # m = 3: P(T(1, 3) > l) count, l = 0..6
    [2, 2, 2, 1, 0, 0, 0]
    """
    N = check_layers(N)
    p = check_prime(N, p)
    n = N - 1
    windows = range(1, n + 1) if windows is None else [check_int(m, "m", 1, n) for m in windows]
    return _edge_level_residues(N, p, windows)


def _edge_level_residues(N: int, p: int, windows: Sequence[int]) -> np.ndarray:
    """:func:`edge_level_residues` for arguments already checked (the workers of :func:`_level_sums`)."""
    n, d = N - 1, dimension(N)
    K = kernel_module()
    out = np.zeros((n + 1, d + 1), dtype=np.int64)
    if n == 0:
        return out
    columns = [n - m for m in windows]  # the window m is the column of the n - m + 1 largest parts
    B, X1, expo = setup_matrices(n, p)
    BC = constants(K, B, expo, n, p)
    M = level_points(d)
    reps: list[int] = []
    partners: list[int] = []
    values: list[np.ndarray] = []
    failures = 0
    stream = pair_points(p, set())
    R = np.empty((2, n))
    while len(reps) < M // 2:
        c, ci = next(stream)
        if not K.edge_values(B, X1, expo, float(c), n, float(p), R, BC):
            failures += 1
            if failures > MAX_POINT_FAILURES:
                raise PointFailureError(f"{failures} evaluation points failed modulo {p}")
            continue
        reps.append(c)
        partners.append(ci)
        values.append(R[:, columns].astype(np.int64))
    z0 = int(K.pfaffian_mod(B.copy(), float(p)))  # Z(q) = Z(0) (1 + q)^d
    points = reps + partners
    F = np.empty((M, len(columns)), dtype=np.int64)
    for i, c in enumerate(points):
        z = z0 * pow(1 + c, d, p) % p
        # representatives: every site of the window in B; partners (complement symmetry): none in B at c
        F[i] = z * (values[i][0] if i < M // 2 else values[i - M // 2][1]) % p
    L = K.lagrange_matrix(np.array(points, dtype=np.float64), float(p)).astype(np.int64)
    coeff = _matmul_mod(L, F, p)  # coeff[l, t]: q^l of the window windows[t]
    if coeff[d + 1 :].any():
        raise ArithmeticError(f"nonzero coefficient beyond the degree d modulo {p}: inconsistent residues")
    fact = [1] * (d + 1)
    for k in range(1, d + 1):
        fact[k] = fact[k - 1] * k % p
    scale = np.array([fact[l] * fact[d - l] % p for l in range(d + 1)], dtype=np.int64)
    for t, m in enumerate(windows):
        out[m] = coeff[: d + 1, t] * scale % p
    return out


def _check_layer_list(N: int, layers: Iterable[int] | None) -> list[int]:
    if layers is None:
        return list(range(2, N + 1))
    return sorted({check_int(i, "i", 2, N) for i in layers})


def lattice_level_sums(N: int, *, layers: Iterable[int] | None = None, workers: int | None = None,
                       progress: Callable[[int], object] | None = None) -> tuple[list[list[int] | None], int]:
    """Exact ``E[m][l] = sum_{|A| = l} w(A) [N_m(A) = 0]`` for every ``m`` and level ``l``, and ``count(N)``.

    ``E[m][l] / count = P(T(1, m) > l)``: the law of the tableau entry of the
    cell ``(1, m)`` (the partial sum ``S_{N-m+1, 1}``).  Multi-modular with the
    proven bound ``0 <= E[m][l] <= count``; checked exactly after the
    reconstruction: ``E[m][0] = count``, ``E[m][d] = 0``, non-increasing in
    ``l`` (``T > l + 1`` implies ``T > l``).

    Parameters
    ----------
    N : int
        Number of layers, ``2..128``.
    layers : sequence of int, optional
        The layers ``i`` (windows ``m = N - i + 1``) wanted, default all of ``2..N``;
        fewer layers save the interpolation and the reconstruction, not the Pfaffians.
    workers : int, optional
        Worker processes (default: the available cores when the run is long
        enough); results do not depend on it.
    progress : callable, optional
        ``progress(1)`` after each prime.

    Returns
    -------
    (E, total) : (list, int)
        ``E[m]`` the list of ``E[m][l]``, ``l = 0..d``, for the requested windows
        (None for the others and for ``m = 0``); ``total = count(N)``.

    Raises
    ------
    ArithmeticError
        If a reconstructed value breaks one of the exact checks.

    Examples
    --------
    >>> E, total = lattice_level_sums(4)
    >>> total, E[3]
    (2, [2, 2, 2, 1, 0, 0, 0])
    """
    N = check_layers(N, maximum=MAX_LAW_N)
    return _level_sums(N, _check_layer_list(N, layers), workers, progress)


def _level_sums(N: int, layers: list[int], workers: int | None,
                progress: Callable[[int], object] | None) -> tuple[list[list[int] | None], int]:
    """:func:`lattice_level_sums` for ``N`` and ``layers`` already checked."""
    n, d = N - 1, dimension(N)
    windows = [N - i + 1 for i in layers]
    total = count(N)
    E: list[list[int] | None] = [None] * (n + 1)
    if n == 0:
        return E, total
    primes = route_primes(N, total)
    nworkers = workers_for(workers, len(primes), law_prime_seconds(N, len(windows)) * len(primes))
    residues = run_primes(_edge_level_residues, [(N, p, windows) for p in primes], None, nworkers,
                          progress, None)  # in the order of the primes
    for m in windows:
        row = crt_many([[r[m, l] for r in residues] for l in range(d + 1)], primes)
        if row[0] != total or row[d] != 0 or any(a < b for a, b in zip(row, row[1:])):
            raise ArithmeticError(f"reconstructed level sums of m={m} break the exact checks")
        E[m] = row
    return E, total


def lattice_gap_laws(N: int, layers: Iterable[int] | None = None, **kwargs: Any) -> dict[int, GapCounts]:
    """Exact rank-gap laws of ``W_{i,1}`` (``= W_{i,i}`` in law, by the mirror symmetry), every layer ``i = 2..N``.

    ``W_{i,1} = S_{i,1}`` is a single tableau entry ``T(1, m)``,
    ``m = N - i + 1``: ``count P(g = h) = E[m][h - 1] - E[m][h]``
    (:func:`lattice_level_sums`).  The law gives the density, the CDF and every
    moment by the Beta mixture of :mod:`forcenet.exact.triangle.distribution`.
    Parameters
    ----------
    N : int
        Number of layers, ``2..128``.
    layers : sequence of int, optional
        The layers ``i`` wanted (default all of ``2..N``).
    **kwargs
        ``workers``, ``progress`` of :func:`lattice_level_sums`.

    Returns
    -------
    dict
        ``{i: GapCounts}`` for the layers ``i`` (``counts`` of length ``d + 2``, ``total = count(N)``).

    Examples
    --------
    >>> lattice_gap_laws(4)[3].counts  # W_{3,1}, N = 4: g = T(1, 2) = 2 in both tableaux
    (0, 0, 2, 0, 0, 0, 0, 0)
    """
    N = check_layers(N, maximum=MAX_LAW_N)
    return _gap_laws(N, _check_layer_list(N, layers), **kwargs)


def _gap_laws(N: int, layers: list[int], workers: int | None = None,
              progress: Callable[[int], object] | None = None) -> dict[int, GapCounts]:
    """:func:`lattice_gap_laws` for ``N`` and ``layers`` already checked."""
    E, total = _level_sums(N, layers, workers, progress)
    laws = {}
    for i in layers:
        row = E[N - i + 1]
        if row is None:
            raise ArithmeticError(f"the level sums of layer {i} are missing")
        d = len(row) - 1  # levels 0..d
        laws[i] = GapCounts(tuple([0] + [row[h - 1] - row[h] for h in range(1, d + 1)] + [0]), total, d)
    return laws


def lattice_mean_W2(N: int, **kwargs: Any) -> list[Fraction]:
    """Exact ``<W_{i,1}^2> = <W_{i,i}^2>`` for ``i = 1..N``: ``E[g (g + 1)] / ((d + 1)(d + 2))``.

    Parameters
    ----------
    N : int
        Number of layers, ``2..128``.
    **kwargs
        As for :func:`lattice_gap_laws` (all layers).

    Returns
    -------
    list of Fraction
        ``<W_{i,1}^2>`` for ``i = 1..N`` (``W_{1,1} = 1``).

    Examples
    --------
    >>> [str(x) for x in lattice_mean_W2(4)]
    ['1', '2/7', '3/28', '1/28']
    """
    N = check_layers(N, maximum=MAX_LAW_N)
    out = [Fraction(1)]
    for _layer, law in sorted(_gap_laws(N, _check_layer_list(N, kwargs.pop("layers", None)), **kwargs).items()):
        num = sum(g * (g + 1) * c for g, c in enumerate(law.counts))
        out.append(Fraction(num, law.total * (law.d + 1) * (law.d + 2)))
    return out


def law_prime_seconds(N: int, windows: int | None = None) -> float:
    """CPU seconds of one prime on the reference machine: the lattice directions' evaluations and the interpolation
    of ``windows`` windows (default all ``N - 1``); ``benchmarks/cost_check.py`` times it on this machine.

    Examples
    --------
    >>> law_prime_seconds(64, 1) < law_prime_seconds(64)
    True
    """
    n, d = N - 1, free_force_count(N)
    M = level_points(d)
    windows = n if windows is None else windows
    return edge_seconds(N) + _SECONDS_PER_LAGRANGE * M**2 + _SECONDS_PER_INTERPOLATION * M**2 * (windows + 3)


def grain_gap_law(N: int, grain: tuple[int, int], **kwargs: Any) -> GapCounts:
    """Exact rank-gap law of one lattice-direction grain ``(i, 1)`` or ``(i, i)``, ``2 <= i <= N``, by Pfaffians.

    The polynomial route of :func:`lattice_gap_laws` for one layer (the same
    Pfaffian evaluations, one window interpolated).  Interior grains
    ``1 < j < i`` are refused: their gap is the difference of two tableau
    entries, which this interpolation of one window's level polynomial does
    not give (``notes/fluctuations.md`` Sec. 3); the order-ideal DP
    (:func:`forcenet.exact.triangle.gaps.grain_gap_counts`) has them to N of about 22.

    Parameters
    ----------
    N : int
        Number of layers, ``2..128``.
    grain : (int, int)
        ``(i, j)`` with ``j = 1`` or ``j = i``, ``2 <= i <= N``.
    **kwargs
        ``workers``, ``progress`` of :func:`lattice_level_sums`.

    Returns
    -------
    GapCounts
        ``counts[g]`` tableaux with gap ``g``, ``total = count(N)``.

    Raises
    ------
    ArgumentError
        If the grain is not on a lattice direction, or ``i = 1`` (``W_{1,1} = 1``).

    Examples
    --------
    >>> grain_gap_law(5, (3, 3)).counts[:6]
    (0, 0, 0, 7, 5, 0)
    """
    N = check_layers(N, maximum=MAX_LAW_N)
    i, j = check_grain(N, grain)
    if i == 1 or j not in (1, i):
        raise ArgumentError(f"grain={tuple(grain)!r} is out of range for the Pfaffian gap law: it must be (i, 1) or "
                         f"(i, i) with 2 <= i <= {N} (interior gaps are two-time quantities, notes/fluctuations.md)")
    return _gap_laws(N, [i], **kwargs)[i]


def lattice_gap_laws_plan(N: int, memory_bytes: int | None = None, workers: int | None = None,
                          layers: int | None = None, *, executor: Executor | None = None) -> Plan:
    """The cost of :func:`lattice_gap_laws`, :func:`lattice_mean_W2` and :func:`grain_gap_law`, one tick per prime.

    Parameters
    ----------
    N : int
        Number of layers.
    memory_bytes : int, optional
        Refuse if the estimated peak memory exceeds it.
    workers : int, optional
        Worker processes, as for the run.
    layers : int, optional
        How many layers are interpolated (default all ``N - 1``; 1 for :func:`grain_gap_law`).
    executor : concurrent.futures.Executor or Dask Client, optional
        Where the per-prime tasks would run: the plan counts its workers
        (:func:`forcenet.exact.triangle.prime_tasks.primes_plan`).

    Returns
    -------
    Plan
        Seconds on the 2-core reference machine, bytes, ticks (primes), or a refusal (N > 128, memory).

    Examples
    --------
    >>> plan = lattice_gap_laws_plan(64)
    >>> plan.runnable, plan.unit
    (True, 'prime')
    >>> lattice_gap_laws_plan(300).refusal
    'N=300 is out of range for the lattice gap laws: N must be an integer in 2..128'
    """
    N = check_layers(N)
    layers = None if layers is None or N > MAX_LAW_N else check_int(layers, "layers", 1, N - 1)
    return lattice_gap_laws_cost(N, memory_bytes, workers, layers, executor=executor)


def lattice_gap_laws_cost(N: int, memory_bytes: int | None = None, workers: int | None = None,
                          layers: int | None = None, *, executor: Executor | None = None) -> Plan:
    """:func:`lattice_gap_laws_plan` of a checked request's ``N`` (and ``layers``): what the engines plan with,
    nothing checked again.

    Examples
    --------
    >>> lattice_gap_laws_cost(64, layers=1) == lattice_gap_laws_plan(64, layers=1)
    True
    """
    what = f"gap laws of W_(i,1) N={N} (Pfaffians)"
    if N > MAX_LAW_N:
        return Plan(what, 0, refusal=f"N={N} is out of range for the lattice gap laws: N must be an integer in 2..{MAX_LAW_N}")
    n, d = N - 1, free_force_count(N)
    nprimes = ceil(tableau_count(N).bit_length() / log2(prime_limit(max(n, 1)) * 0.999))
    windows = n if layers is None else layers
    M = level_points(d)
    per_worker = 8 * (3 * M * M + 2 * M * n) + WORKER_BASE_BYTES
    crt = _SECONDS_PER_CRT * windows * (d + 1) * nprimes
    return primes_plan(what, law_prime_seconds(N, windows), nprimes, per_worker, workers=workers, executor=executor,
                       crt_seconds=crt, memory_bytes=memory_bytes)
