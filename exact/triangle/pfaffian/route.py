"""The Pfaffian route: exact ``<W>`` tables and the normalization in time polynomial in ``N``.

``--method pfaffian`` of ``forcenet table``.  Residues from :mod:`.engine`
for enough word-size primes, rebuilt exactly by the Chinese remainder
theorem (the bound ``0 <= S[m][k] <= (d+1) count`` is proven, so the
reconstruction is exact).  The primes are independent tasks run by
:func:`forcenet.exact.execution.run_tasks` on an executor: a local process
pool by default, or any :class:`concurrent.futures.Executor` given as
``executor=`` (a Dask cluster: ``client.get_executor()``, or the client
itself); ``checkpoint=`` (a directory or a
:class:`~forcenet.exact.checkpoints.CheckpointStore`) records every finished
prime, so a rerun recomputes only the missing ones.  The result never depends
on either.

Cost ``O(N^7 log N)`` word operations: ``O(n^5)`` per prime (``d/2`` level
points, ``n + 1`` values of ``y``, an ``O(n^2)`` displacement elimination
each) and ``O(N^2 log N)`` primes.  Memory ``O(N^3)`` per worker.  It overtakes the
order-ideal DP (``2^(N-1)`` ideals) near ``N = 20`` (``notes/benchmarks.md``).

May import: :mod:`forcenet.exact.validation`, :mod:`forcenet.exact.modular`,
:mod:`forcenet.exact.plan`, :mod:`forcenet.exact.execution`,
:mod:`forcenet.exact.checkpoints` and its own package.

Examples
--------
>>> count(7), count(10)  # d! * normalization, Eq. (4.1)
(33592, 3973186258569120)
>>> [str(x) for x in mean_W(5)[-1]]  # Eqs. (4.63)-(4.77): the bottom row, N = 5
['1/11', '1/4', '7/22', '1/4', '1/11']
"""

from __future__ import annotations

from fractions import Fraction
from math import ceil, factorial, log2

from ...checkpoints import CheckpointStore
from ...execution import as_executor, available_cores, executor_label, executor_workers, run_tasks, wall_seconds
from ...modular import is_prime
from ...plan import Plan, first_moment_only
from ...validation import check_int, check_layers
from .engine import count_residue, edge_residues, level_points, prime_limit, prime_residues, with_kernels_compiled

__all__ = [
    "MAX_N",
    "route_primes",
    "count",
    "normalization",
    "survival_table",
    "mean_W",
    "expected_entries",
    "lattice_direction",
    "lattice_direction_plan",
    "table_plan",
    "table_run",
]

MAX_N = 200
# measured on the 2-core machine (numba 0.68, AVX-512), CPU seconds; notes/benchmarks.md
_SECONDS_PER_ROW = 1.14e-9  # per n^2 and y: the displacement elimination (n pivots of O(n) rows), fitted on N = 20, 100
_SECONDS_PER_PIVOT = 3.1e-8  # per n and y: a pivot's set-up (reading the pivot, the lanes' loop overhead)
_SECONDS_PER_KERNEL = 3.3e-10  # per s^3 of the kernel set-up (four solves with K(q), s = n + 1 or n + 2)
_SECONDS_PER_WEIGHT = 9e-9  # per M^2: the weights of the level functional, the sums over the points, the set-up
_STARTUP_SECONDS = 1.5  # numba import and loading the cached kernels (first compilation ever: ~10 s more)
_PARALLEL_MIN_SECONDS = 20.0  # below this, starting workers (numba import, ~3 s each) costs more than it saves
_TASK_OVERHEAD_SECONDS = 0.025  # a Dask scheduler's cost per task and worker on loopback, result included (benchmarks)
_CRT_SECONDS = 2.3e-9  # per reconstructed entry and prime^2: the client's Chinese remaindering (benchmarks)
_ROUTES = {"count": "pfaffian-count", "table": "pfaffian-table", "lattice": "pfaffian-lattice"}


