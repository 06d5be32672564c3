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
import warnings
from concurrent.futures import Executor
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, Any, overload

from forcenet.core.checkpoints import run_distrusting
from forcenet.core.errors import ArgumentError
from forcenet.core.plan import Plan, duration_text
from forcenet.costed_plans import CostedPlan, Progress, available_memory_or_default, checkpoint_directory
from forcenet.exact.routes import (
    METHODS,
    Choice,
    RowChoice,
    check_request,
    plan_request,
    plan_row,
    run_request,
    run_row,
    takes,
)
from forcenet.results import Table
from forcenet.row_results import Row

if TYPE_CHECKING:
    from forcenet.exact.routes import Request

__all__ = ["Row", "RowPlan", "Table", "TablePlan", "plan", "row", "row_plan", "table"]  # Row, Table: forcenet.row_results, .results


@dataclass(frozen=True, repr=False)  # the plan's own words: CostedPlan.__repr__
class _ExactPlan(CostedPlan):
    """What a table's and a row's plans hold: the checked request and the chosen route's cost."""

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

    def _checked_request(self) -> Request:
        """The request :func:`plan` checked (the registry checks the plan before the run)."""
        if self.request is None:
            raise ArgumentError(f"this {type(self).__name__} was not made by forcenet.plan or forcenet.row_plan: "
                                "make it with one of them")
        return self.request


@dataclass(frozen=True, repr=False)  # the plan's own words: CostedPlan.__repr__
class TablePlan(_ExactPlan):
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
        For a row's plan, the row (layer) ``i``; ``None`` for a whole table.
    request : forcenet.exact.routes.Request, optional
        The checked request the plan was made for (what :meth:`run` hands to the registry).

    Examples
    --------
    >>> import forcenet
    >>> p = forcenet.plan(12)
    >>> p.method, p.runnable, p.refusal
    ('fast', True, None)
    """

    def run(self, progress: Progress | bool | None = None) -> Table:
        """Compute the table this plan describes (the plan is not made again).

        Parameters
        ----------
        progress : callable, bool or None
            ``progress(k)`` is called with the plan's ticks as the run goes;
            ``True``: a progress bar (tqdm); None: nothing.

        Returns
        -------
        Table

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
        request = self._checked_request()
        with self._ticks(progress, f"table N={self.N}") as tick:  # a reused record that fails the route's
            tables = run_distrusting(self.checkpoint, self.N, lambda: run_request(  # exact checks is recomputed
                request, Choice(self.method, self.cost, self.why), tick))
        return Table(self.N, self.method, self.why, tables)


@dataclass(frozen=True, repr=False)  # the plan's own words: CostedPlan.__repr__
class RowPlan(_ExactPlan):
    """A checked request for one row of the exact tables, with its cost: what :func:`row_plan` returns.

    Parameters
    ----------
    N : int
        Number of layers.
    moments : int
        Highest moment ``s`` of ``<W^s>``.
    method : str
        The row's route (``auto`` resolved to the fastest by the plans).
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
        The row (layer) ``i``, ``1..N``.
    request : forcenet.exact.routes.Request, optional
        The checked request the plan was made for.

    Examples
    --------
    >>> import forcenet
    >>> p = forcenet.row_plan(12, 11, moments=2)
    >>> p.row, p.runnable
    (11, True)
    """

    def run(self, progress: Progress | bool | None = None) -> Row:
        """Compute the row this plan describes (the plan is not made again).

        Parameters
        ----------
        progress : callable, bool or None
            ``progress(k)`` with the plan's ticks; ``True``: a progress bar.

        Returns
        -------
        Row

        Raises
        ------
        ArgumentError
            If the plan is refused.

        Examples
        --------
        >>> import forcenet
        >>> forcenet.row_plan(4, 4).run().mean_W
        [Fraction(1, 7), Fraction(5, 14), Fraction(5, 14), Fraction(1, 7)]
        """
        request = self._checked_request()
        with self._ticks(progress, f"table N={self.N}") as tick:
            rows = run_distrusting(self.checkpoint, self.N, lambda: run_row(
                request, RowChoice(self.method, self.cost, self.why), tick))
        return Row(self.N, self._row(), self.method, self.why, rows)

    def _row(self) -> int:
        """The layer this plan is for (:func:`row_plan` always sets it)."""
        if self.row is None:
            raise ArgumentError("this RowPlan names no row: make it with forcenet.row_plan(N, i)")
        return self.row


@overload
def plan(N: int, moments: int = 1, method: str = "auto", *, executor: Executor | None = None,
         checkpoint: str | os.PathLike[str] | None = None, memory_bytes: int | None = None,
         row: None = None) -> TablePlan: ...


@overload
def plan(N: int, moments: int = 1, method: str = "auto", *, executor: Executor | None = None,
         checkpoint: str | os.PathLike[str] | None = None, memory_bytes: int | None = None,
         row: int) -> RowPlan: ...  # deprecated: row_plan


def plan(N: int, moments: int = 1, method: str = "auto", *, executor: Executor | None = None,
         checkpoint: str | os.PathLike[str] | None = None, memory_bytes: int | None = None,
         row: int | None = None) -> TablePlan | RowPlan:
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
        Deprecated: use :func:`row_plan`.

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

    if row is not None:  # one row has its own function now
        warnings.warn("plan(..., row=i) is deprecated: use forcenet.row_plan(N, i, ...)", DeprecationWarning,
                      stacklevel=2)
        return row_plan(N, row, moments, method, executor=executor, checkpoint=checkpoint, memory_bytes=memory_bytes)
    request = check_request(N, moments, method, memory_bytes=memory_bytes, executor=executor)  # the check
    directory = checkpoint_directory(checkpoint)
    if request.memory_bytes is None:
        request = replace(request, memory_bytes=available_memory_or_default())
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


