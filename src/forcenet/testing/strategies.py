"""Hypothesis strategies for the force network ensemble: sizes, grains, networks, scenes, tori.

Needs hypothesis (``pip install 'forcenet[testing]'``). Every random choice
is drawn from hypothesis (a network's sampler seed too), so failures
reproduce and shrink: towards small triangles, the grain ``(1, 1)``, seed 0,
small packings, the empty chicken-wire configuration.

* :func:`layers`, :func:`grains`, :func:`layers_and_grains` — the triangle;
* :func:`force_networks` — exact uniform force networks ``W`` of the
  triangle through :class:`forcenet.numeric.triangle.exact_sampler.ExactSampler`;
* :func:`packing_scenes` — :class:`forcenet.numeric.packing.Scene` with
  ``(N, P, j0, F, pv, mg, ph)`` restricted to scenes that have a force
  network with every force positive (a linear program decides), or to the
  fully mobilized scenes whose exact means :func:`forcenet.testing.exact_mean_W` computes;
* :func:`torus_sizes`, :func:`chicken_wire_configurations` — chicken-wire
  configurations on small tori, any of them (picked among all, enumerated).

Examples
--------
>>> from hypothesis import find
>>> find(layers(), lambda N: N >= 5)                      # shrinks to the smallest
5
>>> find(layers_and_grains(), lambda g: g[1][0] > 3)
(4, (4, 1))
>>> find(force_networks(4), lambda W: W[3, 0] > 0.5).shape
(4, 4)
"""

from __future__ import annotations

from functools import lru_cache
from typing import Any

from forcenet.core.errors import ArgumentError

try:
    from hypothesis import assume
    from hypothesis import strategies as st
except ImportError as exc:  # pragma: no cover - hypothesis is in the testing extra
    raise ImportError("forcenet.testing.strategies needs hypothesis: pip install 'forcenet[testing]'") from exc

from forcenet.core.validation import check_int, check_real
from forcenet.exact.chicken_wire.model import torus_configurations
from forcenet.numeric.chicken_wire.monte_carlo import ChickenWire
from forcenet.numeric.packing import Scene, maximin_network
from forcenet.numeric.triangle.exact_sampler import ExactSampler

__all__ = [
    "layers",
    "grains",
    "layers_and_grains",
    "seeds",
    "force_networks",
    "packing_scenes",
    "torus_sizes",
    "chicken_wire_configurations",
]


def _strategy(value: int | st.SearchStrategy[int] | None, name: str,
              default: st.SearchStrategy[int]) -> st.SearchStrategy[int]:
    """An int, a strategy or None (the default strategy)."""
    if value is None:
        return default
    if isinstance(value, st.SearchStrategy):
        return value
    return st.just(check_int(value, name, 2))


def layers(min_value: int = 2, max_value: int = 10) -> st.SearchStrategy[int]:
    """Numbers of layers ``N`` of the triangle, ``min_value..max_value`` (shrinks to ``min_value``).

    Parameters
    ----------
    min_value : int, default 2
        The smallest ``N`` (``>= 2``).
    max_value : int, default 10
        The largest ``N`` (``>= min_value``).

    Returns
    -------
    hypothesis.strategies.SearchStrategy of int
        The numbers of layers.

    Examples
    --------
    >>> from hypothesis import find
    >>> find(layers(3, 8), lambda N: N % 2 == 0)
    4
    >>> layers(1)
    Traceback (most recent call last):
    ...
    forcenet.core.errors.ArgumentError: min_value=1 is out of range: min_value must be an integer >= 2
    """
    lo = check_int(min_value, "min_value", 2)
    return st.integers(lo, check_int(max_value, "max_value", lo))


def grains(N: int) -> st.SearchStrategy[tuple[int, int]]:
    """Grains ``(i, j)``, ``1 <= j <= i <= N``, of the ``N``-layer triangle (shrinks to ``(1, 1)``).

    Parameters
    ----------
    N : int
        Layers of the triangle (``>= 1``).

    Returns
    -------
    hypothesis.strategies.SearchStrategy of (int, int)
        Grains ``(i, j)``, layer first (the indexing of Sec. 4.2).

    Examples
    --------
    >>> from hypothesis import find
    >>> find(grains(6), lambda g: g[0] == 6 and g[1] > 2)
    (6, 3)
    """
    N = check_int(N, "N", 1)
    return st.integers(1, N).flatmap(lambda i: st.tuples(st.just(i), st.integers(1, i)))


def layers_and_grains(min_layers: int = 2, max_layers: int = 10) -> st.SearchStrategy[tuple[int, tuple[int, int]]]:
    """``(N, (i, j))``: a triangle and one of its grains.

    Parameters
    ----------
    min_layers, max_layers : int
        The range of ``N``, as in :func:`layers`.

    Returns
    -------
    hypothesis.strategies.SearchStrategy of (int, (int, int))
        ``N`` drawn by :func:`layers`, then a grain by :func:`grains`.

    Examples
    --------
    >>> from hypothesis import find
    >>> find(layers_and_grains(4, 6), lambda g: g[1][1] == 2)
    (4, (2, 2))
    """
    return layers(min_layers, max_layers).flatmap(lambda N: st.tuples(st.just(N), grains(N)))


