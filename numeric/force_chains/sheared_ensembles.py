"""The force network ensemble under shear as a registered model (thesis Ch. 8, Secs. 8.2-8.3): its engine.

The model ``shear`` (quantity ``scaling``) enters by the registry (:data:`forcenet.core.registry.REGISTRY`, its
loader in :mod:`forcenet.registry`): :class:`WheelMovesEngine` plans a checked :class:`ShearRequest` and runs it,
``tau`` by ``tau`` (checkpointed), into a :class:`ShearOutcome` that the front door
(:func:`forcenet.shear_scaling`) hands back as a :class:`forcenet.ShearScaling`.  The networks come from the
thesis's wheel moves (:mod:`forcenet.numeric.contact_network.wheel_moves`) or, for the control, from independent
exponential forces with the ensemble's mean per bond direction; the clusters and the fit of Eq. (8.9) from
:mod:`forcenet.numeric.force_chains.anisotropic_scaling`.

Examples
--------
>>> from forcenet.core.registry import REGISTRY
>>> REGISTRY.engine("shear", "scaling", "wheel-moves").name
'wheel-moves'
"""

from __future__ import annotations

import hashlib
import math
import time
from collections.abc import Callable, Sequence
from concurrent.futures import Executor
from dataclasses import dataclass
from typing import Any, NamedTuple

import numpy as np

from forcenet.core.checkpoints import CheckpointStore
from forcenet.core.errors import ArgumentError, ConvergenceError
from forcenet.core.plan import Plan
from forcenet.core.registry import REGISTRY

from ..contact_network.wheel_moves import SECONDS_PER_MOVE, WheelMoves
from .anisotropic_scaling import AnisotropyFit, fit_anisotropy, peak_heights, s2_curves, strip_blocks
from .finite_size_scaling import analyse

__all__ = ["ShearRequest", "ShearOutcome", "WheelMovesEngine", "analyse_shear", "shear_family"]

SECONDS_PER_BOND = 6e-7  # one bond of one rectangle in the clusters' pass (sort, union-find), measured under load
SECONDS_PER_FIT = 0.05  # one fit of Eq. (8.9) (a bootstrap replica)
SECONDS_PER_COLLAPSE = 0.4  # one collapse (6.12) of a strip family, per bootstrap replica


@dataclass(frozen=True)
class ShearRequest:
    """A validated request of :func:`forcenet.shear_scaling_plan` (the front door checks it once)."""

    taus: tuple[float, ...]
    L: int
    shapes: tuple[tuple[float, float], ...]
    strips: tuple[float, ...]
    aspect: float
    samples: int
    thin: int
    blocks: int
    placements: int
    replicas: int
    seed: int
    model: str
    thresholds: tuple[float, float, int]
    checkpoint: str | None

    def key(self) -> str:
        """A digest naming the request in checkpoints."""
        text = repr((self.L, self.shapes, self.strips, self.aspect, self.samples, self.thin, self.placements,
                     self.seed, self.model, self.thresholds))
        return hashlib.sha256(text.encode()).hexdigest()[:16]


class ShearOutcome(NamedTuple):
    """What a run gives, field for field :class:`forcenet.ShearScaling`'s (the front door wraps it)."""

    taus: tuple[float, ...]
    nu_M: list[float]
    nu_M_error: list[float]
    nu_m: list[float]
    nu_m_error: list[float]
    gamma_2_M: list[float]
    gamma_2_m: list[float]
    r: list[float]
    r_error: list[float]
    theta: float
    theta_error: float
    details: dict[str, Any]


def shear_family(strips: Sequence[float], aspect: float) -> tuple[list[tuple[float, float]], list[tuple[float, float]]]:
    """The strips whose short side lies along the largest stress (``nu_M``) and across it (``nu_m``).

    Parameters
    ----------
    strips : sequence of float
        The short sides.
    aspect : float
        Long side over short side.

    Returns
    -------
    tuple of two lists of (float, float)

    Examples
    --------
    >>> shear_family([4, 6], 3.0)
    ([(4, 12.0), (6, 18.0)], [(12.0, 4), (18.0, 6)])
    """
    along = [(l, aspect * l) for l in strips]  # short side along M: nu_M
    across = [(aspect * l, l) for l in strips]  # short side along m: nu_m
    return along, across


