"""The front door for the tableaux count at any size: its plan (:func:`count_plan`) and its decimal digits.

``forcenet.count(N)`` is the number of force networks' combinatorial
skeleton, the standard shifted staircase tableaux, ``d! * normalization``
(Eq. (4.1)), an exact int. Up to ``N = 10^6`` it has up to ``10^12``
digits, so what it costs is asked first: ``forcenet.count_plan(N)`` answers
(seconds, memory, or why not) without doing the work, and its
:meth:`CountPlan.run` computes the count as :class:`TableauxCount`, whose
:meth:`~TableauxCount.to_text` is the decimal ``forcenet count`` prints
(python-flint's conversion is subquadratic; Python's ``str`` of an int over
4300 digits raises by default). The engine is
:mod:`forcenet.exact.triangle.staircase`.

Examples
--------
>>> import forcenet
>>> p = forcenet.count_plan(9)
>>> p.runnable, p.run().to_text()
(True, '108995910720')
>>> len(forcenet.count_plan(84).run().to_text())  # beyond Python's 4300-digit limit of str(int)
4323
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from typing import Any

import flint

from forcenet.core.plan import Plan
from forcenet.core.validation import check_int, check_layers
from forcenet.costed_plans import CostedPlan, Progress, available_memory_or_default
from forcenet.exact.triangle.staircase import count_plan as staircase_plan
from forcenet.exact.triangle.staircase import tableau_count
from forcenet.rendering import Rendered

__all__ = ["CountPlan", "TableauxCount", "count_plan"]



class TableauxCount(Rendered):
    """The number of standard shifted staircase tableaux of ``N`` layers, with its decimal digits.

    What :meth:`CountPlan.run` returns; ``int(c)`` (or ``c.value``) is
    :func:`forcenet.count`'s integer, :meth:`to_text` the digits ``forcenet count``
    prints.

    Parameters
    ----------
    N : int
        Number of layers.
    value : int
        The count, ``d! * normalization`` (Eq. (4.1)).

    Examples
    --------
    >>> import forcenet
    >>> c = forcenet.count_plan(7).run()
    >>> c, int(c) == forcenet.count(7)
    (TableauxCount(N=7, digits=5), True)
    """

    def __init__(self, N: int, value: int):
        self.N, self.value = N, value

    def __repr__(self) -> str:
        return f"TableauxCount(N={self.N}, digits={len(self.to_text())})"

    def __int__(self) -> int:
        return self.value

    def __eq__(self, other: object) -> bool:
        if isinstance(other, TableauxCount):
            return (self.N, self.value) == (other.N, other.value)
        return NotImplemented

    def __hash__(self) -> int:
        return hash((self.N, self.value))

    def to_dict(self) -> dict[str, Any]:
        """``N`` and the count as a decimal string.

        Returns
        -------
        dict

        Examples
        --------
        >>> import forcenet
        >>> forcenet.count_plan(6).run().to_dict()
        {'N': 6, 'count': '286'}
        """
        return {"N": self.N, "count": self.to_text()}

    def to_text(self) -> str:
        """The count in decimal, what ``forcenet count`` prints (and a newline).

        Returns
        -------
        str
            The decimal digits (python-flint's conversion: subquadratic, and no
            limit on the number of digits).

        Examples
        --------
        >>> import forcenet
        >>> forcenet.count_plan(8).run().to_text()
        '23178480'
        """
        return self._decimal

    @cached_property
    def _decimal(self) -> str:
        return str(flint.fmpz(self.value))


@dataclass(frozen=True, repr=False)  # the plan's own words: CostedPlan.__repr__
class CountPlan(CostedPlan):
    """The checked request for the tableaux count of ``N`` layers and its cost: what :func:`count_plan` returns.

    Parameters
    ----------
    N : int
        Number of layers.
    cost : forcenet.core.plan.Plan
        Estimated seconds and peak bytes of the count and its decimal digits, or the refusal.

    Examples
    --------
    >>> import forcenet
    >>> p = forcenet.count_plan(4000)
    >>> p.runnable, p.seconds < 60
    (True, True)
    """

    N: int
    cost: Plan

    def run(self, progress: Progress | bool | None = None) -> TableauxCount:
        """Compute the count this plan describes.

        Parameters
        ----------
        progress : callable, bool or None
            Accepted for the plans' common form; the count reports no ticks.

        Returns
        -------
        TableauxCount

        Raises
        ------
        ArgumentError
            If the plan is refused (``N`` too large, or more memory than available).

        Examples
        --------
        >>> import forcenet
        >>> int(forcenet.count_plan(6).run())
        286
        """
        self.check()
        return TableauxCount(self.N, tableau_count(self.N))  # N checked once, by count_plan


def count_plan(N: int, *, memory_bytes: int | None = None) -> CountPlan:
    """What the tableaux count of ``N`` layers and its decimal digits cost, or why they cannot be had.

    Nothing is computed. The count has about ``d log10 d`` digits
    (``d = N (N - 1)/2``): ``N = 4000`` gives 2.3e7 digits in ~8 s,
    ``N = 8000`` 1.0e8 digits in ~40 s on the 2-core reference machine.

    Parameters
    ----------
    N : int
        Number of layers, ``2..10^6``.
    memory_bytes : int, optional
        Memory the run may use; default: what the machine has available now
        (16 GiB where that is unknown).

    Returns
    -------
    CountPlan
        ``.cost`` (seconds, bytes, or the refusal), ``.run()`` the count.

    Raises
    ------
    ArgumentError
        If ``N`` is not an integer ``>= 2`` (or ``memory_bytes`` not a positive integer).

    Examples
    --------
    >>> import forcenet
    >>> forcenet.count_plan(12).run().to_text()
    '3830793890438041335187545600'
    >>> print(forcenet.count_plan(10**7).refusal)
    N=10000000 is out of range for count: N must be an integer in 2..1000000 (beyond, the integer has more than 10^12 digits)
    >>> print(forcenet.count_plan(10**5, memory_bytes=2**30).refusal)
    count N=100000 (2.16e+10 digits) needs ~192.1 GiB of memory but 1.0 GiB is available

    References
    ----------
    Ostojic (2006), Eq. (4.1) (``d! * normalization``); OEIS A003121.
    """
    N = check_layers(N)
    memory = available_memory_or_default() if memory_bytes is None else check_int(memory_bytes, "memory_bytes", 1)
    return CountPlan(N, staircase_plan(N, memory))
