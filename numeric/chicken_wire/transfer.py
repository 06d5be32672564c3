"""Floating-point transfer matrix of the chicken-wire model (Sec. 7.4.1) on a cylinder.

The row-to-row transfer matrix of :mod:`forcenet.exact.chicken_wire.model` acts on
``3^L`` states; here it is applied without being stored, as a matrix
product operator of bond dimension 2 (the horizontal bond) followed by the
move of the particles to the next row, and its largest eigenvalue comes from
ARPACK (``scipy.sparse.linalg.eigs``).  One product costs ``O(L 3^L)``.

Vertex weights are given per vertex name (``"empty", "Y", "inverted Y",
"H", "R", "L"``).  Two families are used:

- bond fugacity ``t``: every occupied bond weighs ``t`` (vertex weight
  ``t^(degree/2)``); isotropic, so the three particle densities are equal;
- tiling vertices: a chicken-wire site with ``d`` bonds stands for
  ``max(1, d)`` vertices of the square-triangle tiling (Fig. 7.9), weight
  ``exp(-sigma max(1, d))``.

Examples
--------
>>> largest_eigenvalue(4)  # the empty row and a horizontal line around the cylinder
2.0
>>> round(largest_eigenvalue(7, particles=2), 12)  # 2 cos(pi/7)
1.801937735805
"""

from __future__ import annotations

import math
from itertools import combinations
from typing import TYPE_CHECKING, Any

import flint
import mpmath
import numpy as np
from scipy.sparse import csr_matrix
from scipy.sparse.linalg import LinearOperator, eigs

from forcenet.core.errors import ArgumentError
from forcenet.core.plan import Plan
from forcenet.core.validation import check_dps, check_int, check_real
from forcenet.exact.chicken_wire.model import EMPTY as _E
from forcenet.exact.chicken_wire.model import LEFT as _L
from forcenet.exact.chicken_wire.model import RIGHT as _R
from forcenet.exact.chicken_wire.model import SITE_CHOICES, VERTICES
from forcenet.exact.chicken_wire.sectors import sector_polynomial_factors

if TYPE_CHECKING:
    import mpmath
    from scipy.sparse import csr_matrix

__all__ = [
    "TRANSFER_SECONDS",
    "transfer_plan",
    "largest_eigenvalue",
    "sector_entropy",
    "perron_root",
    "sector_entropies",
    "sector_matrix",
    "bond_fugacity_weights",
    "tiling_weights",
    "free_energy",
    "isotropic_entropy",
    "tiling_entropy",
]


# measured seconds of all sectors of the transfer matrix (2-core machine); memory ~ 40 * 3^L bytes per vector
TRANSFER_SECONDS = {8: 0.3, 9: 2, 10: 15, 11: 70, 12: 150, 13: 900}


def transfer_plan(L: int, particles: int | None = None) -> Plan:
    """The cost of :func:`largest_eigenvalue` in one sector (``particles``) or in all ``L + 1`` of them.

    Seconds from the measured all-sector times :data:`TRANSFER_SECONDS`
    (shared evenly by the sectors); memory ``60 * 3^L`` bytes (the vectors of
    the matrix-product operator); one tick per sector.

    Parameters
    ----------
    L : int
        Cylinder width, ``2 <= L <= 14``.
    particles : int, optional
        One sector only, ``0 <= particles <= L`` (default: all).

    Returns
    -------
    Plan
        Refused (naming ``particles``) if the sector does not exist.

    Raises
    ------
    ArgumentError
        If ``L`` is out of range.

    Examples
    --------
    >>> transfer_plan(10).seconds, transfer_plan(10, particles=3).seconds
    (15.0, 1.3636363636363635)
    >>> transfer_plan(6, particles=7).refusal
    'particles=7 is out of range: particles must be an integer in 0..L = 0..6'
    """
    L = check_int(L, "L", 2, 14)
    if particles is not None:
        particles = check_int(particles, "particles", 0)
        if particles > L:
            return Plan(f"transfer matrix L={L}", 0,
                        refusal=f"particles={particles} is out of range: particles must be an integer in 0..L = 0..{L}")
    sectors = 1 if particles is not None else L + 1
    # beyond the table: the measured growth from L = 12 to 13 (sixfold per unit of width)
    total = TRANSFER_SECONDS[13] * 6.0 ** (L - 13) if L > 13 else TRANSFER_SECONDS.get(L, 0.1)
    seconds = total * sectors / (L + 1)
    return Plan(f"transfer matrix L={L}, {sectors} sector(s) of up to 3^{L} states", seconds, 60 * 3**L, sectors, "sector")


