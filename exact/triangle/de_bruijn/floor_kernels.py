"""The compiled kernels of the floor's route (:mod:`.floor`): de Bruijn Pfaffians on the grid, modulo ``p < 2^22``.

The derivation and the route are in :mod:`.floor` and ``notes/fluctuations.md``
Sec. 5.1.  Residues are ``float64`` integers as in :mod:`forcenet.exact.triangle.residues`.  The
grids evaluate their Pfaffians by the displacement kernel of
:mod:`.floor_displacement` (the default), or by the lazy elimination of the
explicit matrices here (:func:`pfaffian_lazy` has the bound; the baseline of
the benchmarks and a second route in the tests).
"""

from __future__ import annotations

import numpy as np

from forcenet.core.compiled import njit

from ..residues import JIT, inv_mod, lred, pfaffian_mod, red
from .floor_displacement import STREAMS, STRIDE, bordered_pfaffians

__all__ = ["pfaffian_lazy", "eliminate", "fill", "grid", "fill_pair", "pfaffian_pair", "grid_pairs",
           "monomials", "gap_residues", "GRID_LANES", "grid_node", "grid_outputs", "add_node", "scale_row"]

GRID_LANES = 16  # nodes of a row side by side in the displacement kernel (the pooled grid)


@njit(**JIT)
def pfaffian_lazy(A: np.ndarray, size: int, p: float, pinv: float) -> tuple[float, bool]:
    """Pfaffian of the skew matrix whose upper triangle is ``A``, modulo ``p < 2^22``, ``size <= 128``.

    The entries may start unreduced, ``0 <= A < 3 p^2`` (:func:`fill`).  No
    pivoting: ``(value, False)`` if a pivot ``A[k, k+1]`` vanishes (the caller
    falls back to :func:`~.kernels.pfaffian_mod`).  Only ``j > i`` is kept and
    updated; an entry is reduced only when its row becomes a pivot row, and
    the multipliers only to ``(-p, 2p)`` (:func:`~.residues.lred`), so it
    changes by less than ``4 p^2`` per step over at most ``size/2 <= 64``
    steps: ``|A| < 3 p^2 + 256 p^2 < 2^52.1``, exact.
    """
    return eliminate(A, size, size, p, pinv)


@njit(**JIT)
def eliminate(A: np.ndarray, size: int, top: int, p: float, pinv: float) -> tuple[float, bool]:
    """:func:`pfaffian_lazy`'s steps over the leading ``size`` rows of an order-``top`` upper triangle:
    ``(product of the pivots, ok)``; the trailing block is left as its Schur complement."""
    result = 1.0
    for k in range(0, size, 2):
        for j in range(k + 1, top):
            A[k, j] = red(A[k, j], p, pinv)
        for j in range(k + 2, top):
            A[k + 1, j] = red(A[k + 1, j], p, pinv)
        a = A[k, k + 1]
        if a == 0.0:
            return 0.0, False
        result = red(result * a, p, pinv)
        ainv = inv_mod(a, p, pinv)
        for i in range(k + 2, top):
            f0 = lred((p - A[k, i]) * ainv, p, pinv)  # A[i, k] / a
            g1 = lred(A[k + 1, i] * ainv, p, pinv)  # -A[i, k+1] / a
            for j in range(i + 1, top):
                A[i, j] += f0 * A[k + 1, j] + g1 * A[k, j]
    return result, True


@njit(inline="always", **JIT)
def _diagonals(n: int, s: float, t: float, y: float, sp: np.ndarray, tp: np.ndarray, p: float,
               pinv: float) -> np.ndarray:
    """The powers ``s^e``, ``t^e`` (into ``sp``, ``tp``) and ``D_e = y s^e + 1 - t^e``, ``e = 2..2n``."""
    sp[0] = 1.0
    tp[0] = 1.0
    for e in range(1, 2 * n + 1):
        sp[e] = red(sp[e - 1] * s, p, pinv)
        tp[e] = red(tp[e - 1] * t, p, pinv)
    D = np.empty(2 * n + 1)
    for e in range(2, 2 * n + 1):
        D[e] = red(y * sp[e] + 1.0 + p - tp[e], p, pinv)
    return D


