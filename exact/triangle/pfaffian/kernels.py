"""Compiled kernels of the Pfaffian route: linear algebra modulo a prime ``p < 2^23`` (numba).

Residues are held as ``float64`` integers in ``[0, p)``.  A product of two
residues is below ``2^46``, so it and short sums of such products are exact
integers in double precision (below ``2^53``); :func:`_red` brings an exact
integer back to ``[0, p)`` with one floating multiply, a floor and at most one
correction (the quotient estimate is off by at most one).  Nothing here
rounds: every value is an exact integer, so the results are exact residues.

The hot loop is the pair elimination of :func:`point_values`.  Entries of
rows that are not yet pivot rows are *not* reduced: each elimination step
adds less than ``2 p^2`` to an entry, so ``p + 2 (n-1) p^2 < 2^53`` (the
engine's choice of primes, :func:`forcenet.exact.triangle.pfaffian.engine.prime_limit`)
keeps every entry exact for the whole elimination, and the update is two
multiply-adds on doubles (vectorised by LLVM).  A pivot row is reduced when
its pivot is taken.

Compiled on first use and cached on disk (``cache=True``); the pure-Python
twin :mod:`.kernels_python` has the same functions and is the reference of
the tests.

May import: nothing of the package.
"""

from __future__ import annotations

import numpy as np
from numba import int64, njit, uint64

__all__ = ["pfaffian_mod", "point_values", "edge_values", "dual_weights", "lagrange_matrix", "weighted_sum"]

_JIT = {"cache": True, "boundscheck": False, "nogil": True}


@njit(inline="always", **_JIT)
def _red(x, p, pinv):
    """The residue of the exact integer ``x`` (``|x| < 2^53``) in ``[0, p)``."""
    x = x - np.floor(x * pinv) * p
    if x < 0.0:
        x += p
    if x >= p:
        x -= p
    return x


@njit(**_JIT)
def _inv(a, p, pinv):
    """``1/a`` modulo ``p`` by the extended Euclidean algorithm (``a`` a nonzero residue; ~60 ns)."""
    t, new_t = int64(0), int64(1)
    r, new_r = int64(p), int64(a)
    while new_r != 0:
        q = r // new_r
        t, new_t = new_t, t - q * new_t
        r, new_r = new_r, r - q * new_r
    return float(t + int64(p) if t < 0 else t)


@njit(**_JIT)
def pfaffian_mod(A, p):
    """Pfaffian of the skew matrix ``A`` (residues, float64) modulo ``p``; ``A`` is overwritten."""
    pinv = 1.0 / p
    size = A.shape[0]
    if size % 2:
        return 0.0
    result = 1.0
    for k in range(0, size, 2):
        piv = -1
        for j in range(k + 1, size):
            if A[k, j] != 0.0:
                piv = j
                break
        if piv < 0:
            return 0.0
        if piv != k + 1:  # swap rows and columns k+1 <-> piv
            for j in range(size):
                A[k + 1, j], A[piv, j] = A[piv, j], A[k + 1, j]
            for i in range(size):
                A[i, k + 1], A[i, piv] = A[i, piv], A[i, k + 1]
            result = _red(-result, p, pinv)
        a = A[k, k + 1]
        result = _red(result * a, p, pinv)
        ainv = _inv(a, p, pinv)
        for i in range(k + 2, size):
            f1 = _red(A[i, k + 1] * ainv, p, pinv)
            f0 = _red(A[i, k] * ainv, p, pinv)
            for j in range(k + 2, size):
                A[i, j] = _red(A[i, j] + f0 * A[k + 1, j] - f1 * A[k, j], p, pinv)
    return result


@njit(fastmath={"contract"}, **_JIT)
def _axpy(M, i, c, g, lo, hi):
    """Row ``i`` of ``M`` plus ``g`` times row ``c``, columns ``lo..hi-1`` (unreduced; a vector loop)."""
    i, c = uint64(i), uint64(c)
    for j in range(lo, hi):
        M[i, j] += g * M[c, j]