def seeds() -> st.SearchStrategy[int]:
    """Seeds for numpy generators, drawn by hypothesis (so that failures reproduce and shrink).

    Returns
    -------
    hypothesis.strategies.SearchStrategy of int
        Integers in ``0..2**32 - 1`` (shrinking to 0).

    Examples
    --------
    >>> from hypothesis import find
    >>> find(seeds(), lambda s: s > 1000)
    1001
    """
    return st.integers(0, 2**32 - 1)


def force_networks(N: int | st.SearchStrategy[int] | None = None, size: int | None = None) -> st.SearchStrategy[Any]:
    """Exact uniform force networks of the fully mobilized triangle.

    Parameters
    ----------
    N : int or strategy, optional
        Layers, or a strategy of them (default ``layers(2, 8)``).
    size : int, optional
        ``None``: one network, ``W`` of shape ``(N, N)`` (``W[i-1, j-1] =
        W_{i,j}``, zero above the diagonal); an integer: ``size`` independent
        networks, shape ``(size, N, N)``.

    Returns
    -------
    hypothesis.strategies.SearchStrategy of numpy.ndarray
        Networks drawn by :class:`~forcenet.numeric.triangle.exact_sampler.ExactSampler`,
        seeded from hypothesis.

    Examples
    --------
    >>> from hypothesis import find
    >>> find(force_networks(layers(3, 6), size=10), lambda W: W.shape[1] > 4).shape
    (10, 5, 5)
    """

    count = None if size is None else check_int(size, "size", 1)

    def draw(pair: tuple[int, int]) -> Any:
        n, seed = pair
        W = ExactSampler(n, seed=seed).sample_W(1 if count is None else count)
        return W[0] if count is None else W

    return st.tuples(_strategy(N, "N", layers(2, 8)), seeds()).map(draw)


_LOADS = {
    "gravity": (False, True),   # pv = 0, mg > 0 (Sec. 3.3.2)
    "top": (True, False),       # pv > 0, mg = 0 (the isotropic family)
    "both": (True, True),
}