def _local_tensor(weights: dict[str, float] | None) -> np.ndarray:
    """``a[d, u, h_left, h_right]``: weight of a site with incoming ``d`` and outgoing ``u``."""
    w = {name: 1.0 for name in VERTICES}
    if weights is not None:
        unknown = set(weights) - set(VERTICES)
        if unknown:
            raise ArgumentError(f"weights: unknown vertex names {sorted(unknown)}; allowed {list(VERTICES)}")
        for name, value in weights.items():
            value = float(value)
            if not (math.isfinite(value) and value >= 0):
                raise ArgumentError(f"weights[{name!r}]={value}: weights must be finite and >= 0")
            w[name] = value
    a = np.zeros((3, 3, 2, 2))
    for incoming, choices in SITE_CHOICES.items():
        for left, right, outgoing, name in choices:
            a[incoming, outgoing, left, right] = w[name]
    return a


def _shift_index(L: int) -> np.ndarray:
    """Index of the next row's incoming state for each outgoing state (-1: collision)."""
    digits = np.indices((3,) * L).reshape(L, -1)  # digits[x] = state of site x
    nxt = np.zeros_like(digits)
    bad = np.zeros(digits.shape[1], dtype=bool)
    for x in range(L):
        isR = digits[x] == _R
        isL = digits[(x + 1) % L] == _L  # an L leaving x+1 enters x
        bad |= isR & isL
        nxt[x] = np.where(isR, _R, np.where(isL, _L, _E))
    index = np.asarray(np.ravel_multi_index(tuple(nxt), (3,) * L))
    index[bad] = -1
    return index


class _Operator:
    def __init__(self, L: int, weights: dict[str, float] | None) -> None:
        self.L = L
        self.a = _local_tensor(weights)
        self.entries = [tuple(int(c) for c in idx) for idx in zip(*np.nonzero(self.a))]
        self.shift = _shift_index(L)
        self.valid = self.shift >= 0

    def matvec(self, v: np.ndarray) -> np.ndarray:
        L, a = self.L, self.a
        v = np.asarray(v).reshape(-1)
        out = np.zeros(3**L, dtype=np.result_type(v, float))
        for seam in (0, 1):  # the horizontal bond crossing the cylinder's seam
            t = np.zeros((3**L, 2), dtype=out.dtype)
            t[:, seam] = v
            for x in range(L):  # site x: contract its incoming digit and the carried bond
                t = t.reshape(3**x, 3, 3 ** (L - x - 1), 2)
                new = np.zeros_like(t)
                for i, u, h, k in self.entries:  # the six vertices; elementwise, so bitwise reproducible
                    new[:, u, :, k] += a[i, u, h, k] * t[:, i, :, h]
                t = new
            out += t.reshape(3**L, 2)[:, seam]
        w = np.zeros_like(out)
        w[self.shift[self.valid]] = out[self.valid]
        return w


def largest_eigenvalue(L: int, weights: dict[str, float] | None = None, particles: int | None = None, tol: float = 1e-14) -> float:
    """Largest eigenvalue of the row-to-row transfer matrix on a cylinder of width ``L``.

    Parameters
    ----------
    L : int
        Width, ``2 <= L <= 14`` (memory ``~ 40 * 3^L`` bytes per vector).
    weights : dict, optional
        Vertex weights by name (default all 1: plain counting).
    particles : int, optional
        Restrict to the sector with this many particles per row (conserved).

    Examples
    --------
    >>> round(largest_eigenvalue(8, particles=4), 12)  # the golden ratio
    1.61803398875
    """

    L = check_int(L, "L", 2, 14)
    op = _Operator(L, weights)
    n = 3**L
    if particles is None:
        keep = np.ones(n, dtype=bool)
    else:
        particles = check_int(particles, "particles", 0, L)
        keep = (np.indices((3,) * L).reshape(L, -1) > 0).sum(axis=0) == particles
    sel = np.flatnonzero(keep)

    def matvec(v: np.ndarray) -> np.ndarray:  # the transfer matrix restricted to the kept states
        full = np.zeros(n)
        full[sel] = np.asarray(v).reshape(-1)
        return op.matvec(full)[sel]

    m = len(sel)
    if m <= 800:  # small: dense
        M = np.column_stack([matvec(e) for e in np.eye(m)])
        return float(np.linalg.eigvals(M).real.max())
    A = LinearOperator((m, m), matvec=matvec, dtype=float)
    vals = eigs(A, k=1, which="LR", v0=np.ones(m), tol=tol, return_eigenvectors=False)
    return float(vals.real.max())


