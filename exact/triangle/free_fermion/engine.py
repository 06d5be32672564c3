"""One prime of the Pfaffian route: the survival table ``S[m][k]`` modulo ``p``.

``S[m][k] = sum_A w(A) [N_m(A) = k]`` (``N_m(A)`` the number of parts ``>= m``
of the ideal ``A``) is, by minor summation and the point-process kernel
(:mod:`.schur`, ``notes/free_fermions.md`` Sec. 3),

    S_B[m][k] = sum_l l! (d-l)! [q^l y^k] Z(q) E_q[y^{N_m(B)}],     Z(q) = count/d! (1 + q)^d,

with ``B`` the complement, ``N_m(A) = (n - m + 1) - N_m(B)``.  Modulo ``p``:

1. ``q`` runs over ``M`` points (``M`` = the even one of ``d+1``, ``d+2``), in
   pairs ``c, 1/c``; only ``c`` is computed, since the complement ``A <-> B``
   gives ``R(1/q, y, m) = y^(n-m+1) R(q, 1/y, m)``;
2. ``y`` runs over ``1`` and pairs ``c, 1/c`` (at least ``n + 1`` points);
3. for each ``c``, :func:`~.kernels.point_values` gives ``R(c, y, m)`` for
   every ``y`` and ``m`` (one kernel and one pair elimination per ``y``);
   a singular ``K(c)`` or a zero pivot moves ``c`` to the next candidate, so
   a prime never fails;
4. the functional ``q^l -> l! (d-l)!`` is a weight vector on the points
   (transposed Vandermonde), and the ``y`` coefficients come from the
   inverse Vandermonde; coefficients beyond the degree ``n - m + 1`` must
   vanish (a check).

Cost: ``M/2`` kernels (``O(n^3)`` each) and ``(M/2) * n`` eliminations by
displacement (``O(n^2)`` each, :func:`~.kernels.point_values`): ``O(n^5)``
word operations per prime.

Residues travel to the kernels as ``float64`` arrays of exact integers in
``[0, p)`` (their representation, :mod:`.kernels`; nothing is rounded) and
come back as ``int64``.
"""

from __future__ import annotations

import threading
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from types import ModuleType

import numpy as np

from forcenet.core.errors import ArgumentError
from forcenet.core.plan import Plan, with_compilation
from forcenet.core.validation import check_int, check_layers

from ...modular import is_prime
from ..staircase import dimension
from .cost import level_points, prime_limit
from .schur import labels

__all__ = ["setup_matrices", "prime_residues", "edge_residues", "count_residue", "PointFailureError",
           "with_kernels_compiled", "kernel_module", "constants", "pair_points", "check_prime"]

MAX_POINT_FAILURES = 64
# compiling the kernels on a first run (empty numba cache), CPU seconds: benchmarks/compile_times.py
COMPILE_SECONDS = {"table": 19.4, "lattice": 18.8}


class PointFailureError(ArithmeticError):
    """Too many evaluation points failed modulo one prime (never seen; a structural zero would show here)."""


