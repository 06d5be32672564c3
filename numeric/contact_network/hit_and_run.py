"""Uniform samples of the force network ensemble on any contact network: coordinate hit-and-run.

The ensemble is the uniform measure on the polytope ``{z : A z = b, G z >= 0}``
(thesis Sec. 2.3.2; :mod:`forcenet.exact.contact_network.polytope`).  The
thesis walks through it "after finding a basis of Ker A", which it calls a
difficult problem for an arbitrary packing.  Two routes (``basis=``):

* ``"dense"``: an orthonormal basis from the singular value decomposition of
  ``A`` (``scipy.linalg.null_space``), so coordinates ``x`` with
  ``z = z* + K x`` are an isometry of the affine subspace and the uniform
  measure in ``x`` is the uniform measure on the force networks; the moves
  below run along its columns (after burn-in rounding);
* ``"projected"``: the same kind of basis without the SVD: ``d`` standard
  normal vectors projected onto ``Ker A`` by the sparse LU of ``A A^T``
  (:mod:`~.kernel_projection`) span the kernel with probability 1, and their
  QR factorization makes them orthonormal; ``O(d * contacts^2)`` less than
  the SVD (2212 contacts: 0.5 s against 3.3 s), ``d * contacts`` floats;
* ``"sparse"``: no basis at all: each move runs along a fresh uniformly random
  direction of ``Ker A``, a standard normal vector projected by one sparse
  solve with ``A A^T`` (:mod:`~.kernel_projection`; Smith's hit-and-run),
  when even the basis does not fit in memory (each move pays a solve's share);
* ``"auto"`` (default): :func:`route_for`: dense below :data:`SPARSE_FROM`
  variables, projected from there while the basis fits in
  :data:`BASIS_BYTES`, sparse beyond; dense when ``A A^T`` is singular.

The move (hit-and-run along the basis directions, "coordinate hit-and-run"):
pick a basis direction ``k`` uniformly, intersect the line ``z + t K_k`` with
every facet ``g_r . z >= 0`` exactly (``t`` between the largest ``-s_r/a_r``
over ``a_r > 0`` and the smallest over ``a_r < 0``, ``s = G z``,
``a = G K_k``), and jump to a uniform point of that chord.  Each move draws
from the uniform measure's exact conditional law on the line, so it leaves
the uniform measure invariant (a Gibbs step, reversible); with directions
spanning the space and a convex body, the chain is irreducible and converges
to the uniform measure (Smith 1984, Oper. Res. 32:1296; Belisle, Romeijn and
Smith 1993 for general direction laws; Lovasz 1999 for hit-and-run's mixing).
A recorded sample is one sweep (``d`` moves); error bars come from the
integrated autocorrelation time of each force's chain
(:func:`forcenet.numeric.autocorr.mean_and_stderr`).

Each move costs ``O(contacts)`` (one column of ``K`` and ``G K``, or one
projected direction), so a sweep costs ``O(d * contacts)``; the projected and
sparse routes' set-up is one sparse LU instead of the SVD's
``O(rows * contacts^2)``.  Rounding drift off ``A z = b`` is removed
between compiled calls by projecting back onto the affine subspace.

Examples
--------
>>> from forcenet.exact.contact_network.model import contact_network
>>> net = contact_network(1, [[0, None, "-3/5", "-4/5"], [0, None, "3/5", "-4/5"], [0, None, 0, -1]], [[0, 0, -1]])
>>> walk = HitAndRun(net)
>>> walk.dimension
1
>>> chain = walk.run(4000, seed=1)
>>> mean, err, tau = chain.statistics()
>>> bool(abs(mean[2] - 0.5) < 5 * err[2])  # the exact mean of the floor's force is 1/2
True
"""

from __future__ import annotations

import time
from collections.abc import Callable
from contextlib import nullcontext
from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy import linalg

from forcenet.core.errors import ArgumentError, ConvergenceError
from forcenet.core.execution import run_tasks
from forcenet.core.validation import check_int
from forcenet.exact.contact_network.model import ContactNetwork
from forcenet.exact.contact_network.polytope import Balance, balance, check_polytope, float_system

from ..autocorr import AutocorrError, mean_and_stderr, pool_means
from ..jit import chunks, first_chunk, njit
from .chain_records import block_rows, block_shape, chain_store, decode_block, encode_block
from .kernel_projection import BATCH, KernelProjector

