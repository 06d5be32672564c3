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

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from forcenet.core.errors import ArgumentError
from forcenet.core.plan import Plan
from forcenet.core.validation import check_int, check_real
from forcenet.costed_plans import CostedPlan, Progress
from forcenet.exact.contact_network.geometries import hexagonal_torus
from forcenet.exact.contact_network.shear_stress import float_yield_stress
from forcenet.exact.contact_network.shear_stress import yield_stress as exact_yield_stress
from forcenet.numeric.contact_network.wheel_moves import YIELD_HEXAGONAL
from forcenet.numeric.force_chains.sheared_ensembles import ShearRequest, shear_family
from forcenet.registry import REGISTRY
from forcenet.shear_results import ShearScaling, YieldStressResult

__all__ = ["yield_stress", "YieldStressResult", "shear_scaling", "shear_scaling_plan", "ShearScaling", "ShearPlan"]

GEOMETRIES = ("hexagonal",)
MAX_EXACT_SIZE = 6  # the exact simplex's time grows like L^7: about 2 minutes at L = 6 on the 2-core machine
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


@dataclass(frozen=True, repr=False)  # the plan's own words: CostedPlan.__repr__
class ShearPlan(CostedPlan):
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

    def run(self, progress: Progress | bool | None = None) -> ShearScaling:
        """Run as planned by the model's registered engine (``progress`` ticks once per ``tau``).

        Parameters
        ----------
        progress : callable, bool or None
            ``progress(k)`` after every ``tau``; ``True``: a progress bar.

        Returns
        -------
        ShearScaling

        Raises
        ------
        ArgumentError
            If the plan is refused.

        Examples
        --------
        >>> plan = shear_scaling_plan((0.0,), L=12, shapes=((4, 3), (4, 6), (8, 3), (8, 6)), strips=(),
        ...                           samples=8, thin=2, replicas=0, thresholds=(0.2, 4.5, 44))
        >>> plan.run().taus
        (0.0,)
        """
        self.cost.check()
        engine = REGISTRY.engine("shear", "scaling", "wheel-moves")
        with self._ticks(progress, "shear") as tick:
            outcome = engine.run(self.request, self.cost, progress=tick)
        return ShearScaling(*outcome)


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
    for a, b in list(shapes_t) + shear_family(strips_t, aspect)[0]:
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
    cost = REGISTRY.engine("shear", "scaling", "wheel-moves").plan(request)
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