def sector_entropy(L: int, particles: int | None = None) -> tuple[float, float]:
    """The largest eigenvalue of a sector and its entropy per site, ``log(lambda) / L``.

    Examples
    --------
    >>> lam, s = sector_entropy(6, particles=2)
    >>> round(lam, 6), round(s, 6)
    (1.732051, 0.091551)
    """
    lam = largest_eigenvalue(L, particles=particles)
    return lam, math.log(lam) / L


def perron_root(L: int, particles: int | None = None, dps: int = 50) -> tuple[list[int], mpmath.mpf]:
    """Largest eigenvalue of the unweighted transfer matrix (a sector or all), to ``dps`` digits.

    The exact integer factors of the characteristic polynomial
    (:func:`forcenet.exact.chicken_wire.sectors.sector_polynomial_factors`)
    have their real roots isolated with ball arithmetic (python-flint, at
    ``dps`` plus guard digits inside ``flint.ctx.workdps``: no global
    precision is touched); the largest one is the Perron root.

    Returns
    -------
    (list of int, mpmath.mpf)
        The minimal polynomial of the root (integer coefficients, constant
        term first) and the root rounded to ``dps`` digits.

    Examples
    --------
    >>> import mpmath
    >>> perron_root(3)
    ([-2, 1], mpf('2.0'))
    >>> poly, lam = perron_root(6, particles=3, dps=30)
    >>> poly, mpmath.nstr(lam, 30)  # 2^(1/3)
    ([-2, 0, 0, 1], '1.25992104989487316476721060728')
    """

    dps = check_dps(dps)
    factors = sector_polynomial_factors(L, particles)
    guard = dps + 10
    best: tuple[list[int], mpmath.mpf] | None = None
    with flint.ctx.workdps(guard), mpmath.workdps(guard):
        for coeffs, _ in factors:
            roots: list[tuple[Any, int]] = flint.fmpz_poly(coeffs).complex_roots()  # type: ignore[assignment]  # flint's stub says one acb; it returns (root, multiplicity) pairs
            for root, _ in roots:
                if root.imag.contains(0):  # a real root, certified by ball arithmetic
                    value = mpmath.mpf(root.real.mid().str(guard, radius=False))
                    if best is None or value > best[1]:
                        best = (coeffs, value)
    if best is None:  # every factor of degree >= 1 has a real Perron root: a bug if not
        raise ArithmeticError(f"no real root among the sector polynomials of L={L}")
    with mpmath.workdps(dps):
        return best[0], +best[1]


def sector_entropies(L: int) -> dict:
    """``{n: log(lambda_n)/L}`` for every particle number ``n`` of the cylinder of width ``L``.

    The largest over ``n >= 1`` estimates the maximal entropy per site of the
    chicken-wire model (``n = 0`` is the empty row, whose ``lambda = 2``
    counts a horizontal line wrapping the cylinder).
    """
    return {k: math.log(largest_eigenvalue(L, particles=k)) / L for k in range(L + 1)}


def bond_fugacity_weights(t: float) -> dict:
    """Vertex weights ``t^(degree/2)``: every occupied bond weighs ``t``."""
    s = math.sqrt(t)
    return {"empty": 1.0, "H": t, "R": t, "L": t, "Y": t * s, "inverted Y": t * s}


def tiling_weights(sigma: float) -> dict:
    """Vertex weights ``exp(-sigma max(1, degree))`` counting square-triangle tiling vertices."""
    e = math.exp(-sigma)
    return {"empty": e, "H": e**2, "R": e**2, "L": e**2, "Y": e**3, "inverted Y": e**3}


def free_energy(L: int, weights: dict[str, float] | None = None) -> float:
    """``(1/L) log lambda_max``: free energy per site of the cylinder of width ``L``."""
    return math.log(largest_eigenvalue(L, weights)) / L


