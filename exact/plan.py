"""What a long computation will cost, decided before it starts.

Every route of ``forcenet table`` (and every other long command) exposes a
*plan* and a *run*.  The plan is cheap: estimated seconds on the 2-core
reference machine, peak bytes, the number of progress ticks the run will
report, or a refusal with its reason (out of the route's range, or more
memory than the caller has).  The engines own their cost knowledge (measured
constants live next to the code they describe); the command line only asks,
announces, refuses or runs.

May import: nothing of the package.

Examples
--------
>>> plan = Plan("exact table N=20", seconds=3.2, nbytes=2**28, ticks=4, unit="pass")
>>> plan.describe()
'~3 s, ~0.25 GiB'
>>> Plan("x", 0, refusal="N=40 is out of range").runnable
False
"""

from __future__ import annotations

import time
from dataclasses import dataclass, replace

__all__ = ["Plan", "duration_text", "combine", "combine_by_time", "phase_progress", "first_moment_only", "chunks",
           "first_chunk", "CHUNK_SECONDS"]

CHUNK_SECONDS = 0.15  # compiled work per call: Ctrl-C is seen within this, the calls' overhead stays far below 1 %


def duration_text(seconds: float) -> str:
    """``seconds`` as a readable duration: 40 s, 12 min, 3.5 h, 90 days.

    Examples
    --------
    >>> duration_text(40), duration_text(720), duration_text(12600), duration_text(8e6)
    ('40 s', '12 min', '3.5 h', '93 days')
    """
    if seconds < 120:
        return f"{seconds:.0f} s"
    if seconds < 7200:
        return f"{seconds / 60:.0f} min"
    if seconds < 2 * 86400:
        return f"{seconds / 3600:.1f} h"
    return f"{seconds / 86400:.0f} days"


@dataclass(frozen=True)
class Plan:
    """The announced cost of a run.

    Attributes
    ----------
    what : str
        What will be computed, for the announcement.
    seconds : float
        Estimated wall time on the 2-core reference machine.
    nbytes : int
        Estimated peak memory.
    ticks : int
        Number of progress ticks the run reports (0: no progress bar).
    unit : str
        What one tick is (a grain, an ideal, a sample, ...).
    refusal : str or None
        Why the run cannot be done at all (range, memory); None if it can.
    """

    what: str
    seconds: float
    nbytes: int = 0
    ticks: int = 0
    unit: str = "step"
    refusal: str | None = None

    @property
    def runnable(self) -> bool:
        return self.refusal is None

    def describe(self) -> str:
        """``'~12 min, ~3.2 GiB'``."""
        text = f"~{duration_text(self.seconds)}"
        if self.nbytes:
            text += f", ~{self.nbytes / 2**30:.2g} GiB"
        return text

    def refuse(self, reason: str) -> "Plan":
        """The same plan, refused (the first reason wins)."""
        return self if self.refusal else replace(self, refusal=reason)

    def within_memory(self, memory_bytes: int | None) -> "Plan":
        """Refused if the peak memory exceeds ``memory_bytes`` (None: no check)."""
        if memory_bytes is None or self.nbytes <= memory_bytes:
            return self
        return self.refuse(
            f"{self.what} needs ~{self.nbytes / 2**30:.1f} GiB of memory but {memory_bytes / 2**30:.1f} GiB is available"
        )


def combine(what: str, plans, unit: str = "step") -> Plan:
    """One plan for several runs done one after the other (times and ticks add, memory is the peak).

    Examples
    --------
    >>> combine("both", [Plan("a", 2, 10, 3), Plan("b", 5, 30, 4)])
    Plan(what='both', seconds=7, nbytes=30, ticks=7, unit='step', refusal=None)
    """
    plans = list(plans)
    refusal = next((p.refusal for p in plans if p.refusal), None)
    return Plan(what, sum(p.seconds for p in plans), max((p.nbytes for p in plans), default=0),
                sum(p.ticks for p in plans), unit, refusal)


def combine_by_time(what: str, plans) -> Plan:
    """One plan for runs of different units (primes, samples) on one bar counted in estimated seconds.

    A phase's tick of ``k`` of its own units advances the bar by ``k`` times
    its seconds per unit (:func:`phase_progress`), so the bar's remaining time
    is right when the phases differ in speed.

    Examples
    --------
    >>> combine_by_time("both", [Plan("a", 20, 10, 4, "prime"), Plan("b", 5, 30, 1000, "sample")])
    Plan(what='both', seconds=25, nbytes=30, ticks=25, unit='s', refusal=None)
    """
    plans = list(plans)
    plan = combine(what, plans, "s")
    return Plan(plan.what, plan.seconds, plan.nbytes, max(1, round(plan.seconds)), "s", plan.refusal)


def phase_progress(progress, plan: Plan):
    """``progress`` (of a :func:`combine_by_time` bar) in the units of one phase ``plan``; None stays None.

    Examples
    --------
    >>> seen = []
    >>> phase_progress(seen.append, Plan("a", 20, 10, 4, "prime"))(2)
    >>> seen
    [10.0]
    """
    if progress is None:
        return None
    rate = plan.seconds / plan.ticks if plan.ticks else 0.0

    def tick(k=1):
        progress(k * rate)

    return tick


def first_moment_only(what: str, method: str, moments: int) -> Plan | None:
    """The refusal of a route that computes ``<W>`` only, or None when ``moments == 1``.

    Examples
    --------
    >>> first_moment_only("x", "lambda", 2).refusal
    'moments=2 is out of range for --method lambda: moments must be 1 (higher moments use --method fast, thesis or maps)'
    >>> first_moment_only("x", "lambda", 1) is None
    True
    """
    if moments == 1:
        return None
    return Plan(what, 0, refusal=f"moments={moments} is out of range for --method {method}: moments must be 1 "
                                 "(higher moments use --method fast, thesis or maps)")


# ------------------------------------------------- compiled work in bounded calls


def chunks(total: int, first: int, seconds: float = CHUNK_SECONDS):
    """Consecutive ranges ``(start, stop)`` covering ``0..total``, each taking about ``seconds``.

    The first range has ``first`` units (the caller's estimate of ``seconds``
    worth); every later one is sized from the measured time of the one before
    (the loop body between two ``yield``s: the compiled call, a progress tick),
    growing at most twofold, so a first call that also compiled or loaded the
    kernel is followed by short ranges that grow back.  The work done does not
    depend on the sizes: callers cut only where the state is complete.

    Examples
    --------
    >>> ranges = list(chunks(10, 4))
    >>> ranges[0], ranges[-1][1], all(a[1] == b[0] for a, b in zip(ranges, ranges[1:]))
    ((0, 4), 10, True)
    >>> list(chunks(0, 5))
    []
    """
    start, size = 0, max(1, int(first))
    while start < total:
        stop = min(total, start + size)
        t0 = time.perf_counter()
        yield start, stop
        elapsed = time.perf_counter() - t0
        grown = 2 * size
        size = grown if elapsed <= 0 else max(1, min(grown, int((stop - start) * seconds / elapsed)))
        start = stop


def first_chunk(seconds_per_unit: float, seconds: float = CHUNK_SECONDS) -> int:
    """The units of the first range of :func:`chunks`, from the model's cost of one unit.

    Examples
    --------
    >>> first_chunk(1e-3)
    150
    >>> first_chunk(10.0)
    1
    """
    return max(1, int(seconds / seconds_per_unit)) if seconds_per_unit > 0 else 1