def row_plan(N: int, row: int, moments: int = 1, method: str = "auto", *, executor: Executor | None = None,
             checkpoint: str | os.PathLike[str] | None = None, memory_bytes: int | None = None) -> RowPlan:
    """What :func:`row` will cost: one row (layer) of the exact tables by its fastest route; nothing is computed.

    Parameters
    ----------
    N : int
        Number of layers of the triangle, ``>= 2``.
    row : int
        The row (layer) ``i``, ``1..N``.
    moments : int
        Highest moment ``s`` of ``<W^s>``, ``1..50``.
    method : str
        ``"auto"`` (the fastest of the row's routes and the whole tables' methods, by their plans), a table
        method (:func:`plan`) or a row's route (``"covers"``: the one-time cover identity on rows 2, 3 and
        ``N - 1`` for ``moments=2``; ``"lattice"``; ``"layers"``: one layer's de Bruijn Pfaffians; ...).
    executor : concurrent.futures.Executor or Dask Client, optional
        Runs the route's independent primes.
    checkpoint : str or os.PathLike, optional
        A directory recording every finished prime of the routes over primes.
    memory_bytes : int, optional
        Memory the run may use; default: what the machine has available now.

    Returns
    -------
    RowPlan
        The chosen route, its estimated cost, or its refusal naming what would work.

    Raises
    ------
    ArgumentError
        If ``N``, ``row``, ``moments`` or ``method`` is out of range.

    Examples
    --------
    >>> import forcenet
    >>> p = forcenet.row_plan(40, 39, moments=2)
    >>> p.method, p.runnable
    ('covers', True)
    """

    request = check_request(N, moments, method, row=row, memory_bytes=memory_bytes, executor=executor)  # the check
    directory = checkpoint_directory(checkpoint)
    if request.memory_bytes is None:
        request = replace(request, memory_bytes=available_memory_or_default())
    request = replace(request, options={} if directory is None else {"checkpoint": directory})
    choice = plan_row(request)
    cost = choice.plan if not choice.why else replace(choice.plan, what=f"{choice.plan.what}; {choice.why}")
    return RowPlan(request.N, request.moments, choice.route, choice.why, cost, request.executor,
                   request.options.get("checkpoint"), request.memory_bytes, request.row, request)


def row(N: int, row: int, moments: int = 1, method: str = "auto", *, executor: Executor | None = None,
        checkpoint: str | os.PathLike[str] | None = None, progress: Progress | bool | None = None,
        memory_bytes: int | None = None) -> Row:
    """One row (layer) ``i`` of the exact tables ``<W_ij>`` (and ``<W_ij^s>``), by the fastest route for that row.

    What ``forcenet table --N N --row i`` computes, to the same bytes. A row can be far cheaper than its table:
    layer ``N - 1`` of ``<W^2>`` from the cover identity, the lattice directions from their level polynomial.

    Parameters
    ----------
    N : int
        Number of layers, ``>= 2``.
    row : int
        The row (layer) ``i``, ``1..N``.
    moments : int
        Highest moment ``s`` of ``<W^s>``, ``1..50``.
    method : str
        ``"auto"`` (default) or a route (see :func:`row_plan`).
    executor : concurrent.futures.Executor or Dask Client, optional
        Runs the route's independent primes.
    checkpoint : str or os.PathLike, optional
        A directory recording every finished prime (resumable runs).
    progress : callable, bool or None
        ``progress(k)`` with the plan's ticks; ``True``: a progress bar.
    memory_bytes : int, optional
        Memory the run may use; default: what the machine has available now.

    Returns
    -------
    Row
        The row's exact :class:`~fractions.Fraction` values, the route used and why.

    Raises
    ------
    ArgumentError
        If the request is out of range, or its plan is refused.

    Examples
    --------
    >>> import forcenet
    >>> r = forcenet.row(7, 6, moments=2, method="pfaffian")  # layer N - 1: the cover identity
    >>> r.method, r.moment(2)[0]
    ('covers', Fraction(3, 253))

    References
    ----------
    Ostojic (2006), Sec. 4.2 (the triangle) and Eq. (4.3); ``notes/fluctuations.md`` Sec. 3.1 (the covers).
    """
    return row_plan(N, row, moments, method, executor=executor, checkpoint=checkpoint,
                    memory_bytes=memory_bytes).run(progress)


@overload
def table(N: int, moments: int = 1, method: str = "auto", *, executor: Executor | None = None,
          checkpoint: str | os.PathLike[str] | None = None, progress: Progress | bool | None = None,
          memory_bytes: int | None = None, row: None = None) -> Table: ...


@overload
def table(N: int, moments: int = 1, method: str = "auto", *, executor: Executor | None = None,
          checkpoint: str | os.PathLike[str] | None = None, progress: Progress | bool | None = None,
          memory_bytes: int | None = None, row: int) -> Row: ...  # deprecated: row


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
        Deprecated: use :func:`row` (one row, a :class:`Row`).

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
    """
    if row is not None:  # one row has its own function now
        warnings.warn("table(..., row=i) is deprecated: use forcenet.row(N, i, ...)", DeprecationWarning, stacklevel=2)
        return row_plan(N, row, moments, method, executor=executor, checkpoint=checkpoint,
                        memory_bytes=memory_bytes).run(progress)
    return plan(N, moments, method, executor=executor, checkpoint=checkpoint,
                memory_bytes=memory_bytes).run(progress)
