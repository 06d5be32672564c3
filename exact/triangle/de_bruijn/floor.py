"""The floor's exact load laws from its Legendre ensemble: de Bruijn Pfaffians on a grid, in polynomial time.

``notes/fluctuations.md`` Sec. 5 has the derivation.  The free partial sums
``v_1 < ... < v_n`` of the floor (``n = N - 1``) have the density
``prod_{a<b} (v_b - v_a)`` on ``[0, 1]``: a beta = 1 Legendre ensemble.  With
``v_0 = 0``, ``v_N = 1`` the floor loads are its spacings,
``W_{N,j} = v_j - v_{j-1}``, and

    sum_j E[(W_{N,j} - w)_+] = Integral_0^(1-w) E(s, s + w) ds,          (1)

``E(s, t) = P(no point in (s, t))``: the set of ``s`` with ``(s, s + w)``
inside the ``j``-th gap has length ``(W_{N,j} - w)_+``.  Marking the points
below ``s`` with ``zeta`` splits (1) by grain: the coefficient of
``zeta^(j-1)`` is ``E[(W_{N,j} - w)_+]``.  By de Bruijn (1955), ``E`` is a
Pfaffian whose entries are explicit polynomials in ``s``, ``t`` and ``zeta``:

    a_kl = c_kl (zeta^2 s^e + 1 - t^e) + mu_k rho_l - mu_l rho_k,   e = k + l + 2,
    c_kl = (l - k) / ((k+1)(l+1)(k+l+2)),  rho_k = (1 - t^(k+1)) / (k+1),  mu_k = (zeta s^(k+1) - 1) / (k+1),

``k, l = 0..n-1``, bordered by ``m_k = (zeta s^(k+1) + 1 - t^(k+1)) / (k+1)``
when ``n`` is odd, divided by the same Pfaffian at ``s = t``.  Both sides of
(1) are polynomials (``E`` of total degree ``<= d``, (1) of degree
``d + 1`` in ``w``), so (1) holds modulo a prime at any residues: the route
evaluates the Pfaffian at the ``(d + 1)(d + 3)`` nodes ``u = b/d``,
``b = 0..d``, ``w = 0..d+2`` (``s = (1 - w) u``; half of them, the others
are their mirrors ``v -> 1 - v``), integrates in ``u`` by exact quadrature
weights (closed Newton-Cotes), recovers (1) as a polynomial in ``w`` by forward differences (the
extra node checks its degree), and its second derivative, the pooled
density ``sum_g x_g Beta(g, d+1-g)``, in the Bernstein basis gives the gap
law ``count x_g``.  Chinese remainders (bound ``N count``) make it exact;
the total mass ``N count`` and the mean ``sum_g g c_g = (d + 1) count`` are
checked exactly.

Cost per prime: ``(d/2 + 1)(d + 3)`` bordered Pfaffians of order ``n + 2``
per pair ``+-zeta`` (one for the pooled law at ``zeta = 1``, ``(n + 2)/2`` for
every grain's law: a rank-two term enters a Pfaffian affinely).  Their
``n x n`` block is Cauchy-like with four generators, so each costs
``O(n^2)`` by a displacement elimination (:mod:`.floor_displacement`; the lazy
``O(n^3)`` elimination of :mod:`.floor_kernels` is the baseline, 3.3-4.7x
slower at N = 20-44): ``O(n^6)`` pooled, ``O(n^7)`` for every grain.  The
two-dimensional grid is the price of a two-time quantity
(``notes/fluctuations.md`` Sec. 4: no evaluate-and-combine route needs fewer
than ``~ d^2/8`` nodes).

Examples
--------
>>> law = floor_pooled_gap_law(4)  # the four floor loads of N = 4, pooled
>>> law.counts, law.total
((0, 4, 2, 2, 0, 0, 0, 0), 8)
>>> floor_gap_laws(4)[2].counts  # W_{4,2}: the rank gap is 2 or 3
(0, 0, 1, 1, 0, 0, 0, 0)
"""

from __future__ import annotations

from collections.abc import Callable
from concurrent.futures import Executor
from functools import cache
from os import PathLike
from typing import Any

import numpy as np

from forcenet.core.checkpoints import CheckpointStore
from forcenet.core.errors import ArgumentError
from forcenet.core.plan import Plan, with_compilation
from forcenet.core.validation import check_layers

