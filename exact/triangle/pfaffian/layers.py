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
>>> law == pool_gaps(layer_gap_counts(5, 3))  # the order-ideal DP
True
"""

from __future__ import annotations

from collections.abc import Callable
from concurrent.futures import Executor
from dataclasses import replace
from fractions import Fraction
from math import comb
from os import PathLike
from typing import Any

import numpy as np

from forcenet.core.errors import ArgumentError
from forcenet.core.plan import Plan, combine, with_compilation
from forcenet.core.validation import check_int, check_layers
from forcenet.core.checkpoints import CheckpointStore
from ..distribution import distribution_plan, layer_pieces_from_gaps, pool_gaps, triangle_force_density
from ..gaps import GapCounts, gap_laws_plan, layer_gap_counts
from ..pieces import Piece, sum_pieces
from ..staircase import count, dimension
from .cost import STARTUP_SECONDS, WORKER_BASE_BYTES
from .floor import (COMPILE_SECONDS, MAX_FLOOR_N, exact_gap_laws, floor_plan, floor_pooled_gap_law, floor_primes,
                    grid_gap_residues, quadrature_weights, zeta_coefficients)
from .floor_kernels import gap_residues, monomials, pfaffian_lazy
from .kernels import lagrange_matrix, pfaffian_mod
from .layer_kernels import layer_fill, layer_grid
from .tasks import checkpoint_store, run_primes, workers_for

__all__ = ["layer_tables", "layer_prime_residues", "layer_pooled_gap_law", "layer_gap_laws", "layer_plan",
           "layer_prime_seconds", "layer_route", "layer_gap_law", "floor_contact_gap_law", "ensemble_route",
           "ensemble_pieces"]

# CPU seconds of the grid, on the floor's reference machine: per node (the fill: powers, moments, two small matrix
# products), per fugacity (a combination of the three parts) and per cube of the order (the lazy elimination).
# Fitted on whole primes, pooled and every load, N = 20-44, layers 3..N-1, on 2026-11-26 on this machine (3.2 us,
# 0.6 us, 2.2e-10 s; within 25 %), then scaled by the floor model's 1.47 (floor._SECONDS_PER_ROW) so that both
# models speak of the same reference machine.
_SECONDS_PER_NODE = 4.7e-6
_SECONDS_PER_FUGACITY = 0.9e-6
_SECONDS_PER_CUBE = 3.2e-10


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
    """:func:`layer_prime_residues` with the prime second: the tasks' checkpoint key (:func:`.tasks.run_primes`)."""
    return layer_prime_residues(N, i, p, grains)


# ------------------------------------------------------------------ exact laws


