"""Independent uniform samples of the fully mobilized triangle (no Markov chain).

A uniform point of the force network ensemble is a uniform random standard
shifted tableau ``T`` of staircase shape ``(N-1, ..., 1)`` plus ``d`` sorted
uniform numbers placed by rank: ``S_x = U_(T(x))`` (``notes/order_polytope.md``).
The tableau is drawn by removing the largest entry first: from shape
``lambda`` the corner in row ``r`` holds the largest entry with probability
``g(lambda - e_r) / g(lambda)``, which Schur's product formula for the number
``g`` of shifted tableaux gives in closed form.

Examples
--------
>>> from forcenet.numeric.triangle.exact_sampler import ExactSampler
>>> sampler = ExactSampler(5, seed=1)
>>> W = sampler.sample_W(4)
>>> W.shape
(4, 5, 5)
>>> bool(abs(W.sum(axis=2) - 1).max() < 1e-12)  # every row carries the unit load
True
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from forcenet.core.plan import Plan, with_compilation
from forcenet.core.validation import check_fits_memory, check_int, check_layers, check_seed
from forcenet.exact.triangle.staircase import dimension

from ..jit import chunks, first_chunk, kernel_choice

if TYPE_CHECKING:
    from forcenet.core.plan import Plan

__all__ = ["ExactSampler", "mean_and_error", "q_from_W", "removal_probabilities", "sample_tableaux", "tableaux_to_W"]


def removal_probabilities(parts: np.ndarray) -> np.ndarray:
    """Probability that the largest entry sits at the end of each row.

    ``parts`` has shape ``(B, L)``: strict partitions, descending, zero-padded.
    Returns ``(B, L)`` probabilities (zero where the row has no removable
    corner); each row of the result sums to 1.

    Examples
    --------
    >>> removal_probabilities(np.array([[2, 1]])).round(6).tolist()
    [[0.0, 1.0]]
    >>> removal_probabilities(np.array([[3, 1]])).round(6).tolist()
    [[0.5, 0.5]]
    """
    lam = parts.astype(np.float64)
    size = lam.sum(axis=1, keepdims=True)
    nxt = np.concatenate([parts[:, 1:], np.zeros_like(parts[:, :1])], axis=1)
    removable = (parts > 0) & ((parts - 1 > nxt) | ((parts == 1) & (nxt == 0)))
    a = lam[:, :, None]  # row r being shortened
    b = lam[:, None, :]  # other rows j
    present = (b > 0) & ~np.eye(parts.shape[1], dtype=bool)[None]
    with np.errstate(divide="ignore", invalid="ignore"):
        factor = ((a - 1 - b) * (a + b)) / ((a - b) * (a - 1 + b))
    factor = np.where(present & removable[:, :, None], factor, 1.0)
    prob = np.where(removable, lam / size * np.prod(factor, axis=2), 0.0)
    return prob


def _pair_terms(a: np.ndarray, b: np.ndarray, logtab: np.ndarray) -> np.ndarray:
    """``log F(a, b)``: the factor of row ``b`` in the removal weight of row ``a``.

    ``F(a, b) = |a-1-b| (a+b) / (|a-b| (a-1+b))`` (Schur's formula); callers
    mask out ``b = 0`` and ``b = a - 1``.
    """
    return (
        logtab[np.abs(a - 1 - b)] + logtab[a + b] - logtab[np.abs(a - b)] - logtab[np.maximum(a - 1 + b, 0)]
    )


def _full_phi(parts: np.ndarray, logtab: np.ndarray) -> np.ndarray:
    """``Phi_r = sum_{j != r} log F(lambda_r, lambda_j)`` over present, non-adjacent rows."""
    a = parts[:, :, None]
    b = parts[:, None, :]
    use = (b > 0) & (a > 0) & (b != a - 1) & ~np.eye(parts.shape[1], dtype=bool)[None]
    return np.where(use, _pair_terms(a, b, logtab), 0.0).sum(axis=2)


def sample_tableaux(N: int, size: int, rng: np.random.Generator, refresh: int | None = None,
                    progress: Callable[[int], object] | None = None) -> np.ndarray:
    """Uniform random standard shifted staircase tableaux.

    The largest remaining entry goes to the end of row ``r`` with
    probability ``g(lambda - e_r) / g(lambda) = (lambda_r/|lambda|) exp(Phi_r)``;
    the log-weights ``Phi`` are updated in ``O(n)`` per removal (only the
    factors involving the shortened row change) and recomputed from scratch
    every ``refresh`` steps against rounding drift.

    Parameters
    ----------
    N : int
        Layers of the triangle, ``>= 2``: the staircase has rows ``n, ..., 1``, ``n = N - 1``.
    size : int
        Tableaux to draw.
    rng : numpy.random.Generator
        The stream.
    refresh : int, optional
        Removals between recomputations of the weights (default ``10 n``).
    progress : callable, optional
        Called with 1 after each removal (every entry of all ``size`` tableaux at once).

    Returns
    -------
    numpy.ndarray
        ``T`` of shape ``(size, n + 1, n + 1)`` with ``T[:, r, c]`` the entry of
        cell ``(r, c)``, ``1 <= r <= c <= n``, zero elsewhere.

    Raises
    ------
    forcenet.core.errors.ArgumentError
        On ``N < 2``.

    Examples
    --------
    >>> T = sample_tableaux(3, 2, np.random.default_rng(0))
    >>> T[0, 1:, 1:].tolist()  # the only tableau of shape (2, 1)
    [[1, 2], [0, 3]]
    """
    N = check_layers(N)
    n = N - 1
    d = dimension(N)
    refresh = refresh or 10 * n
    logtab = np.log(np.maximum(np.arange(2 * n + 2, dtype=np.float64), 1.0))
    parts = np.tile(np.arange(n, 0, -1, dtype=np.int64), (size, 1))
    dtype = np.int32 if d < 2**31 else np.int64
    T = np.zeros((size, n + 1, n + 1), dtype=dtype)
    rows = np.arange(size)
    phi = _full_phi(parts, logtab)
    nxt = np.zeros((size, n), dtype=np.int64)
    for step, entry in enumerate(range(d, 0, -1)):
        if step and step % refresh == 0:
            phi = _full_phi(parts, logtab)
        nxt[:, :-1] = parts[:, 1:]
        removable = (parts > 0) & ~((nxt > 0) & (nxt == parts - 1))
        logw = np.where(removable, phi + logtab[parts], -np.inf)
        w = np.exp(logw - logw.max(axis=1, keepdims=True))
        cum = np.cumsum(w, axis=1)
        u = rng.random(size) * cum[:, -1]
        r = np.minimum((cum < u[:, None]).sum(axis=1), n - 1)
        a = parts[rows, r]
        T[rows, r + 1, r + a] = entry  # 0-based row r spans columns r+1..r+a (1-based)
        # O(n) update of Phi for the other rows: the factor of row r changes a -> a-1
        others = parts
        A = a[:, None]
        old_ok = (others > 0) & (A != others - 1)
        new_ok = (others > 0) & (A - 1 > 0) & (A - 1 != others - 1)
        phi -= np.where(old_ok, _pair_terms(others, A, logtab), 0.0)
        phi += np.where(new_ok, _pair_terms(others, A - 1, logtab), 0.0)
        parts[rows, r] = a - 1
        # Phi of the shortened row itself, from scratch
        B = parts
        own = (B > 0) & (B != A - 2) & (np.arange(n)[None, :] != r[:, None]) & (A - 1 > 0)
        phi[rows, r] = np.where(own, _pair_terms(A - 1, B, logtab), 0.0).sum(axis=1)
        if progress is not None:
            progress(1)
    return T


def tableaux_to_W(T: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """Place sorted uniforms by rank and return ``W`` of shape ``(B, N, N)``.

    ``W[:, i-1, j-1]`` is ``W_{i,j}`` (zero for ``j > i``).

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> W = tableaux_to_W(sample_tableaux(4, 3, rng), rng)
    >>> W.shape, bool(np.allclose(W.sum(axis=2), 1.0))
    ((3, 4, 4), True)
    """
    B, n1, _ = T.shape
    n = n1 - 1
    N = n + 1
    d = dimension(N)
    U = np.sort(rng.random((B, d)), axis=1)
    U = np.concatenate([np.zeros((B, 1)), U], axis=1)  # U[:, k] = k-th order statistic
    S = np.zeros((B, N, N + 1))  # S[:, i-1, j] = S_{i,j}, S_{i,0} = 0
    for i in range(1, N + 1):
        for j in range(1, i):
            S[:, i - 1, j] = U[np.arange(B), T[:, j, N - i + j]]
        S[:, i - 1, i] = 1.0
    return np.diff(S, axis=2) * (np.arange(N)[None, :, None] >= np.arange(N)[None, None, :])


def q_from_W(W: np.ndarray) -> np.ndarray:
    """q-coordinates (Eq. 4.6) of sampled configurations, shape ``(B, N-1, N-1)``.

    ``q_{i,j} = (S_{i+1,j} - S_{i,j-1}) / W_{i,j}``; NaN where ``W_{i,j} = 0``.

    Examples
    --------
    >>> W = np.array([[[1.0, 0.0], [0.25, 0.75]]])
    >>> q_from_W(W).tolist()
    [[[0.25]]]
    """
    S = np.cumsum(W, axis=2)
    B, N, _ = W.shape
    prev = np.concatenate([np.zeros((B, N, 1)), S[:, :, :-1]], axis=2)  # S_{i,j-1}
    with np.errstate(divide="ignore", invalid="ignore"):
        q = (S[:, 1:, : N - 1] - prev[:, :-1, : N - 1]) / W[:, :-1, : N - 1]
    return np.where(np.tril(np.ones((N - 1, N - 1), dtype=bool)), q, np.nan)


def mean_and_error(total: np.ndarray, squares: np.ndarray, samples: int) -> tuple[np.ndarray, np.ndarray]:
    """Mean and standard error of the mean from the sum and the sum of squares of ``samples`` independent draws.

    Examples
    --------
    >>> m, e = mean_and_error(np.array([6.0]), np.array([14.0]), 3)  # draws 1, 2, 3
    >>> float(m[0]), round(float(e[0]) ** 2, 12)  # variance 1, over 3 draws
    (2.0, 0.333333333333)
    """
    mean = total / samples
    var = np.maximum(squares / samples - mean**2, 0.0) * samples / (samples - 1)
    return mean, np.sqrt(var / samples)



def _hook_walk() -> Callable[..., Any]:
    """The compiled hook walk, imported when first needed (its numba decoration imports numba)."""
    from .hook_walk import hook_walk_W

    return hook_walk_W

class ExactSampler:
    """Exact (independent, uniform) sampler of the fully mobilized triangle.

    Parameters
    ----------
    N : int
        Number of layers.
    seed : int or numpy.random.Generator, optional
        Seed for reproducible streams.
    batch : int
        Samples per batch of the reference kernel.
    kernel : {None, "compiled", "python"}
        ``"python"``: the reference route, :func:`sample_tableaux` (Schur's
        removal weights, ``O(d n)`` per tableau, vectorized over a batch) and
        :func:`tableaux_to_W`; ``"compiled"``: Sagan's shifted hook walk
        (:func:`forcenet.numeric.triangle.hook_walk.hook_walk_W`, numba,
        ``O(d log n)`` per tableau, one sample at a time so the stream does not
        depend on batching); ``None`` (default): compiled when numba is
        available.  The two draw from the same distribution but consume the
        random stream differently, so a seed gives different samples.

    Examples
    --------
    >>> s = ExactSampler(4, seed=0)
    >>> mean, stderr = s.mean_W(2000)
    >>> bool(abs(mean[3, 0] - 1 / 7) < 5 * stderr[3, 0])  # exact <W_41> = 1/7
    True
    """

    def __init__(self, N: int, seed: int | np.random.Generator | None = None, batch: int = 4096, kernel: str | None = None) -> None:
        self.kernel = kernel_choice(kernel)
        self.N = check_layers(N)
        check_fits_memory(16 * self.N * (self.N + 1), f"one sample of N={self.N}", "N up to a few 10^4 fits "
                          "(N = 1000: 0.08 s per sample)")
        self.rng = np.random.default_rng(check_seed(seed))
        batch = check_int(batch, "batch", 1)
        # a batch holds B tableaux of N^2 int32 entries: keep it under ~1 GiB
        self.batch = max(1, min(batch, 2**28 // (self.N * self.N)))

    def _compiled(self, size: int, W_out: np.ndarray | None = None, sums: np.ndarray | None = None,
                  squares: np.ndarray | None = None, orders: np.ndarray | None = None,
                  progress: Callable[[int], object] | None = None) -> None:
        """``size`` hook-walk samples into ``W_out`` or added to ``sums``/``squares``, in calls of ~0.15 s.

        Each sample consumes its own stretch of the stream, so the calls
        (:func:`forcenet.numeric.jit.chunks`) change nothing but when Ctrl-C is
        seen; ``progress(k)`` after each call of ``k`` samples.
        """

        N = self.N
        empty = np.zeros((0, N, N))
        stats = np.zeros(1, np.int64)
        orders = np.zeros(0, np.int64) if orders is None else orders
        sums = empty if sums is None else sums
        squares = empty if squares is None else squares
        per_sample = _SECONDS_PER_SQUARE_LOG * N * N * math.log(max(N, 2))
        for start, stop in chunks(size, first_chunk(per_sample)):
            out = empty if W_out is None else W_out[start:stop]
            _hook_walk()(self.rng, N, stop - start, out, sums, squares, orders, stats)
            if progress is not None:
                progress(stop - start)

    def sample_W(self, size: int) -> np.ndarray:
        """``size`` independent configurations, ``W`` of shape ``(size, N, N)``.

        Parameters
        ----------
        size : int
            Number of configurations, ``>= 0``.

        Returns
        -------
        numpy.ndarray
            ``W[k, i-1, j-1] = W_{i,j}`` of configuration ``k`` (zero above the diagonal); each row sums to 1.

        Examples
        --------
        >>> W = ExactSampler(4, seed=1).sample_W(3)
        >>> W.shape, bool(np.allclose(W.sum(axis=2), 1))
        ((3, 4, 4), True)
        """
        size = check_int(size, "size", 0)
        check_fits_memory(8 * size * self.N * self.N, f"sample_W(size={size}) at N={self.N}",
                          "draw fewer at a time, or use moment_sums (running sums, no array of samples)")
        if self.kernel == "compiled":
            W = np.empty((size, self.N, self.N))
            self._compiled(size, W_out=W)
            return W
        T = sample_tableaux(self.N, size, self.rng)
        return tableaux_to_W(T, self.rng)

    def moment_sums(self, samples: int, orders: Sequence[int] = (1, 2),
                    progress: Callable[[int], object] | None = None) -> dict[int, tuple[np.ndarray, np.ndarray]]:
        """Raw sums over ``samples`` independent draws: ``{s: (sum W**s, sum W**(2s))}``, arrays ``(N, N)``.

        Sums from independent runs add (e.g. from several processes, ``forcenet sample --workers``).

        Parameters
        ----------
        samples : int
            Number of independent draws, ``>= 1``.
        orders : sequence of int
            The powers ``s >= 1``.
        progress : callable, optional
            Called with the number of draws done since its last call.

        Returns
        -------
        dict of int to (numpy.ndarray, numpy.ndarray)
            ``{s: (sum of W**s, sum of W**(2s))}``, arrays of shape ``(N, N)``.

        Examples
        --------
        >>> sums = ExactSampler(3, seed=1).moment_sums(10, orders=(1,))
        >>> float(sums[1][0][0, 0])  # W_11 = 1 in every draw
        10.0
        """
        samples = check_int(samples, "samples", 1)
        orders = tuple(check_int(s, "orders", 1) for s in orders)
        if self.kernel == "compiled":
            N = self.N
            table = np.zeros((len(orders), N, N))
            table2 = np.zeros((len(orders), N, N))
            self._compiled(samples, sums=table, squares=table2, orders=np.array(orders, dtype=np.int64),
                           progress=progress)
            return {s: (table[o], table2[o]) for o, s in enumerate(orders)}
        sums = {s: np.zeros((self.N, self.N)) for s in orders}
        squares = {s: np.zeros((self.N, self.N)) for s in orders}
        done = 0
        while done < samples:
            k = min(self.batch, samples - done)
            W = self.sample_W(k)
            for s in orders:
                Ws = W**s
                sums[s] += Ws.sum(axis=0)
                squares[s] += (Ws * Ws).sum(axis=0)
            done += k
            if progress is not None:
                progress(k)
        return {s: (sums[s], squares[s]) for s in orders}

    def moments(self, samples: int, orders: Sequence[int] = (1, 2),
                progress: Callable[[int], object] | None = None) -> dict[int, tuple[np.ndarray, np.ndarray]]:
        """Sample means of ``W**s`` and their standard errors (independent draws).

        Parameters
        ----------
        samples : int
            Number of independent draws, ``>= 2`` (an error bar needs two).
        orders : sequence of int
            The powers ``s >= 1``.
        progress : callable, optional
            Called with the number of draws done since its last call.

        Returns
        -------
        dict of int to (numpy.ndarray, numpy.ndarray)
            ``{s: (mean, stderr)}`` with arrays of shape ``(N, N)``.

        Examples
        --------
        >>> m = ExactSampler(3, seed=1).moments(2000, orders=(2,))
        >>> mean, err = m[2]
        >>> bool(abs(mean[2, 0] - 1 / 10) < 5 * err[2, 0])  # <W_31^2> = 1/10
        True
        """
        samples = check_int(samples, "samples", 2)  # an error bar needs two
        return {s: mean_and_error(total, squares, samples)
                for s, (total, squares) in self.moment_sums(samples, orders, progress).items()}

    def mean_W(self, samples: int, progress: Callable[[int], object] | None = None) -> tuple[np.ndarray, np.ndarray]:
        """Sample mean of ``W`` and its standard error, arrays ``(N, N)``.

        Parameters
        ----------
        samples : int
            Number of independent draws, ``>= 2``.
        progress : callable, optional
            Called with the number of draws done since its last call.

        Returns
        -------
        (numpy.ndarray, numpy.ndarray)
            The mean and its standard error, ``[i-1, j-1]`` for grain ``(i, j)``.

        Examples
        --------
        >>> mean, err = ExactSampler(3, seed=1).mean_W(2000)
        >>> bool(abs(mean[2, 1] - 1 / 2) < 5 * err[2, 1])  # <W_32> = 1/2
        True
        """
        return self.moments(samples, (1,), progress)[1]


_SECONDS_PER_CUBE = 6.5e-8  # reference kernel: seconds per sample and N^3, measured N = 12..300 (2 cores)
_SECONDS_PER_SQUARE_LOG = 1.25e-8  # hook walk: seconds per sample and N^2 ln N, measured N = 200..2000
COMPILE_SECONDS = 9.6  # compiling the hook walk on a first run (empty numba cache): benchmarks/compile_times.py


def sample_plan(N: int, samples: int, memory_bytes: int | None = None, kernel: str | None = None) -> Plan:
    """The cost of drawing ``samples`` exact samples of the ``N``-layer triangle.

    Examples
    --------
    >>> sample_plan(12, 20000).seconds < 3
    True
    >>> sample_plan(1000, 1000).seconds < 300
    True
    >>> sample_plan(100000, 2, memory_bytes=24 * 2**30).runnable
    False
    """

    N, samples = check_layers(N), check_int(samples, "samples", 1)
    compiled = kernel_choice(kernel) == "compiled"
    if compiled:  # one sample at a time: T, W, sums and squares, O(N^2) each
        nbytes = 8 * N * N * 8 + 100 * 2**20
        seconds = _SECONDS_PER_SQUARE_LOG * N * N * math.log(N) * samples + 1.0  # + loading the cached kernel
    else:
        batch = max(1, min(4096, 2**28 // (N * N), samples))
        nbytes = batch * N * N * 32 + 100 * 2**20
        seconds = _SECONDS_PER_CUBE * N**3 * samples + 0.3
    plan = Plan(f"{samples} exact samples N={N}", seconds, nbytes, samples, "sample")
    if compiled:  # a first run (numba's cache lacks the hook walk) compiles it
        plan = with_compilation(plan, "exact sampler", COMPILE_SECONDS, [_hook_walk()])
    return plan.within_memory(memory_bytes)
