"""Every layer's exact load laws from de Bruijn Pfaffians, in polynomial time: the floor's route, one layer up or more.

``notes/fluctuations.md`` Sec. 6 has the derivation.  Layer ``i`` has
``m = i - 1`` free partial sums ``u`` and ``k = N - i`` layers below it; the
floor ``v`` (``n = N - 1`` points) has ``m + k = n``.  The whole pattern is
uniform, so the density of ``u`` is ``Delta(u)`` (the patterns above, a
Gelfand-Tsetlin volume) times the volume of the patterns below with the
floor in ``[0, 1]``.  That volume between ``u`` and a fixed ``v`` is the
determinant ``det[[(v_b - u_a)_+^(k-1)]_(a<=m); [v_b^r]_(r<k)]`` (up to a
constant; ``k = 1`` is the interlacing indicator), and integrating the
floor by de Bruijn (1955) turns it into a Pfaffian of order ``n + n % 2``:
rows ``a <= m`` with the kernel

    K(x, y) = ((y - x)/k) Integral_y^1 ((q - x)(q - y))^(k-1) dq
            = (1/k) sum_(j<k) C(k-1, j)/(k+j) (y - x)^(k-j) (1 - y)^(k+j)      (x < y),

``k`` constant rows ``r`` against them with
``L_r(x) = (1/(r+1)) Integral_x^1 (q - x)^(k-1) (1 - 2 q^(r+1)) dq``, the
floor's constants ``(r' - r)/((r+1)(r'+1)(r+r'+2))`` among them and, for odd
``n``, a border ``(1 - x)^k/k`` and ``1/(r+1)``.  A second de Bruijn
integration, against ``Delta(u) chi(u)``, gives the gap probability of the
layer as the floor's (:mod:`.floor`): a Pfaffian whose entries are explicit
polynomials in ``s``, ``t``, ``zeta`` (:mod:`.layer_kernels`), evaluated on
the floor's grid, integrated in ``s`` and interpolated in ``w``; its second
derivative gives the gap law.  Verified in sympy against the DP's density
for every load of every layer at N = 4, 5, 6, and by this route against the
DP for every layer to N = 10 (tests/test_layers.py).

Cost per prime: the floor's ``(d/2 + 1)(d + 3)`` nodes, one Pfaffian of order
``n + n % 2`` per node and fugacity (one for the pooled law, ``m + 1`` for
every load of the layer), ``O(n^3 + m^2 k)`` each: ``O(n^7)`` pooled.

Examples
--------
>>> law = layer_pooled_gap_law(5, 3)  # the three loads of layer 3, N = 5, pooled
>>> law.total, sum(g * c for g, c in enumerate(law.counts)) == (law.d + 1) * law.total // 3
(36, True)
>>> from forcenet.exact.triangle.gap_counts import pool_gaps
>>> from forcenet.exact.triangle.gaps import layer_gap_counts
>>> law == pool_gaps(layer_gap_counts(5, 3))  # the order-ideal DP
True
"""

from __future__ import annotations

from collections.abc import Callable
from concurrent.futures import Executor
from math import comb
from os import PathLike
from typing import Any

import numpy as np

from forcenet.core.checkpoints import CheckpointStore
from forcenet.core.plan import Plan, with_compilation
from forcenet.core.validation import check_int, check_layers

from ..gap_counts import GapCounts
from ..prime_tasks import checkpoint_store, primes_plan, run_primes, workers_for
from ..residues import lagrange_matrix, pfaffian_mod
from ..staircase import count, dimension, free_force_count
from .floor import (
    COMPILE_SECONDS,
    MAX_FLOOR_N,
    exact_gap_laws,
    floor_primes,
    grid_gap_residues,
    grid_worker_bytes,
    quadrature_weights,
    zeta_coefficients,
)
from .floor_kernels import gap_residues, monomials, pfaffian_lazy
from .layer_kernels import layer_fill, layer_grid

__all__ = ["layer_cost", "layer_tables", "layer_prime_residues", "layer_pooled_gap_law", "layer_gap_laws", "layer_plan",
           "layer_prime_seconds"]

