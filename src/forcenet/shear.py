"""Force networks under shear (thesis Ch. 8): :func:`yield_stress` and :func:`shear_scaling`.

* :func:`yield_stress` -- the largest shear stress ``tau = sigma_xy/sigma_xx``
  the periodic hexagonal packing's polytope admits (Sec. 8.2), exactly
  (a proof checked in rational arithmetic,
  :mod:`forcenet.exact.contact_network.shear_stress`) and by floating LP.
* :func:`shear_scaling` (and :func:`shear_scaling_plan`, what the command
  line runs) -- the anisotropic finite-size scaling of Sec. 8.3: networks of
  the sheared ensemble by wheel moves
  (:mod:`forcenet.numeric.contact_network.wheel_moves`), clusters on
  rectangles along the principal stress axes, ``nu_M``, ``nu_m`` by the
  strips' collapses and the anisotropy ``r(tau)`` by Eq. (8.9)
  (:mod:`forcenet.numeric.force_chains.anisotropic_scaling`), errors by a
  bootstrap over blocks of samples; ``model="independent"`` replaces the
  ensemble by independent exponential forces with the same mean per bond
  direction (anisotropic bond percolation: a control whose exponents are
  known, ``nu = 4/3`` in both directions).

Examples
--------
>>> import forcenet
>>> forcenet.yield_stress("hexagonal", 3).tau_max
'sqrt(3)/3'
"""

from __future__ import annotations

import hashlib
import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from forcenet.core.checkpoints import CheckpointStore
from forcenet.core.errors import ArgumentError, ConvergenceError
from forcenet.core.plan import Plan
from forcenet.core.validation import check_int, check_real
from forcenet.exact.contact_network.geometries import hexagonal_torus
from forcenet.exact.contact_network.shear_stress import float_yield_stress
from forcenet.exact.contact_network.shear_stress import yield_stress as exact_yield_stress
from forcenet.numeric.contact_network.wheel_moves import SECONDS_PER_MOVE, YIELD_HEXAGONAL, WheelMoves
from forcenet.numeric.force_chains.anisotropic_scaling import (
    AnisotropyFit,
    fit_anisotropy,
    peak_heights,
    s2_curves,
    strip_blocks,
)
from forcenet.numeric.force_chains.finite_size_scaling import analyse
from forcenet.shear_results import ShearScaling, YieldStressResult

__all__ = ["yield_stress", "YieldStressResult", "shear_scaling", "shear_scaling_plan", "ShearScaling", "ShearPlan"]

GEOMETRIES = ("hexagonal",)
MAX_EXACT_SIZE = 6  # the exact simplex's time grows like L^7: about 2 minutes at L = 6 on the 2-core machine
SECONDS_PER_BOND = 6e-7  # one bond of one rectangle in the clusters' pass (sort, union-find), measured under load
SECONDS_PER_FIT = 0.05  # one fit of Eq. (8.9) (a bootstrap replica)
SECONDS_PER_COLLAPSE = 0.4  # one collapse (6.12) of a strip family, per bootstrap replica
STRIPS = (4, 6, 8, 10, 12, 16)  # the default strips' short sides (those that fit)
SIDES = (8, 12, 16, 24, 32)  # the default rectangles' sides (the pairs that fit); below 8 corrections bias theta (notes)


def _geometry(geometry: Any) -> str:
    if geometry not in GEOMETRIES:
        raise ArgumentError(f"geometry={geometry!r} is not supported: the sheared ensemble is built on "
                            f"{', '.join(GEOMETRIES)} (the periodic hexagonal packing of Sec. 8.2)")
    return str(geometry)


