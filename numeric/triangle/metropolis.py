"""The Metropolis sampler of Sec. 3.2.4 on the fully mobilized triangle.

State: the q-coordinates ``q_{i,j}``, ``1 <= i <= N-1``, ``1 <= j <= i``
(Eq. 3.8); the forces follow from Eq. (4.5), ``W_{1,1} = 1`` (the overload,
``F = 1``).  The uniform measure on force networks is ``prod W_{i,j} dq``
over the grains carrying a q (Eq. 3.10), so the thesis's move is: pick a grain
at random, draw a new ``q`` uniformly in [0, 1], recompute ``W`` below it,
reject if a lateral force ``F4`` turns negative, else accept with probability
``min(1, prod W_new / prod W_old)``.

Only the triangle under the overload is modelled (``p_v = 0``, ``g = 0``).
With ``ph=None`` the side pressure is taken large enough for every q to be
allowed (the fully mobilized case, ``(2/sqrt 3) p_h > F``); a finite ``ph``
(in units of ``F``) adds the constraints ``F4 >= 0`` with
``F4^{(i,j)} = p_h + (2/sqrt 3) sum_{k<=j} (q_{i,k} W_{i,k} - q_{i-1,k} W_{i-1,k})``
(``forcenet.exact.triangle.configuration.contact_forces``; row 0 stands for the overload,
``q_{0,1} W_{0,1} = 1/2``).

Examples
--------
>>> sampler = TriangleMetropolis(5, seed=1)
>>> chain = sampler.run(sweeps=2000, burn_in=200)
>>> chain.shape
(2000, 5, 5)
>>> 0.2 < sampler.acceptance_rate < 1
True
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from forcenet.core.errors import ArgumentError
from forcenet.core.plan import Plan, with_compilation
from forcenet.core.validation import check_fits_memory, check_int, check_layers, check_seed
from forcenet.exact.triangle.staircase import dimension

from ..jit import chunks, first_chunk, kernel_choice

if TYPE_CHECKING:
    from forcenet.core.plan import Plan

__all__ = ["TriangleMetropolis", "forces_from_q", "lateral_forces", "q_model_samples"]

_C = 2 / math.sqrt(3)


def forces_from_q(q: np.ndarray) -> np.ndarray:
    """``W`` (shape ``(N, N)``, row ``i-1``, zero above the diagonal) from ``q`` (Eq. 4.5).

    ``q`` has shape ``(N-1, N-1)``; row ``i-1`` holds ``q_{i,1..i}``.

    Examples
    --------
    >>> forces_from_q(np.array([[0.25]])).tolist()
    [[1.0, 0.0], [0.25, 0.75]]
    """
    N = q.shape[0] + 1
    W = np.zeros((N, N))
    W[0, 0] = 1.0
    for i in range(1, N):
        w, qq = W[i - 1, :i], q[i - 1, :i]
        W[i, :i] += qq * w
        W[i, 1 : i + 1] += (1 - qq) * w
    return W


def lateral_forces(q: np.ndarray, W: np.ndarray, ph: float) -> np.ndarray:
    """``F4^{(i,j)}`` for ``i = 1..N-1``, ``j = 1..i`` (units of the overload).

    Examples
    --------
    >>> q = np.array([[0.5]]); W = forces_from_q(q)
    >>> lateral_forces(q, W, 1.0).round(12).tolist()
    [[1.0]]
    """
    N = W.shape[0]
    flux = np.zeros((N, N))  # flux[i] = cumsum_j q_{i,j} W_{i,j}; flux[0] is the overload's 1/2
    flux[0, :] = 0.5
    for i in range(1, N):
        flux[i, :i] = np.cumsum(q[i - 1, :i] * W[i - 1, :i])
        flux[i, i:] = flux[i, i - 1]
    F4 = ph + _C * (flux[1:] - np.concatenate([flux[:1], flux[1:-1]]))
    return np.tril(F4[:, : N - 1])



def _kernel(move: str) -> Callable[..., Any]:
    """The compiled sweep kernel of ``move``, imported when first needed (its numba decoration imports numba)."""
    from . import metropolis_kernel, slice_kernel

    return slice_kernel.triangle_slice_sweeps if move == "slice" else metropolis_kernel.triangle_sweeps


def _state(q: np.ndarray, W: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The compiled kernels' running state (:func:`forcenet.numeric.triangle.cone.triangle_state`), loaded with them."""
    from .cone import triangle_state

    return triangle_state(q, W)  # type: ignore[no-any-return]

