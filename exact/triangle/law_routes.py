"""The faster exact route to a law: the order-ideal DP against the polynomial Pfaffian routes.

Every law of the triangle has the order-ideal DP (:mod:`.gaps`,
:mod:`.distribution`; ``N`` up to about 30, memory permitting) and a
polynomial route up to ``N = 128``: the free-fermion lattice laws of the
grains ``(i, 1)``, ``(i, i)`` (:mod:`.free_fermion.fluctuations`) and de
Bruijn's Pfaffians for the floor (:mod:`.de_bruijn.floor`) and every layer
above it (:mod:`.de_bruijn.layers`).  Each ``*_route`` function compares the
plans and names the faster runnable one (the laws are equal, tested); its
``*_gap_law`` / ``*_pieces`` twin runs the route chosen.  What ``forcenet
dist`` runs for ``--layer``, ``--ensemble`` and ``--grain`` beyond the DP.

Examples
--------
>>> layer_route(12, 12)[0], single_grain_route(64, (64, 1))[0]
('ideals', 'pfaffian')
"""

from __future__ import annotations

from collections.abc import Callable
from concurrent.futures import Executor
from dataclasses import replace
from fractions import Fraction
from os import PathLike
from typing import Any

from forcenet.core.checkpoints import CheckpointStore
from forcenet.core.errors import ArgumentError
from forcenet.core.plan import Plan, combine
from forcenet.core.validation import check_grain, check_int, check_layers

from .de_bruijn.floor import MAX_FLOOR_N, floor_cost, floor_gap_laws, floor_pooled_gap_law
from .de_bruijn.layers import layer_cost, layer_gap_laws, layer_pooled_gap_law
from .distribution import distribution_plan, layer_pieces_from_gaps, triangle_force_density
from .free_fermion.fluctuations import MAX_LAW_N, grain_gap_law, lattice_gap_laws_cost
from .gap_counts import GapCounts, pool_gaps
from .gaps import gap_laws_cost, grain_gap_counts, layer_gap_counts
from .pieces import Piece, sum_pieces
from .prime_tasks import STARTUP_SECONDS
from .staircase import count, dimension

__all__ = ["layer_route", "layer_gap_law", "floor_contact_gap_law", "ensemble_route", "ensemble_pieces",
           "single_grain_route", "grain_route", "single_grain_gap_law"]


def layer_route(N: int, i: int, memory_bytes: int | None = None, *,
                executor: Executor | None = None) -> tuple[str, Plan]:
    """The faster exact route to layer ``i``'s pooled gap law, and its plan: ``"floor"``, ``"layers"`` or ``"ideals"``.

    The order-ideal DP (``N <= 30``, memory permitting) against de Bruijn
    Pfaffians: :func:`.de_bruijn.floor.floor_pooled_gap_law` for the floor (``i = N``),
    :func:`.de_bruijn.layers.layer_pooled_gap_law` above it (``N <= 128``).  The faster
    runnable plan wins (the laws are equal, tested).

    Parameters
    ----------
    N, i : int
        Number of layers ``2..128`` and the layer ``2..N``.
    memory_bytes : int, optional
        Memory available to the run.
    executor : concurrent.futures.Executor or Dask Client, optional
        Where the Pfaffians' per-prime tasks would run: their plan counts its
        workers (the DP runs in this process).

    Returns
    -------
    (str, Plan)
        The route's name and its plan.

    Examples
    --------
    >>> layer_route(40, 40)[0], layer_route(40, 20)[0], layer_route(12, 12)[0]
    ('floor', 'layers', 'ideals')
    """
    N = check_layers(N, maximum=MAX_FLOOR_N)
    i = check_int(i, "i", 2, N)
    what = f"exact P(f) of layer {i} N={N}"
    ideals = gap_laws_cost(N, 1, memory_bytes, what=f"{what} (order ideals)")
    name = "floor" if i == N else "layers"
    pfaffians = (floor_cost(N, False, memory_bytes, executor=executor) if i == N
                 else layer_cost(N, i, False, memory_bytes, executor=executor))
    pfaffians = replace(pfaffians, what=f"{what} (de Bruijn Pfaffians)")
    if ideals.runnable and (not pfaffians.runnable or ideals.seconds <= pfaffians.seconds):
        return "ideals", ideals
    return name, pfaffians