@njit(**_JIT)
def _inverse(K, out, p, pinv):
    """``out = K^{-1}`` modulo ``p`` by Gauss-Jordan with row pivoting; False if ``K`` is singular mod p.

    Rows other than the pivot row are reduced lazily: each round adds less
    than ``p^2``, and everything is reduced after ``lazy`` rounds.
    """
    s = K.shape[0]
    M = np.zeros((s, 2 * s))
    for i in range(s):
        for j in range(s):
            M[i, j] = K[i, j]
        M[i, s + i] = 1.0
    lazy = max(1, int((2.0**53 - 2.0**24) / (p * p)) - 1)
    rounds = 0
    for c in range(s):
        r = -1
        for i in range(c, s):
            M[i, c] = _red(M[i, c], p, pinv)
            if r < 0 and M[i, c] != 0.0:
                r = i
        if r < 0:
            return False
        if r != c:
            for j in range(2 * s):
                M[c, j], M[r, j] = M[r, j], M[c, j]
        f = _inv(M[c, c], p, pinv)
        for j in range(c, 2 * s):
            M[c, j] = _red(_red(M[c, j], p, pinv) * f, p, pinv)
        for i in range(s):
            if i != c:
                g = _red(M[i, c], p, pinv)
                if g != 0.0:
                    _axpy(M, i, c, p - g, uint64(c), uint64(2 * s))
        rounds += 1
        if rounds >= lazy:
            for i in range(s):
                for j in range(c, 2 * s):
                    M[i, j] = _red(M[i, j], p, pinv)
            rounds = 0
    for i in range(s):
        for j in range(s):
            out[i, j] = _red(M[i, s + j], p, pinv)
    return True


@njit(fastmath={"contract"}, **_JIT)
def _matmul(A, B, rows, cols, p, pinv):
    """``(A @ B)[:rows, :cols]`` modulo ``p``, reducing after every 64 inner terms (64 p^2 < 2^53)."""
    inner = uint64(A.shape[1])
    rows, cols = uint64(rows), uint64(cols)
    out = np.zeros((rows, cols))
    for k0 in range(uint64(0), inner, uint64(64)):
        for i in range(rows):
            for k in range(k0, min(k0 + uint64(64), inner)):
                a = A[i, k]
                for j in range(cols):
                    out[i, j] += a * B[k, j]
        for i in range(rows):
            for j in range(cols):
                out[i, j] = _red(out[i, j], p, pinv)
    return out


@njit(inline="always", **_JIT)
def _pivot(A, i0, i1, width, p, pinv, c1, c2, size):
    """Reduce the pivot rows ``i0, i1`` (from the first block any row below reads) and fill the multipliers.

    ``c1[i] = A[i1, i] / a``, ``c2[i] = -A[i0, i] / a`` for ``i > i1``: the Schur complement of the pivot
    block ``[[0, a], [-a, 0]]`` is ``A_ij + c1[i] A[i0, j] + c2[i] A[i1, j]``.  Returns the pivot ``a``.
    """
    for j in range(i0 & ~uint64(7), width):
        A[i0, j] = _red(A[i0, j], p, pinv)
        A[i1, j] = _red(A[i1, j], p, pinv)
    a = A[i0, i1]
    if a != 0.0:
        ainv = _inv(a, p, pinv)
        for i in range(i1 + uint64(1), size):
            c1[i] = _red(A[i1, i] * ainv, p, pinv)
            c2[i] = _red((p - A[i0, i]) * ainv, p, pinv)
    return a


