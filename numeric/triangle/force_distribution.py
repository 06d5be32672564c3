"""Force distributions in floating point: exact densities evaluated, sampled histograms with error bars.

* :func:`density_values`, :func:`cdf_values`: a gap law's density and CDF at
  floats, in the stable Bernstein form (no cancellation at any degree);
* :func:`piecewise_values`: an exact piecewise polynomial
  (:class:`forcenet.exact.triangle.distribution.Piece`) at floats, evaluated
  exactly in integers and rounded once;
* :func:`exact_sampler_histogram`, :func:`metropolis_histogram`: histograms of
  the pooled ``f`` of the exact sampler (independent configurations: the error
  bar is the spread between configurations, so correlations between the grains
  of one configuration are accounted for) and of the Metropolis chain (the error
  bar of every bin from its integrated autocorrelation time,
  :mod:`forcenet.numeric.autocorr`; a chain too short to trust is flagged, not
  hidden);
* :func:`comparison_png`: the exact ``P(f)`` against both histograms, one figure.

Pools (as in :mod:`forcenet.exact.triangle.distribution`): ``"ensemble"`` is
every grain of layers ``2..N`` with ``f = i W_{i,j}``; an integer ``i`` is
layer ``i`` alone.
"""

from __future__ import annotations

import io
import math
import warnings
from collections.abc import Callable, Sequence
from fractions import Fraction
from typing import TYPE_CHECKING, Any, NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from forcenet.core.errors import ArgumentError
from forcenet.core.validation import check_int, check_real
from forcenet.exact.triangle.distribution import as_pieces

from ..autocorr import integrated_time
from .exact_sampler import ExactSampler
from .metropolis import TriangleMetropolis

if TYPE_CHECKING:
    from forcenet.exact.triangle.gaps import GapCounts

__all__ = [
    "density_values",
    "cdf_values",
    "piecewise_values",
    "density_grid",
    "histogram_edges",
    "pool_forces",
    "Histogram",
    "exact_sampler_histogram",
    "metropolis_histogram",
    "chi_square",
    "comparison_png",
]


def _gap_probabilities(gaps: Any) -> tuple[int, np.ndarray, np.ndarray]:
    d = gaps.d
    prob = np.array([c / gaps.total for c in gaps.counts[1 : d + 1]], dtype=np.float64)
    g = np.arange(1, d + 1)
    keep = prob > 0
    return d, g[keep], prob[keep]


def density_values(gaps: GapCounts, w: ArrayLike) -> np.ndarray:
    """Density of the spacing with gap law ``gaps`` at floats ``w`` (Bernstein form).

    Parameters
    ----------
    gaps : forcenet.exact.triangle.gaps.GapCounts
        The exact gap law of a spacing (e.g. :func:`forcenet.exact.triangle.gaps.grain_gap_counts`).
    w : array_like of float
        Where to evaluate, in ``[0, 1]``.

    Returns
    -------
    numpy.ndarray
        The density at ``w``, same shape as ``w``: ``d sum_g p_g Bin(g - 1; d - 1, w)``.

    Examples
    --------
    >>> from forcenet.exact.triangle.gaps import grain_gap_counts
    >>> round(float(density_values(grain_gap_counts(3, (3, 2)), 0.5)), 12)
    1.5
    """
    from scipy.stats import binom  # scipy.stats is heavy: loaded when a law is drawn

    w = np.asarray(w, dtype=np.float64)
    d, g, prob = _gap_probabilities(gaps)
    vals = binom.pmf(g[:, None] - 1, d - 1, w.reshape(1, -1))
    return (d * prob @ vals).reshape(w.shape)


def cdf_values(gaps: GapCounts, w: ArrayLike) -> np.ndarray:
    """Distribution function of the spacing with gap law ``gaps`` at floats ``w``.

    Examples
    --------
    >>> from forcenet.exact.triangle.gaps import grain_gap_counts
    >>> float(cdf_values(grain_gap_counts(3, (3, 2)), 0.5))
    0.5
    """
    from scipy.stats import binom  # scipy.stats is heavy: loaded when a law is drawn

    w = np.asarray(w, dtype=np.float64)
    _, g, prob = _gap_probabilities(gaps)
    d = gaps.d
    vals = binom.sf(g[:, None] - 1, d, w.reshape(1, -1))  # P(Bin(d, w) >= g)
    return (prob @ vals).reshape(w.shape)


