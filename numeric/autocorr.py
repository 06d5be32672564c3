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

import math
import warnings
from collections.abc import Iterable, Sequence
from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from forcenet.core.errors import ArgumentError, ForcenetError
from forcenet.core.validation import check_int, check_real

__all__ = ["AutocorrError", "autocorr_function", "batch_means", "integrated_time", "mean_and_stderr",
           "PooledChains", "pool_means", "pool_chains", "all_finite"]


class AutocorrError(ForcenetError):
    """The chain is too short to estimate its autocorrelation time reliably.

    Parameters
    ----------
    message : str
        What was too short, and how long the chain must be.
    tau : numpy.ndarray
        The autocorrelation times estimated anyway, one per observable.

    Examples
    --------
    >>> rng = np.random.default_rng(1)
    >>> try:
    ...     integrated_time(rng.random(50).cumsum())  # a random walk of 50 steps: far too short
    ... except AutocorrError as exc:
    ...     print(str(exc).split(":")[0], exc.tau.shape)
    the chain is too short to trust its autocorrelation time (1,)
    """

    def __init__(self, message: str, tau: np.ndarray) -> None:
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


COLUMN_BLOCK_BYTES = 1 << 28  # the transforms of one block of columns (integrated_time)


def _window_times(x: np.ndarray, c: float) -> np.ndarray:
    """Each column's integrated time by Sokal's window (:func:`integrated_time`), at least 1."""
    n = x.shape[0]
    rho = autocorr_function(x)
    taus = 2.0 * np.cumsum(rho, axis=0) - 1.0
    windows = np.arange(n)[:, None] >= c * taus
    first = np.where(windows.any(axis=0), windows.argmax(axis=0), n - 1)
    tau = taus[first, np.arange(taus.shape[1])]
    return np.maximum(tau, 1.0)  # a constant or anticorrelated column counts as independent


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
    if n == 0:
        raise AutocorrError("the chain has no samples: its autocorrelation time is undefined", np.ones(x.shape[1:]))
    flat = x.reshape(n, -1)
    # columns in blocks of ~COLUMN_BLOCK_BYTES of transforms (each column's is its own: the same times to rounding;
    # one block, the whole array, below it), so 10^4 forces x 4000 states take ~1/10 of the 3 GB they took at once
    step = max(1, COLUMN_BLOCK_BYTES // (64 * max(1, n)))
    tau = np.concatenate([_window_times(flat[:, k:k + step], c) for k in range(0, flat.shape[1], step)]
                         or [np.ones(0)])  # no columns: no times
    tau = tau.reshape(x.shape[1:]) if x.ndim > 1 else tau
    if np.any(tol * tau > n):
        message = (
            f"the chain is too short to trust its autocorrelation time: {n} samples, "
            f"need more than tol * tau = {tol:.0f} * {tau.max():.1f}"
        )
        if not quiet:
            raise AutocorrError(message, tau)

        warnings.warn(message, RuntimeWarning, stacklevel=2)
    return tau


def mean_and_stderr(samples: np.ndarray, c: float = 5.0, tol: float = 50.0) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
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


class PooledChains(NamedTuple):
    """Statistics of independent chains pooled (:func:`pool_chains`), per component."""

    mean: np.ndarray
    stderr: np.ndarray
    std: np.ndarray
    effective_samples: np.ndarray


def pool_means(lengths: Sequence[int], means: Sequence[np.ndarray | float], stderrs: Sequence[np.ndarray | float]
               ) -> tuple[np.ndarray, np.ndarray]:
    """The mean of independent chains of lengths ``n_k`` and its standard error.

    ``mean = sum_k n_k m_k / n`` and ``stderr = sqrt(sum_k (n_k s_k)^2) / n``
    with ``n = sum_k n_k``: the chains are independent, so their errors add in
    quadrature with the weights of their means.

    Parameters
    ----------
    lengths : sequence of int
        The chains' lengths ``n_k`` (at least one chain).
    means, stderrs : sequence of arrays
        Each chain's mean and standard error (:func:`mean_and_stderr`), all of one shape.

    Returns
    -------
    mean, stderr : numpy.ndarray

    Raises
    ------
    ArgumentError
        If there is no chain or the sequences differ in length.

    Examples
    --------
    >>> m, e = pool_means([1, 3], [np.array([0.0]), np.array([4.0])], [np.array([4.0]), np.array([0.0])])
    >>> m.tolist(), e.tolist()
    ([3.0], [1.0])
    """
    n = _lengths(lengths, means, stderrs)
    total = n.sum()
    mean = sum(w * m for w, m in zip(n, means)) / total
    stderr = np.sqrt(sum((w * e) ** 2 for w, e in zip(n, stderrs))) / total
    return np.asarray(mean), np.asarray(stderr)


def _lengths(lengths: Sequence[int], *per_chain: Sequence[object]) -> np.ndarray:
    if not len(lengths) or any(len(x) != len(lengths) for x in per_chain):
        raise ArgumentError(f"need one length and one statistic of each kind per chain, at least one chain "
                         f"(got {len(lengths)} lengths and {[len(x) for x in per_chain]} statistics)")
    return np.array(lengths, dtype=float)


def pool_chains(lengths: Sequence[int], means: Sequence[np.ndarray | float], stderrs: Sequence[np.ndarray | float],
                stds: Sequence[np.ndarray | float], taus: Sequence[np.ndarray | float]) -> PooledChains:
    """Mean, standard error, spread and effective sample size of independent chains pooled.

    The mean and its error are :func:`pool_means`; the spread is the sample
    standard deviation of all ``n = sum_k n_k`` values about the common mean,
    ``sqrt(sum_k [(n_k - 1) s_k^2 + n_k (m_k - m)^2] / (n - 1))`` (one chain:
    its own); the effective sample size is ``sum_k n_k / tau_k``.

    Parameters
    ----------
    lengths : sequence of int
        The chains' lengths ``n_k``.
    means, stderrs, stds, taus : sequence of arrays
        Each chain's mean, standard error, standard deviation (``ddof=1``) and
        integrated autocorrelation time, all of one shape.

    Returns
    -------
    PooledChains
        ``mean``, ``stderr``, ``std`` and ``effective_samples``, per component.

    Raises
    ------
    ArgumentError
        If there is no chain or the sequences differ in length.

    Examples
    --------
    >>> a, b = np.array([1.0, 2.0, 3.0]), np.array([5.0, 6.0, 7.0])
    >>> pooled = pool_chains([3, 3], [a.mean(), b.mean()], [0.5, 0.5], [a.std(ddof=1), b.std(ddof=1)], [1.0, 2.0])
    >>> float(pooled.mean), float(pooled.std) == float(np.concatenate([a, b]).std(ddof=1)), float(pooled.effective_samples)
    (4.0, True, 4.5)
    """
    n = _lengths(lengths, means, stderrs, stds, taus)
    mean, stderr = pool_means(lengths, means, stderrs)
    if len(n) == 1:
        std = np.asarray(stds[0])
    else:
        ss = sum((w - 1) * s ** 2 + w * (m - mean) ** 2 for w, m, s in zip(n, means, stds))
        std = np.sqrt(ss / (n.sum() - 1))
    ess = sum(w / t for w, t in zip(n, taus))
    return PooledChains(mean, stderr, std, np.asarray(ess))


def all_finite(values: Iterable[ArrayLike]) -> bool:
    """Whether every entry of every value is finite (no nan, no infinity).

    Parameters
    ----------
    values : iterable of arrays or numbers
        The results to check (of any shapes).

    Returns
    -------
    bool
        ``True`` when no entry is a nan or an infinity (also for no values).

    Raises
    ------
    TypeError
        If a value is not numeric (``numpy.isfinite`` refuses it).

    Examples
    --------
    >>> all_finite([1.0, np.array([2.0, 3.0])]), all_finite([np.array([1.0, np.inf])])
    (True, False)
    """
    return all(bool(np.all(np.isfinite(v))) for v in values)


def batch_means(chain: ArrayLike, batch_factor: float = 10.0, gap_factor: float = 2.0, pilot: float = 0.25,
                max_batches: int = 50, min_batches: int = 10, c: float = 5.0,
                tol: float = 50.0) -> tuple[np.ndarray, np.ndarray, dict[str, int]]:
    """Spaced batch means of a chain ``(n, G)`` (steps along axis 0), batch length from a pilot's ``tau``.

    The first ``pilot`` fraction of the chain measures the integrated times
    (:func:`integrated_time`: it must be longer than ``tol * tau``) and
    decides the batch length ``b >= batch_factor * tau`` and the gap
    ``gap_factor * tau`` left between batches; the rest is cut into
    ``B = min(max_batches, ...)`` batches. Measuring ``tau`` on other steps
    than the batches keeps the decision to refuse a chain (and the batch
    length) independent of the batch means: a chain accepted because its
    ``tau`` looked small would otherwise tend to have too small a spread of
    batch means (both measure the same slow fluctuations) and fail too often.
    The gaps make neighbouring batch means nearly independent.

    Returns
    -------
    means : array (B, G)
    tau : array (G,)
        Integrated time of each column on the pilot (1 for columns that never vary).
    layout : dict
        ``pilot`` (steps), ``length`` (steps per batch), ``gap`` (steps between batches).

    Raises
    ------
    AutocorrError
        If the pilot is shorter than ``tol * tau`` or the rest holds fewer
        than ``min_batches`` batches (in short: chains shorter than about
        ``200 tau`` are refused).

    Examples
    --------
    >>> x = np.random.default_rng(0).normal(size=(2000, 2))
    >>> means, tau, layout = batch_means(x)
    >>> means.shape, layout
    ((50, 2), {'pilot': 500, 'length': 27, 'gap': 3})
    """

    batch_factor = check_real(batch_factor, "batch_factor", 0, low_open=True)
    gap_factor = check_real(gap_factor, "gap_factor", 0)
    pilot = check_real(pilot, "pilot", 0, 1, low_open=True, high_open=True)
    max_batches = check_int(max_batches, "max_batches", 2)
    min_batches = check_int(min_batches, "min_batches", 2, max_batches)
    x = np.asarray(chain, dtype=float)
    if x.ndim == 1:
        x = x[:, None]
    n = x.shape[0]
    p = max(1, int(n * pilot))
    try:
        tau = integrated_time(x[:p], c=c, tol=tol)
    except AutocorrError as exc:
        need = math.ceil(tol * float(exc.tau.max()) / pilot)
        raise AutocorrError(
            f"the chain is too short to trust its autocorrelation time: {n} steps, tau = {exc.tau.max():.3g} "
            f"measured on the first {p}; that part must exceed {tol:.0f} tau, run at least {need} steps", exc.tau
        ) from None
    t = float(tau.max())
    length, gap = max(1, math.ceil(batch_factor * t)), math.ceil(gap_factor * t)
    rest = n - p
    B = min(max_batches, (rest + gap) // (length + gap))
    if B < min_batches:
        need = p + min_batches * (length + gap) - gap
        raise AutocorrError(
            f"the chain is too short for {min_batches} batch means of {batch_factor:g} tau: {n} steps, "
            f"tau = {t:.3g}; run at least {max(need, math.ceil(need / (1 - pilot)))} steps", tau)
    length = (rest + gap) // B - gap
    starts = n - (B * (length + gap) - gap) + np.arange(B) * (length + gap)
    means = np.stack([x[s:s + length].mean(axis=0) for s in starts])
    return means, tau, {"pilot": p, "length": length, "gap": gap}
