"""Compiled inner loops of the triangle's two samplers (numba, see :mod:`forcenet.numeric.jit`).

* :func:`triangle_sweeps`: the single-q Metropolis chain of
  :class:`forcenet.numeric.triangle.metropolis.TriangleMetropolis`.  It draws the
  random numbers in the same order as the pure-Python reference kernel
  (per sweep: the grains, the new q values, then one uniform per move that
  needs one, lazily), from the same ``numpy.random.Generator``, so a given
  seed gives the same chain move for move.  The move updates only the
  light cone of the grain (``W`` below it), the log-weight ratio over that
  cone, and (finite ``p_h``) the lateral forces ``F4`` to the right of the
  grain's column in the layers below, kept as running sums ``flux`` exactly as
  the reference's ``cumsum`` computes them.  The only floating-point
  difference from the reference is the order in which the log-weight ratio
  is summed (the reference sums whole rows); it can flip an acceptance only
  when a uniform falls within ~1e-15 of the acceptance probability.
* :func:`hook_walk_W`: independent uniform configurations by Sagan's
  shifted hook walk (Sagan 1980, the shifted analog of Greene, Nijenhuis and
  Wilf): the largest remaining entry of the staircase tableau goes to the
  corner where a random walk, started at a uniform cell and jumping to a
  uniform cell of the current cell's shifted hook, stops.  The walk lands on
  corner ``r`` with probability ``g(lambda - e_r)/g(lambda)``, which the
  reference sampler (:func:`forcenet.numeric.triangle.exact_sampler.sample_tableaux`)
  evaluates from Schur's formula in ``O(n)`` per removal; the walk needs no
  weights at all.  Checked in exact rational arithmetic for every strict
  partition of size <= 22 (``tests/test_kernels.py`` repeats it to size 14).

May import: numpy, :mod:`forcenet.numeric.jit`.
"""

from __future__ import annotations

import math

import numpy as np

from ..jit import njit

__all__ = ["triangle_sweeps", "hook_walk_W", "hook_walk_tableaux", "triangle_state"]

_C = 2 / math.sqrt(3)


def triangle_state(q: np.ndarray, W: np.ndarray):
    """The kernel's bookkeeping for a state: ``flux`` (running sums of ``q W``) and zero counts per row.

    ``flux[L, c] = sum_{k <= c} q[L-1, k] W[L-1, k]`` for layer ``L >= 1`` and
    ``c < L`` (extended by its last value), ``flux[0] = 1/2`` (the overload),
    computed with ``numpy.cumsum`` as in
    :func:`forcenet.numeric.triangle.metropolis.lateral_forces`;
    ``zeros[k]`` counts the exact zeros of ``W`` in row ``k``.
    """
    N = W.shape[0]
    flux = np.zeros((N, N))
    flux[0, :] = 0.5
    for i in range(1, N):
        flux[i, :i] = np.cumsum(q[i - 1, :i] * W[i - 1, :i])
        flux[i, i:] = flux[i, i - 1]
    zeros = np.array([int((W[k, : k + 1] == 0.0).sum()) for k in range(N)], dtype=np.int64)
    return flux, zeros


@njit
def _light_cone(q, W, S, i, j):
    """``S`` = the loads ``W`` after ``q[i, j]`` changed, on the light cone ``S[k, j..j+k-i]``, ``k > i`` (Eq. 4.5)."""
    N = W.shape[0]
    for c in range(max(j - 1, 0), min(j + 1, i) + 1):
        S[i, c] = W[i, c]
    for k in range(i + 1, N):
        hi = j + k - i
        if j >= 1:
            S[k - 1, j - 1] = W[k - 1, j - 1]
        if hi < k:
            S[k - 1, hi] = W[k - 1, hi]
        for c in range(j, hi + 1):
            a = 0.0
            if c < k:
                a = q[k - 1, c] * S[k - 1, c]
            if c >= 1:
                a = a + (1.0 - q[k - 1, c - 1]) * S[k - 1, c - 1]
            S[k, c] = a