def yield_stress(geometry: str = "hexagonal", size: int = 3, *, exact: bool = True) -> YieldStressResult:
    """The yield stress: the largest ``tau = sigma_xy / sigma_xx`` with a balanced repulsive network (Sec. 8.2).

    The polytope of the sheared ensemble (Eq. (8.1) imposed on the periodic packing, every grain balanced,
    every force ``>= 0``) is empty beyond it.  ``exact=True``: the rational simplex's optimum with its proof
    (a network at ``tau_max`` and a dual certificate that no network exists beyond), and the floating LP beside.

    Parameters
    ----------
    geometry : str
        ``"hexagonal"``: the periodic hexagonal packing (:func:`~forcenet.exact.contact_network.geometries.hexagonal_torus`).
    size : int
        Its period ``L >= 3`` (``<= 6`` for the exact route, whose time grows like ``L^7``).
    exact : bool
        Run the exact route (default) or only the floating one.

    Returns
    -------
    YieldStressResult

    Raises
    ------
    ArgumentError
        An unknown geometry, a size out of range.

    Examples
    --------
    >>> r = yield_stress("hexagonal", 3)
    >>> r.tau_max, round(r.float_lp, 9)
    ('sqrt(3)/3', 0.577350269)
    >>> yield_stress("snooker", 3)
    Traceback (most recent call last):
    ...
    forcenet.core.errors.ArgumentError: geometry='snooker' is not supported: the sheared ensemble is built on hexagonal (the periodic hexagonal packing of Sec. 8.2)
    """
    geometry = _geometry(geometry)
    size = check_int(size, "size", 3, MAX_EXACT_SIZE if exact else 40)
    net = hexagonal_torus(size).network
    lp = float_yield_stress(net)
    if not exact:
        return YieldStressResult(geometry, size, None, lp, lp, None)
    proof = exact_yield_stress(net)
    return YieldStressResult(geometry, size, str(proof.tau_max), float(proof.tau_max), lp,
                             sum(1 for f in proof.witness if f == 0))


@dataclass(frozen=True)
class ShearRequest:
    """A validated request of :func:`shear_scaling_plan` (the front door checks it once)."""

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


def _family(strips: Sequence[float], aspect: float) -> tuple[list[tuple[float, float]], list[tuple[float, float]]]:
    along = [(l, aspect * l) for l in strips]  # short side along M: nu_M
    across = [(aspect * l, l) for l in strips]  # short side along m: nu_m
    return along, across


def _forces(request: ShearRequest, tau: float, seed: int) -> np.ndarray:
    if request.model == "ensemble":
        return WheelMoves(request.L, tau).run(request.samples, seed=seed, thin=request.thin)
    rng = np.random.default_rng(seed)  # the control: independent exponential forces, the ensemble's mean per direction
    means = np.tile([1.0, 1 + math.sqrt(3) * tau, 1 - math.sqrt(3) * tau], request.L ** 2)
    return rng.exponential(size=(request.samples, means.size)) * means


@dataclass(frozen=True)
class ShearPlan:
    """A planned :func:`shear_scaling` run: its ``cost`` (a :class:`~forcenet.core.plan.Plan`) and :meth:`run`.

    Parameters
    ----------
    request : ShearRequest
        The validated request.
    cost : Plan
        Its estimated time and memory (the command line announces it, refuses it over a minute without ``--force``).

    Examples
    --------
    >>> shear_scaling_plan((0.0, 0.2), L=40).cost.ticks
    2
    """

    request: ShearRequest
    cost: Plan

    def run(self, progress: Callable[..., Any] | None = None) -> ShearScaling:
        """Run as planned (``progress`` ticks once per ``tau``).

        Parameters
        ----------
        progress : callable, optional
            Called with 1 after every ``tau``.

        Returns
        -------
        ShearScaling

        Examples
        --------
        >>> plan = shear_scaling_plan((0.0,), L=12, shapes=((4, 3), (4, 6), (8, 3), (8, 6)), strips=(),
        ...                           samples=8, thin=2, replicas=0, thresholds=(0.2, 4.5, 44))
        >>> plan.run().taus
        (0.0,)
        """
        if not self.cost.runnable:
            raise ArgumentError(str(self.cost.refusal))
        q = self.request
        t0 = time.perf_counter()
        thresholds = np.linspace(*q.thresholds)
        along, across = _family(q.strips, q.aspect)
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
        return _analyse(q, thresholds, shapes, along, across, per_tau, time.perf_counter() - t0)


def _blocks(samples: int, blocks: int) -> list[np.ndarray]:
    return np.array_split(np.arange(samples), min(blocks, samples))


def _fit(q: ShearRequest, thresholds: np.ndarray, per_tau: list[tuple[list[np.ndarray], list[int]]],
         weights: list[np.ndarray] | None) -> AnisotropyFit:
    n = len(q.shapes)
    heights = [peak_heights(sums[:n], bonds[:n], thresholds, None if weights is None else weights[k])
               for k, (sums, bonds) in enumerate(per_tau)]
    return fit_anisotropy(q.shapes, heights)


