"""The t route's statistics (Bonferroni maximum, Hotelling) and its size rule: where Student's t keeps its level.

For ``n`` independent rows of skewness ``gamma`` the two tails of Student's
``t`` at ``s`` (on the scale of the self-normalized sum,
``s = t sqrt(n / (n - 1 + t^2))``) sum to the normal-theory tail times
``cosh(u)``, ``u = s^3 gamma / (3 sqrt n)``, to first order: Wang (Electron.
J. Probab. 10 (2005) 1260), for ``E X^4`` finite and ``s = O(n^(1/6))``,
``P(S_n / V_n >= s) = (1 - Phi(s)) exp(-s^3 E X^3 / (3 sqrt(n) sigma^3))
(1 + O((1 + s) / sqrt n))``; the ``n^(-1/2)`` Edgeworth terms of the two
tails cancel, so ``cosh(u) - 1 ~ u^2 / 2`` is what is left of the skewness.
The route judges (:mod:`forcenet.numeric.agreement`) only where ``u <= U_MAX``
at the critical value of its most skewed value, and charges its Bonferroni
p-value with ``cosh(u)`` (at most ``cosh(1) = 1.54``): a conservative rule,
measured in ``notes/testing_against_exact.md``.

Examples
--------
>>> rows = np.random.default_rng(0).exponential(size=(200, 2))   # skewness 2
>>> judged, u, factor, worst = size_rule(charged_skewness(rows), 200, 1e-3, 2)
>>> judged, bool(u > 1)
(False, True)
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np
from scipy.special import stdtr, stdtrit

__all__ = ["U_MAX", "bonferroni", "charged_skewness", "hotelling", "size_rule", "skew_term", "skewness", "t_rows_needed"]

# the skewness term u may reach U_MAX at the critical value; the level is charged cosh(u) <= cosh(U_MAX)
U_MAX = 1.0
# independent rows: Wang's relative error (1 + s)/sqrt(n) at most EPS, whatever the sample's skewness (a floor that
# does not depend on the rows: the tables judged just above a data-dependent threshold are a biased selection)
EPS = 0.25
_SKEW_RULE = True  # False: the t route without its size rule (benchmarks/false_alarm_rates.py, the rows "t, old")


def skewness(rows: np.ndarray) -> np.ndarray:
    """Sample skewness ``m3 / m2^(3/2)`` of each column of ``(n, G)`` (0 for a constant column).

    Examples
    --------
    >>> skewness(np.array([[0.0, 1.0], [0.0, 2.0], [3.0, 3.0]])).round(3).tolist()
    [0.707, 0.0]
    """
    centred = rows - rows.mean(axis=0)
    m2 = (centred**2).mean(axis=0)
    m3 = (centred**3).mean(axis=0)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(m2 > 0, m3 / np.where(m2 > 0, m2, 1.0) ** 1.5, 0.0)


def skew_term(gamma: float, n: int, level: float, values: int) -> float:
    """``u = s^3 gamma / (3 sqrt n)`` at the critical value of the Bonferroni maximum (the t route's size rule).

    ``s = x sqrt(n / (n - 1 + x^2))`` is the self-normalized sum ``S_n / V_n`` at
    the Student ``t`` critical value ``x`` of one value's two-sided share
    ``level / (values cosh(U_MAX))`` with ``n - 1`` degrees of freedom. Wang
    (Electron. J. Probab. 10 (2005) 1260), for ``E X^4`` finite:
    ``P(S_n/V_n >= s) = (1 - Phi(s)) exp(-s^3 E X^3 / (3 sqrt(n) sigma^3)) (1 + O((1 + s)/sqrt n))``,
    so the two tails of ``|t|`` sum to the normal-theory tail times
    ``cosh(u)`` (to first order). The route judges while ``u <= U_MAX``
    and shrinks its level by ``cosh(u)``.

    Examples
    --------
    >>> round(skew_term(1.7, 2500, 5e-4, 20), 2)   # the most skewed W of N = 6: judged from about 2300 rows
    0.9
    >>> skew_term(0.0, 50, 1e-3, 1)
    0.0
    """
    return _cubed(n, level, values) * abs(gamma) / (3 * math.sqrt(n))


@lru_cache(maxsize=4096)
def _cubed(n: int, level: float, values: int) -> float:
    """``s^3`` at the critical value (cached: the rule and its reason ask it often)."""

    x = -float(stdtrit(n - 1, level / (2 * values * math.cosh(U_MAX))))  # Student t's upper quantile
    return (x * math.sqrt(n / (n - 1 + x * x))) ** 3


def size_rule(gamma: np.ndarray | None, n: int, level: float, G: int,
              floor: bool = False) -> tuple[bool, float | None, float, int | None]:
    """``(judged, u, factor, worst)``: the rule on the t statistics of ``n`` rows, ``G`` values of skewness ``gamma``.

    ``u`` at the critical value of the most skewed value ``worst``, ``factor = cosh(min(u, U_MAX))``;
    ``floor`` (independent rows): besides, ``(1 + s) / sqrt(n) <= EPS``.

    Examples
    --------
    >>> size_rule(np.array([0.1, 0.2]), 1000, 1e-3, 2)[0]
    True
    """
    if gamma is None or not _SKEW_RULE or G == 0:
        return True, None, 1.0, None
    worst = int(np.argmax(gamma))
    u = skew_term(float(gamma[worst]), n, level, G)
    judged = u <= U_MAX and (not floor or n >= floor_rows(level, G, n))
    return judged, u, math.cosh(min(u, U_MAX)), worst


def floor_rows(level: float, values: int, n: int) -> float:
    """``((1 + s) / EPS)^2``, ``s`` at the critical value for ``n`` rows: the fewest rows Wang's error term allows.

    Examples
    --------
    >>> round(floor_rows(1e-3, 1, 500))
    309
    """
    return ((1 + _cubed(n, level, values) ** (1 / 3)) / EPS) ** 2


def charged_skewness(rows: np.ndarray) -> np.ndarray:
    """The skewness the size rule charges independent rows with: ``|g1| + 2 se(g1)``.

    ``se(g1)`` from the empirical influence function of ``g1`` on the
    standardized rows, ``x^3 - g1 - 3 x - (3/2) g1 (x^2 - 1)`` (its mean
    square over ``K``; 6/K for normal rows), and never below ``sqrt(6/K)``:
    the rows that happen to look symmetric (a skewed sample that lacks its
    large values, the samples whose t strays) are not trusted more.

    Examples
    --------
    >>> charged_skewness(np.zeros((6, 1)) + np.arange(6)[:, None]).round(2).tolist()
    [2.0]
    """
    K = rows.shape[0]
    g1 = skewness(rows)
    centred = rows - rows.mean(axis=0)
    sd = np.sqrt((centred**2).mean(axis=0))
    with np.errstate(divide="ignore", invalid="ignore"):
        x = np.where(sd > 0, centred / np.where(sd > 0, sd, 1.0), 0.0)
    influence = x**3 - g1 - 3 * x - 1.5 * g1 * (x**2 - 1)
    se = np.maximum(np.sqrt((influence**2).mean(axis=0) / K), math.sqrt(6.0 / K))
    return np.abs(g1) + 2.0 * se


def t_rows_needed(gamma: float, level: float, values: int, limit: int = 1 << 30) -> int:
    """About the fewest independent rows the t route judges a value of skewness ``gamma`` at.

    Charged ``+ 2 sqrt(6/K)`` (the rows' own influence-function error may ask more), and the floor.

    Examples
    --------
    >>> t_rows_needed(0.0, 1e-3, 1), t_rows_needed(1.7, 5e-4, 20)
    (308, 2296)
    """
    return _t_rows_needed(math.ceil(abs(gamma) * 20) / 20, level, values, limit)  # up to a step of 0.05: cached


@lru_cache(maxsize=1024)
def _t_rows_needed(gamma: float, level: float, values: int, limit: int) -> int:
    def judged(n: int) -> bool:
        charged = abs(gamma) + 2.0 * math.sqrt(6.0 / n)
        return skew_term(charged, n, level, values) <= U_MAX and n >= floor_rows(level, values, n)

    low, high = 2, 4
    while not judged(high):
        if high >= limit:
            return limit
        low, high = high, min(2 * high, limit)
    while high - low > 1:
        mid = (low + high) // 2
        low, high = (low, mid) if judged(mid) else (mid, high)
    return high


def bonferroni(max_z: float, values: int, df: int | None) -> float:
    """``min(1, values P(|T| >= max_z))``: Student t with ``df`` degrees of freedom (``None``: normal).

    Examples
    --------
    >>> round(bonferroni(3.0, 5, None), 4)
    0.0135
    """
    if values == 0:
        return 1.0
    if df is None:
        tail = math.erfc(max_z / math.sqrt(2))  # 2 (1 - Phi(|z|))
    else:
        tail = 2.0 * float(stdtr(df, -max_z))  # Student t's two tails
    return min(1.0, values * tail)


def hotelling(rows: np.ndarray, dev: np.ndarray) -> tuple[float, int, float] | None:
    """``(chi2, rank, p)`` of Hotelling's test on the nondegenerate subspace, or None when the rows are too few.

    Examples
    --------
    >>> rows = np.random.default_rng(0).normal(size=(100, 3))
    >>> hotelling(rows, rows.mean(axis=0))[1]
    3
    """
    from scipy.stats import f as f_dist  # scipy.stats is heavy: loaded when a verdict needs it

    K, G = rows.shape
    if G < 2:
        return None
    S = np.cov(rows, rowvar=False, ddof=1).reshape(G, G)
    w, V = np.linalg.eigh(S)
    keep = w > max(w.max(), 0.0) * 1e-10
    r = int(keep.sum())
    if r < 2 or K < max(5 * r, r + 10):
        return None
    proj = V[:, keep].T @ dev
    chi2 = float(K * np.sum(proj**2 / w[keep]))
    p = float(f_dist.sf(chi2 * (K - r) / (r * (K - 1)), r, K - r))
    return chi2, r, p
