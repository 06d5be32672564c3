"""The free-fermion route: exact ``<W>`` tables and the normalization in time polynomial in ``N``.

The mean of ``forcenet table --method pfaffian`` (its plan :func:`mean_plan`
and :func:`survival_tables`; the method's table engine, higher moments
included, is :mod:`forcenet.exact.triangle.pfaffian_table`), and the public
functions of the route.  Residues from :mod:`.engine` for enough
word-size primes (:func:`.cost.route_primes`), rebuilt exactly by
:func:`forcenet.exact.modular.crt_many` (the bound ``0 <= S[m][k] <= (d+1)
count`` is proven, so the reconstruction is exact).  The primes are
independent tasks (:mod:`forcenet.exact.triangle.prime_tasks`) run on an executor: a local process
pool by default, or any :class:`concurrent.futures.Executor` given as
``executor=`` (a Dask cluster: ``client.get_executor()``, or the client
itself); ``checkpoint=`` (a directory or a
:class:`~forcenet.core.checkpoints.CheckpointStore`) records every finished
prime, so a rerun recomputes only the missing ones.  The result never depends
on either.

Cost ``O(N^7 log N)`` word operations: ``O(n^5)`` per prime (``d/2`` level
points, ``n + 1`` values of ``y``, an ``O(n^2)`` displacement elimination
each) and ``O(N^2 log N)`` primes.  Memory ``O(N^3)`` per worker.  It overtakes the
order-ideal DP (``2^(N-1)`` ideals) near ``N = 20`` (``notes/benchmarks.md``).

The cost model is :mod:`.cost`.

Examples
--------
>>> count(7), count(10)  # d! * normalization, Eq. (4.1)
(33592, 3973186258569120)
>>> [str(x) for x in mean_W(5)[-1]]  # Eqs. (4.63)-(4.77): the bottom row, N = 5
['1/11', '1/4', '7/22', '1/4', '1/11']
"""

from __future__ import annotations

from concurrent.futures import Executor
from fractions import Fraction
from math import ceil, comb, factorial, log2
from os import PathLike
from typing import Any

from forcenet.core.checkpoints import CheckpointStore
from forcenet.core.execution import as_executor
from forcenet.core.plan import Plan, table_range
from forcenet.core.validation import check_layers

from ...modular import crt_many
from ...protocol import Progress, Table
from ..prime_tasks import checkpoint_store, primes_plan, run_primes, workers_for
from ..staircase import dimension, free_force_count, tableau_count
from .cost import CRT_SECONDS, edge_seconds, prime_limit, prime_seconds, route_primes, worker_bytes
from .engine import count_residue, edge_residues, prime_residues, with_kernels_compiled

__all__ = [
    "MAX_N",
    "count",
    "normalization",
    "survival_table",
    "survival_tables",
    "table_from_survival",
    "mean_W",
    "expected_entries",
    "lattice_direction",
    "lattice_direction_plan",
    "mean_plan",
    "route_plan",
]

MAX_N = 200


Checkpoint = str | PathLike | CheckpointStore | None


def count(N: int, *, checkpoint: Checkpoint = None) -> int:
    """The number of tableaux, ``count = d! Pf(B)`` (the normalization (4.1) times ``d!``), by this route.

    Multi-modular, with the proven bound ``count <= d!`` (linear extensions
    of ``d`` elements).  ``checkpoint`` as in :func:`survival_table`.  The
    primes always run in this process, even when the table's run on a
    cluster: each costs ~2 ms at N = 64, less than a scheduler's cost per task
    (770 of them took 13 s through Dask on loopback against 1.2 s here;
    notes/benchmarks.md).

    Parameters
    ----------
    N : int
        Number of layers, ``2..200``.
    checkpoint : str, os.PathLike or CheckpointStore, optional
        Directory of the checkpoint records (as in :func:`survival_table`).

    Returns
    -------
    int
        ``d! Pf(B)``, ``d = N(N-1)/2``.

    Raises
    ------
    ArgumentError
        If ``N`` is outside ``2..200``.
    ArgumentTypeError
        If ``N`` is not an integer.

    Examples
    --------
    >>> [count(N) for N in range(2, 8)]
    [1, 1, 2, 12, 286, 33592]
    """
    N = check_layers(N, maximum=MAX_N)
    primes = route_primes(N, factorial(dimension(N)))
    residues = run_primes(count_residue, [(N, p) for p in primes], None, 1, None,
                          checkpoint_store(checkpoint, "count", N))
    return crt_many([residues], primes)[0]


