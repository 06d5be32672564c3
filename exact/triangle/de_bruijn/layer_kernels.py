"""The compiled kernels of the layers' route (:mod:`.layers`): de Bruijn Pfaffians of a layer above the floor.

The derivation is in :mod:`.layers` and ``notes/fluctuations.md`` Sec. 6.
In the reflected variable ``a = 1 - x`` (the Vandermonde basis ``a^c``) the
kernel is homogeneous, ``K = sum_(alpha<=k) kappa_alpha a_x^alpha a_y^(2k-alpha)``,
so at a node ``(s, t, zeta)`` the de Bruijn matrix of layer ``i``
(``m = i - 1`` points, ``k = N - i`` layers below, order ``n + n % 2``,
``n = N - 1``) has the blocks

    A_cd = E_(c+d) (w_d - w_c) + M_cd - M_dc,   M = P V^T,   P_(c alpha) = kappa_alpha rho_(c+alpha),
           V_(d alpha) = v_(d+2k-alpha),   w_c = sum_alpha kappa_alpha/(c+2k-alpha+1),      c, d < m,
    B_(c r) = sum_gamma lam_(r gamma) S_(c+gamma),   B_(c k) = S_(c+k)/k   (n odd),
    C = the constants (r' - r)/((r+1)(r'+1)(r+r'+2)) and 1/(r+1)   (n odd),

from the moments of ``chi`` in ``X = 1 - x`` (thresholds ``S' = 1 - t < T' = 1 - s``, ``zeta`` marking
``X >= T'``): ``S_a = int X^a chi = sigma_a + zeta rho_a``, and
``int int_(Y<X) X^a Y^b chi chi = D_(a+b+2)/((b+1)(a+b+2)) + v_b rho_a``, with
``D_e = S'^e + zeta^2 (1 - T'^e)``, ``E_e = D_(e+2k+2)/(e+2k+2)``,
``sigma_a = S'^(a+1)/(a+1)``, ``rho_a = (1 - T'^(a+1))/(a+1)``,
``v_b = zeta sigma_b - zeta^2 T'^(b+1)/(b+1)``.  A node costs ``O(m^2 k)``
in one small matrix product (exact in ``float64``: at most ``2k + 2`` products
of residues per sum) and ``O(n^3)`` for its Pfaffian.

Residues are ``float64`` integers as in :mod:`forcenet.exact.triangle.residues`, ``p < 2^22``.
"""

from __future__ import annotations

import numpy as np

from forcenet.core.compiled import njit

from ..residues import JIT, inv_mod, pfaffian_mod, red
from .floor_kernels import add_node, grid_node, grid_outputs, pfaffian_lazy, scale_row

__all__ = ["layer_fill", "layer_grid"]


@njit(**JIT)
def layer_fill(A: np.ndarray, m: int, k: int, s: float, t: float, zeta: float, kap: np.ndarray, lam: np.ndarray,
               w: np.ndarray, iota: np.ndarray, p: float, pinv: float, full: bool) -> None:
    """The de Bruijn matrix of a layer at ``(s, t, zeta)`` (module docstring), reduced; upper triangle, or both
    halves if ``full``.

    ``kap``: ``(k+1,)`` the kernel's coefficients; ``lam``: ``(k, 2k+2)`` the
    constant rows' polynomials in ``a = 1 - x``; ``w``: ``(m,)``;
    ``iota[a] = 1/(a+1)`` for ``a < 2(m + k) + 2``.
    """
    top = m + 2 * k + 2  # moments for a < top
    size = m + k + (m + k) % 2
    lo = red(1.0 + p - t, p, pinv)  # S'
    hi = red(1.0 + p - s, p, pinv)  # T'
    lp = np.empty(2 * top + 1)
    hp = np.empty(2 * top + 1)
    lp[0] = 1.0
    hp[0] = 1.0
    for e in range(1, 2 * top + 1):
        lp[e] = red(lp[e - 1] * lo, p, pinv)
        hp[e] = red(hp[e - 1] * hi, p, pinv)
    z2 = red(zeta * zeta, p, pinv)
    rho = np.empty(top)
    v = np.empty(top)
    S = np.empty(top)
    for a in range(top):
        sig = red(lp[a + 1] * iota[a], p, pinv)
        rho[a] = red((1.0 + p - hp[a + 1]) * iota[a], p, pinv)
        v[a] = red(zeta * sig + (p - z2) * red(hp[a + 1] * iota[a], p, pinv), p, pinv)
        S[a] = red(sig + zeta * rho[a], p, pinv)
    E = np.empty(max(2 * m - 1, 1))
    for e in range(2 * m - 1):
        f = e + 2 * k + 2
        E[e] = red(red(lp[f] + z2 * (1.0 + p - hp[f]), p, pinv) * iota[f - 1], p, pinv)
    P = np.empty((m, k + 1))
    V = np.empty((m, k + 1))
    Hk = np.empty((m, 2 * k + 2))
    for c in range(m):
        for al in range(k + 1):
            P[c, al] = red(kap[al] * rho[c + al], p, pinv)
            V[c, al] = v[c + 2 * k - al]
        for g in range(2 * k + 2):
            Hk[c, g] = S[c + g]
    M = P @ V.T  # sums of k + 1 products < p^2: exact
    B = Hk @ lam.T
    for c in range(m):
        for d in range(c + 1, m):
            A[c, d] = red(E[c + d] * (w[d] + p - w[c]) + M[c, d] - M[d, c], p, pinv)
        for r in range(k):
            A[c, m + r] = red(B[c, r], p, pinv)
        if size > m + k:
            A[c, m + k] = red(S[c + k] * iota[k - 1], p, pinv)
    for r in range(k):  # the floor's constants among the constant rows, and the border's 1/(r+1)
        for q in range(r + 1, k):
            A[m + r, m + q] = red(red(float(q - r) * iota[r], p, pinv) * red(iota[q] * iota[r + q + 1], p, pinv),
                                  p, pinv)
        if size > m + k:
            A[m + r, m + k] = iota[r]
    if full:
        for a in range(size):
            A[a, a] = 0.0
            for b in range(a + 1, size):
                A[b, a] = red(p - A[a, b], p, pinv)


