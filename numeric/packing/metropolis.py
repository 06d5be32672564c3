"""The Metropolis sampler of Sec. 3.2.4 on the N x P packing, and the response G(i, j) (Sec. 3.3).

Examples
--------
>>> from forcenet.numeric.packing.scene import Scene
>>> scene = Scene(N=4, P=5, F=10.0, mg=1.0, j0=3)
>>> sampler = PackingMetropolis(scene, seed=1)
>>> chain = sampler.run(sweeps=500, burn_in=100)
>>> chain.shape
(500, 4, 5)
>>> bool(abs(chain[:, -1].sum(axis=1) - (10 + 4 * 5 * 1.0)).max() < 1e-9)  # the floor carries all
True
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import replace
from types import ModuleType
from typing import Literal, overload

import numpy as np
from numpy.typing import ArrayLike

from forcenet.core.errors import ArgumentError, ArgumentTypeError
from forcenet.core.plan import Plan, with_compilation
from forcenet.core.validation import check_int

from ..autocorr import mean_and_stderr
from ..jit import chunks, first_chunk, kernel_choice
from .networks import maximin_network
from .scene import Scene, forces_from_lateral, forces_from_q, lateral_forces

__all__ = ["PackingMetropolis", "response", "packing_plan"]



def _kernels() -> ModuleType:
    """The compiled kernels' module, imported when first needed (its numba decorations import numba)."""
    from . import kernels

    return kernels

