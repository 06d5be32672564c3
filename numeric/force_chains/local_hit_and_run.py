"""Uniform force networks on a large contact network: hit-and-run along local self-stresses.

The force network ensemble is the uniform measure on ``{f : A f = b, f >= 0}``
(thesis Sec. 2.3.2).  Any ``v`` with ``A v = 0`` (a *self-stress*) is a
direction inside that affine set, and for any fixed direction ``v`` the
uniform measure, conditioned on the line ``f + t v``, is uniform on the chord
where ``f + t v >= 0``.  So the move "pick one of a fixed set of self-stresses
at random, jump to a uniform point of its chord" leaves the ensemble
invariant (a Gibbs step, reversible), and when the set spans ``Ker A`` the
chain is irreducible on the convex polytope (Smith 1984, Oper. Res. 32:1296;
Belisle, Romeijn and Smith 1993: hit-and-run with any direction law whose
support spans the space).  The dense sampler
(:mod:`forcenet.numeric.contact_network.hit_and_run`) uses an orthonormal
basis from an SVD, ``O(contacts)`` per move and ``O(contacts^2)`` memory: out
of reach at the thesis's ``M ~ 10^4`` contacts (Sec. 7.2.1).  Here the
directions are *local*: for every grain ``g``, the self-stresses of the
patch of grains within ``r`` contacts of ``g`` (the null space of ``A``
restricted to the patch's contacts; on the hexagonal packing ``r = 1``
gives the "wheel": six spokes and six rim contacts), so a move touches ~12
forces and a sweep (one move per direction) costs ``O(contacts)``.  The
radius grows until the directions span ``Ker A`` (checked by the rank of
their Gram matrix against ``dim Ker A``); an unspanned kernel is refused,
never sampled.

The chain starts at the maximin network (every force as large as possible,
an interior point: :func:`forcenet.exact.contact_network.polytope.check_polytope`).
Rounding drift off ``A f = b`` is a sum of ``~10^-16`` steps, one per move
(no projection is needed at the sizes planned; the tests bound it).

Examples
--------
>>> from forcenet.exact.contact_network.geometries import snooker
>>> walk = LocalHitAndRun(snooker(4).network)
>>> walk.dimension, walk.radius
(6, 1)
>>> forces = walk.run(200, thin=2, seed=1)
>>> forces.shape, bool(forces.min() >= -1e-12)
((200, 26), True)
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy import linalg, sparse

from forcenet.core.errors import ArgumentError
from forcenet.exact.contact_network.model import ContactNetwork
from forcenet.exact.contact_network.polytope import balance, check_polytope, float_system

from ..jit import njit

__all__ = ["LocalDirections", "local_directions", "local_sweeps", "LocalHitAndRun", "MOVE_SECONDS"]

MOVE_SECONDS = 3.5e-7  # one local move (~12 forces, two random numbers), measured at N = 56..84 on the 2-core machine


@dataclass(frozen=True)
class LocalDirections:
    """Self-stresses spanning ``Ker A``, as sparse rows (CSR): direction ``k`` has entries
    ``value[indptr[k]:indptr[k+1]]`` on contacts ``index[...]`` (unit length).

    Attributes
    ----------
    indptr, index, value : numpy.ndarray
    dimension : int
        ``dim Ker A`` (= the rank of the directions).
    radius : int
        The patches' radius in contacts.
    """

    indptr: np.ndarray
    index: np.ndarray
    value: np.ndarray
    dimension: int
    radius: int

    @property
    def count(self) -> int:
        """The number of directions (a sweep's moves)."""
        return int(self.indptr.size - 1)


def _neighbours(net: ContactNetwork) -> tuple[list[list[int]], list[list[int]]]:
    """Per grain: its neighbouring grains and its contacts."""
    adjacent: list[list[int]] = [[] for _ in range(net.grains)]
    incident: list[list[int]] = [[] for _ in range(net.grains)]
    for c, (i, j, _, _) in enumerate(net.contacts):
        incident[i].append(c)
        if j is not None:
            adjacent[i].append(j)
            adjacent[j].append(i)
            incident[j].append(c)
    return adjacent, incident


def _patch(adjacent: list[list[int]], g: int, radius: int) -> set[int]:
    seen, front = {g}, [g]
    for _ in range(radius):
        front = [n for a in front for n in adjacent[a] if n not in seen]
        seen.update(front)
    return seen


def _rank(matrix: np.ndarray) -> int:
    if matrix.size == 0:
        return 0
    eig = np.linalg.eigvalsh(matrix)
    return int((eig > 1e-9 * max(1.0, float(eig.max()))).sum())


def _csr(rows: list[tuple[np.ndarray, np.ndarray]], width: int
         ) -> tuple[np.ndarray, np.ndarray, np.ndarray, sparse.csr_matrix]:
    counts = np.array([c.size for c, _ in rows], dtype=np.int64)
    indptr = np.concatenate([[0], np.cumsum(counts)]).astype(np.int64)
    index = np.concatenate([c for c, _ in rows]) if rows else np.zeros(0, np.int64)
    value = np.concatenate([v for _, v in rows]) if rows else np.zeros(0)
    return indptr, index, value, sparse.csr_matrix((value, index, indptr), shape=(len(rows), width))


def _patch_stresses(net: ContactNetwork, A: Any, radius: int) -> list[tuple[np.ndarray, np.ndarray]]:
    """The self-stresses of every grain's patch of ``radius`` (each patch once), as (contacts, unit values)."""
    adjacent, incident = _neighbours(net)
    ends = [(i, j) for i, j, _, _ in net.contacts]
    rows: list[tuple[np.ndarray, np.ndarray]] = []
    seen: set[tuple[int, ...]] = set()
    for g in range(net.grains):
        patch = _patch(adjacent, g, radius)
        cols = np.array(sorted({c for a in patch for c in incident[a]
                                if ends[c][0] in patch and (ends[c][1] is None or ends[c][1] in patch)}),
                        dtype=np.int64)
        if cols.size == 0 or tuple(cols) in seen:
            continue
        seen.add(tuple(cols))
        block = A[:, cols].toarray()
        block = block[np.abs(block).sum(axis=1) > 0]
        for v in linalg.null_space(block).T:  # the patch's self-stresses (orthonormal)
            keep = np.abs(v) > 1e-12
            rows.append((cols[keep], v[keep] / np.linalg.norm(v[keep])))
    return rows


def local_directions(net: ContactNetwork, A: Any, dimension: int, max_radius: int = 2) -> LocalDirections:
    """Self-stresses of every grain's patch, the radius raised until they span ``Ker A`` (``dimension``); what
    patches of ``max_radius`` leave unspanned (global self-stresses of a nearly isostatic packing) is completed by
    an orthonormal basis of the rest of ``Ker A`` (dense directions, from an SVD).

    Parameters
    ----------
    net : ContactNetwork
        Frictionless.
    A : scipy.sparse matrix
        The balance matrix (:func:`~forcenet.exact.contact_network.polytope.float_system`).
    dimension : int
        ``dim Ker A``.
    max_radius : int
        The largest patch radius tried.

    Returns
    -------
    LocalDirections
        ``radius`` is 0 when dense directions were needed.

    Examples
    --------
    >>> from forcenet.exact.contact_network.geometries import snooker
    >>> from forcenet.exact.contact_network.polytope import balance, float_system
    >>> net = snooker(5).network
    >>> d = local_directions(net, float_system(balance(net))[0], 10)
    >>> d.count, d.radius
    (13, 1)
    """
    A = A.tocsc()
    width = len(net.contacts)
    rows: list[tuple[np.ndarray, np.ndarray]] = []
    for radius in range(1, max_radius + 1):
        rows = _patch_stresses(net, A, radius)
        indptr, index, value, D = _csr(rows, width)
        if _rank((D @ D.T).toarray()) >= dimension:
            return LocalDirections(indptr, index, value, dimension, radius)
    # complete the span: the part of Ker A orthogonal to the local self-stresses
    kernel = linalg.null_space(A.toarray())
    if rows:
        local = linalg.orth(_csr(rows, width)[3].toarray().T)
        kernel = kernel - local @ (local.T @ kernel)
    rest = linalg.orth(kernel, rcond=1e-9) if kernel.size else kernel
    for v in rest.T:
        keep = np.abs(v) > 1e-12
        rows.append((np.flatnonzero(keep).astype(np.int64), v[keep] / np.linalg.norm(v[keep])))
    indptr, index, value, _ = _csr(rows, width)
    return LocalDirections(indptr, index, value, dimension, 0)


@njit
def local_sweeps(z: np.ndarray, indptr: np.ndarray, index: np.ndarray, value: np.ndarray,
                 rng: np.random.Generator, moves: int) -> None:  # pragma: no cover
    """``moves`` hit-and-run moves, each along a random local self-stress, to a uniform point of its chord."""
    n = indptr.size - 1
    for _ in range(moves):
        k = rng.integers(0, n)
        lo = -np.inf
        hi = np.inf
        for p in range(indptr[k], indptr[k + 1]):
            a = value[p]
            f = z[index[p]]
            if f < 0.0:
                f = 0.0
            if a > 0.0:
                if -f / a > lo:
                    lo = -f / a
            elif a < 0.0:
                if -f / a < hi:
                    hi = -f / a
        if not (hi > lo) or lo == -np.inf or hi == np.inf:
            continue
        t = lo + (hi - lo) * rng.random()
        for p in range(indptr[k], indptr[k + 1]):
            z[index[p]] += t * value[p]


class LocalHitAndRun:
    """Hit-and-run along local self-stresses on a frictionless contact network (module docstring: why uniform).

    Parameters
    ----------
    network : ContactNetwork
        Frictionless, balanced, bounded (refused otherwise, one line).
    dimension : int, optional
        ``dim Ker A`` when known (e.g. ``contacts - 2 grains`` for a rigid packing); computed otherwise.
    max_radius : int
        The largest patch radius (:func:`local_directions`).

    Attributes
    ----------
    dimension : int
    radius : int
        The patches' radius.
    start : numpy.ndarray
        The maximin network.
    """

    def __init__(self, network: ContactNetwork, dimension: int | None = None, max_radius: int = 2) -> None:
        if network.frictional:
            raise ArgumentError("the local hit-and-run samples frictionless networks only: use forcenet.network "
                                "for a frictional one")
        self.network = network
        bal = balance(network)
        A, _, _ = float_system(bal)
        self.start, margin = check_polytope(network, bal)
        if margin <= 1e-9:
            raise ArgumentError("degenerate: some contact carries no force in every force network of this "
                                "packing (a flat polytope); remove those contacts")
        if dimension is None:
            dense = A.toarray()
            dimension = len(network.contacts) - _rank(dense @ dense.T)
        self.directions = local_directions(network, A, dimension, max_radius)
        self.dimension = dimension
        self.radius = self.directions.radius
        self.variables = len(network.contacts)

    def sweep_seconds(self) -> float:
        """Estimated seconds of one sweep (one move per direction)."""
        return self.directions.count * MOVE_SECONDS

    def run(self, samples: int, thin: int = 1, burn_in: int = 100, seed: int | np.random.Generator | None = None
            ) -> np.ndarray:
        """``samples`` force networks, ``thin`` sweeps apart, after ``burn_in`` sweeps from the maximin network.

        Parameters
        ----------
        samples : int
            Networks recorded.
        thin : int
            Sweeps between two recorded networks.
        burn_in : int
            Sweeps discarded first.
        seed : int or numpy.random.Generator, optional
            The random stream.

        Returns
        -------
        numpy.ndarray
            ``(samples, contacts)``: one force network per row (the contacts' order of the network).

        Examples
        --------
        >>> from forcenet.exact.contact_network.geometries import snooker
        >>> LocalHitAndRun(snooker(3).network).run(10, seed=0).shape
        (10, 15)
        """
        rng = seed if isinstance(seed, np.random.Generator) else np.random.default_rng(seed)
        d = self.directions
        z = self.start.copy()
        local_sweeps(z, d.indptr, d.index, d.value, rng, burn_in * d.count)
        out = np.empty((samples, self.variables))
        for k in range(samples):
            local_sweeps(z, d.indptr, d.index, d.value, rng, thin * d.count)
            out[k] = z
        return out
