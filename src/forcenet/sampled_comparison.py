"""An exact pooled ``P(f)`` against the exact sampler's and Metropolis's histograms (``forcenet dist --plot``).

:meth:`forcenet.Law.compare_with_samples` draws both samplers' histograms of
the pooled force ``f = i W_ij`` (a layer's, or every grain of layers
``2..N``) on equal bins of ``[0, f_max]``, and sets them against the exact
bin masses of the law's density (Eqs. (4.5)-(4.9) pooled): a chi-square per
sampler (error bars from the integrated autocorrelation time for the chain,
Sec. 3.2.4) and a two-panel figure.  :meth:`forcenet.LawPlan.with_sampled_comparison`
plans the law and the comparison as one run, the announcement of
``forcenet dist --plot``.

Examples
--------
>>> import forcenet
>>> c = forcenet.law(5, layer=5).compare_with_samples(samples=400, sweeps=400, bins=8, seed=1)
>>> list(c.histograms)
['exact sampler, 400 samples', 'Metropolis, 400 sweeps']
>>> sum(c.exact_bins), c.law.cdf_at(4)  # the exact mass of [0, f_max]: f = 5 W reaches 5
(Fraction(1952448, 1953125), Fraction(1952448, 1953125))
"""

from __future__ import annotations

from dataclasses import dataclass, field
from fractions import Fraction
from typing import TYPE_CHECKING, Any, Generic, Protocol, TypeVar

from forcenet.core.errors import ArgumentError
from forcenet.core.plan import Plan, combine
from forcenet.core.validation import available_memory, check_int, check_real
from forcenet.costed_plans import CostedPlan, Progress
from forcenet.exact.triangle.distribution import bin_probabilities
from forcenet.numeric.triangle.exact_sampler import sample_plan
from forcenet.numeric.triangle.force_distribution import (
    chi_square,
    comparison_png,
    exact_sampler_histogram,
    histogram_edges,
    metropolis_histogram,
)
from forcenet.numeric.triangle.metropolis import metropolis_plan
from forcenet.rendering import Rendered

if TYPE_CHECKING:  # pragma: no cover - annotations only
    import numpy as np

    from forcenet.numeric.triangle.force_distribution import Histogram

__all__ = ["SampledComparison", "SampledComparisonPlan"]



class _PooledLaw(Protocol):  # what the comparison reads of a forcenet.Law (forcenet.law_results imports this module)
    N: int
    pool: str | int | None
    density: list[Any]


L = TypeVar("L", bound=_PooledLaw)
L_co = TypeVar("L_co", bound=_PooledLaw, covariant=True)


class _LawPlan(Protocol[L_co]):  # what it reads of a forcenet.LawPlan (forcenet.laws imports this module)
    @property
    def cost(self) -> Plan: ...

    def run(self, progress: Progress | bool | None = None) -> L_co: ...

MAX_BINS = 1000


