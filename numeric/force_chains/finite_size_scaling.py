"""Finite-size scaling of the clusters of large forces: the thesis's collapse (6.12) and standard estimators.

The data of one system size are *blocks* of samples (independent samples, or
consecutive stretches of a Markov chain longer than its autocorrelation
time), each block holding, at every threshold, the sums over its samples of
the clusters' second moment without the largest cluster, of the largest
cluster and of the number of samples with a wrapping cluster
(:class:`SizeBlocks`).  ``<s^2>(f, M)`` is the mean over samples of that sum
divided by ``M``, the bonds of one sample (Sec. 6.5).  Every error bar is a
bootstrap over the blocks of every size (the blocks resampled with
replacement, every estimator recomputed).

Eq. (6.8), reconstructed (``notes/force_chains.md``): near the critical
threshold ``f_c``,

    <s^2>(f, M) = A_2 M^gamma_2 Phi_2(B (f - f_c) M^(1/(2 nu))),    gamma_2 = D - 1,

so ``m_2(x, M) = M^(-gamma_2) <s^2>`` plotted against
``x = (f - f_c) M^(1/(2 nu))`` collapses for the right ``(gamma_2, nu, f_c)``.
The best collapse minimizes Eq. (6.12),

    chi^2(gamma_2, nu, f_c) = 1/(x_max - x_min) int_{x_min}^{x_max} dx
                              [<m_2(x, M)^2>_M - <m_2(x, M)>_M^2] / <m_2(x, M)>_M^2,

the variance over the sizes ``M`` of the rescaled curves (interpolated at
``x``), relative to their mean square, averaged over the window.  The
thesis's errors are the changes of the optimum as ``x_min``, ``x_max`` vary
over the region of the collapse: :func:`collapse` reports them beside the
bootstrap's.  The standard estimators: the peak height ``~ M^gamma_2``, the
peak position ``f*(M) = f_c + a M^(-1/(2 nu))`` and, with wrapping data, the
crossings of the wrapping probabilities of successive sizes.

The size variable ``S`` is the number of bonds ``M`` (isotropic systems) or,
for an anisotropic model scaled in its vertical size, ``L_vert^2`` (then
``S^(1/(2 nu)) = L_vert^(1/nu)``, Sec. 7.3).

Examples
--------
>>> import numpy as np
>>> f = np.linspace(0.0, 1.0, 201)
>>> sizes = [64.0, 256.0, 1024.0]
>>> def curve(S): return S ** 0.9 * np.exp(-((f - 0.5) * S ** (1 / 3.0)) ** 2)   # gamma_2 0.9, nu 1.5
>>> data = [SizeBlocks.from_curve(S, S, f, curve(S) * S) for S in sizes]
>>> fit = best_collapse(data, window=(-1.0, 1.0), start=(0.85, 1.6, 0.48))
>>> [round(v, 2) for v in fit]
[0.9, 1.5, 0.5]
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import minimize

from forcenet.core.errors import ArgumentError, ConvergenceError
from forcenet.core.validation import check_int

__all__ = ["SizeBlocks", "collapse_cost", "best_collapse", "peak", "peak_estimates", "wrapping_crossings",
           "ScalingFit", "analyse", "default_window", "fit_collapse", "NAMES", "peak_width"]


@dataclass(frozen=True)
class SizeBlocks:
    """One system size's data: ``S`` (the scaling size), ``M`` (bonds per sample), ``thresholds`` (increasing),
    and per block (rows) and threshold (columns) the sums over the block's samples: ``total`` (sum of ``s^2``
    but the largest cluster), ``largest``, ``wraps``; ``samples`` per block; ``label`` (e.g. ``L``)."""

    S: float
    M: int
    thresholds: np.ndarray
    total: np.ndarray
    largest: np.ndarray
    wraps: np.ndarray
    samples: np.ndarray
    label: float = 0.0
    has_wraps: bool = False

    @classmethod
    def from_curve(cls, S: float, M: float, thresholds: np.ndarray, total: np.ndarray) -> SizeBlocks:
        """One block of one sample holding a given ``total`` curve (tests and examples)."""
        row = np.asarray(total, dtype=np.float64)[None, :]
        return cls(float(S), int(M), np.asarray(thresholds, dtype=np.float64), row, np.zeros_like(row),
                   np.zeros_like(row), np.ones(1), label=float(S))

    @property
    def blocks(self) -> int:
        return int(self.samples.size)

    def s2(self, weights: np.ndarray | None = None) -> np.ndarray:
        """``<s^2>(f)`` (Sec. 6.5) with the blocks weighted (a bootstrap's counts), all blocks by default."""
        w = np.ones(self.blocks) if weights is None else weights
        return (w @ self.total) / (float(w @ self.samples) * self.M)

    def wrapping(self, weights: np.ndarray | None = None) -> np.ndarray:
        """The probability that a cluster wraps the torus, per threshold."""
        w = np.ones(self.blocks) if weights is None else weights
        return (w @ self.wraps) / float(w @ self.samples)

    def largest_fraction(self, weights: np.ndarray | None = None) -> np.ndarray:
        """The mean largest cluster over ``M``, per threshold."""
        w = np.ones(self.blocks) if weights is None else weights
        return (w @ self.largest) / (float(w @ self.samples) * self.M)


MIN_STEPS = 8  # the window spans at least this many threshold steps at every size (else chi^2 is infinite)


def collapse_cost(params: Sequence[float], curves: Sequence[tuple[float, np.ndarray, np.ndarray]],
                  window: tuple[float, float], points: int = 64, min_span: float = 0.0) -> float:
    """Eq. (6.12): the relative variance over sizes of ``m_2 = S^-gamma <s^2>`` at ``x = (f - f_c) S^(1/(2 nu))``.

    Parameters
    ----------
    params : (gamma_2, nu, f_c)
        The exponents and threshold tried.
    curves : sequence of (S, f, s2)
        Each size's scaling size, thresholds (increasing) and ``<s^2>``.
    window : (x_min, x_max)
        The integration window in the scaling variable.
    points : int
        The trapezoid rule's points.
    min_span : float
        The least width of the window in thresholds at the largest size (``inf`` below it).

    Returns
    -------
    float
        chi^2; ``inf`` when a size does not cover the window or the parameters are out of range.

    Examples
    --------
    >>> import numpy as np
    >>> f = np.linspace(0, 1, 101)
    >>> curves = [(S, f, S * np.exp(-((f - 0.5) * S) ** 2)) for S in (2.0, 4.0)]   # gamma 1, nu 1/2
    >>> round(collapse_cost((1.0, 0.5, 0.5), curves, (-1.0, 1.0)), 6), collapse_cost((1.0, 1.0, 0.5), curves, (-1, 1)) > 0.01
    (0.0, True)
    """
    gamma, nu, fc = params
    if not (nu > 0.05 and math.isfinite(gamma) and math.isfinite(fc)):
        return math.inf
    anchor = max(S for S, _, _ in curves) ** (1.0 / (2.0 * nu))
    if (window[1] - window[0]) / anchor < min_span:
        return math.inf  # the window would shrink to a sliver of the largest size's peak: the degenerate nu -> 0
    grid = np.linspace(window[0], window[1], points)
    rows = []
    for S, f, s2 in curves:
        scale = S ** (1.0 / (2.0 * nu))
        x = (f - fc) * scale
        if x[0] > grid[0] or x[-1] < grid[-1]:
            return math.inf
        if (grid[-1] - grid[0]) / scale < MIN_STEPS * (f[-1] - f[0]) / (f.size - 1):
            return math.inf  # the window would fall between a few thresholds: the degenerate collapse nu -> 0
        rows.append(np.interp(grid, x, s2) * S ** (-gamma))
    m = np.array(rows)
    mean = m.mean(axis=0)
    if np.any(mean <= 0):
        return math.inf
    integrand = m.var(axis=0) / mean**2
    return float(np.trapezoid(integrand, grid) / (grid[-1] - grid[0]))


def best_collapse(data: Sequence[SizeBlocks], window: tuple[float, float], start: Sequence[float],
                  weights: Sequence[np.ndarray | None] | None = None, min_span: float = 0.0
                  ) -> tuple[float, float, float]:
    """``(gamma_2, nu, f_c)`` minimizing :func:`collapse_cost` (Nelder-Mead in ``(gamma_2, 1/nu, f_c)``).

    Parameters
    ----------
    data : sequence of SizeBlocks
        The sizes.
    window : (x_min, x_max)
        The window of Eq. (6.12).
    start : (gamma_2, nu, f_c)
        The starting point.
    weights : sequence, optional
        Each size's block weights (a bootstrap resample).
    min_span : float
        As :func:`collapse_cost`.

    Returns
    -------
    tuple of float
        The optimum.

    Raises
    ------
    ConvergenceError
        If no finite cost is found near the start.

    Examples
    --------
    See the module's example.
    """
    weights = [None] * len(data) if weights is None else list(weights)
    curves = [(d.S, d.thresholds, d.s2(w)) for d, w in zip(data, weights, strict=True)]

    def cost(p: np.ndarray) -> float:
        return collapse_cost((p[0], 1.0 / p[1], p[2]), curves, window, min_span=min_span) if p[1] > 0 else math.inf

    x0 = np.array([start[0], 1.0 / start[1], start[2]])
    if not math.isfinite(cost(x0)):
        raise ConvergenceError(f"the collapse's window {window} is not covered by every size at the start {tuple(start)}; "
                               "widen the thresholds' range or narrow the window")
    span = float(np.ptp(data[0].thresholds))
    best = (cost(x0), x0)
    for scale in (1.0, 0.5, 0.25):  # restarts: a simplex stalled against a wall of infinite cost starts afresh
        x0 = best[1]
        simplex = np.array([x0, x0 + [0.1 * scale, 0, 0], x0 + [0, 0.15 * scale * x0[1], 0],
                            x0 + [0, 0, 0.01 * scale * span]])
        result = minimize(cost, x0, method="Nelder-Mead",
                          options={"initial_simplex": simplex, "xatol": 1e-5, "fatol": 1e-12, "maxiter": 4000})
        if not result.fun < best[0] - 1e-9 * abs(best[0]):
            break  # the restart found nothing better: the simplex had converged
        best = (float(result.fun), result.x)
    g, inv_nu, fc = best[1]
    return float(g), float(1.0 / inv_nu), float(fc)


def peak(f: np.ndarray, y: np.ndarray, points: int = 7) -> tuple[float, float]:
    """The maximum of a sampled curve: a parabola through the ``points`` values around the largest one.

    Examples
    --------
    >>> import numpy as np
    >>> f = np.linspace(0, 1, 51); fp, h = peak(f, 2 - (f - 0.313) ** 2)
    >>> round(fp, 6), round(h, 6)
    (0.313, 2.0)
    """
    k = int(np.argmax(y))
    half = points // 2
    lo, hi = max(0, k - half), min(y.size, k + half + 1)
    if hi - lo < 3:
        return float(f[k]), float(y[k])
    c2, c1, c0 = np.polyfit(f[lo:hi] - f[k], y[lo:hi], 2)
    if c2 >= 0:
        return float(f[k]), float(y[k])
    dx = float(np.clip(-c1 / (2 * c2), f[lo] - f[k], f[hi - 1] - f[k]))
    return float(f[k] + dx), float(c0 + c1 * dx + c2 * dx * dx)


def peak_width(f: np.ndarray, y: np.ndarray, level: float = 0.5) -> float:
    """The width in ``f`` of the region where a sampled curve exceeds ``level`` times its maximum (linear
    interpolation at both crossings; NaN if the curve does not fall below it on both sides).

    Examples
    --------
    >>> import math
    >>> import numpy as np
    >>> f = np.linspace(-3, 3, 601)
    >>> round(peak_width(f, np.exp(-f**2)), 3), round(2 * math.sqrt(math.log(2)), 3)
    (1.665, 1.665)
    """
    k = int(np.argmax(y))
    h = level * y[k]
    below = np.nonzero(y[:k] <= h)[0]
    above = np.nonzero(y[k:] <= h)[0]
    if below.size == 0 or above.size == 0:
        return math.nan
    i, j = int(below[-1]), k + int(above[0])
    left = f[i] + (h - y[i]) * (f[i + 1] - f[i]) / (y[i + 1] - y[i])
    right = f[j - 1] + (h - y[j - 1]) * (f[j] - f[j - 1]) / (y[j] - y[j - 1])
    return float(right - left)


def peak_estimates(data: Sequence[SizeBlocks], weights: Sequence[np.ndarray | None] | None = None
                   ) -> dict[str, float]:
    """The standard estimators: ``gamma_2`` from the peak heights (slope of ``log max <s^2>`` on ``log S``),
    ``f_c``, ``nu`` from the peak positions ``f*(S) = f_c + a S^(-1/(2 nu))`` (least squares; NaN if it fails),
    and ``nu_width`` from the peak widths at half height, ``~ S^(-1/(2 nu))`` (Eq. 6.8: the scaling function's
    width in ``x`` is fixed; needs neither ``f_c`` nor ``gamma_2``).

    Examples
    --------
    >>> import numpy as np
    >>> f = np.linspace(0, 1, 401)
    >>> data = [SizeBlocks.from_curve(S, S, f, S * S**0.9 * np.exp(-((f - 0.5) * S**0.25 - 0.7) ** 2))
    ...         for S in (256.0, 1024.0, 4096.0, 16384.0)]                       # nu = 2, f* = 0.5 + 0.7 S^-1/4
    >>> e = peak_estimates(data); round(e["gamma_2"], 2), round(e["f_c"], 2), round(e["nu"], 1), round(e["nu_width"], 2)
    (0.9, 0.5, 2.0, 2.0)
    """
    weights = [None] * len(data) if weights is None else list(weights)
    pos, height, S, widths = [], [], [], []
    for d, w in zip(data, weights, strict=True):
        y = d.s2(w)
        fp, h = peak(d.thresholds, y)
        pos.append(fp)
        height.append(h)
        S.append(d.S)
        widths.append(peak_width(d.thresholds, y))
    logS = np.log(S)
    gamma = float(np.polyfit(logS, np.log(np.maximum(height, 1e-300)), 1)[0])
    nu_width = math.nan
    if all(math.isfinite(x) and x > 0 for x in widths):
        slope = float(np.polyfit(logS, np.log(widths), 1)[0])
        nu_width = -1.0 / (2.0 * slope) if slope < 0 else math.nan
    fc = nu = math.nan
    if len(data) >= 3:
        best = (math.inf, math.nan, math.nan)
        for inv in np.linspace(0.05, 1.5, 146):  # for each 1/nu a linear fit of f* on S^(-1/(2 nu)); the best
            u = np.asarray(S) ** (-inv / 2)
            A = np.vstack([np.ones_like(u), u]).T
            coef, res, *_ = np.linalg.lstsq(A, np.asarray(pos), rcond=None)
            r = float(res[0]) if res.size else float(np.sum((A @ coef - pos) ** 2))
            if r < best[0]:
                best = (r, float(coef[0]), 1.0 / inv)
        fc, nu = float(best[1]), float(best[2])
    return {"gamma_2": gamma, "f_c": fc, "nu": nu, "nu_width": nu_width}


def wrapping_crossings(data: Sequence[SizeBlocks], weights: Sequence[np.ndarray | None] | None = None) -> float:
    """``f_c`` as the mean crossing of the wrapping probabilities of successive sizes (NaN without wrapping data).

    Examples
    --------
    >>> import numpy as np
    >>> f = np.linspace(0, 1, 101)
    >>> def blocks(S):
    ...     w = 1 / (1 + np.exp((f - 0.4) * S))[None, :]
    ...     return SizeBlocks(S, 1, f, w, w, w, np.ones(1), has_wraps=True)
    >>> round(wrapping_crossings([blocks(10.0), blocks(20.0)]), 3)
    0.4
    """
    weights = [None] * len(data) if weights is None else list(weights)
    if not all(d.has_wraps for d in data) or len(data) < 2:
        return math.nan
    found = []
    for (a, wa), (b, wb) in zip(zip(data, weights, strict=True), list(zip(data, weights, strict=True))[1:], strict=False):
        grid = np.union1d(a.thresholds, b.thresholds)
        diff = np.interp(grid, a.thresholds, a.wrapping(wa)) - np.interp(grid, b.thresholds, b.wrapping(wb))
        sign = np.nonzero(np.diff(np.sign(diff)) != 0)[0]
        if sign.size:
            k = int(sign[np.argmax(np.abs(np.diff(diff))[sign])])  # the steepest sign change
            t = diff[k] / (diff[k] - diff[k + 1])
            found.append(float(grid[k] + t * (grid[k + 1] - grid[k])))
    return float(np.mean(found)) if found else math.nan


def default_window(data: Sequence[SizeBlocks], level: float = 0.5) -> tuple[float, float]:
    """The region of the collapse, in thresholds: where the largest size's ``<s^2>`` exceeds ``level`` times its
    maximum.

    Examples
    --------
    >>> import numpy as np
    >>> f = np.linspace(0, 1, 401)
    >>> d = [SizeBlocks.from_curve(S, S, f, S * np.exp(-((f - 0.5) * S ** 0.5) ** 2)) for S in (4.0, 16.0)]
    >>> [round(v, 2) for v in default_window(d)]
    [0.29, 0.71]
    """
    big = max(data, key=lambda d: d.S)
    y = big.s2()
    above = np.nonzero(y >= level * y.max())[0]
    return float(big.thresholds[above[0]]), float(big.thresholds[above[-1]])


@dataclass(frozen=True)
class ScalingFit:
    """The exponents with their errors: ``value`` (the collapse at the central window), ``bootstrap`` (the spread
    over block resamples), ``window_spread`` (half the range of the optimum over the windows tried),
    ``sizes_spread`` (the change when the smallest size is left out: corrections to scaling), ``error`` (the
    three in quadrature), and the standard estimators with their bootstrap errors."""

    value: dict[str, float]
    bootstrap: dict[str, float]
    window_spread: dict[str, float]
    sizes_spread: dict[str, float]
    error: dict[str, float]
    window: tuple[float, float]
    cost: float
    estimators: dict[str, float]
    estimator_errors: dict[str, float]
    replicas: int
    windows: list[tuple[float, float]] = field(default_factory=list)
    pinned: bool = False
    """The optimum sits on the window's limit (a smaller ``nu`` would shrink the window below ``MIN_SPAN``): chi^2
    keeps falling towards the degenerate ``nu -> 0``, the collapse does not fix ``nu`` and its errors understate;
    trust the estimators instead."""


NAMES = ("gamma_2", "nu", "f_c")
LEVEL = 0.3  # the window: where the largest size's <s^2> exceeds 30 % of its peak (notes/force_chains.md)
NU_STARTS = (1.0, 1.5, 2.5, 4.0)
MIN_SPAN = 0.2  # the window never narrower than this part of the largest size's peak region (excludes nu -> 0)


def _resample(data: Sequence[SizeBlocks], rng: np.random.Generator) -> list[np.ndarray]:
    return [np.bincount(rng.integers(0, d.blocks, d.blocks), minlength=d.blocks).astype(np.float64) for d in data]


def _curves(data: Sequence[SizeBlocks]) -> list[tuple[float, np.ndarray, np.ndarray]]:
    return [(d.S, d.thresholds, d.s2()) for d in data]


def _x_window(data: Sequence[SizeBlocks], f_window: tuple[float, float], p: Sequence[float]) -> tuple[float, float]:
    """The f-window of the largest size in the scaling variable at ``p``, cut to what every size covers.

    Raises
    ------
    ConvergenceError
        If the cut leaves out the largest size's peak (the collapse would compare tails only).
    """
    big = max(data, key=lambda d: d.S)
    anchor = big.S ** (1.0 / (2.0 * p[1]))
    lo, hi = (f_window[0] - p[2]) * anchor, (f_window[1] - p[2]) * anchor
    for d in data:
        scale = d.S ** (1.0 / (2.0 * p[1]))
        lo, hi = max(lo, (d.thresholds[0] - p[2]) * scale), min(hi, (d.thresholds[-1] - p[2]) * scale)
    top = (peak(big.thresholds, big.s2())[0] - p[2]) * anchor
    if not lo < top < hi:
        raise ConvergenceError(f"at {tuple(p)} the sizes do not all cover the peak of the largest one")
    return lo, hi


def fit_collapse(data: Sequence[SizeBlocks], start: Sequence[float], nu_starts: Sequence[float] = NU_STARTS
                 ) -> tuple[tuple[float, float, float], tuple[float, float], float, float]:
    """The best collapse from several starts (``nu`` from ``start`` and ``nu_starts``; ``f_c`` from ``start`` and
    the largest size's peak).  For each: the window ``[x_min, x_max]`` is the region
    where the largest size's ``<s^2>`` exceeds ``LEVEL`` of its peak (:func:`default_window`), in the scaling
    variable of the start; the optimum in that window; the window again at the optimum; the optimum again.
    The window may not shrink below ``MIN_SPAN`` of that region (``min_span``, which excludes the degenerate ``nu -> 0``);
    the lowest chi^2 wins.

    Returns
    -------
    ((gamma_2, nu, f_c), (x_min, x_max), chi2, min_span)

    Raises
    ------
    ConvergenceError
        If no start gives a covered window.

    Examples
    --------
    >>> import numpy as np
    >>> f = np.linspace(0.0, 1.0, 301)
    >>> data = [SizeBlocks.from_curve(S, S, f, S * S**0.9 * np.exp(-((f - 0.5) * S ** (1 / 3)) ** 2))
    ...         for S in (64.0, 256.0, 1024.0)]
    >>> p, w, c, m = fit_collapse(data, (0.8, 1.4, 0.48)); [round(v, 2) for v in p]
    [0.9, 1.5, 0.5]
    """
    f_window = default_window(data, LEVEL)
    min_span = MIN_SPAN * (f_window[1] - f_window[0])
    best: tuple[tuple[float, float, float], tuple[float, float], float, float] | None = None
    largest = max(data, key=lambda d: d.S)
    f_top = peak(largest.thresholds, largest.s2())[0]
    starts = [(start[0], nu0, fc0) for fc0 in dict.fromkeys((start[2], f_top)) for nu0 in (start[1], *nu_starts)]
    for p in starts:
        try:
            window = _x_window(data, f_window, p)
            p = best_collapse(data, window, p, min_span=min_span)
        except ConvergenceError:
            continue
        for _ in range(2):  # the window followed to the optimum, while every size covers it and its peak
            try:
                moved = _x_window(data, f_window, p)
                p, window = best_collapse(data, moved, p, min_span=min_span), moved
            except ConvergenceError:
                break
        try:
            _x_window(data, f_window, p)  # the optimum itself must keep the largest size's peak in the window
        except ConvergenceError:
            continue
        cost = collapse_cost(p, _curves(data), window, min_span=min_span)
        if math.isfinite(cost) and (best is None or cost < best[2]):
            best = (p, window, cost, min_span)
    if best is None:
        raise ConvergenceError("no collapse found: no starting point gives a window covered by every size; "
                               "widen the thresholds' range")
    return best


def analyse(data: Sequence[SizeBlocks], *, replicas: int = 100, seed: int = 0,
            start: Sequence[float] | None = None) -> ScalingFit:
    """The collapse (6.12) with its window variation and the standard estimators, each with bootstrap errors.

    Parameters
    ----------
    data : sequence of SizeBlocks
        At least three sizes.
    replicas : int
        Bootstrap resamples (blocks with replacement, every size).
    seed : int
        The bootstrap's seed.
    start : (gamma_2, nu, f_c), optional
        Where the collapse's search starts (default: the peak estimators; several ``nu`` are tried besides).

    Returns
    -------
    ScalingFit
        The exponents and threshold with their errors.

    Examples
    --------
    >>> import numpy as np
    >>> f = np.linspace(0.0, 1.0, 301)
    >>> data = [SizeBlocks.from_curve(S, S, f, S * S**0.9 * np.exp(-((f - 0.5) * S ** (1 / 3)) ** 2))
    ...         for S in (64.0, 128.0, 256.0, 1024.0)]
    >>> fit = analyse(data, replicas=0, start=(0.8, 1.4, 0.48))
    >>> [round(fit.value[k], 2) for k in NAMES], round(fit.sizes_spread["nu"], 2)
    ([0.9, 1.5, 0.5], 0.0)
    """
    replicas = check_int(replicas, "replicas", 0)
    if len(data) < 3:
        raise ArgumentError(f"finite-size scaling needs at least 3 system sizes, got {len(data)}")
    data = sorted(data, key=lambda d: d.S)
    estimators = peak_estimates(data)
    crossing = wrapping_crossings(data)
    estimators["f_c_crossing"] = crossing
    if start is None:
        sane = math.isfinite(estimators["nu"]) and 0.8 < estimators["nu"] < 5  # else the peak shift is no guide
        fc0 = crossing if math.isfinite(crossing) else (estimators["f_c"] if sane
                                                         else peak(data[-1].thresholds, data[-1].s2())[0])
        start = (estimators["gamma_2"], estimators["nu"] if sane else 1.5, fc0)
    central, window, cost, min_span = fit_collapse(data, start)
    width = window[1] - window[0]
    windows, optima = [], []
    for a in (-0.2, 0.0, 0.2):  # the thesis's error: the bounds varied over the region of the collapse
        for b in (-0.2, 0.0, 0.2):
            varied = (window[0] + a * width, window[1] + b * width)
            try:
                optima.append(best_collapse(data, varied, central, min_span=0.5 * min_span))
                windows.append(varied)
            except ConvergenceError:
                continue
    spread = {n: float(np.ptp([o[i] for o in optima]) / 2) for i, n in enumerate(NAMES)}
    sizes = {n: 0.0 for n in NAMES}
    if len(data) >= 4:  # corrections to scaling: the optimum without the smallest size
        try:
            without = best_collapse(data[1:], window, central, min_span=min_span)
            sizes = {n: abs(without[i] - central[i]) for i, n in enumerate(NAMES)}
        except ConvergenceError:
            sizes = {n: math.nan for n in NAMES}
    rng = np.random.default_rng(seed)
    boot, boot_est = [], []
    for _ in range(replicas):
        w = _resample(data, rng)
        try:
            boot.append(best_collapse(data, window, central, weights=w, min_span=min_span))
        except ConvergenceError:
            continue
        e = peak_estimates(data, w)
        e["f_c_crossing"] = wrapping_crossings(data, w)
        boot_est.append(e)
    boot_err = {n: float(np.std([b[i] for b in boot], ddof=1)) if len(boot) > 1 else 0.0
                for i, n in enumerate(NAMES)}
    est_err = {}
    for k in estimators:
        values = [e[k] for e in boot_est if math.isfinite(e[k])]
        est_err[k] = float(np.std(values, ddof=1)) if len(values) > 1 else math.nan
    value = dict(zip(NAMES, central, strict=True))
    error = {n: math.sqrt(boot_err[n] ** 2 + spread[n] ** 2 + sizes[n] ** 2) for n in NAMES}
    nudged = (central[0], central[1] * 0.98, central[2])
    pinned = not math.isfinite(collapse_cost(nudged, _curves(data), window, min_span=min_span))
    return ScalingFit(value, boot_err, spread, sizes, error, window, cost, estimators, est_err, len(boot), windows,
                      pinned)