def packing_scenes(*, min_layers: int = 2, max_layers: int = 5, min_width: int = 2, max_width: int = 7,
                   side_pressure: bool | None = None, exact_means: bool = False,
                   min_slack: float = 1e-3) -> st.SearchStrategy[Any]:
    """Scenes of the N x P packing (Sec. 3.3) that have a force network, every force positive.

    Loads are multiples of 1/4 (exact in binary): ``F`` in ``0..20``, ``pv``
    and ``mg`` in ``0..5`` (not both zero), ``j0`` any column. With a finite
    side pressure ``ph`` (a fraction ``0.01..2`` of the total load) the scene
    is kept when the maximin linear program
    (:func:`forcenet.numeric.packing.maximin_network`) finds a network whose
    smallest force exceeds ``min_slack`` times the total load; most draws
    pass.

    Parameters
    ----------
    min_layers, max_layers, min_width, max_width : int
        Ranges of ``N`` and ``P`` (both ``>= 2``).
    side_pressure : bool, optional
        ``True``: finite ``ph`` only; ``False``: the fully mobilized limit
        ``ph=None`` only (every q allowed); ``None``: either.
    exact_means : bool
        Only scenes whose exact ``<W>`` :func:`forcenet.testing.exact_mean_W`
        computes in under a second: fully mobilized, ``N <= 3``,
        ``(N-1)(P-1) <= 8``.
    min_slack : float
        Required smallest force of the maximin network, relative to the total load.

    Returns
    -------
    hypothesis.strategies.SearchStrategy of Scene
        Scenes (:class:`forcenet.numeric.packing.Scene`).

    Examples
    --------
    >>> from hypothesis import find
    >>> scene = find(packing_scenes(side_pressure=True), lambda s: s.N >= 3)
    >>> scene.N, scene.ph is not None
    (3, True)
    """

    lo_n = check_int(min_layers, "min_layers", 2)
    hi_n = check_int(max_layers, "max_layers", lo_n)
    lo_p = check_int(min_width, "min_width", 2)
    hi_p = check_int(max_width, "max_width", lo_p)
    min_slack = check_real(min_slack, "min_slack", 0)
    if exact_means:
        if side_pressure:
            raise ArgumentError("exact_means=True needs the fully mobilized scenes: side_pressure must be False or None")
        side_pressure = False
        hi_n = min(hi_n, 3, 1 + 8 // (lo_p - 1))  # every N left has a P >= min_width with (N-1)(P-1) <= 8
        if lo_n > hi_n:
            raise ArgumentError(f"exact_means=True: no scene with N in {lo_n}..{max_layers}, P >= {lo_p} has "
                             "N <= 3 and (N-1)(P-1) <= 8")
    quarter = st.integers(1, 20).map(lambda k: k / 4)

    @st.composite
    def scene(draw: st.DrawFn) -> Any:
        N = draw(st.integers(lo_n, hi_n))
        top = hi_p if not exact_means else min(hi_p, 8 // (N - 1) + 1)
        P = draw(st.integers(lo_p, top))
        j0 = draw(st.integers(1, P))
        F = draw(st.integers(0, 40)) / 2
        has_pv, has_mg = _LOADS[draw(st.sampled_from(list(_LOADS)))]
        pv = draw(quarter) if has_pv else 0.0
        mg = draw(quarter) if has_mg else 0.0
        finite = draw(st.booleans()) if side_pressure is None else side_pressure
        if not finite:
            return Scene(N=N, P=P, F=F, j0=j0, pv=pv, mg=mg)
        load = F + pv * P + mg * N * P
        ph = load * draw(st.integers(1, 200)) / 100
        s = Scene(N=N, P=P, F=F, j0=j0, pv=pv, mg=mg, ph=ph)
        assume(maximin_network(s)[1] > min_slack * load)
        return s

    return scene()


def torus_sizes(max_sites: int = 12, min_L: int = 2, max_L: int | None = None) -> st.SearchStrategy[tuple[int, int]]:
    """``(L, M)`` with ``min_L <= L <= max_L``, ``M >= 1``, ``L M <= max_sites`` (at most 20: enumeration).

    Parameters
    ----------
    max_sites : int, default 12
        The largest ``L M`` (``2..20``).
    min_L : int, default 2
        The fewest sites per row.
    max_L : int, optional
        The most sites per row (default ``max_sites``).

    Returns
    -------
    hypothesis.strategies.SearchStrategy of (int, int)
        Tori ``(L, M)`` of the chicken-wire model (Sec. 7.4.1).

    Examples
    --------
    >>> from hypothesis import find
    >>> find(torus_sizes(max_L=4), lambda s: s[0] * s[1] >= 9)
    (3, 3)
    """
    max_sites = check_int(max_sites, "max_sites", 2, 20)
    min_L = check_int(min_L, "min_L", 2, max_sites)
    max_L = max_sites if max_L is None else check_int(max_L, "max_L", min_L, max_sites)
    return st.integers(min_L, max_L).flatmap(lambda L: st.tuples(st.just(L), st.integers(1, max_sites // L)))


@lru_cache(maxsize=64)
def _configurations(L: int, M: int) -> tuple:
    return tuple(torus_configurations(L, M))


def chicken_wire_configurations(L: int | None = None, M: int | None = None, *, max_sites: int = 12,
                                max_L: int | None = None) -> st.SearchStrategy[Any]:
    """Chicken-wire configurations on small tori, any of them (Sec. 7.4.1).

    Parameters
    ----------
    L, M : int, optional
        The torus (``L >= 2`` sites per row, ``M >= 1`` rows); default any
        size from :func:`torus_sizes` with ``L M <= max_sites`` and ``L <= max_L``.
    max_sites : int, default 12
        With ``L`` and ``M`` not given: the largest ``L M``.
    max_L : int, optional
        With ``L`` and ``M`` not given: the most sites per row.

    Returns
    -------
    hypothesis.strategies.SearchStrategy of ChickenWire
        Configurations (:class:`forcenet.numeric.chicken_wire.monte_carlo.ChickenWire`).
        The configurations of a torus are enumerated once
        (:func:`forcenet.exact.chicken_wire.model.torus_configurations`) and one
        is picked by index; index 0 is the empty configuration.

    Examples
    --------
    >>> from hypothesis import find
    >>> c = find(chicken_wire_configurations(3, 3), lambda c: any(c.occ.values()))
    >>> sorted(v for v in c.occ.values() if v), c.invalid_sites()    # the smallest: one straight line
    ([frozenset({0, 180}), frozenset({0, 180}), frozenset({0, 180})], [])
    """

    if L is None and M is None:
        sizes = torus_sizes(max_sites, max_L=max_L)
    else:
        if L is None or M is None:
            raise ArgumentError("give both L and M, or neither")
        sizes = st.just((check_int(L, "L", 2), check_int(M, "M", 1)))
        if L * M > 20:
            raise ArgumentError(f"L*M={L * M} is out of range: enumeration is for at most 20 sites")

    def pick(size: tuple[int, int]) -> st.SearchStrategy[Any]:
        configs = _configurations(*size)
        return st.integers(0, len(configs) - 1).map(lambda k: ChickenWire(size[0], size[1], configs[k]))

    return sizes.flatmap(pick)
