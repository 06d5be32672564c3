"""Compiled inner loop of the N x P packing's Metropolis chain (numba, see :mod:`forcenet.numeric.jit`).

:func:`packing_sweeps` runs the chain of
:class:`forcenet.numeric.packing.metropolis.PackingMetropolis` with the random
numbers drawn in the reference kernel's order (per sweep: the grains, the
uniforms for the new q, then one uniform per move that needs one), from the
same ``numpy.random.Generator``: a seed gives the same chain move for move.

A move at grain ``(i, j)`` recomputes ``W`` in its light cone (Eq. 3.9), and,
for a finite ``p_h``, the lateral forces ``F4`` of the layers ``i..N-1`` from
column ``j`` to the right wall: ``F4`` is a running sum along the layer
(``lateral_forces``), so every force to the right of a changed increment
changes.  These running sums are kept between moves and extended exactly as
``numpy.cumsum`` computes them, so the constraint test is bitwise the
reference's; only the log-weight ratio is summed in a different order (over
the cone instead of whole rows).
"""

from __future__ import annotations

import math

import numpy as np

from ..jit import njit
from ..slice_sampling import log_push, slice_shrink
from .scene import Scene, lateral_increments

__all__ = ["packing_sweeps", "packing_slice_sweeps", "packing_state"]


def packing_state(q: np.ndarray, W: np.ndarray, scene: Scene) -> tuple[np.ndarray, np.ndarray]:
    """``(cs, dd)``: the lateral increments ``dd`` (``F4 - F3``) and their running sums ``cs`` (``F4 = p_h + cs``),
    exactly as :func:`forcenet.numeric.packing.scene.lateral_forces` computes them (zeros without a side pressure)."""
    if scene.ph is None:
        return np.zeros(W.shape), np.zeros(W.shape)
    dd = np.ascontiguousarray(lateral_increments(q, W, scene))
    return np.ascontiguousarray(np.cumsum(dd, axis=1)), dd


@njit
def _increment(q: np.ndarray, W: np.ndarray, S: np.ndarray, i: int, j: int, k: int, c: int, top_load: np.ndarray, mg: float,
               N: int) -> float:
    """``F4 - F3`` at grain (k, c) with the proposed state (rows > i inside the cone read from ``S``)."""
    C = 2.0 / math.sqrt(3.0)
    S3 = math.sqrt(3.0)
    if k < N - 1:
        if k == 0:
            F2 = top_load[c] / S3
        else:
            F2 = (C * q[k - 1, c]) * _w(W, S, i, j, k - 1, c)
        return (-F2) + ((2.0 * q[k, c]) * _w(W, S, i, j, k, c) - mg) / S3
    F1 = 0.0
    if c >= 1:
        F1 = C * ((1.0 - q[N - 2, c - 1]) * _w(W, S, i, j, N - 2, c - 1))
    F2 = (C * q[N - 2, c]) * _w(W, S, i, j, N - 2, c)
    return (F1 - F2) / 2.0


@njit
def _w(W: np.ndarray, S: np.ndarray, i: int, j: int, k: int, c: int) -> float:
    P = W.shape[1]
    if k > i and c >= j and c < min(P, j + 1 + k - i):
        return S[k, c]
    return W[k, c]


@njit
def _light_cone(q: np.ndarray, W: np.ndarray, S: np.ndarray, i: int, j: int, mg: float) -> None:
    """``S`` = the loads ``W`` after ``q[i, j]`` changed, on the light cone below it (Eq. 3.9)."""
    N, P = W.shape
    for c in range(max(j - 1, 0), min(j + 2, P)):
        S[i, c] = W[i, c]
    hi = j + 1
    for k in range(i + 1, N):
        if k - 1 > i:
            if j >= 1:
                S[k - 1, j - 1] = W[k - 1, j - 1]
            if hi < P:
                S[k - 1, hi] = W[k - 1, hi]
        hi = min(P, hi + 1)
        for c in range(j, hi):
            a = q[k - 1, c] * S[k - 1, c] + mg
            if c >= 1:
                a = a + (1.0 - q[k - 1, c - 1]) * S[k - 1, c - 1]
            S[k, c] = a


@njit
def _lateral_sums(q: np.ndarray, W: np.ndarray, S: np.ndarray, cs: np.ndarray, dd: np.ndarray, Cn: np.ndarray, Dn: np.ndarray,
                  i: int, j: int, top_load: np.ndarray, mg: float, ph: float, tol: float, check: bool) -> bool:
    """The new increments ``Dn`` (on the cone) and running sums ``Cn`` (``F4 = p_h + Cn``) of layers ``i..N-1``,
    columns ``j..P-1``, with the proposed cone ``S``; extended exactly as ``numpy.cumsum`` does.  With ``check``
    returns False at the first force below ``tol`` (the move is rejected), else True."""
    N, P = W.shape
    for k in range(i, N):
        changed = j + 1 if k == i else min(P, j + 1 + k - i)  # increments that change: columns j..changed-1
        run = cs[k, j - 1] if j >= 1 else 0.0
        for c in range(j, P):
            if c < changed:
                x = _increment(q, W, S, i, j, k, c, top_load, mg, N)
                Dn[k, c] = x
            else:
                x = dd[k, c]
            run = x if c == 0 else run + x
            Cn[k, c] = run
            if check and ph + run < tol:
                return False
    return True