def normalization(N: int) -> Fraction:
    """The normalization (4.1), the volume of the triangle's force space: ``count / d! = Pf(B)``.

    Parameters
    ----------
    N : int
        Number of layers, ``2..200``.

    Returns
    -------
    Fraction
        The volume of the force space, Eq. (4.1).

    Raises
    ------
    ArgumentError
        If ``N`` is outside ``2..200``.
    ArgumentTypeError
        If ``N`` is not an integer.

    Examples
    --------
    >>> normalization(4)
    Fraction(1, 360)
    """
    N = check_layers(N, maximum=MAX_N)
    return Fraction(count(N), factorial(dimension(N)))


def survival_table(N: int, *, workers: int | None = None, progress: Progress | None = None,
                   executor: Executor | None = None, checkpoint: Checkpoint = None) -> tuple[list[list[int]], int]:
    """Exact ``S[m][k] = sum_A w(A) [N_m(A) = k]`` and ``count(N)``, by Pfaffians.

    ``A`` runs over the order ideals (strict partitions with parts ``<= n``),
    ``w(A)`` is the number of tableaux through ``A`` and ``N_m(A)`` the
    number of parts ``>= m``; every row sums to ``(d + 1) count``.

    Parameters
    ----------
    N : int
        Number of layers, ``2..200``.
    workers : int, optional
        Worker processes (default: the available cores when the run is long
        enough to pay for them, else 1).  Results do not depend on it.
    progress : callable, optional
        Called as ``progress(1)`` after each prime (at once for a prime
        taken from the checkpoint).
    executor : concurrent.futures.Executor or dask.distributed.Client, optional
        Runs the per-prime tasks instead of local processes (e.g. a Dask
        cluster's ``client.get_executor()``; its workers need forcenet
        installed, nothing else).  Results do not depend on it.
    checkpoint : str, os.PathLike or CheckpointStore, optional
        Directory of the checkpoint records: finished primes are recorded
        there and not recomputed by a rerun of the same request.

    Returns
    -------
    (S, total) : (list of lists of int, int)
        ``S[m][k]`` for ``m = 1..n`` (row 0 unused), ``k = 0..n``; ``total = count(N)``.

    Raises
    ------
    ArgumentError
        If ``N`` is outside ``2..200``.
    ArgumentTypeError
        If ``N`` is not an integer.
    ArithmeticError
        If the reconstructed rows do not sum to ``(d + 1) count`` (a bug, never expected).

    Examples
    --------
    >>> S, total = survival_table(4)
    >>> total, S[1], S[3]
    (2, [2, 5, 5, 2], [7, 7, 0, 0])
    """
    N = check_layers(N, maximum=MAX_N)
    (S,), total = survival_tables(N, workers, progress, as_executor(executor), checkpoint)
    return S, total


def survival_tables(N: int, workers: int | None, progress: Progress | None, executor: Executor | None,
                    checkpoint: Checkpoint, second: bool = False) -> tuple[list[list[list[int]]], int]:
    """``[S]`` (``[S, S2]`` with ``second``, :func:`.engine.prime_residues`) and ``count(N)``: every prime's
    residues, combined by CRT; ``N`` checked by the caller, ``executor`` resolved (:func:`survival_table`).

    Examples
    --------
    >>> tables, total = survival_tables(4, 1, None, None, None, second=True)
    >>> total, tables[1][3]
    (2, [16, 40, 0, 0])
    """
    n, d = N - 1, dimension(N)
    levels = 2 if second else 1
    total = count(N, checkpoint=checkpoint)
    if n == 0:
        return [[[0]]] * levels, total
    primes = route_primes(N, comb(d + levels, levels) * total)  # |S2| <= (d + 1)(d + 2)/2 count
    tasks = [(N, p, total % p, True) if second else (N, p, total % p) for p in primes]
    nworkers = workers_for(workers, len(tasks), prime_seconds(N) * len(primes), executor)
    residues = run_primes(prime_residues, tasks, executor, nworkers, progress,
                          checkpoint_store(checkpoint, "table2" if second else "table", N))
    residues = [r.reshape((levels, n + 1, n + 1)) for r in residues]
    cells = [(h, m, k) for h in range(levels) for m in range(1, n + 1) for k in range(n + 1)]
    entries = dict(zip(cells, crt_many([[r[cell] for r in residues] for cell in cells], primes)))
    tables = [[[0] * (n + 1)] + [[entries[h, m, k] for k in range(n + 1)] for m in range(1, n + 1)]
              for h in range(levels)]
    for h, table in enumerate(tables):  # level h sums to C(d + 1 + h, h + 1) count
        if any(sum(row) != comb(d + 1 + h, h + 1) * total for row in table[1:]):
            raise ArithmeticError("reconstructed rows do not sum to their totals")
    return tables, total