class TriangleMetropolis:
    """Metropolis sampler in q for the fully mobilized triangle (Sec. 3.2.4).

    Parameters
    ----------
    N : int
        Layers (``N >= 2``).
    seed : int or numpy.random.Generator, optional
    ph : float or None
        Side pressure in units of the overload; ``None`` for the fully
        mobilized limit where every q in [0, 1] is allowed.
    q0 : array, optional
        Initial state, shape ``(N-1, N-1)``; default all ``1/2`` in the fully
        mobilized limit, and for finite ``ph`` the state that sends the load
        down the two lattice directions (every ``F4 = p_h``, feasible for any
        ``p_h > 0``).
    kernel : {None, "compiled", "python"}
        ``"python"``: the reference kernel below (numpy, whole rows per move);
        ``"compiled"``: :func:`forcenet.numeric.triangle.metropolis_kernel.triangle_sweeps`
        (numba, the light cone only), which draws the same random numbers and
        gives the same chain for the same seed, 30-100 times faster; ``None``
        (default): compiled when numba is available.
    move : {"metropolis", "slice"}
        ``"metropolis"``: the thesis's move above.  ``"slice"`` (compiled
        kernel only): the grain's new q is drawn from its exact conditional
        law given the others (the weight is a product of forces affine in
        that q, so log-concave), restricted with a finite ``ph`` to the
        interval where every lateral force stays >= 0, by slice sampling
        with shrinkage (Neal 2003); no move is rejected.

    Raises
    ------
    forcenet.core.errors.ArgumentError
        On ``N < 2``, a ``ph`` that is not a positive finite number, an unknown ``kernel`` or ``move``, the slice
        move without the compiled kernel, a ``q0`` of the wrong shape or (finite ``ph``) with a negative lateral force.

    Examples
    --------
    >>> sampler = TriangleMetropolis(4, seed=2, ph=0.5)
    >>> chain = sampler.run(sweeps=100, burn_in=10)
    >>> chain.shape, bool((lateral_forces(sampler.q, sampler.W, 0.5) >= -1e-12).all())
    ((100, 4, 4), True)
    """

    def __init__(self, N: int, seed: int | np.random.Generator | None = None, ph: float | None = None, q0: ArrayLike | None = None,
                 kernel: str | None = None, move: str = "metropolis") -> None:

        self.kernel = kernel_choice(kernel)
        if move not in ("metropolis", "slice"):
            raise ArgumentError(f"move={move!r}: expected 'metropolis' or 'slice'")
        if move == "slice" and self.kernel != "compiled":
            raise ArgumentError("move='slice' needs the compiled kernel (numba)")
        self.move = move
        self.evaluations = 0
        self.N = check_layers(N)
        check_fits_memory(64 * self.N * self.N, f"the chain's state at N={self.N}", "a smaller N")
        self.rng = np.random.default_rng(check_seed(seed))
        if ph is not None and not (ph > 0 and math.isfinite(ph)):
            raise ArgumentError(f"ph={ph}: the side pressure must be a positive finite number (or None)")
        self.ph = ph
        n = self.N - 1
        if q0 is None:
            self.q = np.tril(np.full((n, n), 0.5))
            if ph is not None:  # the load on the two lattice directions: every F4 = p_h, feasible for any p_h > 0
                self.q[np.arange(1, n), 0] = 1.0
                self.q[np.arange(1, n), np.arange(1, n)] = 0.0
        else:
            self.q = np.array(q0, dtype=float)
        if self.q.shape != (n, n):
            raise ArgumentError(f"q0 has shape {self.q.shape}, expected {(n, n)}")
        self.W = forces_from_q(self.q)
        if ph is not None and (lateral_forces(self.q, self.W, ph) < 0).any():
            raise ArgumentError(f"ph={ph}: the initial state has a negative lateral force; pass a feasible q0")
        self.grains = [(i, j) for i in range(n) for j in range(i + 1)]
        self._lower = np.tril(np.ones((self.N, self.N), dtype=bool))
        self.accepted = 0
        self.attempted = 0
        self.rejected_by_constraint = 0

    @property
    def acceptance_rate(self) -> float:
        """Accepted over attempted single-grain moves so far (NaN before the first move).

        Examples
        --------
        >>> chain = TriangleMetropolis(4, seed=1, kernel="python")
        >>> chain.sweep(10)
        >>> 0 < chain.acceptance_rate < 1
        True
        """
        return self.accepted / self.attempted if self.attempted else float("nan")

    def _propose(self, i: int, j: int, new: float) -> bool:
        """Try ``q[i, j] = new`` (0-based row ``i`` is layer ``i + 1``)."""
        N = self.N
        old = self.q[i, j]
        self.q[i, j] = new
        W_new = self.W.copy()
        for k in range(i + 1, N):  # the layers below the grain, Eq. (4.5)
            w, qq = W_new[k - 1, :k], self.q[k - 1, :k]
            W_new[k, : k + 1] = 0.0
            W_new[k, :k] += qq * w
            W_new[k, 1 : k + 1] += (1 - qq) * w
        if self.ph is not None and (lateral_forces(self.q, W_new, self.ph) < -1e-12).any():
            self.rejected_by_constraint += 1
            self.q[i, j] = old
            return False
        # weight prod W over the layers that carry a q (Eq. 3.10): 0-based rows i+1..N-2
        changed = self._lower[i + 1 : N - 1]
        with np.errstate(divide="ignore"):
            log_new = float(np.log(W_new[i + 1 : N - 1][changed]).sum())
            log_old = float(np.log(self.W[i + 1 : N - 1][changed]).sum())
        if log_old == -math.inf:  # leaving a zero-density start (e.g. the lattice-direction state)
            accept = log_new > -math.inf or self.rng.random() < 0.5
        elif log_new == -math.inf:
            accept = False
        else:
            log_ratio = log_new - log_old
            accept = log_ratio >= 0 or self.rng.random() < math.exp(log_ratio)
        if accept:
            self.W = W_new
            return True
        self.q[i, j] = old
        return False

    def _compiled(self, units: int, out: np.ndarray, thin: int = 1,
                  progress: Callable[[int], object] | None = None) -> None:
        """``units`` records of ``thin`` sweeps into ``out`` (or, ``out`` empty, ``units`` sweeps), compiled.

        The sweeps run in calls of ~0.15 s (:func:`forcenet.numeric.jit.chunks`),
        cut between sweeps, where ``q``, ``W``, the running sums and the
        counters are complete: Ctrl-C is seen between two calls, and the chain
        is the one a single call gives.  ``progress(k)`` after each call that
        recorded ``k`` records.
        """

        flux, zeros = _state(self.q, self.W)
        gi = np.array([g[0] for g in self.grains], dtype=np.int64)
        gj = np.array([g[1] for g in self.grains], dtype=np.int64)
        counters = np.array([self.attempted, self.accepted, self.rejected_by_constraint, self.evaluations, 0],
                            dtype=np.int64)
        ph = 0.0 if self.ph is None else float(self.ph)
        kernel = _kernel(self.move)
        record = out.shape[0] > 0
        per_unit = _compiled_seconds_per_move(self.N, self.ph is not None) * len(self.grains) * (thin if record else 1)
        try:
            for start, stop in chunks(units, first_chunk(per_unit)):
                part = out[start:stop] if record else out
                kernel(self.q, self.W, flux, zeros, gi, gj, self.rng, (stop - start) * (thin if record else 1), ph,
                       self.ph is not None, part, counters, thin)
                if progress is not None and record:
                    progress(stop - start)
        finally:  # also on Ctrl-C: the counters of the sweeps done
            self.attempted, self.accepted, self.rejected_by_constraint = (int(x) for x in counters[:3])
            self.evaluations = int(counters[3])
        if counters[4]:  # pragma: no cover - never observed
            raise ArithmeticError("slice move: an interval shrank 200 times without a point under the density")

    def sweep(self, count: int = 1) -> None:
        """``count`` sweeps; a sweep is ``N(N-1)/2`` single-grain updates.

        Parameters
        ----------
        count : int
            Number of sweeps, ``>= 0``.

        Returns
        -------
        None
            The chain's state (``q``, ``W``) moves on.

        Examples
        --------
        >>> chain = TriangleMetropolis(4, seed=1)
        >>> chain.sweep(5)
        >>> bool(np.allclose(chain.W.sum(axis=1), 1))
        True
        """
        if self.kernel == "compiled":
            if count > 0:
                self._compiled(count, np.empty((0, self.N, self.N)))
            return
        grains = self.grains
        for _ in range(count):
            picks = self.rng.integers(len(grains), size=len(grains))
            values = self.rng.random(len(grains))
            for k, value in zip(picks, values):
                i, j = grains[k]
                self.attempted += 1
                if self._propose(i, j, value):
                    self.accepted += 1

    def run(self, sweeps: int, burn_in: int = 0, progress: Callable[[int], object] | None = None, thin: int = 1) -> np.ndarray:
        """Burn in, then record ``W`` after every ``thin``-th of ``sweeps * thin`` sweeps.

        Parameters
        ----------
        sweeps : int
            Number of records, ``>= 1``.
        burn_in : int
            Sweeps discarded first, ``>= 0``.
        progress : callable, optional
            Called as ``progress(1)`` once per record.
        thin : int
            Sweeps between two records, ``>= 1``.

        Returns
        -------
        numpy.ndarray
            Shape ``(sweeps, N, N)``: ``W`` after each recorded sweep (a Markov chain: test it with ``chain=True``).

        Examples
        --------
        >>> chain = TriangleMetropolis(4, seed=1).run(sweeps=50, burn_in=10)
        >>> chain.shape
        (50, 4, 4)
        """
        sweeps = check_int(sweeps, "sweeps", 1)
        burn_in = check_int(burn_in, "burn_in", 0)
        thin = check_int(thin, "thin", 1)
        check_fits_memory(8 * sweeps * self.N * self.N, f"run(sweeps={sweeps}) at N={self.N}",
                          "record fewer sweeps (thin= keeps every thin-th)")
        self.sweep(burn_in)
        out = np.empty((sweeps, self.N, self.N))
        if self.kernel == "compiled":
            out[:] = 0.0
            self._compiled(sweeps, out, thin, progress)
            return out
        for t in range(sweeps):
            self.sweep(thin)
            out[t] = self.W
            if progress is not None:
                progress(1)
        return out


