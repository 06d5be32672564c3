"""The front door: the exact table of the fully mobilized triangle, and its plan, in one call.

``forcenet.table(N)`` is what ``forcenet table --N N`` computes, by the same
route and to the same bytes: the exact ``<W_ij>`` (and ``<W_ij^s>``) of the
fully mobilized triangle of Sec. 4.2, as :class:`fractions.Fraction`.
``forcenet.plan(N)`` answers what that will cost (or why it cannot run, and
what would) without doing the work.  Both take the same request; a plan runs
as it was checked (:meth:`TablePlan.run`), so a request is validated and
planned once: the registry checks it (:func:`forcenet.exact.routes.check_request`),
plans it (:func:`~forcenet.exact.routes.plan_request`) and, when it runs,
checks the plan (:func:`~forcenet.exact.routes.run_request`).

The routes themselves live in :mod:`forcenet.exact.routes` (the registry of
table engines); this module only names the request, keeps what a user needs
of the answer together (:class:`Table`) and renders it.

Examples
--------
>>> import forcenet
>>> t = forcenet.table(5)
>>> [str(w) for w in t.mean_W[-1]], t.method
(['1/11', '1/4', '7/22', '1/4', '1/11'], 'fast')
>>> t.count, t.normalization   # d! * normalization, Eq. (4.1)
(12, Fraction(1, 302400))
>>> p = forcenet.plan(40)
>>> p.method, p.runnable
('pfaffian', True)
"""

from __future__ import annotations

import os
from collections.abc import Callable, Iterator
from concurrent.futures import Executor
from contextlib import contextmanager
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, Any, Self

from forcenet.core.atomic_files import check_directory
from forcenet.core.errors import ArgumentError
from forcenet.core.plan import Plan, duration_text
from forcenet.core.validation import available_memory, check_progress
from forcenet.results import Row, Table

if TYPE_CHECKING:
    from forcenet.exact.routes import Request

__all__ = ["Row", "Table", "TablePlan", "plan", "table"]  # Row and Table: forcenet.results

Progress = Callable[..., Any]


def _available_memory() -> int:
    """Bytes of memory available now, 16 GiB if unknown (the command line's figure)."""
    return available_memory() or 16 * 2**30


def _checkpoint(checkpoint: object) -> str | None:
    """``checkpoint=`` checked as the command line checks ``--checkpoint`` (one shared check)."""
    return None if checkpoint is None else check_directory(checkpoint, "checkpoint")


class _Costed:
    """What a front door's plan (:class:`TablePlan`, :class:`~forcenet.LawPlan`) says of its ``cost``."""

    cost: Plan

    @contextmanager
    def _ticks(self, progress: Callable[..., Any] | bool | None, desc: str) -> Iterator[Callable[..., Any] | None]:
        """``progress`` as the run's tick: itself if callable, a bar for ``True``, and for ``None`` where a person
        watches (a terminal, a notebook; :func:`forcenet.core.progress.ticks`); none for a refused plan."""
        check_progress(progress)
        from forcenet.core.progress import ticks  # None: a bar where a person watches (the one policy)

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