def _integer_poly(poly: Any) -> tuple[list[int], int]:
    """``(numerators from the constant term up, common denominator)`` of a Poly over QQ."""
    coeffs = [Fraction(int(c.p), int(c.q)) for c in reversed(poly.all_coeffs())]
    den = math.lcm(*(c.denominator for c in coeffs))
    return [c.numerator * (den // c.denominator) for c in coeffs], den


def _exact_eval(nums: Sequence[int], den: int, x: float) -> float:
    """``sum nums[m] x^m / den`` at the float ``x``, exactly, rounded once."""
    fx = Fraction(x)
    p, q = fx.numerator, fx.denominator
    acc, deg = 0, len(nums) - 1
    for m in range(deg, -1, -1):  # Horner in integers: sum a_m p^m q^(deg - m)
        acc = acc * p + nums[m] * q ** (deg - m) if m < deg else nums[m]
    return float(Fraction(acc, den * q**deg))


def piecewise_values(pieces: Any, f: ArrayLike, support: Any = None) -> np.ndarray:
    """A piecewise exact density at floats ``f``, 0 outside: a list of ``Piece``, or one ``Poly`` with its ``support``.

    Parameters
    ----------
    pieces : list of Piece or sympy.Poly
        The exact density (:mod:`forcenet.exact.triangle.distribution`).
    f : array_like of float
        Where to evaluate.
    support : tuple, optional
        ``(lo, hi)``, needed when ``pieces`` is one polynomial.

    Returns
    -------
    numpy.ndarray
        The density at ``f`` (same shape), each value the exact rational rounded once.

    Examples
    --------
    >>> from forcenet.exact.triangle.distribution import triangle_force_density
    >>> round(float(piecewise_values(triangle_force_density(3), 1.0)), 12)
    0.566666666667
    """

    pieces = as_pieces(pieces, support)
    f = np.asarray(f, dtype=np.float64)
    flat = f.reshape(-1)
    out = np.zeros(flat.shape)
    for k, piece in enumerate(pieces):
        lo, hi = float(piece.lo), float(piece.hi)
        last = k == len(pieces) - 1
        nums, den = _integer_poly(piece.poly)
        for t, x in enumerate(flat):
            if lo <= x < hi or (last and x == hi):
                out[t] = _exact_eval(nums, den, float(x))
    return out.reshape(f.shape)


def density_grid(pieces: Any, cdf_pieces: Any, K: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A piecewise density and its CDF at ``K + 1`` equally spaced points ``x_k = top * k / K`` of ``[0, top]``.

    ``top`` is the end of the last piece (as a float); the values are exact
    rationals rounded once (:func:`piecewise_values`).

    Parameters
    ----------
    pieces, cdf_pieces : list of Piece
        The density and its distribution function on the same intervals.
    K : int
        Number of intervals of the grid, ``K >= 1``.

    Returns
    -------
    x, density, cdf : numpy.ndarray
        The points and the two functions at them, each of length ``K + 1``.

    Raises
    ------
    ArgumentError
        If ``K`` is not an integer ``>= 1``.

    Examples
    --------
    >>> from forcenet.exact.triangle.distribution import layer_pieces
    >>> x, p, F = density_grid(*layer_pieces(3, 3), 3)
    >>> x.tolist(), F.tolist()
    ([0.0, 1.0, 2.0, 3.0], [0.0, 0.5555555555555556, 0.8888888888888888, 1.0])
    """
    K = check_int(K, "K", 1)
    top = float(pieces[-1].hi)
    x = np.array([top * k / K for k in range(K + 1)])
    return x, piecewise_values(pieces, x), piecewise_values(cdf_pieces, x)


def histogram_edges(f_max: float, bins: int) -> np.ndarray:
    """The ``bins + 1`` edges of ``bins`` equal bins of ``[0, f_max]``.

    Parameters
    ----------
    f_max : float
        The end of the range, finite and ``> 0``.
    bins : int
        Number of bins, ``>= 1``.

    Returns
    -------
    numpy.ndarray
        ``numpy.linspace(0, f_max, bins + 1)``: the first edge 0, the last ``f_max``.

    Raises
    ------
    ArgumentError
        If ``f_max`` is not a finite number ``> 0`` or ``bins`` not an integer ``>= 1``.

    Examples
    --------
    >>> histogram_edges(2.0, 4).tolist()
    [0.0, 0.5, 1.0, 1.5, 2.0]
    """
    bins = check_int(bins, "bins", 1)
    f_max = check_real(f_max, "f_max", 0, low_open=True)
    return np.linspace(0.0, f_max, bins + 1)


# ------------------------------------------------------------------ sampled histograms


def pool_forces(W: np.ndarray, pool: str | int = "ensemble") -> np.ndarray:
    """``f`` of every grain of the pool in each configuration: shape ``(K, grains)``.

    ``W`` has shape ``(K, N, N)`` (``W[:, i-1, j-1] = W_{i,j}``).

    Examples
    --------
    >>> W = np.array([[[1, 0, 0], [0.5, 0.5, 0], [0.2, 0.3, 0.5]]])
    >>> pool_forces(W).tolist()
    [[1.0, 1.0, 0.6000000000000001, 0.8999999999999999, 1.5]]
    """
    W = np.asarray(W, dtype=np.float64)
    N = W.shape[1]
    layers = range(2, N + 1) if pool == "ensemble" else [check_int(pool, "pool layer", 2, N)]
    return np.concatenate([i * W[:, i - 1, :i] for i in layers], axis=1)


class Histogram(NamedTuple):
    """A sampled density on ``edges``: ``density[k] +- stderr[k]`` on bin ``k``.

    ``tau`` is the largest integrated autocorrelation time in samples (1 for
    independent samples); ``reliable`` is False when the chain is shorter
    than 50 ``tau`` (the error bars are then estimates, flagged as such).
    """

    edges: np.ndarray
    density: np.ndarray
    stderr: np.ndarray
    samples: int
    tau: float
    reliable: bool


def _per_configuration(W: np.ndarray, pool: Any, edges: np.ndarray) -> np.ndarray:
    """Histogram density of each configuration, shape ``(K, bins)`` (mean over grains).

    Counted by ``numpy.bincount`` over blocks of configurations of about a
    million forces each, so no single numpy call runs long (Ctrl-C is seen
    between blocks).

    Examples
    --------
    >>> W = np.array([[[1, 0, 0], [0.5, 0.5, 0], [0.2, 0.3, 0.5]]])
    >>> _per_configuration(W, "ensemble", np.array([0.0, 1.0, 2.0])).tolist()
    [[0.4, 0.6]]
    """
    edges = np.asarray(edges, dtype=np.float64)
    bins = len(edges) - 1
    width = np.diff(edges)
    K = W.shape[0]
    out = np.zeros((K, bins))
    block = max(1, 2**20 // max(1, W.shape[1] * W.shape[1] // 2))
    for start in range(0, K, block):
        f = pool_forces(W[start : start + block], pool)
        idx = np.searchsorted(edges, f, side="right") - 1
        inside = (idx >= 0) & (idx < bins)
        rows = np.broadcast_to(np.arange(f.shape[0])[:, None], f.shape)
        counts = np.bincount(rows[inside] * bins + idx[inside], minlength=f.shape[0] * bins)
        out[start : start + f.shape[0]] = counts.reshape(f.shape[0], bins) / (f.shape[1] * width)
    return out


def _check_edges(edges: Any) -> np.ndarray:
    edges = np.asarray(edges, dtype=np.float64)
    if edges.ndim != 1 or edges.size < 2 or not np.all(np.diff(edges) > 0) or not np.all(np.isfinite(edges)):
        raise ArgumentError("edges: need at least two finite, strictly increasing bin edges")
    return edges


def exact_sampler_histogram(N: int, samples: int, edges: ArrayLike, pool: str | int = "ensemble",
                            seed: int | np.random.Generator | None = 0, progress: Callable[[int], object] | None = None) -> Histogram:
    """Histogram of the pooled ``f`` over ``samples`` independent exact samples.

    The error bar of a bin is the standard error of the per-configuration
    histograms, so the correlations between the grains of one configuration
    are included.

    Parameters
    ----------
    N : int
        Layers of the triangle (Sec. 4.2).
    samples : int
        Independent configurations, ``>= 2``.
    edges : array_like of float
        Increasing bin edges.
    pool : "ensemble" or int, default "ensemble"
        Every grain of layers ``2..N`` with ``f = i W_{i,j}``, or layer ``i`` alone.
    seed : int or numpy.random.Generator or None, default 0
        The sampler's random stream.
    progress : callable, optional
        Called with the number of configurations drawn in each batch.

    Returns
    -------
    Histogram
        ``density +- stderr`` per bin, ``tau = 1``, ``reliable`` True.

    Examples
    --------
    >>> h = exact_sampler_histogram(4, 2000, [0, 1, 2, 4], seed=1)
    >>> bool(abs(h.density @ np.diff(h.edges) - 1) < 1e-12), h.tau
    (True, 1.0)
    """

    samples = check_int(samples, "samples", 2)
    edges = _check_edges(edges)
    sampler = ExactSampler(N, seed=seed)  # validates N
    s1 = np.zeros(len(edges) - 1)
    s2 = np.zeros(len(edges) - 1)
    done = 0
    while done < samples:
        k = min(sampler.batch, samples - done)
        h = _per_configuration(sampler.sample_W(k), pool, edges)
        s1 += h.sum(axis=0)
        s2 += (h * h).sum(axis=0)
        done += k
        if progress is not None:
            progress(k)
    mean = s1 / samples
    var = np.maximum(s2 / samples - mean**2, 0.0) * samples / (samples - 1)
    return Histogram(edges, mean, np.sqrt(var / samples), samples, 1.0, True)


def metropolis_histogram(N: int, sweeps: int, edges: ArrayLike, pool: str | int = "ensemble",
                         burn_in: int | None = None, seed: int | np.random.Generator | None = 0,
                         progress: Callable[[int], object] | None = None) -> Histogram:
    """Histogram of the pooled ``f`` along a Metropolis chain in q (Sec. 3.2.4), one record per sweep.

    Error bars: ``sqrt(var tau / sweeps)`` per bin with ``tau`` its integrated
    autocorrelation time.  If the chain is shorter than ``50 tau`` the
    estimate is kept but ``reliable`` is False (an honest flag, not an error).

    Parameters
    ----------
    N : int
        Layers of the triangle (Sec. 4.2).
    sweeps : int
        Recorded sweeps, ``>= 2``.
    edges : array_like of float
        Increasing bin edges.
    pool : "ensemble" or int, default "ensemble"
        Every grain of layers ``2..N`` with ``f = i W_{i,j}``, or layer ``i`` alone.
    burn_in : int, optional
        Sweeps discarded first (default ``max(100, sweeps // 10)``).
    seed : int or numpy.random.Generator or None, default 0
        The chain's random stream.
    progress : callable, optional
        Ticks with the records made.

    Returns
    -------
    Histogram
        ``density +- stderr`` per bin, the largest ``tau`` over the bins and the ``reliable`` flag.

    Examples
    --------
    >>> h = metropolis_histogram(4, 400, [0, 1, 2, 4], seed=1)
    >>> h.samples, bool(h.tau >= 1)
    (400, True)
    """

    sweeps = check_int(sweeps, "sweeps", 2)  # N: validated by TriangleMetropolis
    burn_in = max(100, sweeps // 10) if burn_in is None else check_int(burn_in, "burn_in", 0)
    edges = _check_edges(edges)
    chain = TriangleMetropolis(N, seed=seed).run(sweeps, burn_in=burn_in, progress=progress)
    h = _per_configuration(chain, pool, edges)
    with warnings.catch_warnings():  # a short chain is reported through ``reliable``, not a warning
        warnings.simplefilter("ignore", RuntimeWarning)
        tau = integrated_time(h, tol=50.0, quiet=True)
    reliable = bool(np.all(50 * tau <= sweeps))
    var = h.var(axis=0, ddof=1)
    return Histogram(edges, h.mean(axis=0), np.sqrt(var * tau / sweeps), sweeps, float(tau.max()), reliable)


def chi_square(hist: Histogram, exact_bins: Sequence[Fraction | float]) -> tuple[float, int, float]:
    """``(chi2, bins, p)``: ``sum ((h - e) / stderr)^2`` over the bins with a nonzero error bar.

    ``exact_bins`` are the exact bin masses (e.g.
    :func:`forcenet.exact.triangle.distribution.bin_probabilities`); ``p`` is
    the chi-square tail probability for that many bins, treating the bins as
    independent (they are not quite: the bins of one configuration are
    anticorrelated, which makes ``p`` conservative).

    Examples
    --------
    >>> h = Histogram(np.array([0.0, 1, 2]), np.array([0.6, 0.4]), np.array([0.1, 0.1]), 100, 1.0, True)
    >>> value, bins, p = chi_square(h, [0.5, 0.5])
    >>> round(value, 12), bins, round(p, 4)
    (2.0, 2, 0.3679)
    """
    from scipy.stats import chi2  # scipy.stats is heavy: loaded when a law is drawn

    e = np.array([float(x) for x in exact_bins]) / np.diff(hist.edges)
    use = hist.stderr > 0
    value = float((((hist.density - e) / np.where(use, hist.stderr, 1.0))[use] ** 2).sum())
    bins = int(use.sum())
    return value, bins, float(chi2.sf(value, bins)) if bins else 1.0


def comparison_png(pieces: Any, exact_bins: Sequence[Fraction | float], histograms: dict, title: str, f_max: float | None = None) -> bytes:
    """PNG bytes: the exact ``P(f)`` (curve and bin averages) against sampled histograms with error bars.

    ``histograms`` maps a label to a :class:`Histogram`; two panels, linear and
    logarithmic.  Uses the Agg backend and never touches the file system.
    """

    import matplotlib

    matplotlib.use("Agg")
    from matplotlib.figure import Figure

    first = next(iter(histograms.values()))
    edges = first.edges
    f_max = float(edges[-1]) if f_max is None else f_max
    grid = np.linspace(0, f_max, 400)
    curve = piecewise_values(pieces, grid)
    centres = 0.5 * (edges[1:] + edges[:-1])
    exact_avg = np.array([float(x) for x in exact_bins]) / np.diff(edges)
    fig = Figure(figsize=(11, 4.5))
    axes = fig.subplots(1, 2)
    styles = ["o", "s", "^", "v"]
    for ax, log in zip(axes, (False, True)):
        ax.plot(grid, curve, "k-", lw=1.2, label="exact P(f)")
        ax.step(edges, np.r_[exact_avg, exact_avg[-1]], "k:", lw=0.8, where="post", label="exact, bin average")
        for k, (label, h) in enumerate(histograms.items()):
            shift = (k - (len(histograms) - 1) / 2) * 0.12 * np.diff(edges)
            flag = "" if h.reliable else " (chain < 50 tau: error bars unreliable)"
            ax.errorbar(centres + shift, h.density, yerr=h.stderr, fmt=styles[k % 4], ms=3.5, capsize=2, lw=0.8,
                        label=f"{label}{flag}")
        ax.set_xlabel("f = force / mean force of its layer")
        ax.set_ylabel("P(f)")
        ax.set_xlim(0, f_max)
        if log:
            ax.set_yscale("log")
            positive = curve[curve > 0]
            ax.set_ylim(max(positive.min() if positive.size else 1e-6, 1e-6), 2 * max(curve.max(), 1e-6))
    axes[0].legend(fontsize=7)
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", dpi=110)
    return buffer.getvalue()