def q_model_samples(N: int, size: int, rng: np.random.Generator) -> np.ndarray:
    """The q-model contrast: independent uniform q on every grain, no weight.

    Parameters
    ----------
    N : int
        Layers, ``>= 2``.
    size : int
        Samples.
    rng : numpy.random.Generator
        The stream.

    Returns
    -------
    numpy.ndarray
        ``W`` samples (Eq. 4.5 from the uniform q), shape ``(size, N, N)``.

    Raises
    ------
    forcenet.core.errors.ArgumentError
        On ``N < 2``.

    Examples
    --------
    >>> W = q_model_samples(3, 2, np.random.default_rng(0))
    >>> W.shape, W.sum(axis=2).round(12).tolist()
    ((2, 3, 3), [[1.0, 1.0, 1.0], [1.0, 1.0, 1.0]])
    """
    N = check_layers(N)
    q = np.tril(rng.random((size, N - 1, N - 1)))
    W = np.zeros((size, N, N))
    W[:, 0, 0] = 1.0
    for i in range(1, N):
        w, qq = W[:, i - 1, :i], q[:, i - 1, :i]
        W[:, i, :i] += qq * w
        W[:, i, 1 : i + 1] += (1 - qq) * w
    return W


_SECONDS_PER_MOVE = 4e-5  # reference kernel, measured: 35-50 us per single-q move (N = 24)


