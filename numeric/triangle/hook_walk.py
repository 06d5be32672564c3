"""Independent uniform configurations of the triangle by Sagan's shifted hook walk (numba, see :mod:`forcenet.numeric.jit`).

A uniform force network of the fully mobilized triangle is a uniform
standard shifted staircase tableau (the order of the partial sums, Sec. 4.2)
and independent sorted uniforms placed by rank.  The tableau comes from
Sagan's shifted hook walk (Sagan 1980, the shifted analog of Greene,
Nijenhuis and Wilf): the largest remaining entry goes to the corner where a
random walk, started at a uniform cell and jumping to a uniform cell of the
current cell's shifted hook, stops.  The walk lands on corner ``r`` with
probability ``g(lambda - e_r)/g(lambda)``, which the reference sampler
(:func:`forcenet.numeric.triangle.exact_sampler.sample_tableaux`) evaluates
from Schur's formula in ``O(n)`` per removal; the walk needs no weights at
all.  Checked in exact rational arithmetic for every strict partition of
size <= 22 (``tests/test_kernels.py`` repeats it to size 14).

Examples
--------
>>> import numpy as np
>>> hook_walk_tableaux(np.random.default_rng(1), 2, 1)[0].tolist()  # the one standard shifted tableau of (2, 1)
[[0, 0, 0], [0, 1, 2], [0, 0, 3]]
"""

from __future__ import annotations

import numpy as np

from forcenet.exact.triangle.staircase import dimension

from ..jit import njit

__all__ = ["hook_walk_W", "hook_walk_tableaux"]


@njit
def _fenwick_add(tree: np.ndarray, r: int, delta: int) -> None:
    k = r + 1
    n = tree.shape[0] - 1
    while k <= n:
        tree[k] += delta
        k += k & (-k)


@njit
def _fenwick_find(tree: np.ndarray, target: int, top: int) -> tuple[int, int]:
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
def _below(rng: np.random.Generator, m: int) -> int:
    """A uniform integer in ``0..m-1`` as ``floor(m U)``: one double per draw, 6 times cheaper than
    ``Generator.integers``; its bias, at most ``m / 2**53`` relative (< 1e-9 for ``m < 2**23``), is far below
    any statistical error reachable here."""
    k = int(rng.random() * m)
    return k if k < m else m - 1


@njit
def _hook_walk_one(rng: np.random.Generator, n: int, lam: np.ndarray, colh: np.ndarray, tree: np.ndarray, T: np.ndarray,
                   stats: np.ndarray) -> None:
    """Fill ``T`` (shape ``(n+1, n+1)``) with a uniform shifted staircase tableau; ``stats[0] +=`` walk steps."""
    d = n * (n + 1) // 2  # dimension(n + 1), Eq. 4.3 (compiled code cannot call it)
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
def _hook_walk_fill(rng: np.random.Generator, n: int, T: np.ndarray, stats: np.ndarray) -> None:
    lam = np.empty(n, np.int64)
    colh = np.empty(n, np.int64)
    tree = np.zeros(n + 1, np.int64)
    for s in range(T.shape[0]):
        _hook_walk_one(rng, n, lam, colh, tree, T[s], stats)


def hook_walk_tableaux(rng: np.random.Generator, n: int, size: int, stats: np.ndarray | None = None) -> np.ndarray:
    """``size`` uniform standard shifted staircase tableaux of shape ``(n, ..., 1)``.

    Same layout as :func:`forcenet.numeric.triangle.exact_sampler.sample_tableaux`.

    Parameters
    ----------
    rng : numpy.random.Generator
        The stream.
    n : int
        The staircase's longest row (``N - 1`` for ``N`` layers), ``>= 0``.
    size : int
        Tableaux to draw.
    stats : numpy.ndarray, optional
        int64, ``stats[0] +=`` the walk steps taken.

    Returns
    -------
    numpy.ndarray
        Shape ``(size, n+1, n+1)``, the entries at ``[r + 1, c + 1]`` of the cells ``(r, c)``.

    Examples
    --------
    >>> hook_walk_tableaux(np.random.default_rng(0), 2, 2).shape
    (2, 3, 3)
    """
    d = dimension(n + 1)
    T = np.zeros((size, n + 1, n + 1), np.int32 if d < 2**31 else np.int64)
    if n > 0:
        _hook_walk_fill(rng, n, T, np.zeros(1, np.int64) if stats is None else stats)
    return T


@njit
def _W_from_tableau(rng: np.random.Generator, T: np.ndarray, N: int, spacing: np.ndarray, W: np.ndarray) -> None:
    """``W`` (``N x N``) from a tableau: sorted uniforms ``U_(k)`` (normalized exponential spacings) placed by rank."""
    n = N - 1
    d = n * (n + 1) // 2  # dimension(n + 1), Eq. 4.3 (compiled code cannot call it)
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
def hook_walk_W(rng: np.random.Generator, N: int, size: int, W_out: np.ndarray, sums: np.ndarray,
                squares: np.ndarray, orders: np.ndarray, stats: np.ndarray) -> None:
    """``size`` independent uniform configurations of the ``N``-layer triangle.

    Each sample draws its tableau (hook walks) and then its ``d + 1``
    exponentials, so the stream does not depend on how samples are batched.

    Parameters
    ----------
    rng : numpy.random.Generator
        The stream.
    N : int
        Layers, ``>= 1``.
    size : int
        Samples to draw.
    W_out : numpy.ndarray
        If it has ``size`` rows (shape ``(size, N, N)``), the configurations are stored there.
    sums, squares : numpy.ndarray
        Shape ``(len(orders), N, N)``: ``sums[o] += W**orders[o]`` and ``squares[o] += W**(2 orders[o])``
        for every sample.
    orders : numpy.ndarray
        The moments to accumulate (empty to skip).
    stats : numpy.ndarray
        int64, ``stats[0] +=`` the walk steps taken.

    Returns
    -------
    None

    Examples
    --------
    >>> W = np.zeros((2, 3, 3)); none = np.zeros((0, 3, 3))
    >>> hook_walk_W(np.random.default_rng(0), 3, 2, W, none, none, np.zeros(0, np.int64), np.zeros(1, np.int64))
    >>> W.sum(axis=2).round(12).tolist()
    [[1.0, 1.0, 1.0], [1.0, 1.0, 1.0]]
    """
    n = N - 1
    d = n * (n + 1) // 2  # dimension(n + 1), Eq. 4.3 (compiled code cannot call it)
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