class SampledComparison(Rendered, Generic[L]):
    """An exact pooled ``P(f)`` against sampled histograms: what :meth:`forcenet.Law.compare_with_samples` returns.

    Parameters
    ----------
    law : forcenet.Law
        The exact pooled law (a layer's or the ensemble's).
    edges : numpy.ndarray
        The ``bins + 1`` edges of equal bins of ``[0, f_max]``.
    exact_bins : list of Fraction
        The exact mass of every bin.
    histograms : dict
        A label (``"exact sampler, K samples"``, ``"Metropolis, S sweeps"``) to its sampled histogram
        (``density``, ``stderr``, ``tau``, ``reliable``).

    Examples
    --------
    >>> import forcenet
    >>> c = forcenet.law(4).compare_with_samples(samples=300, sweeps=300, bins=5, seed=3)
    >>> c
    SampledComparison(N=4, pool='ensemble', bins=5)
    >>> c.notes[0]  # doctest: +ELLIPSIS
    'exact sampler: chi2 = ... over 5 bins (p = ...), tau = 1.0'
    """

    def __init__(self, law: L, edges: np.ndarray, exact_bins: list[Fraction], histograms: dict[str, Histogram]):
        self.law, self.edges, self.exact_bins, self.histograms = law, edges, exact_bins, dict(histograms)

    def __repr__(self) -> str:
        return f"SampledComparison(N={self.law.N}, pool={self.law.pool!r}, bins={len(self.exact_bins)})"

    @property
    def chi_squares(self) -> dict[str, tuple[float, int, float]]:
        """``(chi2, bins, p)`` of every histogram against the exact bin masses (bins with a nonzero error bar).

        Examples
        --------
        >>> import forcenet
        >>> c = forcenet.law(4, layer=4).compare_with_samples(samples=500, sweeps=500, bins=4, seed=2)
        >>> [bins for _, bins, _ in c.chi_squares.values()]
        [4, 4]
        """
        return {label: chi_square(h, self.exact_bins) for label, h in self.histograms.items()}

    @property
    def notes(self) -> list[str]:
        """One line per sampler: its chi-square, the bins, ``p`` and ``tau`` (a chain shorter than 50 ``tau`` flagged),
        the lines ``forcenet dist --plot`` prints on stderr.

        Examples
        --------
        >>> import forcenet
        >>> c = forcenet.law(5).compare_with_samples(samples=200, sweeps=20, bins=6, seed=1)
        >>> c.notes[1]  # doctest: +ELLIPSIS
        'Metropolis: chi2 = ...; chain shorter than 50 tau (tau = ... sweeps): error bars unreliable'
        """
        notes = []
        for label, (chi2, bins, p) in self.chi_squares.items():
            h = self.histograms[label]
            flag = "" if h.reliable else f"; chain shorter than 50 tau (tau = {h.tau:.0f} sweeps): error bars unreliable"
            notes.append(f"{label.split(',')[0]}: chi2 = {chi2:.1f} over {bins} bins (p = {p:.2g}), tau = {h.tau:.1f}"
                         f"{flag}")
        return notes

    @property
    def title(self) -> str:
        """The figure's title: the law, its pool, and the notes.

        Examples
        --------
        >>> import forcenet
        >>> c = forcenet.law(4, layer=3).compare_with_samples(samples=200, sweeps=200, bins=4, seed=1)
        >>> c.title.splitlines()[0]
        'N = 4: exact P(f) (layer 3, f = 3 W_3,j) against sampled histograms (1 sigma error bars)'
        """
        pool = self.law.pool
        pool_text = "every grain of layers 2..N, f = i W_ij" if pool == "ensemble" else f"layer {pool}, f = {pool} W_{pool},j"
        return (f"N = {self.law.N}: exact P(f) ({pool_text}) against sampled histograms (1 sigma error bars)\n"
                + "; ".join(self.notes))

    def to_dict(self) -> dict[str, Any]:
        """The exact bin masses, every sampler's chi-square against them and the notes.

        Returns
        -------
        dict
            ``N``, ``pool``, ``edges``, ``exact_bins`` (exact, as ``"p/q"``), ``chi_squares`` (per sampler:
            ``chi2``, ``bins``, ``p``) and ``notes``.

        Examples
        --------
        >>> import forcenet
        >>> c = forcenet.law(4, layer=4).compare_with_samples(samples=500, sweeps=500, bins=4, seed=2)
        >>> sorted(c.to_dict())
        ['N', 'chi_squares', 'edges', 'exact_bins', 'notes', 'pool']
        """
        return {"N": self.law.N, "pool": self.law.pool, "edges": [float(x) for x in self.edges],
                "exact_bins": [f"{x.numerator}/{x.denominator}" if x.denominator != 1 else str(x.numerator)
                               for x in self.exact_bins],
                "chi_squares": {label.split(",")[0]: {"chi2": chi2, "bins": bins, "p": p}
                                for label, (chi2, bins, p) in self.chi_squares.items()},
                "notes": self.notes}

    def to_text(self) -> str:
        """The comparison in words: the title's first line, then one line per sampler.

        Returns
        -------
        str

        Examples
        --------
        >>> import forcenet
        >>> c = forcenet.law(4, layer=4).compare_with_samples(samples=500, sweeps=500, bins=4, seed=2)
        >>> c.to_text().splitlines()[0]
        'N = 4: exact P(f) (layer 4, f = 4 W_4,j) against sampled histograms (1 sigma error bars)'
        """
        return "\n".join([self.title.splitlines()[0], *(f"  {note}" for note in self.notes)])

    def png(self) -> bytes:
        """The figure as PNG bytes: the exact ``P(f)`` (curve and bin averages) against the histograms with error
        bars, linear and logarithmic (``forcenet dist --plot`` writes these bytes).

        Returns
        -------
        bytes

        Examples
        --------
        >>> import forcenet
        >>> c = forcenet.law(4).compare_with_samples(samples=200, sweeps=200, bins=4, seed=1)
        >>> c.png()[:8]
        b'\\x89PNG\\r\\n\\x1a\\n'
        """
        return comparison_png(self.law.density, self.exact_bins, self.histograms, self.title, float(self.edges[-1]))

    def _repr_png_(self) -> bytes:
        return self.png()