from ...modular import crt_many, primes_for_bound
from ..gap_counts import GapCounts
from ..prime_tasks import WORKER_BASE_BYTES, checkpoint_store, primes_plan, run_primes, workers_for
from ..residues import dual_weights, lagrange_matrix, pfaffian_mod
from ..staircase import count, dimension, free_force_count, tableau_count
from .floor_displacement import bordered_pfaffians, inverse_table
from .floor_kernels import fill, gap_residues, grid, grid_pairs, monomials

__all__ = ["floor_cost", "MAX_FLOOR_N", "floor_primes", "floor_prime_residues", "floor_pooled_gap_law", "floor_gap_laws",
           "floor_plan", "floor_prime_seconds", "de_bruijn_constants", "quadrature_weights", "zeta_coefficients",
           "FLOOR_PRIME_LIMIT", "COMPILE_SECONDS", "grid_gap_residues", "exact_gap_laws", "grid_worker_bytes"]

MAX_FLOOR_N = 128  # the lazy Pfaffian's bound below needs order <= 128
FLOOR_PRIME_LIMIT = 2**22  # lazy elimination: p + 64 * 2 p^2 < 2^53 for every p below it, order <= 128
# Compiling the kernels on a first run (numba's cache empty): 54 s (pooled) and 75 s (every load) measured on
# 2026-11-26 on this machine at load 7, against 19 s for the table's kernels (free_fermion.engine.COMPILE_SECONDS) on the
# reference machine, which this session's machine ran 2-3.5x slower: about 25 s and 35 s there.
COMPILE_SECONDS = {"floor": 25.0, "floor-grains": 35.0}
# CPU seconds per bordered Pfaffian by the displacement kernel: per n^2 (the rows of the n/2 pivots) and per n
# (a pivot's set-up, the loop's prologue, the generators). Fitted on whole primes at N = 20 and 44 (every load;
# 0.52 and 45 ns, checked at N = 28, 36 and on the pooled grid at N = 28-60 within 8 %) on 2026-11-26, then scaled
# by 1.47, the factor by which the same day's machine ran the elimination kernel faster than its own model
# (31.5 s against 46.3 s per prime at N = 36), so that the two models speak of the same reference machine.
# Refitted 2026-12-06 (issue 53: estimates within 1.5x): whole primes of every floor load at N = 16, 24, 32, 40
# took 0.034, 0.415, 2.99, 14.4 CPU s (load ~20 on 2 cores), 0.46-0.63 of the old model, which had the pivot's
# share three times too large (its ratio N = 40 over N = 16 was 328 against the measured 422); least squares
# on the relative error gives 0.88 ns per row and 22 ns per pivot (within 9 % at the four sizes).
_SECONDS_PER_ROW = 8.8e-10
_SECONDS_PER_PIVOT = 2.2e-8


# ------------------------------------------------------------------ one prime


def de_bruijn_constants(n: int, p: int) -> tuple[np.ndarray, np.ndarray]:
    """``(C, iota)`` modulo ``p``: ``C_kl = (l - k)/((k+1)(l+1)(k+l+2))`` and ``iota_k = 1/(k+1)``, ``k, l < n``.

    Examples
    --------
    >>> C, iota = de_bruijn_constants(2, 7)
    >>> C.tolist(), iota.tolist()  # C_01 = 1/(1*2*3) = 6 mod 7
    ([[0.0, 6.0], [1.0, 0.0]], [1.0, 4.0])
    """
    iota = np.array([pow(k + 1, p - 2, p) for k in range(n)], dtype=np.float64)
    C = np.zeros((n, n))
    for k in range(n):
        for m in range(n):
            C[k, m] = (m - k) % p * pow((k + 1) * (m + 1) * (k + m + 2), p - 2, p) % p
    return C, iota