@njit(**JIT)
def _quadratic(A: np.ndarray, F0: np.ndarray, Q: np.ndarray, P: np.ndarray, zeta: float, size: int, p: float,
               pinv: float) -> None:
    """``A = F0 + zeta Q + zeta^2 P`` on the upper triangle: the matrix at ``zeta`` from its three parts."""
    z2 = red(zeta * zeta, p, pinv)
    for a in range(size):
        for b in range(a + 1, size):
            A[a, b] = red(F0[a, b] + red(zeta * Q[a, b], p, pinv) + z2 * P[a, b], p, pinv)


@njit(**JIT)
def layer_grid(m: int, k: int, d: int, p: float, zetas: np.ndarray, lam_u: np.ndarray, kap: np.ndarray, lam: np.ndarray,
               w: np.ndarray, iota: np.ndarray) -> tuple[np.ndarray, np.ndarray, int]:
    """Half the grid (the floor's, :func:`~.floor_kernels.grid`) for a layer, at every ``zeta`` of ``zetas``
    (the columns): ``(A, B, failures)``, ``(1 - w) sum_b lam_u[b] Pf(s, t, zeta)`` over the nodes
    ``u = b/d``, ``b <= d/2`` (``A``) and the same without the middle node (``B``), rows ``w = 0..d+2``.

    The matrix is quadratic in ``zeta`` entry by entry, so with more than
    three fugacities it is filled at ``zeta = 0, 1, -1`` only and combined
    (:func:`_quadratic`).  One lazy elimination per Pfaffian; a vanishing
    pivot falls back to the pivoting :func:`~.kernels.pfaffian_mod`.
    """
    pinv = 1.0 / p
    nz = zetas.shape[0]
    size = m + k + (m + k) % 2
    A = np.zeros((size, size))
    F0 = np.zeros((size, size))
    Q = np.zeros((size, size))
    P = np.zeros((size, size))
    half = (p + 1) / 2  # 1/2 modulo p
    parts = nz > 3
    outA, outB, vals = grid_outputs(d, nz)
    failures = 0
    dinv = inv_mod(float(d), p, pinv)
    for a in range(d + 3):
        one_w = red(1.0 + p - a, p, pinv)
        for b in range(d // 2 + 1):
            s, t = grid_node(a, b, one_w, dinv, p, pinv)
            if parts:
                layer_fill(F0, m, k, s, t, 0.0, kap, lam, w, iota, p, pinv, False)
                layer_fill(Q, m, k, s, t, 1.0, kap, lam, w, iota, p, pinv, False)
                layer_fill(P, m, k, s, t, p - 1.0, kap, lam, w, iota, p, pinv, False)
                for r in range(size):
                    for c in range(r + 1, size):
                        plus, minus = Q[r, c], P[r, c]
                        Q[r, c] = red((plus + p - minus) * half, p, pinv)
                        P[r, c] = red(red((plus + minus) * half, p, pinv) + p - F0[r, c], p, pinv)
            for z in range(nz):
                if parts:
                    _quadratic(A, F0, Q, P, zetas[z], size, p, pinv)
                else:
                    layer_fill(A, m, k, s, t, zetas[z], kap, lam, w, iota, p, pinv, False)
                value, good = pfaffian_lazy(A, size, p, pinv)
                if not good:
                    failures += 1
                    layer_fill(A, m, k, s, t, zetas[z], kap, lam, w, iota, p, pinv, True)
                    value = pfaffian_mod(A, p)
                vals[z] = value
            add_node(outA, outB, a, lam_u[b], vals, 2 * b != d, p, pinv)
        scale_row(outA, outB, a, one_w, p, pinv)
    return outA, outB, failures