def setup_matrices(n: int, p: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``B`` (``q = 0``), ``X1`` and the exponents with ``K(q) = B + Q X1 Q``, ``Q = diag(q^expo)``, mod ``p``.

    ``B_ij = beta_i beta_j M_ij``, ``X1_ij = -(-1)^(i+j) alpha_i alpha_j M_ij`` with
    ``alpha_a = beta_a = 1/a!`` (``alpha_0' = 0``): :func:`.schur.minor_summation_matrix`
    at ``q = 1`` split in its two parts.
    """
    values = labels(n)
    s = len(values)
    invfact = [1] * (n + 1)
    f = 1
    for a in range(1, n + 1):
        f = f * a % p
        invfact[a] = pow(f, p - 2, p)
    inv = [0] + [pow(k, p - 2, p) for k in range(1, 2 * n + 1)]  # 1/(a + b), a + b <= 2n
    beta = np.array([invfact[a] for a in values], dtype=np.int64)
    alpha = beta.copy()
    if n % 2 == 0:
        alpha[n + 1] = 0  # the second zero 0'
    parts = np.array(values, dtype=np.int64)
    M = (parts[:, None] - parts[None, :]) % p * np.array(inv, dtype=np.int64)[parts[:, None] + parts[None, :]] % p
    if n % 2 == 0:
        M[n, n + 1], M[n + 1, n] = 1, p - 1  # Schur's entry between the two zeros
    B = beta[:, None] * beta[None, :] % p * M % p
    idx = np.arange(s)
    sign = np.where((idx[:, None] + idx[None, :]) % 2 == 0, p - 1, 1)  # -(-1)^(i+j)
    X1 = alpha[:, None] * alpha[None, :] % p * M % p * sign % p
    return B.astype(np.float64), X1.astype(np.float64), parts


def constants(K: ModuleType, B: np.ndarray, expo: np.ndarray, n: int, p: int) -> np.ndarray | None:
    """The per-prime constants of the kernel module ``K`` (:func:`~.kernels.kernel_constants`), or None if it has none.

    Examples
    --------
    >>> B, X1, expo = setup_matrices(4, 101)
    >>> from types import SimpleNamespace
    >>> constants(kernel_module(), B, expo, 4, 101).shape, constants(SimpleNamespace(), B, expo, 4, 101)
    ((4, 6), None)
    """
    make = getattr(K, "kernel_constants", None)
    return None if make is None else make(B, expo, n, float(p))


_ORACLES: list[ModuleType] = []  # kernel modules standing in for the compiled kernels in this process (tests)


def kernel_module() -> ModuleType:
    """The kernel module of the per-prime functions: :mod:`.kernels`, or a test's stand-in (:func:`_oracle_kernels`)."""
    if _ORACLES:
        return _ORACLES[-1]
    from . import kernels

    return kernels


@contextmanager
def _oracle_kernels(module: ModuleType) -> Iterator[None]:
    """Within the block, this process's per-prime functions call ``module`` (a test oracle with the kernels'
    interface) in place of the compiled kernels; tasks sent to other processes do not see it."""
    _ORACLES.append(module)
    try:
        yield
    finally:
        _ORACLES.pop()


def count_residue(N: int, p: int) -> int:
    """``count(N) mod p = d! Pf(B) mod p`` (the normalization (4.1) at ``q = 0``)."""
    n, d = N - 1, dimension(N)
    if n == 0:
        return 1
    B, _, _ = setup_matrices(n, p)
    pf = int(kernel_module().pfaffian_mod(B.copy(), float(p)))
    fact = 1
    for k in range(2, d + 1):
        fact = fact * k % p
    return fact * pf % p


def with_kernels_compiled(plan: Plan, lattice: bool = False, in_workers: bool = False) -> Plan:
    """``plan`` plus compiling the compiled kernels of :func:`prime_residues` (``lattice``: of
    :func:`edge_residues`) when numba's cache lacks them (a first run, :data:`COMPILE_SECONDS`);
    ``in_workers``: for the CPU features of forcenet's worker processes.

    Examples
    --------
    >>> plan = with_kernels_compiled(Plan("x", 3.0))
    >>> plan.seconds - plan.compile_seconds
    3.0
    """
    from . import kernels

    entries = [kernels.pfaffian_mod, kernels.master_factors, kernels.dual_block, kernels.weighted_rows,
               kernels.edge_values if lattice else kernels.point_values]
    if not lattice:
        entries.append(kernels.lagrange_matrix)
    name = "lattice" if lattice else "table"
    return with_compilation(plan, f"Pfaffian {name}", COMPILE_SECONDS[name], entries, in_workers=in_workers)


def pair_points(p: int, taken: set[int]) -> Iterator[tuple[int, int]]:
    """Pairs ``(c, 1/c)`` modulo ``p``, ``c = 2, 3, ...``, with ``c != 1/c`` and neither already taken (both are then taken).

    Examples
    --------
    >>> stream = pair_points(11, {1})
    >>> next(stream), next(stream)
    ((2, 6), (3, 4))
    """
    c = 2
    while True:
        if c >= p - 1:
            raise PointFailureError(f"ran out of evaluation points modulo {p}")
        ci = pow(c, p - 2, p)
        if ci != c and c not in taken and ci not in taken:
            taken.update((c, ci))
            yield c, ci
        c += 1


def check_prime(N: int, p: int) -> int:
    """``p`` if it is a prime the route may use for ``N`` layers (above ``2 N + 2`` and ``d + 1``, below :func:`prime_limit`).

    Raises
    ------
    ArgumentError
        If ``p`` is not such a prime.

    Examples
    --------
    >>> check_prime(4, 8388593)
    8388593
    """
    n, d = N - 1, dimension(N)
    limit = prime_limit(max(n, 1))
    low = max(2 * N + 3, d + 2)  # p > d: d! and count are units mod p (count divides d!), B is invertible
    p = check_int(p, "p", low, limit - 1)
    if not is_prime(p):
        raise ArgumentError(f"p={p} is out of range: p must be a prime in {low}..{limit - 1}")
    return p


_WORK = threading.local()


def _work_array(shape: tuple[int, ...]) -> np.ndarray:
    """A float64 array of ``shape`` on a buffer of this thread, reused from prime to prime.

    The level values of one prime take ``M/2 (n + 1) n`` doubles (0.2 GB at
    N = 100); a fresh allocation per prime costs its page faults every time
    (7 % of a prime at N = 100), a reused one only once per worker.
    """
    size = int(np.prod(shape))
    buffer = getattr(_WORK, "buffer", None)
    if buffer is None or buffer.size < size:
        buffer = _WORK.buffer = np.empty(size)
    return buffer[:size].reshape(shape)


def _level_sums(N: int, p: int, K: ModuleType, values: Callable[[float, np.ndarray], bool], shape: tuple[int, ...],
                shifts: tuple[int, ...] = (0,)) -> list[tuple[np.ndarray, np.ndarray]]:
    """Evaluate ``values(c, R)`` at the ``M/2`` representatives; the weighted sums over them and over their partners.

    ``values`` fills ``R`` (shape ``shape``) at ``q = c`` and returns False on a
    zero pivot or a singular ``K(c)``, which moves ``c`` to the next candidate.
    Returns ``[(T1, T2)]``, one pair per ``shift`` ``h``: ``sum_c lam(c) Z(c) R(c)``
    and ``sum_c lam(1/c) Z(1/c) R(c)``, where ``lam`` are the weights of the
    functional ``q^l -> (l + h)! (d - l)!`` (``h = 0``: the level sums; ``h = 1``:
    the level sums weighted by ``l + 1``, the second moments of the entries,
    ``notes/fluctuations.md`` Sec. 1) on the ``M`` points ``c, 1/c`` (the caller
    turns ``R(c)`` into ``R(1/c)`` by the complement symmetry).
    """
    d = dimension(N)
    M = level_points(d)
    taken: set = set()
    reps: list[int] = []
    partners: list[int] = []
    failures = 0
    stream = pair_points(p, taken)
    R = _work_array((M // 2,) + tuple(shape))  # filled in place, one slice per representative
    R[...] = 1.0
    while len(reps) < M // 2:
        c, ci = next(stream)
        slot = R[len(reps)]
        if not values(float(c), slot):
            failures += 1
            if failures > MAX_POINT_FAILURES:
                raise PointFailureError(f"{failures} evaluation points failed modulo {p}")
            slot[...] = 1.0
            continue
        reps.append(c)
        partners.append(ci)
    points = np.array(reps + partners, dtype=np.float64)
    fact = [1] * (d + 2)
    for k in range(1, d + 2):
        fact[k] = fact[k - 1] * k % p
    B, _, _ = setup_matrices(N - 1, p)
    z0 = int(K.pfaffian_mod(B.copy(), float(p)))  # Z(q) = Z(0) (1 + q)^d
    z = [z0 * pow(1 + int(points[i]), d, p) % p for i in range(M)]
    half = M // 2
    sums = []
    for h in shifts:
        g = np.zeros(M)
        g[: d + 1] = [fact[l + h] * fact[d - l] % p for l in range(d + 1)]
        lam = K.dual_weights(points, g, float(p))
        weight = np.array([int(lam[i]) * z[i] % p for i in range(M)], dtype=np.float64)
        sums.append((K.weighted_sum(weight[:half], R, float(p)), K.weighted_sum(weight[half:], R, float(p))))
    return sums


def prime_residues(N: int, p: int, total_mod_p: int | None = None, second: bool = False) -> np.ndarray:
    """``S[m][k] mod p`` (``m = 1..n`` rows, ``k = 0..n`` columns; row 0 unused) for ``N`` layers.

    With ``second``, also ``S2[m][k] = sum_A (|A| + 1) w(A) [N_m(A) = k]``, the
    same sums weighted by the level plus one (the second moments of the
    tableau entries, ``notes/fluctuations.md`` Sec. 1): the same evaluations,
    a second level functional.

    Parameters
    ----------
    N : int
        Number of layers, ``N >= 2``.
    p : int
        A prime below :func:`prime_limit` ``(N - 1)``, above ``2 N + 2`` and ``d + 1``.
    total_mod_p : int, optional
        ``count(N) mod p``; when given, every row is checked to sum to
        ``(d + 1) count`` modulo ``p`` (``S2``: ``(d + 1)(d + 2)/2 count``).
    second : bool
        Return ``[S, S2]`` (shape ``(2, n + 1, n + 1)``) instead of ``S``.

    Returns
    -------
    numpy.ndarray of int64, shape ``(n + 1, n + 1)`` (``(2, n + 1, n + 1)`` with ``second``)

    Examples
    --------
    >>> S = prime_residues(4, 8388593)
    >>> S[1].tolist(), S[3].tolist()  # sum_A w(A) [N_m(A) = k]; each row sums to (d+1) count = 14
    ([2, 5, 5, 2], [7, 7, 0, 0])
    >>> prime_residues(4, 8388593, second=True)[1][3].tolist()  # each row sums to (d+1)(d+2)/2 count = 56
    [16, 40, 0, 0]
    """
    N = check_layers(N)
    n, d = N - 1, dimension(N)
    p = check_prime(N, p)
    K = kernel_module()
    shifts = (0, 1) if second else (0,)
    if n == 0:
        S = np.zeros((len(shifts), 1, 1), dtype=np.int64)
        return S if second else S[0]
    B, X1, expo = setup_matrices(n, p)
    # y points: 1 and pairs (c, 1/c), at least n + 1 of them
    y_stream = pair_points(p, {1})
    ys = [1] + [v for _ in range((n + 1) // 2) for v in next(y_stream)]
    ny = len(ys)
    inv_index = [0] + [k + 1 + (1 if k % 2 == 0 else -1) for k in range(ny - 1)]
    us = np.array([(y - 1) % p for y in ys[1:]], dtype=np.float64)
    # R[j, k] = E_c[y_j^{N_m(B)}], m = n - k (row 0: y = 1, all ones)
    BC = constants(K, B, expo, n, p)
    sums = _level_sums(N, p, K, lambda c, R: K.point_values(B, X1, expo, c, us, n, float(p), R[1:], BC), (ny, n), shifts)
    L = K.lagrange_matrix(np.array(ys, dtype=np.float64), float(p)).astype(np.int64)
    out = np.zeros((len(shifts), n + 1, n + 1), dtype=np.int64)
    for h, (T1, T2) in zip(shifts, sums):
        T = np.zeros((ny, n), dtype=np.int64)
        for j in range(ny):
            for k in range(n):
                w = k + 1  # window size n - m + 1; partners: R(1/c, y) = y^w R(c, 1/y)
                T[j, k] = (int(T1[j, k]) + pow(ys[j], w, p) * int(T2[inv_index[j], k])) % p
        coeff = _matmul_mod(L, T, p)  # coeff[t, k]: coefficient of y^t of the window k
        S = out[h]
        for k in range(n):
            w = k + 1
            if coeff[w + 1 :, k].any():
                raise ArithmeticError(f"nonzero coefficient beyond the degree modulo {p}: inconsistent residues")
            m = n - k
            for t in range(w + 1):
                S[m, w - t] = coeff[t, k]  # N_m(A) = w - N_m(B)
        if total_mod_p is not None:
            target = (d + 1) * (d + 2 if h else 1) * pow(2 if h else 1, -1, p) * total_mod_p % p
            if any(int(S[m].sum()) % p != target for m in range(1, n + 1)):
                raise ArithmeticError(f"rows do not sum to their total modulo {p}")
    return out if second else out[0]


def edge_residues(N: int, p: int) -> np.ndarray:
    """``S[m][0] mod p`` for ``m = 1..n`` (entry 0 unused): the lattice-direction column alone.

    ``S[m][0] = sum_A w(A) [N_m(A) = 0]`` is the top coefficient in ``y`` of
    ``Z(q) E_q[y^{N_m(B)}]`` for the representatives and, through the
    complement symmetry, the value at ``y = 0`` for their partners: two
    eliminations per level point (:func:`~.kernels.edge_values`) instead of
    ``n + 1``.  The last column ``S[m][n - m + 1]`` comes from the same values
    with the roles swapped; the mirror symmetry of the triangle says the two
    are equal, which is checked.

    Examples
    --------
    >>> edge_residues(4, 8388593).tolist()  # S[m][0]: compare prime_residues(4, p)[:, 0]
    [0, 2, 4, 7]
    """
    N = check_layers(N)
    n = N - 1
    p = check_prime(N, p)
    K = kernel_module()
    out = np.zeros(n + 1, dtype=np.int64)
    if n == 0:
        return out
    B, X1, expo = setup_matrices(n, p)
    BC = constants(K, B, expo, n, p)
    [(T1, T2)] = _level_sums(N, p, K, lambda c, R: K.edge_values(B, X1, expo, c, n, float(p), R, BC), (2, n))
    first = (T1[0].astype(np.int64) + T2[1].astype(np.int64)) % p  # all of the window in B
    last = (T1[1].astype(np.int64) + T2[0].astype(np.int64)) % p  # none of the window in B
    if (first != last).any():
        raise ArithmeticError(f"the two lattice directions differ modulo {p}: inconsistent residues")
    out[n - np.arange(n)] = first  # index k is the window of the k + 1 largest parts, m = n - k
    return out


def _matmul_mod(A: np.ndarray, B: np.ndarray, p: int) -> np.ndarray:
    """``A @ B mod p`` for int64 residues below ``2^25`` (sums of 2^12 products stay below 2^63)."""
    out = np.zeros((A.shape[0], B.shape[1]), dtype=np.int64)
    for start in range(0, A.shape[1], 1 << 12):
        out = (out + A[:, start : start + (1 << 12)] @ B[start : start + (1 << 12)]) % p
    return out