def _zeta_nodes(n: int) -> tuple[np.ndarray, int, list[int]]:
    """``n + 1`` fugacities in pairs ``+-z`` (and 0 when ``n`` is even): ``(zpos, with_zero, the column order)``."""
    with_zero = 1 - n % 2
    zpos = np.arange(1, (n + 1 - with_zero) // 2 + 1, dtype=np.float64)
    nodes = [0] * with_zero + [v for z in range(1, len(zpos) + 1) for v in (z, -z)]
    return zpos, with_zero, nodes


def quadrature_weights(d: int, p: int) -> np.ndarray:
    """Closed Newton-Cotes weights on the nodes ``u = b/d``, ``b = 0..d``, modulo ``p``: the functional
    ``Integral_0^1 u^k du = 1/(k+1)``, ``k <= d``, on the Lagrange basis.

    Examples
    --------
    >>> quadrature_weights(2, 7).tolist()  # Simpson: 1/6, 4/6, 1/6
    [6.0, 3.0, 6.0]
    """
    nodes_u = np.array([b * pow(d, p - 2, p) % p for b in range(d + 1)], dtype=np.float64)
    return dual_weights(nodes_u, np.array([pow(k + 1, p - 2, p) for k in range(d + 1)], dtype=np.float64), float(p))


def zeta_coefficients(values: np.ndarray, lagrange: np.ndarray, p: int) -> np.ndarray:
    """Rows: the coefficients in ``zeta`` of each row of values (columns at the nodes of the Lagrange matrix
    :func:`~.kernels.lagrange_matrix`, residues below ``2^22``: the products stay exact in ``int64``)."""
    return (values.astype(np.int64) @ lagrange.astype(np.int64).T) % p


def floor_prime_residues(N: int, p: int, grains: bool = False, kernel: str = "displacement") -> np.ndarray:
    """The floor's gap counts modulo one prime: pooled (one row) or of every grain ``j = 1..N`` (``N`` rows).

    Parameters
    ----------
    N : int
        Number of layers, ``2..128``.
    p : int
        A prime of the route (:func:`floor_primes`).
    grains : bool
        Every grain's law (``n + 1`` values of ``zeta``) instead of the pooled one (``zeta = 1``).
    kernel : {"displacement", "elimination"}
        How each Pfaffian is evaluated: by its displacement structure
        (:mod:`.floor_displacement`, ``O(n^2)``, the default) or by the lazy
        elimination of the explicit matrix (``O(n^3)``; the baseline).  Same residues.

    Returns
    -------
    numpy.ndarray
        ``int64``, shape ``(rows, d + 2)``: ``counts[g]`` modulo ``p``.

    Raises
    ------
    ArithmeticError
        If the recovered polynomial (1) has a degree above ``d + 1`` (it never has), or the normalization vanishes.

    Examples
    --------
    >>> floor_prime_residues(3, 4194301).tolist()
    [[0, 2, 1, 0, 0]]
    """
    N = check_layers(N, maximum=MAX_FLOOR_N)
    if kernel not in ("displacement", "elimination"):
        raise ArgumentError(f"kernel={kernel!r} is out of range: it must be 'displacement' or 'elimination'")
    displacement = kernel == "displacement"
    n, d = N - 1, dimension(N)
    C, iota = de_bruijn_constants(n, p)
    invx = inverse_table(n, p)
    lam = quadrature_weights(d, p)
    size = n + (n % 2)
    A = np.zeros((size, size))
    fill(A, n, size, 0.0, 0.0, 1.0, C, iota, np.empty(2 * n + 1), np.empty(2 * n + 1), p, 1.0 / p, True)
    Z = int(pfaffian_mod(A, p))
    if Z == 0:
        raise ArithmeticError(f"the floor's normalization vanishes modulo p={p}")
    if grains:  # A(zeta) + zeta^n B(1/zeta), in coefficients
        zpos, with_zero, nodes = _zeta_nodes(n)
        half, mirror, _failures = grid_pairs(n, d, p, zpos, with_zero, lam, C, iota, invx, displacement)
        lagrange = lagrange_matrix(np.array([z % p for z in nodes], dtype=np.float64), float(p))
        values = (zeta_coefficients(half, lagrange, p) + zeta_coefficients(mirror, lagrange, p)[:, ::-1]) % p
    else:
        half, mirror, _failures = grid(n, d, p, lam, C, iota, invx, displacement)
        values = (half + mirror) % p
    return grid_gap_residues(values, Z, N, p, "the floor")


def grid_gap_residues(values: np.ndarray, Z: int, N: int, p: int, what: str) -> np.ndarray:
    """The gap counts modulo ``p`` from a grid's sums (rows ``w = 0..d+2``, a column per law) and the
    normalization ``Z``: ``int64``, shape ``(laws, d + 2)``; ``what`` names the route in the error.

    Raises
    ------
    ArithmeticError
        If a recovered polynomial (1) has a degree above ``d + 1``.
    """
    d = dimension(N)
    rows = (values.astype(np.int64) * pow(Z, p - 2, p) % p).T.astype(np.float64)  # rows: grain j = k + 1, or the pool
    total_mod = float(count(N) % p)
    out = np.empty((rows.shape[0], d + 2), dtype=np.int64)
    for r, J in enumerate(rows):
        g = gap_residues(np.ascontiguousarray(J), d, total_mod, p)
        if g[0] < 0:
            raise ArithmeticError(f"{what}'s integral (1) has degree above d + 1 modulo p={p}")
        out[r] = g.astype(np.int64)
    return out


# ------------------------------------------------------------------ exact laws


@cache  # every layer's plan asks for the same primes (moments_plan, ensemble_route)
def floor_primes(N: int) -> tuple[int, ...]:
    """The primes of the floor route: below ``2^22``, above ``max(2N + 3, d + 3)``, product above ``N count(N)``.

    Examples
    --------
    >>> floor_primes(5)
    (4194301,)
    """
    N = check_layers(N, maximum=MAX_FLOOR_N)
    return primes_for_bound(N * tableau_count(N), limit=FLOOR_PRIME_LIMIT,
                            smallest=max(2 * N + 3, free_force_count(N) + 3))


def _laws(N: int, grains: bool, workers: int | None, progress: Callable[..., Any] | None,
          executor: Executor | None, checkpoint: str | PathLike | CheckpointStore | None) -> list[GapCounts]:
    total = count(N)
    primes = floor_primes(N)
    # a record: one gap law (gaps 0..d + 1) per grain of the floor, or the pooled one
    store = checkpoint_store(checkpoint, "floor-grains" if grains else "floor", N,
                             shape=(N if grains else 1, dimension(N) + 2))
    nworkers = workers_for(workers, len(primes), floor_prime_seconds(N, grains) * len(primes), executor)
    residues = run_primes(floor_prime_residues, [(N, p, grains) for p in primes], executor, nworkers, progress, store)
    return exact_gap_laws(residues, primes, N, total * (N if not grains else 1), "the floor")


def exact_gap_laws(residues: list, primes: tuple[int, ...], N: int, mass: int, what: str) -> list[GapCounts]:
    """The exact gap laws of one row of ``loads`` by Chinese remainders of every prime's residues, checked: each
    law's mass ``mass``, and the loads' gaps summing to ``(d + 1) count`` (the loads of a layer sum to 1)."""
    d, total = dimension(N), count(N)
    laws = []
    for r in range(residues[0].shape[0]):
        counts = crt_many([[int(res[r, g]) for res in residues] for g in range(d + 2)], primes)
        if counts[0] or counts[d + 1] or sum(counts) != mass or any(c > mass for c in counts):
            raise ArithmeticError(f"{what}'s reconstructed gap law {r} breaks the exact checks (mass {mass})")
        laws.append(GapCounts(tuple(counts), mass, d))
    if sum(g * c for law in laws for g, c in enumerate(law.counts)) != (d + 1) * total:
        raise ArithmeticError(f"{what}'s reconstructed gap laws do not sum to the overload")
    return laws


def floor_pooled_gap_law(N: int, *, workers: int | None = None, progress: Callable[..., Any] | None = None,
                         executor: Executor | None = None,
                         checkpoint: str | PathLike | CheckpointStore | None = None) -> GapCounts:
    """Exact rank-gap law of the floor's ``N`` loads ``W_{N,1..N}``, pooled, by de Bruijn Pfaffians (module docstring).

    Equal to ``pool_gaps(layer_gap_counts(N, N))`` of the order-ideal DP
    (tested), which stops near N = 22; this route is polynomial (``O(n^6)``
    per prime, :func:`floor_plan`).  The pooled density, its CDF and moments
    follow from :mod:`forcenet.exact.triangle.distribution`
    (``density_from_gaps``; ``f = N W`` for the floor's ``P(f)``).

    Parameters
    ----------
    N : int
        Number of layers, ``2..128``.
    workers : int, optional
        Local worker processes (default: the available cores when the run is long enough).
    progress : callable, optional
        ``progress(1)`` after each prime.
    executor : concurrent.futures.Executor or dask Client, optional
        Where the per-prime tasks run (:func:`forcenet.core.execution.run_tasks`).
    checkpoint : path or CheckpointStore, optional
        Keep every finished prime there; a rerun reuses them.

    Returns
    -------
    GapCounts
        ``counts[g] = sum_j #{tableaux with gap g at W_{N,j}}``, ``total = N count(N)``.

    Raises
    ------
    ArgumentError
        If ``N`` is out of range.

    Examples
    --------
    >>> from forcenet.exact.triangle.distribution import moment_from_gaps
    >>> moment_from_gaps(floor_pooled_gap_law(5), 2)  # <W^2> over the floor of N = 5
    Fraction(127, 1980)
    """
    N = check_layers(N, maximum=MAX_FLOOR_N)
    return _laws(N, False, workers, progress, executor, checkpoint)[0]


def floor_gap_laws(N: int, *, workers: int | None = None, progress: Callable[..., Any] | None = None,
                   executor: Executor | None = None,
                   checkpoint: str | PathLike | CheckpointStore | None = None) -> dict[int, GapCounts]:
    """Exact rank-gap law of every floor load ``W_{N,j}``, ``j = 1..N``, by de Bruijn Pfaffians with a fugacity.

    The pooled route (:func:`floor_pooled_gap_law`) at ``zeta = 0..n``: ``n + 1``
    times its cost.  Parameters as there.

    Returns
    -------
    dict
        ``{j: GapCounts}``, ``total = count(N)``.

    Examples
    --------
    >>> laws = floor_gap_laws(5)
    >>> laws[1].counts[:3], laws[1] == laws[5]  # the corner is Beta(1, d); the mirror symmetry
    ((0, 12, 0), True)
    """
    N = check_layers(N, maximum=MAX_FLOOR_N)
    laws = _laws(N, True, workers, progress, executor, checkpoint)
    return {j: law for j, law in enumerate(laws, start=1)}


def floor_prime_seconds(N: int, grains: bool = False) -> float:
    """CPU seconds of one prime of the floor route on the reference machine.

    Examples
    --------
    >>> 18 < floor_prime_seconds(40, grains=True) / floor_prime_seconds(40) < 24  # n + 1 fugacities, in pairs
    True
    """
    n, d = N - 1, free_force_count(N)
    nodes = (d // 2 + 1) * (d + 3)  # half the grid: the mirror
    lanes = (n + 2) // 2 if grains else 1  # one bordered Pfaffian per pair +-zeta
    return nodes * lanes * (_SECONDS_PER_ROW * n * n + _SECONDS_PER_PIVOT * n)


def grid_worker_bytes(N: int) -> int:
    """Peak bytes of one worker of the de Bruijn grids (the floor's and a layer's): four rows of ``N + 1`` per node
    of a ``d + 3`` column, beside the worker process itself.

    Examples
    --------
    >>> grid_worker_bytes(40) - WORKER_BASE_BYTES  # d = 780
    1027296
    """
    return 8 * (free_force_count(N) + 3) * (N + 1) * 4 + WORKER_BASE_BYTES


def floor_plan(N: int, grains: bool = False, memory_bytes: int | None = None, workers: int | None = None, *,
               executor: Executor | None = None) -> Plan:
    """The cost of :func:`floor_pooled_gap_law` (or :func:`floor_gap_laws`), one tick per prime.

    On ``executor`` (a Dask cluster's included) the plan counts its workers
    (:func:`forcenet.exact.triangle.prime_tasks.primes_plan`), else ``workers``
    local processes.

    Examples
    --------
    >>> plan = floor_plan(40)
    >>> plan.runnable, plan.unit, plan.ticks
    (True, 'prime', 109)
    >>> floor_plan(200).refusal
    'N=200 is out of range for the floor route: N must be an integer in 2..128'
    """
    return floor_cost(check_layers(N), grains, memory_bytes, workers, executor=executor)


def floor_cost(N: int, grains: bool = False, memory_bytes: int | None = None, workers: int | None = None, *,
               executor: Executor | None = None, store: CheckpointStore | None = None) -> Plan:
    """:func:`floor_plan` of a checked request's ``N``: what the engines plan with, nothing checked again;
    with the floor's ``store``, only the primes it does not hold yet.

    Examples
    --------
    >>> floor_cost(40) == floor_plan(40)
    True
    """
    what = f"the floor's {'gap laws' if grains else 'pooled gap law'} N={N} (de Bruijn Pfaffians)"
    if N > MAX_FLOOR_N:
        return Plan(what, 0, refusal=f"N={N} is out of range for the floor route: N must be an integer in 2..{MAX_FLOOR_N}")
    per_worker = grid_worker_bytes(N)
    kernels = [grid_pairs if grains else grid, bordered_pfaffians, monomials, gap_residues, pfaffian_mod]
    name = "floor-grains" if grains else "floor"
    primes = floor_primes(N)
    reused = sum(store.holds(p) for p in primes) if store is not None else 0  # a resumed run: only the rest
    return primes_plan(what, floor_prime_seconds(N, grains), len(primes), per_worker, workers=workers,
                       executor=executor, store=store, reused=reused, memory_bytes=memory_bytes,
                       compile=lambda plan, in_workers: with_compilation(plan, f"Pfaffian {name}", COMPILE_SECONDS[name],
                                                                          kernels, in_workers=in_workers))