def mean_W(N: int, **kwargs: Any) -> Table:
    """Exact ``<W_{i,j}>`` table, rows ``i = 1..N``, ``j = 1..i``, by Pfaffians (Eqs. (4.63)-(4.77)).

    ``<W_ij> (d + 1) count = S[m][j - 1]`` with ``m = N - i + 1``: the grain's
    bounding partial sums are eligible exactly when ``N_m(A) = j - 1``
    (``notes/free_fermions.md`` Sec. 0).  Same layout as
    :func:`forcenet.exact.triangle.moments.mean_W`; keyword arguments go to
    :func:`survival_table`.

    Parameters
    ----------
    N : int
        Number of layers, ``2..200``.
    **kwargs
        ``workers``, ``progress``, ``executor``, ``checkpoint`` of
        :func:`survival_table` (results do not depend on them).

    Returns
    -------
    list of lists of Fraction
        Row ``i`` holds ``<W_{i,j}>`` for ``j = 1..i``.

    Raises
    ------
    ArgumentError
        If ``N`` is outside ``2..200``.
    ArgumentTypeError
        If ``N`` is not an integer.

    Examples
    --------
    >>> [str(x) for x in mean_W(4)[-1]]
    ['1/7', '5/14', '5/14', '1/7']
    """
    N = check_layers(N, maximum=MAX_N)
    S, total = survival_table(N, **kwargs)
    return table_from_survival(N, S, total)


def table_from_survival(N: int, S: list[list[int]], total: int) -> Table:
    """``<W_ij> = S[N - i + 1][j - 1] / ((d + 1) count)``, row ``i = 1`` the apex.

    Examples
    --------
    >>> S, total = survival_table(3)
    >>> table_from_survival(3, S, total)[-1]
    [Fraction(1, 4), Fraction(1, 2), Fraction(1, 4)]
    """
    den = total * (dimension(N) + 1)
    table = [[Fraction(1)]]
    for i in range(2, N + 1):
        m = N - i + 1
        table.append([Fraction(S[m][j - 1], den) for j in range(1, i + 1)])
    return table


def expected_entries(N: int, **kwargs: Any) -> dict[tuple[int, int], Fraction]:
    """``E[T(r, c)]`` of a uniform standard tableau of the shifted staircase (Sec. 4.6), every cell (exact).

    ``T(x) = #{k : x not in I_k}`` along the chain, so
    ``E[T(r, c)] count = sum_{k < r} S[c - r + 1][k]``.

    Parameters
    ----------
    N : int
        Number of layers, ``2..200``.
    **kwargs
        ``workers``, ``progress``, ``executor``, ``checkpoint`` of
        :func:`survival_table` (results do not depend on them).

    Returns
    -------
    dict of (int, int) to Fraction
        ``E[T(r, c)]`` for ``1 <= r <= c <= N - 1``.

    Raises
    ------
    ArgumentError
        If ``N`` is outside ``2..200``.
    ArgumentTypeError
        If ``N`` is not an integer.

    Examples
    --------
    >>> E = expected_entries(3)
    >>> E[(1, 1)], E[(1, 2)], E[(2, 2)]
    (Fraction(1, 1), Fraction(2, 1), Fraction(3, 1))
    """
    N = check_layers(N, maximum=MAX_N)
    n = N - 1
    S, total = survival_table(N, **kwargs)
    return {(r, c): Fraction(sum(S[c - r + 1][:r]), total) for r in range(1, n + 1) for c in range(r, n + 1)}