# CPU seconds of the grid, on the floor's reference machine: per node (the fill: powers, moments, two small matrix
# products), per fugacity (a combination of the three parts) and per cube of the order (the lazy elimination).
# Fitted on whole primes, pooled and every load, N = 20-44, layers 3..N-1, on 2026-11-26 on this machine (3.2 us,
# 0.6 us, 2.2e-10 s; within 25 %), then scaled by the floor model's 1.47 (floor._SECONDS_PER_ROW) so that both
# models speak of the same reference machine. Rescaled by 0.6 on 2026-12-06 (issue 53: estimates within 1.5x):
# whole primes of every load of layer N/2 at N = 24 and 32 took 1.95 and 13.2 CPU s, 0.64 and 0.54 of the model
# (the floor's refit, floor._SECONDS_PER_ROW, no longer carries the 1.47 either).
_SECONDS_PER_NODE = 2.8e-6
_SECONDS_PER_FUGACITY = 0.54e-6
_SECONDS_PER_CUBE = 1.9e-10


# ------------------------------------------------------------------ one prime


def layer_tables(N: int, i: int, p: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The kernel of layer ``i`` modulo ``p`` in the reflected variable ``a = 1 - x`` (module docstring,
    :mod:`.layer_kernels`): ``(kappa, lam, w, iota)``, ``float64`` residues.

    ``K = sum_alpha kappa[alpha] a_x^alpha a_y^(2k - alpha)`` (homogeneous),
    ``L_r = sum_g lam[r, g] a^g``, ``w[c] = sum_alpha kappa[alpha]/(c + 2k - alpha + 1)``
    (``c < m``), ``iota[a] = 1/(a + 1)`` for ``a < 4N + 4``.

    Examples
    --------
    >>> kappa, lam, w, iota = layer_tables(4, 3, 101)  # k = 1: K = (a_x - a_y) a_y, L_0 = a^2 - a
    >>> kappa.tolist(), lam.tolist()
    ([100.0, 1.0], [[0.0, 100.0, 1.0, 0.0]])
    """
    N = check_layers(N, maximum=MAX_FLOOR_N)
    i = check_int(i, "i", 2, N - 1)
    m, k = i - 1, N - i
    inv = [0] + [pow(a, p - 2, p) for a in range(1, 4 * N + 6)]
    kappa = [0] * (k + 1)
    for j in range(k):  # (1/k) C(k-1, j)/(k+j) (a_x - a_y)^(k-j) a_y^(k+j)
        c = inv[k] * comb(k - 1, j) * inv[k + j]
        for al in range(k - j + 1):
            kappa[al] += c * comb(k - j, al) * (-1) ** (k - j - al)
    kappa = [c % p for c in kappa]
    lam = np.zeros((k, 2 * k + 2), dtype=np.int64)
    for r in range(k):  # (1/(r+1)) [a^k/k - 2 sum_j C(r+1, j)/(k+j) (1 - a)^(r+1-j) a^(k+j)]
        row = [0] * (2 * k + 2)
        row[k] += inv[k]
        for j in range(r + 2):
            c = -2 * comb(r + 1, j) * inv[k + j]
            for l in range(r + 2 - j):
                row[k + j + l] += c * comb(r + 1 - j, l) * (-1) ** l
        lam[r] = [c % p * inv[r + 1] % p for c in row]
    w = [sum(kappa[al] * inv[c + 2 * k - al + 1] for al in range(k + 1)) % p for c in range(m)]
    iota = np.array(inv[1:4 * N + 5], dtype=np.float64)
    return (np.array(kappa, dtype=np.float64), lam.astype(np.float64), np.array(w, dtype=np.float64), iota)


def layer_prime_residues(N: int, i: int, p: int, grains: bool = False) -> np.ndarray:
    """Layer ``i``'s gap counts modulo one prime: pooled (one row) or of every load ``j = 1..i`` (``i`` rows).

    Parameters
    ----------
    N : int
        Number of layers, ``3..128``.
    i : int
        The layer, ``2..N-1`` (the floor, ``i = N``, is :func:`.floor.floor_prime_residues`).
    p : int
        A prime of the route (:func:`.floor.floor_primes`).
    grains : bool
        Every load's law (``m + 1`` values of ``zeta``) instead of the pooled one (``zeta = 1``).

    Returns and raises as :func:`.floor.floor_prime_residues` (``counts[g]``
    modulo ``p``, ``int64``, one row per law; ``ArithmeticError`` if a check fails).

    Examples
    --------
    >>> layer_prime_residues(3, 2, 4194301).tolist()  # W_{2,1}, W_{2,2} of N = 3, pooled: both of gap 2
    [[0, 0, 2, 0, 0]]
    """
    N = check_layers(N, maximum=MAX_FLOOR_N)
    i = check_int(i, "i", 2, N - 1)
    m, k, d = i - 1, N - i, dimension(N)
    kappa, lam, w, iota = layer_tables(N, i, p)
    size = N - 1 + (N - 1) % 2
    A = np.zeros((size, size))
    layer_fill(A, m, k, 0.0, 0.0, 1.0, kappa, lam, w, iota, p, 1.0 / p, True)
    Z = int(pfaffian_mod(A, p))
    if Z == 0:
        raise ArithmeticError(f"layer {i}'s normalization vanishes modulo p={p}")
    zetas = np.arange(m + 1, dtype=np.float64) if grains else np.ones(1)
    half, mirror, _failures = layer_grid(m, k, d, p, zetas, quadrature_weights(d, p), kappa, lam, w, iota)
    if grains:  # A(zeta) + zeta^m B(1/zeta), in coefficients
        lagrange = lagrange_matrix(zetas, float(p))
        values = (zeta_coefficients(half, lagrange, p) + zeta_coefficients(mirror, lagrange, p)[:, ::-1]) % p
    else:
        values = (half + mirror) % p
    return grid_gap_residues(values, Z, N, p, f"layer {i}")


def _prime_task(N: int, p: int, i: int, grains: bool) -> np.ndarray:
    """:func:`layer_prime_residues` with the prime second: the tasks' checkpoint key (:func:`forcenet.exact.triangle.prime_tasks.run_primes`)."""
    return layer_prime_residues(N, i, p, grains)


# ------------------------------------------------------------------ exact laws


def _laws(N: int, i: int, grains: bool, workers: int | None, progress: Callable[..., Any] | None,
          executor: Executor | None, checkpoint: str | PathLike | CheckpointStore | None) -> list[GapCounts]:
    total = count(N)
    primes = floor_primes(N)
    # a record: one gap law (gaps 0..d + 1) per grain of layer i, or the pooled one
    store = checkpoint_store(checkpoint, "layer-grains" if grains else "layer", N, layer=i,
                             shape=(i if grains else 1, dimension(N) + 2))
    nworkers = workers_for(workers, len(primes), layer_prime_seconds(N, i, grains) * len(primes), executor)
    residues = run_primes(_prime_task, [(N, p, i, grains) for p in primes], executor, nworkers, progress, store)
    return exact_gap_laws(residues, primes, N, total * (i if not grains else 1), f"layer {i}")


def layer_pooled_gap_law(N: int, i: int, *, workers: int | None = None,
                         progress: Callable[..., Any] | None = None, executor: Executor | None = None,
                         checkpoint: str | PathLike | CheckpointStore | None = None) -> GapCounts:
    """Exact rank-gap law of layer ``i``'s loads ``W_{i,1..i}``, pooled, by de Bruijn Pfaffians (module docstring).

    Equal to ``pool_gaps(layer_gap_counts(N, i))`` of the order-ideal DP
    (tested), which stops near N = 22-30; this route is polynomial
    (:func:`layer_plan`).  The floor (``i = N``) is :func:`.floor.floor_pooled_gap_law`.

    Parameters
    ----------
    N : int
        Number of layers, ``3..128``.
    i : int
        The layer, ``2..N-1``.
    workers, progress, executor, checkpoint
        As for :func:`.floor.floor_pooled_gap_law`: local processes, a tick per
        prime, where the per-prime tasks run, the records a rerun reuses.

    Returns
    -------
    GapCounts
        ``counts[g] = sum_j #{tableaux with gap g at W_{i,j}}``, ``total = i count(N)``.

    Raises
    ------
    ArgumentError
        If ``N`` or ``i`` is out of range.

    Examples
    --------
    >>> from forcenet.exact.triangle.gap_counts import moment_from_gaps
    >>> moment_from_gaps(layer_pooled_gap_law(5, 4), 2)  # <W^2> over layer 4 of N = 5
    Fraction(1, 12)
    """
    N = check_layers(N, maximum=MAX_FLOOR_N)
    i = check_int(i, "i", 2, N - 1)
    return _laws(N, i, False, workers, progress, executor, checkpoint)[0]


def layer_gap_laws(N: int, i: int, *, workers: int | None = None, progress: Callable[..., Any] | None = None,
                   executor: Executor | None = None,
                   checkpoint: str | PathLike | CheckpointStore | None = None) -> dict[int, GapCounts]:
    """Exact rank-gap law of every load ``W_{i,j}``, ``j = 1..i``, of layer ``i``, by de Bruijn Pfaffians with a
    fugacity: :func:`layer_pooled_gap_law` at ``zeta = 0..i-1``, ``i`` times its cost.  Parameters as there;
    returns ``{j: GapCounts}`` with ``total = count(N)``.

    Examples
    --------
    >>> laws = layer_gap_laws(6, 4)
    >>> laws[2] == laws[3], laws[1].counts[:3]  # the mirror; W_{4,1} has gap >= 3 below the corner of layer 4
    (True, (0, 0, 0))
    """
    N = check_layers(N, maximum=MAX_FLOOR_N)
    i = check_int(i, "i", 2, N - 1)
    laws = _laws(N, i, True, workers, progress, executor, checkpoint)
    return {j: law for j, law in enumerate(laws, start=1)}


def layer_prime_seconds(N: int, i: int, grains: bool = False) -> float:
    """CPU seconds of one prime of the layers' route on the reference machine.

    Examples
    --------
    >>> 20 < layer_prime_seconds(30, 29, grains=True) / layer_prime_seconds(30, 29) < 29  # i values of zeta
    True
    """
    n, d, m = N - 1, free_force_count(N), i - 1
    nodes = (d // 2 + 1) * (d + 3)  # half the grid: the mirror
    pfaffian = _SECONDS_PER_CUBE * (n + n % 2) ** 3
    if not grains:
        return nodes * (_SECONDS_PER_NODE + pfaffian)
    fills = 3 if m + 1 > 3 else m + 1  # the parts at zeta = 0, 1, -1, or each zeta itself
    return nodes * (fills * _SECONDS_PER_NODE + (m + 1) * (_SECONDS_PER_FUGACITY + pfaffian))


def layer_plan(N: int, i: int, grains: bool = False, memory_bytes: int | None = None,
               workers: int | None = None, *, executor: Executor | None = None) -> Plan:
    """The cost of :func:`layer_pooled_gap_law` (or :func:`layer_gap_laws`), one tick per prime.

    On ``executor`` the plan counts its workers
    (:func:`forcenet.exact.triangle.prime_tasks.primes_plan`), else ``workers``
    local processes.

    Examples
    --------
    >>> plan = layer_plan(40, 39)
    >>> plan.runnable, plan.unit, plan.ticks
    (True, 'prime', 109)
    """
    N = check_layers(N, maximum=MAX_FLOOR_N)
    return layer_cost(N, check_int(i, "i", 2, N - 1), grains, memory_bytes, workers, executor=executor)


def layer_cost(N: int, i: int, grains: bool = False, memory_bytes: int | None = None,
               workers: int | None = None, *, executor: Executor | None = None,
               store: CheckpointStore | None = None) -> Plan:
    """:func:`layer_plan` of a checked request's numbers (``2 <= i < N <= 128``): what the engines plan with, every
    layer of a table or of the ensemble, nothing checked again; with the layer's ``store``, only the primes it does
    not hold yet.

    Examples
    --------
    >>> layer_cost(40, 39) == layer_plan(40, 39)
    True
    """
    what = f"layer {i}'s {'gap laws' if grains else 'pooled gap law'} N={N} (de Bruijn Pfaffians)"
    per_worker = grid_worker_bytes(N)
    kernels = [layer_grid, layer_fill, pfaffian_lazy, monomials, gap_residues, pfaffian_mod]
    primes = floor_primes(N)
    reused = sum(store.holds(p) for p in primes) if store is not None else 0  # a resumed run: only the rest
    return primes_plan(what, layer_prime_seconds(N, i, grains), len(primes), per_worker, workers=workers,
                       executor=executor, store=store, reused=reused, memory_bytes=memory_bytes,
                       compile=lambda plan, in_workers: with_compilation(plan, "Pfaffian layers", COMPILE_SECONDS["floor"],
                                                                          kernels, in_workers=in_workers))
