"""Compiled kernels of the free-fermion route: linear algebra modulo a prime ``p < 2^25`` (numba).

Residues are ``float64`` integers, reduced by the shared arithmetic of
:mod:`forcenet.exact.triangle.residues` (``red``, ``lred``, ``inv_mod``; the
skew-symmetric elimination ``skew_solve`` for the kernel ``K(c)``, half the
work of the general ``solve`` that the dense test baseline keeps).  Nothing here
rounds: every value is an exact integer, so the results are exact residues.

The hot loop is :func:`point_values`: for every ``y`` the leading
pair-Pfaffians of ``J + D_u W D_u`` by a **displacement-structure (GKO-type)
elimination** (``notes/free_fermions.md`` Sec. 4.1).  With node values ``+a``
on copy 0 and ``-a`` on copy 1 of the part ``a``, ``(x_i + x_j) A_ij`` has rank
two, so the matrix is carried by two generator columns and the pair entries
``A[2b, 2b+1]`` (where ``x_i + x_j = 0``); each pivot costs ``O(n)`` instead of
``O(n^2)``.  The elimination is fraction-free (no modular inverse until the
end: the serial inverse per pivot took 16 % of the elimination at N = 100,
the extra multiplications take most of that back; net 2-11 % at N = 100-60),
eight values of ``y`` go side by side, and the loop over the parts is a
vector loop.  The state of the eight lanes lives in one flat array at a
compile-time row stride (:data:`_STRIDE`), so the compiler proves that the
rows never overlap and the vector loop runs without run-time alias checks
(1.4x per elimination at N = 100 against one array per row,
``notes/benchmarks.md``).  Bounds: loose residues are below ``2p`` in size,
so every sum formed is below ``8 p^2 < 2^53``.

The dense pair elimination that this replaced is a private test and
benchmark baseline of the package, beside a pure-Python twin of these
functions (the reference of the tests).  A kernel module's interface
(what :mod:`.engine` calls) includes the shared ``pfaffian_mod``,
``dual_weights`` and ``weighted_sum`` of :mod:`forcenet.exact.triangle.residues`,
named here.  Compiled on first use and cached on disk (:mod:`forcenet.core.compiled`).
"""

from __future__ import annotations

import numpy as np
from numba import uint64

from forcenet.core.compiled import njit
from forcenet.core.errors import ArgumentError

from ..residues import (
    JIT,
    dual_block,
    dual_weights,
    inv_mod,
    lagrange_matrix,
    lred,
    master_factors,
    pfaffian_mod,
    red,
    skew_solve,
    weighted_rows,
    weighted_sum,
)

__all__ = ["pfaffian_mod", "point_values", "edge_values", "kernel_constants", "dual_weights", "lagrange_matrix", "weighted_sum", "LANES",
           "node_value", "master_factors", "dual_block", "weighted_rows"]

LANES = 8  # values of y eliminated side by side


@njit(inline="always", **JIT)
def node_value(i: int, n: int) -> int:
    """Node value of row ``i``: ``+a`` on copy 0 (even rows) and ``-a`` on copy 1 of the part ``a = n - i // 2``."""
    a = n - i // 2
    return a if i % 2 == 0 else -a


@njit(**JIT)
def _pivot_inverses(n: int, p: float) -> np.ndarray:
    """``T[k, 2 pc + rc, b] = 1/(x_row + x_pivot)`` modulo ``p``: pivot copy ``pc`` of site ``k``, row copy ``rc`` of site ``b > k``.

    With the node values ``x = +a`` (copy 0) and ``-a`` (copy 1) of the part
    ``a = n - site``, the sums are ``+-(n - b) +- (n - k)``, never zero for
    ``b != k``.  Zero for ``b <= k`` and in the padding ``b >= n`` (width ``n + 8``).
    """
    pinv = 1.0 / p
    size = 2 * n
    inv = np.zeros(2 * size + 1)  # 1/v for v = -2n..2n at index v + 2n
    for v in range(1, size + 1):
        iv = inv_mod(float(v), p, pinv)
        inv[size + v] = iv
        inv[size - v] = 0.0 if iv == 0.0 else p - iv
    T = np.zeros((n, 4, n + 8))
    for k in range(n):
        for pc in range(2):
            for rc in range(2):
                for b in range(k + 1, n):
                    T[k, 2 * pc + rc, b] = inv[size + node_value(2 * b + rc, n) + node_value(2 * k + pc, n)]
    return T


