"""The full N x P hexagonal packing of Secs. 3.2-3.3: scenes and forces.

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
:class:`forcenet.numeric.triangle.TriangleMetropolis` and
:class:`forcenet.numeric.triangle.ExactSampler`.

The sampler is :mod:`.metropolis`, the independent rejection route and the
maximin network :mod:`.networks`.

Examples
--------
>>> scene = Scene(N=4, P=5, F=10.0, mg=1.0, j0=3)
>>> W = forces_from_q(np.full((4, 5), 0.5), scene)
>>> bool(abs(W[-1].sum() - (10 + 4 * 5 * 1.0)) < 1e-9)  # the floor carries all
True
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from forcenet.core.errors import ArgumentError
from forcenet.core.validation import check_int, check_real

__all__ = ["Scene", "forces_from_q", "forces_from_lateral", "lateral_forces", "lateral_increments", "contact_forces",
           "SQRT3"]

_C = 2 / math.sqrt(3)
SQRT3 = math.sqrt(3)  # the contact geometry of the triangular lattice (Eqs. 3.1-3.3)


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

    Raises
    ------
    forcenet.core.errors.ArgumentError
        On ``N`` or ``P`` below 2, ``j0`` outside ``1..P``, a negative load, a ``ph`` that is not positive, or
        ``pv = mg = 0`` (only the triangle under the overload: use the triangle's samplers).

    Examples
    --------
    >>> Scene(N=20, P=41, F=10.0, pv=1.0, ph=1.0).j0
    21
    >>> Scene(N=20, P=41, j0=50)
    Traceback (most recent call last):
    ...
    forcenet.core.errors.ArgumentError: j0=50 is out of range: j0 must be an integer in 1..41
    """

    N: int
    P: int
    F: float = 1.0
    j0: int | None = None
    pv: float = 0.0
    mg: float = 0.0
    ph: float | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "N", check_int(self.N, "N", 2))
        object.__setattr__(self, "P", check_int(self.P, "P", 2))
        for name in ("F", "pv", "mg"):
            object.__setattr__(self, name, check_real(getattr(self, name), name, 0))
        j0 = (self.P + 1) // 2 if self.j0 is None else check_int(self.j0, "j0", 1, self.P)
        object.__setattr__(self, "j0", j0)
        if self.ph is not None:
            object.__setattr__(self, "ph", check_real(self.ph, "ph", 0, low_open=True))
        if self.pv == 0 and self.mg == 0:
            raise ArgumentError(
                "pv=0 and mg=0: only the triangle under the overload carries load; "
                "use forcenet.numeric.triangle.TriangleMetropolis or forcenet.numeric.triangle.ExactSampler (CLI: omit --P)"
            )

    @property
    def top_load(self) -> np.ndarray:
        """The load on the top layer, ``W_ext,j = p_v + F delta_{j,j0}`` (Fig. 3.1).

        Examples
        --------
        >>> Scene(N=3, P=5, F=10.0, pv=1.0).top_load.tolist()
        [1.0, 1.0, 11.0, 1.0, 1.0]
        """
        w = np.full(self.P, self.pv)
        j0 = self.j0 if self.j0 is not None else (self.P + 1) // 2  # set by __post_init__
        w[j0 - 1] += self.F
        return w

    @property
    def name(self) -> str:
        """The kind of scene: ``"gravity"`` (``mg > 0``, no top pressure), ``"isotropic"`` (no weight, ``ph = pv``) or ``"general"``.

        Examples
        --------
        >>> Scene(N=3, P=5, mg=1.0).name, Scene(N=3, P=5, pv=1.0, ph=1.0).name, Scene(N=3, P=5, pv=1.0).name
        ('gravity', 'isotropic', 'general')
        """
        if self.mg > 0 and self.pv == 0:
            return "gravity"
        if self.mg == 0 and self.ph is not None and self.ph == self.pv:
            return "isotropic"
        return "general"