def _laws(N: int, i: int, grains: bool, workers: int | None, progress: Callable[..., Any] | None,
          executor: Executor | None, checkpoint: str | PathLike | CheckpointStore | None) -> list[GapCounts]:
    total = count(N)
    primes = floor_primes(N)
    store = checkpoint_store(checkpoint, "layer-grains" if grains else "layer", N, layer=i)
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
    >>> from forcenet.exact.triangle.distribution import moment_from_gaps
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
    n, d, m = N - 1, dimension(N), i - 1
    nodes = (d // 2 + 1) * (d + 3)  # half the grid: the mirror
    pfaffian = _SECONDS_PER_CUBE * (n + n % 2) ** 3
    if not grains:
        return nodes * (_SECONDS_PER_NODE + pfaffian)
    fills = 3 if m + 1 > 3 else m + 1  # the parts at zeta = 0, 1, -1, or each zeta itself
    return nodes * (fills * _SECONDS_PER_NODE + (m + 1) * (_SECONDS_PER_FUGACITY + pfaffian))


def layer_plan(N: int, i: int, grains: bool = False, memory_bytes: int | None = None,
               workers: int | None = None) -> Plan:
    """The cost of :func:`layer_pooled_gap_law` (or :func:`layer_gap_laws`), one tick per prime.

    Examples
    --------
    >>> plan = layer_plan(40, 39)
    >>> plan.runnable, plan.unit, plan.ticks
    (True, 'prime', 109)
    """
    N = check_layers(N, maximum=MAX_FLOOR_N)
    i = check_int(i, "i", 2, N - 1)
    what = f"layer {i}'s {'gap laws' if grains else 'pooled gap law'} N={N} (de Bruijn Pfaffians)"
    nprimes = len(floor_primes(N))
    cpu = layer_prime_seconds(N, i, grains) * nprimes
    nworkers = workers_for(workers, nprimes, cpu)
    per_worker = 8 * (dimension(N) + 3) * (N + 1) * 4 + WORKER_BASE_BYTES
    plan = Plan(what, STARTUP_SECONDS * (1 + (nworkers > 1)) + cpu / nworkers, nworkers * per_worker, nprimes,
                "prime").within_memory(memory_bytes)
    kernels = [layer_grid, layer_fill, pfaffian_lazy, monomials, gap_residues, pfaffian_mod]
    return with_compilation(plan, "Pfaffian layers", COMPILE_SECONDS["floor"], kernels)


# ------------------------------------------------------------------ route choice


def layer_route(N: int, i: int, memory_bytes: int | None = None) -> tuple[str, Plan]:
    """The faster exact route to layer ``i``'s pooled gap law, and its plan: ``"floor"``, ``"layers"`` or ``"ideals"``.

    The order-ideal DP (``N <= 30``, memory permitting) against de Bruijn
    Pfaffians: :func:`.floor.floor_pooled_gap_law` for the floor (``i = N``),
    :func:`layer_pooled_gap_law` above it (``N <= 128``).  The faster
    runnable plan wins (the laws are equal, tested).

    Parameters
    ----------
    N, i : int
        Number of layers ``2..128`` and the layer ``2..N``.
    memory_bytes : int, optional
        Memory available to the run.

    Returns
    -------
    (str, Plan)
        The route's name and its plan.

    Examples
    --------
    >>> layer_route(40, 40)[0], layer_route(40, 20)[0], layer_route(12, 12)[0]
    ('floor', 'layers', 'ideals')
    """
    N = check_layers(N, maximum=MAX_FLOOR_N)
    i = check_int(i, "i", 2, N)
    what = f"exact P(f) of layer {i} N={N}"
    ideals = gap_laws_plan(N, 1, memory_bytes, what=f"{what} (order ideals)")
    name = "floor" if i == N else "layers"
    pfaffians = floor_plan(N, False, memory_bytes) if i == N else layer_plan(N, i, False, memory_bytes)
    pfaffians = replace(pfaffians, what=f"{what} (de Bruijn Pfaffians)")
    if ideals.runnable and (not pfaffians.runnable or ideals.seconds <= pfaffians.seconds):
        return "ideals", ideals
    return name, pfaffians


def layer_gap_law(N: int, i: int, route: str, progress: Callable[..., Any] | None = None, *,
                  executor: Executor | None = None,
                  checkpoint: str | PathLike | CheckpointStore | None = None) -> GapCounts:
    """Layer ``i``'s pooled gap law by the route :func:`layer_route` chose.

    ``executor`` and ``checkpoint`` (as for :func:`layer_pooled_gap_law`)
    belong to the Pfaffian routes, the ones over primes; the DP refuses them.

    Examples
    --------
    >>> layer_gap_law(7, 7, "floor") == layer_gap_law(7, 7, "ideals")
    True
    >>> layer_gap_law(7, 4, "layers") == layer_gap_law(7, 4, "ideals")
    True
    """
    N = check_layers(N, maximum=MAX_FLOOR_N)
    i = check_int(i, "i", 2, N)
    if route == "ideals":
        if executor is not None or checkpoint is not None:
            raise ArgumentError("executor= and checkpoint= belong to the Pfaffian routes over primes, not to the DP")
        return pool_gaps(layer_gap_counts(N, i, progress))
    if route == "floor" and i == N:
        return floor_pooled_gap_law(N, progress=progress, executor=executor, checkpoint=checkpoint)
    if route == "layers" and i < N:
        return layer_pooled_gap_law(N, i, progress=progress, executor=executor, checkpoint=checkpoint)
    raise ArgumentError(f"route={route!r} is out of range for layer {i}: it must be 'ideals', 'floor' for the "
                        f"floor (layer {N}) or 'layers' for a layer above it")


def floor_contact_gap_law(N: int, layer: GapCounts | None = None, **options: Any) -> GapCounts:
    """Exact pooled rank-gap law of the ``2(N - 1)`` contact forces between layer ``N - 1`` and the floor.

    These contacts (``F5``, ``F6`` of the grains of layer ``N - 1``, (3.4))
    are the spacings between a floor partial sum ``v_j`` and its two
    neighbours ``u_(j-1) < v_j < u_j`` of layer ``N - 1``.  ``v_j`` is
    covered by those two cells only, so given the rest of the tableau its
    rank is uniform among the ``g - 1`` ranks strictly between theirs (``g``
    the rank gap of ``W_(N-1,j) = u_j - u_(j-1)``): the contact gap is uniform
    on ``1..g-1`` (continuously, ``F = q W`` with ``q`` uniform and
    independent).  Hence ``counts[g'] = 2 sum_(g > g') x_g/(g - 1)`` from
    layer ``N - 1``'s pooled law ``x``, exact integers (checked).  Equal to
    the DP's contact laws pooled (tested).

    Parameters
    ----------
    N : int
        Number of layers, ``3..128``.
    layer : GapCounts, optional
        Layer ``N - 1``'s pooled gap law, if already computed; else by :func:`layer_route`'s route.
    **options
        ``executor``, ``checkpoint``, ``progress`` for :func:`layer_gap_law` (the Pfaffian route).

    Returns
    -------
    GapCounts
        ``total = 2 (N - 1) count(N)``.

    Examples
    --------
    >>> law = floor_contact_gap_law(8)
    >>> from fractions import Fraction  # P(0) of f = F/<F>: d P(gap 1) <F>, <F> = 1/(2(N - 1))
    >>> Fraction(law.d * law.counts[1], law.total) / (2 * 7)
    Fraction(4143, 4199)
    """
    N = check_layers(N, maximum=MAX_FLOOR_N)
    if N < 3:
        raise ArgumentError(f"N={N} is out of range: the contacts above the floor need N >= 3 (N in 3..{MAX_FLOOR_N})")
    d = dimension(N)
    if layer is None:
        route, _plan = layer_route(N, N - 1)
        layer = layer_gap_law(N, N - 1, route, **options)
    if layer.d != d or layer.total != (N - 1) * count(N) or len(layer.counts) != d + 2:
        raise ArgumentError(f"layer is not layer N-1's pooled gap law for N={N} (d={d}, total (N-1) count(N))")
    counts = [0] * (d + 2)
    acc = 0
    for g in range(d + 1, 1, -1):
        q, r = divmod(layer.counts[g], g - 1)
        if r:
            raise ArithmeticError(f"layer N-1's gap count at g={g} is not divisible by g - 1: not a layer law")
        acc += q
        counts[g - 1] = 2 * acc
    return GapCounts(tuple(counts), 2 * layer.total, d)


def ensemble_route(N: int, memory_bytes: int | None = None) -> tuple[str, Plan]:
    """The faster exact route to the ensemble ``P(f)`` (every grain of layers ``2..N``): ``"pfaffians"`` or ``"ideals"``.

    The order-ideal DP (``N - 1`` passes, ``N <= 30``) against every layer's
    pooled law by de Bruijn Pfaffians (:func:`layer_pooled_gap_law` and the
    floor's, ``N <= 128``); the faster runnable plan wins.

    Examples
    --------
    >>> ensemble_route(12)[0], ensemble_route(40)[0]
    ('ideals', 'pfaffians')
    """
    N = check_layers(N, maximum=MAX_FLOOR_N)
    ideals = distribution_plan(N, "ensemble", memory_bytes)
    plans = [layer_plan(N, i, False, memory_bytes) for i in range(2, N)] + [floor_plan(N, False, memory_bytes)]
    pfaffians = combine(f"exact ensemble P(f) N={N} (de Bruijn Pfaffians, every layer's pooled law)", plans, "prime")
    pfaffians = replace(pfaffians, seconds=pfaffians.seconds - (len(plans) - 1) * STARTUP_SECONDS)  # one process
    if ideals.runnable and (not pfaffians.runnable or ideals.seconds <= pfaffians.seconds):
        return "ideals", ideals
    return "pfaffians", pfaffians


def ensemble_pieces(N: int, route: str, progress: Callable[..., Any] | None = None, *,
                    executor: Executor | None = None, checkpoint: str | PathLike | None = None) -> list[Piece]:
    """The exact ensemble ``P(f)``, ``f = i W_ij`` over every grain of layers ``2..N``, by :func:`ensemble_route`'s route.

    As :func:`forcenet.exact.triangle.distribution.triangle_force_density`
    (equal, tested), which is the ``"ideals"`` route; ``"pfaffians"`` takes
    every layer's pooled gap law from de Bruijn Pfaffians instead
    (``executor``, ``checkpoint``: a directory, one request per layer).

    Examples
    --------
    >>> ensemble_pieces(5, "pfaffians") == ensemble_pieces(5, "ideals")
    True
    """
    N = check_layers(N, maximum=MAX_FLOOR_N)
    if route == "ideals":
        if executor is not None or checkpoint is not None:
            raise ArgumentError("executor= and checkpoint= belong to the Pfaffian routes over primes, not to the DP")
        return triangle_force_density(N, progress=progress)
    if route != "pfaffians":
        raise ArgumentError(f"route={route!r} is out of range for the ensemble: it must be 'ideals' or 'pfaffians'")
    grains = N * (N + 1) // 2 - 1
    terms = []
    for i in range(2, N + 1):
        gaps = layer_gap_law(N, i, "floor" if i == N else "layers", progress, executor=executor, checkpoint=checkpoint)
        (piece,), _cdf = layer_pieces_from_gaps(gaps, i)
        terms.append((piece.hi, piece.poly * Fraction(i, grains)))
    return sum_pieces(terms, piece.poly.gens[0])