def _analyse(q: ShearRequest, thresholds: np.ndarray, shapes: list[tuple[float, float]],
             along: list[tuple[float, float]], across: list[tuple[float, float]],
             per_tau: list[tuple[list[np.ndarray], list[int]]], seconds: float) -> ShearScaling:
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
    return ShearScaling(tuple(q.taus), exps["nu_M"], exps["nu_M_error"], exps["nu_m"], exps["nu_m_error"],
                        exps["g_M"], exps["g_m"], list(central.r), r_err, central.theta, theta_err, details)


def shear_scaling_plan(taus: Sequence[float] = (0.0, 0.1, 0.2, 0.3), *, L: int = 40,
                       shapes: Sequence[tuple[float, float]] | None = None,
                       strips: Sequence[float] | None = None, aspect: float = 3.0, samples: int = 200,
                       thin: int = 20, blocks: int = 20, placements: int = 4, replicas: int = 30, seed: int = 0,
                       model: str = "ensemble", thresholds: tuple[float, float, int] = (0.3, 3.0, 136),
                       checkpoint: str | None = None) -> ShearPlan:
    """Validate and plan an anisotropic scaling run (Sec. 8.3); see :func:`shear_scaling`.

    Parameters
    ----------
    taus, L, shapes, strips, aspect, samples, thin, blocks, placements, replicas, seed, model, thresholds, checkpoint
        As in :func:`shear_scaling`.

    Returns
    -------
    ShearPlan

    Raises
    ------
    ArgumentError
        A ``tau`` beyond the yield stress, a rectangle that does not fit in the torus, a value out of range.

    Examples
    --------
    >>> shear_scaling_plan().cost.seconds < 600
    True
    >>> shear_scaling_plan((0.7,))
    Traceback (most recent call last):
    ...
    forcenet.core.errors.ArgumentError: taus[0]=0.7 is beyond the yield stress of the hexagonal packing, tau_max = 1/sqrt(3) = 0.57735: give |tau| < 0.57735
    """
    if isinstance(taus, (str, bytes)) or not isinstance(taus, Sequence) or not taus:
        raise ArgumentError(f"taus={taus!r} must be a non-empty list of shear stresses")
    checked = []
    for k, t in enumerate(taus):
        value = check_real(t, f"taus[{k}]")
        if not abs(value) < YIELD_HEXAGONAL:
            raise ArgumentError(f"taus[{k}]={value!r} is beyond the yield stress of the hexagonal packing, tau_max = "
                                f"1/sqrt(3) = {YIELD_HEXAGONAL:.5f}: give |tau| < {YIELD_HEXAGONAL:.5f}")
        checked.append(value)
    L = check_int(L, "L", 6)
    if model not in ("ensemble", "independent"):
        raise ArgumentError(f"model={model!r} is not a shear model: give 'ensemble' (wheel moves) or 'independent' "
                            "(independent exponential forces, the percolation control)")
    aspect = check_real(aspect, "aspect", 1.0)
    if strips is None:  # the default widths whose strips fit in the torus; fewer than three: no nu
        fitting = [w for w in STRIPS if math.hypot(w, aspect * w) < L]
        strips = fitting if len(fitting) >= 3 else []
    strips_t = tuple(check_real(s, "strips", 1.0) for s in strips)
    if 0 < len(strips_t) < 3:
        raise ArgumentError(f"strips={list(strips)!r}: the collapse needs at least 3 strip widths (none: no nu_M, nu_m)")
    if shapes is None:  # a symmetric grid: at tau = 0 the data are symmetric and r = 1 tests the mirror symmetry
        shapes = [(a, b) for a in SIDES for b in SIDES if math.hypot(a, b) < L]
    shapes_t = tuple((check_real(a, "shapes", 1.0), check_real(b, "shapes", 1.0)) for a, b in shapes)
    if len(shapes_t) < 4:
        raise ArgumentError(f"L={L} leaves {len(shapes_t)} rectangles for the fit of Eq. (8.9), which needs at least 4: "
                            "give L >= 20 or more shapes")
    for a, b in list(shapes_t) + _family(strips_t, aspect)[0]:
        if math.hypot(a, b) >= L:
            raise ArgumentError(f"a {a} x {b} rectangle does not fit in the L={L} torus (its diagonal must be "
                                f"shorter than L): give a larger L or smaller shapes and strips")
    lo, hi, count = thresholds
    lo, hi = check_real(lo, "thresholds", 0.0), check_real(hi, "thresholds", 0.0)
    count = check_int(count, "thresholds", 16)
    if not hi > lo:
        raise ArgumentError(f"thresholds={thresholds!r}: the largest must exceed the smallest")
    request = ShearRequest(tuple(checked), L, shapes_t, strips_t, aspect, check_int(samples, "samples", 4),
                           check_int(thin, "thin", 1), check_int(blocks, "blocks", 2),
                           check_int(placements, "placements", 1), check_int(replicas, "replicas", 0),
                           check_int(seed, "seed", 0), model, (lo, hi, count),
                           None if checkpoint is None else str(checkpoint))
    along, across = _family(strips_t, aspect)
    bonds = sum(3.5 * a * b for a, b in list(shapes_t) + along + across) * request.placements
    per_tau = (request.samples * request.thin + max(100, L * L)) * L * L * SECONDS_PER_MOVE \
        + request.samples * bonds * SECONDS_PER_BOND * math.log2(max(2.0, bonds / request.placements)) / 10
    fits = (request.replicas + 1) * (SECONDS_PER_FIT + 2 * SECONDS_PER_COLLAPSE * len(checked) * bool(strips_t))
    nbytes = int(request.samples * 3 * L * L * 8 + len(checked) * (len(shapes_t) + 2 * len(strips_t))
                 * request.samples * count * 8)
    cost = Plan(f"anisotropic scaling under shear ({model}, L={L}, {len(checked)} taus, {request.samples} samples)",
                len(checked) * per_tau + fits, nbytes, len(checked), "tau")
    return ShearPlan(request, cost)


