"""The compiled slice-move chain of the triangle (numba, see :mod:`forcenet.numeric.jit`).

:func:`triangle_slice_sweeps` runs
:class:`forcenet.numeric.triangle.metropolis.TriangleMetropolis` with
``move="slice"``: the grain's new q is drawn from its conditional law given
the others.  Every load of the light cone is affine in that q, so the weight
``prod W`` (Eq. 3.10) is a product of affine factors, log-concave, and the
lateral forces ``F4`` (finite ``p_h``) are affine too: the allowed q form an
interval, found from the derivatives ``dW/dq`` on the cone (Eq. 4.5
differentiated), on which :func:`forcenet.numeric.slice_sampling.slice_shrink`
draws the new q.  The state is then committed with :mod:`.cone`.
"""

from __future__ import annotations

import math

import numpy as np

from ..jit import njit
from ..slice_sampling import slice_shrink
from .cone import cone_running_sums, light_cone, record_loads, store_cone

__all__ = ["triangle_slice_sweeps"]


@njit
def _triangle_commit(q: np.ndarray, W: np.ndarray, flux: np.ndarray, zeros: np.ndarray, i: int, j: int, new: float,
                     has_ph: bool, S: np.ndarray, Fn: np.ndarray) -> None:
    """Set ``q[i, j] = new``; bring the light cone of ``W``, the zero counts and the running sums up to date."""
    N = W.shape[0]
    q[i, j] = new
    light_cone(q, W, S, i, j)
    if has_ph:
        cone_running_sums(q, W, S, flux, Fn, i, j)
    store_cone(W, S, zeros, i, j)
    if has_ph:
        for L in range(i + 1, N):
            for c in range(j, L + 1):
                flux[L, c] = Fn[L, c]


@njit
def triangle_slice_sweeps(q: np.ndarray, W: np.ndarray, flux: np.ndarray, zeros: np.ndarray, gi: np.ndarray,
                          gj: np.ndarray, rng: np.random.Generator, sweeps: int, ph: float, has_ph: bool,
                          out: np.ndarray, counters: np.ndarray, thin: int = 1) -> None:
    """Like :func:`forcenet.numeric.triangle.metropolis_kernel.triangle_sweeps` with the slice move.

    The grain's new q is drawn from its conditional law given the others,
    restricted to the interval where every lateral force stays >= 0 (finite
    ``p_h``), by slice sampling with shrinkage.  From a zero-density state (the
    lattice-direction start) a move draws q uniformly in its interval instead.

    Parameters
    ----------
    q, W, flux, zeros, gi, gj, rng, sweeps, ph, has_ph, out, thin
        As for :func:`forcenet.numeric.triangle.metropolis_kernel.triangle_sweeps`.
    counters : numpy.ndarray
        int64: moves, moves that changed q, 0, density evaluations, give-ups; updated in place.

    Returns
    -------
    None

    Examples
    --------
    >>> from forcenet.numeric.triangle.metropolis import TriangleMetropolis
    >>> sampler = TriangleMetropolis(4, seed=0, move="slice")  # its sweeps run this kernel
    >>> sampler.sweep(10)
    >>> sampler.attempted, sampler.accepted  # 10 sweeps of 6 grains; every move changes q
    (60, 60)
    """
    N = W.shape[0]
    G = gi.shape[0]
    C = 2.0 / math.sqrt(3.0)
    picks = np.empty(G, np.int64)
    R = np.zeros((N, N))
    dfl = np.zeros((N + 1, N + 1))
    r = np.empty(N * N)
    S = np.zeros((N, N))
    Fn = np.zeros((N, N))
    record = out.shape[0] > 0
    for s in range(sweeps):
        for m in range(G):
            picks[m] = rng.integers(0, G)
        for m in range(G):
            g = picks[m]
            i = gi[g]
            j = gj[g]
            q_old = q[i, j]
            w0 = W[i, j]
            lo = -q_old
            hi_t = 1.0 - q_old
            # dW/dq on the cone (Eq. 4.5 differentiated)
            R[i + 1, j] = w0
            R[i + 1, j + 1] = -w0
            for k in range(i + 2, N):
                for c in range(j, j + k - i + 1):
                    a = 0.0
                    if c <= j + k - 1 - i:
                        a = q[k - 1, c] * R[k - 1, c]
                    if c - 1 >= j:
                        a = a + (1.0 - q[k - 1, c - 1]) * R[k - 1, c - 1]
                    R[k, c] = a
            zero_density = False
            for k in range(i + 1, N - 1):
                if zeros[k] > 0:
                    zero_density = True
            m_cells = 0
            if not zero_density:
                for k in range(i + 1, N - 1):
                    for c in range(j, j + k - i + 1):
                        r[m_cells] = R[k, c] / W[k, c]
                        m_cells += 1
            if has_ph:  # F4 of layer L, column c: ph + C (flux[L, c] - flux[L-1, c]), affine in q
                for L in range(i + 1, N):
                    run = 0.0
                    for c in range(j, L + 1):
                        if L == i + 1:
                            if c == j:
                                run = w0
                        elif c <= j + L - 1 - i:
                            run += q[L - 1, c] * R[L - 1, c]
                        dfl[L, c] = run
                    for c in range(j, L):
                        below = dfl[L - 1, c] if L - 1 >= i + 1 else 0.0
                        slope = C * (dfl[L, c] - below)
                        slack = ph + C * (flux[L, c] - flux[L - 1, c]) + 1e-12
                        if slack < 0.0:
                            slack = 0.0
                        if slope > 0.0:
                            lo = max(lo, -slack / slope)
                        elif slope < 0.0:
                            hi_t = min(hi_t, -slack / slope)
            lo = min(lo, 0.0)
            hi_t = max(hi_t, 0.0)
            if zero_density:
                t = lo + rng.random() * (hi_t - lo)
            else:
                t = slice_shrink(rng, lo, hi_t, r, m_cells, counters)
            new = min(1.0, max(0.0, q_old + t))
            _triangle_commit(q, W, flux, zeros, i, j, new, has_ph, S, Fn)
            counters[0] += 1
            if new != q_old:
                counters[1] += 1
        if record and (s + 1) % thin == 0:
            record_loads(out, (s + 1) // thin - 1, W)