# compiling the kernel on a first run (empty numba cache), CPU seconds: benchmarks/compile_times.py
COMPILE_SECONDS = {"metropolis": 6.5, "slice": 7.6}


def _compiled_seconds_per_move(N: int, ph: bool) -> float:
    """The compiled kernel's cost of one move: a fixed part and ~2.5 ns per force of the light cone (~N^2/9 on
    average); a finite ``ph`` adds the running sums right of the grain (benchmarks/bench_samplers.py:
    0.21, 0.52, 1.43 us at N = 11, 24, 50; 0.62 us at N = 24 with ``p_h = 0.3``)."""
    return 2e-7 + 4e-9 * N * N / 9 * (1.5 if ph else 1)


def metropolis_plan(N: int, sweeps: int, burn_in: int = 0, memory_bytes: int | None = None, ph: bool = False,
                    kernel: str | None = None, move: str = "metropolis") -> Plan:
    """The cost of :meth:`TriangleMetropolis.run` (time per move measured; the chain is stored).

    With the compiled kernel and numba's cache lacking it (a first run), the
    plan includes compiling it (:data:`COMPILE_SECONDS`).

    Examples
    --------
    >>> metropolis_plan(11, 20000, 2000, kernel="python").seconds < 60
    True
    >>> plan = metropolis_plan(24, 20000, 2000)
    >>> plan.seconds - plan.compile_seconds < 5
    True
    """

    N = check_layers(N)
    sweeps, burn_in = check_int(sweeps, "sweeps", 1), check_int(burn_in, "burn_in", 0)
    if move not in COMPILE_SECONDS:
        raise ArgumentError(f"move={move!r}: expected 'metropolis' or 'slice'")
    moves = dimension(N) * (sweeps + burn_in)  # N(N-1)/2 grains per sweep
    compiled = kernel_choice(kernel) == "compiled"
    if compiled:
        per_move, start = _compiled_seconds_per_move(N, ph), 1.0  # + loading the cached kernel
    else:
        per_move, start = _SECONDS_PER_MOVE, 0.2
    plan = Plan(f"Metropolis N={N}, {sweeps} sweeps", per_move * moves + start,
                sweeps * N * N * 8 + 100 * 2**20, sweeps, "sweep")
    if compiled:
  # a first run (numba's cache lacks the kernel) compiles it
        plan = with_compilation(plan, f"triangle {move}", COMPILE_SECONDS[move], [_kernel(move)])
    return plan.within_memory(memory_bytes)
