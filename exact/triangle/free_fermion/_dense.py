"""Private: the dense baseline of the free-fermion route, kernel matrices and pair eliminations in ``O(n^3)`` per ``y``.

A test oracle and benchmark baseline, not part of the library's interface:
no function of the package imports it; the tests and benchmarks put it in
place of the compiled kernels with ``engine._oracle_kernels``.

Before the displacement elimination of :mod:`.kernels`, every ``(q, y)`` cost
one dense pair elimination of the ``2n``-square matrix ``J + D_u W D_u``
(``notes/free_fermions.md`` Sec. 4).  It is kept, unchanged, as

* the baseline the benchmarks measure the displacement route against
  (``benchmarks/pfaffian_table.py``), and
* a second route in the tests: :func:`point_values_dense` must equal
  :func:`.kernels.point_values` for every ``y``, and :func:`_kernel_matrix`
  (inverse and products) must give the generators and pair entries that
  :func:`.kernels._kernel_generators` computes from four solves.

Entries of rows that are not yet pivot rows are *not* reduced: each
elimination step adds less than ``2 p^2`` to an entry, so
``p + 2 (n-1) p^2 < 2^53`` (:func:`forcenet.exact.triangle.free_fermion.cost.dense_prime_limit`)
keeps every entry exact for the whole elimination, and the update is two
multiply-adds on doubles (vectorised by LLVM).  A pivot row is reduced when
its pivot is taken.

It also carries the whole kernel interface of :mod:`.kernels` with
``point_values`` = :func:`point_values_dense`.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numba import uint64

from forcenet.core.compiled import njit

from ..residues import JIT, inv_mod, red, solve
from .kernels import dual_weights, edge_values, lagrange_matrix, node_value, pfaffian_mod, weighted_sum

__all__ = ["point_values_dense", "displacement_generators", "pfaffian_mod", "point_values", "edge_values", "dual_weights",
           "lagrange_matrix", "weighted_sum"]


@njit(fastmath={"contract"}, **JIT)
def _matmul(A: Any, B: np.ndarray, rows: Any, cols: Any, p: float, pinv: float) -> np.ndarray:
    """``(A @ B)[:rows, :cols]`` modulo ``p``, reducing after every ``chunk`` inner terms (``p + chunk p^2 < 2^53``)."""
    inner = uint64(A.shape[1])
    rows, cols = uint64(rows), uint64(cols)
    chunk = uint64(max(1, min(64, int((2.0**53 - p) / (p * p)))))
    out = np.zeros((rows, cols))
    for k0 in range(uint64(0), inner, chunk):
        for i in range(rows):
            for k in range(k0, min(k0 + chunk, inner)):
                a = A[i, k]
                for j in range(cols):
                    out[i, j] += a * B[k, j]
        for i in range(rows):
            for j in range(cols):
                out[i, j] = red(out[i, j], p, pinv)
    return out


@njit(inline="always", **JIT)
def _pivot(A: np.ndarray, i0: Any, i1: Any, width: Any, p: float, pinv: float, c1: np.ndarray, c2: np.ndarray,
           size: Any) -> float:
    """Reduce the pivot rows ``i0, i1`` (from the first block any row below reads) and fill the multipliers.

    ``c1[i] = A[i1, i] / a``, ``c2[i] = -A[i0, i] / a`` for ``i > i1``: the Schur complement of the pivot
    block ``[[0, a], [-a, 0]]`` is ``A_ij + c1[i] A[i0, j] + c2[i] A[i1, j]``.  Returns the pivot ``a``.
    """
    for j in range(i0 & ~uint64(7), width):
        A[i0, j] = red(A[i0, j], p, pinv)
        A[i1, j] = red(A[i1, j], p, pinv)
    a = A[i0, i1]
    if a != 0.0:
        ainv = inv_mod(a, p, pinv)
        for i in range(i1 + uint64(1), size):
            c1[i] = red(A[i1, i] * ainv, p, pinv)
            c2[i] = red((p - A[i0, i]) * ainv, p, pinv)
    return a


@njit(fastmath={"contract"}, **JIT)
def _eliminate(A: Any, n: int, p: float, pinv: float, c1: np.ndarray, c2: np.ndarray, d1: np.ndarray,
               d2: np.ndarray, out: np.ndarray) -> bool:
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
        pf = red(pf * a, p, pinv)
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
        pf = red(pf * b, p, pinv)
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


@njit(**JIT)
def _scaled_rows(A: np.ndarray, Wt: Any, scale: np.ndarray) -> None:
    """Upper triangle of ``D_u W D_u`` into ``A`` (row ``i`` scaled by ``scale[i % 2]``), zeros below it in the first block."""
    size = uint64(Wt.shape[0])
    for i in range(size):
        for j in range(i & ~uint64(7), i + uint64(1)):
            A[i, j] = 0.0
        r = i % uint64(2)
        for j in range(i + uint64(1), size):
            A[i, j] = Wt[i, j] * scale[r, j]


@njit(**JIT)
def _kernel_matrix(B: np.ndarray, X1: np.ndarray, expo: np.ndarray, c: float, n: int, p: float, Wt: np.ndarray) -> bool:
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
            x = red(x * c, p, pinv)
        qp[i] = x
    K = np.empty((s, s))
    for i in range(s):
        for j in range(s):
            K[i, j] = red(B[i, j] + red(qp[i] * X1[i, j], p, pinv) * qp[j], p, pinv)
    Ki = solve(K, np.eye(s), p, pinv)  # the inverse: elimination on the identity
    if Ki is None:
        return False
    BKi = _matmul(B, Ki, n, s, p, pinv)
    BKiB = _matmul(BKi, B, n, n, p, pinv)
    for a in range(n):
        for b in range(a, n):
            if b > a:
                Wt[2 * a, 2 * b] = red(BKiB[a, b] - B[a, b], p, pinv)
                Wt[2 * a + 1, 2 * b] = p - BKi[b, a]
                Wt[2 * a + 1, 2 * b + 1] = p - Ki[a, b]
            Wt[2 * a, 2 * b + 1] = BKi[a, b]
    return True


@njit(**JIT)
def _window_pfaffians(A: np.ndarray, Wt: np.ndarray, u: float, with_j: bool, n: int, p: float, bufs: np.ndarray,
                      out: np.ndarray) -> bool:
    """Leading pair-Pfaffians of ``D_u W D_u`` (``+ J`` if ``with_j``), ``D_u = diag(u, 1, u, 1, ...)``."""
    pinv = 1.0 / p
    size = 2 * n
    scale = np.empty((2, size))
    uu = red(u * u, p, pinv)
    for j in range(0, size, 2):
        scale[0, j], scale[0, j + 1] = uu, u  # row of copy 0
        scale[1, j], scale[1, j + 1] = u, 1.0  # row of copy 1
    _scaled_rows(A, Wt, scale)  # entries below p^2, which the lazy bound allows
    if with_j:
        for a in range(n):
            A[2 * a, 2 * a + 1] += 1.0
    return _eliminate(A, n, p, pinv, bufs[0], bufs[1], bufs[2], bufs[3], out)


@njit(**JIT)
def point_values_dense(B: np.ndarray, X1: np.ndarray, expo: np.ndarray, c: float, us: np.ndarray, n: int, p: float,
                       R: np.ndarray, BC: np.ndarray | None = None) -> bool:
    """:func:`point_values` by the dense pair elimination (the baseline; needs ``p + 2 (n-1) p^2 < 2^53``).

    Builds the kernel ``W`` (:func:`_kernel_matrix`) and, for every ``u_j`` of
    ``us``, the leading pair-Pfaffians of ``J + D_u W D_u``: ``R[j, k]`` is the
    window of the ``k + 1`` largest parts (``m = n - k``).  Returns False when
    ``K(c)`` is singular or a pivot vanishes modulo ``p`` (the caller takes
    another ``c``).  ``BC`` is accepted for the interface and not used.
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