def layer_gap_law(N: int, i: int, route: str, progress: Callable[..., Any] | None = None, *,
                  executor: Executor | None = None,
                  checkpoint: str | PathLike | CheckpointStore | None = None) -> GapCounts:
    """Layer ``i``'s pooled gap law by the route :func:`layer_route` chose.

    ``executor`` and ``checkpoint`` (as for :func:`layer_pooled_gap_law`)
    belong to the Pfaffian routes, the ones over primes; the DP refuses them.

    Examples
    --------
    >>> layer_gap_law(7, 7, "floor") == layer_gap_law(7, 7, "ideals")
    True
    >>> layer_gap_law(7, 4, "layers") == layer_gap_law(7, 4, "ideals")
    True
    """
    N = check_layers(N, maximum=MAX_FLOOR_N)
    i = check_int(i, "i", 2, N)
    if route == "ideals":
        if executor is not None or checkpoint is not None:
            raise ArgumentError("executor= and checkpoint= belong to the Pfaffian routes over primes, not to the DP")
        return pool_gaps(layer_gap_counts(N, i, progress))
    if route == "floor" and i == N:
        return floor_pooled_gap_law(N, progress=progress, executor=executor, checkpoint=checkpoint)
    if route == "layers" and i < N:
        return layer_pooled_gap_law(N, i, progress=progress, executor=executor, checkpoint=checkpoint)
    raise ArgumentError(f"route={route!r} is out of range for layer {i}: it must be 'ideals', 'floor' for the "
                        f"floor (layer {N}) or 'layers' for a layer above it")


def floor_contact_gap_law(N: int, layer: GapCounts | None = None, **options: Any) -> GapCounts:
    """Exact pooled rank-gap law of the ``2(N - 1)`` contact forces between layer ``N - 1`` and the floor.

    These contacts (``F5``, ``F6`` of the grains of layer ``N - 1``, (3.4))
    are the spacings between a floor partial sum ``v_j`` and its two
    neighbours ``u_(j-1) < v_j < u_j`` of layer ``N - 1``.  ``v_j`` is
    covered by those two cells only, so given the rest of the tableau its
    rank is uniform among the ``g - 1`` ranks strictly between theirs (``g``
    the rank gap of ``W_(N-1,j) = u_j - u_(j-1)``): the contact gap is uniform
    on ``1..g-1`` (continuously, ``F = q W`` with ``q`` uniform and
    independent).  Hence ``counts[g'] = 2 sum_(g > g') x_g/(g - 1)`` from
    layer ``N - 1``'s pooled law ``x``, exact integers (checked).  Equal to
    the DP's contact laws pooled (tested).

    Parameters
    ----------
    N : int
        Number of layers, ``3..128``.
    layer : GapCounts, optional
        Layer ``N - 1``'s pooled gap law, if already computed; else by :func:`layer_route`'s route.
    **options
        ``executor``, ``checkpoint``, ``progress`` for :func:`layer_gap_law` (the Pfaffian route).

    Returns
    -------
    GapCounts
        ``total = 2 (N - 1) count(N)``.

    Examples
    --------
    >>> law = floor_contact_gap_law(8)
    >>> from fractions import Fraction  # P(0) of f = F/<F>: d P(gap 1) <F>, <F> = 1/(2(N - 1))
    >>> Fraction(law.d * law.counts[1], law.total) / (2 * 7)
    Fraction(4143, 4199)
    """
    N = check_layers(N, maximum=MAX_FLOOR_N)
    if N < 3:
        raise ArgumentError(f"N={N} is out of range: the contacts above the floor need N >= 3 (N in 3..{MAX_FLOOR_N})")
    d = dimension(N)
    if layer is None:
        route, _plan = layer_route(N, N - 1)
        layer = layer_gap_law(N, N - 1, route, **options)
    if layer.d != d or layer.total != (N - 1) * count(N) or len(layer.counts) != d + 2:
        raise ArgumentError(f"layer is not layer N-1's pooled gap law for N={N} (d={d}, total (N-1) count(N))")
    counts = [0] * (d + 2)
    acc = 0
    for g in range(d + 1, 1, -1):
        q, r = divmod(layer.counts[g], g - 1)
        if r:
            raise ArithmeticError(f"layer N-1's gap count at g={g} is not divisible by g - 1: not a layer law")
        acc += q
        counts[g - 1] = 2 * acc
    return GapCounts(tuple(counts), 2 * layer.total, d)


