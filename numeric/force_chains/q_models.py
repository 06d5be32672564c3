"""The q-models of Sec. 7.3 on the tilted rectangular lattice: independent and microcanonical.

The lattice: ``L`` rows of ``W`` grains, periodic horizontally; grain
``(i, j)`` rests on ``(i + 1, j)`` (its left bond, force ``F_l``) and
``(i + 1, j + 1 mod W)`` (its right bond, ``F_r``); the bonds of the last
row end on ``W`` floor nodes.  Every grain has four contacts (Fig. 2.8), the
bonds are ``M = 2 W L``.  A uniform unit pressure on the top: every grain of
row 0 carries ``W_0j = 1``; below, ``W_ij = F_r(i-1, j-1) + F_l(i-1, j)``
(the vertical force balance, scalar); ``F_l = q W``, ``F_r = (1 - q) W``.

* **Independent q-model** (Sec. 7.3.1; Liu et al., Science 269, 513 (1995);
  Coppersmith et al., Phys. Rev. E 53, 4673 (1996)): every ``q`` uniform in
  ``(0, 1)``, independently.  Check: without gravity the product of
  ``Gamma(2)`` laws ``P(w) = 4 w e^(-2 w)`` is invariant (two independent
  ``Exp`` halves ``q w``, ``(1 - q) w`` of a ``Gamma(2)`` load sum to a
  ``Gamma(2)`` load), so at depth the loads tend to ``4 w e^(-2 w)`` and the
  bond forces ``F = q W`` to the exponential ``2 e^(-2 f)`` (mean 1/2): the
  thesis's "P(f) exactly exponential at large depths".
* **Microcanonical q-model** (Sec. 7.3.2): every vertical force network
  equally likely, the uniform law on the flow polytope ``{F_l(i,j) in
  [0, W_ij]}`` (Lebesgue in the ``F_l``; the joint law of the ``q`` is
  ``prod W_ij dq_ij``).  Sampled by heat-bath moves along fixed directions
  (a hit-and-run restricted to the cycle directions, exact for the uniform
  law): the *plaquette* of grain ``a = (i, j)`` with children ``b = (i+1, j)``,
  ``c = (i+1, j+1)`` and common grandchild ``d = (i+2, j+1)`` moves ``delta``
  from ``a -> c -> d`` to ``a -> b -> d`` (``F_l(a) += delta``,
  ``F_r(a) -= delta``, ``F_r(b) += delta``, ``F_l(c) -= delta``: every
  load but ``W_b``, ``W_c`` unchanged), ``delta`` uniform over the interval
  keeping the four forces non-negative; a grain of the last row moves
  ``delta`` between its two floor bonds.  In the ``F_l`` these are the
  directions ``e_a - e_c`` and ``e_a``: they span the space, so the chain is
  irreducible on the (convex) polytope.  Exact small volumes:
  :mod:`forcenet.exact.q_model.flow_polytope`.

Examples
--------
>>> import numpy as np
>>> lattice = q_lattice(3, 4)
>>> lattice.sites, lattice.bonds
(16, 24)
>>> F = independent_forces(3, 4, np.random.default_rng(0).random((1, 3, 4)))
>>> bool(np.allclose(F[0].reshape(3, 8).sum(axis=1), 4.0))   # every row carries the top's load
True
"""

from __future__ import annotations

import numpy as np

from forcenet.core.validation import check_int

from ..jit import njit
from .newman_ziff import Lattice

__all__ = ["q_lattice", "independent_forces", "independent_samples", "microcanonical_chain", "microcanonical_samples",
           "loads"]


def q_lattice(L: int, W: int) -> Lattice:
    """The bonds of the tilted rectangular lattice: ``L`` rows of ``W`` grains and ``W`` floor nodes.

    Bond ``2 (i W + j)`` is grain ``(i, j)``'s left bond, ``2 (i W + j) + 1`` its right one; the displacement
    counts the horizontal wraps (a cluster wrapping horizontally is detected).

    Examples
    --------
    >>> q_lattice(2, 3).head.tolist(), q_lattice(2, 3).tail.tolist()
    ([0, 0, 1, 1, 2, 2, 3, 3, 4, 4, 5, 5], [3, 4, 4, 5, 5, 3, 6, 7, 7, 8, 8, 6])
    """
    L, W = check_int(L, "L", 1), check_int(W, "W", 2)
    grid_i, grid_j = np.meshgrid(np.arange(L), np.arange(W), indexing="ij")
    i, j = grid_i.ravel(), grid_j.ravel()
    grain = i * W + j
    head = np.repeat(grain, 2)
    tail = np.empty_like(head)
    tail[0::2] = (i + 1) * W + j
    tail[1::2] = (i + 1) * W + (j + 1) % W
    dx = np.zeros_like(head)
    dx[1::2] = 1
    as64 = lambda a: np.ascontiguousarray(a, dtype=np.int64)  # noqa: E731
    return Lattice("q-lattice", L, (L + 1) * W, as64(head), as64(tail), as64(dx), as64(np.ones_like(head)))


@njit
def _forces_from_q(q: np.ndarray, top: np.ndarray, out: np.ndarray) -> None:
    """``out[r]`` = the bond forces of sample ``r`` (bond order of :func:`q_lattice`) from its ``q[r, i, j]`` and
    its top loads ``top[r]``."""
    K, L, W = q.shape
    load = np.empty(W)
    below = np.empty(W)
    for r in range(K):
        for j in range(W):
            load[j] = top[r, j]
        for i in range(L):
            for j in range(W):
                below[j] = 0.0
            for j in range(W):
                fl = q[r, i, j] * load[j]
                fr = load[j] - fl
                out[r, 2 * (i * W + j)] = fl
                out[r, 2 * (i * W + j) + 1] = fr
                below[j] += fl
                below[(j + 1) % W] += fr
            for j in range(W):
                load[j] = below[j]