__all__ = ["HitAndRun", "Chain", "hit_and_run_sweeps", "SECONDS_PER_FLOP", "sweep_seconds", "setup_seconds",
           "SPARSE_FROM", "BASIS_BYTES", "BASIS_COPIES", "BASES", "route_for", "rounding_sweeps",
           "rounding_seconds", "chain_task",
           "chain_bits_task", "run_chains"]

BASES = ("auto", "dense", "projected", "sparse")
SPARSE_FROM = 2000  # variables from which "auto" factors A A^T sparsely: the projected basis's set-up is 0.5 s
# CPU against the SVD's 3.3 s at 2212 contacts, 0.3 against 1.7 s at 1744 (one thread; notes/benchmarks.md)
BASIS_BYTES = 2 << 30  # the most the projected route's basis-sized arrays may take at once: beyond, "sparse"
BASIS_COPIES = 8  # d x variables float64 arrays held at the peak: K, K^T, the rounding's pilot (2), its old and new
# directions, and on frictional networks G K (counted: a review of the walk, 2026-12-06)
BASIS_SEED = 20061  # the projected basis's normal vectors: fixed, so a walk is a function of its network
SECONDS_PER_PROJECTED = 5e-8  # a projected move per variable: normals, the solve's share (980 contacts: 45 us)
SECONDS_PER_FLOP = 2.1e-9  # a move's two loops per force (the chord, the step): 2.05 ns at 1086 and 2212 contacts, 1.6 at 320
SECONDS_PER_QR_FLOP = 1e-10  # LAPACK's QR of the projected basis, one thread
SECONDS_PER_MOVE = 2e-8  # a move's two draws and loop overhead (triangle N = 5: 1.0 us a sweep of 10 moves on 40 forces)


def route_for(variables: int, dimension: int) -> str:
    """The route ``basis="auto"`` takes (module docstring): ``"dense"``, ``"projected"`` or ``"sparse"``.

    Examples
    --------
    >>> route_for(980, 91), route_for(9961, 1080), route_for(200000, 20000)
    ('dense', 'projected', 'sparse')
    """
    if variables < SPARSE_FROM:
        return "dense"
    return "projected" if 8 * BASIS_COPIES * dimension * variables <= BASIS_BYTES else "sparse"


def rounding_sweeps(dimension: int) -> int:
    """The sweeps of the burn-in's rounding (:attr:`HitAndRun.rounding_rounds` pilot runs of ``max(50, 2 d)``).

    Examples
    --------
    >>> rounding_sweeps(1), rounding_sweeps(230)
    (0, 920)
    """
    return HitAndRun.rounding_rounds * max(50, 2 * dimension) if dimension > 1 else 0


def sweep_seconds(dimension: int, variables: int, inequalities: int, sparse: bool = False) -> float:
    """Estimated seconds of one sweep (``d`` moves, each over a column of ``K`` and of ``G K``; ``sparse``: the
    basis-free route, each along a fresh direction, a normal vector and its share of a sparse solve, :mod:`.kernel_projection`).

    Examples
    --------
    >>> sweep_seconds(100, 300, 300) > 0, sweep_seconds(100, 300, 300, True) > sweep_seconds(100, 300, 300)
    (True, True)
    """
    per = SECONDS_PER_PROJECTED if sparse else SECONDS_PER_FLOP
    return max(1, dimension) * (variables + inequalities) * per + SECONDS_PER_MOVE * dimension


def setup_seconds(rows: int, variables: int, dimension: int = 0) -> float:
    """Estimated seconds of the walk's set-up before its rounding: the SVD's ``O(rows * variables * min)`` on the
    dense route, a sparse LU and a few null vectors of ``A A^T`` on the others, and the projected basis's
    solve with ``d`` right-hand sides and its QR (``2 variables d^2`` flops) where :func:`route_for` takes it.

    Examples
    --------
    >>> setup_seconds(9000, 9961, 961) < 10, setup_seconds(1600, 1744) > 1.0
    (True, True)
    """
    route = route_for(variables, dimension)
    if route == "dense":  # the SVD: 0.4, 1.7, 3.3 s CPU at 980, 1744, 2212 contacts (rows 900, 1600, 2000)
        return 4e-10 * rows * variables * min(rows, variables) + 2e-5 * (variables + rows)
    lu = 2e-4 * (rows + variables)
    if route == "sparse":
        return lu
    return lu + dimension * variables * SECONDS_PER_PROJECTED + 2 * variables * dimension**2 * SECONDS_PER_QR_FLOP


