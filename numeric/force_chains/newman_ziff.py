"""Clusters of large forces at every threshold in one pass (Newman-Ziff union-find, compiled).

Thesis Sec. 6.5: keep the bonds whose force exceeds a threshold ``f``; a
cluster's size ``s`` is its number of bonds; ``<s^2>(f)`` is the sum of
``s^2`` over the clusters of a sample *leaving out its largest cluster*,
divided by the number ``M`` of bonds of the force network (the thesis's
normalization), averaged over samples.

Rather than one search per threshold (the thesis's depth-first search), the
bonds of a sample are added in decreasing force (Newman and Ziff, Phys. Rev.
E 64, 016706 (2001)) to a union-find forest with path halving, threshold
after threshold: the bonds are grouped by the first threshold they exceed
(a binary search each and a counting sort; the order inside a group does not
matter, so no full sort of the forces is needed), and after each group the
running statistics of the forest are recorded: the sum of ``s^2`` (updated in O(1) per bond: a merge of
clusters ``a`` and ``b`` adds ``(a + b + 1)^2 - a^2 - b^2``), the largest
cluster (sizes only grow, so a running maximum) and, when the bonds carry
their lattice displacement, whether a cluster wraps around the torus (the
offset of every site from its root is kept; a bond closing a loop whose net
displacement is not zero wraps, Newman-Ziff Sec. II.D).  ``O(M log T)``
for the grouping and ``M`` near-constant-time unions per sample.

The lattices (periodic ``L x L``): ``square`` (``M = 2 L^2``, bond
percolation threshold ``p_c = 1/2``), ``triangular`` (``M = 3 L^2``,
``p_c = 2 sin(pi/18)``), ``honeycomb`` (``M = 3 L^2``,
``p_c = 1 - 2 sin(pi/18)``) (Sykes and Essam, J. Math. Phys. 5, 1117 (1964)).

Examples
--------
>>> import numpy as np
>>> lattice = periodic_lattice("square", 4)
>>> lattice.bonds, lattice.sites
(32, 16)
>>> forces = np.linspace(0.0, 1.0, 32)[None, :]       # one sample, distinct forces
>>> stats = sweep_lattice(lattice, forces, np.array([2.0, 0.5, -1.0]))
>>> stats.total[0].tolist(), stats.largest[0].tolist()   # f > 2: none; f > -1: one cluster of 32 bonds
([0, 48, 0], [0, 4, 32])
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from forcenet.core.errors import ArgumentError
from forcenet.core.validation import check_int

from ..jit import njit

__all__ = ["Lattice", "periodic_lattice", "critical_threshold", "SweepStatistics", "sweep_lattice", "sweep_samples",
           "cluster_sizes", "size_distribution", "LATTICES"]

LATTICES = ("square", "triangular", "honeycomb")


@dataclass(frozen=True)
class Lattice:
    """A bond list: ``head``, ``tail`` (site indices) and each bond's displacement ``dx``, ``dy`` from head to
    tail in lattice units (zeros: no wrapping detected), with the number of ``sites``."""

    name: str
    L: int
    sites: int
    head: np.ndarray
    tail: np.ndarray
    dx: np.ndarray
    dy: np.ndarray

    @property
    def bonds(self) -> int:
        return int(self.head.size)


def periodic_lattice(name: str, L: int) -> Lattice:
    """The bonds of a periodic ``L x L`` lattice (``square``, ``triangular`` or ``honeycomb``).

    Parameters
    ----------
    name : str
        The lattice.
    L : int
        Linear size in unit cells (at least 2).

    Returns
    -------
    Lattice
        Bonds with their displacements (wrapping clusters are detected).

    Examples
    --------
    >>> [(periodic_lattice(n, 3).sites, periodic_lattice(n, 3).bonds) for n in LATTICES]
    [(9, 18), (9, 27), (18, 27)]
    """
    L = check_int(L, "L", 2)
    if name not in LATTICES:
        raise ArgumentError(f"lattice={name!r} is out of range: lattice must be one of {', '.join(LATTICES)}")
    grid_x, grid_y = np.meshgrid(np.arange(L), np.arange(L), indexing="xy")
    x, y = grid_x.ravel(), grid_y.ravel()
    cell = x + L * y
    right, up, diag = (x + 1) % L + L * y, x + L * ((y + 1) % L), (x + 1) % L + L * ((y + 1) % L)
    one, zero = np.ones_like(x), np.zeros_like(x)
    if name == "square":
        head, tail = np.concatenate([cell, cell]), np.concatenate([right, up])
        dx, dy = np.concatenate([one, zero]), np.concatenate([zero, one])
        sites = L * L
    elif name == "triangular":  # the square lattice with one diagonal per cell
        head, tail = np.concatenate([cell, cell, cell]), np.concatenate([right, up, diag])
        dx, dy = np.concatenate([one, zero, one]), np.concatenate([zero, one, one])
        sites = L * L
    else:  # honeycomb: sites A = cell, B = L^2 + cell; A(x,y) joins B(x,y), B(x-1,y), B(x,y-1)
        left, down = (x - 1) % L + L * y, x + L * ((y - 1) % L)
        head = np.concatenate([cell, cell, cell])
        tail = L * L + np.concatenate([cell, left, down])
        dx, dy = np.concatenate([zero, -one, zero]), np.concatenate([zero, zero, -one])
        sites = 2 * L * L
    as64 = lambda a: np.ascontiguousarray(a, dtype=np.int64)  # noqa: E731
    return Lattice(name, L, sites, as64(head), as64(tail), as64(dx), as64(dy))


def critical_threshold(name: str) -> float:
    """``f_c = 1 - p_c`` for independent uniform forces in ``[0, 1]`` (a bond is kept with probability ``1 - f``).

    Examples
    --------
    >>> critical_threshold("square"), round(critical_threshold("triangular"), 6)
    (0.5, 0.652704)
    """
    p_c = {"square": 0.5, "triangular": 2 * math.sin(math.pi / 18), "honeycomb": 1 - 2 * math.sin(math.pi / 18)}
    if name not in p_c:
        raise ArgumentError(f"lattice={name!r} is out of range: lattice must be one of {', '.join(LATTICES)}")
    return 1.0 - p_c[name]


@dataclass(frozen=True)
class SweepStatistics:
    """Per sample (rows) and threshold (columns): ``total`` = sum of ``s^2`` over the clusters but the largest,
    ``largest`` = the largest cluster's bonds, ``wraps`` = 1 if a cluster wraps the torus (0 without
    displacements)."""

    total: np.ndarray
    largest: np.ndarray
    wraps: np.ndarray


@njit
def _root(parent: np.ndarray, a: int) -> int:
    while parent[a] != a:  # path halving
        parent[a] = parent[parent[a]]
        a = parent[a]
    return a


@njit
def _root_offset(parent: np.ndarray, ox: np.ndarray, oy: np.ndarray, a: int) -> tuple[int, int, int]:
    """The root of ``a`` and ``a``'s offset from it; the path is compressed, offsets summed (Newman-Ziff II.D)."""
    r = a
    sx = 0
    sy = 0
    while parent[r] != r:
        sx += ox[r]
        sy += oy[r]
        r = parent[r]
    b = a  # second pass: every node on the path points at the root, its offset the remaining sum
    rx = sx
    ry = sy
    while parent[b] != b:
        nxt = parent[b]
        nx = rx - ox[b]
        ny = ry - oy[b]
        parent[b] = r
        ox[b] = rx
        oy[b] = ry
        b = nxt
        rx = nx
        ry = ny
    return r, sx, sy