def forces_from_q(q: np.ndarray, scene: Scene) -> np.ndarray:
    """``W_{i,j}`` (shape ``(N, P)``) from ``q`` (shape ``(N-1, P)``), Eq. (3.9).

    The last column of ``q`` is ignored (the right column has ``q = 1``).

    Parameters
    ----------
    q : numpy.ndarray
        Shape ``(..., N-1, P)``, entries in [0, 1].
    scene : Scene
        The boundary conditions.

    Returns
    -------
    numpy.ndarray
        Shape ``(..., N, P)``.

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


def lateral_increments(q: np.ndarray, W: np.ndarray, scene: Scene) -> np.ndarray:
    """``F4 - F3`` on every grain (shape ``(N, P)``): the lateral forces are ``p_h`` plus their running sums.

    Parameters
    ----------
    q : numpy.ndarray
        The q-coordinates, shape ``(N-1, P)`` (the last column is taken as 1).
    W : numpy.ndarray
        The loads from ``q`` (:func:`forces_from_q`), shape ``(N, P)``.
    scene : Scene
        The boundary conditions.

    Returns
    -------
    numpy.ndarray
        Shape ``(N, P)``.

    Examples
    --------
    >>> s = Scene(N=2, P=2, F=1.0, pv=1.0, ph=1.0, j0=1)
    >>> q = np.array([[1.0, 1.0]])
    >>> lateral_increments(q, forces_from_q(q, s), s).round(6).tolist()
    [[1.154701, 0.57735], [-1.154701, -0.57735]]
    """
    N, mg = scene.N, scene.mg
    q = np.array(q, dtype=float)
    q[:, -1] = 1.0
    F2 = np.empty_like(W)  # force from the upper-right neighbour
    F2[0] = scene.top_load / SQRT3
    F2[1:] = _C * q * W[:-1]
    d = np.empty_like(W)
    d[: N - 1] = -F2[: N - 1] + (2 * q * W[: N - 1] - mg) / SQRT3  # Eq. (3.2) with (3.8)
    F1 = np.zeros(W.shape[1])  # bottom layer: force from the upper-left neighbour
    F1[1:] = _C * ((1 - q[-1]) * W[-2])[:-1]
    d[N - 1] = (F1 - F2[N - 1]) / 2
    return d


def lateral_forces(q: np.ndarray, W: np.ndarray, scene: Scene) -> np.ndarray:
    """``F4^{(i,j)}`` on every grain (shape ``(N, P)``); column ``P`` is the right wall.

    Parameters
    ----------
    q : numpy.ndarray
        The q-coordinates, shape ``(N-1, P)``.
    W : numpy.ndarray
        The loads from ``q`` (:func:`forces_from_q`), shape ``(N, P)``.
    scene : Scene
        The boundary conditions, with a finite ``ph``.

    Returns
    -------
    numpy.ndarray
        Shape ``(N, P)``.

    Raises
    ------
    forcenet.core.errors.ArgumentError
        If ``scene.ph`` is None.

    Examples
    --------
    >>> s = Scene(N=2, P=2, F=1.0, pv=1.0, ph=1.0, j0=1)
    >>> q = np.array([[1.0, 1.0]])
    >>> lateral_forces(q, forces_from_q(q, s), s).round(6).tolist()  # the floor row is pulled apart
    [[2.154701, 2.732051], [-0.154701, -0.732051]]
    """
    if scene.ph is None:
        raise ArgumentError("scene.ph is None: lateral forces need a finite side pressure ph")
    return scene.ph + np.cumsum(lateral_increments(q, W, scene), axis=1)


def forces_from_lateral(x: np.ndarray, scene: Scene) -> dict:
    """All contact forces from the free lateral forces ``F4^{(i,j)}``, ``i < N``, ``j < P`` (Sec. 3.2.2).

    ``x`` has shape ``(..., N-1, P-1)``; the result maps ``"F1".."F6"`` to
    arrays of shape ``(..., N, P)``, solved grain by grain from the top left
    with (3.1)-(3.3): ``F5 = F2 + (F4 - F3) + mg/sqrt 3``,
    ``F6 = F1 - (F4 - F3) + mg/sqrt 3``; the right column (no contact 6)
    and the bottom layer have their ``F4`` fixed by balance.  ``scene.ph=None``
    is taken as ``ph = 0`` (only differences of lateral forces matter then).
    Every force is affine in ``x``.

    Parameters
    ----------
    x : numpy.ndarray
        The free lateral forces, shape ``(..., N-1, P-1)``.
    scene : Scene
        The boundary conditions.

    Returns
    -------
    dict
        ``"F1"`` .. ``"F6"``: arrays of shape ``(..., N, P)``.

    Raises
    ------
    forcenet.core.errors.ArgumentError
        If ``x`` has the wrong shape.

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
        raise ArgumentError(f"x has shape {x.shape}, expected (..., {N - 1}, {P - 1})")
    shape = x.shape[:-2] + (N, P)
    F = {k: np.zeros(shape) for k in ("F1", "F2", "F3", "F4", "F5", "F6")}
    g = mg / SQRT3
    ph = 0.0 if scene.ph is None else scene.ph
    F3: float | np.ndarray
    F["F1"][..., 0, :] = F["F2"][..., 0, :] = scene.top_load / SQRT3
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


def contact_forces(q: np.ndarray, scene: Scene) -> dict:
    """All contact forces ``F1..F6`` (arrays of shape ``(N, P)``) and the floor forces.

    Absent contacts are 0 (left column F1, right column F6, bottom layer
    F5/F6); ``F3`` of the left column is ``p_h`` and ``F4`` of the right
    column is the right-wall force.  Used to check force balance grain by
    grain.

    Parameters
    ----------
    q : numpy.ndarray
        The q-coordinates, shape ``(N-1, P)``.
    scene : Scene
        The boundary conditions, with a finite ``ph``.

    Returns
    -------
    dict
        ``"F1"`` .. ``"F6"``, ``"floor"`` (the floor's forces, bottom layer) and ``"W"``: arrays ``(N, P)``.

    Raises
    ------
    forcenet.core.errors.ArgumentError
        If ``scene.ph`` is None.

    Examples
    --------
    >>> s = Scene(N=2, P=2, F=1.0, pv=1.0, ph=1.0, j0=1)
    >>> f = contact_forces(np.array([[0.5, 1.0]]), s)
    >>> bool(np.allclose(f["floor"][-1], f["W"][-1]))
    True
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
    F1[0] = F2[0] = scene.top_load / SQRT3
    F2[1:] = F5[:-1]
    F1[1:, 1:] = F6[:-1, :-1]
    floor = np.zeros((N, P))
    floor[-1] = W[-1]
    return {"F1": F1, "F2": F2, "F3": F3, "F4": F4, "F5": F5, "F6": F6, "floor": floor, "W": W}
