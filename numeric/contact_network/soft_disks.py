"""A disordered packing in mechanical equilibrium: soft disks relaxed under a piston's pressure in a box.

The force network ensemble needs a contact network *in mechanical balance*:
contacts of random points (Delaunay) are not one -- under a pressure on their
hull no compressive force network balances most of them -- so this module
makes one the way simulations do (thesis Sec. 7.2.2 takes its disordered
networks from such packings).  Bidisperse disks (radii ``1/2`` and ``7/10``)
repel harmonically where they overlap, ``f = k * overlap``; a floor and two
side walls hold them, a piston of pressure ``p`` presses from above; FIRE
(Bitzek et al., Phys. Rev. Lett. 97, 170201 (2006)) minimizes the enthalpy
``E + p * W * H`` until the largest unbalanced force is ``tol * p`` (units:
``k = 1``, disk diameter ~1).

The contact network: every overlapping pair and every disk touching the
floor or a side wall is a contact (walls are fixed bodies: ``j = None``); the
piston's forces on the top disks are prescribed *loads* (the pressure fixes
the force scale; a piston contact would let the whole packing be squeezed
without bound: a self-stress).  The relaxed forces balance these loads with
every force positive, so the ensemble's polytope has an interior point.

Examples
--------
>>> packing = relaxed_packing(30, seed=1)
>>> net = packing.network()
>>> net.grains, net.exact, len(net.contacts) > 30
(30, False, True)
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree

from forcenet.core.errors import ConvergenceError
from forcenet.core.validation import check_int, check_real
from forcenet.exact.contact_network.model import ContactNetwork, contact_network

__all__ = ["SoftDiskPacking", "relaxed_packing"]


@dataclass(frozen=True)
class SoftDiskPacking:
    """A relaxed packing: positions, radii, the box and the piston.

    Attributes
    ----------
    positions : numpy.ndarray
        ``(n, 2)`` disk centres.
    radii : numpy.ndarray
    width, height : float
        The box ``0 <= x <= width``, the piston at ``y = height``.
    pressure : float
    residual : float
        The largest unbalanced force on a disk at the end (relative to ``pressure``).
    """

    positions: np.ndarray
    radii: np.ndarray
    width: float
    height: float
    pressure: float
    residual: float

    def _overlaps(self) -> tuple[np.ndarray, np.ndarray]:
        tree = cKDTree(self.positions)
        pairs = tree.query_pairs(2 * float(self.radii.max()), output_type="ndarray")
        if pairs.size == 0:
            return pairs.reshape(0, 2), np.zeros(0)
        d = np.linalg.norm(self.positions[pairs[:, 1]] - self.positions[pairs[:, 0]], axis=1)
        overlap = self.radii[pairs[:, 0]] + self.radii[pairs[:, 1]] - d
        return pairs, overlap

    def network(self, threshold: float = 1e-9) -> ContactNetwork:
        """The contact network (floats): overlapping pairs and wall contacts; the piston's forces as loads.

        Parameters
        ----------
        threshold : float
            An overlap below ``threshold`` (relative to the radius) is no contact.

        Returns
        -------
        ContactNetwork

        Examples
        --------
        >>> relaxed_packing(12, seed=2).network().frictional
        False
        """
        pairs, overlap = self._overlaps()
        x, r = self.positions, self.radii
        contacts: list[list[object]] = []
        for (i, j), o in zip(pairs, overlap):
            if o > threshold * min(r[i], r[j]):
                n = (x[j] - x[i]) / np.linalg.norm(x[j] - x[i])
                contacts.append([int(i), int(j), float(n[0]), float(n[1])])
        loads = []
        for g in range(len(r)):
            if r[g] - x[g, 0] > threshold * r[g]:
                contacts.append([g, None, -1.0, 0.0])
            if x[g, 0] + r[g] - self.width > threshold * r[g]:
                contacts.append([g, None, 1.0, 0.0])
            if r[g] - x[g, 1] > threshold * r[g]:
                contacts.append([g, None, 0.0, -1.0])
            piston = x[g, 1] + r[g] - self.height
            if piston > threshold * r[g]:
                loads.append([g, 0.0, -float(piston)])
        return contact_network(len(r), contacts, loads, positions=[tuple(map(float, p)) for p in x],
                               radii=[float(v) for v in r])


def _forces(x: np.ndarray, r: np.ndarray, width: float, height: float,
            tree_pairs: np.ndarray) -> tuple[np.ndarray, float, float]:
    """Forces on the disks and on the piston (upward), and the potential energy."""
    force = np.zeros_like(x)
    energy = 0.0
    if tree_pairs.size:
        i, j = tree_pairs[:, 0], tree_pairs[:, 1]
        delta = x[j] - x[i]
        d = np.linalg.norm(delta, axis=1)
        overlap = r[i] + r[j] - d
        touching = overlap > 0
        i, j, delta, d, overlap = i[touching], j[touching], delta[touching], d[touching], overlap[touching]
        push = (overlap / d)[:, None] * delta
        np.add.at(force, j, push)
        np.add.at(force, i, -push)
        energy += 0.5 * float((overlap**2).sum())
    for axis, low in ((0, True), (0, False), (1, True)):
        o = (r - x[:, axis]) if low else (x[:, axis] + r - width)
        o = np.maximum(o, 0.0)
        force[:, axis] += o if low else -o
        energy += 0.5 * float((o**2).sum())
    top = np.maximum(x[:, 1] + r - height, 0.0)
    force[:, 1] -= top
    energy += 0.5 * float((top**2).sum())
    return force, float(top.sum()), energy


def relaxed_packing(grains: int, *, pressure: float = 0.01, seed: int | None = None, tol: float = 1e-9,
                    max_steps: int = 400000) -> SoftDiskPacking:
    """Relax ``grains`` bidisperse soft disks under a piston of ``pressure`` in a box, by FIRE.

    Parameters
    ----------
    grains : int
        Number of disks, ``>= 2``.
    pressure : float
        The piston's pressure (``k = 1``; 0.01 gives overlaps of ~1 % of a diameter).
    seed : int, optional
        The random start.
    tol : float
        Stop when every disk's unbalanced force is below ``tol * pressure``.
    max_steps : int
        ConvergenceError beyond.

    Returns
    -------
    SoftDiskPacking

    Raises
    ------
    ConvergenceError
        If FIRE has not converged within ``max_steps``.

    Examples
    --------
    >>> p = relaxed_packing(20, seed=0)
    >>> bool(p.residual < 1e-9)
    True
    """
    grains = check_int(grains, "grains", 2)
    pressure = check_real(pressure, "pressure", 0, low_open=True)
    rng = np.random.default_rng(seed)
    r = np.where(rng.random(grains) < 0.5, 0.5, 0.7)
    area = float(np.pi * (r**2).sum())
    width = float(np.sqrt(area / 0.84))
    height = 2.0 * width
    x = np.column_stack([rng.uniform(r, width - r), rng.uniform(r, height - r)])
    v = np.zeros_like(x)
    vh = 0.0
    dt, dt_max, alpha, since = 0.05, 0.5, 0.1, 0
    skin = 0.3
    pairs = cKDTree(x).query_pairs(2 * r.max() + skin, output_type="ndarray")
    anchor = x.copy()
    load = pressure * width
    for step in range(max_steps):
        if np.abs(x - anchor).max() > skin / 2:
            pairs = cKDTree(x).query_pairs(2 * r.max() + skin, output_type="ndarray")
            anchor = x.copy()
        force, up, _ = _forces(x, r, width, height, pairs)
        fh = up - load  # the piston: pushed up by the disks, down by the pressure
        worst = max(float(np.abs(force).max()), abs(fh) / np.sqrt(grains))
        if worst < tol * pressure and step > 10:
            return SoftDiskPacking(x, r, width, height, pressure, worst / pressure)
        power = float((force * v).sum()) + fh * vh
        if power > 0:  # FIRE: mix the velocity toward the force, speed up after a while
            norm_v = np.sqrt(float((v**2).sum()) + vh * vh)
            norm_f = np.sqrt(float((force**2).sum()) + fh * fh) or 1.0
            v = (1 - alpha) * v + alpha * norm_v * force / norm_f
            vh = (1 - alpha) * vh + alpha * norm_v * fh / norm_f
            since += 1
            if since > 5:
                dt, alpha = min(dt * 1.1, dt_max), alpha * 0.99
        else:
            v[:] = 0.0
            vh = 0.0
            dt, alpha, since = dt * 0.5, 0.1, 0
        v += dt * force
        vh += dt * fh / np.sqrt(grains)  # a piston as heavy as sqrt(n) disks
        x += dt * v
        height += dt * vh
    raise ConvergenceError(f"the soft disks did not relax within {max_steps} FIRE steps (the largest unbalanced "
                           f"force is {worst / pressure:.2g} times the pressure); raise max_steps or tol")
