"""The front door for Monte Carlo: ``<W_ij>`` with standard errors (:func:`sample`), and its plan (:func:`sample_plan`).

``forcenet.sample(N, samples)`` is what ``forcenet sample --N N --samples K``
computes, by the same engine and to the same bytes: independent exact
samples of the fully mobilized triangle (the hook walk, uniform tableaux of
Sec. 4.2), or the thesis's Markov chain of single-``q`` moves (Sec. 3.2.4,
Eqs. (3.8)-(3.10)) on the triangle or on the full ``N x P`` packing of
Sec. 3.2 (``scene=forcenet.Scene(...)``).  ``workers`` processes share
the work (:func:`forcenet.numeric.parallel_chains.sample_in_parallel`):
exact samples come in streams of the seed and the stream's index, so their
result depends on the arguments and ``seed`` alone, whatever ``workers``;
Markov chains are one per worker, their result fixed by ``seed`` and
``workers``.
``forcenet.sample_plan(...)`` validates the same request once and answers
what it will cost without doing the work; :meth:`SamplePlan.run` runs it.

Examples
--------
>>> import forcenet
>>> s = forcenet.sample(5, 2000, seed=3)
>>> bool(abs(s.mean[-1, 2] - 7 / 22) < 5 * s.stderr[-1, 2])  # the exact <W_53> = 7/22 (forcenet.table)
True
>>> p = forcenet.sample_plan(12, 20000, sampler="metropolis")
>>> p.runnable, p.burn_in
(True, 2000)
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, ClassVar

from forcenet.core.errors import ArgumentError, ArgumentTypeError, ConvergenceError
from forcenet.core.plan import Plan
from forcenet.core.validation import available_memory, check_int, check_real
from forcenet.costed_plans import CostedPlan, Progress
from forcenet.numeric.autocorr import AutocorrError, all_finite
from forcenet.numeric.packing.metropolis import packing_plan
from forcenet.numeric.packing.scene import Scene
from forcenet.numeric.parallel_chains import parallel_plan, sample_in_parallel
from forcenet.numeric.triangle.exact_sampler import sample_plan as exact_plan
from forcenet.numeric.triangle.metropolis import metropolis_plan
from forcenet.sample_results import Samples

if TYPE_CHECKING:  # pragma: no cover - annotations only
    from forcenet.numeric.packing.scene import Scene

__all__ = ["SamplePlan", "Samples", "sample", "sample_plan"]  # Samples: forcenet.sample_results


SAMPLERS = ("exact", "metropolis")
MOVES = ("metropolis", "slice")
MAX_WORKERS = 64


@dataclass(frozen=True, repr=False)  # the plan's own words: CostedPlan.__repr__
class SamplePlan(CostedPlan):
    """A checked Monte Carlo request with its cost: what :func:`sample_plan` returns (make it with :func:`sample_plan`).

    Parameters
    ----------
    N : int
        Number of layers.
    samples : int
        Samples (exact) or recorded sweeps (metropolis), over all workers.
    sampler : {"exact", "metropolis"}
        The sampler.
    seed : int
        The seed.
    workers : int
        Processes.
    F : float
        The overload on grain ``(1, j0)`` (the packing's: its scene's).
    ph : float or None
        Side pressure (None: fully mobilized; the packing's: its scene's).
    scene : forcenet.Scene or None
        The N x P packing; None for the triangle.
    burn_in : int or None
        Sweeps each chain discards first (None for exact samples).
    response : bool
        Also ``G(i, j)`` from a second chain (the packing).
    move : {"metropolis", "slice"}
        The chains' move.
    cost : forcenet.core.plan.Plan
        Estimated seconds, peak bytes, progress ticks, or the refusal.

    Attributes
    ----------
    load_range : tuple of float
        ``(1e-100, 1e100)``: where the loads may lie (their squares enter the error bars, far from overflow).

    Examples
    --------
    >>> import forcenet
    >>> p = forcenet.sample_plan(6, 4000, sampler="metropolis", workers=2)
    >>> p.cost.what, p.cost.ticks
    ('Metropolis N=6, 4000 sweeps, 2 workers', 4000)
    """

    load_range: ClassVar[tuple[float, float]] = (1e-100, 1e100)

    N: int
    samples: int
    sampler: str
    seed: int
    workers: int
    F: float
    ph: float | None
    scene: Scene | None
    burn_in: int | None
    response: bool
    move: str
    cost: Plan

    def run(self, progress: Progress | bool | None = None) -> Samples:
        """Draw the samples this plan describes (the plan is not made again) and pool them.

        Parameters
        ----------
        progress : callable, bool or None
            ``progress(k)`` per ``k`` samples or sweeps done; ``True``: a progress bar (tqdm).

        Returns
        -------
        Samples

        Raises
        ------
        ArgumentError
            If the plan is refused, or the run produced non-finite values (loads overflowing the floating point).
        ConvergenceError
            If a chain is too short to judge its autocorrelation time (run more sweeps).

        Examples
        --------
        >>> import forcenet
        >>> forcenet.sample_plan(4, 300, seed=7).run().effective_samples
        300.0
        """

        self.check()
        try:
            with self._ticks(progress, f"{self.sampler} N={self.N}") as tick:
                result = sample_in_parallel(self.sampler, self.N, self.samples, seed=self.seed,
                                            workers=self.workers,
                                            F=self.F, ph=self.ph, scene=self.scene, burn_in=self.burn_in or 0,
                                            response=self.response, move=self.move, progress=tick)
        except AutocorrError as exc:  # the chain cannot judge its own error bar: more sweeps would
            raise ConvergenceError(f"samples={self.samples}: {exc}; run more sweeps") from exc
        extra = result.extra
        values = [result.mean, result.stderr, extra["effective_samples"]] + [extra[k] for k in ("G", "stderr_G")
                                                                             if k in extra]
        if not all_finite(values):  # never a nan or an infinity as a result: an overflow of the model's numbers
            low, high = self.load_range
            raise ArgumentError("the run produced non-finite values (the loads overflow the floating-point range); "
                                f"give loads in [{low:g}, {high:g}]")
        return Samples(self.N, self.sampler, self.samples, self.seed, self.workers, result.mean, result.stderr,
                       extra, self.scene)


def _choice(value: Any, name: str, choices: tuple[str, ...]) -> str:
    if value not in choices:
        raise ArgumentError(f"{name}={value!r} is not one of {', '.join(map(repr, choices))}")
    return str(value)


def _check_loads(F: float, ph: float | None, scene: Scene | None) -> None:
    """Refuse loads whose squares would overflow or vanish (the triangle's F alone scales out: any finite F)."""
    low, high = SamplePlan.load_range
    if scene is not None:
        for name in ("F", "pv", "mg", "ph"):
            value = getattr(scene, name)
            if value is not None and value != 0 and not low <= value <= high:
                raise ArgumentError(f"{name}={value:g} is out of range: the packing's loads F, pv, mg, ph (scene=) "
                                    f"must lie in [{low:g}, {high:g}] (0 allowed for pv, mg)")
    elif ph is not None and not low <= ph / F <= high:
        raise ArgumentError(f"ph={ph:g} with F={F:g}: the ratio ph/F must lie in [{low:g}, {high:g}]")


def _scene_loads(scene: Any, F: Any, ph: Any) -> tuple[float, float | None]:
    """The packing's loads are its scene's: ``F``/``ph`` given beside ``scene`` must equal them."""

    if not isinstance(scene, Scene):
        raise ArgumentTypeError(f"scene={scene!r} is not a scene: give forcenet.Scene(N=..., P=..., ...)")
    if F is not None and check_real(F, "F", 0, low_open=True) != scene.F:
        raise ArgumentError(f"F={F} and scene.F={scene.F}: the packing's overload is its scene's; give it in "
                            "forcenet.Scene(..., F=...) and omit F")
    if ph is not None and (scene.ph is None or check_real(ph, "ph", 0, low_open=True) != scene.ph):
        raise ArgumentError(f"ph={ph} and scene.ph={scene.ph}: the packing's side pressure is its scene's; give it "
                            "in forcenet.Scene(..., ph=...) and omit ph")
    return scene.F, scene.ph


def sample_plan(N: int, samples: int, *, sampler: str = "exact", seed: int = 0, workers: int = 1,
                F: float | None = None, ph: float | None = None, scene: Scene | None = None,
                burn_in: int | None = None, response: bool = False, move: str = "metropolis",
                memory_bytes: int | None = None) -> SamplePlan:
    """What :func:`sample` will cost for this request, or why it cannot run; nothing is drawn.

    Parameters
    ----------
    N : int
        Number of layers, ``>= 2`` (with ``scene``: the scene's ``N``).
    samples : int
        Independent samples (exact) or recorded sweeps (metropolis), over all workers, ``>= 2``.
    sampler : {"exact", "metropolis"}
        ``"exact"``: independent exact samples of the fully mobilized triangle (the default);
        ``"metropolis"``: the thesis's Markov chain (also the packing, ``scene``).
    seed : int
        The seed, ``0 <= seed < 2**63``: exact samples depend on it alone, chains on it and ``workers``.
    workers : int
        Processes, ``1..64`` and at most ``samples``: independent chains (metropolis, seeds
        ``SeedSequence(seed).spawn(workers)``), or the exact sampler's streams of 10,000 samples shared out.
    F : float, optional
        The overload on grain ``(1, j0)``, a finite number ``> 0`` (default 1; with ``scene``: the scene's).
    ph : float, optional
        Side (left-wall) pressure of the triangle's chain (metropolis only); None: fully mobilized.
        With ``scene``: the scene's.
    scene : forcenet.Scene, optional
        The full N x P packing (metropolis only): walls, gravity, top pressure (Sec. 3.2).
    burn_in : int, optional
        Sweeps each chain discards first (metropolis only; default ``max(100, samples // 10)``).
    response : bool
        Also ``G(i, j) = (<W>_{p+F} - <W>_p) / F`` from a second chain (the packing only).
    move : {"metropolis", "slice"}
        The chains' move: the thesis's single-``q`` move, or each ``q`` drawn from its conditional law on its
        allowed interval (shorter autocorrelation times).
    memory_bytes : int, optional
        Memory the run may use; default: what the machine has available now.

    Returns
    -------
    SamplePlan
        The request, its estimated cost, or its refusal.

    Raises
    ------
    ArgumentError, ArgumentTypeError
        If an argument is out of range, an option does not apply to the sampler, or a load would overflow.

    Examples
    --------
    >>> import forcenet
    >>> forcenet.sample_plan(8, 2000).cost.what
    '2000 exact samples N=8'
    >>> forcenet.sample_plan(8, 2000, ph=0.5)
    Traceback (most recent call last):
    ...
    forcenet.core.errors.ArgumentError: ph=0.5 applies to sampler='metropolis' only (the exact sampler is the fully mobilized ensemble)
    """
    N, samples = check_int(N, "N", 2), check_int(samples, "samples", 2)
    sampler, move = _choice(sampler, "sampler", SAMPLERS), _choice(move, "move", MOVES)
    seed, workers = check_int(seed, "seed", 0, 2**63 - 1), check_int(workers, "workers", 1, MAX_WORKERS)
    response = bool(response)
    memory = (available_memory() or 16 * 2**30) if memory_bytes is None else check_int(memory_bytes, "memory_bytes", 1)
    chain = sampler == "metropolis"
    for name, value, given in (("ph", ph, ph is not None), ("scene", scene, scene is not None),
                               ("burn_in", burn_in, burn_in is not None), ("move", move, move != "metropolis")):
        if given and not chain:
            raise ArgumentError(f"{name}={value!r} applies to sampler='metropolis' only "
                                + ("(the exact sampler is the fully mobilized ensemble)" if name in ("ph", "scene")
                                   else "(exact samples need none)" if name == "burn_in" else "(exact samples)"))
    if scene is not None:
        F, ph = _scene_loads(scene, F, ph)
        if scene.N != N:
            raise ArgumentError(f"N={N} and scene.N={scene.N} differ: give the scene's number of layers")
    else:
        F = 1.0 if F is None else check_real(F, "F", 0, low_open=True)
        ph = None if ph is None else check_real(ph, "ph", 0, low_open=True)
        if response:
            raise ArgumentError("response=True needs the full packing (scene=forcenet.Scene(...)): on the triangle "
                                "G(i, j) = <W_ij>/F")
    _check_loads(F, ph, scene)
    if workers > samples:
        raise ArgumentError(f"workers={workers}: more workers than samples ({samples}); use at most {samples}")
    burn = (max(100, samples // 10) if burn_in is None else check_int(burn_in, "burn_in", 0)) if chain else None
    cost = _cost(N, samples, sampler, workers, ph, scene, burn, response, move, memory)
    return SamplePlan(N, samples, sampler, seed, workers, F, ph, scene, burn, response, move, cost)


def _cost(N: int, samples: int, sampler: str, workers: int, ph: float | None, scene: Scene | None,
          burn: int | None, response: bool, move: str, memory: int) -> Plan:
    """The sampler's plan for every sample in one process, spread over ``workers`` processes."""

    if burn is None:
        plan = exact_plan(N, samples, memory)
    elif scene is None:
        plan = metropolis_plan(N, samples, burn * workers, memory, ph=ph is not None, move=move)
    else:
        plan = packing_plan(scene, samples, burn * workers, 2 if response else 1, memory, move=move)
    return parallel_plan(plan, workers, memory)  # the processes on the machine's cores, each with its own share


def sample(N: int, samples: int, *, sampler: str = "exact", seed: int = 0, workers: int = 1,
           F: float | None = None, ph: float | None = None, scene: Scene | None = None, burn_in: int | None = None,
           response: bool = False, move: str = "metropolis", progress: Progress | bool | None = None,
           memory_bytes: int | None = None) -> Samples:
    """Monte Carlo ``<W_ij>`` with standard errors, as ``forcenet sample`` computes it (same engine, same bytes).

    The estimator of ``<W_ij>`` over the force network ensemble: for the
    exact sampler the mean of independent uniform samples (``samples``
    effective samples); for the Markov chain of Sec. 3.2.4 (moves in ``q``,
    Eqs. (3.8)-(3.10), uniform measure Eq. (3.10)) the pooled chains' means
    with error bars from their integrated autocorrelation times.

    Parameters
    ----------
    N : int
        Number of layers, ``>= 2``.
    samples : int
        Independent samples (exact) or recorded sweeps (metropolis), ``>= 2``.
    sampler : {"exact", "metropolis"}
        As in :func:`sample_plan`.
    seed : int
        The seed; the result depends on it and on ``workers`` only.
    workers : int
        Processes, ``1..64``, at most ``samples``.
    F : float, optional
        The overload (default 1; with ``scene``: the scene's).
    ph : float, optional
        Side pressure of the triangle's chain (None: fully mobilized).
    scene : forcenet.Scene, optional
        The full N x P packing (metropolis only).
    burn_in : int, optional
        Sweeps discarded by each chain (default ``max(100, samples // 10)``).
    response : bool
        Also the response ``G(i, j)`` (the packing only).
    move : {"metropolis", "slice"}
        The chains' move.
    progress : callable, bool or None
        ``progress(k)`` per ``k`` samples or sweeps; ``True``: a progress bar.
    memory_bytes : int, optional
        Memory the run may use; default: what the machine has available now.

    Returns
    -------
    Samples
        The means, their standard errors, the effective sample size and the chains' statistics.

    Raises
    ------
    ArgumentError, ArgumentTypeError
        If the request is out of range or its plan refused (memory), or the run overflowed.
    ConvergenceError
        If a chain is too short to judge its autocorrelation time (run more sweeps).

    Examples
    --------
    >>> import forcenet
    >>> s = forcenet.sample(6, 3000, sampler="metropolis", seed=1)
    >>> s.sampler, s.extra["burn_in"], s.tau >= 1
    ('metropolis', 300, True)
    >>> scene = forcenet.Scene(N=3, P=5, F=20.0, mg=1.0)
    >>> forcenet.sample(3, 2000, sampler="metropolis", scene=scene, seed=2).mean.shape
    (3, 5)
    >>> forcenet.sample(6, 50, sampler="metropolis")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    forcenet.core.errors.ConvergenceError: samples=50: ...too short...; run more sweeps
    """
    return sample_plan(N, samples, sampler=sampler, seed=seed, workers=workers, F=F, ph=ph, scene=scene,
                       burn_in=burn_in, response=response, move=move, memory_bytes=memory_bytes).check().run(progress)
