"""The force network ensemble's models of Table 7.1 (Sec. 7.2): snooker, disordered and averaged networks.

* ``snooker`` (Sec. 7.2.1): the ensemble on the snooker packing of ``N``
  layers (:func:`forcenet.exact.contact_network.geometries.snooker`: the
  hexagonal packing of monodisperse frictionless disks in a triangle, an
  isotropic pressure 1 on its three sides), sampled uniformly by
  :mod:`.local_hit_and_run` (the thesis used a Metropolis walk in its
  q-coordinates; any uniform sampler of the polytope serves).
* ``disordered`` (Sec. 7.2.2): the ensemble on disordered contact networks.
  The thesis took fixed networks from Lennard-Jones simulations (z = 4.7 to
  6 contacts per grain) and generated force networks by simulated annealing
  (not known to be uniform); here each size has ``PACKINGS`` fixed packings
  of ``L^2`` bidisperse soft disks relaxed under a piston of pressure 0.1
  (:func:`forcenet.numeric.contact_network.soft_disks.relaxed_packing`; z ~
  4.7), shared in turn by the blocks, and their force networks are drawn
  uniformly, so the disorder of the contacts is averaged over 8 packings.
* ``averaged`` (Sec. 7.2.3, non-uniform sampling): on the snooker packing,
  each network is the average of ``P`` networks of the ensemble (``P``
  consecutive thinned states of the chain), which moves weight from the
  polytope's boundary to its bulk.

A block is one independent chain (burn-in from the maximin network, then
``count`` networks ``thin`` sweeps apart, ``thin = THIN_PER_LAYER * L``
sweeps: a few times the integrated autocorrelation time of the slowest force,
measured at ``L = 4..30`` as ``~4.5 L`` sweeps); the block reports the
integrated autocorrelation time of its recorded networks' mean squared force
(``forcenet.numeric.autocorr``), which should be ~1.  The clusters are made of
the grain-grain contacts; ``M`` is the number of contacts, the walls' included
(the thesis's ``M``: "the total number of contacts", Fig. 7.2).

Examples
--------
>>> import numpy as np
>>> row = block_task("snooker", 6, 8, 0, 0, 0, np.array([0.4, 0.8]), 1).view(np.float64)
>>> row.shape, float(row[6]), float(row[7])
((9,), 8.0, 57.0)
"""

from __future__ import annotations

import functools

import numpy as np

from forcenet.core.errors import ArgumentError
from forcenet.exact.contact_network.geometries import snooker
from forcenet.exact.contact_network.model import ContactNetwork
from forcenet.numeric.autocorr import integrated_time
from forcenet.numeric.contact_network.soft_disks import relaxed_packing

from .local_hit_and_run import MOVE_SECONDS, LocalHitAndRun
from .newman_ziff import Lattice, sweep_lattice

__all__ = ["NETWORK_MODELS", "THIN_PER_LAYER", "BURN_IN_SWEEPS", "ensemble_networks", "block_task", "network_size",
           "block_seconds", "setup_seconds", "pilot_thresholds", "PACKINGS", "BUILD_SECONDS"]

NETWORK_MODELS = ("snooker", "disordered", "averaged")
THIN_PER_LAYER = 5  # sweeps between recorded networks per layer (tau of the slowest force ~ 4.5 L sweeps)
BURN_IN_SWEEPS = 40  # burn-in per layer, in sweeps (~10 tau)
PACKINGS = 8  # disordered packings per size (blocks share them in turn)
BUILD_SECONDS = 0.02  # a disordered packing relaxed and its sampler built, per disk (100 disks: 7.5 s at load 20 on 2 cores)
PRESSURE = 0.1  # the soft disks' piston pressure: z ~ 4.7 contacts per disk, the thesis's lowest (Fig. 7.3 a)


@functools.lru_cache(maxsize=8)
def _snooker_walk(N: int) -> tuple[LocalHitAndRun, Lattice]:
    """The sampler and the bond list of the snooker packing of ``N`` layers (kept per process)."""
    net = snooker(N).network
    # the triangulated triangle is rigid: A has full row rank, so dim Ker A = contacts - 2 grains (= N(N-1)/2)
    return LocalHitAndRun(net, len(net.contacts) - 2 * net.grains), _bonds(net, N)


def _bonds(net: ContactNetwork, L: int) -> Lattice:
    grain_contacts = [(i, j) for i, j, _, _ in net.contacts if j is not None]
    head = np.array([i for i, _ in grain_contacts], dtype=np.int64)
    tail = np.array([j for _, j in grain_contacts], dtype=np.int64)
    zeros = np.zeros(head.size, dtype=np.int64)
    return Lattice("contacts", L, net.grains, head, tail, zeros, zeros)


@functools.lru_cache(maxsize=16)
def _packing_walk(L: int, packing: int) -> tuple[LocalHitAndRun, Lattice]:
    """The sampler on the soft-disk packing number ``packing`` of ``L^2`` disks (kept per process)."""
    net = relaxed_packing(L * L, pressure=PRESSURE, seed=packing).network()
    return LocalHitAndRun(net, max_radius=1), _bonds(net, L)  # wheels where they exist, the rest dense


def _walk(model: str, L: int, packing: int) -> tuple[LocalHitAndRun, Lattice]:
    return _packing_walk(L, packing) if model == "disordered" else _snooker_walk(L)