def _forces(request: ShearRequest, tau: float, seed: int) -> np.ndarray:
    if request.model == "ensemble":
        return WheelMoves(request.L, tau).run(request.samples, seed=seed, thin=request.thin)
    rng = np.random.default_rng(seed)  # the control: independent exponential forces, the ensemble's mean per direction
    means = np.tile([1.0, 1 + math.sqrt(3) * tau, 1 - math.sqrt(3) * tau], request.L ** 2)
    return rng.exponential(size=(request.samples, means.size)) * means


class WheelMovesEngine:
    """The model ``shear``'s engine: wheel-move networks (or the control's), their clusters, Eqs. (8.2)-(8.9)."""

    name = "wheel-moves"
    model = "shear"
    quantities = frozenset({"scaling"})

    def plan(self, request: ShearRequest) -> Plan:
        """The run's cost: the moves and the clusters' passes per ``tau``, the fits of every bootstrap replica.

        Parameters
        ----------
        request : ShearRequest

        Returns
        -------
        Plan

        Examples
        --------
        >>> import forcenet
        >>> forcenet.shear_scaling_plan((0.0, 0.2), L=40).cost.ticks
        2
        """
        along, across = shear_family(request.strips, request.aspect)
        bonds = sum(3.5 * a * b for a, b in list(request.shapes) + along + across) * request.placements
        per_tau = (request.samples * request.thin + max(100, request.L * request.L)) * request.L * request.L * SECONDS_PER_MOVE \
            + request.samples * bonds * SECONDS_PER_BOND * math.log2(max(2.0, bonds / request.placements)) / 10
        fits = (request.replicas + 1) * (SECONDS_PER_FIT + 2 * SECONDS_PER_COLLAPSE * len(request.taus) * bool(request.strips))
        nbytes = int(request.samples * 3 * request.L * request.L * 8 + len(request.taus) * (len(request.shapes) + 2 * len(request.strips))
                     * request.samples * request.thresholds[2] * 8)
        cost = Plan(f"anisotropic scaling under shear ({request.model}, L={request.L}, {len(request.taus)} taus, {request.samples} samples)",
                    len(request.taus) * per_tau + fits, nbytes, len(request.taus), "tau")
        return cost

    def run(self, request: ShearRequest, plan: Plan, *, progress: Callable[..., Any] | None = None,
            executor: Executor | None = None) -> ShearOutcome:
        """Run as planned, ``tau`` by ``tau`` (each recorded when ``request.checkpoint`` is set).

        Parameters
        ----------
        request : ShearRequest
        plan : Plan
        progress : callable, optional
            Called with 1 after every ``tau``.
        executor : concurrent.futures.Executor, optional
            Unused: the ``tau`` run in this process, one after another.

        Returns
        -------
        ShearOutcome

        Examples
        --------
        >>> import forcenet
        >>> p = forcenet.shear_scaling_plan((0.0,), L=12, shapes=((4, 3), (4, 6), (8, 3), (8, 6)), strips=(),
        ...                                 samples=8, thin=2, replicas=0, thresholds=(0.2, 4.5, 44))
        >>> WheelMovesEngine().run(p.request, p.cost).taus
        (0.0,)
        """
        q = request
        t0 = time.perf_counter()
        thresholds = np.linspace(*q.thresholds)
        along, across = shear_family(q.strips, q.aspect)
        shapes = list(q.shapes) + along + across
        seeds = [int(s.generate_state(1)[0]) for s in np.random.SeedSequence(q.seed).spawn(len(q.taus))]
        store = (CheckpointStore(q.checkpoint, f"shear-{q.key()}", q.L, shape=(len(shapes), q.samples,
                                                                                 len(thresholds)))
                 if q.checkpoint is not None else None)
        per_tau: list[tuple[list[np.ndarray], list[int]]] = []
        for k, tau in enumerate(q.taus):
            saved = store.load(k) if store is not None else None
            bonds = None
            if saved is None:
                sums, bonds = s2_curves(_forces(q, tau, seeds[k]), q.L, shapes, thresholds, q.placements, q.seed)
                if store is not None:
                    store.save(k, np.stack(sums))
            else:
                sums = list(saved)
            if bonds is None:
                bonds = s2_curves(np.ones((1, 3 * q.L ** 2)), q.L, shapes, thresholds[:1], q.placements, q.seed)[1]
            per_tau.append((sums, bonds))
            if progress is not None:
                progress(1)
        return analyse_shear(q, thresholds, shapes, along, across, per_tau, time.perf_counter() - t0)


