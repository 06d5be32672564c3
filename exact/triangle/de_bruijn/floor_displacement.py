"""The floor's bordered de Bruijn Pfaffians by their displacement structure, modulo ``p < 2^22`` (numba).

The bordered matrix of :func:`~.floor_kernels.fill_pair` (``notes/fluctuations.md``
Sec. 5.1) is ``M = [[Y, sigma, rho], [., 0, 0]]`` with ``Y`` of order
``n + n % 2`` (bordered by ``rho`` and ``1`` when ``n`` is odd).  Its ``n x n``
block is Cauchy-like: with the node values ``x_k = k + 1``,

    (x_k + x_m) Y_km = G_k Omega G_m^T,   G = [rho, 1 + t^x, y sigma, s^x],
    Omega = [[0, 1, 0, 0], [-1, 0, 0, 0], [0, 0, 0, 1], [0, 0, -1, 0]],

(``rho_k = (1 - t^x_k)/x_k``, ``sigma_k = s^x_k/x_k``: ``C`` has
``(x_k + x_m) c_km = 1/x_k - 1/x_m``, and the ``y``-free part collapses to
``rho (1 + t^x)^T - (1 + t^x) rho^T``; derived in the notes, checked against
the explicit matrix by the tests).  A Schur complement keeps the form with
``G_2 - A_21 A_11^{-1} G_1`` (Gohberg-Kailath-Olshevsky), so a pivot pair costs
``O(n)`` per remaining row instead of ``O(n^2)``: the two entries
``A[i, k]``, ``A[i, k+1]`` from the generators, then four generator and two
border entries updated.  The border columns ``sigma``, ``rho`` (and, ``n``
odd, the bordering row's ``rho``: the same column, so it is not stored) are
carried explicitly, and the ``2 x 2`` block they close only when ``n`` is
even; for ``n`` odd the last pair ``(n - 1, n)`` gives ``S = -B_0/B_1``.

The elimination is fraction-free, as :mod:`.kernels`: after a pivot ``c``
(seen at the scale ``sigma``) the generators and borders are ``c`` times the
Schur complement's; the scales are divided out at the end with one modular
inverse per lane.  Bounds: every stored value is a loose residue in ``(-p, 2p)``
(:func:`~.residues.lred`) or reduced, so a generator product sum is below
``16 p^2``, an update below ``10 p^2``, both below ``2^48`` for ``p < 2^22``:
exact in ``float64``.  The loop over the rows is a vector loop over one flat
array with a compile-time stride (:data:`STRIDE`), padded to a multiple of 4
rows (zeros, which stay zero).

Measured (``notes/benchmarks.md``): against the lazy elimination of
:mod:`.floor_kernels`, 4.3-5.8x per bordered Pfaffian at N = 36-48 and
3.3-4.7x per prime of the floor route at N = 20-44, in the same run
(``benchmarks/floor_displacement.py``).
"""

from __future__ import annotations

import numpy as np
from numba import uint64

from forcenet.core.compiled import njit

from ..residues import JIT, inv_mod, lred, red

__all__ = ["STRIDE", "STREAMS", "bordered_pfaffians", "inverse_table", "lane_buffer"]

STRIDE = 136
"""Rows per stream of a lane: ``n + 3`` (the padding) for ``n <= 127``; a compile-time constant, not a power of two."""
STREAMS = 6  # the four generators rho, 1 + t^x, y sigma, s^x; the border columns sigma, rho
_US = uint64(STRIDE)


def inverse_table(n: int, p: int) -> np.ndarray:
    """``1/v`` modulo ``p`` for ``v = 0..2n + 15`` (``0`` at ``v = 0``): the node sums ``x_i + x_k`` and the padding.

    Examples
    --------
    >>> inverse_table(1, 7)[:4].tolist()
    [0.0, 1.0, 4.0, 5.0]
    """
    return np.array([0.0] + [float(pow(v, p - 2, p)) for v in range(1, 2 * n + 16)])


def lane_buffer(lanes: int) -> np.ndarray:
    """The zeroed state of ``lanes`` lanes for :func:`bordered_pfaffians` (the padding rows must start at zero)."""
    return np.zeros(STREAMS * STRIDE * lanes)