@njit(**JIT)
def fill(A: np.ndarray, n: int, size: int, s: float, t: float, zeta: float, C: np.ndarray, iota: np.ndarray,
         sp: np.ndarray, tp: np.ndarray, p: float, pinv: float, full: bool) -> None:
    """The de Bruijn matrix at ``(s, t, zeta)`` (module docstring): the upper triangle unreduced (``< 3 p^2``), or
    both halves reduced if ``full``."""
    D = _diagonals(n, s, t, red(zeta * zeta, p, pinv), sp, tp, p, pinv)
    rho = np.empty(n)
    mu = np.empty(n)
    nmu = np.empty(n)
    for k in range(n):
        rho[k] = red((1.0 + p - tp[k + 1]) * iota[k], p, pinv)
        mu[k] = red((red(zeta * sp[k + 1], p, pinv) + p - 1.0) * iota[k], p, pinv)
        nmu[k] = p - mu[k]
    for k in range(n):
        for m in range(k + 1, n):
            A[k, m] = C[k, m] * D[k + m + 2] + mu[k] * rho[m] + nmu[m] * rho[k]
        if size > n:
            A[k, n] = red(mu[k] + iota[k] + rho[k], p, pinv)  # zeta s^(k+1)/(k+1) + rho_k
    if full:
        for k in range(size):
            A[k, k] = 0.0
            for m in range(k + 1, size):
                A[k, m] = red(A[k, m], p, pinv)
                A[m, k] = red(p - A[k, m], p, pinv)


@njit(inline="always", **JIT)
def add_node(outA: np.ndarray, outB: np.ndarray, a: int, weight: float, vals: np.ndarray, mirrored: bool, p: float,
             pinv: float) -> None:
    """Row ``a`` of both sums plus ``weight`` times the node's values (``B`` only for a node with a mirror)."""
    for c in range(vals.shape[0]):
        term = red(weight * vals[c], p, pinv)
        outA[a, c] = red(outA[a, c] + term, p, pinv)
        if mirrored:
            outB[a, c] = red(outB[a, c] + term, p, pinv)


