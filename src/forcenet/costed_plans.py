"""The base of every front-door plan: a checked request with its cost, said before any work is done.

A plan (:class:`forcenet.TablePlan`, :class:`forcenet.LawPlan`, :class:`forcenet.SamplePlan`, ...) is a frozen
value holding its request and its :class:`forcenet.core.plan.Plan` (seconds, bytes, ticks, refusal);
:class:`CostedPlan` gives them one set of answers about that cost (``runnable``, ``refusal``, ``seconds``,
``nbytes``, ``describe``, ``check``) and one progress tick for their ``run``.  It imports no engine, so a front
door loads only its own engines.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import Any, Self

from forcenet.core.atomic_files import check_directory
from forcenet.core.plan import Plan
from forcenet.core.progress import ticks
from forcenet.core.validation import available_memory, check_progress

__all__ = ["CostedPlan", "Progress", "available_memory_or_default", "checkpoint_directory"]

Progress = Callable[..., Any]


def available_memory_or_default() -> int:
    """Bytes of memory available now, 16 GiB if unknown (the command line's figure)."""
    return available_memory() or 16 * 2**30


def checkpoint_directory(checkpoint: object) -> str | None:
    """``checkpoint=`` checked as the command line checks ``--checkpoint`` (one shared check)."""
    return None if checkpoint is None else check_directory(checkpoint, "checkpoint")


class CostedPlan:
    """What a front door's plan (:class:`TablePlan`, :class:`~forcenet.LawPlan`) says of its ``cost``."""

    cost: Plan

    @contextmanager
    def _ticks(self, progress: Callable[..., Any] | bool | None, desc: str) -> Iterator[Callable[..., Any] | None]:
        """``progress`` as the run's tick: itself if callable, a bar for ``True``, and for ``None`` where a person
        watches (a terminal, a notebook; :func:`forcenet.core.progress.ticks`); none for a refused plan."""
        check_progress(progress)

        with ticks(self.cost, progress, desc) as tick:
            yield tick

    def __repr__(self) -> str:
        """The plan's own words (:meth:`forcenet.core.plan.Plan.__repr__`), under this class's name."""
        return type(self).__name__ + repr(self.cost)[len("Plan"):]

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