def lattice_direction(N: int, *, workers: int | None = None, progress: Progress | None = None,
                      executor: Executor | None = None, checkpoint: Checkpoint = None) -> list[Fraction]:
    """Exact ``<W_{i,1}> = <W_{i,i}>``, ``i = 1..N``: the lattice directions (Eqs. (4.63)-(4.77), Fig. 3.5).

    Only the first column ``S[m][0]`` of the survival table, from two
    eliminations per level point instead of ``n + 1`` (:func:`~.engine.edge_residues`);
    the kernel set-up, the same for both, is then most of the work: about 4
    times cheaper than :func:`mean_W` at N = 100 (``notes/benchmarks.md``).  ``<W_{i,1}> (d + 1) count = S[N - i + 1][0]``.
    The keyword arguments are those of :func:`survival_table`.

    Parameters
    ----------
    N : int
        Number of layers, ``2..200``.
    workers : int, optional
        Worker processes, as in :func:`survival_table`.
    progress : callable, optional
        Called as ``progress(1)`` after each prime.
    executor : concurrent.futures.Executor or dask.distributed.Client, optional
        Runs the per-prime tasks, as in :func:`survival_table`.
    checkpoint : str, os.PathLike or CheckpointStore, optional
        Directory of the checkpoint records (as in :func:`survival_table`).

    Returns
    -------
    list of Fraction
        ``<W_{i,1}>`` for ``i = 1..N`` (the apex first, 1).

    Raises
    ------
    ArgumentError
        If ``N`` is outside ``2..200``.
    ArgumentTypeError
        If ``N`` is not an integer.
    ArithmeticError
        If a reconstructed sum is out of its proven range (a bug, never expected).

    Examples
    --------
    >>> [str(x) for x in lattice_direction(5)]
    ['1', '1/2', '41/132', '2/11', '1/11']
    """
    N = check_layers(N, maximum=MAX_N)
    n, d = N - 1, dimension(N)
    executor = as_executor(executor)
    total = count(N, checkpoint=checkpoint)
    if n == 0:
        return [Fraction(1)]
    primes = route_primes(N, (d + 1) * total)
    nworkers = workers_for(workers, len(primes), edge_seconds(N) * len(primes), executor)
    residues = run_primes(edge_residues, [(N, p) for p in primes], executor, nworkers, progress,
                          checkpoint_store(checkpoint, "lattice", N))
    den = (d + 1) * total
    column = dict(zip(range(1, n + 1), crt_many([[r[m] for r in residues] for m in range(1, n + 1)], primes)))
    if any(not 0 < v < den for v in column.values()):
        raise ArithmeticError("reconstructed lattice-direction sums out of range")
    return [Fraction(1)] + [Fraction(column[N - i + 1], den) for i in range(2, N + 1)]


def lattice_direction_plan(N: int, memory_bytes: int | None = None, workers: int | None = None, *,
                           executor: Executor | None = None, checkpoint: Checkpoint = None) -> Plan:
    """The cost of :func:`lattice_direction` (the plan of ``notes/benchmarks.md``'s model).

    With ``executor`` the plan counts its workers (and the scheduler's cost
    per task); with ``checkpoint`` it counts only the primes not yet recorded
    and says so.

    Parameters
    ----------
    N : int
        Number of layers, ``>= 2`` (the route reaches ``N <= 200``; above, the plan is refused).
    memory_bytes : int, optional
        Memory available to the run (None: not checked).
    workers : int, optional
        Local worker processes (default: the cores when the run pays for them).
    executor : concurrent.futures.Executor or Dask Client, optional
        Runs the per-prime tasks; the plan counts its workers.
    checkpoint : str, os.PathLike or CheckpointStore, optional
        The plan counts only the primes not yet recorded there.

    Returns
    -------
    Plan
        Its ``refusal`` says why when the request is out of reach.

    Raises
    ------
    ArgumentError
        If ``N < 2``.
    ArgumentTypeError
        If ``N`` is not an integer.

    Examples
    --------
    >>> lattice_direction_plan(100).runnable
    True
    """
    N = check_layers(N)
    what = f"<W_(i,1)> N={N} (Pfaffians)"
    if N > MAX_N:
        return Plan(what, 0, refusal=f"N={N} is out of range for the Pfaffian route: N must be an integer in 2..{MAX_N}")
    n = N - 1
    per_worker = worker_bytes(N, 2)
    return route_plan(what, N, edge_seconds(N), per_worker, workers, executor, checkpoint_store(checkpoint, "lattice", N),
                      memory_bytes, entries=n, lattice=True)