@njit
def _store_cone(W, S, zeros, i, j):
    """Accept a new ``q[i, j]``: copy the light cone ``S`` into ``W``, keeping the zero counts per layer."""
    N = W.shape[0]
    for k in range(i + 1, N):
        dz = 0
        for c in range(j, j + k - i + 1):
            if W[k, c] == 0.0:
                dz -= 1
            if S[k, c] == 0.0:
                dz += 1
            W[k, c] = S[k, c]
        zeros[k] += dz


@njit
def _triangle_move(q, W, flux, zeros, i, j, new, rng, ph, has_ph, counters, S, Fn):
    """One single-q move at 0-based grain (i, j); returns True if accepted."""
    N = W.shape[0]
    C = 2.0 / math.sqrt(3.0)
    old = q[i, j]
    q[i, j] = new
    # --- the light cone: S[k, j..j+k-i] for k = i+1..N-1 (Eq. 4.5)
    _light_cone(q, W, S, i, j)
    # --- lateral forces F4 >= 0 (finite p_h): layers L = i+1..N-1, columns j..L-1
    if has_ph:
        for L in range(i + 1, N):
            row = L - 1  # q row and W row of layer L
            run = flux[L, j - 1] if j >= 1 else 0.0
            for c in range(j, L):
                if row >= i + 1 and c <= j + row - i:
                    w = S[row, c]
                else:
                    w = W[row, c]
                x = q[row, c] * w
                run = x if c == 0 else run + x
                Fn[L, c] = run
            Fn[L, L] = Fn[L, L - 1]
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
    log_ratio = 0.0
    ratio = 1.0  # products of up to 8 ratios between logs: one log per 8 cells
    count = 0
    for k in range(i + 1, N - 1):
        for c in range(j, j + k - i + 1):
            wn = S[k, c]
            wo = W[k, c]
            if wn == 0.0:
                zeros_new += 1
            if wo == 0.0:
                zeros_new -= 1
            elif wn != 0.0:
                ratio *= wn / wo
                count += 1
                if count == 8 or not (1e-150 < ratio < 1e150):
                    log_ratio += math.log(ratio)
                    ratio = 1.0
                    count = 0
    log_ratio += math.log(ratio)
    if zeros_old > 0:  # leaving a zero-density start (e.g. the lattice-direction state)
        accept = zeros_new == 0 or rng.random() < 0.5
    elif zeros_new > 0:
        accept = False
    else:
        accept = log_ratio >= 0.0 or rng.random() < math.exp(log_ratio)
    if not accept:
        q[i, j] = old
        return False
    _store_cone(W, S, zeros, i, j)
    if has_ph:
        for L in range(i + 1, N):
            for c in range(j, L + 1):
                flux[L, c] = Fn[L, c]
    return True