@njit(inline="always", **JIT)
def grid_outputs(d: int, nz: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The two half-grid sums (rows ``w = 0..d+2``) and one node's values."""
    return np.zeros((d + 3, nz)), np.zeros((d + 3, nz)), np.empty(nz)


@njit(inline="always", **JIT)
def grid_node(a: int, b: int, one_w: float, dinv: float, p: float, pinv: float) -> tuple[float, float]:
    """The node ``(u = b/d, w = a)``: ``s = (1 - w) u``, ``t = s + w``."""
    s = red(one_w * red(b * dinv, p, pinv), p, pinv)
    return s, red(s + a, p, pinv)


@njit(inline="always", **JIT)
def scale_row(outA: np.ndarray, outB: np.ndarray, a: int, factor: float, p: float, pinv: float) -> None:
    for c in range(outA.shape[1]):
        outA[a, c] = red(outA[a, c] * factor, p, pinv)
        outB[a, c] = red(outB[a, c] * factor, p, pinv)


@njit(inline="always", **JIT)
def _lane_state(lanes: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The displacement kernel's state and per-lane arrays for ``lanes`` lanes: ``Z, ss, ts, pf, S, ok``."""
    return (np.zeros(STREAMS * STRIDE * lanes), np.empty(lanes), np.empty(lanes), np.empty(lanes), np.empty(lanes),
            np.empty(lanes, dtype=np.bool_))


@njit(**JIT)
def grid(n: int, d: int, p: float, lam: np.ndarray, C: np.ndarray, iota: np.ndarray, invx: np.ndarray,
         displacement: bool) -> tuple[np.ndarray, np.ndarray, int]:
    """Half the grid at ``zeta = 1``, by the mirror ``v -> 1 - v``: ``(1 - w) sum_b lam_b Pf(s, t)`` over the
    nodes ``u = b/d``, ``b <= d/2`` (``A``), and the same without the middle node (``B``), for ``w = 0..d+2``, mod
    ``p``; ``s = (1 - w) u``, ``t = s + w``.

    The node ``d - b`` is the mirror of ``b`` (``s, t -> 1 - t, 1 - s``) with
    the weight ``lam_b`` and the same Pfaffian at ``zeta = 1``, so the whole
    sum is ``A + B``.  ``displacement``: the nodes of a row go
    :data:`GRID_LANES` at a time through
    :func:`~.floor_displacement.bordered_pfaffians` (``Pf X(1) = Pf Y (1 - S)``);
    otherwise one lazy elimination of the de Bruijn matrix per node (the
    baseline).  ``invx``: :func:`~.floor_displacement.inverse_table`.
    """
    pinv = 1.0 / p
    size = n + (n % 2)
    A = np.zeros((size, size))
    sp = np.empty(2 * n + 1)
    tp = np.empty(2 * n + 1)
    outA, outB, vals = grid_outputs(d, 1)
    failures = 0
    dinv = inv_mod(float(d), p, pinv)
    half = d // 2 + 1
    Z, ss, ts, pf, S, ok = _lane_state(GRID_LANES)
    ys = np.ones(GRID_LANES)
    for a in range(d + 3):
        one_w = red(1.0 + p - a, p, pinv)
        for b0 in range(0, half, GRID_LANES):
            lanes = min(GRID_LANES, half - b0)
            for l in range(lanes):
                ss[l], ts[l] = grid_node(a, b0 + l, one_w, dinv, p, pinv)
            if displacement:
                bordered_pfaffians(n, ss[:lanes], ts[:lanes], ys[:lanes], invx, p, Z, pf, S, ok)
            for l in range(lanes):
                if displacement and ok[l]:
                    value = red(pf[l] * red(1.0 + p - S[l], p, pinv), p, pinv)
                else:
                    good = False
                    if not displacement:
                        fill(A, n, size, ss[l], ts[l], 1.0, C, iota, sp, tp, p, pinv, False)
                        value, good = pfaffian_lazy(A, size, p, pinv)
                    if not good:  # a vanishing pivot: pivoting
                        failures += 1
                        fill(A, n, size, ss[l], ts[l], 1.0, C, iota, sp, tp, p, pinv, True)
                        value = pfaffian_mod(A, p)
                vals[0] = value
                add_node(outA, outB, a, lam[b0 + l], vals, 2 * (b0 + l) != d, p, pinv)
        scale_row(outA, outB, a, one_w, p, pinv)
    return outA, outB, failures


@njit(**JIT)
def fill_pair(A: np.ndarray, n: int, s: float, t: float, y: float, C: np.ndarray, iota: np.ndarray, sp: np.ndarray,
              tp: np.ndarray, p: float, pinv: float) -> None:
    """The bordered matrix ``M = [[Y, sigma, rho], [., 0, 0]]`` at ``y = zeta^2`` (upper triangle, ``< 3 p^2``).

    The de Bruijn matrix is ``X(zeta) = Y(zeta^2) + zeta (sigma rho^T - rho sigma^T)``
    (``Y`` of order ``n + n % 2``, bordered by ``rho`` and ``1`` when ``n`` is odd),
    and a rank-two skew term enters a Pfaffian affinely:
    ``Pf X(+-zeta) = Pf Y -+ zeta Pf M = Pf Y (1 -+ zeta S)``, ``S`` the last
    entry left after eliminating ``Y`` (:func:`pfaffian_pair`; the sign is
    the Schur complement's, checked against :func:`fill` in the tests).
    """
    D = _diagonals(n, s, t, y, sp, tp, p, pinv)
    rho = np.empty(n)
    sig = np.empty(n)
    niota = np.empty(n)
    for k in range(n):
        rho[k] = red((1.0 + p - tp[k + 1]) * iota[k], p, pinv)
        sig[k] = red(sp[k + 1] * iota[k], p, pinv)
        niota[k] = p - iota[k]
    size = n + n % 2
    for k in range(n):
        for m in range(k + 1, n):
            A[k, m] = C[k, m] * D[k + m + 2] + niota[k] * rho[m] + iota[m] * rho[k]
        if size > n:
            A[k, n] = rho[k]
        A[k, size] = sig[k]
        A[k, size + 1] = rho[k]
    if size > n:
        A[n, size] = 0.0
        A[n, size + 1] = 1.0
    A[size, size + 1] = 0.0


@njit(**JIT)
def pfaffian_pair(A: np.ndarray, size: int, p: float, pinv: float) -> tuple[float, float, bool]:
    """``(Pf Y, S, ok)`` for ``M`` of :func:`fill_pair` (``Y`` of order ``size``): :func:`pfaffian_lazy`'s steps
    over ``Y`` only, then the one entry left."""
    result, ok = eliminate(A, size, size + 2, p, pinv)
    if not ok:
        return 0.0, 0.0, False
    return result, red(A[size, size + 1], p, pinv), True


@njit(**JIT)
def grid_pairs(n: int, d: int, p: float, zpos: np.ndarray, with_zero: int, lam: np.ndarray, C: np.ndarray,
               iota: np.ndarray, invx: np.ndarray, displacement: bool) -> tuple[np.ndarray, np.ndarray, int]:
    """:func:`grid` for every floor load: ``zeta`` in ``[0 if with_zero] + [z, -z for z in zpos]`` (the columns),
    each pair ``+-z`` from one bordered Pfaffian (:func:`fill_pair`).

    ``displacement``: the pairs of a node go side by side through
    :func:`~.floor_displacement.bordered_pfaffians`; otherwise one lazy
    elimination each (:func:`pfaffian_pair`, the baseline).  A vanishing
    pivot falls back to two pivoting Pfaffians.
    """
    pinv = 1.0 / p
    size = n + (n % 2)
    M = np.zeros((size + 2, size + 2))
    A = np.zeros((size, size))
    sp = np.empty(2 * n + 1)
    tp = np.empty(2 * n + 1)
    npairs = with_zero + zpos.shape[0]
    nz = with_zero + 2 * zpos.shape[0]
    outA, outB, vals = grid_outputs(d, nz)
    failures = 0
    dinv = inv_mod(float(d), p, pinv)
    Z, ss, ts, pf, S, ok = _lane_state(npairs)
    zetas = np.empty(npairs)
    ys = np.empty(npairs)
    for z in range(npairs):
        zetas[z] = 0.0 if (with_zero and z == 0) else zpos[z - with_zero]
        ys[z] = red(zetas[z] * zetas[z], p, pinv)
    for a in range(d + 3):
        one_w = red(1.0 + p - a, p, pinv)
        for b in range(d // 2 + 1):
            s, t = grid_node(a, b, one_w, dinv, p, pinv)
            ss[:] = s
            ts[:] = t
            if displacement:
                bordered_pfaffians(n, ss, ts, ys, invx, p, Z, pf, S, ok)
            else:
                for z in range(npairs):
                    fill_pair(M, n, s, t, ys[z], C, iota, sp, tp, p, pinv)
                    pf[z], S[z], ok[z] = pfaffian_pair(M, size, p, pinv)
            for z in range(npairs):
                zeta = zetas[z]
                cols = (0, 0) if (with_zero and z == 0) else (with_zero + 2 * (z - with_zero), with_zero + 2 * (z - with_zero) + 1)
                if ok[z]:
                    zS = red(zeta * S[z], p, pinv)
                    vals[cols[0]] = red(pf[z] * red(1.0 + p - zS, p, pinv), p, pinv)
                    vals[cols[1]] = red(pf[z] * red(1.0 + zS, p, pinv), p, pinv)
                else:
                    failures += 1
                    for c, zz in ((cols[0], zeta), (cols[1], p - zeta if zeta != 0.0 else 0.0)):
                        fill(A, n, size, s, t, zz, C, iota, sp, tp, p, pinv, True)
                        vals[c] = pfaffian_mod(A, p)
            add_node(outA, outB, a, lam[b], vals, 2 * b != d, p, pinv)
        scale_row(outA, outB, a, one_w, p, pinv)
    return outA, outB, failures


@njit(**JIT)
def monomials(values: np.ndarray, p: float) -> np.ndarray:
    """Monomial coefficients of the polynomial through ``(a, values[a])``, ``a = 0..k``, by forward differences."""
    pinv = 1.0 / p
    k = values.shape[0] - 1
    diff = values.copy()
    for r in range(1, k + 1):  # diff[r] = Delta^r f(0)
        for a in range(k, r - 1, -1):
            diff[a] = red(diff[a] - diff[a - 1] + p, p, pinv)
    coef = np.zeros(k + 1)
    basis = np.zeros(k + 1)  # binom(w, r), constant term first
    basis[0] = 1.0
    coef[0] = diff[0]
    for r in range(1, k + 1):
        ir = inv_mod(float(r), p, pinv)
        for m in range(r, 0, -1):  # basis *= (w - r + 1) / r
            basis[m] = red(red(basis[m - 1] + (p - (r - 1)) * basis[m], p, pinv) * ir, p, pinv)
        basis[0] = red(red((p - (r - 1)) * basis[0], p, pinv) * ir, p, pinv)
        for m in range(r + 1):
            coef[m] = red(coef[m] + diff[r] * basis[m], p, pinv)
    return coef


@njit(**JIT)
def gap_residues(J: np.ndarray, d: int, total_mod: float, p: float) -> np.ndarray:
    """``count x_g`` mod ``p`` from the values of (1) at ``w = 0..d+2``; ``-1`` in slot 0 if the degree exceeds ``d + 1``."""
    pinv = 1.0 / p
    coef = monomials(J, p)
    out = np.zeros(d + 2)
    if coef[d + 2] != 0.0:
        out[0] = -1.0
        return out
    fact = np.empty(d + 1)
    fact[0] = 1.0
    for k in range(1, d + 1):
        fact[k] = red(fact[k - 1] * k, p, pinv)
    ifact = np.empty(d + 1)
    for k in range(d + 1):
        ifact[k] = inv_mod(fact[k], p, pinv)
    delta = np.empty(d)  # the density (second derivative), monomials
    for k in range(d):
        delta[k] = red(coef[k + 2] * red(float((k + 1) * (k + 2)), p, pinv), p, pinv)
    scale = red(total_mod * inv_mod(float(d), p, pinv), p, pinv)  # count / d
    for k in range(d):  # Bernstein: beta_k = sum_i C(k, i) / C(d-1, i) delta_i, gap k + 1
        acc = 0.0
        for i in range(k + 1):
            # C(k, i) / C(d-1, i) = k! (d-1-i)! / ((k-i)! (d-1)!)
            ratio = red(red(fact[k] * ifact[k - i], p, pinv) * red(fact[d - 1 - i] * ifact[d - 1], p, pinv), p, pinv)
            acc = red(acc + ratio * delta[i], p, pinv)
        out[k + 1] = red(acc * scale, p, pinv)
    return out