def mean_plan(N: int, *, memory_bytes: int | None = None, executor: Executor | None = None,
              workers: int | None = None, checkpoint: Checkpoint = None) -> Plan:
    """The cost of :func:`mean_W` (the mean of ``forcenet table --method pfaffian``), one tick per prime.

    Parameters
    ----------
    N : int
        Number of layers, ``>= 2`` (the route reaches ``N <= 200``).
    memory_bytes : int, optional
        Memory available to the run (None: not checked).
    executor : concurrent.futures.Executor or Dask Client, optional
        Runs the per-prime tasks; the plan counts its workers (and the
        scheduler's cost per task).  Default: a local process pool when the
        run pays for starting it.
    workers : int, optional
        Local worker processes (default: the cores when the run pays for them).
    checkpoint : str, os.PathLike or CheckpointStore, optional
        The plan counts only the primes not yet recorded there, and says so.

    Returns
    -------
    Plan

    Raises
    ------
    ArgumentError
        If ``N`` is not an integer ``>= 2``.

    Examples
    --------
    >>> plan = mean_plan(32)
    >>> plan.runnable, plan.ticks, plan.unit
    (True, 55, 'prime')
    >>> mean_plan(201).refusal
    'N=201 is out of range for --method pfaffian: N must be an integer in 2..200'
    """
    N = check_layers(N)
    what = f"exact table N={N} (Pfaffians)"
    refusal = table_range(what, "pfaffian", N, 1, MAX_N)
    if refusal is not None:
        return refusal
    n = N - 1
    per_worker = worker_bytes(N, n + 2)
    return route_plan(what, N, prime_seconds(N), per_worker, workers, executor, checkpoint_store(checkpoint, "table", N),
                      memory_bytes, entries=n * n, lattice=False)


def route_plan(what: str, N: int, per_prime: float, per_worker: int, workers: int | None, executor: Executor | None,
               store: CheckpointStore | None, memory_bytes: int | None, entries: int, lattice: bool,
               bound_factor: int = 1) -> Plan:
    """The plan of a run over the route's primes: :func:`forcenet.exact.triangle.prime_tasks.primes_plan` with this
    route's primes, Chinese remaindering and kernels.

    The primes are those of :func:`.cost.route_primes` for the bound
    ``bound_factor (d + 1) count`` (the survival sums'), those recorded in
    ``store`` not counted; the client's Chinese remaindering of ``entries``
    integers is quadratic in the number of primes; a local run compiles the
    kernels of :func:`.engine.prime_residues` (``lattice``: of
    :func:`.engine.edge_residues`) when this machine's cache lacks them.

    Examples
    --------
    >>> route_plan("x", 12, 0.01, 2**20, 1, None, None, None, 121, False).unit
    'prime'
    """
    n, d = N - 1, free_force_count(N)
    bound = (d + 1) * tableau_count(N) * bound_factor  # what the primes' product must exceed
    nprimes = ceil(bound.bit_length() / log2(prime_limit(max(n, 1)) * 0.999))
    reused = 0
    if store is not None:
        primes = route_primes(N, bound)
        nprimes, reused = len(primes), sum(store.holds(p) for p in primes)
    return primes_plan(what, per_prime, nprimes, per_worker, workers=workers, executor=executor, store=store,
                       reused=reused, crt_seconds=CRT_SECONDS * entries * nprimes**2, memory_bytes=memory_bytes,
                       compile=lambda plan, in_workers: with_kernels_compiled(plan, lattice, in_workers))