@njit
def _bucket_order(force: np.ndarray, levels: np.ndarray, bucket: np.ndarray, counts: np.ndarray,
                  order: np.ndarray) -> None:
    """The bonds grouped by the first (decreasing) level they exceed: a counting sort on ``T + 1`` buckets.

    Within a bucket the order does not matter (the statistics are read only at the levels), so no full sort
    of the forces is needed: a binary search per bond and two passes, ``O(M log T)``."""
    T = levels.size
    for k in range(T + 2):
        counts[k] = 0
    for b in range(force.size):
        f = force[b]
        lo = 0
        hi = T  # the first t with levels[t] < f (levels decrease); T if none
        while lo < hi:
            mid = (lo + hi) >> 1
            if levels[mid] < f:
                hi = mid
            else:
                lo = mid + 1
        bucket[b] = lo
        counts[lo + 1] += 1
    for k in range(T + 1):
        counts[k + 1] += counts[k]
    for b in range(force.size):  # counts[k] is now the start of bucket k
        k = bucket[b]
        order[counts[k]] = b
        counts[k] += 1


@njit
def _sweep_one(sites: int, head: np.ndarray, tail: np.ndarray, dx: np.ndarray, dy: np.ndarray, force: np.ndarray,
               levels: np.ndarray, track: bool, parent: np.ndarray, size: np.ndarray, ox: np.ndarray, oy: np.ndarray,
               bucket: np.ndarray, counts: np.ndarray, order: np.ndarray,
               total: np.ndarray, largest: np.ndarray, wraps: np.ndarray) -> None:
    """One sample: bonds added level by level (decreasing); at each level the bonds with ``f > level``."""
    for a in range(sites):
        parent[a] = a
        size[a] = 0
        ox[a] = 0
        oy[a] = 0
    _bucket_order(force, levels, bucket, counts, order)  # after it, counts[t] = the bonds with f > levels[t]
    k = 0
    s2 = 0
    big = 0
    wrapped = 0
    for t in range(levels.size):
        end = counts[t]
        while k < end:
            b = order[k]
            k += 1
            if track:
                ra, ax, ay = _root_offset(parent, ox, oy, head[b])
                rb, bx, by = _root_offset(parent, ox, oy, tail[b])
            else:
                ra = _root(parent, head[b])
                rb = _root(parent, tail[b])
                ax = ay = bx = by = 0
            sa = size[ra]
            if ra == rb:  # a loop: one bond more; it wraps if its net displacement is not zero
                size[ra] = sa + 1
                s2 += 2 * sa + 1
                if track and (ax + dx[b] - bx != 0 or ay + dy[b] - by != 0):
                    wrapped = 1
                if sa + 1 > big:
                    big = sa + 1
                continue
            sb = size[rb]
            if sa < sb:  # union by size (in bonds): the smaller tree under the larger
                ra, rb = rb, ra
                sa, sb = sb, sa
                ax, bx = bx, ax
                ay, by = by, ay
                parent[rb] = ra  # rb (old ra) sits at offset ax_old + d - bx_old from the new root
                if track:
                    ox[rb] = -(bx + dx[b] - ax)
                    oy[rb] = -(by + dy[b] - ay)
            else:
                parent[rb] = ra
                if track:
                    ox[rb] = ax + dx[b] - bx
                    oy[rb] = ay + dy[b] - by
            s = sa + sb + 1
            size[ra] = s
            s2 += s * s - sa * sa - sb * sb
            if s > big:
                big = s
        total[t] = s2 - big * big
        largest[t] = big
        wraps[t] = wrapped


