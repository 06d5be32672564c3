"""Private: the kernels of :mod:`.kernels` in pure Python integers, the tests' reference of the compiled path.

A test oracle, not part of the library's interface: no function of the
package imports it; the tests put it in place of the compiled kernels with
``engine._oracle_kernels``.

Same functions, same arguments (residues may be given as floats or ints),
same results; written for clarity (textbook pair elimination, full
reduction after every operation), so the tests can check the compiled,
lazily reduced kernels against it on small ``N``.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

__all__ = ["pfaffian_mod", "point_values", "edge_values", "dual_weights", "lagrange_matrix", "weighted_sum"]


def _ints(A: Any) -> list[list[int]]:
    return [[int(x) for x in row] for row in np.asarray(A)]


def _pair_pfaffians(A: list[list[int]], p: int, pivoting: bool) -> list[int] | None:
    """Leading pair-Pfaffians ``Pf(A[:2k, :2k])``, ``k = 1..size/2`` (None where a pivot vanishes)."""
    A = [row[:] for row in A]
    size = len(A)
    out: list[int] = []
    result = 1
    for k in range(0, size, 2):
        if A[k][k + 1] % p == 0 and pivoting:
            piv = next((j for j in range(k + 2, size) if A[k][j] % p), None)
            if piv is None:
                return out + [0] * ((size - k) // 2)
            A[k + 1], A[piv] = A[piv], A[k + 1]
            for row in A:
                row[k + 1], row[piv] = row[piv], row[k + 1]
            result = -result
        a = A[k][k + 1] % p
        if a == 0:
            return None
        result = result * a % p
        out.append(result)
        ainv = pow(a, p - 2, p)
        for i in range(k + 2, size):
            f0, f1 = A[i][k] * ainv % p, A[i][k + 1] * ainv % p
            for j in range(k + 2, size):
                A[i][j] = (A[i][j] + f0 * A[k + 1][j] - f1 * A[k][j]) % p
    return out


def pfaffian_mod(A: Any, p: Any) -> int:
    """Pfaffian of the skew matrix ``A`` modulo ``p``."""
    p = int(p)
    if len(A) % 2:
        return 0
    values = _pair_pfaffians(_ints(A), p, pivoting=True)
    return values[-1] if values else 1


def _inverse(K: list[list[int]], p: int) -> list[list[int]] | None:
    s = len(K)
    M = [row[:] + [int(i == j) for j in range(s)] for i, row in enumerate(K)]
    for c in range(s):
        r = next((r for r in range(c, s) if M[r][c] % p), None)
        if r is None:
            return None
        M[c], M[r] = M[r], M[c]
        f = pow(M[c][c], p - 2, p)
        M[c] = [x * f % p for x in M[c]]
        for i in range(s):
            if i != c and M[i][c] % p:
                g = M[i][c]
                M[i] = [(x - g * y) % p for x, y in zip(M[i], M[c])]
    return [row[s:] for row in M]


def _kernel_matrix(B: Any, X1: Any, expo: Any, c: int, n: int,
                   p: int) -> Callable[[int, bool], list[list[int]]] | None:
    """The kernel ``W`` at ``q = c`` as a function ``(u, with_j) -> J + D_u W D_u`` (None if ``K(c)`` is singular)."""
    B, X1 = _ints(B), _ints(X1)
    s = len(B)
    qp = [pow(c, int(e), p) for e in expo]
    K = [[(B[i][j] + qp[i] * X1[i][j] * qp[j]) % p for j in range(s)] for i in range(s)]
    Ki = _inverse(K, p)
    if Ki is None:
        return None
    BKi = [[sum(B[i][k] * Ki[k][j] for k in range(s)) % p for j in range(s)] for i in range(s)]
    BKiB = [[sum(BKi[i][k] * B[k][j] for k in range(s)) % p for j in range(s)] for i in range(s)]

    def matrix(u: int, with_j: bool) -> list[list[int]]:
        size = 2 * n
        A = [[0] * size for _ in range(size)]
        for a in range(n):
            for b in range(n):
                # W = -G0^{-1}, G0^{-1} = [[B - B K^-1 B, -B K^-1], [K^-1 B, K^-1]], scaled by D_u
                A[2 * a][2 * b] = (BKiB[a][b] - B[a][b]) * u * u % p
                A[2 * a][2 * b + 1] = BKi[a][b] * u % p
                A[2 * a + 1][2 * b] = -BKi[b][a] * u % p
                A[2 * a + 1][2 * b + 1] = -Ki[a][b] % p
            if with_j:
                A[2 * a][2 * a + 1] = (A[2 * a][2 * a + 1] + 1) % p
                A[2 * a + 1][2 * a] = (A[2 * a + 1][2 * a] - 1) % p
        return A

    return matrix


def point_values(B: Any, X1: Any, expo: Any, c: Any, us: Any, n: Any, p: Any, R: np.ndarray, BC: Any = None) -> bool:
    """Pure-Python twin of :func:`.kernels.point_values` (fills ``R``, returns False on a zero pivot; ``BC`` unused)."""
    p, c, n = int(p), int(c), int(n)
    matrix = _kernel_matrix(B, X1, expo, c, n, p)
    if matrix is None:
        return False
    for jy, u in enumerate(int(x) for x in us):
        values = _pair_pfaffians(matrix(u, True), p, pivoting=False)
        if values is None:
            return False
        R[jy, :] = values
    return True


def edge_values(B: Any, X1: Any, expo: Any, c: Any, n: Any, p: Any, R: np.ndarray, BC: Any = None) -> bool:
    """Pure-Python twin of :func:`.kernels.edge_values`: ``R[0]`` Pfaffians of ``W``, ``R[1]`` at ``y = 0`` (``BC`` unused)."""
    p, c, n = int(p), int(c), int(n)
    matrix = _kernel_matrix(B, X1, expo, c, n, p)
    if matrix is None:
        return False
    for row, (u, with_j) in enumerate(((1, False), (p - 1, True))):
        values = _pair_pfaffians(matrix(u, with_j), p, pivoting=False)
        if values is None:
            return False
        R[row, :] = values
    return True


def _quotients(points: list[int], p: int) -> list[list[int]]:
    """For each point ``x_i``: the coefficients of ``prod_{j != i} (X - x_j)`` (low to high)."""
    out = []
    for i, _ in enumerate(points):
        poly = [1]
        for j, x in enumerate(points):
            if j != i:
                poly = [((poly[k - 1] if k else 0) - x * (poly[k] if k < len(poly) else 0)) % p for k in range(len(poly) + 1)]
        out.append(poly)
    return out


def dual_weights(points: Any, g: Any, p: Any) -> np.ndarray:
    """``lam`` with ``sum_i lam_i points_i^l = g_l`` for ``l < M`` (solved through the Lagrange basis)."""
    p = int(p)
    points = [int(x) for x in points]
    lam = []
    for x, poly in zip(points, _quotients(points, p)):
        den = sum(cf * pow(x, k, p) for k, cf in enumerate(poly)) % p
        lam.append(sum(int(gk) * cf for gk, cf in zip(g, poly)) * pow(den, p - 2, p) % p)
    return np.array(lam, dtype=np.float64)


def lagrange_matrix(points: Any, p: Any) -> np.ndarray:
    """``L[k, j]``: coefficient of ``X^k`` in the Lagrange basis polynomial of ``points_j``."""
    p = int(p)
    points = [int(x) for x in points]
    M = len(points)
    L = np.zeros((M, M))
    for j, (x, poly) in enumerate(zip(points, _quotients(points, p))):
        den = pow(sum(cf * pow(x, k, p) for k, cf in enumerate(poly)) % p, p - 2, p)
        for k, cf in enumerate(poly):
            L[k, j] = cf * den % p
    return L


def weighted_sum(w: Any, R: Any, p: Any) -> np.ndarray:
    """``sum_i w_i R[i]`` modulo ``p``."""
    p = int(p)
    R = np.asarray(R).astype(np.int64)
    out = np.zeros(R.shape[1:], dtype=object)
    for wi, Ri in zip(w, R):
        out = (out + int(wi) * Ri.astype(object)) % p
    return out.astype(np.float64)