# Row stride of the lanes' state (:func:`_gko_windows`): a compile-time constant, so the
# compiler sees that the five rows of a lane never overlap (no run-time alias checks in
# the vector loop); not a power of two (no cache-set conflicts). Needs n + 8 <= _STRIDE.
_STRIDE = 216
_USTRIDE = uint64(_STRIDE)


@njit(**JIT)
def _check_width(n: int) -> None:
    """Refuse ``n`` parts that do not fit the lanes' rows (``n + 8 <= _STRIDE``: N <= 209, beyond the route's 200)."""
    if n + 8 > _STRIDE:
        raise ArgumentError("n is out of range: the kernels need n + 8 <= _STRIDE (216)")


@njit(inline="always", fastmath={"contract"}, **JIT)
def _row_update(a0: float, a1: float, t0: float, t1: float, h00: float, h01: float, h10: float, h11: float, q00: float,
                q01: float, q10: float, q11: float, c: float, p: float,
                pinv: float) -> tuple[float, float, float, float]:
    """One row with generators ``(a0, a1)``: ``E0, E1`` (its entries in the two pivot columns) and ``c F - E1 F_i0 + E0 F_i1``."""
    e0 = lred(lred(a0 * h00 + a1 * h01, p, pinv) * t0, p, pinv)
    e1 = lred(lred(a0 * h10 + a1 * h11, p, pinv) * t1, p, pinv)
    return e0, e1, lred(c * a0 - e1 * q00 + e0 * q10, p, pinv), lred(c * a1 - e1 * q01 + e0 * q11, p, pinv)


@njit(fastmath={"contract"}, **JIT)
def _gko_sites(Z: np.ndarray, o: int, Tk: np.ndarray, k: int, n: int, h00: float, h01: float, h10: float, h11: float,
               q00: float, q01: float, q10: float, q11: float, c: float, p: float, pinv: float) -> None:
    """One fraction-free pivot (site ``k``, pivot value ``c``) on the sites ``b > k`` of one lane: a vector loop over ``b``.

    ``Z[o + r S + b]`` (``S`` = :data:`_STRIDE`): rows ``r = 0, 1`` the
    generators of the copy-0 rows, ``2, 3`` of the copy-1 rows, ``4`` the pair
    entries ``A[2b, 2b+1]``.  For each row ``i``: ``E0 = A[i, i0]``,
    ``E1 = A[i, i1]`` from the generators (``h`` = the pivot generators turned
    by ``Omega``; ``Tk`` the inverse node sums), then
    ``F_i <- c F_i - E1 F_i0 + E0 F_i1`` (``q`` = the pivot generators) and
    ``A[2b, 2b+1] <- c (c A[2b, 2b+1] + E1(2b) E0(2b+1) - E0(2b) E1(2b+1))``:
    the Schur complement times ``c^2``, with no division
    (``notes/free_fermions.md`` Sec. 4.1).  Loose residues (size below
    ``2p``): every sum formed is below ``8 p^2``.  The loop runs over whole
    blocks of 8 from ``k + 1``; the padding (``Tk = 0`` there) stays bounded
    and is never read.
    """
    lo = uint64(k + 1)
    for b in range(lo, lo + ((uint64(n) - lo + uint64(7)) & ~uint64(7))):
        i0 = uint64(o) + b
        i1 = i0 + _USTRIDE
        i2 = i1 + _USTRIDE
        i3 = i2 + _USTRIDE
        i4 = i3 + _USTRIDE
        x0, x1, Z[i0], Z[i1] = _row_update(Z[i0], Z[i1], Tk[0, b], Tk[2, b], h00, h01, h10, h11, q00, q01, q10, q11, c,
                                           p, pinv)  # the copy-0 row of site b
        y0, y1, Z[i2], Z[i3] = _row_update(Z[i2], Z[i3], Tk[1, b], Tk[3, b], h00, h01, h10, h11, q00, q01, q10, q11, c,
                                           p, pinv)  # the copy-1 row
        Z[i4] = lred(c * lred(c * Z[i4] + lred(x1 * y0 - x0 * y1, p, pinv), p, pinv), p, pinv)


