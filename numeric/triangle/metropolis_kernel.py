"""The compiled single-q Metropolis chain of the triangle (numba, see :mod:`forcenet.numeric.jit`).

:func:`triangle_sweeps` runs the chain of
:class:`forcenet.numeric.triangle.metropolis.TriangleMetropolis`.  It draws
the random numbers in the same order as the pure-Python reference kernel (per
sweep: the grains, the new q values, then one uniform per move that needs
one, lazily), from the same ``numpy.random.Generator``, so a given seed gives
the same chain move for move.  A move updates only the light cone of the
grain (``W`` below it, :mod:`.cone`), the log-weight ratio over that cone
(Eq. 3.10, :func:`forcenet.numeric.slice_sampling.log_push`), and (finite
``p_h``) the running sums whose differences are the lateral forces ``F4``.
The only floating-point difference from the reference is the order in which
the log-weight ratio is summed (the reference sums whole rows); it can flip
an acceptance only when a uniform falls within ~1e-15 of the acceptance
probability.
"""

from __future__ import annotations

import math

import numpy as np

from ..jit import njit
from ..slice_sampling import log_push
from .cone import cone_running_sums, light_cone, record_loads, store_cone

__all__ = ["triangle_sweeps"]


@njit
def _triangle_move(q: np.ndarray, W: np.ndarray, flux: np.ndarray, zeros: np.ndarray, i: int, j: int, new: float,
                   rng: np.random.Generator, ph: float, has_ph: bool, counters: np.ndarray, S: np.ndarray,
                   Fn: np.ndarray) -> bool:
    """One single-q move at 0-based grain (i, j); returns True if accepted."""
    N = W.shape[0]
    C = 2.0 / math.sqrt(3.0)
    old = q[i, j]
    q[i, j] = new
    light_cone(q, W, S, i, j)
    # --- lateral forces F4 = ph + C (flux[L] - flux[L-1]) >= 0 (finite p_h): layers i+1..N-1, columns j..L-1
    if has_ph:
        cone_running_sums(q, W, S, flux, Fn, i, j)
        for L in range(i + 1, N):
            for c in range(j, L):
                above = Fn[L - 1, c] if L - 1 >= i + 1 else flux[L - 1, c]
                if ph + C * (Fn[L, c] - above) < -1e-12:
                    q[i, j] = old
                    counters[2] += 1
                    return False
    # --- the weight prod W over rows i+1..N-2 (Eq. 3.10): zeros and the log ratio on the cone
    zeros_old = 0
    for k in range(i + 1, N - 1):
        zeros_old += zeros[k]
    zeros_new = zeros_old
    total, ratio, count = 0.0, 1.0, 0
    for k in range(i + 1, N - 1):
        for c in range(j, j + k - i + 1):
            wn = S[k, c]
            wo = W[k, c]
            if wn == 0.0:
                zeros_new += 1
            if wo == 0.0:
                zeros_new -= 1
            elif wn != 0.0:
                total, ratio, count = log_push(total, ratio, count, wn / wo)
    log_ratio = total + math.log(ratio)
    if zeros_old > 0:  # leaving a zero-density start (e.g. the lattice-direction state)
        accept = zeros_new == 0 or rng.random() < 0.5
    elif zeros_new > 0:
        accept = False
    else:
        accept = log_ratio >= 0.0 or rng.random() < math.exp(log_ratio)
    if not accept:
        q[i, j] = old
        return False
    store_cone(W, S, zeros, i, j)
    if has_ph:
        for L in range(i + 1, N):
            for c in range(j, L + 1):
                flux[L, c] = Fn[L, c]
    return True


@njit
def triangle_sweeps(q: np.ndarray, W: np.ndarray, flux: np.ndarray, zeros: np.ndarray, gi: np.ndarray,
                    gj: np.ndarray, rng: np.random.Generator, sweeps: int, ph: float, has_ph: bool,
                    out: np.ndarray, counters: np.ndarray, thin: int = 1) -> None:
    """``sweeps`` sweeps of ``len(gi)`` single-q Metropolis moves, in place.

    Parameters
    ----------
    q, W : numpy.ndarray
        The state (:class:`forcenet.numeric.triangle.metropolis.TriangleMetropolis`), updated in place.
    flux, zeros : numpy.ndarray
        Its bookkeeping, from :func:`forcenet.numeric.triangle.cone.triangle_state`, kept up to date.
    gi, gj : numpy.ndarray
        The 0-based grains (int64) a move picks from.
    rng : numpy.random.Generator
        The chain's generator.
    sweeps : int
        Sweeps to run.
    ph : float
        The side pressure (units of the overload); ignored unless ``has_ph``.
    has_ph : bool
        Whether the lateral forces are constrained (finite ``p_h``).
    out : numpy.ndarray
        ``W`` is recorded into ``out[s // thin]`` after every ``thin``-th sweep if ``out`` is non-empty.
    counters : numpy.ndarray
        int64: attempted, accepted, rejected by the constraint (updated in place), then two unused here.
    thin : int
        Sweeps per record.

    Returns
    -------
    None

    Examples
    --------
    >>> import numpy as np
    >>> from forcenet.numeric.triangle.cone import triangle_state
    >>> from forcenet.numeric.triangle.metropolis import forces_from_q
    >>> q = np.tril(np.full((3, 3), 0.5)); W = forces_from_q(q); flux, zeros = triangle_state(q, W)
    >>> gi, gj = np.array([0, 1, 1, 2, 2, 2]), np.array([0, 0, 1, 0, 1, 2])
    >>> counters = np.zeros(5, np.int64)
    >>> triangle_sweeps(q, W, flux, zeros, gi, gj, np.random.default_rng(0), 10, 0.0, False,
    ...                 np.empty((0, 4, 4)), counters)
    >>> int(counters[0]), bool(np.allclose(W.sum(axis=1), 1.0))
    (60, True)
    """
    N = W.shape[0]
    G = gi.shape[0]
    picks = np.empty(G, np.int64)
    values = np.empty(G)
    S = np.zeros((N, N))
    Fn = np.zeros((N, N))
    record = out.shape[0] > 0
    for s in range(sweeps):
        for m in range(G):
            picks[m] = rng.integers(0, G)
        for m in range(G):
            values[m] = rng.random()
        for m in range(G):
            g = picks[m]
            counters[0] += 1
            if _triangle_move(q, W, flux, zeros, gi[g], gj[g], values[m], rng, ph, has_ph, counters, S, Fn):
                counters[1] += 1
        if record and (s + 1) % thin == 0:
            record_loads(out, (s + 1) // thin - 1, W)