def _blocks(samples: int, blocks: int) -> list[np.ndarray]:
    return np.array_split(np.arange(samples), min(blocks, samples))


def _fit(q: ShearRequest, thresholds: np.ndarray, per_tau: list[tuple[list[np.ndarray], list[int]]],
         weights: list[np.ndarray] | None) -> AnisotropyFit:
    n = len(q.shapes)
    heights = [peak_heights(sums[:n], bonds[:n], thresholds, None if weights is None else weights[k])
               for k, (sums, bonds) in enumerate(per_tau)]
    return fit_anisotropy(q.shapes, heights)


def analyse_shear(q: ShearRequest, thresholds: np.ndarray, shapes: list[tuple[float, float]],
             along: list[tuple[float, float]], across: list[tuple[float, float]],
             per_tau: list[tuple[list[np.ndarray], list[int]]], seconds: float) -> ShearOutcome:
    n, m = len(q.shapes), len(along)
    central = _fit(q, thresholds, per_tau, None)
    rng = np.random.default_rng(q.seed + 1)
    parts = _blocks(q.samples, q.blocks)
    boot: list[AnisotropyFit] = []
    for _ in range(q.replicas):  # blocks of consecutive samples with replacement, every tau
        weights = []
        for _tau in q.taus:
            counts = np.bincount(rng.integers(0, len(parts), len(parts)), minlength=len(parts))
            w = np.zeros(q.samples)
            for part, c in zip(parts, counts):
                w[part] = c
            weights.append(w)
        try:
            boot.append(_fit(q, thresholds, per_tau, weights))
        except ConvergenceError:
            continue
    r_err = [float(np.std([b.r[k] for b in boot], ddof=1)) if len(boot) > 1 else math.nan
             for k in range(len(q.taus))]
    theta_err = float(np.std([b.theta for b in boot], ddof=1)) if len(boot) > 1 else math.nan
    exps: dict[str, list[float]] = {k: [] for k in ("nu_M", "nu_M_error", "nu_m", "nu_m_error", "g_M", "g_m")}
    notes: list[str] = []
    shifts: dict[str, list[float]] = {}
    for k, (sums, bonds) in enumerate(per_tau):
        for name, lo, g in (("nu_M", n, "g_M"), ("nu_m", n + m, "g_m")):
            if not m:  # no strips asked for: no exponents
                for key in (name, name + "_error", g):
                    exps[key].append(math.nan)
                continue
            data = strip_blocks(sums[lo:lo + m], bonds[lo:lo + m], q.strips, thresholds, q.blocks)
            try:
                fit = analyse(data, replicas=q.replicas, seed=q.seed)
                exps[name].append(fit.value["nu"])
                exps[name + "_error"].append(fit.error["nu"])
                exps[g].append(fit.value["gamma_2"])
                shifts.setdefault(name, []).append(fit.estimators.get("nu", math.nan))  # the peak shift's nu
                if fit.pinned:
                    notes.append(f"tau={q.taus[k]}: the {name} collapse is pinned at its window's limit")
            except (ConvergenceError, ArgumentError) as exc:
                notes.append(f"tau={q.taus[k]}: no {name} collapse ({exc})")
                shifts.setdefault(name, []).append(math.nan)
                for key in (name, name + "_error", g):
                    exps[key].append(math.nan)
    heights = [peak_heights(sums[:n], bonds[:n], thresholds).tolist() for sums, bonds in per_tau]
    details = {"model": q.model, "L": q.L, "samples": q.samples, "thin": q.thin, "seed": q.seed,
               "placements": q.placements, "blocks": q.blocks, "replicas": len(boot), "shapes": [list(s) for s in q.shapes],
               "s2_max": heights, "strips": list(q.strips), "aspect": q.aspect, "k": central.k,
               "b_M": list(central.bM), "b_m": list(central.bm), "fit_residual": central.residual,
               "nu_peak_shift": shifts, "notes": notes, "seconds": seconds}
    return ShearOutcome(tuple(q.taus), exps["nu_M"], exps["nu_M_error"], exps["nu_m"], exps["nu_m_error"],
                        exps["g_M"], exps["g_m"], list(central.r), r_err, central.theta, theta_err, details)


REGISTRY.register(WheelMovesEngine())  # this module is the registry's loader for the model "shear"