@njit(inline="always", fastmath={"contract"}, **JIT)
def _update(x: float, c: float, e0: float, e1: float, q0: float, q1: float, p: float, pinv: float) -> float:
    """``c x - e1 q0 + e0 q1``: a row's entry after the fraction-free Schur step (below ``10 p^2`` before reduction)."""
    return lred(c * x - e1 * q0 + e0 * q1, p, pinv)


@njit(fastmath={"contract"}, **JIT)
def _step(Z: np.ndarray, o: int, k: int, n: int, invx: np.ndarray, c: float, p: float, pinv: float) -> None:
    """The pivot pair ``(k, k+1)`` of one lane (offset ``o``) on the rows ``k + 2..n - 1`` (padded): a vector loop.

    ``A[i, k] = G_i Omega G_k^T / (x_i + x_k)``, ``A[i, k+1]`` the same, then
    ``G_i <- c G_i - A[i, k+1] G_k + A[i, k] G_(k+1)`` and the border columns alike.
    """
    k0 = uint64(o) + uint64(k)
    g0, g1, g2, g3 = Z[k0], Z[k0 + _US], Z[k0 + 2 * _US], Z[k0 + 3 * _US]
    b0, b1 = Z[k0 + 4 * _US], Z[k0 + 5 * _US]
    k1 = k0 + uint64(1)
    h0, h1, h2, h3 = Z[k1], Z[k1 + _US], Z[k1 + 2 * _US], Z[k1 + 3 * _US]
    d0, d1 = Z[k1 + 4 * _US], Z[k1 + 5 * _US]
    lo = uint64(k + 2)
    xo = uint64(k + 2)  # x_i + x_k = i + k + 2
    for i in range(lo, lo + ((uint64(n) - lo + uint64(3)) & ~uint64(3))):
        i0 = uint64(o) + i
        i1 = i0 + _US  # chained offsets: the compiler sees the streams apart (no run-time alias checks)
        i2 = i1 + _US
        i3 = i2 + _US
        i4 = i3 + _US
        i5 = i4 + _US
        a0, a1, a2, a3 = Z[i0], Z[i1], Z[i2], Z[i3]
        e0 = lred(lred((a0 * g1 - a1 * g0) + (a2 * g3 - a3 * g2), p, pinv) * invx[xo + i], p, pinv)
        e1 = lred(lred((a0 * h1 - a1 * h0) + (a2 * h3 - a3 * h2), p, pinv) * invx[xo + i + uint64(1)], p, pinv)
        Z[i0] = _update(a0, c, e0, e1, g0, h0, p, pinv)
        Z[i1] = _update(a1, c, e0, e1, g1, h1, p, pinv)
        Z[i2] = _update(a2, c, e0, e1, g2, h2, p, pinv)
        Z[i3] = _update(a3, c, e0, e1, g3, h3, p, pinv)
        Z[i4] = _update(Z[i4], c, e0, e1, b0, d0, p, pinv)
        Z[i5] = _update(Z[i5], c, e0, e1, b1, d1, p, pinv)


@njit(**JIT)
def _copy_fill(Z: np.ndarray, o: int, n: int, y: float, p: float, pinv: float) -> None:
    """The lane at ``o`` from the one before it (same ``s``, ``t``; its state not yet eliminated), at ``y``."""
    src = o - STREAMS * STRIDE
    for k in range(n):
        for r in (0, 1, 3, 4, 5):
            Z[o + r * STRIDE + k] = Z[src + r * STRIDE + k]
        Z[o + 2 * STRIDE + k] = red(y * Z[o + 4 * STRIDE + k], p, pinv)


@njit(**JIT)
def _fill(Z: np.ndarray, o: int, n: int, s: float, t: float, y: float, invx: np.ndarray, p: float, pinv: float) -> None:
    """The generators and border columns of one lane at ``(s, t, y)``."""
    sk = 1.0
    tk = 1.0
    for k in range(n):
        sk = red(sk * s, p, pinv)
        tk = red(tk * t, p, pinv)
        rho = red(invx[k + 1] * (1.0 + p - tk), p, pinv)
        sig = red(invx[k + 1] * sk, p, pinv)
        Z[o + k] = rho
        Z[o + STRIDE + k] = 1.0 + tk
        Z[o + 2 * STRIDE + k] = red(y * sig, p, pinv)
        Z[o + 3 * STRIDE + k] = sk
        Z[o + 4 * STRIDE + k] = sig  # the column sigma
        Z[o + 5 * STRIDE + k] = rho  # the column rho (and, n odd, the bordering row's)