def ensemble_networks(model: str, L: int, count: int, rng: np.random.Generator, average: int = 1,
                      packing: int = 0) -> tuple[np.ndarray, Lattice, int]:
    """``count`` force networks of ``model`` at size ``L``: the grain-grain forces, the bond list, the contacts.

    Parameters
    ----------
    model : {"snooker", "disordered", "averaged"}
    L : int
        Layers of the snooker triangle; ``L^2`` disks of a disordered packing.
    count : int
        Networks.
    rng : numpy.random.Generator
    average : int
        ``P``: networks averaged into one (model ``averaged``).
    packing : int
        The seed of the disordered packing.

    Returns
    -------
    forces : numpy.ndarray
        ``(count, bonds)``.
    lattice : Lattice
        The grain-grain contacts.
    contacts : int
        All contacts (walls included): the thesis's ``M``.

    Examples
    --------
    >>> f, lat, M = ensemble_networks("averaged", 5, 3, np.random.default_rng(0), average=2)
    >>> f.shape, lat.bonds, M
    ((3, 30), 30, 40)
    """
    if model not in NETWORK_MODELS:
        raise ArgumentError(f"model={model!r} is out of range: model must be one of {', '.join(NETWORK_MODELS)}")
    walk, lattice = _walk(model, L, packing)
    P = average if model == "averaged" else 1
    states = walk.run(count * P, THIN_PER_LAYER * L, BURN_IN_SWEEPS * L, rng)
    keep = np.array([c for c, (_, j, _, _) in enumerate(walk.network.contacts) if j is not None], dtype=np.int64)
    forces = states[:, keep].reshape(count, P, keep.size).mean(axis=1)  # Sec. 7.2.3: the average of P networks
    return np.ascontiguousarray(forces), lattice, walk.variables


def block_task(model: str, L: int, count: int, seed: int, size_index: int, block: int, thresholds: np.ndarray,
               average: int) -> np.ndarray:
    """One block: ``count`` networks of one chain, their cluster statistics summed per threshold.

    Returns
    -------
    numpy.ndarray of int64, shape (3 T + 3,)
        The bits of float64 numbers (``.view(np.float64)`` reads them; the checkpoint store keeps int64 records
        exactly): the sums of ``total / M`` (``<s^2>`` without the largest cluster, per contact of the block's
        network), ``largest / M``, ``wraps`` (zeros: no periodic wrapping here), then ``count``, the contacts ``M``
        and the integrated autocorrelation time (in recorded networks) of the networks' mean squared force.

    Examples
    --------
    >>> block_task("snooker", 5, 4, 1, 0, 0, np.array([0.5]), 1).view(np.float64)[-3:-1].tolist()
    [4.0, 40.0]
    """
    rng = np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(size_index, block)))
    # PACKINGS disordered packings per size, each sampled by every PACKINGS-th block's chain
    packing = int(np.random.SeedSequence(seed, spawn_key=(size_index, 2**30 + block % PACKINGS)).generate_state(1)[0])
    forces, lattice, M = ensemble_networks(model, L, count, rng, average, packing)
    stats = sweep_lattice(lattice, forces, thresholds, wrapping=False)
    series = (forces**2).mean(axis=1)[:, None]
    tau = float(integrated_time(series, tol=1.0, quiet=True)[0]) if count >= 4 else 1.0
    row = np.concatenate([stats.total.sum(0) / M, stats.largest.sum(0) / M, stats.wraps.sum(0), [count, M, tau]])
    return row.astype(np.float64).view(np.int64)  # the bits of the floats: the checkpoint store keeps int64


def network_size(model: str, L: int) -> tuple[int, int]:
    """``(contacts, moves per sweep)`` of size ``L``: exact for the snooker packing, an estimate for a disordered
    packing (~2.2 contacts and ~0.5 self-stresses per disk).

    Examples
    --------
    >>> network_size("snooker", 20)
    (610, 193)
    """
    if model == "disordered":
        return int(2.2 * L * L), max(1, L * L // 2)
    contacts = 3 * L * (L - 1) // 2 + 2 * L
    return contacts, contacts - L * (L + 1) + 3


def block_seconds(model: str, L: int, count: int, average: int) -> float:
    """Estimated seconds of one block: burn-in and recorded sweeps, the packing (disordered), the clusters.

    Examples
    --------
    >>> block_seconds("snooker", 20, 100, 1) > 0
    True
    """
    contacts, moves = network_size(model, L)
    P = average if model == "averaged" else 1
    sweeps = BURN_IN_SWEEPS * L + count * P * THIN_PER_LAYER * L
    return sweeps * moves * MOVE_SECONDS + count * contacts * 2e-7


def setup_seconds(model: str, L: int) -> float:
    """Estimated seconds to build the samplers of size ``L`` once per process (the maximin network's linear
    program, the patches, the Gram matrix's rank): the snooker packing's, 65 s at ``L = 84``, 9 s at 56,
    measured; the ``PACKINGS`` disordered packings' (relaxation and sampler).

    Examples
    --------
    >>> round(setup_seconds("snooker", 84))
    65
    """
    if model == "disordered":
        return PACKINGS * BUILD_SECONDS * L * L
    return 65.0 * (network_size(model, L)[0] / network_size(model, 84)[0]) ** 2.4


def pilot_thresholds(model: str, sizes: tuple[int, ...], seed: int, thresholds: int, average: int) -> np.ndarray:
    """The thresholds: quantiles 1 %..99 % of the forces of 16 pilot networks of a small size (<= 12; the
    forces' scale is the pressure's at every size).

    Examples
    --------
    >>> t = pilot_thresholds("snooker", (6, 8, 10), 0, 5, 1)
    >>> t.size, bool(t[0] < t[-1])
    (5, True)
    """
    L = max([s for s in sizes if s <= 12] or [min(sizes)])
    rng = np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(2**31 - 1,)))
    forces = ensemble_networks(model, L, 16, rng, average)[0].ravel()
    return np.unique(np.quantile(forces, np.linspace(0.01, 0.99, thresholds)))