class PackingMetropolis:
    """Metropolis sampler of Sec. 3.2.4 on the N x P packing.

    A move picks a free grain (``i < N``, ``j < P``), draws its q uniformly in
    [0, 1], recomputes ``W`` in its light cone and (finite ``ph``) every lateral
    force; a negative force rejects the move, otherwise it is accepted with
    probability ``min(1, prod W_new / prod W_old)`` over the free grains
    (Eq. 3.10).

    Parameters
    ----------
    scene : Scene
    seed : int or numpy.random.Generator, optional
    step : float or None
        ``None``: the thesis's move, a new q uniform in [0, 1].  A width in
        (0, 1]: ``q + step * U(-1, 1)`` reflected into [0, 1] (symmetric, so
        the same acceptance rule), for scenes where the F4 >= 0 constraints
        confine q to narrow ranges (Fig. 3.6).
    q0 : array, optional
        Initial state, shape ``(N-1, P)``.  Default: ``q = 1/2`` when every
        q is allowed (``ph=None``); otherwise the network that maximizes the
        smallest force (a linear program, :func:`maximin_network`), with a
        clear error if no repulsive network exists.
    kernel : {None, "compiled", "python"}
        ``"python"``: the reference kernel (:meth:`_propose`, numpy, whole
        arrays per move); ``"compiled"``:
        :func:`forcenet.numeric.packing.kernels.packing_sweeps` (numba), which
        draws the same random numbers and gives the same chain for a seed;
        ``None`` (default): compiled when numba is available.
    move : {"metropolis", "slice"}
        ``"metropolis"``: the thesis's single-q move above.  ``"slice"``
        (compiled kernel only): the grain's new q is drawn from its exact
        conditional law given all the others, restricted to the interval of
        q where every force stays non-negative (all forces are affine in one
        q, so the allowed set is an interval, and the weight, a product of
        affine functions, is log-concave on it), by slice sampling with
        shrinkage (Neal 2003); no move is rejected.

    Examples
    --------
    >>> s = Scene(N=5, P=9, F=10.0, pv=1.0, ph=1.0)
    >>> m = PackingMetropolis(s, seed=3)
    >>> chain = m.run(sweeps=200, burn_in=50)
    >>> 0.05 < m.acceptance_rate < 1
    True

    Raises
    ------
    forcenet.core.errors.ArgumentError
        On an unknown ``kernel`` or ``move``, the slice move without the compiled kernel or with a ``step``, a
        ``step`` outside (0, 1], a ``q0`` of the wrong shape, outside [0, 1] or infeasible, or a scene with no
        repulsive network.
    forcenet.core.errors.ArgumentTypeError
        If ``scene`` is not a :class:`Scene`.
    """

    def __init__(self, scene: Scene, seed: int | np.random.Generator | None = None, q0: ArrayLike | None = None, step: float | None = None,
                 kernel: str | None = None, move: str = "metropolis") -> None:

        self.kernel = kernel_choice(kernel)
        if move not in ("metropolis", "slice"):
            raise ArgumentError(f"move={move!r}: expected 'metropolis' or 'slice'")
        if move == "slice" and (self.kernel != "compiled" or step is not None):
            raise ArgumentError("move='slice' needs the compiled kernel (numba) and no step")
        self.move = move
        self.evaluations = 0
        if not isinstance(scene, Scene):
            raise ArgumentTypeError(f"scene={scene!r}: expected a forcenet.numeric.packing.Scene")
        if step is not None and not (0 < step <= 1):
            raise ArgumentError(f"step={step} is out of range: the proposal width must be in (0, 1] (or None)")
        self.step = step
        self.scene = scene
        self.rng = np.random.default_rng(seed)
        N, P = scene.N, scene.P
        if q0 is None:
            self.q = self._feasible_start()
        else:
            self.q = np.array(q0, dtype=float)
            if self.q.shape != (N - 1, P):
                raise ArgumentError(f"q0 has shape {self.q.shape}, expected {(N - 1, P)}")
            if ((self.q < 0) | (self.q > 1)).any():
                raise ArgumentError("q0: every q must lie in [0, 1]")
            self.q[:, -1] = 1.0
        self.W = forces_from_q(self.q, scene)
        if not self._feasible(self.q, self.W):
            raise ArgumentError("q0: the initial state has a negative force or a zero weight; pass a feasible q0")
        self.grains = [(i, j) for i in range(N - 1) for j in range(P - 1)]
        self.accepted = 0
        self.attempted = 0
        self.rejected_by_constraint = 0

    def _feasible_start(self) -> np.ndarray:
        """``q = 1/2`` (fully mobilized), else the force network of largest minimal force.

        With a finite ``ph`` all forces are affine in the ``(N-1)(P-1)`` free
        lateral forces (Sec. 3.2.2); a linear program maximizes the smallest
        force, which gives a strictly interior start, or proves that no
        repulsive network exists.
        """
        N, P = self.scene.N, self.scene.P
        q = np.full((N - 1, P), 0.5)
        q[:, -1] = 1.0
        if self.scene.ph is None:
            return q
        x, slack = maximin_network(self.scene)
        if slack <= 0:
            raise ArgumentError(
                f"no force network with all forces > 0 exists for {self.scene}: "
                f"the largest smallest force is {slack:.3g}; raise ph or lower F"
            )
        f = forces_from_lateral(x, self.scene)
        F5, F6 = f["F5"][:-1, :-1], f["F6"][:-1, :-1]
        q[:, :-1] = F5 / (F5 + F6)
        return q

    def _feasible(self, q: np.ndarray, W: np.ndarray) -> bool:
        if (W[:-1, :-1] <= 0).any():
            return False
        if self.scene.ph is None:
            return True
        return bool((lateral_forces(q, W, self.scene) >= -1e-9 * max(1.0, self.scene.ph)).all())

    @property
    def acceptance_rate(self) -> float:
        """Accepted over attempted moves so far (NaN before the first move).

        Examples
        --------
        >>> m = PackingMetropolis(Scene(N=3, P=4, pv=1.0), seed=0)
        >>> m.sweep(20)
        >>> 0 < m.acceptance_rate <= 1
        True
        """
        return self.accepted / self.attempted if self.attempted else float("nan")

    def _propose(self, i: int, j: int, new: float) -> bool:
        scene, N, P, mg = self.scene, self.scene.N, self.scene.P, self.scene.mg
        old = self.q[i, j]
        self.q[i, j] = new
        W_new = self.W.copy()
        lo, hi = j, j + 1  # the light cone of grain (i, j), Eq. (3.9)
        for k in range(i + 1, N):
            hi = min(P, hi + 1)
            w, qq = W_new[k - 1], self.q[k - 1]
            row = qq[lo:hi] * w[lo:hi] + mg
            left = max(lo, 1)
            row[left - lo :] += (1 - qq[left - 1 : hi - 1]) * w[left - 1 : hi - 1]
            W_new[k, lo:hi] = row
        free_new = W_new[i + 1 : N - 1, lo : P - 1]
        if (free_new <= 0).any():
            self.q[i, j] = old
            return False
        if scene.ph is not None and (lateral_forces(self.q, W_new, scene) < -1e-9 * max(1.0, scene.ph)).any():
            self.rejected_by_constraint += 1
            self.q[i, j] = old
            return False
        log_ratio = float(np.log(free_new).sum() - np.log(self.W[i + 1 : N - 1, lo : P - 1]).sum())
        if log_ratio >= 0 or self.rng.random() < math.exp(log_ratio):
            self.W = W_new
            return True
        self.q[i, j] = old
        return False

    def _compiled(self, units: int, out: np.ndarray, qs: np.ndarray, thin: int = 1,
                  progress: Callable[[int], object] | None = None) -> None:
        """``units`` records of ``thin`` sweeps into ``out`` (and ``qs`` if non-empty), or (``out`` empty) ``units``
        sweeps, compiled, in calls of ~0.15 s cut between sweeps (:func:`forcenet.numeric.jit.chunks`): Ctrl-C
        is seen between two calls, and the chain is the one a single call gives; ``progress(k)`` per call."""

        scene = self.scene
        kernels = _kernels()
        cs, dd = kernels.packing_state(self.q, self.W, scene)
        gi = np.array([g[0] for g in self.grains], dtype=np.int64)
        gj = np.array([g[1] for g in self.grains], dtype=np.int64)
        counters = np.array([self.attempted, self.accepted, self.rejected_by_constraint, self.evaluations, 0],
                            dtype=np.int64)
        ph = 0.0 if scene.ph is None else float(scene.ph)
        tol = -1e-9 * max(1.0, ph)
        step = 0.0 if self.step is None else float(self.step)
        top = np.ascontiguousarray(scene.top_load, dtype=float)
        record = out.shape[0] > 0
        per_unit = _compiled_seconds_per_move(scene) * len(self.grains) * (thin if record else 1)
        try:
            for start, stop in chunks(units, first_chunk(per_unit)):
                sweeps = (stop - start) * (thin if record else 1)
                W_part = out[start:stop] if record else out
                q_part = qs[start:stop] if qs.shape[0] else qs
                if self.move == "slice":
                    kernels.packing_slice_sweeps(self.q, self.W, cs, dd, gi, gj, self.rng, sweeps, ph, scene.ph is not None,
                                         tol, top, float(scene.mg), W_part, q_part, counters, thin)
                else:
                    kernels.packing_sweeps(self.q, self.W, cs, dd, gi, gj, self.rng, sweeps, ph, scene.ph is not None, tol,
                                   step, top, float(scene.mg), W_part, q_part, counters, thin)
                if progress is not None and record:
                    progress(stop - start)
        finally:  # also on Ctrl-C: the counters of the sweeps done
            self.attempted, self.accepted, self.rejected_by_constraint = (int(x) for x in counters[:3])
            self.evaluations = int(counters[3])
        if counters[4]:  # pragma: no cover - never observed
            raise ArithmeticError("slice move: an interval shrank 200 times without a point under the density")

    def sweep(self, count: int = 1) -> None:
        """``count`` sweeps of ``(N-1)(P-1)`` single-grain updates (Sec. 3.2.4), the state kept in ``q`` and ``W``.

        Parameters
        ----------
        count : int, default 1
            Sweeps to run; each attempts one move per free grain.

        Examples
        --------
        >>> m = PackingMetropolis(Scene(N=3, P=4, pv=1.0), seed=0)
        >>> m.sweep(5)
        >>> m.attempted  # 5 sweeps of (3 - 1)(4 - 1) moves
        30
        """
        if self.kernel == "compiled":
            if count > 0:
                N, P = self.scene.N, self.scene.P
                self._compiled(count, np.empty((0, N, P)), np.empty((0, N - 1, P)))
            return
        n = len(self.grains)
        for _ in range(count):
            for k, value in zip(self.rng.integers(n, size=n), self.rng.random(n)):
                i, j = self.grains[k]
                if self.step is not None:  # symmetric local move, reflected into [0, 1]
                    value = abs(self.q[i, j] + self.step * (2 * value - 1))
                    value = 2 - value if value > 1 else value
                self.attempted += 1
                if self._propose(i, j, value):
                    self.accepted += 1

    @overload
    def run(self, sweeps: int, burn_in: int = 0, progress: Callable[[int], object] | None = None,
            record_q: Literal[False] = False, thin: int = 1) -> np.ndarray: ...

    @overload
    def run(self, sweeps: int, burn_in: int = 0, progress: Callable[[int], object] | None = None, *,
            record_q: Literal[True], thin: int = 1) -> tuple[np.ndarray, np.ndarray]: ...

    def run(self, sweeps: int, burn_in: int = 0, progress: Callable[[int], object] | None = None,
            record_q: bool = False, thin: int = 1) -> np.ndarray | tuple[np.ndarray, np.ndarray]:
        """Burn in, then record ``W`` (and ``q`` if asked) after every ``thin``-th of ``sweeps * thin`` sweeps.

        Parameters
        ----------
        sweeps : int
            Records to keep (``>= 1``).
        burn_in : int, default 0
            Sweeps run first and not recorded.
        progress : callable, optional
            Called with the number of new records (once per record, or per compiled call).
        record_q : bool, default False
            Also return the ``q`` of every record.
        thin : int, default 1
            Sweeps between two records.

        Returns
        -------
        numpy.ndarray or tuple of numpy.ndarray
            ``W`` of shape ``(sweeps, N, P)`` (Eq. 3.9), or ``(W, q)`` with ``q`` of shape ``(sweeps, N-1, P)``.

        Examples
        --------
        >>> m = PackingMetropolis(Scene(N=3, P=4, pv=1.0), seed=0)
        >>> W, q = m.run(sweeps=10, burn_in=5, record_q=True)
        >>> W.shape, q.shape
        ((10, 3, 4), (10, 2, 4))
        """
        sweeps, burn_in = check_int(sweeps, "sweeps", 1), check_int(burn_in, "burn_in", 0)
        thin = check_int(thin, "thin", 1)
        self.sweep(burn_in)
        out = np.empty((sweeps, self.scene.N, self.scene.P))
        qs = np.empty(((sweeps if record_q else 0),) + self.q.shape)  # empty: q is not recorded
        if self.kernel == "compiled":
            self._compiled(sweeps, out, qs, thin, progress)
            return (out, qs) if record_q else out
        for t in range(sweeps):
            self.sweep(thin)
            out[t] = self.W
            if record_q:
                qs[t] = self.q
            if progress is not None:
                progress(1)
        return (out, qs) if record_q else out


