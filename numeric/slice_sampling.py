"""The batched log-product and the slice sampler shared by the triangle's and the packing's compiled kernels.

Both models weigh a force network by ``prod W`` over the grains that carry a
q (Eq. 3.10).  A move changes the loads ``W`` only in the light cone of the
grain, so the kernels need ``log prod W_new / prod W_old`` over that cone, and
the slice move needs ``log prod (1 + t r_c)`` (the weight at ``q_old + t``
relative to ``q_old``: every load of the cone is affine in one q).  Both are
sums of logs of many factors near 1; :func:`log_push` multiplies up to 8
factors before taking one log (and earlier when the product leaves
``(1e-150, 1e150)``), which is what both kernels did before this module
existed, so the chains are bit for bit the ones they were.

:func:`slice_shrink` is slice sampling with shrinkage (Neal 2003, Ann.
Statist. 31, 705) of ``t`` on an interval that contains 0 for the
log-concave density ``prod_c (1 + t r_c)``.

Examples
--------
>>> import math
>>> total, ratio, count = 0.0, 1.0, 0
>>> for x in (2.0, 0.5, 4.0):
...     total, ratio, count = log_push(total, ratio, count, x)
>>> round(total + math.log(ratio), 12) == round(math.log(4.0), 12)
True
"""

from __future__ import annotations

import math

import numpy as np

from .jit import njit

__all__ = ["log_push", "log_product", "slice_shrink", "GIVE_UP"]

GIVE_UP = 200  # shrinkage steps before a move gives up and stays (never observed)


@njit
def log_push(total: float, ratio: float, count: int, x: float) -> tuple[float, float, int]:
    """Multiply ``x`` into a batched log-product: the sum of logs is ``total + log(ratio)`` throughout.

    Parameters
    ----------
    total : float
        The logs taken so far.
    ratio : float
        The product of the factors not yet logged.
    count : int
        How many factors ``ratio`` holds (one log per 8 factors).
    x : float
        The next factor, ``> 0``.

    Returns
    -------
    tuple of (float, float, int)
        The new ``(total, ratio, count)``.

    Examples
    --------
    >>> log_push(0.0, 1.0, 0, 3.0)
    (0.0, 3.0, 1)
    >>> log_push(0.0, 2.0, 7, 1.0)[1:]
    (1.0, 0)
    """
    ratio *= x
    count += 1
    if count == 8 or not (1e-150 < ratio < 1e150):
        return total + math.log(ratio), 1.0, 0
    return total, ratio, count


@njit
def log_product(t: float, r: np.ndarray, m: int) -> float:
    """``sum_c log(1 + t r_c)`` over ``r[:m]``: the log-weight at ``q_old + t`` relative to ``q_old``.

    Parameters
    ----------
    t : float
        The change of q.
    r : numpy.ndarray
        The relative slopes ``(dW/dq) / W`` of the cone's loads (float64, at least ``m`` entries).
    m : int
        How many entries of ``r`` to use.

    Returns
    -------
    float
        The log of the product, ``-inf`` if a factor is ``<= 0`` (outside the density's support).

    Examples
    --------
    >>> import numpy as np
    >>> bool(abs(log_product(0.5, np.array([1.0, -1.0]), 2) - math.log(0.75)) < 1e-15)
    True
    >>> log_product(2.0, np.array([-1.0]), 1)
    -inf
    """
    total, ratio, count = 0.0, 1.0, 0
    for c in range(m):
        x = 1.0 + t * r[c]
        if x <= 0.0:
            return -np.inf
        total, ratio, count = log_push(total, ratio, count, x)
    return total + math.log(ratio)


@njit
def slice_shrink(rng: np.random.Generator, lo: float, hi: float, r: np.ndarray, m: int,
                 counters: np.ndarray) -> float:
    """One slice-sampling update of ``t`` from 0 on ``[lo, hi]`` (containing 0) for the density ``prod (1 + t r_c)``.

    Draws a level ``log u`` (``u`` uniform under the density at ``t = 0``, where
    it is 1) as ``-Exp(1)``, then points uniform in the interval, shrinking it
    toward 0 past each point below the level (Neal 2003, Fig. 5); the first
    point above the level is the new ``t``.  Random numbers: one exponential,
    then one uniform per point.

    Parameters
    ----------
    rng : numpy.random.Generator
        The chain's generator.
    lo, hi : float
        The interval of allowed ``t``, ``lo <= 0 <= hi``.
    r : numpy.ndarray
        The relative slopes of the weight's factors (see :func:`log_product`).
    m : int
        How many entries of ``r`` to use.
    counters : numpy.ndarray
        The kernel's int64 counters: ``counters[3]`` counts density evaluations,
        ``counters[4]`` moves that gave up after :data:`GIVE_UP` shrinkages.

    Returns
    -------
    float
        The new ``t``; 0.0 (stay) if the move gave up.

    Examples
    --------
    >>> import numpy as np
    >>> counters = np.zeros(5, np.int64)
    >>> t = slice_shrink(np.random.default_rng(1), -0.5, 0.5, np.array([1.0, -1.0]), 2, counters)
    >>> bool(-0.5 <= t <= 0.5), bool(counters[3] >= 1), int(counters[4])
    (True, True, 0)
    """
    y = -rng.standard_exponential()
    left, right = lo, hi
    for _ in range(GIVE_UP):
        t = left + rng.random() * (right - left)
        counters[3] += 1
        if log_product(t, r, m) > y:
            return t
        if t < 0.0:
            left = t
        else:
            right = t
    counters[4] += 1
    return 0.0