@njit(fastmath={"contract"}, **_JIT)
def _eliminate(A, n, p, pinv, c1, c2, d1, d2, out):
    """Leading pair-Pfaffians of the skew matrix ``A`` (upper triangle, ``2n``-square), lazily reduced.

    ``out[k] = Pf(A[:2k+2, :2k+2])``; False on a zero pivot (the caller moves
    the evaluation point).  Two pivots per sweep: the second pivot's rows get
    the first update, then every row below receives both (a rank-4 update),
    so the trailing matrix is read and written once per two pivots.

    ``A`` may be wider than ``2n`` (zero columns): rows are updated in whole
    blocks of 8 from a multiple of 8, so the vector loop has no remainder.
    The entries this touches below the diagonal (zero at the start) are never
    read for a result; they obey the same bound, since the pivot rows are
    reduced from the first block on.  Contracting ``a*b + c`` into one fused
    multiply-add is exact here (every result is an integer below ``2^53``).
    """
    size = uint64(2 * n)
    width = uint64(A.shape[1])
    one = uint64(1)
    two = uint64(2)
    block = ~uint64(7)
    pf = 1.0
    k = 0
    while k < n:
        i0 = uint64(2 * k)
        i1 = i0 + one
        a = _pivot(A, i0, i1, width, p, pinv, c1, c2, size)
        if a == 0.0:
            return False
        pf = _red(pf * a, p, pinv)
        out[k] = pf
        if k == n - 1:
            break
        j0 = i1 + one  # the next pivot rows: first update, then pivot
        j1 = j0 + one
        a1, a2, b1, b2 = c1[j0], c2[j0], c1[j1], c2[j1]
        for j in range(i0 & block, width):
            x0 = A[i0, j]
            x1 = A[i1, j]
            A[j0, j] = A[j0, j] + a1 * x0 + a2 * x1
            A[j1, j] = A[j1, j] + b1 * x0 + b2 * x1
        b = _pivot(A, j0, j1, width, p, pinv, d1, d2, size)
        if b == 0.0:
            return False
        pf = _red(pf * b, p, pinv)
        out[k + 1] = pf
        if k + 1 == n - 1:
            break
        i = j1 + one
        while i + one < size:  # two rows at a time, both pivots at once
            e1, e2, f1, f2 = c1[i], c2[i], d1[i], d2[i]
            g1, g2, h1, h2 = c1[i + one], c2[i + one], d1[i + one], d2[i + one]
            for j in range((i + one) & block, width):
                x0 = A[i0, j]
                x1 = A[i1, j]
                y0 = A[j0, j]
                y1 = A[j1, j]
                A[i, j] = A[i, j] + e1 * x0 + e2 * x1 + f1 * y0 + f2 * y1
                A[i + one, j] = A[i + one, j] + g1 * x0 + g2 * x1 + h1 * y0 + h2 * y1
            i += two
        if i < size:
            e1, e2, f1, f2 = c1[i], c2[i], d1[i], d2[i]
            for j in range((i + one) & block, width):
                A[i, j] = A[i, j] + e1 * A[i0, j] + e2 * A[i1, j] + f1 * A[j0, j] + f2 * A[j1, j]
        k += 2
    return True


@njit(**_JIT)
def _scaled_rows(A, Wt, scale):
    """Upper triangle of ``D_u W D_u`` into ``A`` (row ``i`` scaled by ``scale[i % 2]``), zeros below it in the first block."""
    size = uint64(Wt.shape[0])
    for i in range(size):
        for j in range(i & ~uint64(7), i + uint64(1)):
            A[i, j] = 0.0
        r = i % uint64(2)
        for j in range(i + uint64(1), size):
            A[i, j] = Wt[i, j] * scale[r, j]