@njit(**JIT)
def displacement_generators(Wt: np.ndarray, n: int, p: float, F: np.ndarray) -> bool:
    """Two generators of the kernel ``W``: ``(x_i + x_j) W_ij = F_i0 F_j1 - F_i1 F_j0`` for all ``i < j``.

    ``Wt`` is the upper triangle of ``W`` (:func:`_kernel_matrix`), ``x`` the
    node values (:func:`node_value`).  The left side is the displacement
    ``D W + W D`` (``D = diag(x)``); it is found to have rank two (the rank-2
    term is read off its first nonzero entry and the whole matrix is then
    checked, so nothing rests on the rank being two).  Returns False if the
    check fails (rank above two: the caller moves the point).
    """
    pinv = 1.0 / p
    size = 2 * n
    bi, bj = -1, -1
    g = 0.0
    for i in range(size):
        for j in range(i + 1, size):
            s = node_value(i, n) + node_value(j, n)
            if s != 0:
                g = red((s + p if s < 0 else s) * Wt[i, j], p, pinv)
                if g != 0.0:
                    bi, bj = i, j
                    break
        if bi >= 0:
            break
    if bi < 0:  # the displacement vanishes
        for i in range(size):
            F[i, 0] = 0.0
            F[i, 1] = 0.0
        return True
    ginv = inv_mod(g, p, pinv)
    for i in range(size):  # F_0 = column bi / g, F_1 = column bj (of the skew displacement)
        for col in range(2):
            j = bi if col == 0 else bj
            s = node_value(i, n) + node_value(j, n)
            if i == j or s == 0:
                v = 0.0
            elif i < j:
                v = red((s + p if s < 0 else s) * Wt[i, j], p, pinv)
            else:
                v = red(p - red((s + p if s < 0 else s) * Wt[j, i], p, pinv), p, pinv)
            F[i, col] = red(v * ginv, p, pinv) if col == 0 else v
    for i in range(size):  # the check: the displacement minus the rank-2 term is zero
        for j in range(i + 1, size):
            s = node_value(i, n) + node_value(j, n)
            lhs = 0.0 if s == 0 else red((s + p if s < 0 else s) * Wt[i, j], p, pinv)
            rhs = red(F[i, 0] * F[j, 1] + (p - F[i, 1]) * F[j, 0], p, pinv)
            if lhs != rhs:
                return False
    return True


# The kernel interface of :mod:`.kernels` with the dense elimination in place of the displacement one
# (the engine with these kernels in place of the compiled ones): every other kernel is shared.
point_values = point_values_dense
