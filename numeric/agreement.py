"""Does a table of sampled means agree with its exact values?  Tests with a stated false-alarm rate.

The statistical engine of :mod:`forcenet.testing` (and through it of the
command line's cross-check): one implementation.

Rows
    ``K`` independent samples (:func:`compare_samples`), or the ``B`` batch
    means of a Markov chain (:func:`compare_chain`, :func:`~forcenet.numeric.autocorr.batch_means`):
    ``tau``, the largest integrated autocorrelation time, is measured on the
    first quarter of the chain (:func:`forcenet.numeric.autocorr.integrated_time`,
    which refuses a stretch shorter than ``50 tau``); the rest is cut into 10
    to 50 batches of at least ``10 tau`` steps, ``2 tau`` apart. Chains
    shorter than about ``200 tau`` are refused.
Two routes, for the ``G`` values that vary
    * **bounded** (``bounds=(lo, hi)`` given, independent rows): a betting
      p-value per value (:mod:`forcenet.numeric.betting`: a nonnegative
      martingale under the exact mean and Ville's inequality), Bonferroni
      over the values: ``p = min(1, G min p_g)``, failing at ``p <= alpha``.
      **Guaranteed at every K** for any distribution inside the bounds: no
      normal approximation. A mean at an end of its range is that end
      almost surely: compared exactly, a difference is a certain failure.
    * **t** (no bounds, or the batch means of a chain): ``t = (mean -
      exact) / stderr`` per value, Student ``t`` with ``K - 1`` (or ``B - 1``)
      degrees of freedom; the largest ``|t|`` with its Bonferroni p-value
      ``min(1, G P(|T| >= max |t|))``; Hotelling's ``T^2 = K d' S^+ d`` on the
      nondegenerate subspace of the covariance (``(K - r)/(r (K - 1)) T^2 ~
      F(r, K - r)``, ``r`` the rank, run when ``r >= 2`` and ``K >= max(5 r,
      r + 10)``); the maximum and Hotelling at ``alpha/2`` each (the maximum
      at ``alpha`` when Hotelling does not run). Exact for normal rows,
      asymptotic otherwise; judged only under **the size rule** below.

**The t route's level: the size rule** (:mod:`forcenet.numeric.size_rule`).
The skewness term ``u = s^3 gamma / (3 sqrt n)`` of Student's t tail (Wang
2005) must stay at most ``U_MAX = 1`` at the critical value of the most
skewed value; the Bonferroni p-value is charged ``cosh(u)``. Independent
rows are charged ``|g1| + 2 sqrt(6 / K)``, a chain's batch means of ``L``
steps ``|g1 of the steps| sqrt(1.5 tau / L)`` (measured: 0.48 against 0.53
on a Beta(1, 8) AR(1) chain, 0.29 against 0.37 on W_51 of the Metropolis
chain, N = 5). Below the rule (``judged`` False) no t verdict: only a
deviation overwhelming without any distribution (:mod:`.chebyshev`:
Chebyshev on the autocorrelation-corrected error, its variance bounded
above) is DISAGREES; else ``cannot judge``, the reason giving the rows (or
steps) needed. No verdict weakens as the evidence grows (issue 53).

**Cannot judge.** A report whose statistics cannot support a verdict says
``verdict == "cannot judge"`` with its ``reason`` (``passed`` is False):
fewer independent rows than the bounded test could ever fail on (every row
at an end of the range would not reach ``alpha``), rows or batch means
below the t route's size rule, a value that never varies while its exact
mean differs (zero variance: no t statistic). A chain too short for its
guard, or for ``min_batches`` batches, is refused up front
(:class:`forcenet.numeric.autocorr.AutocorrError`). A disagreement a test
valid at that size supports is reported whatever else is said.

**What is guaranteed.** Independent rows with bounds: a correct sampler
fails with probability at most ``alpha`` at every ``K`` (the union bound
over the values, Ville's inequality per value). The t route: at most
``alpha`` by the union bound, exactly so for normal rows, and to first order
in the skewness wherever the size rule lets it judge (no test of a mean
without bounds has a level guaranteed at finite ``K`` for every
distribution: Bahadur and Savage 1956); for a chain, besides, as the batch length over ``tau`` grows (fixed
number of batches; the gaps and the separate measurement of ``tau`` remove
the finite-length excess measured without them, ``1.1-1.4 alpha``). The
measured rates are in ``tests/test_testing.py`` and
``notes/testing_against_exact.md``.

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
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from forcenet.core.errors import ArgumentError
from forcenet.core.validation import check_real

from .autocorr import batch_means, integrated_time
from .betting import betting_pvalues, blind_values, cached_rows_needed
from .chebyshev import chain_dof, chebyshev_pvalue, rows_dof
from .size_rule import U_MAX, charged_skewness, size_rule, skewness, t_rows_needed
from .size_rule import bonferroni as _bonferroni
from .size_rule import hotelling as _hotelling
from .table_agreement import TableAgreement, _same

__all__ = ["TableAgreement", "batch_means", "compare_samples", "compare_chain", "compare_means", "varying_columns"]

_FIXED_RTOL = 1e-12  # a column is "fixed" when it varies by less than this (relative)


def varying_columns(x: np.ndarray) -> np.ndarray:
    """Columns of ``(K, G)`` that vary by more than rounding (``1e-12`` relative): the rest are fixed values.

    Examples
    --------
    >>> varying_columns(np.array([[1.0, 0.2], [1.0 + 1e-15, 0.7]])).tolist()
    [False, True]
    """
    spread = x.max(axis=0) - x.min(axis=0)
    return spread > _FIXED_RTOL * np.maximum(1.0, np.abs(x).max(axis=0))


def _split(x: np.ndarray, mu: np.ndarray, keys: list) -> tuple[np.ndarray, tuple[tuple[Any, float, float], ...]]:
    """Separate the columns that never vary (compared exactly) from the others."""
    fixed = ~varying_columns(x)
    return ~fixed, tuple((keys[g], float(x[0, g]), float(mu[g])) for g in np.flatnonzero(fixed))


def _z_scores(rows: np.ndarray, mu: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Means, ``(mean - exact) / stderr`` (infinite where a constant column differs) and the stderrs."""
    K, mean = rows.shape[0], rows.mean(axis=0)
    dev = mean - mu
    stderr = rows.std(axis=0, ddof=1) / math.sqrt(K) if K > 1 else np.full(mean.shape, np.inf)
    with np.errstate(divide="ignore", invalid="ignore"):
        z = np.where(stderr > 0, dev / stderr, np.where(dev == 0, 0.0, np.inf * np.sign(dev)))
    return mean, dev, stderr, z