@njit(**_JIT)
def _kernel_matrix(B, X1, expo, c, n, p, Wt):
    """The kernel ``W`` at ``q = c`` (upper triangle, copies interleaved) into ``Wt``; False if ``K(c)`` is singular.

    ``K(c) = B + Q X1 Q`` (``Q = diag(c^expo)``), ``W = -G0^{-1}`` restricted to the sites,
    ``G0^{-1} = [[B - B K^-1 B, -B K^-1], [K^-1 B, K^-1]]``; row ``2a`` is copy 0 of site ``a``
    (the part ``n - a``), row ``2a + 1`` copy 1.
    """
    pinv = 1.0 / p
    s = B.shape[0]
    qp = np.empty(s)
    for i in range(s):
        x = 1.0
        for _ in range(expo[i]):
            x = _red(x * c, p, pinv)
        qp[i] = x
    K = np.empty((s, s))
    for i in range(s):
        for j in range(s):
            K[i, j] = _red(B[i, j] + _red(qp[i] * X1[i, j], p, pinv) * qp[j], p, pinv)
    Ki = np.empty((s, s))
    if not _inverse(K, Ki, p, pinv):
        return False
    BKi = _matmul(B, Ki, n, s, p, pinv)
    BKiB = _matmul(BKi, B, n, n, p, pinv)
    for a in range(n):
        for b in range(a, n):
            if b > a:
                Wt[2 * a, 2 * b] = _red(BKiB[a, b] - B[a, b], p, pinv)
                Wt[2 * a + 1, 2 * b] = p - BKi[b, a]
                Wt[2 * a + 1, 2 * b + 1] = p - Ki[a, b]
            Wt[2 * a, 2 * b + 1] = BKi[a, b]
    return True


@njit(**_JIT)
def _window_pfaffians(A, Wt, u, with_j, n, p, bufs, out):
    """Leading pair-Pfaffians of ``D_u W D_u`` (``+ J`` if ``with_j``), ``D_u = diag(u, 1, u, 1, ...)``."""
    pinv = 1.0 / p
    size = 2 * n
    scale = np.empty((2, size))
    uu = _red(u * u, p, pinv)
    for j in range(0, size, 2):
        scale[0, j], scale[0, j + 1] = uu, u  # row of copy 0
        scale[1, j], scale[1, j + 1] = u, 1.0  # row of copy 1
    _scaled_rows(A, Wt, scale)  # entries below p^2, which the lazy bound allows
    if with_j:
        for a in range(n):
            A[2 * a, 2 * a + 1] += 1.0
    return _eliminate(A, n, p, pinv, bufs[0], bufs[1], bufs[2], bufs[3], out)


