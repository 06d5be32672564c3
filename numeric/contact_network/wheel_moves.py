"""Uniform samples of the sheared hexagonal torus' ensemble by wheel moves (thesis Sec. 8.2, after Vlugt).

The ensemble under shear (:mod:`forcenet.exact.contact_network.shear_stress`)
is the uniform measure on the forces ``f >= 0`` of the periodic hexagonal
packing (:func:`forcenet.exact.contact_network.geometries.hexagonal_torus`)
balancing every grain with the imposed stress ``sigma_xx = sigma_yy = P``,
``sigma_xy = tau P`` (Eq. (8.1)).  The thesis (Sec. 8.2) samples it by
*wheel moves*: around a grain ``g``, the six bonds between its neighbours
(the rim) change by ``+d`` and its six own bonds (the spokes) by ``-d``.
Each neighbour ``k`` at unit vector ``n_k`` from ``g`` then gains
``d (2 n_k - n_(k+1) - n_(k-1)) - d n_k = 0`` (``n_(k+1) + n_(k-1) = n_k`` on
the hexagon) and ``g`` gains ``-d sum_k n_k = 0``: balance holds; each bond
direction appears twice on the rim and twice among the spokes, so
``sum f n n^T`` is unchanged: the stress holds.

The move here is the heat-bath (Gibbs) step along a wheel: ``d`` uniform on
the chord ``[-min rim, min spokes]`` of the polytope on that line, which
leaves the uniform measure invariant (as hit-and-run's steps do,
:mod:`.hit_and_run`); the ``L^2`` wheels span the ``L^2 - 1`` dimensions of
the polytope (their sum is zero; tested against the kernel's dimension), so
the chain is irreducible.  A sweep is ``L^2`` moves at random grains, ``O(1)``
each -- against hit-and-run's ``O(d * contacts)`` per move, which is why the
thesis's large packings are in reach.  The start is the thesis's: every bond
direction with one force, ``p (1, 1 + sqrt(3) tau, 1 - sqrt(3) tau)``
(:func:`~forcenet.exact.contact_network.shear_stress.uniform_network`).

Examples
--------
>>> walk = WheelMoves(6, 0.2)
>>> forces = walk.run(20, seed=1)
>>> forces.shape, bool(abs(forces.mean() - 1.0) < 1e-12)
((20, 108), True)
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np

from forcenet.core.errors import ArgumentError
from forcenet.core.validation import check_int

from ..jit import chunks, first_chunk, njit

__all__ = ["WheelMoves", "wheels", "wheel_sweeps", "SECONDS_PER_MOVE", "YIELD_HEXAGONAL"]

SECONDS_PER_MOVE = 6e-8  # one compiled wheel move (12 bonds read, 12 written), measured on the 2-core machine
YIELD_HEXAGONAL = 1 / math.sqrt(3)  # the exact yield stress of the hexagonal lattice (shear_stress, notes/shear.md)


def wheels(L: int) -> tuple[np.ndarray, np.ndarray]:
    """The spokes and rims of the ``L^2`` wheels of the ``L x L`` torus, in its contact numbering.

    Contact ``3 g + k`` is the ``k``-th bond (``side``, ``up``, ``upleft``) of grain ``g = (j - 1) L + (i - 1)``
    (:func:`~forcenet.exact.contact_network.geometries.hexagonal_torus`).

    Parameters
    ----------
    L : int
        The torus' period, ``>= 3``.

    Returns
    -------
    (numpy.ndarray, numpy.ndarray)
        ``spokes[g]`` and ``rim[g]``, six contacts each.

    Examples
    --------
    >>> spokes, rim = wheels(3)
    >>> spokes[0].tolist(), rim[0].tolist()
    ([0, 1, 2, 6, 19, 23], [5, 15, 7, 20, 18, 22])
    """
    L = check_int(L, "L", 3)

    def grain(i: int, j: int) -> int:
        return (j % L) * L + (i % L)

    spokes = np.empty((L * L, 6), dtype=np.int64)
    rim = np.empty((L * L, 6), dtype=np.int64)
    for j in range(L):
        for i in range(L):
            g = grain(i, j)
            east, north_west = grain(i + 1, j), grain(i - 1, j + 1)  # the rim from east round to south-east
            west, south_west, south_east = grain(i - 1, j), grain(i, j - 1), grain(i + 1, j - 1)
            spokes[g] = [3 * g, 3 * g + 1, 3 * g + 2, 3 * west, 3 * south_west + 1, 3 * south_east + 2]
            rim[g] = [3 * east + 2, 3 * north_west, 3 * west + 1, 3 * south_west + 2, 3 * south_west,
                      3 * south_east + 1]
    return spokes, rim


@njit(cache=True)
def wheel_sweeps(f: np.ndarray, spokes: np.ndarray, rim: np.ndarray, moves: int, u: np.ndarray) -> None:
    """``moves`` heat-bath wheel moves in place; ``u`` holds ``2 moves`` uniform numbers (grain, then chord)."""
    grains = spokes.shape[0]
    for m in range(moves):
        g = min(int(u[2 * m] * grains), grains - 1)
        low = f[rim[g, 0]]
        high = f[spokes[g, 0]]
        for k in range(1, 6):
            low = min(low, f[rim[g, k]])
            high = min(high, f[spokes[g, k]])
        d = -low + u[2 * m + 1] * (low + high)
        for k in range(6):
            f[rim[g, k]] += d
            f[spokes[g, k]] -= d


class WheelMoves:
    """The wheel-move chain on the ``L x L`` hexagonal torus under shear ``tau`` (module docstring).

    Parameters
    ----------
    L : int
        The torus' period, ``>= 3``.
    tau : float
        The shear stress ``sigma_xy / sigma_xx``, ``|tau| < 1/sqrt(3)`` (the yield stress: there the polytope is
        flat).
    pressure : float
        The mean force (default 1).

    Examples
    --------
    >>> WheelMoves(4, 0.6)
    Traceback (most recent call last):
    ...
    forcenet.core.errors.ArgumentError: tau=0.6 is beyond the yield stress of the hexagonal packing, tau_max = 1/sqrt(3) = 0.57735: give |tau| < 0.57735
    """

    def __init__(self, L: int, tau: float, pressure: float = 1.0) -> None:
        self.L = check_int(L, "L", 3)
        tau = float(tau)
        if not abs(tau) < YIELD_HEXAGONAL:
            raise ArgumentError(f"tau={tau!r} is beyond the yield stress of the hexagonal packing, tau_max = "
                                f"1/sqrt(3) = {YIELD_HEXAGONAL:.5f}: give |tau| < {YIELD_HEXAGONAL:.5f}")
        if not (math.isfinite(pressure) and pressure > 0):
            raise ArgumentError(f"pressure={pressure!r} is out of range: the mean force must be > 0")
        self.tau, self.pressure = tau, float(pressure)
        self.spokes, self.rim = wheels(self.L)
        root3 = math.sqrt(3.0)
        self.start = np.tile([pressure, pressure * (1 + root3 * tau), pressure * (1 - root3 * tau)], self.L ** 2)

    def sweep_seconds(self) -> float:
        """Estimated seconds per sweep (``L^2`` moves)."""
        return SECONDS_PER_MOVE * self.L ** 2

    def run(self, samples: int, seed: int | None = None, burn_in: int | None = None, thin: int = 1,
            progress: Callable[..., Any] | None = None, state: np.ndarray | None = None) -> np.ndarray:
        """``samples`` networks, ``thin`` sweeps apart, after ``burn_in`` sweeps (default ``max(100, L^2)``).

        Parameters
        ----------
        samples : int
            Recorded networks.
        seed : int, optional
            Seed of ``numpy.random.default_rng``.
        burn_in : int, optional
            Sweeps discarded first.
        thin : int
            Sweeps between recorded networks.
        progress : callable, optional
            Called with the networks recorded, per compiled call.
        state : numpy.ndarray, optional
            Where the chain starts (a recorded network: a chain continued); default :attr:`start`.

        Returns
        -------
        numpy.ndarray
            ``(samples, 3 L^2)`` forces, contact ``3 g + k``.

        Examples
        --------
        >>> WheelMoves(3, 0.0).run(2, seed=0, burn_in=0, thin=1).shape
        (2, 27)
        """
        samples = check_int(samples, "samples", 1)
        thin = check_int(thin, "thin", 1)
        rng = np.random.default_rng(seed)
        n = self.L ** 2
        burn = max(100, n) if burn_in is None else check_int(burn_in, "burn_in", 0)
        f = (self.start if state is None else state).astype(np.float64).copy()
        for start, stop in chunks(burn, first_chunk(self.sweep_seconds())):
            wheel_sweeps(f, self.spokes, self.rim, (stop - start) * n, rng.random(2 * (stop - start) * n))
        out = np.empty((samples, f.size))
        for start, stop in chunks(samples, first_chunk(self.sweep_seconds() * thin)):
            for k in range(start, stop):
                wheel_sweeps(f, self.spokes, self.rim, thin * n, rng.random(2 * thin * n))
                out[k] = f
            if progress is not None:
                progress(stop - start)
        return out
