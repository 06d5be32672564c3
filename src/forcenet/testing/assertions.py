"""Sampled values against their exact counterparts, with a stated false-alarm rate.

``samples`` has one row per sample (independent draws) or per step (a
Markov chain, ``chain=True``) and the shape of the table after it:
``(K,)`` for one value, ``(K, N, N)`` for the triangle's ``W``, ``(K, N, P)``
for a packing. ``exact`` has the table's shape; it may be ragged (the rows
of ``forcenet.exact.mean_W(N)``) and hold ``Fraction``, sympy numbers or
``None``: missing entries and ``None`` are not tested.

``bounds=(lo, hi)`` (numbers, or tables shaped like ``exact``) says where
every sample lies: every ``W`` of the triangle in ``[0, 1]``, a packing's
``W`` in ``[0, the row's load]``, an observable in ``[min, max]`` over the
configurations a chain can visit. The project's tables carry theirs
(:class:`forcenet.exact.protocol.BoundedTable`: ``mean_W``,
``moment_table``, ``exact_mean_W``), used when no ``bounds`` are given
(``bounds=False``: none). With bounds, independent samples get the
bounded test (betting, :mod:`forcenet.numeric.betting`) whose level holds at
every number of samples; without, the t route (Student t per value, the
Bonferroni maximum, Hotelling's chi-square) judges only where its size rule
says the t tail keeps its level (:mod:`forcenet.numeric.agreement`; about
2300-4000 rows at 1e-3 for the triangle's ``W`` at N = 6) and says ``cannot judge``
below it, DISAGREES included. A chain (``chain=True``) is cut into spaced
batch means tested by the t route (bounds, when given, are checked and a
mean at an end of its range is compared exactly).

**Guarantee.** A correct sampler fails with probability at most ``alpha``,
whatever the correlations between the values: at every ``K`` with bounds;
exact for normal rows and to first order in the skewness on the t route,
at the sizes it judges; for a chain
asymptotic in the batch length over the integrated time ``tau`` (``tau``
measured on its first quarter, which must exceed ``50 tau``, then 10 to 50
batches of at least ``10 tau`` steps, ``2 tau`` apart: chains shorter than
about ``200 tau`` are refused). When the rows cannot support a verdict the
report says ``cannot judge`` with its reason and :func:`assert_agrees` raises
:class:`CannotJudgeError`. Details and measured rates:
:mod:`forcenet.numeric.agreement`, ``notes/testing_against_exact.md``.

Examples
--------
>>> from forcenet.exact import mean_W
>>> from forcenet.numeric.triangle.exact_sampler import ExactSampler
>>> W = ExactSampler(5, seed=1).sample_W(4000)
>>> report = assert_agrees(W, mean_W(5))   # the table's bounds [0, 1]; 14 varying grains; W_11 = 1 exactly
>>> report.values, report.passed, report.method
(14, True, 'bounded')
>>> compare(W[:12], mean_W(5)).verdict
'cannot judge'
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Sequence
from numbers import Number
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from forcenet.core.errors import ArgumentError, ArgumentTypeError, ForcenetError
from forcenet.core.validation import check_real
from forcenet.numeric.agreement import TableAgreement, compare_chain, compare_means, compare_samples, varying_columns
from forcenet.numeric.autocorr import integrated_time

__all__ = ["CannotJudgeError", "DisagreementError", "TableAgreement", "assert_agrees", "assert_means_agree", "compare",
           "exact_array", "samples_array"]


class DisagreementError(ForcenetError, AssertionError):
    """Sampled values disagree with their exact counterparts; ``report`` holds the details.

    Parameters
    ----------
    report : TableAgreement
        The comparison that disagreed (its message is the exception's).

    Examples
    --------
    >>> from fractions import Fraction
    >>> import forcenet
    >>> from forcenet.testing import assert_agrees
    >>> wrong = [list(row) for row in forcenet.table(4).mean_W]  # a claimed table with two floor loads off
    >>> wrong[3][0] += Fraction(1, 20); wrong[3][1] -= Fraction(1, 20)
    >>> try:
    ...     assert_agrees(forcenet.ExactSampler(4, seed=1).sample_W(2000), wrong)
    ... except DisagreementError as exc:
    ...     print(exc.report.verdict, isinstance(exc, AssertionError))
    DISAGREES True
    """

    def __init__(self, report: TableAgreement) -> None:
        super().__init__(report.message())
        self.report = report


class CannotJudgeError(ForcenetError, AssertionError):
    """The samples cannot support a verdict (too few rows, a constant value); ``report.reason`` says why.

    Parameters
    ----------
    report : TableAgreement
        The comparison that could not judge (its message is the exception's).

    Examples
    --------
    >>> import forcenet
    >>> from forcenet.testing import assert_agrees
    >>> try:
    ...     assert_agrees(forcenet.ExactSampler(4, seed=1).sample_W(5), forcenet.table(4).mean_W)
    ... except CannotJudgeError as exc:  # an AssertionError: a test fails rather than passing silently
    ...     print(exc.report.verdict)
    cannot judge
    """

    def __init__(self, report: TableAgreement) -> None:
        super().__init__(report.message())
        self.report = report


def _bounds_array(bounds: Any, shape: tuple[int, ...], tested: np.ndarray) -> tuple[np.ndarray, ...]:
    """``bounds=(lo, hi)``: each a number or a table shaped like ``exact``; as arrays over the tested values."""
    try:
        ends = list(bounds) if not isinstance(bounds, (str, bytes)) else []
    except TypeError:
        ends = []
    if len(ends) != 2:
        raise ArgumentError(f"bounds={bounds!r}: give (lo, hi), numbers or tables shaped like exact, e.g. bounds=(0, 1)")
    out = []
    for name, end in zip(("bounds[0] (lo)", "bounds[1] (hi)"), ends):
        if not isinstance(end, (list, tuple, np.ndarray)):
            out.append(np.full(int(tested.sum()), _to_float(end, name)))
        else:
            table = exact_array(end, shape, name=name)
            if np.isnan(table[tested]).any():
                raise ArgumentError(f"{name}: a tested value has no bound (None or missing): give a number for "
                                    f"every value that exact tests")
            out.append(table[tested])
    return tuple(out)


def _to_float(value: Any, name: str, none_ok: bool = False) -> float:
    """One entry of an exact table or of its bounds as a float (``None``: NaN, untested, where allowed)."""
    if value is None and none_ok:
        return math.nan
    what = ("a number (Fraction, sympy number, int or float), or None for a value not to test" if none_ok
            else "a number (Fraction, sympy number, int or float)")
    if value is None or value is True or value is False or isinstance(value, (str, bytes, np.bool_)):
        raise ArgumentTypeError(f"{name}={value!r} is not a number: give {what}")
    try:
        x = float(value)
    except (TypeError, ValueError):
        if hasattr(value, "__len__"):
            raise ArgumentError(f"{name} is a sequence where one sample has no further axis: the samples have "
                                f"fewer axes than {name.split('[')[0]}; give one row per sample shaped like "
                                f"exact") from None
        raise ArgumentTypeError(f"{name}={value!r} is not a number: give {what}") from None
    except OverflowError:
        raise ArgumentError(f"{name}={value!r} is too large for a float") from None
    if not math.isfinite(x):
        raise ArgumentError(f"{name}={value!r} is not finite: give {what}")
    return x


def exact_array(exact: Any, shape: Sequence[int], *, name: str = "exact") -> np.ndarray:
    """The exact table as floats of the given shape; ``NaN`` where nothing is to be tested.

    Ragged rows are padded (``mean_W(N)`` row ``i`` has ``i`` entries),
    ``None`` entries are not tested.

    Parameters
    ----------
    exact : scalar, array or nested (ragged) sequence
        The exact values (``Fraction``, sympy numbers, floats or ``None``).
    shape : sequence of int
        The shape of one sample.
    name : str
        What the table is called in error messages (``exact``, or a bound).

    Returns
    -------
    numpy.ndarray
        Floats of shape ``shape``, ``NaN`` where nothing is to be tested.

    Raises
    ------
    ArgumentError
        If ``exact`` has more entries than the samples' axis, a number where the
        samples have an axis, (an array) another shape, or an entry that is not
        finite (``NaN`` or infinite: ``None`` marks a value not to test).
    ArgumentTypeError
        If an entry is not a number (a string, a bool).

    Examples
    --------
    >>> from fractions import Fraction
    >>> exact_array([[1], [Fraction(1, 2), Fraction(1, 2)]], (2, 2)).tolist()
    [[1.0, nan], [0.5, 0.5]]
    >>> exact_array([[1, 2, 3]], (1, 2))
    Traceback (most recent call last):
    ...
    forcenet.core.errors.ArgumentError: exact[0] has 3 entries, more than the samples' axis of length 2 (one sample has shape (1, 2)): give samples and exact of the same table
    """
    shape = tuple(shape)
    out = np.full(shape, np.nan)

    def fill(value: Any, index: tuple[int, ...]) -> None:
        where = name + "".join(f"[{k}]" for k in index)
        if len(index) == len(shape):
            out[index] = _to_float(value, where, none_ok=True)
            return
        if value is None:
            return
        if isinstance(value, (str, bytes)):
            raise ArgumentTypeError(f"{where}={value!r} is not a number: give a number or a sequence of numbers")
        if isinstance(value, Number) or not hasattr(value, "__len__"):
            raise ArgumentError(f"{where} is a single number where the samples have an axis of length "
                                f"{shape[len(index)]} (one sample has shape {shape}): give samples and {name} of "
                                f"the same table")
        if len(value) > shape[len(index)]:
            raise ArgumentError(f"{where} has {len(value)} entries, more than the samples' axis of length "
                                f"{shape[len(index)]} (one sample has shape {shape}): give samples and {name} of "
                                f"the same table")
        for k, item in enumerate(value):
            fill(item, index + (k,))

    if isinstance(exact, np.ndarray) and exact.dtype != object:
        if exact.shape != shape:
            raise ArgumentError(f"{name} has shape {exact.shape}, one sample has shape {shape}: give samples and "
                                f"{name} of the same table")
        if exact.dtype.kind not in "iuf":
            raise ArgumentTypeError(f"{name} is an array of {exact.dtype}: give numbers")
        table = exact.astype(float)
        if not np.isfinite(table).all():
            raise ArgumentError(f"{name} holds a value that is not finite: give numbers, or None (an object "
                                f"array or a list) for a value not to test")
        return table
    fill(exact, ())
    return out


def _default_keys(shape: tuple[int, ...], positions: Any) -> list[Any]:
    if len(shape) == 0:
        return ["value"]
    if len(shape) == 1:
        return [int(p[0]) + 1 for p in positions]
    return [tuple(int(k) + 1 for k in p) for p in positions]


def _autocorrelated(flat: np.ndarray) -> float | None:
    """The largest integrated time over a few columns, if the rows look like a chain (else None).

    The threshold ``max(3.5, 1 + 80 / sqrt(n))`` sits far above the estimate's
    spread for independent rows (its 99.9% quantile over 16 columns: 2.3 at
    ``n = 500``, 1.8 at 1000 for normal rows; 2.1 at 1000 for the skewed
    ``W`` of N = 10, largest of 800 tables 2.6: the former threshold 2.4
    refused independent rows about once in 1000 tables, as often as a
    false alarm at the default level); it catches chains, not all of them.
    """

    n = min(flat.shape[0], 4096)
    if n < 500:
        return None
    cols = np.flatnonzero(varying_columns(flat))
    if cols.size == 0:
        return None
    cols = cols[np.linspace(0, cols.size - 1, min(cols.size, 16)).astype(int)]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        tau = float(integrated_time(flat[:n, cols], quiet=True).max())
    return tau if tau > max(3.5, 1.0 + 80.0 / math.sqrt(n)) else None


_BATCHING = frozenset({"batch_factor", "gap_factor", "pilot", "max_batches", "min_batches", "c", "tol"})
_SAMPLES = "give one row per sample: a rectangular array of numbers of shape (K, ...), K >= 2, a row shaped like exact"


def _flag(value: object, name: str, none_ok: bool = False) -> Any:
    """``chain`` / ``hotelling``: True or False (``hotelling`` also None), never a string or a number."""
    if value is None and none_ok:
        return None
    if value is True or value is False or isinstance(value, np.bool_):  # the two bools (numpy's too), not 0/1
        return bool(value)
    allowed = "True, False or None" if none_ok else "True or False"
    raise ArgumentTypeError(f"{name}={value!r} is not a bool: give {name}={allowed}")


def _alpha(alpha: Any) -> float:
    """The level: a number strictly between 0 and 1, never a string."""

    if isinstance(alpha, (str, bytes)):
        raise ArgumentTypeError(f"alpha={alpha!r} is a string: give a number in (0, 1), e.g. alpha=1e-3")
    return check_real(alpha, "alpha", 0, 1, low_open=True, high_open=True)


def samples_array(samples: Any, name: str = "samples") -> np.ndarray:
    """``samples`` as a float array ``(K, ...)`` with ``K >= 1`` rows of finite numbers, or a clear refusal.

    Parameters
    ----------
    samples : array_like
        One row per sample (numbers: ints, floats, bools, Fractions).
    name : str
        The argument's name in the messages.

    Returns
    -------
    numpy.ndarray
        Floats, at least one axis, at least one row and one value.

    Raises
    ------
    ArgumentTypeError
        On strings, complex numbers, ``None`` entries or a non-array.
    ArgumentError
        On an empty, ragged or scalar input, or a number that is not finite (or too large for a float).

    Examples
    --------
    >>> samples_array([[1, 2], [3, 4]]).dtype
    dtype('float64')
    >>> samples_array([[1, 2], [3]])
    Traceback (most recent call last):
    ...
    forcenet.core.errors.ArgumentError: samples is ragged (rows of different lengths): give one row per sample: ...
    """
    if samples is None or isinstance(samples, (str, bytes, dict, set, frozenset)) or callable(samples):
        raise ArgumentTypeError(f"{name} is a {type(samples).__name__}: {_SAMPLES}")
    try:
        x = np.asarray(samples)
    except ValueError:
        raise ArgumentError(f"{name} is ragged (rows of different lengths): {_SAMPLES}") from None
    except (TypeError, OverflowError) as error:
        raise ArgumentTypeError(f"{name} is not an array of numbers ({error}): {_SAMPLES}") from None
    kind = x.dtype.kind
    if kind == "O":  # Python ints beyond int64, Fractions, sympy numbers, or anything else
        odd = [v for v in x.flat if isinstance(v, (str, bytes, complex)) or not isinstance(v, Number)]
        if odd:
            bad = odd[0]
            raise ArgumentTypeError(f"{name} holds {bad!r}, not a real number: {_SAMPLES}")
        try:
            x = x.astype(float)
        except OverflowError:
            raise ArgumentError(f"{name} holds a number too large for a float: {_SAMPLES}") from None
        except (TypeError, ValueError):
            raise ArgumentTypeError(f"{name} holds an entry that is not a real number: {_SAMPLES}") from None
        kind = "f"
    if kind == "c":
        raise ArgumentTypeError(f"{name} holds complex numbers: {_SAMPLES} (real numbers)")
    if kind not in "biuf":
        example = next(iter(x.flat), None) if x.size else None
        raise ArgumentTypeError(f"{name} holds {example!r} (dtype {x.dtype}), not numbers: {_SAMPLES}")
    x = x.astype(float)
    if x.ndim == 0:
        raise ArgumentError(f"{name} is a single number: {_SAMPLES}")
    if x.shape[0] == 0:
        raise ArgumentError(f"{name} is empty (0 rows): {_SAMPLES}")
    if x.size == 0:
        raise ArgumentError(f"{name} has rows of no values (shape {x.shape}): {_SAMPLES}")
    if not np.isfinite(x).all():
        at = tuple(int(k) for k in np.argwhere(~np.isfinite(x))[0])
        raise ArgumentError(f"{name} holds {x[at]} at {at}: every sample must be a finite number")
    return x


def compare(samples: ArrayLike, exact: Any, *, chain: bool = False, alpha: float = 1e-3,
            keys: Sequence[Any] | None = None, bounds: Sequence[Any] | None = None,
            hotelling: bool | None = None, **batching: Any) -> TableAgreement:
    """The whole-table comparison of ``samples`` with ``exact`` (see the module docstring).

    Parameters
    ----------
    samples : array_like, shape (K, ...)
        Independent samples, or the steps of a Markov chain (``chain=True``).
    exact : scalar, array, nested (ragged) sequence or forcenet.Table
        The exact means, shaped like one sample; ``None``/missing: not tested. A
        :class:`forcenet.Table` stands for its ``mean_W``; a project table
        (carrying its bounds) with fewer rows than the samples is refused.
    chain : bool
        The rows are successive states of a Markov chain: spaced batch means
        (:func:`forcenet.numeric.autocorr.batch_means`; ``batching`` passes
        ``batch_factor``, ``gap_factor``, ``pilot``, ``max_batches``,
        ``min_batches``). With ``chain=False`` rows that look autocorrelated
        (integrated time above ``max(3.5, 1 + 80/sqrt(n))`` on 500 rows or more) are refused.
    alpha : float
        The test's level: a correct sampler fails with probability at most ``alpha``.
    keys : sequence, optional
        One name per tested value (row-major order); default: 1-based indices,
        ``(i, j)`` for a table (the thesis's grain ``(i, j)``).
    bounds : (lo, hi) or False, optional
        Every sample of a value lies in ``[lo, hi]``; each a number or a table
        shaped like ``exact``. Independent samples then get the bounded test,
        valid at every number of samples; samples or exact values outside are
        refused (``ArgumentError``). Default: the bounds the exact table
        carries (the project's tables do: ``mean_W(N)`` and
        ``moment_table(N, s)`` in ``[0, 1]``, ``exact_mean_W(scene)`` in
        ``[0, the row's load]``; :class:`forcenet.exact.protocol.BoundedTable`),
        else none. ``False``: none, not even the table's (the t route).
    hotelling : bool, optional
        ``None``: run Hotelling's test when the rows suffice (see
        :mod:`forcenet.numeric.agreement`); ``False``: only the maximum. The
        t route only.
    **batching
        With ``chain=True``: ``batch_factor``, ``gap_factor``, ``pilot``,
        ``max_batches``, ``min_batches`` of
        :func:`forcenet.numeric.autocorr.batch_means`.

    Returns
    -------
    TableAgreement
        ``verdict`` (``"agrees"``, ``"DISAGREES"``, ``"cannot judge"`` with its
        ``reason``), ``passed``, ``summary()``, ``message()``, ``worst_values(k)``,
        the z-scores and ``tau``.

    Raises
    ------
    forcenet.numeric.autocorr.AutocorrError
        If a chain is too short to trust.
    ArgumentError
        On shapes that do not match, non-finite samples, or independent rows that look like a chain.

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> compare(rng.uniform(size=400), 0.5, bounds=(0, 1)).passed   # one value in [0, 1]
    True
    >>> print(compare(rng.exponential(size=400), 1.0).reason)       # doctest: +ELLIPSIS
    400 rows are too few for the t statistics without bounds: value is skewed (sample skewness ...
    >>> compare(rng.normal(0.5, 1, size=400), 0.5).passed
    True
    >>> compare(np.cumsum(rng.normal(size=4000)), 0.0)
    Traceback (most recent call last):
    ...
    forcenet.core.errors.ArgumentError: samples look autocorrelated (integrated time ...): pass chain=True
    """
    chain = _flag(chain, "chain")
    hotelling = _flag(hotelling, "hotelling", none_ok=True)
    if hasattr(exact, "mean_W") and hasattr(exact, "moments"):  # a forcenet.Table: its <W_ij>, with their bounds
        exact = exact.mean_W
    alpha = _alpha(alpha)
    x = samples_array(samples)
    shape = x.shape[1:]
    mu = exact_array(exact, shape)
    if getattr(exact, "bounds", None) is not None and shape and len(exact) < shape[0]:  # a whole project table
        raise ArgumentError(f"exact is a table of {len(exact)} rows, fewer than the samples' first axis of length "
                            f"{shape[0]} (one sample has shape {shape}): give samples and exact of the same table")
    tested = ~np.isnan(mu)
    if not tested.any():
        raise ArgumentError("exact has no value to test: give at least one number (None marks a value not to test)")
    positions = np.argwhere(tested) if shape else np.zeros((1, 0), dtype=int)
    flat = x.reshape(x.shape[0], -1)[:, tested.ravel()]
    try:
        names = _default_keys(shape, positions) if keys is None else list(keys)
    except TypeError:
        raise ArgumentTypeError(f"keys={keys!r} is not a sequence: give one name per tested value") from None
    if len(names) != flat.shape[1]:
        raise ArgumentError(f"keys has {len(names)} names for {flat.shape[1]} tested values: give one per value")
    unknown = sorted(set(batching) - _BATCHING)
    if unknown:
        raise ArgumentTypeError(f"compare() got unexpected keywords {unknown}: the batch options of a chain are "
                                f"{sorted(_BATCHING)}")
    source = None
    if bounds is None and getattr(exact, "bounds", None) is not None:  # the project's tables carry their bounds
        bounds, source = exact.bounds, getattr(exact, "observable", "") or "the exact table's bounds"
    if bounds is False:
        bounds = None
    if bounds is not None:
        bounds = _bounds_array(bounds, shape, tested)
    try:
        if chain:
            return compare_chain(flat, mu[tested], keys=names, alpha=alpha, hotelling=hotelling, bounds=bounds,
                                 **batching)
        if batching:
            raise ArgumentTypeError(f"{sorted(batching)}: batch options apply to chains (chain=True)")
        tau = _autocorrelated(flat)
        if tau is not None:
            raise ArgumentError(f"samples look autocorrelated (integrated time {tau:.2g}): pass chain=True")
        return compare_samples(flat, mu[tested], keys=names, alpha=alpha, hotelling=hotelling, bounds=bounds)
    except ArgumentError as error:
        if source is None or "bounds" not in str(error):
            raise
        raise ArgumentError(f"{error} [bounds from the exact table: {source}; pass bounds=(lo, hi) for others, or "
                            f"bounds=False for none]") from None


def assert_agrees(samples: ArrayLike, exact: Any, **options: Any) -> TableAgreement:
    """:func:`compare`, raising :class:`DisagreementError` (an ``AssertionError``) when the table disagrees.

    The message names the worst values, their z-scores and (for a chain)
    their integrated times. Raises :class:`CannotJudgeError` (an
    ``AssertionError`` too) when the samples cannot support a verdict.
    Returns the report when the table agrees.

    Parameters
    ----------
    samples : array_like, shape (K, ...)
        Independent samples, or the steps of a Markov chain (``chain=True``).
    exact : scalar, array, nested (ragged) sequence or forcenet.Table
        The exact means, shaped like one sample; ``None``/missing: not tested. A
        :class:`forcenet.Table` stands for its ``mean_W``; a project table
        (carrying its bounds) with fewer rows than the samples is refused.
    **options
        ``chain``, ``alpha``, ``keys``, ``bounds``, ``hotelling`` and the batch
        options of :func:`compare`.

    Returns
    -------
    TableAgreement
        The report, when the table agrees.

    Raises
    ------
    DisagreementError
        If the table disagrees at level ``alpha`` (an ``AssertionError``).
    CannotJudgeError
        If the samples cannot support a verdict (an ``AssertionError``).
    ArgumentError
        On the bad input :func:`compare` refuses.

    Examples
    --------
    >>> from forcenet.exact import mean_W
    >>> from forcenet.numeric.triangle.metropolis import q_model_samples
    >>> W = q_model_samples(5, 4000, np.random.default_rng(0))   # i.i.d. q: not the ensemble
    >>> assert_agrees(W, mean_W(5))
    Traceback (most recent call last):
    ...
    forcenet.testing.assertions.DisagreementError: sampled means DISAGREE with the exact values at level 0.001
      worst values: (3, 2): mean 0.497 vs exact 0.3788, z = +31.81; (4, 4): mean 0.1262 vs exact 0.1818, z = -23.53; ...
    """
    report = compare(samples, exact, **options)
    if report.verdict == "cannot judge":
        raise CannotJudgeError(report)
    if not report.passed:
        raise DisagreementError(report)
    return report


def assert_means_agree(mean: ArrayLike, stderr: ArrayLike, exact: Any, *, alpha: float = 1e-3,
                       keys: Sequence[Any] | None = None, df: int | None = None) -> TableAgreement:
    """Means with standard errors you trust (e.g. ``mean_and_stderr``) against exact values.

    Only the Bonferroni maximum (no covariance); ``df=None`` takes the
    z-scores as standard normal. Prefer :func:`assert_agrees` on the
    samples themselves: the Student t of its batch means accounts for the
    uncertainty of the standard errors, this one does not.

    Parameters
    ----------
    mean : array_like
        The estimated means.
    stderr : array_like
        Their standard errors (broadcast to ``mean``'s shape).
    exact : scalar, array or nested (ragged) sequence
        The exact means, shaped like ``mean``; ``None``/missing: not tested.
    alpha : float
        The test's level.
    keys : sequence, optional
        One name per tested value (default: 1-based indices).
    df : int, optional
        Degrees of freedom of a Student t for the z-scores (``None``: normal).

    Returns
    -------
    TableAgreement
        The report, when the means agree.

    Raises
    ------
    DisagreementError
        If the means disagree at level ``alpha`` (an ``AssertionError``).
    ArgumentError
        If ``exact`` does not fit ``mean``'s shape.

    Examples
    --------
    >>> assert_means_agree([0.5, 0.26], [0.01, 0.01], [0.5, 0.25]).passed
    True
    """
    mean = np.asarray(mean, dtype=float)
    mu = exact_array(exact, mean.shape)
    tested = ~np.isnan(mu)
    positions = np.argwhere(tested) if mean.shape else np.zeros((1, 0), dtype=int)
    names = _default_keys(mean.shape, positions) if keys is None else list(keys)
    stderr = np.broadcast_to(np.asarray(stderr, dtype=float), mean.shape)
    report = compare_means(mean[tested], stderr[tested], mu[tested], keys=names, alpha=alpha, df=df)
    if not report.passed:
        raise DisagreementError(report)
    return report
