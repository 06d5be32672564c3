"""A heat-bath chain on the partial sums, right or wrong on purpose: the power and level tables' test chain.

The triangle's configurations are the interlacing partial sums
``S_{i-1,j-1} <= S_{i,j} <= S_{i-1,j}`` with ``S_{i,0} = 0`` and
``S_{i,i} = 1`` (Eq. (4.5) and the interlacing of Sec. 4.1: ``W`` in units
of the overload, every row summing to 1), uniformly distributed. The heat
bath redraws one free sum uniformly between its four neighbours (the rows
above and below); the sums of one row do not constrain each other, so the
even rows, then the odd rows, are redrawn at once. ``bias`` draws
``u**bias`` instead of the uniform ``u``: a wrong sampler whose error grows
with ``bias - 1`` (issue 53's chain: ``N = 6``, 20000 sweeps, ``u**1.3``).

Examples
--------
>>> W = heat_bath_W(4, 3, seed=0)
>>> W.shape, bool(abs(W.sum(axis=2) - 1).max() < 1e-12)
((3, 4, 4), True)
"""

from __future__ import annotations

import numpy as np

from forcenet.core.validation import check_int, check_real

__all__ = ["heat_bath_W"]


def heat_bath_W(N: int, sweeps: int, seed: int, bias: float = 1.0) -> np.ndarray:
    """``W`` after each of ``sweeps`` heat-bath sweeps over the partial sums, shape ``(sweeps, N, N)``.

    Parameters
    ----------
    N : int
        Layers (at least 2).
    sweeps : int
        Sweeps recorded (each redraws every free sum once).
    seed : int
        Seed of numpy's generator.
    bias : float
        The draw is ``u**bias``: 1 is the correct chain (the uniform measure on the interlacing sums).

    Returns
    -------
    numpy.ndarray
        ``W[t, i - 1, j - 1] = S_{i,j} - S_{i,j-1}`` (0 above the diagonal).

    Examples
    --------
    >>> heat_bath_W(2, 2, seed=1)[:, 1].round(3).tolist()
    [[0.512, 0.488], [0.95, 0.05]]
    """
    N = check_int(N, "N", 2)
    sweeps = check_int(sweeps, "sweeps", 1)
    bias = check_real(bias, "bias", 0, None, low_open=True)
    rng = np.random.default_rng(seed)
    S = np.zeros((N + 1, N + 1))  # S[i - 1, j] = S_{i,j}; row i - 1 starts equally spaced (it interlaces)
    for i in range(1, N + 1):
        S[i - 1, : i + 1] = np.arange(i + 1) / i
    out = np.zeros((sweeps, N, N))
    for t in range(sweeps):
        for parity in (1, 0):
            for r in range(1 + parity, N, 2):  # row index r = i - 1, rows 2..N (row 1 has no free sum)
                j = np.arange(1, r + 1)
                lo, hi = S[r - 1, j - 1], S[r - 1, j]  # the row above: S_{i-1,j-1} <= S_{i,j} <= S_{i-1,j}
                if r + 1 < N:  # the row below: S_{i+1,j} <= S_{i,j} <= S_{i+1,j+1}
                    lo, hi = np.maximum(lo, S[r + 1, j]), np.minimum(hi, S[r + 1, j + 1])
                S[r, j] = lo + (hi - lo) * rng.random(r) ** bias
        for r in range(N):
            out[t, r, : r + 1] = np.diff(S[r, : r + 2])
    return out
