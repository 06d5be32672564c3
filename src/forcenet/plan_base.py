"""The base of every front door's plan: what a plan says of its cost (:class:`PlanBase`), and the memory default.

Kept apart from the front doors themselves so that each imports its own
engines at its top and none loads another's: :class:`~forcenet.TablePlan`,
:class:`~forcenet.LawPlan`, :class:`~forcenet.SamplePlan`,
:class:`~forcenet.CountPlan`, the chicken-wire plans and
:class:`~forcenet.SampledComparisonPlan` all derive from it.

Examples
--------
>>> import forcenet
>>> isinstance(forcenet.plan(5), PlanBase), memory_or_default() > 0
(True, True)
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import Any, Self

from forcenet.core.plan import Plan
from forcenet.core.validation import available_memory

__all__ = ["PlanBase", "memory_or_default"]


def memory_or_default() -> int:
    """Bytes of memory available now, 16 GiB if unknown (the command line's figure).

    Examples
    --------
    >>> memory_or_default() > 0
    True
    """
    return available_memory() or 16 * 2**30


class PlanBase:
    """What every front door's plan (:class:`~forcenet.TablePlan`, :class:`~forcenet.LawPlan`, ...) says of its
    ``cost``: runnable, refusal, seconds, bytes, the cost in words, ``check``, and the run's progress ticks."""

    cost: Plan

    @contextmanager
    def _ticks(self, progress: Callable[..., Any] | bool | None, desc: str) -> Iterator[Callable[..., Any] | None]:
        """``progress`` as the run's tick: itself if callable, a tqdm bar for ``True`` (closed at the end; none for
        a refused plan), else None."""
        if progress is not True or not self.runnable:
            yield progress if callable(progress) else None
            return
        from tqdm.auto import tqdm  # optional display: loaded for a bar only

        bar = tqdm(total=self.cost.ticks or None, desc=desc, unit=self.cost.unit)
        try:
            yield bar.update
        finally:
            bar.close()

    @property
    def runnable(self) -> bool:
        """True when the request can run (in range, within memory).

        Examples
        --------
        >>> import forcenet
        >>> forcenet.plan(40).runnable, forcenet.plan(40, method="lambda").runnable
        (True, False)
        """
        return self.cost.runnable

    @property
    def refusal(self) -> str | None:
        """Why it cannot run, and what would; None when it can.

        Examples
        --------
        >>> import forcenet
        >>> print(forcenet.plan(13, method="lambda").refusal)  # doctest: +ELLIPSIS
        N=13 is out of range for --method lambda: ...; method='auto' runs it by fast (~0 s)
        """
        return self.cost.refusal

    @property
    def seconds(self) -> float:
        """Estimated wall time on the 2-core reference machine.

        Examples
        --------
        >>> import forcenet
        >>> forcenet.plan(5).seconds < 1
        True
        """
        return self.cost.seconds

    @property
    def nbytes(self) -> int:
        """Estimated peak memory in bytes.

        Examples
        --------
        >>> import forcenet
        >>> forcenet.plan(64).nbytes < 2**31
        True
        """
        return self.cost.nbytes

    def describe(self) -> str:
        """The cost in words: ``'~1 min, ~0.25 GiB'``.

        Returns
        -------
        str

        Examples
        --------
        >>> import forcenet
        >>> forcenet.plan(6, method="fast").describe()  # doctest: +ELLIPSIS
        '~0 s, ~...GiB'
        """
        return self.cost.describe()

    def check(self) -> Self:
        """The plan itself when it can run; else :class:`~forcenet.ArgumentError` with its refusal.

        Returns
        -------
        TablePlan or LawPlan
            This plan.

        Raises
        ------
        ArgumentError
            If the plan is refused.

        Examples
        --------
        >>> import forcenet
        >>> forcenet.plan(7).check().method
        'fast'
        """
        self.cost.check()
        return self