def _report(keys: Sequence[Any], mean: np.ndarray, mu: np.ndarray, stderr: np.ndarray, z: np.ndarray,
            **fields: Any) -> TableAgreement:
    return TableAgreement(keys=tuple(keys), mean=tuple(map(float, mean)), exact=tuple(map(float, mu)),
                          stderr=tuple(map(float, stderr)), z=tuple(map(float, z)), **fields)


def _rows_test(rows: np.ndarray, mu: np.ndarray, keys: Sequence[Any], alpha: float, hotelling: bool | None, fixed: Any,
               reason: str | None = None, gamma: np.ndarray | None = None,
               too_few: Callable[[Any, Any, float], str] | None = None, floor: bool = False,
               error: tuple[Any, ...] | None = None, **extra: Any) -> TableAgreement:
    """The t route: t per value, Bonferroni maximum, Hotelling, on rows ``(K, G)``.

    ``gamma`` (one per value): the skewness the size rule charges the rows' t statistics with; below the size
    where they keep their level the report carries ``judged=False`` and ``too_few(u, worst, level)`` as its reason,
    and the distribution-free bound (:mod:`.chebyshev`) on ``error = (stderr, dof)`` (default: the rows') decides
    what is overwhelming.
    """
    K = rows.shape[0]
    mean, dev, stderr, z = _z_scores(rows, mu)
    G = mean.size
    hot = _hotelling(rows, dev) if (hotelling is None or hotelling) and G >= 2 else None
    if hotelling and hot is None and G >= 2:
        raise ArgumentError(f"hotelling=True needs more rows: {K} rows for {G} values")
    level_max, level_chi2 = (alpha / 2, alpha / 2) if hot is not None else (alpha, 0.0)
    judged, u, factor, worst = size_rule(gamma, K, level_max, G, floor)
    if not judged and too_few is not None:
        reason = too_few(u, worst, level_max) + ("" if reason is None else f"; besides, {reason}")
    max_z = float(np.abs(z).max()) if G else 0.0
    if not judged:
        se, dof, *fourth = error if error is not None else (stderr, rows_dof(rows))  # fourth: (reach, blocks)
        extra["p_bound"], extra["z_bound"], _ = chebyshev_pvalue(dev, se, dof, alpha, *fourth)
    return _report(keys, mean, mu, stderr, z, df=K - 1, alpha=alpha,
                   p_max=min(1.0, factor * _bonferroni(max_z, G, K - 1)),
                   level_max=level_max, chi2=None if hot is None else hot[0], dof=0 if hot is None else hot[1],
                   p_chi2=None if hot is None else hot[2], level_chi2=level_chi2, fixed=fixed, reason=reason,
                   judged=judged, skew_term=u, **extra)