@njit
def _store(W: np.ndarray, S: np.ndarray, cs: np.ndarray, dd: np.ndarray, Cn: np.ndarray, Dn: np.ndarray, i: int, j: int,
           has_ph: bool) -> None:
    """Accept a new ``q[i, j]``: copy the light cone ``S`` into ``W`` and the new running sums."""
    N, P = W.shape
    hi = j + 1
    for k in range(i + 1, N):
        hi = min(P, hi + 1)
        for c in range(j, hi):
            W[k, c] = S[k, c]
    if has_ph:
        for k in range(i, N):
            changed = j + 1 if k == i else min(P, j + 1 + k - i)
            for c in range(j, changed):
                dd[k, c] = Dn[k, c]
            for c in range(j, P):
                cs[k, c] = Cn[k, c]


@njit
def _packing_move(q: np.ndarray, W: np.ndarray, cs: np.ndarray, dd: np.ndarray, i: int, j: int, new: float,
                  rng: np.random.Generator, ph: float, has_ph: bool, tol: float, top_load: np.ndarray, mg: float,
                  counters: np.ndarray, S: np.ndarray, Cn: np.ndarray, Dn: np.ndarray) -> bool:
    N, P = W.shape
    old = q[i, j]
    q[i, j] = new
    # --- the light cone, Eq. (3.9)
    _light_cone(q, W, S, i, j, mg)
    # --- every free W > 0
    hi = j + 1
    for k in range(i + 1, N - 1):
        hi = min(P, hi + 1)
        for c in range(j, min(hi, P - 1)):
            if S[k, c] <= 0.0:
                q[i, j] = old
                return False
    # --- lateral forces: layers i..N-1, columns j..P-1
    if has_ph and not _lateral_sums(q, W, S, cs, dd, Cn, Dn, i, j, top_load, mg, ph, tol, True):
        q[i, j] = old
        counters[2] += 1
        return False
    # --- the weight prod W over the free grains (Eq. 3.10), on the cone
    total, ratio, count = 0.0, 1.0, 0
    hi = j + 1
    for k in range(i + 1, N - 1):
        hi = min(P, hi + 1)
        for c in range(j, min(hi, P - 1)):
            total, ratio, count = log_push(total, ratio, count, S[k, c] / W[k, c])
    log_ratio = total + math.log(ratio)
    if not (log_ratio >= 0.0 or rng.random() < math.exp(log_ratio)):
        q[i, j] = old
        return False
    _store(W, S, cs, dd, Cn, Dn, i, j, has_ph)
    return True


@njit
def packing_sweeps(q: np.ndarray, W: np.ndarray, cs: np.ndarray, dd: np.ndarray, gi: np.ndarray, gj: np.ndarray,
                   rng: np.random.Generator, sweeps: int, ph: float, has_ph: bool, tol: float, step: float,
                   top_load: np.ndarray, mg: float, out: np.ndarray, qs: np.ndarray, counters: np.ndarray,
                   thin: int = 1) -> None:
    """``sweeps`` sweeps of ``len(gi)`` moves; ``W`` (and ``q``) recorded after every ``thin``-th sweep if ``out``
    (``qs``) is non-empty.

    ``step <= 0`` is the thesis's move (a new q uniform in [0, 1]); ``step > 0``
    the reflected local move of width ``step``.  ``counters``: attempted,
    accepted, rejected by a negative lateral force.
    """
    N, P = W.shape
    G = gi.shape[0]
    picks = np.empty(G, np.int64)
    values = np.empty(G)
    S = np.zeros((N, P))
    Cn = np.zeros((N, P))
    Dn = np.zeros((N, P))
    for s in range(sweeps):
        for m in range(G):
            picks[m] = rng.integers(0, G)
        for m in range(G):
            values[m] = rng.random()
        for m in range(G):
            g = picks[m]
            i = gi[g]
            j = gj[g]
            value = values[m]
            if step > 0.0:
                value = abs(q[i, j] + step * (2.0 * value - 1.0))
                if value > 1.0:
                    value = 2.0 - value
            counters[0] += 1
            if _packing_move(q, W, cs, dd, i, j, value, rng, ph, has_ph, tol, top_load, mg, counters, S, Cn, Dn):
                counters[1] += 1
        if (s + 1) % thin == 0:
            t = (s + 1) // thin - 1
            if out.shape[0] > 0:
                out[t] = W
            if qs.shape[0] > 0:
                qs[t] = q


# ------------------------------------------------------------------ the slice move


