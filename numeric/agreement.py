"""Does a table of sampled means agree with its exact values?  Tests with a stated false-alarm rate.

Two statistics for a whole table of ``G`` values estimated from ``K``
independent samples, both with a p-value that is valid for the number of
values tested (no "4-sigma surprise" from taking a maximum over 60 grains):

* Hotelling's ``T^2 = K d' S^{-1} d`` with ``d`` the deviations of the sample
  means and ``S`` the sample covariance: ``(K-G)/(G(K-1)) T^2 ~ F(G, K-G)``
  for a correct sampler (normal approximation of the means);
* the largest ``|z|`` with its Bonferroni p-value ``min(1, 2 G (1 - Phi(|z|)))``,
  conservative whatever the correlations.

The table passes at level ``alpha`` when both p-values exceed ``alpha``; a
correct sampler then fails with probability at most about ``2 alpha``.

May import: numpy, scipy.

Examples
--------
>>> rng = np.random.default_rng(0)
>>> samples = rng.normal(size=(4000, 5)) + np.arange(5)
>>> result = compare_samples(samples, np.arange(5))
>>> result.passed, result.dof
(True, 5)
>>> compare_samples(samples, np.arange(5) + 0.1).passed  # a bias of 0.1 = 6 standard errors
False
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["TableAgreement", "compare_samples", "compare_means"]


@dataclass(frozen=True)
class TableAgreement:
    """The outcome of a whole-table comparison (see the module docstring)."""

    values: int
    samples: int
    max_z: float
    worst: object
    p_max: float
    chi2: float
    dof: int
    p_chi2: float
    rms_z: float
    alpha: float
    z_scores: tuple = ()

    @property
    def passed(self) -> bool:
        return self.p_max > self.alpha and self.p_chi2 > self.alpha

    def summary(self) -> str:
        """Two lines for a report."""
        verdict = "agrees" if self.passed else "DISAGREES"
        return (
            f"Hotelling chi2 = {self.chi2:.1f} on {self.dof} degrees of freedom (p = {self.p_chi2:.3g}); "
            f"max |z| = {self.max_z:.2f} at {self.worst} (Bonferroni p = {self.p_max:.3g} over {self.values} values)\n"
            f"{verdict} at level {self.alpha:g} (a correct sampler fails at most ~{2 * self.alpha:g} of the time)"
        )

    def worst_values(self, k: int = 3):
        """The ``k`` largest ``(|z|, key)``."""
        return sorted(self.z_scores, key=lambda t: -abs(t[0]))[:k]


def _bonferroni(max_z: float, values: int) -> float:
    tail = math.erfc(max_z / math.sqrt(2))  # 2 (1 - Phi(|z|))
    return min(1.0, values * tail)


def compare_samples(samples, exact, keys=None, alpha: float = 1e-3) -> TableAgreement:
    """Compare independent samples ``(K, G)`` of ``G`` quantities with their exact means ``(G,)``.

    Parameters
    ----------
    samples : array_like, shape (K, G)
        One row per independent sample (use batch means for a Markov chain).
    exact : array_like, shape (G,)
        The exact expectations (converted to float here, at the edge).
    keys : sequence, optional
        Names of the ``G`` quantities (e.g. grains), for the report.
    alpha : float
        Level of each of the two tests.
    """
    from scipy.stats import f as f_dist

    x = np.asarray(samples, dtype=float)
    mu = np.asarray([float(v) for v in exact])
    K, G = x.shape
    if K < G + 2:
        raise ValueError(f"samples: {K} samples of {G} values; need at least G + 2 = {G + 2} for the covariance")
    keys = list(keys) if keys is not None else list(range(G))
    mean = x.mean(axis=0)
    dev = mean - mu
    S = np.cov(x, rowvar=False, ddof=1).reshape(G, G)
    stderr = np.sqrt(np.maximum(np.diag(S), 0) / K)
    z = np.divide(dev, stderr, out=np.zeros(G), where=stderr > 0)
    # Hotelling on the nondegenerate subspace (constraints such as row sums make S singular)
    w, V = np.linalg.eigh(S)
    keep = w > w.max() * 1e-10
    dof = int(keep.sum())
    proj = V[:, keep].T @ dev
    chi2 = float(K * np.sum(proj**2 / w[keep]))
    if K - dof > 0:
        p_chi2 = float(f_dist.sf(chi2 * (K - dof) / (dof * (K - 1)), dof, K - dof))
    else:  # pragma: no cover - excluded by the check above
        p_chi2 = float("nan")
    k = int(np.argmax(np.abs(z)))
    max_z = float(abs(z[k]))
    return TableAgreement(
        values=G, samples=K, max_z=max_z, worst=keys[k], p_max=_bonferroni(max_z, G),
        chi2=chi2, dof=dof, p_chi2=p_chi2, rms_z=float(np.sqrt(np.mean(z**2))), alpha=alpha,
        z_scores=tuple((float(zz), key) for zz, key in zip(z, keys)),
    )


def compare_means(mean, stderr, exact, keys=None, alpha: float = 1e-3) -> TableAgreement:
    """Max-|z| test only, from means and standard errors (e.g. from autocorrelation times).

    The chi-square needs the covariance and is reported as not computed
    (``dof = 0``, ``p_chi2 = 1``).

    Examples
    --------
    >>> compare_means([1.0, 2.02], [0.01, 0.01], [1, 2]).max_z
    2.0000000000000018
    """
    mean = np.asarray(mean, dtype=float).ravel()
    stderr = np.asarray(stderr, dtype=float).ravel()
    mu = np.asarray([float(v) for v in np.ravel(exact)])
    G = mean.size
    keys = list(keys) if keys is not None else list(range(G))
    z = np.divide(mean - mu, stderr, out=np.zeros(G), where=stderr > 0)
    k = int(np.argmax(np.abs(z)))
    max_z = float(abs(z[k]))
    return TableAgreement(
        values=G, samples=0, max_z=max_z, worst=keys[k], p_max=_bonferroni(max_z, G), chi2=0.0, dof=0,
        p_chi2=1.0, rms_z=float(np.sqrt(np.mean(z**2))), alpha=alpha,
        z_scores=tuple((float(zz), key) for zz, key in zip(z, keys)),
    )