def _bounds(bounds: Any, G: int) -> list[np.ndarray]:
    """``(lo, hi)`` as two float arrays of length ``G`` (scalars or one entry per value)."""
    try:
        lo, hi = bounds
    except (TypeError, ValueError):
        raise ArgumentError(f"bounds={bounds!r}: give (lo, hi), two numbers or two arrays of one entry per value") from None
    out = []
    for name, end in (("lo", lo), ("hi", hi)):
        arr = np.asarray(end, dtype=float).ravel()
        if arr.size not in (1, G):
            raise ArgumentError(f"bounds: {name} has {arr.size} entries for {G} values")
        out.append(np.broadcast_to(arr, (G,)))
    return out


def _inside(rows: np.ndarray, mu: np.ndarray, keys: Sequence[Any], bounds: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The bounds as arrays and their rounding tolerance; raises if a bound, exact value or sample is off."""
    G = rows.shape[1]
    lo, hi = _bounds(bounds, G)
    tol = 1e-9 * np.maximum(np.abs(hi - lo), 1.0)
    bad = ~(np.isfinite(lo) & np.isfinite(hi) & (lo < hi))
    if bad.any():
        n = int(np.argmax(bad))
        raise ArgumentError(f"bounds of {str(keys[n])}: [{lo[n]:g}, {hi[n]:g}] must be finite with lo < hi")
    bad = (mu < lo - tol) | (mu > hi + tol)
    if bad.any():
        n = int(np.argmax(bad))
        raise ArgumentError(f"exact value of {str(keys[n])} = {mu[n]:.6g} lies outside its bounds "
                         f"[{lo[n]:g}, {hi[n]:g}]")
    out = (rows < lo - tol) | (rows > hi + tol)
    if out.any():
        r, n = (int(v) for v in np.argwhere(out)[0])
        raise ArgumentError(f"samples of {str(keys[n])}: row {r} = {rows[r, n]:.6g} lies outside the bounds "
                         f"[{lo[n]:g}, {hi[n]:g}] (wrong bounds, or a sampler outside the model)")
    return lo, hi, tol


def _bounded_test(rows: np.ndarray, mu: np.ndarray, keys: Any, alpha: float, bounds: Any,
                  fixed: Any = (), **extra: Any) -> TableAgreement:
    """The bounded route: a betting p-value per value (:mod:`.betting`), Bonferroni over the values.

    A value whose exact mean is an end of its range is that end almost surely: compared exactly.
    """

    K, G = rows.shape
    lo, hi, tol = _inside(rows, mu, keys, bounds)
    at_end = (mu - lo <= tol) | (hi - mu <= tol)
    far = np.abs(rows - mu).argmax(axis=0)
    fixed = tuple(fixed) + tuple((keys[n], float(rows[far[n], n]), float(mu[n])) for n in np.flatnonzero(at_end))
    test = ~at_end
    if extra.get("tau") is not None:
        extra["tau"] = tuple(float(t) for t in np.asarray(extra["tau"])[test])
    keys = [k for k, t in zip(keys, test) if t]
    rows, mu, lo, hi = rows[:, test], mu[test], lo[test], hi[test]
    G = rows.shape[1]
    mean, dev, stderr, z = _z_scores(rows, mu)
    share = alpha / max(G, 1)  # Bonferroni share of each value
    p = betting_pvalues(rows, mu, lo, hi, share) if G else np.ones(0)
    reason = None
    blind = blind_values(K, tuple(mu), tuple(lo), tuple(hi), share) if G else np.zeros(0, bool)
    if blind.any():
        n = int(np.flatnonzero(blind)[0])
        others = f" (and {int(blind.sum()) - 1} other values)" if blind.sum() > 1 else ""
        reason = (f"{K} rows are too few: no sample of {K} rows could reveal a wrong mean of {str(keys[n])}"
                  f"{others} at level {alpha:g} over {G} values; "
                  f"the bounded test needs at least {cached_rows_needed(tuple(mu), tuple(lo), tuple(hi), share)} rows")
    return _report(keys, mean, mu, stderr, z, df=K - 1, alpha=alpha,
                   p_max=float(min(1.0, G * p.min())) if G else 1.0, level_max=alpha, fixed=fixed,
                   method="bounded", reason=reason, fixed_certain=True, **extra)


def _prepare(samples: ArrayLike, exact: ArrayLike, keys: Sequence[Any] | None,
             name: str = "samples") -> tuple[np.ndarray, np.ndarray, list[Any]]:
    x = np.asarray(samples, dtype=float)
    if x.ndim == 1:
        x = x[:, None]
    if x.ndim != 2:
        raise ArgumentError(f"{name} has shape {x.shape}: expected (rows, values)")
    if not np.isfinite(x).all():
        bad = np.argwhere(~np.isfinite(x))[0]
        raise ArgumentError(f"{name} contains a non-finite number (row {bad[0]}, column {bad[1]})")
    mu = np.asarray([float(v) for v in np.ravel(np.asarray(exact, dtype=object))])
    if mu.size != x.shape[1]:
        raise ArgumentError(f"exact has {mu.size} values, {name} has {x.shape[1]} columns")
    keys = list(keys) if keys is not None else list(range(x.shape[1]))
    if len(keys) != x.shape[1]:
        raise ArgumentError(f"keys has {len(keys)} names for {x.shape[1]} values")
    return x, mu, keys


def _check_alpha(alpha: Any) -> float:
    return check_real(alpha, "alpha", 0, 1, low_open=True, high_open=True)


def _t_reason(K: int | None, fixed: Any) -> str | None:
    """Why the t route cannot judge a constant value off its exact mean (``K`` rows, or a chain: None)."""
    for key, sampled, exact in fixed:
        if not _same(sampled, exact):
            return (f"{str(key)} never varies in {K} rows ({sampled!r}) but its exact mean is {exact!r}: "
                    f"a wrong fixed value, or too few rows to see it vary; pass bounds=(lo, hi) to decide")
    return None


def compare_samples(samples: ArrayLike, exact: Any, keys: list[Any] | None = None, alpha: float = 1e-3,
                    hotelling: bool | None = None, bounds: Any = None) -> TableAgreement:
    """Compare independent samples ``(K, G)`` of ``G`` quantities with their exact means ``(G,)``.

    Parameters
    ----------
    samples : array_like, shape (K, G)
        One row per independent sample (for a Markov chain use :func:`compare_chain`).
    exact : array_like, shape (G,)
        The exact expectations (``Fraction``, sympy or float; converted to float here).
    keys : sequence, optional
        Names of the ``G`` quantities (e.g. grains), for the report.
    alpha : float
        Level of the whole-table test: a correct sampler fails with probability at most ``alpha``.
    hotelling : bool, optional
        Run Hotelling's test (t route only): ``None`` when the rows suffice, ``False`` never, ``True`` always (or raise).
    bounds : (lo, hi), optional
        Every sample of a value lies in ``[lo, hi]`` (numbers, or arrays of one entry per value): the
        bounded test, valid at any ``K``. Without bounds, the t route judges under its size rule.

    Returns
    -------
    TableAgreement
        ``verdict`` ``"cannot judge"`` (``passed`` False, ``reason`` set) when the rows cannot support one.
    """
    alpha = _check_alpha(alpha)
    x, mu, keys = _prepare(samples, exact, keys)
    if x.shape[0] < 2:
        raise ArgumentError(f"samples: {x.shape[0]} row; an error bar needs at least 2")
    if bounds is not None:
        if hotelling:
            raise ArgumentError("hotelling=True: Hotelling's test belongs to the t route (no bounds)")
        return _bounded_test(x, mu, keys, alpha, bounds, samples=x.shape[0])
    vary, fixed = _split(x, mu, keys)
    rows, K = x[:, vary], x.shape[0]
    names = [k for k, v in zip(keys, vary) if v]

    def too_few(u: Any, worst: Any, level: float) -> str:
        g = float(abs(skewness(rows[:, worst:worst + 1])[0]))
        return (f"{K} rows are too few for the t statistics without bounds: {str(names[worst])} is skewed "
                f"(sample skewness {g:.2g}) and at level {alpha:g} over {rows.shape[1]} values their tail is trusted "
                f"from about {t_rows_needed(g, level, rows.shape[1])} rows on (skewness term {u:.2g}, trusted to "
                f"{U_MAX:g}; Wang's error term (1 + s)/sqrt(K), trusted to 1/4); "
                f"pass bounds=(lo, hi) (every sample of a value lies in [lo, hi]) for the bounded test, valid at "
                f"any number of rows, or draw more")

    return _rows_test(rows, mu[vary], names, alpha, hotelling, fixed, reason=_t_reason(K, fixed),
                      gamma=charged_skewness(rows), too_few=too_few, floor=True, samples=K)


def compare_chain(chain: ArrayLike, exact: Any, keys: list[Any] | None = None, alpha: float = 1e-3,
                  hotelling: bool | None = None, bounds: Any = None, **batching: Any) -> TableAgreement:
    """Compare a Markov chain ``(n, G)`` with exact means ``(G,)`` through batch means.

    Same parameters as :func:`compare_samples`; ``batching`` goes to
    :func:`batch_means` (``batch_factor``, ``gap_factor``, ``pilot``,
    ``max_batches``, ``min_batches``). Raises :class:`forcenet.numeric.autocorr.AutocorrError`
    on a chain too short to trust.

    The batch means go to the t route under its size rule (batch means are
    not independent: no test on them has a level guaranteed at finite length;
    ``notes/testing_against_exact.md``). ``bounds`` are checked on every
    step; a mean at an end of its range is compared exactly.

    Examples
    --------
    >>> rng = np.random.default_rng(1)
    >>> x = np.zeros(20000)
    >>> for t in range(1, x.size):  # AR(1) around 0, tau = 19
    ...     x[t] = 0.9 * x[t - 1] + rng.normal()
    >>> report = compare_chain(x, [0.0])
    >>> report.passed, report.batches, bool(15 < report.tau[0] < 25)
    (True, 50, True)
    >>> compare_chain(x[:500], [0.0])
    Traceback (most recent call last):
    ...
    forcenet.numeric.autocorr.AutocorrError: the chain is too short to trust its autocorrelation time: ...
    """
    alpha = _check_alpha(alpha)
    x, mu, keys = _prepare(chain, exact, keys, name="chain")
    vary, fixed = _split(x, mu, keys)
    certain = bounds is not None
    if certain:  # values checked; a mean at an end of its range is compared exactly, with certainty
        lo, hi, tol = _inside(x, mu, keys, bounds)
        at_end = (mu - lo <= tol) | (hi - mu <= tol)
        far = np.abs(x - mu).argmax(axis=0)
        reason = _t_reason(None, [f for f, end in zip(fixed, at_end[~vary]) if not end])
        fixed = tuple((keys[n], float(x[far[n], n]), float(mu[n])) for n in np.flatnonzero(at_end))
        vary &= ~at_end
    else:
        reason = _t_reason(None, fixed)
    if not vary.any():
        return _rows_test(x[:2, vary], mu[vary], [], alpha, False, fixed, reason=reason, fixed_certain=certain,
                          samples=x.shape[0])
    means, tau, layout = batch_means(x[:, vary], **batching)
    names = [k for k, v in zip(keys, vary) if v]
    steps = np.abs(skewness(x[:, vary]))
    whole = integrated_time(x[:, vary], tol=0.0)  # the autocorrelation-corrected error, for the bound
    error: tuple[Any, ...] = (np.sqrt(x[:, vary].var(axis=0, ddof=1) * whole / x.shape[0]),
                              chain_dof(x.shape[0], whole))
    if certain:  # within bounds: the fourth moment of the batches' mean, bounded by the range (.chebyshev)
        error += (np.maximum(mu - lo, hi - mu)[vary], means.shape[0])
    gamma = steps * np.sqrt(1.5 * np.asarray(tau, dtype=float) / layout["length"])  # a batch: length / (1.5 tau) rows

    def too_few(u: Any, worst: Any, level: float) -> str:
        return (f"the chain's {means.shape[0]} batch means of {layout['length']} steps are too few for the t "
                f"statistics: {str(names[worst])} is skewed (steps: {steps[worst]:.2g}, batch means: about "
                f"{gamma[worst]:.2g}) and at level {alpha:g} over {len(names)} values their tail is trusted from "
                f"about {int(math.ceil(x.shape[0] * (u / U_MAX) ** 2))} steps on (skewness term {u:.2g} > "
                f"{U_MAX:g}); run a longer chain")

    return _rows_test(means, mu[vary], names, alpha, hotelling, fixed, gamma=gamma, too_few=too_few, error=error,
                      reason=reason, fixed_certain=certain, samples=x.shape[0], tau=tuple(map(float, tau)),
                      batches=means.shape[0], batch_length=layout["length"], batch_gap=layout["gap"],
                      pilot=layout["pilot"])


def compare_means(mean: ArrayLike, stderr: ArrayLike, exact: ArrayLike, keys: list[Any] | None = None,
                  alpha: float = 1e-3, df: int | None = None) -> TableAgreement:
    """Max-|z| test only, from means and standard errors (e.g. from autocorrelation times).

    ``df=None`` takes ``z`` as standard normal (the standard errors are
    trusted); pass the degrees of freedom of the standard errors otherwise.

    Examples
    --------
    >>> report = compare_means([1.0, 2.02], [0.01, 0.01], [1, 2])
    >>> round(report.max_z, 6), report.worst, report.passed
    (2.0, 1, True)
    """
    alpha = _check_alpha(alpha)
    mean = np.asarray(mean, dtype=float).ravel()
    stderr = np.asarray(stderr, dtype=float).ravel()
    mu = np.asarray([float(v) for v in np.ravel(np.asarray(exact, dtype=object))])
    if not (mean.size == stderr.size == mu.size):
        raise ArgumentError(f"mean, stderr and exact have {mean.size}, {stderr.size} and {mu.size} values")
    keys = list(keys) if keys is not None else list(range(mean.size))
    dev = mean - mu
    with np.errstate(divide="ignore", invalid="ignore"):
        z = np.where(stderr > 0, dev / stderr, np.where(dev == 0, 0.0, np.inf * np.sign(dev)))
    max_z = float(np.abs(z).max()) if z.size else 0.0
    return TableAgreement(
        keys=tuple(keys), mean=tuple(map(float, mean)), exact=tuple(map(float, mu)), stderr=tuple(map(float, stderr)),
        z=tuple(map(float, z)), df=df, alpha=alpha, p_max=_bonferroni(max_z, mean.size, df), level_max=alpha,
    )