@njit(**JIT)
def _gko_windows(F: np.ndarray, Wd: np.ndarray, T: np.ndarray, us: np.ndarray, js: np.ndarray, n: int, p: float,
                 out: np.ndarray, Z: np.ndarray) -> bool:
    """Leading pair-Pfaffians of ``js J + D_u W D_u`` for every lane ``l`` (``u = us[l]``), by displacement.

    ``F``: the generators of ``W`` (:func:`_kernel_generators`); ``Wd[b] = W[2b, 2b+1]``,
    the entries the generators do not determine; ``T``: :func:`_pivot_inverses`.
    ``out[l, k] = Pf`` of the leading ``2k + 2`` block.  The Schur complement
    after a pivot is again of this form (Gohberg-Kailath-Olshevsky): the
    generators of the remaining rows get ``- A21 A11^{-1} F1`` and the pair
    entries their own rank-2 update (:func:`_gko_sites`).  The elimination is
    fraction-free: after pivot ``k`` the state is the Schur complement times
    ``sigma_(k+1)^2``, ``sigma_(k+1) = c'_k sigma_k``, so the pivot seen is
    ``c'_k = sigma_k^2 c_k``; the scales are divided out at the end, one
    modular inverse per lane.  ``Z``: the lanes' state, ``5 S`` values per lane
    (``S`` = :data:`_STRIDE`).  Returns False on a zero pivot.
    """
    pinv = 1.0 / p
    L = us.shape[0]
    S = _STRIDE
    for l in range(L):
        u = us[l]
        o = 5 * S * l
        for b in range(n, n + 8):  # the padding of the last block
            for r in range(5):
                Z[o + r * S + b] = 0.0
        for b in range(n):
            Z[o + b] = red(F[2 * b, 0] * u, p, pinv)  # D_u scales copy 0
            Z[o + S + b] = red(F[2 * b, 1] * u, p, pinv)
            Z[o + 2 * S + b] = F[2 * b + 1, 0]
            Z[o + 3 * S + b] = F[2 * b + 1, 1]
            Z[o + 4 * S + b] = red(js[l] + u * Wd[b], p, pinv)
    for k in range(n):
        for l in range(L):
            c = red(Z[5 * S * l + 4 * S + k], p, pinv)  # the pivot, scaled by sigma_k^2
            if c == 0.0:
                return False
            out[l, k] = c
        if k == n - 1:
            break
        Tk = T[k]
        for l in range(L):
            o = 5 * S * l
            q0 = red(Z[o + k], p, pinv)  # F_i0 = (q0, q1), F_i1 = (q2, q3)
            q1 = red(Z[o + S + k], p, pinv)
            q2 = red(Z[o + 2 * S + k], p, pinv)
            q3 = red(Z[o + 3 * S + k], p, pinv)
            # Omega F_i0 = (F_i0,1, -F_i0,0), the same for F_i1 (not divided by the pivot: fraction-free)
            _gko_sites(Z, o, Tk, k, n, q1, p - q0, q3, p - q2, q0, q1, q2, q3, out[l, k], p, pinv)
    # undo the scales: sigma_0 = 1, sigma_(k+1) = c'_k sigma_k, c_k = c'_k / sigma_k^2, Pf_k = prod_(j<=k) c_j
    sig = np.ones(L)
    den = np.ones(L)
    num = np.ones(L)
    sq = np.empty((L, n))
    for k in range(n):
        for l in range(L):
            s2 = red(sig[l] * sig[l], p, pinv)
            sq[l, k] = s2
            den[l] = red(den[l] * s2, p, pinv)
            num[l] = red(num[l] * out[l, k], p, pinv)
            sig[l] = red(sig[l] * out[l, k], p, pinv)
            out[l, k] = num[l]  # prod_(j<=k) c'_j; divided by prod_(j<=k) sigma_j^2 below
    for l in range(L):
        dinv = inv_mod(den[l], p, pinv)
        for k in range(n - 1, -1, -1):
            out[l, k] = red(out[l, k] * dinv, p, pinv)
            dinv = red(dinv * sq[l, k], p, pinv)
    return True


