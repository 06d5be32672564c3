"""What is overwhelming without a distribution: Chebyshev's bound on an estimated error, Bonferroni over the values.

The t route (:mod:`forcenet.numeric.size_rule`) refuses rows too skewed for
Student's tail at the stated level; a grossly wrong sampler makes its own
rows skewed, so without this module the verdict weakened as the bias grew
(issue 53: ``z = -180`` was "cannot judge", a bias ten times milder
DISAGREES). Where the size rule cannot certify the level, this bound still
decides, with no assumption on the distribution of the mean:

* **Chebyshev.** ``P(|mean - exact| >= k sigma) <= 1 / k^2`` for any
  distribution with variance ``sigma^2`` (``sigma`` the error of the mean:
  ``s / sqrt(K)`` for independent rows, ``sqrt(var tau / n)`` for a chain,
  the autocorrelation-corrected error of :func:`forcenet.numeric.autocorr.mean_and_stderr`).
* **The variance is estimated.** ``sigma^2`` is replaced by an upper
  confidence bound, ``est nu / chi2_nu(delta)``, the chi-square lower
  quantile with the estimate's equivalent degrees of freedom ``nu``:
  ``2 (K - 1) / (kurtosis - 1)`` for ``K`` rows (``K - 1`` for normal rows),
  ``n / (2 M + 1)`` for a chain's window ``M ~ 5 tau`` (Sokal 1997, Eq.
  (3.19): the variance of the windowed estimate is ``2 (2 M + 1) / n`` of its
  square). The lower tail of a sum of nonnegative terms is lighter than the
  normal one (Maurer 2003), and the chi-square's lighter still than the normal
  quantile's ``1 - z sqrt(2 / nu)``.
* **The level.** Per value, ``1 / k^2 + delta <= alpha / G``: ``delta =
  alpha / (10 G)``, ``k = sqrt(G / (0.9 alpha))`` (149 at ``G = 20``,
  ``alpha = 1e-3``). The Bonferroni p-value reported is
  ``min(1, G / z_max^2 + alpha / 10)`` with ``z = |mean - exact| / sigma_up``.
* **A chain with bounds** (every step of a value in ``[lo, hi]``): Markov's
  inequality on the fourth moment of the mean of its ``B`` spaced batches
  instead (:func:`chebyshev_pvalue`'s ``reach`` and ``blocks``), the fourth
  moment bounded by the range: decisive from ``z ~ 30-60`` for the
  triangle's ``W`` at N = 6. Which bound runs is fixed by the bounds being
  given, before the data are seen.

Only overwhelming deviations pass (``z`` above ~150 for a table of 20 values
at ``1e-3``): the price of assuming nothing. Measured in
``notes/testing_against_exact.md``.

Examples
--------
>>> p, z, infl = chebyshev_pvalue(np.array([0.5, 0.001]), np.array([0.002, 0.001]), np.array([300.0, 300.0]), 1e-3)
>>> bool(p < 1e-3), round(float(z), 1), bool(1.0 < infl < 1.5)
(True, 211.1, True)
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["VARIANCE_SHARE", "chebyshev_pvalue", "chain_dof", "rows_dof", "threshold"]

VARIANCE_SHARE = 0.1  # of the level: the variance's upper confidence bound; the rest is Chebyshev's


def threshold(alpha: float, values: int) -> float:
    """``k = sqrt(G / ((1 - VARIANCE_SHARE) alpha))``: the ``z`` the bound needs over ``G`` values.

    Examples
    --------
    >>> round(threshold(1e-3, 20))
    149
    """
    return math.sqrt(values / ((1 - VARIANCE_SHARE) * alpha))


def rows_dof(rows: np.ndarray) -> np.ndarray:
    """Equivalent degrees of freedom of each column's sample variance: ``2 (K - 1) / (kurtosis - 1)``.

    The sample kurtosis (fourth standardized moment) is floored at 3, the
    normal value, so no column is trusted more than normal rows would be.

    Examples
    --------
    >>> rows_dof(np.random.default_rng(0).normal(size=(200, 1))).round().tolist()
    [199.0]
    """
    K = rows.shape[0]
    centred = rows - rows.mean(axis=0)
    m2 = (centred**2).mean(axis=0)
    with np.errstate(divide="ignore", invalid="ignore"):
        kurtosis = np.where(m2 > 0, (centred**4).mean(axis=0) / np.where(m2 > 0, m2, 1.0) ** 2, 3.0)
    return np.asarray(2.0 * (K - 1) / (np.maximum(kurtosis, 3.0) - 1.0), dtype=float)


def chain_dof(steps: int, tau: np.ndarray, c: float = 5.0) -> np.ndarray:
    """Equivalent degrees of freedom of a chain's windowed error: ``n / (2 M + 1)``, ``M = c tau`` (Sokal 1997).

    Examples
    --------
    >>> chain_dof(20000, np.array([10.0])).round(1).tolist()
    [198.0]
    """
    return np.asarray(steps / (2.0 * c * np.asarray(tau, dtype=float) + 1.0), dtype=float)


def chebyshev_pvalue(dev: np.ndarray, stderr: np.ndarray, dof: np.ndarray, alpha: float,
                     reach: np.ndarray | None = None, blocks: int | None = None) -> tuple[float, float, float]:
    """``(p, z_max, inflation)``: the distribution-free Bonferroni p-value of the deviations ``dev``.

    With ``reach`` (each value's largest distance from its exact mean within its bounds, ``max(exact - lo,
    hi - exact)``) and ``blocks`` (the chain's ``B`` spaced batches, independent as the t route takes them), the
    fourth moment replaces the second (Markov's inequality on ``(mean - exact)^4``): the mean of ``B``
    independent blocks of variance ``v_B = B sigma^2`` within the bounds has
    ``E (mean - exact)^4 = (E (Y - exact)^4 + 3 (B - 1) v_B^2) / B^3 <= (reach^2 v_B + 3 (B - 1) v_B^2) / B^3``
    (``(Y - exact)^4 <= reach^2 (Y - exact)^2``), increasing in ``sigma``, so its upper bound serves as for
    Chebyshev; it decides from ``z ~ 30-60`` where Chebyshev needs ~150.

    Parameters
    ----------
    dev : array
        ``mean - exact`` per value.
    stderr : array
        The estimated error of each mean.
    dof : array
        Equivalent degrees of freedom of each ``stderr**2`` (:func:`rows_dof`, :func:`chain_dof`).
    alpha : float
        The level the p-value is compared with (it fixes the variance's share, ``alpha / 10``).

    Returns
    -------
    p : float
        ``min(1, G / z_max^2 + alpha / 10)``; at most ``alpha`` exactly when ``z_max >= threshold(alpha, G)``.
    z_max : float
        The largest ``|dev| / sigma_up`` (``sigma_up``: the error's upper confidence bound).
    inflation : float
        ``sigma_up / stderr`` of that value.
    """
    from scipy.stats import chi2  # scipy.stats is heavy: loaded when a verdict needs it

    G = int(np.size(dev))
    if G == 0:
        return 1.0, 0.0, 1.0
    dof = np.maximum(np.asarray(dof, dtype=float), 1.0)
    inflation = np.sqrt(dof / chi2.ppf(VARIANCE_SHARE * alpha / G, dof))  # sigma^2 <= est nu / chi2_nu(delta)
    with np.errstate(divide="ignore", invalid="ignore"):
        z = np.where(stderr > 0, np.abs(dev) / (stderr * inflation), np.where(dev == 0, 0.0, np.inf))
        if reach is not None and blocks is not None:  # Markov on the fourth moment (the docstring)
            v = blocks * (stderr * inflation) ** 2  # a block's variance, bounded above
            tail = (np.asarray(reach) ** 2 * v + 3 * (blocks - 1) * v**2) / (blocks**3 * np.abs(dev) ** 4)
        else:  # Chebyshev
            tail = 1.0 / z**2
    worst = int(np.argmax(z))
    z_max = float(z[worst])
    p = 1.0 if z_max == 0 else min(1.0, G * float(np.nanmin(tail)) + VARIANCE_SHARE * alpha)
    return p, z_max, float(inflation[worst])