def route_primes(N: int):
    """The primes of the route for ``N`` layers, largest first, below :func:`~.engine.prime_limit` ``(N - 1)``.

    Examples
    --------
    >>> from itertools import islice
    >>> list(islice(route_primes(32), 3))
    [33554393, 33554383, 33554371]
    """
    N = check_layers(N)
    p = prime_limit(max(N - 1, 1)) - 1
    while p > max(2 * N + 3, N * (N - 1) // 2 + 2):
        if is_prime(p):
            yield p
        p -= 1
    raise ArithmeticError(f"N={N}: ran out of primes")  # pragma: no cover - millions of primes


def _primes_above(bound: int, N: int) -> list[int]:
    """Route primes whose product exceeds ``bound`` (a non-negative integer ``<= bound`` is then determined)."""
    out, product = [], 1
    for p in route_primes(N):
        if product > bound:
            break
        out.append(p)
        product *= p
    return out


class _CRT:
    """Chinese remaindering with a precomputed basis: ``x = sum_i r_i e_i mod P``."""

    def __init__(self, primes):
        self.modulus = 1
        for p in primes:
            self.modulus *= p
        self.basis = []
        for p in primes:
            rest = self.modulus // p
            self.basis.append(rest * pow(rest % p, -1, p))

    def __call__(self, residues) -> int:
        return sum(int(r) * e for r, e in zip(residues, self.basis)) % self.modulus


def count(N: int, backend: str = "numba", *, executor=None, checkpoint=None) -> int:
    """The number of tableaux, ``count = d! Pf(B)`` (the normalization (4.1) times ``d!``), by this route.

    Multi-modular, with the proven bound ``count <= d!`` (linear extensions
    of ``d`` elements).  ``executor`` and ``checkpoint`` as in
    :func:`survival_table` (by default the primes run in this process).

    Examples
    --------
    >>> [count(N) for N in range(2, 8)]
    [1, 1, 2, 12, 286, 33592]
    """
    N = check_layers(N, maximum=MAX_N)
    primes = _primes_above(factorial(N * (N - 1) // 2), N)
    residues = _run_primes(count_residue, [(N, p, backend) for p in primes], executor, 1, None,
                           _store(checkpoint, "count", N))
    return _CRT(primes)([int(r) for r in residues])


def normalization(N: int, backend: str = "numba") -> Fraction:
    """The normalization (4.1), the volume of the triangle's force space: ``count / d! = Pf(B)``.

    Examples
    --------
    >>> normalization(4)
    Fraction(1, 360)
    """
    N = check_layers(N, maximum=MAX_N)
    return Fraction(count(N, backend), factorial(N * (N - 1) // 2))


def _store(checkpoint, route: str, N: int):
    """The checkpoint store of one route's request: None, from a directory, or a given store (reused when it is
    this request's, else its directory and report)."""
    if checkpoint is None:
        return None
    name = _ROUTES[route]
    if isinstance(checkpoint, CheckpointStore):
        if checkpoint.request["route"] == name and checkpoint.request["N"] == N:
            return checkpoint
        return CheckpointStore(checkpoint.directory, name, N, report=checkpoint.report)
    return CheckpointStore(checkpoint, name, N)


def _run_primes(function, tasks, executor, nworkers: int, progress, store):
    """``[function(*task)]`` over the tasks (``task[1]`` is the prime, the checkpoint key), in task order: on the
    executor, else in ``nworkers`` local processes (spawn: the parent may hold threads, the children load the
    cached kernels)."""
    return run_tasks(function, tasks, executor=executor, workers=nworkers, progress=progress, store=store,
                     keys=[task[1] for task in tasks])


def _workers(workers, tasks: int, seconds: float, executor=None) -> int:
    """Tasks run at once: the executor's workers, else ``workers`` local processes (default: the cores when the
    run pays for starting them)."""
    if executor is not None:
        return max(1, executor_workers(executor) or 1)
    if workers is None:
        workers = available_cores() if seconds >= _PARALLEL_MIN_SECONDS else 1
    workers = check_int(workers, "workers", 1)
    return max(1, min(workers, tasks))


def survival_table(N: int, *, workers: int | None = None, progress=None, backend: str = "numba", executor=None,
                   checkpoint=None):
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
    backend : {"numba", "python"}
        Compiled kernels or their pure-Python twins (tests, small ``N``).
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

    Examples
    --------
    >>> S, total = survival_table(4)
    >>> total, S[1], S[3]
    (2, [2, 5, 5, 2], [7, 7, 0, 0])
    """
    N = check_layers(N, maximum=MAX_N)
    n, d = N - 1, N * (N - 1) // 2
    executor = as_executor(executor)
    total = count(N, backend, executor=executor, checkpoint=checkpoint)
    if n == 0:
        return [[0]], total
    primes = _primes_above((d + 1) * total, N)
    tasks = [(N, p, backend, total % p) for p in primes]
    nworkers = _workers(workers, len(tasks), _seconds(N) * len(primes), executor)
    residues = _run_primes(prime_residues, tasks, executor, nworkers, progress, _store(checkpoint, "table", N))
    crt = _CRT(primes)
    out = [[0] * (n + 1)]
    for m in range(1, n + 1):
        out.append([crt([r[m, k] for r in residues]) for k in range(n + 1)])
    if any(sum(row) != (d + 1) * total for row in out[1:]):
        raise ArithmeticError("reconstructed rows do not sum to (d + 1) count")
    return out, total


def mean_W(N: int, **kwargs) -> list[list[Fraction]]:
    """Exact ``<W_{i,j}>`` table, rows ``i = 1..N``, ``j = 1..i``, by Pfaffians (Eqs. (4.63)-(4.77)).

    ``<W_ij> (d + 1) count = S[m][j - 1]`` with ``m = N - i + 1``: the grain's
    bounding partial sums are eligible exactly when ``N_m(A) = j - 1``
    (``notes/free_fermions.md`` Sec. 0).  Same layout as
    :func:`forcenet.exact.triangle.moments.mean_W`; keyword arguments go to
    :func:`survival_table`.

    Examples
    --------
    >>> [str(x) for x in mean_W(4)[-1]]
    ['1/7', '5/14', '5/14', '1/7']
    """
    N = check_layers(N, maximum=MAX_N)
    S, total = survival_table(N, **kwargs)
    den = total * (N * (N - 1) // 2 + 1)
    table = [[Fraction(1)]]
    for i in range(2, N + 1):
        m = N - i + 1
        table.append([Fraction(S[m][j - 1], den) for j in range(1, i + 1)])
    return table


def expected_entries(N: int, **kwargs) -> dict:
    """``E[T(r, c)]`` of a uniform random standard tableau of the shifted staircase, every cell (exact).

    ``T(x) = #{k : x not in I_k}`` along the chain, so
    ``E[T(r, c)] count = sum_{k < r} S[c - r + 1][k]``.

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


def lattice_direction(N: int, *, workers: int | None = None, progress=None, backend: str = "numba", executor=None,
                      checkpoint=None) -> list[Fraction]:
    """Exact ``<W_{i,1}> = <W_{i,i}>`` for ``i = 1..N``: the response on the two lattice directions.

    Only the first column ``S[m][0]`` of the survival table, from two
    eliminations per level point instead of ``n + 1`` (:func:`~.engine.edge_residues`);
    the kernel set-up, the same for both, is then most of the work: about 4
    times cheaper than :func:`mean_W` at N = 100 (``notes/benchmarks.md``).  ``<W_{i,1}> (d + 1) count = S[N - i + 1][0]``.
    The keyword arguments are those of :func:`survival_table`.

    Examples
    --------
    >>> [str(x) for x in lattice_direction(5)]
    ['1', '1/2', '41/132', '2/11', '1/11']
    """
    N = check_layers(N, maximum=MAX_N)
    n, d = N - 1, N * (N - 1) // 2
    executor = as_executor(executor)
    total = count(N, backend, executor=executor, checkpoint=checkpoint)
    if n == 0:
        return [Fraction(1)]
    primes = _primes_above((d + 1) * total, N)
    nworkers = _workers(workers, len(primes), _edge_seconds(N) * len(primes), executor)
    residues = _run_primes(edge_residues, [(N, p, backend) for p in primes], executor, nworkers, progress,
                           _store(checkpoint, "lattice", N))
    crt = _CRT(primes)
    den = (d + 1) * total
    column = {m: crt([r[m] for r in residues]) for m in range(1, n + 1)}
    if any(not 0 < v < den for v in column.values()):
        raise ArithmeticError("reconstructed lattice-direction sums out of range")
    return [Fraction(1)] + [Fraction(column[N - i + 1], den) for i in range(2, N + 1)]


def _edge_seconds(N: int) -> float:
    """CPU seconds of one prime of :func:`lattice_direction`."""
    n, d = N - 1, N * (N - 1) // 2
    s = n + 1 + (n + 1) % 2
    per_y = _SECONDS_PER_PIVOT * n + _SECONDS_PER_ROW * n**2
    return level_points(d) // 2 * (2 * per_y + _SECONDS_PER_KERNEL * s**3) + _SECONDS_PER_WEIGHT * level_points(d) ** 2 + 1e-3


def lattice_direction_plan(N: int, memory_bytes: int | None = None, workers: int | None = None, *, executor=None,
                           checkpoint=None) -> Plan:
    """The cost of :func:`lattice_direction` (the plan of ``notes/benchmarks.md``'s model).

    With ``executor`` the plan counts its workers (and the scheduler's cost
    per task); with ``checkpoint`` it counts only the primes not yet recorded
    and says so.

    Examples
    --------
    >>> lattice_direction_plan(100).runnable
    True
    """
    N = check_layers(N)
    what = f"<W_(i,1)> N={N} (Pfaffians)"
    if N > MAX_N:
        return Plan(what, 0, refusal=f"N={N} is out of range for the Pfaffian route: N must be an integer in 2..{MAX_N}")
    n, d = N - 1, N * (N - 1) // 2
    per_worker = level_points(d) // 2 * 2 * n * 8 + 160 * 2**20
    return _primes_plan(what, N, _edge_seconds(N), per_worker, workers, executor, _store(checkpoint, "lattice", N),
                        memory_bytes, entries=n, lattice=True)


def _primes_plan(what: str, N: int, per_prime: float, per_worker: int, workers, executor, store, memory_bytes,
                 entries: int, lattice: bool) -> Plan:
    """The plan of a run over the route's primes: ``per_prime`` CPU seconds each, spread over the workers (those of
    ``executor``, else local processes), the primes recorded in ``store`` not counted; then the client's Chinese
    remaindering of ``entries`` integers (quadratic in the number of primes); compiling the kernels first when this
    machine's cache lacks them (a local run)."""
    n, d = N - 1, N * (N - 1) // 2
    nprimes = ceil(((d + 1) * _count_bound(N)).bit_length() / log2(prime_limit(max(n, 1)) * 0.999))
    reused = 0
    if store is not None:
        primes = _primes_above((d + 1) * _count_bound(N), N)
        nprimes, reused = len(primes), sum(store.holds(p) for p in primes)
    executor = as_executor(executor)
    nworkers = _workers(workers, max(1, nprimes - reused), per_prime * (nprimes - reused), executor)
    overhead = _TASK_OVERHEAD_SECONDS if executor is not None else 0.0
    seconds = (_STARTUP_SECONDS * (1 + (nworkers > 1)) + wall_seconds(per_prime, nprimes - reused, nworkers, overhead)
               + _CRT_SECONDS * entries * nprimes**2)
    if executor is not None:
        what += f" on {nworkers} worker{'s' if nworkers > 1 else ''} of {executor_label(executor)}"
    if store is not None:
        what += f"; checkpoints in {store.path}: {reused} of {nprimes} primes recorded"
    local = 1 if executor is not None else nworkers  # a cluster's workers hold their share on their own machines
    plan = Plan(what, seconds, local * per_worker, nprimes, "prime")
    if executor is None:  # the workers compile (or load) the kernels on their own machines
        plan = with_kernels_compiled(plan, lattice)
    return plan.within_memory(memory_bytes)


def _seconds(N: int) -> float:
    """CPU seconds of one prime (the model of ``notes/benchmarks.md``)."""
    n, d = N - 1, N * (N - 1) // 2
    reps = level_points(d) // 2
    ys = 2 * ((n + 1) // 2)
    s = n + 1 + (n + 1) % 2
    per_y = _SECONDS_PER_PIVOT * n + _SECONDS_PER_ROW * n**2
    return reps * (ys * per_y + _SECONDS_PER_KERNEL * s**3) + _SECONDS_PER_WEIGHT * level_points(d) ** 2 + 1e-3


def table_plan(N: int, moments: int = 1, memory_bytes: int | None = None, workers: int | None = None, *,
               executor=None, checkpoint=None) -> Plan:
    """The cost of :func:`table_run` (``forcenet table --method pfaffian``); ``executor`` and ``checkpoint`` as in
    :func:`lattice_direction_plan`.

    Examples
    --------
    >>> plan = table_plan(32)
    >>> plan.runnable, plan.ticks, plan.unit
    (True, 55, 'prime')
    >>> table_plan(8, moments=2).refusal
    'moments=2 is out of range for --method pfaffian: moments must be 1 (higher moments use --method fast, thesis or maps)'
    >>> table_plan(201).refusal
    'N=201 is out of range for --method pfaffian: N must be an integer in 2..200'
    """
    N, moments = check_layers(N), check_int(moments, "moments", 1)
    what = f"exact table N={N} (Pfaffians)"
    if moments > 1:
        return first_moment_only(what, "pfaffian", moments)
    if N > MAX_N:
        return Plan(what, 0, refusal=f"N={N} is out of range for --method pfaffian: N must be an integer in 2..{MAX_N}")
    n, d = N - 1, N * (N - 1) // 2
    per_worker = level_points(d) // 2 * (n + 2) * n * 8 + 160 * 2**20
    return _primes_plan(what, N, _seconds(N), per_worker, workers, executor, _store(checkpoint, "table", N),
                        memory_bytes, entries=n * n, lattice=False)


def _count_bound(N: int) -> int:
    """``count(N)`` for the plan's prime count (the product formula; the run recomputes it by Pfaffians)."""
    from ..staircase import count as product_formula

    return product_formula(N)


def table_run(N: int, moments: int = 1, progress=None, workers: int | None = None, *, executor=None,
              checkpoint=None) -> dict:
    """``{1: <W> table}`` by Pfaffians; ``progress(1)`` per prime; the keywords of :func:`survival_table`.

    Examples
    --------
    >>> [str(x) for x in table_run(5)[1][-1]]
    ['1/11', '1/4', '7/22', '1/4', '1/11']
    """
    N = check_layers(N, maximum=MAX_N)
    check_int(moments, "moments", 1, 1)
    return {1: mean_W(N, progress=progress, workers=workers, executor=executor, checkpoint=checkpoint)}