@njit(**JIT)
def _kernel_generators(B: np.ndarray, X1: np.ndarray, expo: np.ndarray, c: float, n: int, p: float, F: np.ndarray,
                       Wd: np.ndarray, C: np.ndarray) -> bool:
    """The kernel ``W`` at ``q = c`` as its two displacement generators ``F`` and pair entries ``Wd``, in ``O(n^3/2)``.

    ``notes/free_fermions.md`` Sec. 4.1: with ``D B + B D = u v^T - v u^T``
    (``u = beta a``, ``v = beta``), ``D X + X D = -(u' v'^T - v' u'^T)``
    (``u' = Q S alpha a``, ``v' = Q S alpha``) and ``K = B + X``,

        F_0 = [v - B K^-1 v ; K^-1 v],   F_1 = [u - B K^-1 (u + u') ; K^-1 (u + u')]

    on the parts (copy 0 ; copy 1), and ``W[2b, 2b+1] = (B K^-1)_bb`` with
    ``K^-1`` read off its own displacement ``K^-1 (D K + K D) K^-1`` (four
    solves with ``K``, no inverse, no matrix product).  ``alpha``, ``beta``
    are read off the columns of the zero label of ``B`` and ``X1``.  Returns
    False if ``K(c)`` is singular modulo ``p``.
    """
    pinv = 1.0 / p
    s = B.shape[0]
    z = n  # the (first) zero label
    sign_z = 1.0 if n % 2 == 0 else p - 1.0  # (-1)^z
    powers = np.empty(n + 1)  # c^a, a = 0..n: one chain of n products (not one per label: 10 % of a point at N = 152)
    powers[0] = 1.0
    for a in range(1, n + 1):
        powers[a] = red(powers[a - 1] * c, p, pinv)
    qp = np.empty(s)
    for i in range(s):
        qp[i] = powers[expo[i]]
    Rhs = np.zeros((s, 4))  # u, v, u', v'
    for i in range(s):
        a = float(expo[i])  # type: ignore[assignment]  # the name holds an int above (numba unifies)
        if i < n:
            v = B[i, z]  # beta_i beta_0 M_i0 = beta_i
            sa = red(X1[i, z] * (p - sign_z), p, pinv)  # (S alpha)_i = -(-1)^z X1[i, z]
        else:
            v = 1.0
            sa = sign_z if i == z else 0.0  # alpha_0 = 1, alpha_0' = 0
        Rhs[i, 0] = red(v * a, p, pinv)
        Rhs[i, 1] = v
        Rhs[i, 2] = red(red(sa * a, p, pinv) * qp[i], p, pinv)
        Rhs[i, 3] = red(sa * qp[i], p, pinv)
    K = np.zeros((s, s))  # skew-symmetric: its upper triangle is all skew_solve reads
    for i in range(s):
        for j in range(i + 1, s):
            K[i, j] = red(B[i, j] + red(qp[i] * X1[i, j], p, pinv) * qp[j], p, pinv)
    Y = skew_solve(K, Rhs, p, pinv)
    if Y is None:
        return False
    # f = u + u' side, g = v side: B K^-1 (u + u') and B K^-1 v, then the pair entries
    # (B K^-1)_bb = sum_j B_bj (K^-1)_jb with (K^-1)_jb (a_j + a_b) = (-y_u y_v^T + y_v y_u^T + y_u' y_v'^T - y_v' y_u'^T)_jb,
    # i.e. sum_j C_bj (...)_jb with C = kernel_constants: all as exact float64 dot products of residues with the
    # 13-bit halves of residues (each term below 2^38, a sum of s < 2^8 terms below 2^46), one reduction each
    yk = np.empty(s)
    for i in range(s):
        yk[i] = red(Y[i, 0] + Y[i, 2], p, pinv)
    Ys = np.empty((10, s))
    for j in range(s):
        _split(yk[j], Ys, 0, j)
        _split(Y[j, 1], Ys, 2, j)  # y_v
        _split(Y[j, 0], Ys, 4, j)  # y_u
        _split(Y[j, 2], Ys, 6, j)  # y_u'
        _split(Y[j, 3], Ys, 8, j)  # y_v'
    for a in range(n):
        bk = _join(_dot(B[a], Ys[0], s), _dot(B[a], Ys[1], s), p, pinv)
        bv = _join(_dot(B[a], Ys[2], s), _dot(B[a], Ys[3], s), p, pinv)
        F[2 * a, 0] = red(Rhs[a, 1] + p - bv, p, pinv)
        F[2 * a + 1, 0] = Y[a, 1]
        F[2 * a, 1] = red(Rhs[a, 0] + p - bk, p, pinv)
        F[2 * a + 1, 1] = yk[a]
    for b in range(n):
        sv = _join(_dot(C[b], Ys[2], s), _dot(C[b], Ys[3], s), p, pinv)
        s0 = _join(_dot(C[b], Ys[4], s), _dot(C[b], Ys[5], s), p, pinv)
        s2 = _join(_dot(C[b], Ys[6], s), _dot(C[b], Ys[7], s), p, pinv)
        s3 = _join(_dot(C[b], Ys[8], s), _dot(C[b], Ys[9], s), p, pinv)
        Wd[b] = red(Y[b, 0] * sv + (p - Y[b, 1]) * s0 + Y[b, 3] * s2 + (p - Y[b, 2]) * s3, p, pinv)
    return True


