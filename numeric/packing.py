"""The full N x P hexagonal packing of Secs. 3.2-3.3 and its Metropolis sampler.

Geometry (the reading is argued in ``notes/thesis_reading.md``, "The full
packing"): ``N`` layers of ``P`` grains indexed as in Eqs. (3.4) and (3.9),
grain ``(i, j)`` resting on ``(i+1, j)`` (contact 5) and ``(i+1, j+1)``
(contact 6).  The left column has no upper-left neighbour; the right column
has no lower-right neighbour, so its ``q_{i,P} = 1``; vertical walls act on
the left and right ends of every layer with horizontal forces only, and the
floor carries the bottom layer.  The left wall pushes with ``p_h``
(``F3^{(i,1)} = p_h``); the right-wall force ``F4^{(i,P)}`` follows from
force balance and must be ``>= 0`` like every other force.  The free
parameters are the ``(N-1)(P-1)`` lateral forces ``F4^{(i,j)}``,
``i < N``, ``j < P``: the thesis's ``d_K`` (Sec. 3.2.1), parametrized by
``q_{i,j}`` (Eq. 3.8) with the uniform measure ``prod W_{i,j} dq_{i,j}``
(Eq. 3.10).

Forces (units of the user's choice, all in the same unit):

- top load ``W_ext,j = p_v + F delta_{j, j0}`` enters as ``F1 = F2 = W_ext/sqrt 3``;
- (3.9): ``W_{i,j} = q_{i-1,j} W_{i-1,j} + (1 - q_{i-1,j-1}) W_{i-1,j-1} + m g``,
  ``W_{1,j} = W_ext,j + m g``;
- (3.2)/(3.8): ``F4 = F3 - F2 + (2 q W - m g)/sqrt 3`` for ``i < N``;
- bottom layer: ``F4 = F3 + (F1 - F2)/2`` (horizontal balance on the floor).

Scenes (Sec. 3.3): ``ph=None`` is the fully mobilized limit (every q allowed,
used by the thesis for the gravity scene); gravity ``pv = 0, mg > 0``;
isotropic ``ph = pv = p, mg = 0``.  The fully mobilized scene without gravity
(``pv = mg = 0``) lives on the triangle under the overload:
:class:`numeric.metropolis.TriangleMetropolis` and
:class:`numeric.exact_sampler.ExactSampler`.

Examples
--------
>>> scene = Scene(N=4, P=5, F=10.0, mg=1.0, j0=3)
>>> sampler = PackingMetropolis(scene, seed=1)
>>> chain = sampler.run(sweeps=500, burn_in=100)
>>> chain.shape
(500, 4, 5)
>>> bool(abs(chain[:, -1].sum(axis=1) - (10 + 4 * 5 * 1.0)).max() < 1e-9)  # the floor carries all
True
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = [
    "Scene",
    "PackingMetropolis",
    "forces_from_q",
    "forces_from_lateral",
    "lateral_forces",
    "contact_forces",
    "maximin_network",
    "uniform_networks",
    "response",
]

_C = 2 / math.sqrt(3)
_S3 = math.sqrt(3)


def _positive_int(name, value, minimum):
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise TypeError(f"{name}={value!r}: must be an integer >= {minimum}")
    if value < minimum:
        raise ValueError(f"{name}={value} is out of range: {name} must be >= {minimum}")
    return int(value)


def _nonnegative(name, value):
    value = float(value)
    if not (math.isfinite(value) and value >= 0):
        raise ValueError(f"{name}={value} is out of range: {name} must be a finite number >= 0")
    return value


@dataclass(frozen=True)
class Scene:
    """Boundary conditions of the N x P packing (Fig. 3.1).

    Parameters
    ----------
    N, P : int
        Layers (``>= 2``) and grains per layer (``>= 2``).
    F : float
        Overload on grain ``(1, j0)``.
    j0 : int, optional
        Column of the overload, ``1..P`` (default: the middle, ``(P+1)//2``).
    pv, mg : float
        Top pressure (force per top grain) and grain weight.
    ph : float or None
        Left-wall force per layer; ``None``: large enough for every q in
        [0, 1] to be allowed (the thesis's choice for gravity, Sec. 3.3.2).

    Examples
    --------
    >>> Scene(N=20, P=41, F=10.0, pv=1.0, ph=1.0).j0
    21
    >>> Scene(N=20, P=41, j0=50)
    Traceback (most recent call last):
    ...
    ValueError: j0=50 is out of range: the overload column must be in 1..P = 1..41
    """

    N: int
    P: int
    F: float = 1.0
    j0: int | None = None
    pv: float = 0.0
    mg: float = 0.0
    ph: float | None = None

    def __post_init__(self):
        object.__setattr__(self, "N", _positive_int("N", self.N, 2))
        object.__setattr__(self, "P", _positive_int("P", self.P, 2))
        for name in ("F", "pv", "mg"):
            object.__setattr__(self, name, _nonnegative(name, getattr(self, name)))
        j0 = (self.P + 1) // 2 if self.j0 is None else _positive_int("j0", self.j0, 1)
        if j0 > self.P:
            raise ValueError(f"j0={j0} is out of range: the overload column must be in 1..P = 1..{self.P}")
        object.__setattr__(self, "j0", j0)
        if self.ph is not None:
            ph = float(self.ph)
            if not (math.isfinite(ph) and ph > 0):
                raise ValueError(f"ph={ph} is out of range: ph must be a finite number > 0 (or None)")
            object.__setattr__(self, "ph", ph)
        if self.pv == 0 and self.mg == 0:
            raise ValueError(
                "pv=0 and mg=0: only the triangle under the overload carries load; "
                "use numeric.metropolis.TriangleMetropolis or numeric.exact_sampler.ExactSampler (CLI: omit --P)"
            )

    @property
    def top_load(self) -> np.ndarray:
        """``W_ext,j = p_v + F delta_{j,j0}``."""
        w = np.full(self.P, self.pv)
        w[self.j0 - 1] += self.F
        return w

    @property
    def name(self) -> str:
        if self.mg > 0 and self.pv == 0:
            return "gravity"
        if self.mg == 0 and self.ph is not None and self.ph == self.pv:
            return "isotropic"
        return "general"


def forces_from_q(q: np.ndarray, scene: Scene) -> np.ndarray:
    """``W_{i,j}`` (shape ``(N, P)``) from ``q`` (shape ``(N-1, P)``), Eq. (3.9).

    The last column of ``q`` is ignored (the right column has ``q = 1``).

    Examples
    --------
    >>> s = Scene(N=2, P=2, F=1.0, pv=1.0, j0=1)
    >>> forces_from_q(np.array([[0.25, 0.5]]), s).tolist()
    [[2.0, 1.0], [0.5, 2.5]]
    """
    N, P, mg = scene.N, scene.P, scene.mg
    q = np.array(q, dtype=float)
    q[..., -1] = 1.0
    W = np.empty(q.shape[:-2] + (N, P))
    W[..., 0, :] = scene.top_load + mg
    for i in range(1, N):
        w, qq = W[..., i - 1, :], q[..., i - 1, :]
        W[..., i, :] = qq * w + mg
        W[..., i, 1:] += ((1 - qq) * w)[..., :-1]
    return W


def _lateral_increments(q: np.ndarray, W: np.ndarray, scene: Scene) -> np.ndarray:
    """``F4 - F3`` on every grain (shape ``(N, P)``)."""
    N, mg = scene.N, scene.mg
    q = np.array(q, dtype=float)
    q[:, -1] = 1.0
    F2 = np.empty_like(W)  # force from the upper-right neighbour
    F2[0] = scene.top_load / _S3
    F2[1:] = _C * q * W[:-1]
    d = np.empty_like(W)
    d[: N - 1] = -F2[: N - 1] + (2 * q * W[: N - 1] - mg) / _S3  # Eq. (3.2) with (3.8)
    F1 = np.zeros(W.shape[1])  # bottom layer: force from the upper-left neighbour
    F1[1:] = _C * ((1 - q[-1]) * W[-2])[:-1]
    d[N - 1] = (F1 - F2[N - 1]) / 2
    return d


def lateral_forces(q: np.ndarray, W: np.ndarray, scene: Scene) -> np.ndarray:
    """``F4^{(i,j)}`` on every grain (shape ``(N, P)``); column ``P`` is the right wall.

    Needs a finite ``scene.ph``.

    Examples
    --------
    >>> s = Scene(N=2, P=2, F=1.0, pv=1.0, ph=1.0, j0=1)
    >>> q = np.array([[1.0, 1.0]])
    >>> lateral_forces(q, forces_from_q(q, s), s).round(6).tolist()  # the floor row is pulled apart
    [[2.154701, 2.732051], [-0.154701, -0.732051]]
    """
    if scene.ph is None:
        raise ValueError("scene.ph is None: lateral forces need a finite side pressure ph")
    return scene.ph + np.cumsum(_lateral_increments(q, W, scene), axis=1)


def forces_from_lateral(x: np.ndarray, scene: Scene) -> dict:
    """All contact forces from the free lateral forces ``F4^{(i,j)}``, ``i < N``, ``j < P`` (Sec. 3.2.2).

    ``x`` has shape ``(..., N-1, P-1)``; the result maps ``"F1".."F6"`` to
    arrays of shape ``(..., N, P)``, solved grain by grain from the top left
    with (3.1)-(3.3): ``F5 = F2 + (F4 - F3) + mg/sqrt 3``,
    ``F6 = F1 - (F4 - F3) + mg/sqrt 3``; the right column (no contact 6)
    and the bottom layer have their ``F4`` fixed by balance.  ``scene.ph=None``
    is taken as ``ph = 0`` (only differences of lateral forces matter then).
    Every force is affine in ``x``.

    Examples
    --------
    >>> s = Scene(N=2, P=2, F=1.0, pv=1.0, ph=1.0, j0=1)
    >>> f = forces_from_lateral(np.array([[1.0 + 1 / 3**0.5]]), s)
    >>> [round(float(v), 6) for v in (f["F5"][0, 0], f["F6"][0, 0], f["F4"][1, 1])]
    [1.732051, 0.57735, -0.154701]
    """
    N, P, mg = scene.N, scene.P, scene.mg
    x = np.asarray(x, dtype=float)
    if x.shape[-2:] != (N - 1, P - 1):
        raise ValueError(f"x has shape {x.shape}, expected (..., {N - 1}, {P - 1})")
    shape = x.shape[:-2] + (N, P)
    F = {k: np.zeros(shape) for k in ("F1", "F2", "F3", "F4", "F5", "F6")}
    g = mg / _S3
    ph = 0.0 if scene.ph is None else scene.ph
    F["F1"][..., 0, :] = F["F2"][..., 0, :] = scene.top_load / _S3
    for i in range(N):
        if i > 0:
            F["F2"][..., i, :] = F["F5"][..., i - 1, :]
            F["F1"][..., i, 1:] = F["F6"][..., i - 1, :-1]
        F3 = ph
        for j in range(P):
            F["F3"][..., i, j] = F3
            F1, F2 = F["F1"][..., i, j], F["F2"][..., i, j]
            if i == N - 1:  # on the floor: horizontal balance only
                F4 = F3 + (F1 - F2) / 2
            elif j == P - 1:  # no lower-right contact: F6 = 0 fixes the wall force
                F4 = F3 + F1 + g
                F["F5"][..., i, j] = F2 + F1 + 2 * g
            else:
                F4 = x[..., i, j]
                F["F5"][..., i, j] = F2 + (F4 - F3) + g
                F["F6"][..., i, j] = F1 - (F4 - F3) + g
            F["F4"][..., i, j] = F4
            F3 = F4
    return F


def _affine_constraints(scene: Scene):
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


def uniform_networks(scene: Scene, size: int, rng, batch: int = 200_000):
    """Independent uniform force networks by rejection in the lateral forces (Sec. 3.2.2).

    The route that checks the q-coordinates and the measure of Eq. (3.10):
    the free lateral forces are drawn uniformly in their bounding box (from
    linear programs) and kept when every force is repulsive.  Exponentially
    slow in ``(N-1)(P-1)``; for small packings only.

    Returns ``W`` samples of shape ``(size, N, P)`` and the acceptance rate.
    """
    from scipy.optimize import linprog

    N, P = scene.N, scene.P
    n = (N - 1) * (P - 1)
    if n > 12:
        raise ValueError(f"(N-1)(P-1)={n}: rejection sampling is for at most 12 free lateral forces")
    A, b = _affine_constraints(scene)
    lo, hi = np.empty(n), np.empty(n)
    for k in range(n):
        for sign, out in ((1.0, lo), (-1.0, hi)):
            c = np.zeros(n)
            c[k] = sign
            res = linprog(c, A_ub=-A.T, b_ub=b, bounds=[(None, None)] * n, method="highs")
            if res.status != 0:
                raise ValueError(f"no repulsive force network exists for {scene} ({res.message})")
            out[k] = res.x[k]
    kept, tried = [], 0
    while sum(len(k) for k in kept) < size:
        x = lo + (hi - lo) * rng.random((batch, n))
        tried += batch
        kept.append(x[((x @ A + b) >= 0).all(axis=1)])
        accepted = sum(len(k) for k in kept)
        if accepted < 1e-4 * tried:
            raise ValueError(
                f"acceptance {accepted / tried:.1e} after {tried} draws: the polytope fills too little "
                "of its bounding box for rejection sampling; use PackingMetropolis"
            )
    accepted = sum(len(k) for k in kept)
    x = np.concatenate(kept)[:size]
    f = forces_from_lateral(x.reshape(size, N - 1, P - 1), scene)
    W = np.empty((size, N, P))
    W[:, :-1] = (_S3 / 2) * (f["F5"] + f["F6"])[:, :-1]
    W[:, -1] = (_S3 / 2) * (f["F1"] + f["F2"])[:, -1] + scene.mg
    return W, accepted / tried


def maximin_network(scene: Scene):
    """The free lateral forces maximizing the smallest contact force (a linear program).

    Returns ``(x, slack)``: ``x`` of shape ``(N-1, P-1)`` and the smallest
    force of that network (``<= 0``: no strictly repulsive network exists).
    Needs a finite ``scene.ph``.
    """
    from scipy.optimize import linprog

    if scene.ph is None:
        raise ValueError("scene.ph is None: every q is allowed, no linear program is needed")
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
        raise RuntimeError(f"linear program failed: {res.message}")
    x = res.x[:n]
    slack = float(min(res.x[n], b[~keep].min())) if (~keep).any() else float(res.x[n])
    return x.reshape(N - 1, P - 1), slack


def contact_forces(q: np.ndarray, scene: Scene) -> dict:
    """All contact forces ``F1..F6`` (arrays of shape ``(N, P)``) and the floor forces.

    Absent contacts are 0 (left column F1, right column F6, bottom layer
    F5/F6); ``F3`` of the left column is ``p_h`` and ``F4`` of the right
    column is the right-wall force.  Used to check force balance grain by
    grain.
    """
    N, P = scene.N, scene.P
    q = np.array(q, dtype=float)
    q[:, -1] = 1.0
    W = forces_from_q(q, scene)
    F4 = lateral_forces(q, W, scene)
    F3 = np.empty_like(F4)
    F3[:, 0] = scene.ph
    F3[:, 1:] = F4[:, :-1]
    F5 = np.zeros((N, P))
    F6 = np.zeros((N, P))
    F5[:-1] = _C * q * W[:-1]
    F6[:-1] = _C * (1 - q) * W[:-1]
    F1 = np.zeros((N, P))
    F2 = np.zeros((N, P))
    F1[0] = F2[0] = scene.top_load / _S3
    F2[1:] = F5[:-1]
    F1[1:, 1:] = F6[:-1, :-1]
    floor = np.zeros((N, P))
    floor[-1] = W[-1]
    return {"F1": F1, "F2": F2, "F3": F3, "F4": F4, "F5": F5, "F6": F6, "floor": floor, "W": W}


class PackingMetropolis:
    """Metropolis sampler of Sec. 3.2.4 on the N x P packing.

    A move picks a free grain (``i < N``, ``j < P``), draws its q uniformly in
    [0, 1], recomputes ``W`` in its light cone and (finite ``ph``) every lateral
    force; a negative force rejects the move, otherwise it is accepted with
    probability ``min(1, prod W_new / prod W_old)`` over the free grains
    (Eq. 3.10).

    Parameters
    ----------
    scene : Scene
    seed : int or numpy.random.Generator, optional
    step : float or None
        ``None``: the thesis's move, a new q uniform in [0, 1].  A width in
        (0, 1]: ``q + step * U(-1, 1)`` reflected into [0, 1] (symmetric, so
        the same acceptance rule), for scenes where the F4 >= 0 constraints
        confine q to narrow ranges (Fig. 3.6).
    q0 : array, optional
        Initial state, shape ``(N-1, P)``.  Default: ``q = 1/2`` when every
        q is allowed (``ph=None``); otherwise the network that maximizes the
        smallest force (a linear program, :func:`maximin_network`), with a
        clear error if no repulsive network exists.

    Examples
    --------
    >>> s = Scene(N=5, P=9, F=10.0, pv=1.0, ph=1.0)
    >>> m = PackingMetropolis(s, seed=3)
    >>> chain = m.run(sweeps=200, burn_in=50)
    >>> 0.05 < m.acceptance_rate < 1
    True
    """

    def __init__(self, scene: Scene, seed=None, q0=None, step: float | None = None):
        if not isinstance(scene, Scene):
            raise TypeError(f"scene={scene!r}: expected a numeric.packing.Scene")
        if step is not None and not (0 < step <= 1):
            raise ValueError(f"step={step} is out of range: the proposal width must be in (0, 1] (or None)")
        self.step = step
        self.scene = scene
        self.rng = np.random.default_rng(seed)
        N, P = scene.N, scene.P
        if q0 is None:
            self.q = self._feasible_start()
        else:
            self.q = np.array(q0, dtype=float)
            if self.q.shape != (N - 1, P):
                raise ValueError(f"q0 has shape {self.q.shape}, expected {(N - 1, P)}")
            if ((self.q < 0) | (self.q > 1)).any():
                raise ValueError("q0: every q must lie in [0, 1]")
            self.q[:, -1] = 1.0
        self.W = forces_from_q(self.q, scene)
        if not self._feasible(self.q, self.W):
            raise ValueError("q0: the initial state has a negative force or a zero weight; pass a feasible q0")
        self.grains = [(i, j) for i in range(N - 1) for j in range(P - 1)]
        self.accepted = 0
        self.attempted = 0
        self.rejected_by_constraint = 0

    def _feasible_start(self) -> np.ndarray:
        """``q = 1/2`` (fully mobilized), else the force network of largest minimal force.

        With a finite ``ph`` all forces are affine in the ``(N-1)(P-1)`` free
        lateral forces (Sec. 3.2.2); a linear program maximizes the smallest
        force, which gives a strictly interior start, or proves that no
        repulsive network exists.
        """
        N, P = self.scene.N, self.scene.P
        q = np.full((N - 1, P), 0.5)
        q[:, -1] = 1.0
        if self.scene.ph is None:
            return q
        x, slack = maximin_network(self.scene)
        if slack <= 0:
            raise ValueError(
                f"no force network with all forces > 0 exists for {self.scene}: "
                f"the largest smallest force is {slack:.3g}; raise ph or lower F"
            )
        f = forces_from_lateral(x, self.scene)
        F5, F6 = f["F5"][:-1, :-1], f["F6"][:-1, :-1]
        q[:, :-1] = F5 / (F5 + F6)
        return q

    def _feasible(self, q, W) -> bool:
        if (W[:-1, :-1] <= 0).any():
            return False
        if self.scene.ph is None:
            return True
        return bool((lateral_forces(q, W, self.scene) >= -1e-9 * max(1.0, self.scene.ph)).all())

    @property
    def acceptance_rate(self) -> float:
        return self.accepted / self.attempted if self.attempted else float("nan")

    def _propose(self, i: int, j: int, new: float) -> bool:
        scene, N, P, mg = self.scene, self.scene.N, self.scene.P, self.scene.mg
        old = self.q[i, j]
        self.q[i, j] = new
        W_new = self.W.copy()
        lo, hi = j, j + 1  # the light cone of grain (i, j), Eq. (3.9)
        for k in range(i + 1, N):
            hi = min(P, hi + 1)
            w, qq = W_new[k - 1], self.q[k - 1]
            row = qq[lo:hi] * w[lo:hi] + mg
            left = max(lo, 1)
            row[left - lo :] += (1 - qq[left - 1 : hi - 1]) * w[left - 1 : hi - 1]
            W_new[k, lo:hi] = row
        free_new = W_new[i + 1 : N - 1, lo : P - 1]
        if (free_new <= 0).any():
            self.q[i, j] = old
            return False
        if scene.ph is not None and (lateral_forces(self.q, W_new, scene) < -1e-9 * max(1.0, scene.ph)).any():
            self.rejected_by_constraint += 1
            self.q[i, j] = old
            return False
        log_ratio = float(np.log(free_new).sum() - np.log(self.W[i + 1 : N - 1, lo : P - 1]).sum())
        if log_ratio >= 0 or self.rng.random() < math.exp(log_ratio):
            self.W = W_new
            return True
        self.q[i, j] = old
        return False

    def sweep(self, count: int = 1) -> None:
        """``count`` sweeps of ``(N-1)(P-1)`` single-grain updates."""
        n = len(self.grains)
        for _ in range(count):
            for k, value in zip(self.rng.integers(n, size=n), self.rng.random(n)):
                i, j = self.grains[k]
                if self.step is not None:  # symmetric local move, reflected into [0, 1]
                    value = abs(self.q[i, j] + self.step * (2 * value - 1))
                    value = 2 - value if value > 1 else value
                self.attempted += 1
                if self._propose(i, j, value):
                    self.accepted += 1

    def run(self, sweeps: int, burn_in: int = 0, progress=None, record_q: bool = False):
        """Burn in, then record ``W`` (and ``q`` if asked) after each sweep.

        Returns ``W`` of shape ``(sweeps, N, P)``, or ``(W, q)``.
        """
        if sweeps < 1 or burn_in < 0:
            raise ValueError(f"sweeps={sweeps}, burn_in={burn_in}: need sweeps >= 1 and burn_in >= 0")
        self.sweep(burn_in)
        out = np.empty((sweeps, self.scene.N, self.scene.P))
        qs = np.empty((sweeps,) + self.q.shape) if record_q else None
        for t in range(sweeps):
            self.sweep()
            out[t] = self.W
            if record_q:
                qs[t] = self.q
            if progress is not None:
                progress(1)
        return (out, qs) if record_q else out


def response(scene: Scene, sweeps: int, burn_in: int, seed: int = 0, progress=None):
    """Mean response ``G(i,j) = (<W>_{p+F} - <W>_p)/F`` with standard errors.

    Two independent chains, with and without the overload (Sec. 3.1); each
    error bar comes from the integrated autocorrelation time
    (:func:`numeric.autocorr.mean_and_stderr`, which raises on a chain too
    short to trust), and the two are added in quadrature.

    Returns
    -------
    G, stderr_G, info : arrays of shape ``(N, P)`` and a dict (acceptance, tau).
    """
    from dataclasses import replace

    from numeric.autocorr import mean_and_stderr

    if scene.F <= 0:
        raise ValueError(f"F={scene.F}: the response needs an overload F > 0")
    seeds = np.random.SeedSequence(seed).spawn(2)
    loaded = PackingMetropolis(scene, seed=np.random.default_rng(seeds[0]))
    base = PackingMetropolis(replace(scene, F=0.0), seed=np.random.default_rng(seeds[1]))
    m1, e1, t1 = mean_and_stderr(loaded.run(sweeps, burn_in, progress))
    m0, e0, t0 = mean_and_stderr(base.run(sweeps, burn_in, progress))
    G = (m1 - m0) / scene.F
    err = np.hypot(e1, e0) / scene.F
    info = {
        "acceptance": [loaded.acceptance_rate, base.acceptance_rate],
        "tau_max": float(max(t1.max(), t0.max())),
    }
    return G, err, info
