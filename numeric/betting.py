"""Means of bounded variables tested by betting: a level that holds at every sample size.

For rows ``x_1..x_K`` known to lie in ``[lo, hi]`` and a claimed mean ``m``
strictly inside, the two capital processes (Waudby-Smith and Ramdas,
"Estimating means of bounded random variables by betting", JRSS B 86 (2024) 1;
the hedged capital of their Sec. 4)

    K+_t = prod_{s <= t} (1 + l+_s (x_s - m)),    K-_t = prod_{s <= t} (1 - l-_s (x_s - m))

with bets ``l+-_s`` chosen from ``x_1..x_{s-1}`` only, are nonnegative
martingales when ``m`` is the true mean of independent rows. Their average
``e_t = (K+_t + K-_t) / 2`` is one too, so by Ville's inequality
``P(max_t e_t >= 1/p) <= p`` for every ``p``: ``p = min(1, 1 / max_t e_t)``
is a valid p-value whatever the distribution in ``[lo, hi]`` and whatever
``K`` (no normal approximation, no skewness correction, nothing asymptotic).

The bets (in units where ``[lo, hi] = [0, 1]``): ``l_s = sqrt(2 log(2/level)
/ (K v_s))``, the size that detects the smallest shift at the final row
``K`` for a variance ``v`` (the predictable plug-in of Waudby-Smith and
Ramdas, tuned to the fixed ``K``), with ``v_s`` the running variance about
the running mean, started from the largest variance a mean ``m`` allows,
``m (1 - m)`` (Bhatia-Davis), at weight ``prior``; truncated at
``c / m`` and ``c / (1 - m)`` so that no factor falls below ``1 - c``.
``c = 0.9`` and ``prior = 0.1`` were the most powerful of the variants
measured (``notes/testing_against_exact.md``).

Examples
--------
>>> rng = np.random.default_rng(0)
>>> x = rng.beta(2, 5, size=(300, 2))                    # means 2/7 each
>>> p = betting_pvalues(x, np.array([2 / 7, 0.35]), 0.0, 1.0, level=1e-3)
>>> bool(p[0] > 0.1), bool(p[1] < 1e-3)
(True, True)
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np
from numpy.typing import ArrayLike

__all__ = ["betting_pvalues", "blind_values", "cached_rows_needed", "extreme_pvalues", "rows_needed"]

_C = 0.9  # largest fraction of the capital at stake in one row
_PRIOR = 0.1  # weight, in rows, of the starting variance m (1 - m)
_CHUNK = 1 << 21  # elements of (rows x columns) per block: bounds the memory of a whole table


def _log_evidence(u: np.ndarray, m: np.ndarray, K: int, level: float) -> np.ndarray:
    """``max_t log e_t`` for rows ``u`` in ``[0, 1]`` (shape (K, g)) against means ``m`` in ``(0, 1)``."""
    g = u.shape[1]
    t = np.arange(1, K + 1, dtype=float)[:, None]
    before = np.cumsum(u, axis=0) - u  # sum of the rows before t
    mean = (m + before) / t  # running mean, the claimed mean as one pseudo-row: uses rows < t only
    square = np.cumsum((u - mean) ** 2, axis=0)
    square -= (u - mean) ** 2
    var = (_PRIOR * m * (1 - m) + square) / (t - 1 + _PRIOR)
    bet = np.sqrt(2.0 * math.log(2.0 / level) / (K * var))
    d = u - m
    up = np.cumsum(np.log1p(np.minimum(bet, _C / m) * d), axis=0)
    down = np.cumsum(np.log1p(-np.minimum(bet, _C / (1 - m)) * d), axis=0)
    log_e = np.logaddexp(up, down) - math.log(2.0)
    return log_e.max(axis=0) if g else np.zeros(0)


def betting_pvalues(x: ArrayLike, mean: ArrayLike, lo: ArrayLike, hi: ArrayLike, level: float) -> np.ndarray:
    """Per column, the betting p-value of ``H0: E x = mean`` for independent rows in ``[lo, hi]``.

    Parameters
    ----------
    x : array (K, G)
        Independent rows, every entry in ``[lo, hi]`` (checked by the caller).
    mean : array (G,)
        Claimed means, strictly inside ``(lo, hi)``.
    lo, hi : float or array (G,)
        The range of each column.
    level : float
        The level the bets are sized for (the Bonferroni share of one column);
        the p-values are valid whatever it is, the power is best near it.

    Returns
    -------
    array (G,)
        ``min(1, 1 / max_t e_t)``: ``P(p <= u) <= u`` for every ``u`` under ``H0``.

    Examples
    --------
    >>> x = np.random.default_rng(1).uniform(size=(200, 1))
    >>> bool(betting_pvalues(x, np.array([0.5]), 0, 1, 0.01)[0] > 0.01)
    True
    """
    x = np.asarray(x, dtype=float)
    K, G = x.shape
    width = np.broadcast_to(np.asarray(hi, dtype=float) - np.asarray(lo, dtype=float), (G,))
    low = np.broadcast_to(np.asarray(lo, dtype=float), (G,))
    m = (np.asarray(mean, dtype=float) - low) / width
    out = np.empty(G)
    step = max(1, _CHUNK // max(K, 1))
    for a in range(0, G, step):
        u = np.clip((x[:, a:a + step] - low[a:a + step]) / width[a:a + step], 0.0, 1.0)
        out[a:a + step] = _log_evidence(u, m[a:a + step], K, level)
    return np.minimum(1.0, np.exp(-out))


def extreme_pvalues(K: int, mean: ArrayLike, lo: ArrayLike, hi: ArrayLike, level: float) -> np.ndarray:
    """The smallest p-value ``K`` rows can give a column: every row at one end of its range.

    When it exceeds ``level`` no sample of ``K`` rows can reveal a wrong mean
    of that column: the test cannot judge it.

    Examples
    --------
    >>> extreme_pvalues(2, np.array([0.3]), 0, 1, 1e-3).round(3).tolist()
    [0.208]
    """
    m = np.asarray(mean, dtype=float)
    G = m.size
    ends = [np.broadcast_to(np.asarray(end, dtype=float), (G,)) for end in (lo, hi)]
    return np.minimum(*[betting_pvalues(np.broadcast_to(end, (K, G)), m, lo, hi, level) for end in ends])


def rows_needed(mean: ArrayLike, lo: ArrayLike, hi: ArrayLike, level: float, limit: int = 1 << 20) -> int:
    """The fewest rows ``K`` for which some sample could fail every column at ``level`` (``limit`` if none).

    Examples
    --------
    >>> rows_needed(np.array([0.3, 0.5]), 0, 1, 1e-3)
    12
    """
    def enough(K: int) -> bool:
        return bool((extreme_pvalues(K, mean, lo, hi, level) <= level).all())

    low, high = 1, 2
    while not enough(high):
        if high >= limit:
            return limit
        low, high = high, min(2 * high, limit)
    while high - low > 1:
        mid = (low + high) // 2
        low, high = (low, mid) if enough(mid) else (mid, high)
    return high


@lru_cache(maxsize=64)
def blind_values(K: int, mean: tuple[float, ...], lo: tuple[float, ...], hi: tuple[float, ...],
                 level: float) -> np.ndarray:
    """The values no sample of ``K`` rows could fail at ``level`` (cached: tests and benchmarks repeat one table).

    Examples
    --------
    >>> blind_values(3, (0.5,), (0.0,), (1.0,), 1e-3).tolist()
    [True]
    """
    return extreme_pvalues(K, np.array(mean), np.array(lo), np.array(hi), level) > level


@lru_cache(maxsize=64)
def cached_rows_needed(mean: tuple[float, ...], lo: tuple[float, ...], hi: tuple[float, ...], level: float) -> int:
    """:func:`rows_needed` of tuples, cached.

    Examples
    --------
    >>> cached_rows_needed((0.5,), (0.0,), (1.0,), 1e-3) == rows_needed(np.array([0.5]), 0.0, 1.0, 1e-3)
    True
    """
    return rows_needed(np.array(mean), np.array(lo), np.array(hi), level)