@njit(**JIT)
def kernel_constants(B: np.ndarray, expo: np.ndarray, n: int, p: float) -> np.ndarray:
    """``C[b, j] = B[b, j] / (a_j + a_b)`` modulo ``p`` (``0`` at ``j = b``), ``b`` a part: the same for every level point.

    The pair entries of the kernel are ``W[2b, 2b+1] = sum_j C[b, j] g_jb``
    with ``g`` the rank-four displacement of ``K^-1`` (:func:`_kernel_generators`);
    computed once per prime and passed to :func:`point_values` and
    :func:`edge_values` (``BC``).
    """
    pinv = 1.0 / p
    s = B.shape[0]
    inv = np.zeros(2 * n + 1)
    for v in range(1, 2 * n + 1):
        inv[v] = inv_mod(float(v), p, pinv)
    C = np.zeros((n, s))
    for b in range(n):
        for j in range(s):
            if j != b:
                C[b, j] = red(B[b, j] * inv[expo[j] + expo[b]], p, pinv)
    return C


@njit(inline="always", **JIT)
def _split(v: float, Ys: np.ndarray, row: int, j: int) -> None:
    """The residue ``v`` as ``8192 hi + lo`` into ``Ys[row, j]`` (``hi < 2^12``) and ``Ys[row + 1, j]`` (``lo < 2^13``)."""
    hi = np.floor(v * (1.0 / 8192.0))
    Ys[row, j] = hi
    Ys[row + 1, j] = v - hi * 8192.0


@njit(fastmath={"contract", "reassoc"}, **JIT)  # not inlined by numba: its own reassoc flag lets LLVM vectorize the sum
def _dot(x: np.ndarray, y: np.ndarray, s: int) -> float:
    """``sum x_j y_j``, ``j < s``, of exact integers whose sum stays below ``2^53`` (any order is exact)."""
    acc = 0.0
    for j in range(s):
        acc += x[j] * y[j]
    return acc