def shear_scaling(taus: Sequence[float] = (0.0, 0.1, 0.2, 0.3), **options: Any) -> ShearScaling:
    """Anisotropic finite-size scaling of the force network ensemble under shear (thesis Sec. 8.3, Eqs. (8.2)-(8.9)).

    Networks of the ``L x L`` periodic hexagonal packing under ``sigma_xy = tau sigma_xx`` by wheel moves, clusters
    of forces above each threshold on rectangles along the principal stress axes (every spanning cluster left
    out), ``<s^2>(f)`` and its peak.  ``nu_M`` (``nu_m``): the one-length collapse (6.12) of strips whose short
    side is along (across) the largest stress; ``r(tau)``: Eq. (8.9) fitted to ``<s^2>_max(L_M, L_m)`` of every
    ``tau`` at once.  Errors: a bootstrap over blocks of consecutive samples.

    Parameters
    ----------
    taus : sequence of float
        Shear stresses, ``|tau| < 1/sqrt(3)`` (the yield stress).
    **options
        ``L`` (torus period, default 40), ``shapes`` (the ``(L_M, L_m)`` rectangles of (8.9); default
        every pair of sides ``8 .. 32`` that fits), ``strips`` (short sides, default those of ``4 .. 16`` that fit;
        none, or fewer than 3 fitting: no ``nu_M``, ``nu_m``), ``aspect`` (default 3),
        ``samples`` (per ``tau``, default 200), ``thin`` (sweeps between samples, default 20), ``blocks`` (the
        bootstrap's, default 20), ``placements`` (rectangles per sample, default 4), ``replicas`` (default 30),
        ``seed``, ``model`` (``"ensemble"`` or ``"independent"``), ``thresholds`` (``(low, high, count)``),
        ``checkpoint`` (a directory: every finished ``tau`` recorded, a rerun resumes).

    Returns
    -------
    ShearScaling

    Examples
    --------
    >>> result = shear_scaling((0.0,), L=12, shapes=((4, 3), (4, 6), (8, 3), (8, 6)), strips=(), samples=8,
    ...                        thin=2, replicas=0, thresholds=(0.2, 4.5, 44))
    >>> len(result.r), result.details["model"]
    (1, 'ensemble')
    """
    return shear_scaling_plan(taus, **options).run()


_EXAMPLE: list[ShearScaling] = []


def example() -> ShearScaling:
    """A small run (two ``tau``, a 16-torus), made once per process: the examples' data.

    Returns
    -------
    ShearScaling

    Examples
    --------
    >>> example().taus
    (0.0, 0.3)
    """
    if not _EXAMPLE:
        _EXAMPLE.append(shear_scaling((0.0, 0.3), L=16, shapes=((4, 3), (4, 6), (4, 12), (8, 3), (8, 6), (8, 12)),
                                      strips=(), samples=12, thin=4, replicas=0, blocks=4,
                                      thresholds=(0.2, 4.5, 44)))
    return _EXAMPLE[0]
