"""Integrated autocorrelation times and honest error bars for Markov chains.

Follows the estimator used by emcee (Goodman & Weare 2010; Sokal 1997):
the normalised autocorrelation function from an FFT, summed up to the first
window ``M >= c * tau(M)``.  Like emcee's ``integrated_time``, it *raises*
when the chain is shorter than ``tol * tau``: an error bar from a chain too
short to trust is not returned.

Examples
--------
>>> import numpy as np
>>> rng = np.random.default_rng(0)
>>> x = np.zeros(20000)
>>> for t in range(1, x.size):  # AR(1) with tau = (1 + 0.9) / (1 - 0.9) = 19
...     x[t] = 0.9 * x[t - 1] + rng.normal()
>>> tau = integrated_time(x)
>>> bool(15 < tau[0] < 23)
True
"""

from __future__ import annotations

import numpy as np

__all__ = ["AutocorrError", "autocorr_function", "integrated_time", "mean_and_stderr"]


class AutocorrError(Exception):
    """The chain is too short to estimate its autocorrelation time reliably."""

    def __init__(self, message, tau):
        super().__init__(message)
        self.tau = tau


def autocorr_function(x: np.ndarray) -> np.ndarray:
    """Normalised autocorrelation function along axis 0 (columns independent)."""
    x = np.asarray(x, dtype=float)
    if x.ndim == 1:
        x = x[:, None]
    n = x.shape[0]
    size = 1 << (2 * n - 1).bit_length()
    centred = x - x.mean(axis=0)
    f = np.fft.rfft(centred, n=size, axis=0)
    acf = np.fft.irfft(f * np.conj(f), axis=0)[:n]
    var = acf[0].copy()
    constant = var <= 0
    var[constant] = 1.0
    acf /= var
    acf[:, constant] = 0.0
    acf[0, constant] = 1.0
    return acf


def integrated_time(x: np.ndarray, c: float = 5.0, tol: float = 50.0, quiet: bool = False) -> np.ndarray:
    """Integrated autocorrelation time of each column of ``x`` (chain along axis 0).

    Parameters
    ----------
    x : array, shape (n,) or (n, k)
    c : float
        Window constant: the sum stops at the first ``M >= c * tau(M)``.
    tol : float
        The chain must be longer than ``tol * tau`` for every column.
    quiet : bool
        Return the (untrustworthy) estimate with a warning instead of raising.

    Raises
    ------
    AutocorrError
        If ``n < tol * tau`` for some column.
    """
    x = np.asarray(x, dtype=float)
    n = x.shape[0]
    rho = autocorr_function(x)
    taus = 2.0 * np.cumsum(rho, axis=0) - 1.0
    windows = np.arange(n)[:, None] >= c * taus
    first = np.where(windows.any(axis=0), windows.argmax(axis=0), n - 1)
    tau = taus[first, np.arange(taus.shape[1])]
    tau = np.maximum(tau, 1.0)  # a constant or anticorrelated column counts as independent
    if np.any(tol * tau > n):
        message = (
            f"the chain is too short to trust its autocorrelation time: {n} samples, "
            f"need more than tol * tau = {tol:.0f} * {tau.max():.1f}"
        )
        if not quiet:
            raise AutocorrError(message, tau)
        import warnings

        warnings.warn(message, RuntimeWarning, stacklevel=2)
    return tau


def mean_and_stderr(samples: np.ndarray, c: float = 5.0, tol: float = 50.0):
    """Mean and standard error of correlated samples (axis 0), via ``integrated_time``.

    ``stderr = sqrt(var * tau / n)``; columns that never vary get 0.  Extra axes
    are flattened for the estimate and restored on output.

    Returns
    -------
    mean, stderr, tau : arrays of the sample shape
    """
    samples = np.asarray(samples, dtype=float)
    shape = samples.shape[1:]
    flat = samples.reshape(samples.shape[0], -1)
    tau = integrated_time(flat, c=c, tol=tol)
    var = flat.var(axis=0, ddof=1)
    stderr = np.sqrt(var * tau / flat.shape[0])
    return flat.mean(axis=0).reshape(shape), stderr.reshape(shape), tau.reshape(shape)