@njit
def _sweep_shared(sites: int, head: np.ndarray, tail: np.ndarray, dx: np.ndarray, dy: np.ndarray, forces: np.ndarray,
                  levels: np.ndarray, track: bool, total: np.ndarray, largest: np.ndarray, wraps: np.ndarray) -> None:
    parent = np.empty(sites, np.int64)
    size = np.empty(sites, np.int64)
    ox = np.empty(sites, np.int64)
    oy = np.empty(sites, np.int64)
    bucket = np.empty(forces.shape[1], np.int64)
    order = np.empty(forces.shape[1], np.int64)
    counts = np.empty(levels.size + 2, np.int64)
    for r in range(forces.shape[0]):
        _sweep_one(sites, head, tail, dx, dy, forces[r], levels, track, parent, size, ox, oy, bucket, counts, order,
                   total[r], largest[r], wraps[r])


@njit
def _sweep_ragged(starts: np.ndarray, sites: np.ndarray, head: np.ndarray, tail: np.ndarray, force: np.ndarray,
                  levels: np.ndarray, total: np.ndarray, largest: np.ndarray, wraps: np.ndarray) -> None:
    n = 1
    for r in range(sites.size):
        n = max(n, sites[r])
    parent = np.empty(n, np.int64)
    size = np.empty(n, np.int64)
    ox = np.zeros(n, np.int64)
    oy = np.zeros(n, np.int64)
    bucket = np.empty(force.size, np.int64)
    order = np.empty(force.size, np.int64)
    counts = np.empty(levels.size + 2, np.int64)
    for r in range(starts.size - 1):
        lo, hi = starts[r], starts[r + 1]
        _sweep_one(sites[r], head[lo:hi], tail[lo:hi], head[lo:hi], head[lo:hi], force[lo:hi], levels, False, parent,
                   size, ox, oy, bucket[lo:hi], counts, order[lo:hi], total[r], largest[r], wraps[r])