def ensemble_route(N: int, memory_bytes: int | None = None, *,
                   executor: Executor | None = None) -> tuple[str, Plan]:
    """The faster exact route to the ensemble ``P(f)`` (every grain of layers ``2..N``): ``"pfaffians"`` or ``"ideals"``.

    The order-ideal DP (``N - 1`` passes, ``N <= 30``) against every layer's
    pooled law by de Bruijn Pfaffians (:func:`layer_pooled_gap_law` and the
    floor's, ``N <= 128``); the faster runnable plan wins.

    Examples
    --------
    >>> ensemble_route(12)[0], ensemble_route(40)[0]
    ('ideals', 'pfaffians')
    """
    N = check_layers(N, maximum=MAX_FLOOR_N)
    ideals = distribution_plan(N, "ensemble", memory_bytes)
    plans = ([layer_cost(N, i, False, memory_bytes, executor=executor) for i in range(2, N)]
             + [floor_cost(N, False, memory_bytes, executor=executor)])
    pfaffians = combine(f"exact ensemble P(f) N={N} (de Bruijn Pfaffians, every layer's pooled law)", plans, "prime")
    pfaffians = replace(pfaffians, seconds=pfaffians.seconds - (len(plans) - 1) * STARTUP_SECONDS)  # one process
    if ideals.runnable and (not pfaffians.runnable or ideals.seconds <= pfaffians.seconds):
        return "ideals", ideals
    return "pfaffians", pfaffians


def ensemble_pieces(N: int, route: str, progress: Callable[..., Any] | None = None, *,
                    executor: Executor | None = None, checkpoint: str | PathLike | None = None) -> list[Piece]:
    """The exact ensemble ``P(f)``, ``f = i W_ij`` over every grain of layers ``2..N``, by :func:`ensemble_route`'s route.

    As :func:`forcenet.exact.triangle.distribution.triangle_force_density`
    (equal, tested), which is the ``"ideals"`` route; ``"pfaffians"`` takes
    every layer's pooled gap law from de Bruijn Pfaffians instead
    (``executor``, ``checkpoint``: a directory, one request per layer).

    Examples
    --------
    >>> ensemble_pieces(5, "pfaffians") == ensemble_pieces(5, "ideals")
    True
    """
    N = check_layers(N, maximum=MAX_FLOOR_N)
    if route == "ideals":
        if executor is not None or checkpoint is not None:
            raise ArgumentError("executor= and checkpoint= belong to the Pfaffian routes over primes, not to the DP")
        return triangle_force_density(N, progress=progress)
    if route != "pfaffians":
        raise ArgumentError(f"route={route!r} is out of range for the ensemble: it must be 'ideals' or 'pfaffians'")
    grains = N * (N + 1) // 2 - 1
    terms = []
    for i in range(2, N + 1):
        gaps = layer_gap_law(N, i, "floor" if i == N else "layers", progress, executor=executor, checkpoint=checkpoint)
        (piece,), _cdf = layer_pieces_from_gaps(gaps, i)
        terms.append((piece.hi, piece.poly * Fraction(i, grains)))
    return sum_pieces(terms, piece.poly.gens[0])


def single_grain_route(N: int, grain: tuple[int, int], memory_bytes: int | None = None, *,
                       executor: Executor | None = None) -> tuple[str, Plan]:
    """The faster exact route to one grain's gap law, and its plan: ``"pfaffian"``, ``"floor"``, ``"layers"`` or
    ``"ideals"``.

    Every grain has the order-ideal DP
    (:func:`forcenet.exact.triangle.gaps.grain_gap_counts`, ``N <= 30``) and a
    polynomial route, ``N <= 128``: the Pfaffian one of the lattice
    directions ``(i, 1)``, ``(i, i)`` (:func:`.free_fermion.fluctuations.grain_gap_law`, one-time), de
    Bruijn Pfaffians with a fugacity for the floor loads ``(N, j)``
    (:func:`.de_bruijn.floor.floor_gap_laws`) and for the other interior loads
    (:func:`.de_bruijn.layers.layer_gap_laws`, every load of the layer at once; the gap
    is a two-time quantity, ``notes/fluctuations.md`` Sec. 3, so these are
    two-dimensional grids).  The faster runnable plan wins (the laws are
    equal, tested).

    Parameters
    ----------
    N : int
        Number of layers, ``2..128``.
    grain : (int, int)
        ``(i, j)``, ``2 <= i <= N``, ``1 <= j <= i``.
    memory_bytes : int, optional
        Memory available to the run.
    executor : concurrent.futures.Executor or Dask Client, optional
        Where the Pfaffians' per-prime tasks would run: their plans count its
        workers (the DP runs in this process).

    Returns
    -------
    (str, Plan)
        The route's name and its plan (refused, with the reason of every
        route, when none can run).

    Raises
    ------
    ArgumentError
        If ``N`` or the grain is out of range.

    Examples
    --------
    >>> single_grain_route(64, (64, 1))[0], single_grain_route(12, (12, 6))[0]
    ('pfaffian', 'ideals')
    >>> single_grain_route(40, (39, 20))[0]
    'layers'
    """
    N = check_layers(N, maximum=MAX_LAW_N)
    return grain_route(N, check_grain(N, grain), memory_bytes, executor=executor)