def independent_forces(L: int, W: int, q: np.ndarray, top: np.ndarray | None = None) -> np.ndarray:
    """The bond forces of the q-model for given ``q`` of shape ``(K, L, W)`` and top loads (default 1 each).

    Examples
    --------
    >>> import numpy as np
    >>> independent_forces(1, 2, np.array([[[0.25, 0.5]]])).tolist()
    [[0.25, 0.75, 0.5, 0.5]]
    """
    q = np.ascontiguousarray(q, dtype=np.float64)
    top = np.ones((q.shape[0], W)) if top is None else np.ascontiguousarray(np.broadcast_to(top, (q.shape[0], W)),
                                                                           dtype=np.float64)
    out = np.empty((q.shape[0], 2 * L * W))
    _forces_from_q(q, top, out)
    return out


def independent_samples(L: int, W: int, samples: int, rng: np.random.Generator) -> np.ndarray:
    """``samples`` independent force networks of the independent q-model (uniform ``q``), shape ``(K, 2 L W)``.

    Examples
    --------
    >>> import numpy as np
    >>> independent_samples(4, 5, 3, np.random.default_rng(1)).shape
    (3, 40)
    """
    return independent_forces(L, W, rng.random((check_int(samples, "samples", 1), L, W)))


def loads(forces: np.ndarray, L: int, W: int) -> np.ndarray:
    """The loads ``W_ij`` (shape ``(K, L, W)``) of force networks in :func:`q_lattice`'s bond order.

    Examples
    --------
    >>> import numpy as np
    >>> loads(independent_forces(2, 2, np.full((1, 2, 2), 0.5)), 2, 2).tolist()
    [[[1.0, 1.0], [1.0, 1.0]]]
    """
    f = np.asarray(forces).reshape(-1, L, W, 2)
    return f.sum(axis=3)


@njit
def _heat_bath(F: np.ndarray, L: int, W: int, sweeps: int, u: np.ndarray) -> None:
    """``sweeps`` systematic sweeps of heat-bath moves on the flow polytope; ``u``: one uniform per move."""
    n = 0
    for _ in range(sweeps):
        for i in range(L):
            for j in range(W):
                a = 2 * (i * W + j)
                if i == L - 1:  # between the two floor bonds
                    lo = -F[a]
                    hi = F[a + 1]
                    d = lo + (hi - lo) * u[n]
                    F[a] += d
                    F[a + 1] -= d
                else:
                    b = 2 * ((i + 1) * W + j)
                    c = 2 * ((i + 1) * W + (j + 1) % W)
                    lo = max(-F[a], -F[b + 1])
                    hi = min(F[a + 1], F[c])
                    d = lo + (hi - lo) * u[n]
                    F[a] += d
                    F[a + 1] -= d
                    F[b + 1] += d
                    F[c] -= d
                n += 1


def microcanonical_chain(L: int, W: int, samples: int, thin: int, burn_in: int, rng: np.random.Generator
                         ) -> np.ndarray:
    """A heat-bath chain on the flow polytope from the uniform network (every ``q = 1/2``): ``burn_in`` sweeps,
    then ``samples`` networks ``thin`` sweeps apart, shape ``(K, 2 L W)``.

    Parameters
    ----------
    L, W : int
        Rows and grains per row.
    samples, thin, burn_in : int
        Networks kept, sweeps between them, sweeps before the first.
    rng : numpy.random.Generator
        The random numbers (one uniform per move).

    Returns
    -------
    ndarray
        The bond forces, one network per row.

    Examples
    --------
    >>> import numpy as np
    >>> F = microcanonical_chain(3, 3, 2, 5, 10, np.random.default_rng(2))
    >>> bool((F >= 0).all()), bool(np.allclose(loads(F, 3, 3)[:, 0], 1.0))
    (True, True)
    """
    L, W = check_int(L, "L", 1), check_int(W, "W", 2)
    samples, thin, burn_in = check_int(samples, "samples", 1), check_int(thin, "thin", 1), check_int(burn_in, "burn_in", 0)
    F = independent_forces(L, W, np.full((1, L, W), 0.5))[0]
    out = np.empty((samples, F.size))
    _sweeps(F, L, W, burn_in, rng)
    for k in range(samples):
        _sweeps(F, L, W, thin, rng)
        out[k] = F
    return out


SWEEP_NUMBERS = 2**21  # uniforms drawn at once (16 MiB): the sweeps run in chunks of about this many moves


def _sweeps(F: np.ndarray, L: int, W: int, sweeps: int, rng: np.random.Generator) -> None:
    """``sweeps`` heat-bath sweeps, the uniforms drawn in chunks (the same numbers, in the same order, as one draw)."""
    per = max(1, SWEEP_NUMBERS // (L * W))
    done = 0
    while done < sweeps:
        n = min(per, sweeps - done)
        _heat_bath(F, L, W, n, rng.random(L * W * n))
        done += n


def microcanonical_samples(L: int, W: int, samples: int, rng: np.random.Generator) -> np.ndarray:
    """Networks of the microcanonical q-model for finite-size scaling: one chain with ``L^2`` sweeps of burn-in
    and ``max(1, L^2 // 16)`` sweeps between networks (the load field relaxes diffusively over the depth ``L``;
    the thinning is checked by the integrated autocorrelation time in ``tests/test_force_chains_models.py``).

    Examples
    --------
    >>> import numpy as np
    >>> microcanonical_samples(4, 4, 3, np.random.default_rng(0)).shape
    (3, 32)
    """
    return microcanonical_chain(L, W, samples, max(1, L * L // 16), L * L, rng)