def _levels(thresholds: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The thresholds in decreasing order (the pass's) and the permutation back to the caller's order."""
    thresholds = np.asarray(thresholds, dtype=np.float64)
    if thresholds.ndim != 1 or thresholds.size == 0 or not np.all(np.isfinite(thresholds)):
        raise ArgumentError("thresholds must be a non-empty 1-d array of finite numbers")
    order = np.argsort(-thresholds, kind="stable")
    return np.ascontiguousarray(thresholds[order]), np.argsort(order, kind="stable")


def _empty(rows: int, columns: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    return (np.zeros((rows, columns), np.int64), np.zeros((rows, columns), np.int64),
            np.zeros((rows, columns), np.int64))


def sweep_lattice(lattice: Lattice, forces: np.ndarray, thresholds: np.ndarray, *, wrapping: bool = True
                  ) -> SweepStatistics:
    """Every threshold's cluster statistics for samples on one bond list (one pass per sample).

    Parameters
    ----------
    lattice : Lattice
        The bonds (:func:`periodic_lattice`, or any :class:`Lattice`).
    forces : ndarray, shape (K, M)
        One row of bond forces per sample.
    thresholds : ndarray
        The thresholds ``f`` (any order): bonds with force ``> f`` are kept.
    wrapping : bool
        Track the displacements (``wraps``); a little slower.

    Returns
    -------
    SweepStatistics
        Arrays of shape ``(K, len(thresholds))`` in the thresholds' order.

    Examples
    --------
    >>> import numpy as np
    >>> lattice = periodic_lattice("square", 2)       # 4 sites, 8 bonds (L = 2 doubles them)
    >>> s = sweep_lattice(lattice, np.arange(8.0)[None, :], np.array([5.5, 3.5]))
    >>> s.total.tolist(), s.largest.tolist(), s.wraps.tolist()
    ([[1, 4]], [[1, 2]], [[0, 1]])
    """
    forces = np.ascontiguousarray(forces, dtype=np.float64)
    if forces.ndim != 2 or forces.shape[1] != lattice.bonds:
        raise ArgumentError(f"forces must have shape (samples, {lattice.bonds}), got {forces.shape}")
    levels, back = _levels(thresholds)
    total, largest, wraps = _empty(forces.shape[0], levels.size)
    _sweep_shared(lattice.sites, lattice.head, lattice.tail, lattice.dx, lattice.dy, forces, levels, bool(wrapping),
                  total, largest, wraps)
    return SweepStatistics(total[:, back], largest[:, back], wraps[:, back])


def sweep_samples(starts: np.ndarray, sites: np.ndarray, head: np.ndarray, tail: np.ndarray, force: np.ndarray,
                  thresholds: np.ndarray) -> SweepStatistics:
    """Every threshold's cluster statistics for samples each with its own graph (users' data; no wrapping).

    Parameters
    ----------
    starts : ndarray of int, shape (K + 1,)
        Sample ``r``'s bonds are ``starts[r]:starts[r+1]`` of the flat arrays.
    sites : ndarray of int, shape (K,)
        Sample ``r``'s sites are numbered ``0 .. sites[r] - 1``.
    head, tail, force : ndarray
        The bonds' ends and forces, samples one after the other.
    thresholds : ndarray
        The thresholds.

    Returns
    -------
    SweepStatistics
        ``wraps`` is all zeros (no geometry is known).

    Examples
    --------
    >>> import numpy as np
    >>> # a triangle of bonds 0-1-2 and a separate bond 3-4: f = 3, 2, 1, 5
    >>> s = sweep_samples(np.array([0, 4]), np.array([5]), np.array([0, 1, 2, 3]), np.array([1, 2, 0, 4]),
    ...                   np.array([3.0, 2.0, 1.0, 5.0]), np.array([0.5, 2.5]))
    >>> s.total.tolist(), s.largest.tolist()    # f > 0.5: clusters of 3 and 1 bonds; f > 2.5: 1 and 1
    ([[1, 1]], [[3, 1]])
    """
    starts = np.ascontiguousarray(starts, dtype=np.int64)
    sites = np.ascontiguousarray(sites, dtype=np.int64)
    head = np.ascontiguousarray(head, dtype=np.int64)
    tail = np.ascontiguousarray(tail, dtype=np.int64)
    force = np.ascontiguousarray(force, dtype=np.float64)
    levels, back = _levels(thresholds)
    total, largest, wraps = _empty(sites.size, levels.size)
    _sweep_ragged(starts, sites, head, tail, force, levels, total, largest, wraps)
    return SweepStatistics(total[:, back], largest[:, back], wraps[:, back])


@njit
def _sizes_at(sites: int, head: np.ndarray, tail: np.ndarray, force: np.ndarray, threshold: float,
              parent: np.ndarray, size: np.ndarray) -> np.ndarray:
    for a in range(sites):
        parent[a] = a
        size[a] = 0
    for b in range(force.size):
        if force[b] > threshold:
            ra = _root(parent, head[b])
            rb = _root(parent, tail[b])
            if ra != rb:
                if size[ra] < size[rb]:
                    ra, rb = rb, ra
                parent[rb] = ra
                size[ra] += size[rb]
            size[ra] += 1
    count = 0
    for a in range(sites):
        if parent[a] == a and size[a] > 0:
            count += 1
    out = np.empty(count, np.int64)
    k = 0
    for a in range(sites):
        if parent[a] == a and size[a] > 0:
            out[k] = size[a]
            k += 1
    return out


def cluster_sizes(sites: int, head: np.ndarray, tail: np.ndarray, force: np.ndarray, threshold: float) -> np.ndarray:
    """The sizes (in bonds) of the clusters of bonds with force ``> threshold``, largest first (the ``n_s`` data).

    Parameters
    ----------
    sites : int
        Number of sites.
    head, tail, force : ndarray
        One sample's bonds.
    threshold : float
        The threshold.

    Returns
    -------
    ndarray of int
        Every cluster's number of bonds, in decreasing order.

    Examples
    --------
    >>> import numpy as np
    >>> cluster_sizes(5, np.array([0, 1, 2, 3]), np.array([1, 2, 0, 4]), np.array([3.0, 2.0, 1.0, 5.0]), 0.5).tolist()
    [3, 1]
    """
    sites = check_int(sites, "sites", 1)
    sizes = _sizes_at(sites, np.ascontiguousarray(head, dtype=np.int64), np.ascontiguousarray(tail, dtype=np.int64),
                      np.ascontiguousarray(force, dtype=np.float64), float(threshold), np.empty(sites, np.int64),
                      np.empty(sites, np.int64))
    return np.sort(sizes)[::-1]


def size_distribution(starts: np.ndarray, sites: np.ndarray, head: np.ndarray, tail: np.ndarray, force: np.ndarray,
                      threshold: float) -> tuple[np.ndarray, np.ndarray]:
    """``n_s`` at one threshold: clusters of ``s`` bonds per bond, in bins ``[2^k, 2^(k+1))`` (Eq. 6.1's
    ``P(s, f)``: the number per bond of clusters of size ``s``, averaged over the bin and the samples).

    Parameters
    ----------
    starts, sites, head, tail, force : ndarray
        The samples, as :func:`sweep_samples` takes them.
    threshold : float
        The threshold.

    Returns
    -------
    (lower, n_s) : ndarray, ndarray
        The bins' lower sizes ``2^k`` and ``n_s`` (clusters per bond and per unit of size).

    Examples
    --------
    >>> import numpy as np
    >>> lower, n_s = size_distribution(np.array([0, 4]), np.array([5]), np.array([0, 1, 2, 3]),
    ...                                np.array([1, 2, 0, 4]), np.array([3.0, 2.0, 1.0, 5.0]), 0.5)
    >>> lower.tolist(), n_s.tolist()            # one cluster of 1 bond, one of 3 (bin [2, 4) has width 2)
    ([1, 2], [0.25, 0.125])
    """
    counts = np.zeros(64, np.int64)
    n = int(np.max(sites))
    parent, size = np.empty(n, np.int64), np.empty(n, np.int64)
    for r in range(len(sites)):
        lo, hi = int(starts[r]), int(starts[r + 1])
        sizes = _sizes_at(int(sites[r]), np.ascontiguousarray(head[lo:hi], dtype=np.int64),
                          np.ascontiguousarray(tail[lo:hi], dtype=np.int64),
                          np.ascontiguousarray(force[lo:hi], dtype=np.float64), float(threshold), parent, size)
        np.add.at(counts, np.floor(np.log2(sizes)).astype(np.int64), 1)
    top = int(np.max(np.nonzero(counts)[0])) + 1 if counts.any() else 0
    lower = 2 ** np.arange(top)
    return lower, counts[:top] / (lower * float(len(force)))