@njit
def _packing_commit(q: np.ndarray, W: np.ndarray, cs: np.ndarray, dd: np.ndarray, i: int, j: int, new: float,
                    top_load: np.ndarray, mg: float, ph: float, tol: float, has_ph: bool, S: np.ndarray, Cn: np.ndarray,
                    Dn: np.ndarray) -> None:
    """Set ``q[i, j] = new`` and bring ``W`` (the cone) and the running sums up to date, as the Metropolis kernel does."""
    q[i, j] = new
    _light_cone(q, W, S, i, j, mg)
    if has_ph:
        _lateral_sums(q, W, S, cs, dd, Cn, Dn, i, j, top_load, mg, ph, tol, False)
    _store(W, S, cs, dd, Cn, Dn, i, j, has_ph)


@njit
def packing_slice_sweeps(q: np.ndarray, W: np.ndarray, cs: np.ndarray, dd: np.ndarray, gi: np.ndarray,
                         gj: np.ndarray, rng: np.random.Generator, sweeps: int, ph: float, has_ph: bool, tol: float,
                         top_load: np.ndarray, mg: float, out: np.ndarray, qs: np.ndarray, counters: np.ndarray,
                         thin: int = 1) -> None:
    """Like :func:`packing_sweeps` with the slice move: the new q of the grain is drawn from its exact
    conditional law restricted to the interval where every force stays non-negative (an interval: all
    forces are affine in one q), by slice sampling; no move is rejected.

    ``counters``: moves, moves, 0, density evaluations, give-ups.
    """
    N, P = W.shape
    G = gi.shape[0]
    C = 2.0 / math.sqrt(3.0)
    S3 = math.sqrt(3.0)
    picks = np.empty(G, np.int64)
    R = np.zeros((N, P))
    r = np.empty(N * P)
    S = np.zeros((N, P))
    Cn = np.zeros((N, P))
    Dn = np.zeros((N, P))
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
            # dW/dq on the cone
            hi = min(P, j + 2)
            for c in range(j, hi):
                R[i + 1, c] = w0 if c == j else -w0
            for k in range(i + 2, N):
                prev = hi
                hi = min(P, hi + 1)
                for c in range(j, hi):
                    a = 0.0
                    if c < prev:
                        a = q[k - 1, c] * R[k - 1, c]
                    if c - 1 >= j:
                        a = a + (1.0 - q[k - 1, c - 1]) * R[k - 1, c - 1]
                    R[k, c] = a
            # free W > 0, and the weight's cone cells r = R / W
            m_cells = 0
            hi = j + 1
            for k in range(i + 1, N - 1):
                hi = min(P, hi + 1)
                for c in range(j, min(hi, P - 1)):
                    rc = R[k, c] / W[k, c]
                    r[m_cells] = rc
                    m_cells += 1
                    if rc > 0.0:
                        lo = max(lo, -1.0 / rc)
                    elif rc < 0.0:
                        hi_t = min(hi_t, -1.0 / rc)
            # F4 >= tol: each is affine in q, F4 + t dF4
            if has_ph:
                for k in range(i, N):
                    run = 0.0
                    hik = j + 1 if k == i else min(P, j + 1 + k - i)
                    hik1 = j + 1 if k - 1 == i else min(P, j + k - i)  # cone of row k-1 (k-1 > i)
                    for c in range(j, P):
                        dx = 0.0
                        if k < N - 1:
                            if k == i + 1:
                                if c == j:
                                    dx -= C * w0
                            elif k > i + 1 and c < hik1:
                                dx -= (C * q[k - 1, c]) * R[k - 1, c]
                            if k == i:
                                if c == j:
                                    dx += 2.0 * w0 / S3
                            elif c < hik:
                                dx += 2.0 * q[k, c] * R[k, c] / S3
                        else:
                            dF1 = 0.0
                            dF2 = 0.0
                            if N - 2 == i:
                                if c - 1 == j:
                                    dF1 = -C * w0
                                if c == j:
                                    dF2 = C * w0
                            else:
                                if c >= 1 and c - 1 >= j and c - 1 < hik1:
                                    dF1 = C * (1.0 - q[N - 2, c - 1]) * R[N - 2, c - 1]
                                if c < hik1:
                                    dF2 = C * q[N - 2, c] * R[N - 2, c]
                            dx = (dF1 - dF2) / 2.0
                        run += dx
                        slack = ph + cs[k, c] - tol  # >= 0 now
                        if run > 0.0:
                            lo = max(lo, -slack / run)
                        elif run < 0.0:
                            hi_t = min(hi_t, -slack / run)
            lo = min(lo, 0.0)
            hi_t = max(hi_t, 0.0)
            new = min(1.0, max(0.0, q_old + slice_shrink(rng, lo, hi_t, r, m_cells, counters)))
            _packing_commit(q, W, cs, dd, i, j, new, top_load, mg, ph, tol, has_ph, S, Cn, Dn)
            counters[0] += 1
            counters[1] += 1
        if (s + 1) % thin == 0:
            t = (s + 1) // thin - 1
            if out.shape[0] > 0:
                out[t] = W
            if qs.shape[0] > 0:
                qs[t] = q