@njit(inline="always", **JIT)
def _join(hi: float, lo: float, p: float, pinv: float) -> float:
    """``(8192 hi + lo) mod p`` for the two exact sums of a split dot product."""
    return red(red(hi, p, pinv) * 8192.0 + lo, p, pinv)


@njit(**JIT)
def point_values(B: np.ndarray, X1: np.ndarray, expo: np.ndarray, c: float, us: np.ndarray, n: int, p: float,
                 R: np.ndarray, BC: np.ndarray | None = None) -> bool:
    """``R[j, k] = E_c[y_j^{N_m(B)}]`` at the level fugacity ``q = c``, modulo ``p``, every ``y_j = 1 + u_j``.

    Builds the kernel ``W`` as its two displacement generators
    (:func:`_kernel_generators`) and, for every ``u_j`` of ``us``
    (:data:`LANES` at a time), the leading pair-Pfaffians of
    ``J + D_u W D_u`` (:func:`_gko_windows`): ``R[j, k]`` is the window of
    the ``k + 1`` largest parts (``m = n - k``).  Returns False when ``K(c)``
    is singular or a pivot vanishes modulo ``p`` (the caller takes another ``c``).
    ``BC``: :func:`kernel_constants` ``(B, expo, n, p)``, the same for every
    point of a prime (computed here when not given).
    """
    _check_width(n)
    size = 2 * n
    F = np.empty((size, 2))
    Wd = np.empty(n)
    if BC is None:
        C = kernel_constants(B, expo, n, p)
    else:
        C = BC
    if not _kernel_generators(B, X1, expo, c, n, p, F, Wd, C):
        return False
    T = _pivot_inverses(n, p)
    L = LANES
    Z = np.empty(5 * _STRIDE * L)
    out = np.empty((L, n))
    js = np.ones(L)
    ny = us.shape[0]
    for j0 in range(0, ny, L):
        lanes = min(L, ny - j0)  # the last group may be narrower
        if not _gko_windows(F, Wd, T, us[j0 : j0 + lanes], js[:lanes], n, p, out, Z):
            return False
        for l in range(lanes):
            for k in range(n):
                R[j0 + l, k] = out[l, k]
    return True


@njit(**JIT)
def edge_values(B: np.ndarray, X1: np.ndarray, expo: np.ndarray, c: float, n: int, p: float, R: np.ndarray,
                BC: np.ndarray | None = None) -> bool:
    """The two extreme coefficients in ``y`` of every window at ``q = c``, modulo ``p``.

    ``R[0, k] = P_c(every site of the window in B)``: the top coefficient of
    ``Pf(J + D_u W D_u)`` in ``u``, i.e. the Pfaffian of ``W`` itself (a
    correlation function of the point process); ``R[1, k] = P_c(no site of the
    window in B)``: the value at ``y = 0`` (``u = -1``).  Two eliminations per
    point instead of ``n + 1``, both by displacement (two lanes).  ``BC`` as in
    :func:`point_values`.
    """
    _check_width(n)
    size = 2 * n
    F = np.empty((size, 2))
    Wd = np.empty(n)
    if BC is None:
        C = kernel_constants(B, expo, n, p)
    else:
        C = BC
    if not _kernel_generators(B, X1, expo, c, n, p, F, Wd, C):
        return False
    T = _pivot_inverses(n, p)
    us = np.array([1.0, p - 1.0])
    js = np.array([0.0, 1.0])  # W alone; J + D_u W D_u at u = -1
    Z = np.empty(5 * _STRIDE * 2)
    out = np.empty((2, n))
    if not _gko_windows(F, Wd, T, us, js, n, p, out, Z):
        return False
    for r in range(2):
        for k in range(n):
            R[r, k] = out[r, k]
    return True