def grain_route(N: int, grain: tuple[int, int], memory_bytes: int | None = None, *,
                executor: Executor | None = None) -> tuple[str, Plan]:
    """:func:`single_grain_route` of a checked law request's ``N`` and grain (the law's policy asks it), nothing
    checked again.

    Examples
    --------
    >>> grain_route(64, (64, 1)) == single_grain_route(64, (64, 1))
    True
    """
    i, j = grain
    what = f"exact density of W_({i},{j}) N={N}"
    ideals = gap_laws_cost(N, 1, memory_bytes, what=f"{what} (order ideals)")
    if i == N and 1 < j < N:  # a floor load: the DP or de Bruijn Pfaffians with a fugacity (every floor load at once)
        floor = replace(floor_cost(N, True, memory_bytes, executor=executor), what=f"{what} (de Bruijn Pfaffians, every floor load)")
        if ideals.runnable and (not floor.runnable or ideals.seconds <= floor.seconds):
            return "ideals", ideals
        return "floor", floor
    if i == 1:  # W_11 = 1
        return "ideals", ideals
    if j not in (1, i):  # an interior load above the floor: the DP or the layer's de Bruijn Pfaffians
        layers = replace(layer_cost(N, i, True, memory_bytes, executor=executor), what=f"{what} (de Bruijn Pfaffians, every load of layer {i})")
        if ideals.runnable and (not layers.runnable or ideals.seconds <= layers.seconds):
            return "ideals", ideals
        return "layers", layers
    pfaffian = replace(lattice_gap_laws_cost(N, memory_bytes, layers=1, executor=executor), what=f"{what} (Pfaffians)")
    if ideals.runnable and (not pfaffian.runnable or ideals.seconds <= pfaffian.seconds):
        return "ideals", ideals
    return "pfaffian", pfaffian


def single_grain_gap_law(N: int, grain: tuple[int, int], route: str, progress: Callable[[int], object] | None = None,
                         **options: Any) -> GapCounts:
    """One grain's gap law by the route :func:`single_grain_route` chose.

    Parameters
    ----------
    N : int
        Number of layers.
    grain : (int, int)
        The grain ``(i, j)``.
    route : {"pfaffian", "floor", "layers", "ideals"}
        The route.
    progress : callable, optional
        ``progress(k)`` with the route's plan's ticks.
    **options
        ``executor``, ``checkpoint`` of :func:`.de_bruijn.floor.floor_gap_laws` (the de Bruijn routes only).

    Returns
    -------
    GapCounts

    Raises
    ------
    ArgumentError
        If the route does not reach the grain.

    Examples
    --------
    >>> single_grain_gap_law(6, (6, 1), "pfaffian") == single_grain_gap_law(6, (6, 1), "ideals")
    True
    """
    if route == "floor" and grain[0] == N:
        return floor_gap_laws(N, progress=progress, **options)[grain[1]]
    if route == "layers" and grain[0] < N:
        return layer_gap_laws(N, grain[0], progress=progress, **options)[grain[1]]
    if options:
        raise ArgumentError(f"{', '.join(sorted(options))}: only the de Bruijn routes (route='floor', 'layers') take "
                            f"them")
    if route == "ideals":
        return grain_gap_counts(N, grain, progress)
    if route == "pfaffian":
        return grain_gap_law(N, grain, progress=progress)
    raise ArgumentError(f"route={route!r} is not a route to grain {tuple(grain)!r}: it must be 'pfaffian', 'ideals', "
                        f"'floor' for a floor load (N, j) or 'layers' for a load above the floor")