@njit
def triangle_sweeps(q, W, flux, zeros, gi, gj, rng, sweeps, ph, has_ph, out, counters, thin=1):
    """``sweeps`` sweeps of ``len(gi)`` single-q moves; ``W`` recorded into ``out[s // thin]`` after every
    ``thin``-th sweep if ``out`` is non-empty.

    ``counters`` (int64[3]): attempted, accepted, rejected by the constraint; updated in place.
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
            t = (s + 1) // thin - 1
            for k in range(N):
                for c in range(k + 1):
                    out[t, k, c] = W[k, c]


# ----------------------------------------------------------------- the exact sampler


@njit
def _fenwick_add(tree, r, delta):
    k = r + 1
    n = tree.shape[0] - 1
    while k <= n:
        tree[k] += delta
        k += k & (-k)


@njit
def _fenwick_find(tree, target, top):
    """Smallest 0-based row r with prefix(r + 1) > target; also returns prefix(r)."""
    pos = 0
    acc = 0
    step = top
    n = tree.shape[0] - 1
    while step > 0:
        nxt = pos + step
        if nxt <= n and acc + tree[nxt] <= target:
            pos = nxt
            acc += tree[nxt]
        step >>= 1
    return pos, acc


@njit
def _below(rng, m):
    """A uniform integer in ``0..m-1`` as ``floor(m U)``: one double per draw, 6 times cheaper than
    ``Generator.integers``; its bias, at most ``m / 2**53`` relative (< 1e-9 for ``m < 2**23``), is far below
    any statistical error reachable here."""
    k = int(rng.random() * m)
    return k if k < m else m - 1


@njit
def _hook_walk_one(rng, n, lam, colh, tree, T, stats):
    """Fill ``T`` (shape ``(n+1, n+1)``) with a uniform shifted staircase tableau; ``stats[0] +=`` walk steps."""
    d = n * (n + 1) // 2
    for r in range(n):
        lam[r] = n - r
        colh[r] = r + 1
    tree[:] = 0
    for r in range(n):
        _fenwick_add(tree, r, lam[r])
    top = 1
    while top * 2 <= n:
        top *= 2
    size = d
    steps = 0
    for entry in range(d, 0, -1):
        idx = _below(rng, size)
        r, before = _fenwick_find(tree, idx, top)
        c = r + (idx - before)
        while True:  # the shifted hook walk
            arm = r + lam[r] - 1 - c
            leg = colh[c] - r - 1
            extra = lam[c + 1] if c + 1 < n else 0
            h = arm + leg + extra
            if h == 0:
                break
            k = _below(rng, h)
            steps += 1
            if k < arm:
                c = c + 1 + k
            elif k < arm + leg:
                r = r + 1 + (k - arm)
            else:
                r = c + 1
                c = c + 1 + (k - arm - leg)
        T[r + 1, c + 1] = entry
        lam[r] -= 1
        colh[c] -= 1
        _fenwick_add(tree, r, -1)
        size -= 1
    stats[0] += steps


@njit
def _hook_walk_fill(rng, n, T, stats):
    lam = np.empty(n, np.int64)
    colh = np.empty(n, np.int64)
    tree = np.zeros(n + 1, np.int64)
    for s in range(T.shape[0]):
        _hook_walk_one(rng, n, lam, colh, tree, T[s], stats)


def hook_walk_tableaux(rng, n: int, size: int, stats=None) -> np.ndarray:
    """``size`` uniform standard shifted staircase tableaux of shape ``(n, ..., 1)``, shape ``(size, n+1, n+1)``.

    Same layout as :func:`forcenet.numeric.triangle.exact_sampler.sample_tableaux`.
    """
    d = n * (n + 1) // 2
    T = np.zeros((size, n + 1, n + 1), np.int32 if d < 2**31 else np.int64)
    if n > 0:
        _hook_walk_fill(rng, n, T, np.zeros(1, np.int64) if stats is None else stats)
    return T


@njit
def _W_from_tableau(rng, T, N, spacing, W):
    """``W`` (``N x N``) from a tableau: sorted uniforms ``U_(k)`` (normalized exponential spacings) placed by rank."""
    n = N - 1
    d = n * (n + 1) // 2
    total = 0.0
    spacing[0] = 0.0
    for k in range(1, d + 2):
        total += rng.standard_exponential()
        spacing[k] = total
    inv = 1.0 / total  # U_(k) = spacing[k] / spacing[d + 1], k = 1..d
    for i in range(1, N + 1):
        prev = 0.0
        for j in range(1, i):
            s = spacing[T[j, N - i + j]] * inv
            W[i - 1, j - 1] = s - prev
            prev = s
        W[i - 1, i - 1] = 1.0 - prev
        for j in range(i, N):
            W[i - 1, j] = 0.0


@njit
def hook_walk_W(rng, N, size, W_out, sums, squares, orders, stats):
    """``size`` independent uniform configurations of the ``N``-layer triangle.

    Each sample draws its tableau (hook walks) and then its ``d + 1``
    exponentials, so the stream does not depend on how samples are batched.
    If ``W_out`` has ``size`` rows the configurations are stored there;
    ``sums[o] += W**orders[o]`` and ``squares[o] += W**(2 orders[o])`` are
    accumulated for every sample (pass empty ``orders`` to skip).
    """
    n = N - 1
    d = n * (n + 1) // 2
    T = np.zeros((n + 1, n + 1), np.int64)
    lam = np.empty(max(n, 1), np.int64)
    colh = np.empty(max(n, 1), np.int64)
    tree = np.zeros(n + 1, np.int64)
    spacing = np.empty(d + 2)
    W = np.empty((N, N))
    store = W_out.shape[0] == size
    for s in range(size):
        if n > 0:
            _hook_walk_one(rng, n, lam, colh, tree, T, stats)
        _W_from_tableau(rng, T, N, spacing, W)
        if store:
            W_out[s] = W
        for o in range(orders.shape[0]):
            p = orders[o]
            for i in range(N):
                for j in range(i + 1):
                    x = W[i, j] ** p
                    sums[o, i, j] += x
                    squares[o, i, j] += x * x


# ------------------------------------------------------------------ the slice move


@njit
def _triangle_commit(q, W, flux, zeros, i, j, new, has_ph, S):
    """Set ``q[i, j] = new``; recompute the light cone of ``W``, the zero counts and the running sums."""
    N = W.shape[0]
    q[i, j] = new
    _light_cone(q, W, S, i, j)
    _store_cone(W, S, zeros, i, j)
    if has_ph:
        for L in range(i + 1, N):
            row = L - 1
            run = flux[L, j - 1] if j >= 1 else 0.0
            for c in range(j, L):
                x = q[row, c] * W[row, c]
                run = x if c == 0 else run + x
                flux[L, c] = run
            flux[L, L] = flux[L, L - 1]


@njit
def _slice_t(rng, lo, hi, r, m, counters):
    """Slice sampling with shrinkage of ``t`` in ``[lo, hi]`` (containing 0) for the density
    ``prod_c (1 + t r_c)`` (log-concave); returns ``t``."""
    y = -rng.standard_exponential()
    left, right = lo, hi
    for _ in range(200):
        t = left + rng.random() * (right - left)
        counters[3] += 1
        total = 0.0
        ratio = 1.0
        count = 0
        ok = True
        for c in range(m):
            x = 1.0 + t * r[c]
            if x <= 0.0:
                ok = False
                break
            ratio *= x
            count += 1
            if count == 8 or not (1e-150 < ratio < 1e150):
                total += math.log(ratio)
                ratio = 1.0
                count = 0
        if ok and total + math.log(ratio) > y:
            return t
        if t < 0.0:
            left = t
        else:
            right = t
    counters[4] += 1
    return 0.0


@njit
def triangle_slice_sweeps(q, W, flux, zeros, gi, gj, rng, sweeps, ph, has_ph, out, counters, thin=1):
    """Like :func:`triangle_sweeps` with the slice move: the grain's new q is drawn from its conditional
    law given the others (the weight is a product of forces affine in that q, log-concave), restricted to
    the interval where every lateral force stays >= 0 (finite ``p_h``), by slice sampling with shrinkage.

    ``counters``: moves, moves that changed q, 0, density evaluations, give-ups.  From a zero-density
    state (the lattice-direction start) a move draws q uniformly in its interval instead.
    """
    N = W.shape[0]
    G = gi.shape[0]
    C = 2.0 / math.sqrt(3.0)
    picks = np.empty(G, np.int64)
    R = np.zeros((N, N))
    dfl = np.zeros((N + 1, N + 1))
    r = np.empty(N * N)
    S = np.zeros((N, N))
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
                t = _slice_t(rng, lo, hi_t, r, m_cells, counters)
            new = min(1.0, max(0.0, q_old + t))
            _triangle_commit(q, W, flux, zeros, i, j, new, has_ph, S)
            counters[0] += 1
            if new != q_old:
                counters[1] += 1
        if record and (s + 1) % thin == 0:
            t_rec = (s + 1) // thin - 1
            for k in range(N):
                for c in range(k + 1):
                    out[t_rec, k, c] = W[k, c]