def response(scene: Scene, sweeps: int, burn_in: int, seed: int | np.random.SeedSequence = 0, progress: Callable[[int], object] | None = None,
             move: str = "metropolis") -> tuple[np.ndarray, np.ndarray, dict]:
    """Mean response ``G(i,j) = (<W>_{p+F} - <W>_p)/F`` with standard errors.

    Two independent chains, with and without the overload (Sec. 3.1); each
    error bar comes from the integrated autocorrelation time
    (:func:`forcenet.numeric.autocorr.mean_and_stderr`, which raises on a chain too
    short to trust), and the two are added in quadrature.

    Parameters
    ----------
    scene : Scene
        The packing, with its overload ``F > 0``.
    sweeps, burn_in : int
        Recorded sweeps and burn-in sweeps of each chain.
    seed : int or numpy.random.SeedSequence
        Spawns the two chains' streams.
    progress : callable, optional
        Ticks once per record of either chain.
    move : {"metropolis", "slice"}
        As in :class:`PackingMetropolis`.

    Returns
    -------
    G, stderr_G, info : arrays of shape ``(N, P)`` and a dict (acceptance, tau).

    Raises
    ------
    forcenet.core.errors.ArgumentError
        On ``F <= 0`` or a bad argument of the samplers.
    forcenet.numeric.autocorr.AutocorrError
        If a chain is too short to trust its error bars.

    Examples
    --------
    >>> G, err, info = response(Scene(N=3, P=3, F=1.0, mg=1.0, j0=2), 2000, 100, seed=1)
    >>> bool(abs(G[-1].sum() - 1) < 1e-9)  # the floor carries the whole overload
    True
    """

    if scene.F <= 0:
        raise ArgumentError(f"F={scene.F}: the response needs an overload F > 0")
    seeds = (seed if isinstance(seed, np.random.SeedSequence) else np.random.SeedSequence(seed)).spawn(2)
    loaded = PackingMetropolis(scene, seed=np.random.default_rng(seeds[0]), move=move)
    base = PackingMetropolis(replace(scene, F=0.0), seed=np.random.default_rng(seeds[1]), move=move)
    m1, e1, t1 = mean_and_stderr(loaded.run(sweeps, burn_in, progress))
    m0, e0, t0 = mean_and_stderr(base.run(sweeps, burn_in, progress))
    G = (m1 - m0) / scene.F
    err = np.hypot(e1, e0) / scene.F
    info = {
        "acceptance": [loaded.acceptance_rate, base.acceptance_rate],
        "tau_max": float(max(t1.max(), t0.max())),
    }
    return G, err, info