@njit(**JIT)
def bordered_pfaffians(n: int, ss: np.ndarray, ts: np.ndarray, ys: np.ndarray, invx: np.ndarray, p: float,
                       Z: np.ndarray, pf: np.ndarray, S: np.ndarray, ok: np.ndarray) -> None:
    """``Pf Y`` and ``S`` of :func:`~.floor_kernels.fill_pair`'s matrix at every lane ``(ss[l], ts[l], ys[l])``.

    The same residues as :func:`~.floor_kernels.pfaffian_pair` (tested), by
    the displacement structure (module docstring).  ``invx`` is
    :func:`inverse_table`, ``Z`` a :func:`lane_buffer` of at least as many
    lanes.  ``ok[l]`` is False when a pivot vanishes modulo ``p`` (the same
    pivots as the lazy elimination's: the caller falls back to pivoting).
    """
    pinv = 1.0 / p
    odd = n % 2
    for l in range(ys.shape[0]):  # the lanes' generators first: lanes at the same node share all but y sigma
        if l > 0 and ss[l] == ss[l - 1] and ts[l] == ts[l - 1]:
            _copy_fill(Z, STREAMS * STRIDE * l, n, ys[l], p, pinv)
        else:
            _fill(Z, STREAMS * STRIDE * l, n, ss[l], ts[l], ys[l], invx, p, pinv)
    for l in range(ys.shape[0]):
        o = STREAMS * STRIDE * l
        z01 = 0.0  # A[size, size+1] times sigma (n even)
        sigma = 1.0  # the scale: the product of the pivots seen
        num = 1.0  # the product of the pivots seen
        den = 1.0  # the product of sigma^2 before each pivot
        good = True
        for k in range(0, n - 1, 2):
            ko = o + k
            q0, q1, q2, q3 = Z[ko], Z[ko + STRIDE], Z[ko + 2 * STRIDE], Z[ko + 3 * STRIDE]
            r0, r1, r2, r3 = Z[ko + 1], Z[ko + 1 + STRIDE], Z[ko + 1 + 2 * STRIDE], Z[ko + 1 + 3 * STRIDE]
            c = red(lred((q0 * r1 - q1 * r0) + (q2 * r3 - q3 * r2), p, pinv) * invx[2 * k + 3], p, pinv)
            if c == 0.0:
                good = False
                break
            if not odd:  # the border block: c z01 - sigma (B_k0 B_(k+1)1 - B_(k+1)0 B_k1)
                cross = lred(Z[ko + 4 * STRIDE] * Z[ko + 1 + 5 * STRIDE] - Z[ko + 1 + 4 * STRIDE] * Z[ko + 5 * STRIDE],
                             p, pinv)
                z01 = lred(c * z01 - sigma * cross, p, pinv)
            den = red(den * red(sigma * sigma, p, pinv), p, pinv)
            num = red(num * c, p, pinv)
            _step(Z, o, k, n, invx, c, p, pinv)
            sigma = red(sigma * c, p, pinv)
        ok[l] = good
        if not good:
            continue
        ds = red(den * sigma, p, pinv)
        if odd:  # the pair (n - 1, n): its pivot is B_1/sigma, and S = -B_0/B_1
            b0 = red(Z[o + n - 1 + 4 * STRIDE], p, pinv)
            b1 = red(Z[o + n - 1 + 5 * STRIDE], p, pinv)
            if b1 == 0.0:
                ok[l] = False
                continue
            inv = inv_mod(red(ds * b1, p, pinv), p, pinv)  # 1/(den sigma b1)
            pf[l] = red(red(num * b1, p, pinv) * red(inv * b1, p, pinv), p, pinv)  # num b1 / (den sigma)
            S[l] = red(red(p - b0, p, pinv) * red(inv * ds, p, pinv), p, pinv)
        else:
            inv = inv_mod(ds, p, pinv)
            pf[l] = red(num * red(inv * sigma, p, pinv), p, pinv)  # num / den
            S[l] = red(red(z01, p, pinv) * red(inv * den, p, pinv), p, pinv)  # z01 / sigma
