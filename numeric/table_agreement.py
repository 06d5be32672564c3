"""The report of a whole-table comparison: :class:`TableAgreement`, its verdict and its wording.

:mod:`forcenet.numeric.agreement` runs the tests (the bounded betting route
and the t route with its size rule) and returns this frozen report; the
testing toolkit (:mod:`forcenet.testing`) raises with its :meth:`~TableAgreement.message`
and the command line's cross-check prints its :meth:`~TableAgreement.plain` words.

Examples
--------
>>> report = TableAgreement(keys=("W_1",), mean=(1.02,), exact=(1.0,), stderr=(0.01,), z=(2.0,), df=None,
...                         alpha=1e-3, p_max=0.0455, level_max=1e-3)
>>> report.verdict, report.max_z
('agrees', 2.0)
"""

from __future__ import annotations

import math
import textwrap
from dataclasses import dataclass
from typing import Any

__all__ = ["TableAgreement"]


@dataclass(frozen=True)
class TableAgreement:
    """The outcome of a whole-table comparison (see :mod:`forcenet.numeric.agreement`).

    Per tested (varying) value, in the order of ``keys``: the sampled
    ``mean``, the ``exact`` value, the ``stderr`` of the mean, ``z`` and, for
    a chain, its integrated time ``tau``. ``fixed`` lists the values that
    never vary as ``(key, sampled, exact)``. Built by
    :func:`~forcenet.numeric.agreement.compare_samples`,
    :func:`~forcenet.numeric.agreement.compare_chain` and
    :func:`~forcenet.numeric.agreement.compare_means`, not by hand.

    Parameters
    ----------
    keys : tuple
        The tested values' names (e.g. ``"W_1"`` or ``(i, j)``).
    mean, exact, stderr, z : tuple of float
        Per key: the sampled mean, the exact value, the standard error of the
        mean and ``z = (mean - exact) / stderr``.
    df : int or None
        Degrees of freedom of Student's t for ``z`` (``None``: standard normal).
    alpha : float
        The false-alarm rate of the whole table.
    p_max, level_max : float
        The Bonferroni p-value of the largest ``|z|`` and the level it is tested at.
    chi2 : float or None
        Hotelling's statistic (``None`` when not run).
    dof : int
        Its degrees of freedom (the covariance's rank).
    p_chi2 : float or None
        Its p-value.
    level_chi2 : float
        The level it is tested at.
    fixed : tuple
        The values that never vary, as ``(key, sampled, exact)``.
    samples : int
        Rows, or steps of a chain.
    tau : tuple of float or None
        A chain's integrated autocorrelation time per key.
    batches, batch_length, batch_gap, pilot : int or None
        A chain's batch means: their number, length and spacing, and the
        steps ``tau`` was measured on.
    method : str
        ``"t"`` or ``"bounded"`` (the betting test).
    reason : str or None
        Why the statistics cannot judge (``None`` when they can).
    fixed_certain : bool
        A fixed value that differs is a certain failure.
    judged : bool
        The size rule lets the t route judge.
    skew_term : float or None
        The skewness term ``u`` of the t tail.
    p_bound, z_bound : float or None
        The distribution-free bound's p-value and largest ``z``.

    Examples
    --------
    >>> from forcenet.numeric.agreement import compare_means
    >>> report = compare_means([1.02, 1.9], [0.01, 0.05], [1.0, 2.0], keys=["W_1", "W_2"])
    >>> report.verdict, report.keys
    ('agrees', ('W_1', 'W_2'))
    """

    keys: tuple
    mean: tuple
    exact: tuple
    stderr: tuple
    z: tuple
    df: int | None
    alpha: float
    p_max: float
    level_max: float
    chi2: float | None = None
    dof: int = 0
    p_chi2: float | None = None
    level_chi2: float = 0.0
    fixed: tuple = ()
    samples: int = 0
    tau: tuple | None = None
    batches: int | None = None
    batch_length: int | None = None
    batch_gap: int | None = None
    pilot: int | None = None
    method: str = "t"
    reason: str | None = None
    fixed_certain: bool = False
    judged: bool = True
    skew_term: float | None = None
    p_bound: float | None = None
    z_bound: float | None = None

    @property
    def values(self) -> int:
        """Number of values tested statistically.

        Examples
        --------
        >>> from forcenet.numeric.agreement import compare_means
        >>> report = compare_means([1.02, 1.9], [0.01, 0.05], [1.0, 2.0], keys=["W_1", "W_2"])
        >>> report.values
        2
        """
        return len(self.keys)

    @property
    def max_z(self) -> float:
        """The largest ``|z|`` over the tested values (0 when none is tested).

        Examples
        --------
        >>> from forcenet.numeric.agreement import compare_means
        >>> report = compare_means([1.02, 1.9], [0.01, 0.05], [1.0, 2.0], keys=["W_1", "W_2"])
        >>> round(report.max_z, 6)
        2.0
        """
        return max((abs(z) for z in self.z), default=0.0)

    @property
    def worst(self) -> Any:
        """The key of the largest ``|z|`` (``None`` when no value is tested).

        Examples
        --------
        >>> from forcenet.numeric.agreement import compare_means
        >>> report = compare_means([1.02, 1.9], [0.01, 0.05], [1.0, 2.0], keys=["W_1", "W_2"])
        >>> report.worst
        'W_1'
        """
        return self.worst_values(1)[0][1] if self.keys else None

    @property
    def rms_z(self) -> float:
        """The root mean square of ``z`` over the tested values (0 when none is tested).

        Examples
        --------
        >>> from forcenet.numeric.agreement import compare_means
        >>> report = compare_means([1.02, 1.9], [0.01, 0.05], [1.0, 2.0], keys=["W_1", "W_2"])
        >>> round(report.rms_z, 6)
        2.0
        """
        return math.sqrt(sum(z * z for z in self.z) / len(self.z)) if self.z else 0.0

    @property
    def z_scores(self) -> tuple:
        """``(z, key)`` for every tested value.

        Examples
        --------
        >>> from forcenet.numeric.agreement import compare_means
        >>> report = compare_means([1.02, 1.9], [0.01, 0.05], [1.0, 2.0], keys=["W_1", "W_2"])
        >>> [(round(z, 6), key) for z, key in report.z_scores]
        [(2.0, 'W_1'), (-2.0, 'W_2')]
        """
        return tuple(zip(self.z, self.keys))

    @property
    def fixed_failures(self) -> tuple:
        """The fixed values whose sample differs from the exact value.

        Examples
        --------
        >>> import numpy as np
        >>> from forcenet.numeric.agreement import compare_samples
        >>> rows = np.column_stack([np.random.default_rng(0).normal(size=400), np.ones(400)])
        >>> compare_samples(rows, [0.0, 1.5], keys=["W_1", "W_2"]).fixed_failures
        (('W_2', 1.0, 1.5),)
        """
        return tuple(f for f in self.fixed if not _same(f[1], f[2]))

    @property
    def disagrees(self) -> bool:
        """A disagreement the statistics support (at level ``alpha``), whatever else is said.

        A fixed value that differs is one for the bounded test (an exact mean at the end of its range is
        that end); for the t route a value constant in the sample may still vary: ``reason`` says so.
        Below the size where the t statistics keep their level (``judged`` False) they support nothing.

        Examples
        --------
        >>> from forcenet.numeric.agreement import compare_means
        >>> report = compare_means([1.02, 1.9], [0.01, 0.05], [1.0, 2.0], keys=["W_1", "W_2"])
        >>> report.disagrees
        False
        >>> compare_means([1.2], [0.01], [1.0]).disagrees  # 20 standard errors off
        True
        """
        if self.fixed_failures and self.fixed_certain:
            return True
        if not self.judged:  # only what is overwhelming without a distribution (.chebyshev)
            return self.p_bound is not None and self.p_bound <= self.alpha
        if self.p_max <= self.level_max:
            return True
        return self.p_chi2 is not None and self.p_chi2 <= self.level_chi2

    @property
    def verdict(self) -> str:
        """``"agrees"``, ``"DISAGREES"`` or ``"cannot judge"`` (then ``reason`` says why).

        Examples
        --------
        >>> from forcenet.numeric.agreement import compare_means
        >>> report = compare_means([1.02, 1.9], [0.01, 0.05], [1.0, 2.0], keys=["W_1", "W_2"])
        >>> report.verdict
        'agrees'
        """
        if self.disagrees:
            return "DISAGREES"
        return "cannot judge" if self.reason else "agrees"

    @property
    def passed(self) -> bool:
        """The table agrees: no disagreement, and the statistics can judge it.

        Examples
        --------
        >>> from forcenet.numeric.agreement import compare_means
        >>> report = compare_means([1.02, 1.9], [0.01, 0.05], [1.0, 2.0], keys=["W_1", "W_2"])
        >>> report.passed
        True
        """
        return self.verdict == "agrees"

    def worst_values(self, k: int = 3) -> list[tuple[float, Any]]:
        """The ``k`` largest ``(|z|, key)``, largest first (``z`` signed).

        Parameters
        ----------
        k : int, default 3
            How many values.

        Returns
        -------
        list of (float, key)
            ``(z, key)`` by decreasing ``|z|`` (ties in the order of ``keys``).

        Examples
        --------
        >>> from forcenet.numeric.agreement import compare_means
        >>> report = compare_means([1.02, 1.9], [0.01, 0.05], [1.0, 2.0], keys=["W_1", "W_2"])
        >>> [(round(z, 6), key) for z, key in report.worst_values(1)]
        [(2.0, 'W_1')]
        """
        order = sorted(range(len(self.z)), key=lambda n: -abs(self.z[n]))[:k]
        return [(self.z[n], self.keys[n]) for n in order]

    def _chain_line(self) -> str:
        if self.tau is None:
            return ""
        return (
            f"chain of {self.samples} steps, tau = {max(self.tau):.3g} (largest over {self.values} values, "
            f"measured on the first {self.pilot}): {self.batches} batch means of {self.batch_length} steps "
            f"{self.batch_gap} apart, Student t with {self.df} dof\n"
        )

    def _verdict_line(self) -> str:
        if self.verdict == "cannot judge":
            return f"cannot judge: {self.reason}"
        return (f"{self.verdict} at level {self.alpha:g} "
                f"(a correct sampler fails at most {self.alpha:g} of the time)")

    def summary(self) -> str:
        """A few lines for a report: the tests run, their p-values and levels, the verdict.

        Returns
        -------
        str
            The statistics' details (:meth:`plain` says the verdict in words).

        Examples
        --------
        >>> from forcenet.numeric.agreement import compare_means
        >>> report = compare_means([1.02, 1.9], [0.01, 0.05], [1.0, 2.0], keys=["W_1", "W_2"])
        >>> print(report.summary())  # doctest: +ELLIPSIS
        Hotelling chi2 not run (too few rows for the covariance); max |z| = 2.00 at W_1 (Bonferroni p = 0.091 ...
        agrees at level 0.001 (a correct sampler fails at most 0.001 of the time)
        """
        lines = []
        if self.method == "bounded":
            lines.append(
                f"bounded test (betting, valid at any number of rows): Bonferroni p = {self.p_max:.3g} "
                f"over {self.values} values, tested at {self.level_max:g}; max |z| = {self.max_z:.2f} at "
                f"{str(self.worst)}; Hotelling chi2 not run (its level is only asymptotic)\n")
        else:
            if self.p_chi2 is not None:
                lines.append(
                    f"Hotelling chi2 = {self.chi2:.1f} on {self.dof} degrees of freedom "
                    f"(p = {self.p_chi2:.3g}, tested at {self.level_chi2:g}); "
                )
            else:
                lines.append("Hotelling chi2 not run (too few rows for the covariance); ")
            lines[-1] += (
                f"max |z| = {self.max_z:.2f} at {str(self.worst)} "
                f"(Bonferroni p = {self.p_max:.3g} over {self.values} values, tested at {self.level_max:g})\n"
            )
        if self.fixed:
            bad = self.fixed_failures
            lines.append(f"{len(self.fixed)} fixed values compared exactly: "
                         + ("all equal\n" if not bad else f"{len(bad)} differ\n"))
        lines.append(self._chain_line())
        if self.p_bound is not None:
            lines.append(f"distribution-free bound (Markov on the error's second or, within bounds, fourth moment, "
                         f"its variance bounded above): largest z = {self.z_bound:.3g}, p = {self.p_bound:.3g}\n")
        lines.append(self._verdict_line())
        return "".join(lines)

    def plain(self) -> str:
        """The verdict in plain words, lines of at most 78 columns (:meth:`summary`: the statistics' details).

        Returns
        -------
        str
            The verdict and the largest deviation, wrapped at 78 columns.

        Examples
        --------
        >>> from forcenet.numeric.agreement import compare_means
        >>> report = compare_means([1.02, 1.9], [0.01, 0.05], [1.0, 2.0], keys=["W_1", "W_2"])
        >>> print(report.plain())
        agrees with the exact values within the statistical errors; the largest
        deviation is 2.0 standard errors, at W_1 (sampled 1.02, exact 1) (a correct
        sampler fails this check at most 0.10% of the time)
        """
        n = max(range(len(self.z)), key=lambda m: abs(self.z[m]), default=None)
        worst = "" if n is None else (f"the largest deviation is {abs(self.z[n]):.1f} standard errors, at {self.keys[n]} "
                                      f"(sampled {self.mean[n]:.4g}, exact {self.exact[n]:.4g})")
        text = {"cannot judge": f"cannot judge: {self.reason}",
                "DISAGREES": f"DISAGREES with the exact values: {worst or 'a fixed value differs'}",
                "agrees": "agrees with the exact values within the statistical errors" + (f"; {worst}" if worst else "")
                }[self.verdict] + f" (a correct sampler fails this check at most {self.alpha:.2%} of the time)"
        return textwrap.fill(text, 78, break_on_hyphens=False)

    def message(self, k: int = 3) -> str:
        """The failure message: the worst values with their z (and tau), then the summary.

        Parameters
        ----------
        k : int, default 3
            How many of the worst values to show.

        Returns
        -------
        str
            The message :class:`forcenet.testing.DisagreementError` carries.

        Examples
        --------
        >>> from forcenet.numeric.agreement import compare_means
        >>> report = compare_means([1.02, 1.9], [0.01, 0.05], [1.0, 2.0], keys=["W_1", "W_2"])
        >>> print(report.message(1).splitlines()[1])
          worst values: W_1: mean 1.02 vs exact 1, z = +2.00
        """
        head = {"agrees": "sampled means agree with the exact values",
                "DISAGREES": "sampled means DISAGREE with the exact values",
                "cannot judge": "sampled means CANNOT BE JUDGED against the exact values"}[self.verdict]
        parts = []
        index = {key: n for n, key in enumerate(self.keys)}
        for z, key in self.worst_values(k):
            n = index[key]
            text = f"{str(key)}: mean {self.mean[n]:.4g} vs exact {self.exact[n]:.4g}, z = {z:+.2f}"
            if self.tau is not None:
                text += f", tau = {self.tau[n]:.3g}"
            parts.append(text)
        lines = [f"{head} at level {self.alpha:g}", "  worst values: " + "; ".join(parts)]
        for key, sampled, exact in self.fixed_failures[:k]:
            why = "its exact mean is an end of its range" if self.fixed_certain else "never varies"
            lines.append(f"  fixed value {str(key)}: sampled {sampled!r} ({why}), exact {exact!r}")
        lines += ["  " + line for line in self.summary().splitlines()]
        return "\n".join(lines)

    __str__ = message


def _same(a: float, b: float) -> bool:
    return abs(a - b) <= 1e-9 * max(1.0, abs(b))