# measured seconds per move of the reference kernel: gravity scene N = 12, P = 25 (every q allowed): 64 s for
# 2200 sweeps; isotropic scene N = 8, P = 17 (finite ph): 311 s for 44000 sweeps
_SECONDS_PER_MOVE = {True: 1.1e-4, False: 6.5e-5}


def _compiled_seconds_per_move(scene: Scene) -> float:
    """The compiled kernel's cost of one move (benchmarks/bench_samplers.py, notes/benchmarks.md).

    A fixed part, the light cone (~N^2/4 forces on average), and with a finite
    ``ph`` the lateral forces right of the grain in the layers below it (~N P/4
    on average, often cut short by a rejection).  Measured: 0.61-0.80 us on the isotropic 8 x 17 scene,
    0.45 us on the gravity 20 x 41 scene.
    """
    N, P = scene.N, scene.P
    cone = min(N * N / 4, N * P / 2)
    return 2.5e-7 + 2.5e-9 * cone + (1e-8 * N * P / 4 if scene.ph is not None else 0.0)


# compiling the kernel on a first run (empty numba cache), CPU seconds: benchmarks/compile_times.py
COMPILE_SECONDS = {"metropolis": 11.5, "slice": 15.7}


def packing_plan(scene: Scene, sweeps: int, burn_in: int = 0, chains: int = 1, memory_bytes: int | None = None,
                 kernel: str | None = None, move: str = "metropolis") -> Plan:
    """The cost of ``chains`` runs of :meth:`PackingMetropolis.run` (the chains are stored).

    Examples
    --------
    >>> packing_plan(Scene(N=12, P=25, F=1000, mg=1), 2000, 200, kernel="python").seconds > 60
    True
    >>> compiled = packing_plan(Scene(N=12, P=25, F=1000, mg=1), 2000, 200)  # (+ compiling it on a first run)
    >>> packing_plan(Scene(N=12, P=25, F=1000, mg=1), 2000, 200, kernel="python").seconds > 30 * (
    ...     compiled.seconds - compiled.compile_seconds - 1.5)
    True
    """

    sweeps, burn_in = check_int(sweeps, "sweeps", 1), check_int(burn_in, "burn_in", 0)
    if move not in COMPILE_SECONDS:
        raise ArgumentError(f"move={move!r}: expected 'metropolis' or 'slice'")
    moves = (scene.N - 1) * (scene.P - 1) * (sweeps + burn_in) * chains
    compiled = kernel_choice(kernel) == "compiled"
    if compiled:
        per_move, start = _compiled_seconds_per_move(scene), 1.5  # + loading the cached kernel
    else:
        per_move, start = _SECONDS_PER_MOVE[scene.ph is None], 0.5
    plan = Plan(f"Metropolis on the {scene.N} x {scene.P} packing, {chains} x {sweeps} sweeps",
                per_move * moves + start,
                sweeps * scene.N * scene.P * 8 + 150 * 2**20, sweeps * chains, "sweep")
    if compiled:  # a first run (numba's cache lacks the kernel) compiles it
        kernels = _kernels()
        entry = kernels.packing_slice_sweeps if move == "slice" else kernels.packing_sweeps
        plan = with_compilation(plan, f"packing {move}", COMPILE_SECONDS[move], [entry])
    return plan.within_memory(memory_bytes)
