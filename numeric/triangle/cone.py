"""The triangle chain's state under a single-q move: the light cone of loads and the lateral running sums.

Shared by the two compiled chains (:mod:`.metropolis_kernel`, :mod:`.slice_kernel`).
A change of ``q[i, j]`` (0-based row ``i`` is layer ``i + 1``) changes the
loads ``W`` (Eq. 4.5) only on the light cone ``W[k, j..j+k-i]``, ``k > i``,
and, for a finite side pressure, the running sums ``flux`` (whose differences
between layers are the lateral forces ``F4``) to the right of column ``j``
in the layers below.  :func:`light_cone` computes the new cone into a
scratch array ``S``, :func:`cone_running_sums` the new running sums into a
scratch array ``Fn``, :func:`store_cone` commits the cone.  The running sums
are extended exactly as ``numpy.cumsum`` computes them in
:func:`forcenet.numeric.triangle.metropolis.lateral_forces`, so the
constraint test is bitwise the reference kernel's.

Examples
--------
>>> import numpy as np
>>> from forcenet.numeric.triangle.metropolis import forces_from_q
>>> q = np.array([[0.5, 0.0], [0.25, 0.5]])
>>> flux, zeros = triangle_state(q, forces_from_q(q))
>>> flux.tolist(), zeros.tolist()
([[0.5, 0.5, 0.5], [0.5, 0.5, 0.5], [0.125, 0.375, 0.375]], [0, 0, 0])
"""

from __future__ import annotations

import numpy as np

from ..jit import njit

__all__ = ["triangle_state", "light_cone", "store_cone", "cone_running_sums", "record_loads"]


def triangle_state(q: np.ndarray, W: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The compiled kernels' bookkeeping for a state: ``flux`` (running sums of ``q W``) and zero counts per row.

    ``flux[L, c] = sum_{k <= c} q[L-1, k] W[L-1, k]`` for layer ``L >= 1`` and
    ``c < L`` (extended by its last value), ``flux[0] = 1/2`` (the overload),
    computed with ``numpy.cumsum`` as in
    :func:`forcenet.numeric.triangle.metropolis.lateral_forces`;
    ``zeros[k]`` counts the exact zeros of ``W`` in row ``k``.

    Parameters
    ----------
    q : numpy.ndarray
        The q-coordinates, shape ``(N-1, N-1)``.
    W : numpy.ndarray
        The loads from ``q`` (Eq. 4.5), shape ``(N, N)``.

    Returns
    -------
    flux : numpy.ndarray
        Shape ``(N, N)``, float64.
    zeros : numpy.ndarray
        Shape ``(N,)``, int64.

    Examples
    --------
    >>> import numpy as np
    >>> triangle_state(np.array([[1.0]]), np.array([[1.0, 0.0], [1.0, 0.0]]))[1].tolist()  # q = 1: one zero load
    [0, 1]
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
def light_cone(q: np.ndarray, W: np.ndarray, S: np.ndarray, i: int, j: int) -> None:
    """``S`` = the loads ``W`` after ``q[i, j]`` changed, on the light cone ``S[k, j..j+k-i]``, ``k > i`` (Eq. 4.5).

    The cells of ``S`` the recursion reads next to the cone are copied from ``W``.
    """
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
def store_cone(W: np.ndarray, S: np.ndarray, zeros: np.ndarray, i: int, j: int) -> None:
    """Commit a new ``q[i, j]``: copy the light cone ``S`` into ``W``, keeping the zero counts per row."""
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
def cone_running_sums(q: np.ndarray, W: np.ndarray, S: np.ndarray, flux: np.ndarray, Fn: np.ndarray,
                      i: int, j: int) -> None:
    """``Fn[L, j..L]`` = the running sums of ``q W`` of layers ``L > i`` with the cone ``S`` (from :func:`light_cone`).

    Row ``L - 1`` of ``q`` and ``W`` feeds layer ``L``; the sums left of
    column ``j`` do not change and are read from ``flux``; ``Fn[L, L]``
    extends the last sum, as :func:`triangle_state` does.
    """
    N = W.shape[0]
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


@njit
def record_loads(out: np.ndarray, t: int, W: np.ndarray) -> None:
    """``out[t] = W`` on the lower triangle (the loads of the ``N`` layers), the chains' record of a state."""
    N = W.shape[0]
    for k in range(N):
        for c in range(k + 1):
            out[t, k, c] = W[k, c]