@njit(**_JIT)
def point_values(B, X1, expo, c, us, n, p, R):
    """``R[j, k] = E_c[y_j^{N_m(B)}]`` at the level fugacity ``q = c``, modulo ``p``, every ``y_j = 1 + u_j``.

    Builds the kernel ``W`` (:func:`_kernel_matrix`) and, for every ``u_j`` of
    ``us``, the leading pair-Pfaffians of ``J + D_u W D_u``: ``R[j, k]`` is the
    window of the ``k + 1`` largest parts (``m = n - k``).  Returns False when
    ``K(c)`` is singular or a pivot vanishes modulo ``p`` (the caller takes
    another ``c``).
    """
    size = 2 * n
    Wt = np.zeros((size, size))
    if not _kernel_matrix(B, X1, expo, c, n, p, Wt):
        return False
    A = np.zeros((size, (size + 7) // 8 * 8))  # padded to whole blocks of 8 (zeros stay zero)
    bufs = np.empty((4, size))
    out = np.empty(n)
    for jy in range(us.shape[0]):
        if not _window_pfaffians(A, Wt, us[jy], True, n, p, bufs, out):
            return False
        for k in range(n):
            R[jy, k] = out[k]
    return True


@njit(**_JIT)
def edge_values(B, X1, expo, c, n, p, R):
    """The two extreme coefficients in ``y`` of every window at ``q = c``, modulo ``p``.

    ``R[0, k] = P_c(every site of the window in B)``: the top coefficient of
    ``Pf(J + D_u W D_u)`` in ``u``, i.e. the Pfaffian of ``W`` itself (a
    correlation function of the point process); ``R[1, k] = P_c(no site of the
    window in B)``: the value at ``y = 0`` (``u = -1``).  Two eliminations per
    point instead of ``n + 1``.
    """
    size = 2 * n
    Wt = np.zeros((size, size))
    if not _kernel_matrix(B, X1, expo, c, n, p, Wt):
        return False
    A = np.zeros((size, (size + 7) // 8 * 8))
    bufs = np.empty((4, size))
    out = np.empty(n)
    if not _window_pfaffians(A, Wt, 1.0, False, n, p, bufs, out):
        return False
    for k in range(n):
        R[0, k] = out[k]
    if not _window_pfaffians(A, Wt, p - 1.0, True, n, p, bufs, out):
        return False
    for k in range(n):
        R[1, k] = out[k]
    return True


@njit(**_JIT)
def _quotient_at(P, x, p, pinv, q):
    """Synthetic division of the monic ``P`` (coefficients low to high) by ``(X - x)`` into ``q``."""
    deg = P.shape[0] - 1
    q[deg - 1] = 1.0
    for k in range(deg - 1, 0, -1):
        q[k - 1] = _red(P[k] + x * q[k], p, pinv)


@njit(**_JIT)
def _master(points, p, pinv):
    """Coefficients (low to high) of ``prod_i (X - points_i)`` modulo ``p``."""
    M = points.shape[0]
    P = np.zeros(M + 1)
    P[0] = 1.0
    for i in range(M):
        x = p - points[i]
        for k in range(i + 1, 0, -1):
            P[k] = _red(P[k - 1] + x * P[k], p, pinv)
        P[0] = _red(x * P[0], p, pinv)
    return P


@njit(**_JIT)
def dual_weights(points, g, p):
    """``lam`` with ``sum_i lam_i points_i^l = g_l`` for ``l < M`` (transposed Vandermonde, O(M^2)).

    ``lam_i = phi(L_i)`` for the Lagrange basis ``L_i`` and the functional ``phi(X^l) = g_l``.
    """
    pinv = 1.0 / p
    M = points.shape[0]
    P = _master(points, p, pinv)
    q = np.empty(M)
    lam = np.empty(M)
    for i in range(M):
        _quotient_at(P, points[i], p, pinv, q)
        num = 0.0
        den = 0.0
        for k in range(M - 1, -1, -1):
            num = _red(num + g[k] * q[k], p, pinv)
            den = _red(den * points[i] + q[k], p, pinv)
        lam[i] = _red(num * _inv(den, p, pinv), p, pinv)
    return lam


@njit(**_JIT)
def lagrange_matrix(points, p):
    """``L[k, j]``: coefficient of ``X^k`` in the Lagrange basis polynomial of ``points_j`` (the inverse Vandermonde)."""
    pinv = 1.0 / p
    M = points.shape[0]
    P = _master(points, p, pinv)
    q = np.empty(M)
    L = np.empty((M, M))
    for j in range(M):
        _quotient_at(P, points[j], p, pinv, q)
        den = 0.0
        for k in range(M - 1, -1, -1):
            den = _red(den * points[j] + q[k], p, pinv)
        f = _inv(den, p, pinv)
        for k in range(M):
            L[k, j] = _red(q[k] * f, p, pinv)
    return L


@njit(**_JIT)
def weighted_sum(w, R, p):
    """``sum_i w_i R[i]`` modulo ``p`` for a stack ``R`` of shape ``(m, a, b)`` (lazy, every 64 terms)."""
    pinv = 1.0 / p
    m, a, b = R.shape
    out = np.zeros((a, b))
    for i in range(m):
        wi = w[i]
        for x in range(a):
            for y in range(b):
                out[x, y] += wi * R[i, x, y]
        if i % 64 == 63:
            for x in range(a):
                for y in range(b):
                    out[x, y] = _red(out[x, y], p, pinv)
    for x in range(a):
        for y in range(b):
            out[x, y] = _red(out[x, y], p, pinv)
    return out