def rounding_seconds(dimension: int, variables: int, per_sweep: float) -> float:
    """Estimated seconds of the burn-in's rounding: its pilot sweeps and, per round, the pilot's coordinates,
    their covariance's eigenvectors and the new directions (``~6 variables d^2`` flops).

    Examples
    --------
    >>> rounding_seconds(1080, 9961, 0.0154) > 60
    True
    """
    rounds = HitAndRun.rounding_rounds if dimension > 1 else 0
    return rounding_sweeps(dimension) * per_sweep + rounds * 6 * variables * dimension**2 * SECONDS_PER_QR_FLOP


@njit(error_model="numpy")  # a zero a_r divides to inf or nan, discarded by the selects (no exception check)
def hit_and_run_sweeps(z: np.ndarray, s: np.ndarray, KT: np.ndarray, GKT: np.ndarray, same: bool,
                       rng: np.random.Generator, sweeps: int, out: np.ndarray, record: bool,
                       thin: int) -> None:  # pragma: no cover
    """``sweeps`` sweeps of ``d`` coordinate hit-and-run moves; with ``record``, row ``k`` of ``out`` is ``z``
    after sweep ``(k + 1) * thin`` (one call per chunk of recorded states: numba's dispatch costs ~1e-5 s a call).

    ``KT[k]`` and ``GKT[k]`` are the direction ``k`` in forces and in slacks (``same``: the slacks are the forces,
    ``s`` is ``z``, frictionless networks).
    """
    d = KT.shape[0]
    m = z.shape[0]
    r_count = s.shape[0]
    for sweep in range(sweeps):
        for _ in range(d):
            k = rng.integers(0, d)
            lo = -np.inf
            hi = np.inf
            slack = z if same else s
            direction = KT[k] if same else GKT[k]
            for r in range(r_count if not same else m):
                # the chord's ends: lo = max of -s_r/a_r over a_r > 0, hi = min over a_r < 0 (module docstring);
                # written without branches (selects: the sign of a_r is a coin flip the processor cannot
                # predict), the division done for every r and its result kept only where the old branch kept it
                a = direction[r]
                value = slack[r] if slack[r] > 0.0 else 0.0
                bound = -value / a
                up = bound if a > 1e-300 else -np.inf
                down = bound if a < -1e-300 else np.inf
                lo = up if up > lo else lo
                hi = down if down < hi else hi
            if not (hi > lo):  # a chord of length zero (on a facet): stay
                continue
            t = lo + (hi - lo) * rng.random()
            line = KT[k]
            for j in range(m):
                z[j] += t * line[j]
            if not same:
                grow = GKT[k]
                for r in range(r_count):
                    s[r] += t * grow[r]
        if record and (sweep + 1) % thin == 0:
            row = (sweep + 1) // thin - 1
            for j in range(m):
                out[row, j] = z[j]


