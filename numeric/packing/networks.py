"""Independent routes on the N x P packing: rejection sampling and the maximin network (Sec. 3.2.2).

:func:`uniform_networks` draws the free lateral forces uniformly in their
bounding box and keeps the repulsive networks: independent uniform samples
that check the q-coordinates and the measure (3.10) of the Metropolis
sampler.  :func:`maximin_network` is the linear program that maximizes the
smallest contact force (a feasible start, or a proof that none exists).
"""

from __future__ import annotations

import numpy as np

from forcenet.core.errors import ArgumentError, ConvergenceError

from .scene import SQRT3, Scene, forces_from_lateral

__all__ = ["uniform_networks", "maximin_network"]


def _affine_constraints(scene: Scene) -> tuple[np.ndarray, np.ndarray]:
    """``(A, b)`` with the constrained forces ``= x @ A + b`` (flattened ``x``).

    Constrained: ``F5``/``F6`` of every existing contact, and with a finite
    ``ph`` every ``F4`` (internal, right wall, bottom layer).
    """
    N, P = scene.N, scene.P
    n = (N - 1) * (P - 1)
    basis = np.concatenate([np.zeros((1, n)), np.eye(n)]).reshape(n + 1, N - 1, P - 1)
    forces = forces_from_lateral(basis, scene)
    rows = [forces["F5"][:, :-1, :].reshape(n + 1, -1)]
    rows.append(forces["F6"][:, :-1, :-1].reshape(n + 1, -1))  # the right column has no contact 6
    if scene.ph is not None:
        rows.append(forces["F4"].reshape(n + 1, -1))
    M = np.concatenate(rows, axis=1)
    return M[1:] - M[0], M[0]


def uniform_networks(scene: Scene, size: int, rng: np.random.Generator, batch: int = 200_000) -> tuple[np.ndarray, float]:
    """Independent uniform force networks by rejection in the lateral forces (Sec. 3.2.2).

    The route that checks the q-coordinates and the measure of Eq. (3.10):
    the free lateral forces are drawn uniformly in their bounding box (from
    linear programs) and kept when every force is repulsive.  Exponentially
    slow in ``(N-1)(P-1)``; for small packings only.

    Parameters
    ----------
    scene : Scene
        The packing, ``(N-1)(P-1) <= 12``.
    size : int
        Networks to draw.
    rng : numpy.random.Generator
        The stream.
    batch : int
        Candidates per round.

    Returns
    -------
    W : numpy.ndarray
        Shape ``(size, N, P)``.
    acceptance : float
        The fraction of candidates kept.

    Raises
    ------
    forcenet.core.errors.ArgumentError
        If the packing is too large, no repulsive network exists, or the acceptance is below ``1e-4``.

    Examples
    --------
    >>> W, rate = uniform_networks(Scene(N=2, P=2, F=1.0, pv=1.0, ph=1.0), 100, np.random.default_rng(0))
    >>> W.shape, 0 < rate <= 1
    ((100, 2, 2), True)
    """
    from scipy.optimize import linprog  # scipy.optimize is heavy: loaded when a packing is solved

    N, P = scene.N, scene.P
    n = (N - 1) * (P - 1)
    if n > 12:
        raise ArgumentError(f"(N-1)(P-1)={n}: rejection sampling is for at most 12 free lateral forces")
    A, b = _affine_constraints(scene)
    lo, hi = np.empty(n), np.empty(n)
    for k in range(n):
        for sign, out in ((1.0, lo), (-1.0, hi)):
            c = np.zeros(n)
            c[k] = sign
            res = linprog(c, A_ub=-A.T, b_ub=b, bounds=[(None, None)] * n, method="highs")
            if res.status != 0:
                raise ArgumentError(f"no repulsive force network exists for {scene} ({res.message})")
            out[k] = res.x[k]
    kept: list[np.ndarray] = []
    tried = 0
    while sum(len(k) for k in kept) < size:
        x = lo + (hi - lo) * rng.random((batch, n))
        tried += batch
        kept.append(x[((x @ A + b) >= 0).all(axis=1)])
        accepted = sum(len(k) for k in kept)
        if accepted < 1e-4 * tried:
            raise ArgumentError(
                f"acceptance {accepted / tried:.1e} after {tried} draws: the polytope fills too little "
                "of its bounding box for rejection sampling; use PackingMetropolis"
            )
    accepted = sum(len(k) for k in kept)
    x = np.concatenate(kept)[:size]
    f = forces_from_lateral(x.reshape(size, N - 1, P - 1), scene)
    W = np.empty((size, N, P))
    W[:, :-1] = (SQRT3 / 2) * (f["F5"] + f["F6"])[:, :-1]
    W[:, -1] = (SQRT3 / 2) * (f["F1"] + f["F2"])[:, -1] + scene.mg
    return W, accepted / tried


def maximin_network(scene: Scene) -> tuple[np.ndarray, float]:
    """The free lateral forces maximizing the smallest contact force (a linear program).

    Returns ``(x, slack)``: ``x`` of shape ``(N-1, P-1)`` and the smallest
    force of that network (``<= 0``: no strictly repulsive network exists).

    Parameters
    ----------
    scene : Scene
        The packing, with a finite ``ph``.

    Returns
    -------
    x : numpy.ndarray
        Shape ``(N-1, P-1)``.
    slack : float
        The smallest contact force of that network.

    Raises
    ------
    forcenet.core.errors.ArgumentError
        If ``scene.ph`` is None.
    ConvergenceError
        If the linear program fails (also a ``RuntimeError``).

    Examples
    --------
    >>> x, slack = maximin_network(Scene(N=2, P=2, F=1.0, pv=1.0, ph=1.0))
    >>> x.shape, bool(slack > 0)
    ((1, 1), True)
    """
    from scipy.optimize import linprog  # scipy.optimize is heavy: loaded when a packing is solved

    if scene.ph is None:
        raise ArgumentError("scene.ph is None: every q is allowed, no linear program is needed")
    N, P = scene.N, scene.P
    n = (N - 1) * (P - 1)
    A, b = _affine_constraints(scene)
    keep = np.abs(A).sum(axis=0) > 0
    # maximize t subject to x @ A + b >= t on the forces that depend on x;
    # the fixed ones (b only) enter the reported slack
    A_ub = np.hstack([-A[:, keep].T, np.ones((int(keep.sum()), 1))])
    res = linprog(
        c=np.r_[np.zeros(n), -1.0],
        A_ub=A_ub,
        b_ub=b[keep],
        bounds=[(None, None)] * n + [(None, float(np.abs(b).max() + 1))],
        method="highs",
    )
    if res.status != 0:
        raise ConvergenceError(f"the maximin linear program of {scene} failed: {res.message}; "
                               "check that the scene's loads can be balanced (forcenet.numeric.packing.scene)")
    x = res.x[:n]
    slack = float(min(res.x[n], b[~keep].min())) if (~keep).any() else float(res.x[n])
    return x.reshape(N - 1, P - 1), slack