@dataclass(frozen=True, repr=False)  # the plan's own words: _Costed.__repr__
class TablePlan(_Costed):
    """A checked request for an exact table, with its cost: what :func:`plan` returns (make it with :func:`plan`).

    Parameters
    ----------
    N : int
        Number of layers.
    moments : int
        Highest moment ``s`` of ``<W^s>``.
    method : str
        The route that runs it (``auto`` resolved to the fastest by the plans).
    why : str
        Why ``auto`` chose ``method`` (empty for an explicit method).
    cost : forcenet.core.plan.Plan
        Estimated seconds, peak bytes, progress ticks, or the refusal.
    executor : concurrent.futures.Executor or Dask Client, optional
        Runs the route's independent tasks.
    checkpoint : CheckpointStore or str, optional
        Where the route records finished tasks.
    memory_bytes : int, optional
        The memory the plan was checked against.
    row : int, optional
        One row (layer) ``i`` of the tables instead of the whole table; ``method`` then names the row's route.
    request : forcenet.exact.routes.Request, optional
        The checked request the plan was made for (what :meth:`run` hands to the registry).

    Examples
    --------
    >>> import forcenet
    >>> p = forcenet.plan(12)
    >>> p.method, p.runnable, p.refusal
    ('fast', True, None)
    """

    N: int
    moments: int
    method: str
    why: str
    cost: Plan
    executor: Executor | None = field(default=None, repr=False)
    checkpoint: Any = field(default=None, repr=False)
    memory_bytes: int | None = field(default=None, repr=False)
    row: int | None = None
    request: Request | None = field(default=None, repr=False)  # the checked request it was planned for

    def run(self, progress: Progress | bool | None = None) -> Table | Row:
        """Compute the table (or the row) this plan describes (the plan is not made again).

        Parameters
        ----------
        progress : callable, bool or None
            ``progress(k)`` is called with the plan's ticks as the run goes;
            ``True``: a progress bar (tqdm); None: nothing.

        Returns
        -------
        Table or Row
            :class:`Row` when the plan was made with ``row=``.

        Raises
        ------
        ArgumentError
            If the plan is refused.

        Examples
        --------
        >>> import forcenet
        >>> forcenet.plan(4, method="thesis").run().mean_W[-1]
        [Fraction(1, 7), Fraction(5, 14), Fraction(5, 14), Fraction(1, 7)]
        """
        from forcenet.core.checkpoints import run_distrusting  # numpy: not before a run
        from forcenet.exact.routes import Choice, RowChoice, run_request, run_row  # the engines, on first use

        request = self.request  # checked once by plan(); the registry checks the plan before the run
        if request is None:
            raise ArgumentError("this TablePlan was not made by forcenet.plan: make it with forcenet.plan(N, ...)")
        with self._ticks(progress, f"table N={self.N}") as tick:  # a reused record that fails the route's
            if self.row is not None:                                 # exact checks is named, dropped, recomputed
                rows = run_distrusting(self.checkpoint, self.N, lambda: run_row(
                    request, RowChoice(self.method, self.cost, self.why), tick))
                return Row(self.N, self.row, self.method, self.why, rows)
            tables = run_distrusting(self.checkpoint, self.N, lambda: run_request(
                request, Choice(self.method, self.cost, self.why), tick))
        return Table(self.N, self.method, self.why, tables)


def plan(N: int, moments: int = 1, method: str = "auto", *, executor: Executor | None = None,
         checkpoint: str | os.PathLike[str] | None = None, memory_bytes: int | None = None,
         row: int | None = None) -> TablePlan:
    """What :func:`table` will cost for this request, or why it cannot run and what would; nothing is computed.

    Parameters
    ----------
    N : int
        Number of layers of the triangle, ``>= 2``.
    moments : int
        Highest moment ``s`` of ``<W^s>``, ``1..50``.
    method : str
        ``"auto"`` (the fastest route by the plans, the default), ``"fast"``
        (order-ideal dynamic program), ``"thesis"`` (nested-matrix integration,
        Secs. 4.3-4.5), ``"lambda"`` (the recursions (4.50), (4.73)-(4.77)),
        ``"maps"`` (map counting, Sec. 4.6) or ``"pfaffian"`` (Schur
        Pfaffians, polynomial in N).
    executor : concurrent.futures.Executor or Dask Client, optional
        Runs the Pfaffian route's independent primes (``auto`` then chooses
        among the routes that use it).
    checkpoint : str or os.PathLike, optional
        A directory where the Pfaffian route records every finished prime; a
        rerun recomputes only what is missing.
    memory_bytes : int, optional
        Memory the run may use; default: what the machine has available now.
    row : int, optional
        Only row (layer) ``i``, ``1..N``, by the fastest exact route for that row
        (:func:`forcenet.exact.routes.choose_row`: for ``moments=2`` the one-time
        cover identity on the rows 2, 3 and ``N - 1``, the lattice route, one
        layer's de Bruijn Pfaffians, or a whole table's row).

    Returns
    -------
    TablePlan
        The chosen method, its estimated cost, or its refusal naming what would work.

    Raises
    ------
    ArgumentError
        If ``N``, ``moments`` or ``method`` is out of range.

    Examples
    --------
    >>> import forcenet
    >>> forcenet.plan(200).method
    'pfaffian'
    >>> print(forcenet.plan(40, method="fast").refusal)  # doctest: +ELLIPSIS
    N=40 is out of range for the exact table here: ...; method='auto' runs it by pfaffian (~...)
    """
    from forcenet.exact.routes import METHODS, check_request, plan_request, takes  # the engines: not before a plan

    request = check_request(N, moments, method, row=row, memory_bytes=memory_bytes, executor=executor)  # the check
    directory = _checkpoint(checkpoint)
    if request.memory_bytes is None:
        request = replace(request, memory_bytes=_available_memory())
    if row is not None:
        return _row_plan(replace(request, options={} if directory is None else {"checkpoint": directory}))
    request = replace(request, directory=directory)
    over_primes = executor is not None or directory is not None  # the routes over independent primes use them
    choice = plan_request(request, [m for m in METHODS[:-1] if takes(m, "checkpoint")] if over_primes else None)
    # one request per layer (a directory): the route's plan counts each layer's own held records
    cost, why, store = choice.plan, choice.why, request.stores.get(choice.method)
    if why:
        cost = replace(cost, what=f"{cost.what}; {why}")
    elif not cost.runnable and request.method != "auto":  # an explicit method out of reach: name what runs it
        others = [m for m in METHODS[:-1] if m != request.method]
        other = plan_request(replace(request, method="auto", executor=None, directory=None), others)
        if other.plan.runnable:
            cost = replace(cost, refusal=f"{cost.refusal}; method='auto' runs it by {other.method} "
                                         f"(~{duration_text(other.plan.seconds)})")
    return TablePlan(request.N, request.moments, choice.method, why, cost, executor, store, request.memory_bytes,
                     request=request)


