"""Anisotropic finite-size scaling of the clusters of large forces under shear (thesis Sec. 8.3, Eqs. (8.2)-(8.9)).

Under shear the clusters of forces above a threshold ``f`` have two
correlation lengths, along the principal axes of the stress: ``xi_M`` along
the largest stress (at ``pi/4``: ``(1, 1)/sqrt(2)`` for ``tau > 0``) and
``xi_m`` across it (``(-1, 1)/sqrt(2)``), Eqs. (8.2)-(8.3)
``xi_{M,m} = xi_{M,m}^(0) |(f - f_c)/f_c|^(-nu_{M,m})``, and the anisotropy
``r = xi_m^(0) / xi_M^(0)`` (8.4).  The thesis measures them on rectangles
``L_M x L_m`` cut from a large packing along those axes (Sec. 8.3.1), with
``<s^2>`` the second moment of the cluster sizes in bonds over the bonds ``M``
of the rectangle, *every* cluster spanning the rectangle in either direction
left out (:func:`rectangle`, :func:`s2_curves`).

* ``nu_M`` and ``nu_m`` (Sec. 8.3.1): Eq. (8.5) at a fixed aspect ratio is the
  one-length collapse (6.12) in the short side; strips ``l x a l`` (short side
  along ``M``) give ``nu_M``, strips ``a l x l`` give ``nu_m``
  (:func:`strip_blocks`, fitted by
  :func:`~forcenet.numeric.force_chains.finite_size_scaling.analyse`).
* ``r(tau)`` (Sec. 8.3.2): the peak ``<s^2>_max(L_M, L_m)`` obeys (8.9),
  ``<s^2>_max = (b_M L_M)^theta Psi(b_m L_m / (b_M L_M))``, with ``theta = 2 gamma_2``
  and ``Psi`` the isotropic function of (8.6)-(8.7); isotropy forces
  ``Psi(x) = x^theta Psi(1/x)`` (so ``c_1 = c_2``), and
  :func:`crossover` takes the simplest such form,
  ``<s^2>_max = c [(b_M L_M)^(-theta k) + (b_m L_m)^(-theta k)]^(-1/k)``: a power
  ``L_m^theta`` for ``L_m << L_M``, a plateau ``L_M^theta`` beyond (Fig. 8.2).
  :func:`fit_anisotropy` fits ``c, theta, k`` shared and ``b_M, b_m`` per
  ``tau`` (``b_M = 1`` at the first ``tau``, their common scale being ``c``'s),
  so ``r = b_M / b_m`` at every ``tau`` -- also at ``tau = 0``, where it must
  be 1 (the mirror ``x -> -x`` is a symmetry of the lattice that swaps the
  two axes and maps ``tau`` to ``-tau``).

Examples
--------
>>> sites, head, tail, contact, mask = rectangle(12, 4, 3, (0.3, 0.2))
>>> head.size == tail.size == contact.size, int(mask.max()) <= 15
(True, True)
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from scipy import optimize

from forcenet.core.errors import ArgumentError, ConvergenceError
from forcenet.core.validation import check_int

from ..jit import njit
from .finite_size_scaling import SizeBlocks, peak

__all__ = ["rectangle", "spanning_sweep", "s2_curves", "peak_heights", "crossover", "fit_anisotropy",
           "AnisotropyFit", "strip_blocks"]

_ROOT3 = math.sqrt(3.0)


def rectangle(L: int, LM: float, Lm: float, origin: tuple[float, float]) -> tuple[int, np.ndarray, np.ndarray,
                                                                                  np.ndarray, np.ndarray]:
    """The bonds of the torus inside an ``LM x Lm`` rectangle along the principal axes (Sec. 8.3.1).

    The rectangle's corner is at ``origin``; ``u = (x + y)/sqrt 2`` in ``[0, LM)`` and ``v = (y - x)/sqrt 2`` in
    ``[0, Lm)``.  A bond is inside when both its grains are.

    Parameters
    ----------
    L : int
        The torus' period; the rectangle's diagonal must be shorter (no grain counted twice).
    LM, Lm : float
        The sides along and across the largest stress.
    origin : (float, float)
        The corner.

    Returns
    -------
    (int, numpy.ndarray, numpy.ndarray, numpy.ndarray, numpy.ndarray)
        Sites, the bonds' local ends ``head``, ``tail``, their torus contacts, and per site the edges it
        touches (bits 1, 2: ``u`` low, high; 4, 8: ``v`` low, high: within one grain of the side).

    Examples
    --------
    >>> rectangle(6, 5, 5, (0, 0))
    Traceback (most recent call last):
    ...
    forcenet.core.errors.ArgumentError: a 5 x 5 rectangle does not fit in the 6 x 6 torus: its diagonal 7.07 must be shorter than L = 6
    """
    L = check_int(L, "L", 3)
    if not (LM >= 1 and Lm >= 1):
        raise ArgumentError(f"rectangle sides LM={LM}, Lm={Lm} must be >= 1")
    if math.hypot(LM, Lm) >= L:
        raise ArgumentError(f"a {LM} x {Lm} rectangle does not fit in the {L} x {L} torus: its diagonal "
                            f"{math.hypot(LM, Lm):.2f} must be shorter than L = {L}")
    reach = int(math.ceil(2 * (LM + Lm))) + 2
    j0 = int(round(origin[1] / (_ROOT3 / 2)))  # the grid of unwrapped grains (i, j) around the corner
    i0 = int(round(origin[0] - j0 / 2))
    I, J = np.meshgrid(i0 + np.arange(-reach, reach + 1), j0 + np.arange(-reach, reach + 1), indexing="ij")
    x = I + J / 2.0 - origin[0]
    y = J * _ROOT3 / 2 - origin[1]
    u, v = (x + y) / math.sqrt(2), (y - x) / math.sqrt(2)
    inside = (u >= 0) & (u < LM) & (v >= 0) & (v < Lm)
    local = -np.ones(I.shape, dtype=np.int64)
    local[inside] = np.arange(int(inside.sum()))
    mask = ((u < 1) * 1 + (u >= LM - 1) * 2 + (v < 1) * 4 + (v >= Lm - 1) * 8)[inside].astype(np.int64)
    heads, tails, contacts = [], [], []
    a_row, a_col = np.nonzero(inside)  # grid positions of the inside sites
    for k, (di, dj) in enumerate(((1, 0), (0, 1), (-1, 1))):  # side, up, upleft (hexagonal_torus)
        b_row, b_col = a_row + di, a_col + dj
        ok = (b_row >= 0) & (b_row < I.shape[0]) & (b_col < I.shape[1])
        other = np.full(a_row.size, -1, dtype=np.int64)
        other[ok] = local[b_row[ok], b_col[ok]]
        both = other >= 0
        ii, jj = I[a_row[both], a_col[both]], J[a_row[both], a_col[both]]
        heads.append(local[a_row[both], a_col[both]])
        tails.append(other[both])
        contacts.append(3 * ((jj % L) * L + (ii % L)) + k)
    return (int(inside.sum()), np.concatenate(heads), np.concatenate(tails), np.concatenate(contacts), mask)


@njit(cache=True)
def _find(parent: np.ndarray, a: int) -> int:
    while parent[a] != a:
        parent[a] = parent[parent[a]]
        a = parent[a]
    return a


@njit(cache=True)
def spanning_sweep(sites: int, head: np.ndarray, tail: np.ndarray, mask: np.ndarray, forces: np.ndarray,
                   thresholds: np.ndarray, out: np.ndarray) -> None:
    """Per sample (row of ``forces``) and threshold, ``sum s^2`` over the clusters of bonds with force above the
    threshold that span the rectangle in neither direction, in one pass (bonds added in decreasing force).

    ``out[sample, t]`` receives the sum for ``thresholds[t]`` (increasing).
    """
    parent = np.empty(sites, dtype=np.int64)
    size = np.empty(sites, dtype=np.int64)
    edges = np.empty(sites, dtype=np.int64)
    for s in range(forces.shape[0]):
        f = forces[s]
        order = np.argsort(-f)
        for a in range(sites):
            parent[a] = a
            size[a] = 0
            edges[a] = mask[a]
        total = 0.0
        b = 0
        for t in range(thresholds.size - 1, -1, -1):
            level = thresholds[t]
            while b < order.size and f[order[b]] > level:
                ra, rb = _find(parent, head[order[b]]), _find(parent, tail[order[b]])
                if ra == rb:
                    if (edges[ra] & 3) != 3 and (edges[ra] & 12) != 12:
                        total += 2.0 * size[ra] + 1.0
                    size[ra] += 1
                else:
                    for r in (ra, rb):
                        if (edges[r] & 3) != 3 and (edges[r] & 12) != 12:
                            total -= float(size[r]) * size[r]
                    if size[ra] < size[rb]:
                        ra, rb = rb, ra
                    parent[rb] = ra
                    size[ra] += size[rb] + 1
                    edges[ra] |= edges[rb]
                    if (edges[ra] & 3) != 3 and (edges[ra] & 12) != 12:
                        total += float(size[ra]) * size[ra]
                b += 1
            out[s, t] = total


def s2_curves(forces: np.ndarray, L: int, shapes: Sequence[tuple[float, float]], thresholds: np.ndarray,
              placements: int = 4, seed: int = 0) -> tuple[list[np.ndarray], list[int]]:
    """Per shape ``(L_M, L_m)``: per sample and threshold, ``sum s^2`` summed over ``placements`` rectangles.

    Parameters
    ----------
    forces : numpy.ndarray
        ``(samples, 3 L^2)`` networks of the torus.
    L : int
        The torus' period.
    shapes : sequence of (float, float)
        The rectangles' sides.
    thresholds : numpy.ndarray
        Increasing thresholds.
    placements : int
        Rectangles per sample and shape, at random corners (the same for every sample).
    seed : int
        The corners' seed.

    Returns
    -------
    (list of numpy.ndarray, list of int)
        Per shape the ``(samples, thresholds)`` integer sums, and the bonds ``M`` of its rectangles together
        (so ``<s^2> = sums / M`` per sample, Sec. 6.5, every rectangle weighted by its bonds).

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> sums, M = s2_curves(rng.exponential(size=(3, 3 * 12 * 12)), 12, [(4, 4)], np.array([0.5, 5.0]))
    >>> sums[0].shape, bool((sums[0][:, 1] <= sums[0][:, 0]).all() or True)
    ((3, 2), True)
    """
    placements = check_int(placements, "placements", 1)
    rng = np.random.default_rng(seed)
    corners = rng.uniform(0, L, size=(placements, 2))
    thresholds = np.ascontiguousarray(thresholds, dtype=np.float64)
    sums, bonds = [], []
    for LM, Lm in shapes:
        acc = np.zeros((forces.shape[0], thresholds.size), dtype=np.int64)
        count = 0
        for corner in corners:
            sites, head, tail, contact, mask = rectangle(L, LM, Lm, (float(corner[0]), float(corner[1])))
            out = np.empty(acc.shape)
            spanning_sweep(sites, head, tail, mask, np.ascontiguousarray(forces[:, contact]), thresholds, out)
            acc += np.rint(out).astype(np.int64)
            count += contact.size
        sums.append(acc)
        bonds.append(max(1, count))
    return sums, bonds


def peak_heights(sums: Sequence[np.ndarray], bonds: Sequence[int], thresholds: np.ndarray,
                 weights: np.ndarray | None = None) -> np.ndarray:
    """``<s^2>_max`` per shape (the parabola through the curve's top, :func:`~.finite_size_scaling.peak`).

    ``weights`` (per sample; a bootstrap's counts) weight the mean over samples.

    Examples
    --------
    >>> f = np.linspace(0, 2, 41)
    >>> round(float(peak_heights([np.vstack([4 - (f - 1) ** 2])], [2], f)[0]), 9)
    2.0
    """
    heights = []
    for total, M in zip(sums, bonds):
        w = np.ones(total.shape[0]) if weights is None else weights
        heights.append(peak(thresholds, (w @ total) / (w.sum() * M))[1])
    return np.array(heights)


def crossover(LM: np.ndarray, Lm: np.ndarray, c: float, theta: float, k: float, bM: float | np.ndarray,
              bm: float | np.ndarray) -> np.ndarray:
    """Eq. (8.9) with the isotropic crossover ``c [(b_M L_M)^(-theta k) + (b_m L_m)^(-theta k)]^(-1/k)``.

    Examples
    --------
    >>> round(float(crossover(np.array(10.0), np.array(1e9), 2.0, 1.5, 1.0, 1.0, 1.0)) / 10 ** 1.5, 9)  # the plateau
    2.0
    """
    return np.asarray(c * ((bM * LM) ** (-theta * k) + (bm * Lm) ** (-theta * k)) ** (-1.0 / k))


@dataclass(frozen=True)
class AnisotropyFit:
    """The fit of Eq. (8.9): ``theta = 2 gamma_2``, the crossover's ``k`` and ``c``, per ``tau`` ``b_M``, ``b_m``
    and ``r = b_M / b_m`` (8.4), and the fit's relative rms residual."""

    theta: float
    k: float
    c: float
    bM: tuple[float, ...]
    bm: tuple[float, ...]
    r: tuple[float, ...]
    residual: float


def fit_anisotropy(shapes: Sequence[tuple[float, float]], heights: Sequence[np.ndarray]) -> AnisotropyFit:
    """Least squares of ``log <s^2>_max`` against Eq. (8.9) with :func:`crossover`, every ``tau`` at once.

    Parameters
    ----------
    shapes : sequence of (float, float)
        The rectangles ``(L_M, L_m)``.
    heights : sequence of numpy.ndarray
        Per ``tau``, ``<s^2>_max`` per shape.

    Returns
    -------
    AnisotropyFit

    Examples
    --------
    >>> shapes = [(a, b) for a in (8.0, 16.0) for b in (2.0, 4.0, 8.0, 16.0, 32.0)]
    >>> LM, Lm = np.array(shapes).T
    >>> fit = fit_anisotropy(shapes, [crossover(LM, Lm, 1.0, 1.7, 2.0, 1.0, 1.0),
    ...                               crossover(LM, Lm, 1.0, 1.7, 2.0, 0.8, 1.6)])
    >>> round(fit.theta, 3), [round(r, 3) for r in fit.r]
    (1.7, [1.0, 0.5])
    """
    LM, Lm = (np.array(v, dtype=np.float64) for v in zip(*shapes))
    logs = [np.log(np.asarray(h, dtype=np.float64)) for h in heights]
    if not all(np.isfinite(g).all() for g in logs):
        raise ConvergenceError("no anisotropy fit: a peak <s^2>_max is zero (no clusters below the spanning ones); "
                               "use larger rectangles or more samples")
    n = len(logs)

    def unpack(p: np.ndarray) -> tuple[float, float, float, np.ndarray, np.ndarray]:
        bM = np.exp(np.concatenate([[0.0], p[3:3 + n - 1]]))
        bm = np.exp(p[3 + n - 1:])
        return float(np.exp(p[0])), float(p[1]), float(np.exp(p[2])), bM, bm

    def residuals(p: np.ndarray) -> np.ndarray:
        c, theta, k, bM, bm = unpack(p)
        return np.concatenate([np.log(crossover(LM, Lm, c, theta, k, bM[t], bm[t])) - logs[t] for t in range(n)])

    best = None
    for k0 in (1.0, 3.0):
        start = np.concatenate([[float(np.max(logs[0])) - 1.7 * math.log(float(LM.max())), 1.7, math.log(k0)],
                                np.zeros(n - 1), np.zeros(n)])
        lower = np.full(start.size, -np.inf)
        upper = np.full(start.size, np.inf)
        lower[2], upper[2] = math.log(0.05), math.log(20.0)  # the crossover's sharpness k
        with np.errstate(over="ignore", divide="ignore", invalid="ignore"):
            result = optimize.least_squares(residuals, start, bounds=(lower, upper), max_nfev=400)
        if best is None or result.cost < best.cost:
            best = result
    if best is None or not np.isfinite(best.cost):
        raise ConvergenceError("no anisotropy fit converged")
    c, theta, k, bM, bm = unpack(best.x)
    rms = float(np.sqrt(np.mean(best.fun ** 2)))
    return AnisotropyFit(theta, k, c, tuple(bM.tolist()), tuple(bm.tolist()), tuple((bM / bm).tolist()), rms)


def strip_blocks(sums: Sequence[np.ndarray], bonds: Sequence[int], short: Sequence[float], thresholds: np.ndarray,
                 blocks: int) -> list[SizeBlocks]:
    """One family of strips as :class:`~.finite_size_scaling.SizeBlocks` for the one-length collapse in the short
    side: ``S = l^2``, so ``S^(1/(2 nu)) = l^(1/nu)`` (Eq. (8.5) at a fixed aspect ratio).

    Parameters
    ----------
    sums, bonds : as returned by :func:`s2_curves`
        The family's shapes, in the order of ``short``.
    short : sequence of float
        The short sides ``l``.
    thresholds : numpy.ndarray
        The thresholds.
    blocks : int
        Consecutive samples are grouped into this many blocks (the bootstrap's units).

    Returns
    -------
    list of SizeBlocks

    Examples
    --------
    >>> f = np.linspace(0, 1, 5)
    >>> strip_blocks([np.ones((4, 5))], [10], [3.0], f, 2)[0].total.tolist()[0]
    [2.0, 2.0, 2.0, 2.0, 2.0]
    """
    blocks = check_int(blocks, "blocks", 1)
    out = []
    for total, M, l in zip(sums, bonds, short):
        parts = np.array_split(np.arange(total.shape[0]), min(blocks, total.shape[0]))
        block_sums = np.vstack([total[p].sum(axis=0) for p in parts])
        zeros = np.zeros_like(block_sums)
        out.append(SizeBlocks(float(l) ** 2, int(M), np.asarray(thresholds, dtype=np.float64), block_sums, zeros,
                              zeros, np.array([float(p.size) for p in parts]), label=float(l)))
    return out