@dataclass(frozen=True)
class Chain:
    """The recorded forces, one row per sweep, with the labels of :class:`~forcenet.exact.contact_network.polytope.Balance`.

    Attributes
    ----------
    samples : numpy.ndarray
        ``(samples, variables)``.
    labels : tuple of str
    seconds : float
        The sampling's wall time.
    fixed : numpy.ndarray or None
        The variables balance alone fixes (constant).
    lengths : tuple of int
        The independent chains' lengths, in order (empty: one chain).
    """

    samples: np.ndarray
    labels: tuple[str, ...]
    seconds: float
    fixed: np.ndarray | None = None
    lengths: tuple[int, ...] = ()

    def _moments(self, values: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        fixed = np.zeros(values.shape[1], dtype=bool) if self.fixed is None else self.fixed
        mean, err, tau = values.mean(axis=0), np.zeros(values.shape[1]), np.ones(values.shape[1])
        if not (~fixed).any():
            return mean, err, tau
        lengths = self.lengths or (values.shape[0],)
        try:
            stats = [mean_and_stderr(part[:, ~fixed]) for part in np.split(values, np.cumsum(lengths)[:-1])]
        except AutocorrError as exc:  # the fix, in the words of the front door and the command line
            raise AutocorrError(f"{exc}; the sampler needs a longer chain: raise samples (--samples) or thin "
                                "(--thin)", exc.tau) from None
        pooled_mean, pooled_err = pool_means(lengths, [m for m, _, _ in stats], [e for _, e, _ in stats])
        mean[~fixed], err[~fixed] = pooled_mean, pooled_err
        tau[~fixed] = np.mean([t for _, _, t in stats], axis=0)
        return mean, err, tau

    def statistics(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(mean, standard error, tau)`` per variable, from the integrated autocorrelation time (a force that
        balance alone fixes has error 0 and tau 1).

        Examples
        --------
        >>> Chain(np.arange(200.0).reshape(100, 2) % 7, ("f0", "f1"), 0.0).statistics()[0].shape
        (2,)
        """
        return self._moments(self.samples)

    def second_moments(self) -> tuple[np.ndarray, np.ndarray]:
        """``<z^2>`` per variable and its standard error (the autocorrelation time of ``z^2``).

        Examples
        --------
        >>> Chain(np.arange(200.0).reshape(100, 2) % 7, ("f0", "f1"), 0.0).second_moments()[0].shape
        (2,)
        """
        mean, err, _ = self._moments(self.samples**2)
        return mean, err


class HitAndRun:
    """Coordinate hit-and-run on a contact network's ensemble (module docstring: why it is uniform).

    Parameters
    ----------
    network : ContactNetwork
        Checked at construction (:func:`~forcenet.exact.contact_network.polytope.check_polytope`): not balanced,
        infeasible or unbounded networks are refused before any sampling.

    Attributes
    ----------
    dimension : int
        ``dim Ker A``.
    start : numpy.ndarray
        The maximin network (an interior point), where every chain starts.
    """

    rounding_rounds = 2  # pilot runs whose principal axes become the directions (burn-in only)

    def __init__(self, network: ContactNetwork, bal: Balance | None = None, basis: str = "auto") -> None:
        self.network = network
        self.balance = balance(network) if bal is None else bal
        A, b, G = float_system(self.balance)
        self.start, margin = check_polytope(network, self.balance)
        scale = max(1.0, float(np.abs(b).max(initial=0.0)))
        if margin <= 1e-9 * scale:
            raise ArgumentError("degenerate: some contact carries no force (or its friction cone is saturated) in "
                                "every force network of this packing, so the polytope is flat; remove those "
                                "contacts or use the exact route (--exact), which handles it")
        self.G, self.b = G, b
        self.same = not network.frictional
        self.projector: KernelProjector | None = None
        if basis not in BASES:
            raise ArgumentError(f"basis={basis!r} is out of range: basis must be one of {', '.join(BASES)}",
                                argument="basis")
        m = self.balance.variables
        route = route_for(m, m - min(A.shape[0], m)) if basis == "auto" else basis
        if route != "dense" and A.shape[0]:
            try:  # the sparse LU of A A^T (kernel_projection): no SVD, 10^4 contacts
                self.projector = KernelProjector(A, b, 3 if network.frictional else 2)
            except ArgumentError:
                if basis != "auto":
                    raise
        #: the route taken: "dense" (SVD basis), "projected" (basis by projection) or "sparse" (no basis)
        self.route = "dense" if self.projector is None else route
        if self.projector is not None:
            self.dimension = self.projector.dimension
            self.fixed = self.projector.fixed(np.random.default_rng(0))
            self.K = self.KT = self.GKT = np.zeros((0, m))
            if self.route == "sparse":
                return
            self.K = self._projected_basis(self.projector)
        else:
            dense = A.toarray()
            self.K = linalg.null_space(dense) if dense.size else np.eye(m)
            # forces that Ker A does not move are fixed by balance alone (a grain with two contacts): constant
            self.fixed = np.linalg.norm(self.K, axis=1) < 1e-10
            self.K[self.fixed] = 0.0
            self.dimension = int(self.K.shape[1])
        self.KT = np.ascontiguousarray(self.K.T)
        self.GKT = self.KT if self.same else np.ascontiguousarray((G @ self.K).T)

    def _projected_basis(self, projector: KernelProjector) -> np.ndarray:
        """An orthonormal basis of ``Ker A`` (``variables x d``) from ``d`` projected standard normal vectors
        (:meth:`~.kernel_projection.KernelProjector.directions`: each in the kernel, jointly spanning it with
        probability 1) by QR; the forces balance fixes are zero in every column, as on the dense route."""
        if self.dimension == 0:
            return np.zeros((self.balance.variables, 0))
        with projector.one_thread():
            D = projector.directions(np.random.default_rng(BASIS_SEED), self.dimension)
        D[:, self.fixed] = 0.0
        K, R = np.linalg.qr(D.T)
        pivots = np.abs(np.diag(R))
        if pivots.min() <= 1e-9 * pivots.max():  # d projected normals spanning less than Ker A: rounding, not chance
            raise ConvergenceError(f"the projected directions span {int((pivots > 1e-9 * pivots.max()).sum())} of "
                                   f"Ker A's {self.dimension} dimensions: use basis='dense' or basis='sparse'")
        return np.ascontiguousarray(K)

    def _sweeps(self, z: np.ndarray, s: np.ndarray, KT: np.ndarray, GKT: np.ndarray, rng: np.random.Generator,
                count: int, out: np.ndarray, record: bool) -> None:
        """``count`` sweeps of ``d`` moves (row ``k`` of ``out`` is ``z`` after sweep ``k`` when ``record``): along
        the directions ``KT`` (dense), or along fresh random kernel directions, ``BATCH`` per sparse solve."""
        projector = self.projector
        if self.route != "sparse" or projector is None:
            hit_and_run_sweeps(z, s, KT, GKT, self.same, rng, count, out, record, 1)
            return
        for sweep in range(count):
            if self.dimension == 0 and record:  # nothing moves: the one force network
                out[sweep] = z
            left = self.dimension
            while left > 0:
                batch = min(BATCH, left)
                left -= batch
                D = projector.directions(rng, batch)
                D[:, self.fixed] = 0.0
                GD = D if self.same else np.ascontiguousarray(np.asarray(self.G @ D.T).T)
                last = record and left == 0
                hit_and_run_sweeps(z, s, D, GD, self.same, rng, 1, out[sweep:sweep + 1] if last else out[:0], last,
                                   1)

    def sweep_seconds(self) -> float:
        """Estimated seconds per sweep (:func:`sweep_seconds`)."""
        return sweep_seconds(self.dimension, self.balance.variables, 0 if self.same else self.balance.inequalities,
                             self.route == "sparse")

    def _project(self, z: np.ndarray) -> np.ndarray:
        """Back onto ``A z = b`` (the start satisfies it; ``K`` spans the kernel)."""
        if self.projector is not None:
            return self.projector.project(z)
        delta = z - self.start
        return self.start + self.K @ (self.K.T @ delta)

    def _rounded(self, z: np.ndarray, s: np.ndarray, rng: np.random.Generator) -> tuple[Any, ...]:
        """Rounding (during burn-in only): the directions become the principal axes of pilot runs, so a long thin
        polytope is crossed along its length; fixed afterwards (the chain recorded is a Gibbs sampler with one
        fixed orthonormal direction set: uniform). Returns ``(z, s, KT, GKT)``; deterministic given ``rng``."""
        KT, GKT = self.KT, self.GKT
        per = self.sweep_seconds()
        for _ in range(self.rounding_rounds if self.dimension > 1 and self.route != "sparse" else 0):
            pilot = np.empty((max(50, 2 * self.dimension), self.balance.variables))
            for start, stop in chunks(pilot.shape[0], first_chunk(per)):
                hit_and_run_sweeps(z, s, KT, GKT, self.same, rng, stop - start, pilot[start:stop], True, 1)
            z, s = self._projected(z)
            coordinates = (pilot - self.start) @ self.K
            _, axes = np.linalg.eigh(np.cov(coordinates.T))
            directions = self.K @ axes
            KT = np.ascontiguousarray(directions.T)
            GKT = KT if self.same else np.ascontiguousarray(np.asarray(self.G @ directions).T)
        return z, s, KT, GKT

    def _projected(self, z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``z`` back on ``A z = b`` and its slacks ``G z`` (at points fixed by the request: same seed, same bits)."""
        z = self._project(z)
        return z, (np.asarray(self.G @ z).ravel() if not self.same else np.zeros(0))

    def run(self, samples: int, seed: int | None = None, burn_in: int | None = None,
            progress: Callable[..., Any] | None = None, thin: int = 1, checkpoint: str | None = None,
            block: int | None = None) -> Chain:
        """``samples`` states recorded, ``thin`` sweeps apart, after ``burn_in`` sweeps (default: a tenth of the
        sweeps, at least 100).

        The states are recorded in blocks (:func:`~.chain_records.block_rows`, a function of the request alone);
        after each the forces are projected back onto ``A z = b`` and, with ``checkpoint``, the block is saved.
        A rerun with the same arguments and directory resumes after the last finished block and gives the same
        states, bit for bit, as an uninterrupted run.

        Parameters
        ----------
        samples : int
            Recorded sweeps.
        seed : int, optional
            The seed of ``numpy.random.default_rng``: same seed, same chain.
        burn_in : int, optional
            Sweeps discarded first.
        progress : callable, optional
            Called with the number of recorded states done, per compiled call.
        thin : int
            Sweeps between two recorded states (memory: ``samples * contacts`` floats).
        checkpoint : str, optional
            A directory recording every finished block (:mod:`~.chain_records`).
        block : int, optional
            States per block (default :func:`~.chain_records.block_rows`); part of the request.

        Returns
        -------
        Chain

        Examples
        --------
        >>> from forcenet.exact.contact_network.geometries import triangle
        >>> chain = HitAndRun(triangle(3).network).run(50, seed=0)
        >>> chain.samples.shape
        (50, 15)
        """
        # the sparse route's solves with BLAS in one thread, entered once (threadpoolctl's context costs ms)
        thin = check_int(thin, "thin", 1)  # the kernel records every thin-th sweep: 0 or less records nothing
        with self.projector.one_thread() if self.projector is not None else nullcontext():
            return self._run(samples, seed, burn_in, progress, thin, checkpoint, block)

    def _run(self, samples: int, seed: int | None, burn_in: int | None, progress: Callable[..., Any] | None,
             thin: int, checkpoint: str | None, block: int | None) -> Chain:
        rng = np.random.default_rng(seed)
        m = self.balance.variables
        burn = max(100, samples * thin // 10) if burn_in is None else burn_in
        rows = block_rows(samples, thin, self.dimension, m, block)
        edges = list(range(0, samples, rows)) + [samples]
        store = None if checkpoint is None else chain_store(
            checkpoint, self.network, ("chain", seed, samples, burn_in, thin, rows, _STORE_ROUTE[self.route]),
            block_shape(rows, m))
        t0 = time.perf_counter()
        per = self.sweep_seconds()
        z, s = self._projected(self.start.copy())
        z, s, KT, GKT = self._rounded(z, s, rng)
        out = np.empty((samples, m))
        done = 0
        while store is not None and done < len(edges) - 1:  # the longest run of finished blocks
            record = store.load(done)
            if record is None:
                break
            out[edges[done]:edges[done + 1]], z, state = decode_block(record, edges[done + 1] - edges[done], m, rows)
            rng.bit_generator.state = state
            done += 1
        scratch = np.empty((1, m))
        if done:
            s = np.asarray(self.G @ z).ravel() if not self.same else np.zeros(0)  # z was saved projected
            if progress is not None:
                progress(edges[done])
        else:
            for first in range(0, burn, rows * thin):  # projected every block's worth of sweeps, as below
                for start, stop in chunks(min(burn, first + rows * thin) - first, first_chunk(per)):
                    self._sweeps(z, s, KT, GKT, rng, stop - start, scratch, False)
                z, s = self._projected(z)
        for b in range(done, len(edges) - 1):
            for start, stop in chunks(edges[b + 1] - edges[b], first_chunk(per * thin)):
                first, last = edges[b] + start, edges[b] + stop
                if self.route != "sparse":  # one compiled call per chunk, recording every thin-th sweep
                    hit_and_run_sweeps(z, s, KT, GKT, self.same, rng, (last - first) * thin, out[first:last], True,
                                       thin)
                    if progress is not None:
                        progress(stop - start)
                    continue
                for k in range(first, last):  # thin - 1 sweeps unrecorded, then one recorded
                    if thin > 1:
                        self._sweeps(z, s, KT, GKT, rng, thin - 1, scratch, False)
                    self._sweeps(z, s, KT, GKT, rng, 1, out[k:k + 1], True)
                if progress is not None:
                    progress(stop - start)
            z, s = self._projected(z)
            if store is not None:
                store.save(b, encode_block(out[edges[b]:edges[b + 1]], z, rng, rows))
        return Chain(out, self.balance.labels, time.perf_counter() - t0, self.fixed)


_STORE_ROUTE: dict[str, Any] = {"dense": True, "sparse": False, "projected": "projected"}  # checkpoint keys


def chain_task(network: ContactNetwork, samples: int, seed: int, burn_in: int | None, thin: int) -> Chain:
    """One independent chain (a task of :func:`run_chains`, run in a worker process or a Dask worker).

    Examples
    --------
    >>> from forcenet.exact.contact_network.geometries import triangle
    >>> chain_task(triangle(3).network, 20, 1, 10, 1).samples.shape
    (20, 15)
    """
    return HitAndRun(network).run(samples, seed, burn_in, thin=thin)


def chain_bits_task(network: ContactNetwork, samples: int, seed: int, burn_in: int | None, thin: int,
                    rows: int) -> np.ndarray:
    """One chain's states as a checkpoint record: their float64 bit patterns as int64, padded to ``rows`` states.

    Examples
    --------
    >>> from forcenet.exact.contact_network.geometries import triangle
    >>> chain_bits_task(triangle(3).network, 20, 1, 10, 1, 21).shape
    (21, 15)
    """
    states = chain_task(network, samples, seed, burn_in, thin).samples
    padded = np.zeros((rows, states.shape[1]))
    padded[:samples] = states
    return padded.view(np.int64)


def run_chains(network: ContactNetwork, samples: int, seed: int | None, burn_in: int | None, thin: int, chains: int,
               executor: Any = None, progress: Callable[..., Any] | None = None, checkpoint: str | None = None,
               fixed: np.ndarray | None = None) -> Chain:
    """``chains`` independent chains of ``samples // chains`` states each (seeds ``SeedSequence(seed).spawn``),
    run by :func:`forcenet.core.execution.run_tasks` (a local process pool, or ``executor``: a Dask client's),
    joined into one :class:`Chain` whose statistics pool the chains (:meth:`Chain.statistics`).

    With ``checkpoint`` (a directory) every finished chain is recorded as it arrives (one record per chain,
    :mod:`~.chain_records`) and a rerun of the same request runs only the chains missing; ``fixed`` (the forces
    balance alone fixes, :attr:`HitAndRun.fixed`) then saves rebuilding a walk here.

    Examples
    --------
    >>> from forcenet.exact.contact_network.geometries import triangle
    >>> chain = run_chains(triangle(3).network, 400, 1, 50, 1, 2)
    >>> chain.samples.shape, chain.lengths
    ((400, 15), (200, 200))
    """
    seeds = [int(s.generate_state(1)[0]) for s in np.random.SeedSequence(seed).spawn(chains)]
    shares = [samples // chains + (1 if k < samples % chains else 0) for k in range(chains)]
    t0 = time.perf_counter()
    if checkpoint is None:
        parts = run_tasks(chain_task, [(network, share, s, burn_in, thin) for share, s in zip(shares, seeds)],
                          executor=executor, workers=chains, progress=progress, weights=shares)
        return Chain(np.concatenate([part.samples for part in parts]), parts[0].labels, time.perf_counter() - t0,
                     parts[0].fixed, tuple(shares))
    bal = balance(network)
    rows = max(shares)
    store = chain_store(checkpoint, network, ("chains", seed, samples, burn_in, thin, chains), (rows, bal.variables))
    records = run_tasks(chain_bits_task, [(network, share, s, burn_in, thin, rows) for share, s in zip(shares, seeds)],
                        executor=executor, workers=chains, progress=progress, weights=shares, store=store,
                        keys=list(range(chains)))
    states = np.concatenate([np.ascontiguousarray(r, dtype=np.int64).view(np.float64)[:share]
                             for r, share in zip(records, shares)])
    if fixed is None:
        fixed = HitAndRun(network, bal).fixed
    return Chain(states, bal.labels, time.perf_counter() - t0, fixed, tuple(shares))