@dataclass(frozen=True, repr=False)  # the plan's own words: CostedPlan.__repr__
class SampledComparisonPlan(CostedPlan, Generic[L]):
    """A checked comparison of an exact pooled ``P(f)`` with sampled histograms, with its cost (the law's too when it
    is still to be computed): what :meth:`forcenet.LawPlan.with_sampled_comparison` returns.

    Parameters
    ----------
    N : int
        Number of layers.
    pool : "ensemble" or int
        The pooled force: every grain of layers ``2..N``, or layer ``i``.
    samples : int
        Exact samples.
    sweeps : int
        Metropolis sweeps (burn-in ``max(100, sweeps // 10)``).
    bins : int
        Equal bins of ``[0, f_max]``.
    f_max : float
        The histograms' range.
    seed : int
        Both samplers' seed.
    cost : forcenet.core.plan.Plan
        Estimated seconds, peak bytes, progress ticks (the law's, then the samplers'), or the refusal.
    law_plan : forcenet.LawPlan, optional
        The law still to compute (None when ``law`` is given).
    law : forcenet.Law, optional
        The law already computed.

    Examples
    --------
    >>> import forcenet
    >>> p = forcenet.law_plan(6).with_sampled_comparison(samples=1000, sweeps=500)
    >>> p.cost.what
    'exact ensemble P(f) N=6 (5 passes) with its sampled comparison'
    """

    N: int
    pool: str | int
    samples: int
    sweeps: int
    bins: int
    f_max: float
    seed: int
    cost: Plan
    law_plan: _LawPlan[L] | None = field(default=None, repr=False)
    law: L | None = field(default=None, repr=False)

    def run(self, progress: Progress | bool | None = None) -> SampledComparison[L]:
        """Compute the law (if the plan holds none), draw both histograms, and set them against the exact bins.

        Parameters
        ----------
        progress : callable, bool or None
            ``progress(k)`` with the plan's ticks (the law's, then samples and sweeps); ``True``: a progress bar.

        Returns
        -------
        SampledComparison

        Raises
        ------
        ArgumentError
            If the plan is refused.

        Examples
        --------
        >>> import forcenet
        >>> c = forcenet.law_plan(5, layer=4).with_sampled_comparison(samples=300, sweeps=300, bins=6).run()
        >>> c.law.quantity, len(c.exact_bins)
        ('P(f), f = 4 W_{4,j} (layer 4)', 6)
        """
        self.check()
        with self._ticks(progress, f"comparison N={self.N}") as tick:
            if self.law is not None:
                law = self.law
            elif self.law_plan is not None:
                law = self.law_plan.run(progress=tick)
            else:
                raise ArgumentError("this SampledComparisonPlan holds neither a law nor its plan: make it with "
                                    "forcenet.law_plan(...).with_sampled_comparison(...)")
            edges = histogram_edges(self.f_max, self.bins)
            exact_bins = bin_probabilities(law.density, edges)
            histograms = {
                f"exact sampler, {self.samples} samples": exact_sampler_histogram(
                    self.N, self.samples, edges, self.pool, self.seed, tick),
                f"Metropolis, {self.sweeps} sweeps": metropolis_histogram(
                    self.N, self.sweeps, edges, self.pool, seed=self.seed, progress=tick)}
        return SampledComparison(law, edges, exact_bins, histograms)


def comparison_plan(N: int, pool: Any, *, samples: Any, sweeps: Any, bins: Any, f_max: Any, seed: Any,
                    law_plan: _LawPlan[L] | None = None, law: L | None = None,
                    memory_bytes: int | None = None) -> SampledComparisonPlan[L]:
    """The checked comparison of the pooled law of ``law_plan`` (or of ``law``) and its cost (what the methods call).

    Parameters
    ----------
    N : int
        Number of layers.
    pool : "ensemble", int or None
        The law's pool (None: a grain's or a contact's law, refused).
    samples, sweeps, bins, f_max, seed
        As in :meth:`forcenet.Law.compare_with_samples`.
    law_plan : forcenet.LawPlan, optional
        The law still to compute: its cost comes first.
    law : forcenet.Law, optional
        The law already computed.
    memory_bytes : int, optional
        Memory the run may use; default: what the machine has available now.

    Returns
    -------
    SampledComparisonPlan

    Raises
    ------
    ArgumentError, ArgumentTypeError
        If the law is not a pooled ``P(f)``, or an argument is out of range.

    Examples
    --------
    >>> comparison_plan(6, "ensemble", samples=1000, sweeps=500, bins=10, f_max=4.0, seed=0).cost.ticks
    1500
    """
    if pool is None:
        raise ArgumentError("compare_with_samples compares a pooled P(f) with sampled histograms: make the law of a "
                            "layer (forcenet.law(N, layer=i)) or of the ensemble (forcenet.law(N))")
    samples, sweeps = check_int(samples, "samples", 2), check_int(sweeps, "sweeps", 2)
    bins, f_max = check_int(bins, "bins", 1, MAX_BINS), check_real(f_max, "f_max", 0, low_open=True)
    seed = check_int(seed, "seed", 0, 2**63 - 1)
    memory = (available_memory() or 16 * 2**30) if memory_bytes is None else check_int(memory_bytes, "memory_bytes", 1)
    burn = max(100, sweeps // 10)
    sampled = [sample_plan(N, samples, memory), metropolis_plan(N, sweeps, burn, memory)]
    if law_plan is not None:
        cost = combine(f"{law_plan.cost.what} with its sampled comparison", [law_plan.cost, *sampled], "step")
    else:
        cost = combine(f"sampled comparison N={N}, {samples} samples and {sweeps} sweeps", sampled, "step")
    return SampledComparisonPlan(N, pool, samples, sweeps, bins, f_max, seed, cost, law_plan, law)