def _row_plan(request: Request) -> TablePlan:
    """One row's plan: its route by :func:`forcenet.exact.routes.choose_row`, planned once with the options."""
    from forcenet.exact.routes import plan_row

    choice = plan_row(request)
    cost = choice.plan if not choice.why else replace(choice.plan, what=f"{choice.plan.what}; {choice.why}")
    return TablePlan(request.N, request.moments, choice.route, choice.why, cost, request.executor,
                     request.options.get("checkpoint"), request.memory_bytes, request.row, request)


def table(N: int, moments: int = 1, method: str = "auto", *, executor: Executor | None = None,
          checkpoint: str | os.PathLike[str] | None = None, progress: Progress | bool | None = None,
          memory_bytes: int | None = None, row: int | None = None) -> Table | Row:
    """The exact table of ``<W_ij>`` (and ``<W_ij^s>``) of the fully mobilized triangle, as ``forcenet table`` makes it.

    The vertical force ``W_ij`` on grain ``j`` of layer ``i`` (Sec. 4.2),
    averaged over the uniform measure on force networks in balance (the
    order polytope of the shifted staircase), exactly.  ``method="auto"``
    runs the fastest route by the plans (:func:`plan`), the same choice and
    the same bytes as the command line.

    Parameters
    ----------
    N : int
        Number of layers, ``>= 2``.
    moments : int
        Highest moment ``s`` of ``<W^s>``, ``1..50``.
    method : str
        ``"auto"`` (default), ``"fast"``, ``"thesis"``, ``"lambda"``,
        ``"maps"`` or ``"pfaffian"`` (see :func:`plan`).
    executor : concurrent.futures.Executor or Dask Client, optional
        Runs the Pfaffian route's independent primes (a Dask
        ``Client`` or ``client.get_executor()`` runs them on a cluster).
        Default: worker processes on every core once the work pays for
        starting them (the mean from ``N = 37``), else this process.  A script
        makes the call under ``if __name__ == "__main__":`` (spawned
        workers import it again).
    checkpoint : str or os.PathLike, optional
        A directory recording every finished prime (resumable runs).
    progress : callable, bool or None
        ``progress(k)`` with the plan's ticks; ``True``: a progress bar.
    memory_bytes : int, optional
        Memory the run may use; default: what the machine has available now.
    row : int, optional
        Only row (layer) ``i`` by the fastest route for that row (see :func:`plan`): a :class:`Row`.

    Returns
    -------
    Table or Row
        Exact :class:`~fractions.Fraction` rows, the method used and why.

    Raises
    ------
    ArgumentError
        If the request is out of range, or its plan is refused (the message
        names the route that would run it).
    ClusterError
        If a worker process (local or on a cluster) is lost, or a script's
        workers cannot start (the ``__main__`` guard).

    Examples
    --------
    >>> import forcenet
    >>> t = forcenet.table(6, moments=2)
    >>> t.mean_W[5][1], t.moment(2)[5][1]  # grain (6, 2)
    (Fraction(413, 2288), Fraction(855, 19448))
    >>> forcenet.table(40, method="fast")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    forcenet.core.errors.ArgumentError: N=40 is out of range for the exact table here: ...; method='auto' runs it by pfaffian (~...)
    >>> r = forcenet.table(7, moments=2, row=6, method="pfaffian")  # layer N - 1: the cover identity
    >>> r.method, r.moment(2)[0]
    ('covers', Fraction(3, 253))
    """
    return plan(N, moments, method, executor=executor, checkpoint=checkpoint,
                memory_bytes=memory_bytes, row=row).run(progress)