def isotropic_entropy(L: int, t: float, h: float = 1e-4) -> tuple[float, float]:
    """Entropy per site and density ``Q`` of left-moving particles at bond fugacity ``t``.

    Legendre transform of ``f(mu) = free_energy(L, t = e^mu)``:
    ``b = df/dmu`` bonds per site (central difference of width ``h``),
    ``Q = b/3`` per direction (isotropy), ``s = f - mu b``.

    Returns ``(s, Q)``.
    """
    mu = math.log(t)
    f = free_energy(L, bond_fugacity_weights(t))
    fp = free_energy(L, bond_fugacity_weights(math.exp(mu + h)))
    fm = free_energy(L, bond_fugacity_weights(math.exp(mu - h)))
    b = (fp - fm) / (2 * h)
    return f - mu * b, b / 3


def tiling_entropy(L: int, bracket: tuple[float, float] = (0.01, 1.0), xtol: float = 1e-13) -> float:
    """Entropy per tiling vertex on a cylinder of width ``L``: the root of ``f(sigma) = 0``.

    With weights :func:`tiling_weights`, ``log Z / area = max_v (s(v) - sigma v)``
    over the density ``v`` of tiling vertices, which vanishes exactly at
    ``sigma = max_v s(v)/v``: the maximal entropy per vertex of the
    square-triangle tiling (in the limit ``L -> infinity``).
    """
    from scipy.optimize import brentq  # scipy.optimize is heavy: loaded when a tiling entropy is solved

    return brentq(lambda s: free_energy(L, tiling_weights(s)), *bracket, xtol=xtol)


def sector_matrix(L: int, n: int, m: int, photon_fugacity: float = 1.0, hop_fugacity: float = 1.0) -> csr_matrix:
    """Sparse transfer matrix restricted to ``n`` particles of which ``m`` are left-moving.

    Built from the particle picture (Sec. 7.4.1): every R followed by an L
    (next particle to the right, cyclically) may exchange kinds through a
    photon; then R's stay and L's move one site left; collisions are
    forbidden.  Independent of the matrix-product-operator route, and only
    ``C(L, n) C(n, m)`` states, so ``L = 18`` is within reach.

    ``photon_fugacity`` weighs every horizontal bond: a photon from the R at
    ``x_j`` to the L at ``x_{j+1}`` has ``(x_{j+1} - x_j) mod L`` bonds.
    ``hop_fugacity`` weighs every photon exchange (one Y and one inverted Y).

    Returns
    -------
    scipy.sparse.csr_matrix
    """

    L = check_int(L, "L", 2)
    n = check_int(n, "n", 0, L)
    m = check_int(m, "m", 0, n)
    states: list[tuple[tuple[int, ...], tuple[int, ...]]] = []
    for pos in combinations(range(L), n):
        for lab in combinations(range(n), m):
            labels = [_R] * n
            for j in lab:
                labels[j] = _L
            states.append((pos, tuple(labels)))
    if len(states) > 5_000_000:
        raise ArgumentError(f"sector of {len(states)} states is too large (limit 5,000,000)")
    index = {s: i for i, s in enumerate(states)}
    photon_fugacity = check_real(photon_fugacity, "photon_fugacity", 0, low_open=True)
    hop_fugacity = check_real(hop_fugacity, "hop_fugacity", 0, low_open=True)
    rows, cols, vals = [], [], []
    for i, (pos, kinds) in enumerate(states):
        pairs = [j for j in range(n) if kinds[j] == _R and kinds[(j + 1) % n] == _L]
        for r in range(len(pairs) + 1):
            for sub in combinations(pairs, r):
                new = list(kinds)
                for j in sub:
                    new[j], new[(j + 1) % n] = _L, _R
                newpos = [(pos[j] - 1) % L if new[j] == _L else pos[j] for j in range(n)]
                if len(set(newpos)) < n:
                    continue
                order = sorted(range(n), key=newpos.__getitem__)
                rows.append(index[(tuple(newpos[j] for j in order), tuple(new[j] for j in order))])
                cols.append(i)
                bonds = sum((pos[(j + 1) % n] - pos[j]) % L for j in sub)
                vals.append(photon_fugacity**bonds * hop_fugacity ** len(sub))
    return csr_matrix((np.array(vals, dtype=float), (rows, cols)), shape=(len(states), len(states)))
