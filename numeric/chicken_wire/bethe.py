"""Nested Bethe ansatz for the chicken-wire transfer matrix (Sec. 7.4.1).

Derivation: ``notes/chicken_wire.md``, Sec. 5.  In the sector with ``n``
particles per row, ``m`` of them left-moving, the largest eigenvalue of the
row-to-row transfer matrix (all vertex weights 1) is ``Lambda = prod_l u_l``
where ``w_1..w_n`` (inverse particle momenta) and ``u_1..u_m`` (label
rapidities) solve

    prod_l (u_l - w_k)  = (-1)^(n-1) W w_k^(L-n+m),      k = 1..n,
    prod_j (u_l - w_j)  = (-1)^(m-1) W u_l^m / U,         l = 1..m,

with ``W = prod_j w_j`` and ``U = prod_l u_l``.  Every eigenvalue of the sector
comes from some solution; the largest (translation-invariant, ``W = 1``)
has ``w`` and ``u`` symmetric about the real axis (for even ``n`` every
``|w_k| = 1``).  The equations are checked against the transfer
matrix in ``tests/test_bethe.py``.

Examples
--------
>>> sol = solve_ground_state(9, 4, 2)
>>> round(sol.eigenvalue, 12)
1.855529779351
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable, Iterable
from dataclasses import dataclass
from typing import Any, TypeVar

import numpy as np
from threadpoolctl import threadpool_limits

from forcenet.core.errors import ArgumentError, ConvergenceError
from forcenet.core.validation import check_int

T = TypeVar("T")

Progress = Callable[..., object] | None  # called with one tick (or a count of them)

__all__ = [
    "RANDOM_TRIES",
    "Progress",
    "BetheSolution",
    "bethe_residuals",
    "first_level_roots",
    "solve_ground_state",
    "newton_polish",
    "ground_state_sequence",
    "photon_density",
    "y_density",
    "follow_fugacity",
    "IsotropicPoint",
    "isotropic_state",
    "isotropic_sequence",
]


@dataclass
class BetheSolution:
    """Roots of the Bethe equations for one sector."""

    L: int
    n: int
    m: int
    w: np.ndarray
    u: np.ndarray
    residual: float

    @property
    def eigenvalue(self) -> float:
        return float(np.prod(self.u).real)

    @property
    def entropy_per_site(self) -> float:
        """``log(Lambda)/L``."""
        return float(np.sum(np.log(self.u)).real) / self.L

    @property
    def momentum_factor(self) -> complex:
        """``W = prod w``; 1 for the translation-invariant ground state."""
        return complex(np.prod(self.w))


def _one_blas_thread(function: Callable[..., T]) -> Callable[..., T]:
    """Run with single-threaded BLAS: the Newton systems are small (n + m <= ~1000), and
    threaded BLAS on them is several times slower than one thread (75 s against 11 s at L = 240)."""

    @functools.wraps(function)
    def wrapper(*args: Any, **kwargs: Any) -> T:
        with threadpool_limits(1):
            return function(*args, **kwargs)

    return wrapper


def bethe_residuals(w: np.ndarray, u: np.ndarray, L: int) -> np.ndarray:
    """Relative residuals of the two sets of Bethe equations (complex, length ``n + m``).

    Computed from sums of logarithms, so that products of hundreds of
    factors neither overflow nor underflow.
    """
    w = np.asarray(w, dtype=complex)
    u = np.asarray(u, dtype=complex)
    n, m = len(w), len(u)
    logW, logU = np.log(w).sum(), np.log(u).sum()
    D = L - n + m
    lhs1 = np.log(u[None, :] - w[:, None]).sum(axis=1)
    rhs1 = (n - 1) * 1j * math.pi + logW + D * np.log(w)
    lhs2 = np.log(u[:, None] - w[None, :]).sum(axis=1)
    rhs2 = (m - 1) * 1j * math.pi + logW + m * np.log(u) - logU
    return np.concatenate([np.expm1(lhs1 - rhs1), np.expm1(lhs2 - rhs2)])


def first_level_roots(u: np.ndarray, L: int, n: int, w0: np.ndarray | None = None, iterations: int = 200, log_fugacity: float = 0.0) -> np.ndarray:
    """The ``n`` ground-state roots ``w`` of the first set of equations for given ``u`` (with ``W = 1``).

    Log form: ``w_k = exp(i pi (2k - n - 1)/D) (prod_l (u_l - w_k))^(1/D)``,
    ``D = L - n + m``, iterated to a fixed point (a contraction for
    ``m << D``; quadratic Newton polish at the end).  With a photon
    fugacity ``tau = e^mu`` the translation-invariant state has
    ``W = tau^(m-n)`` and the roots are divided by ``tau``.
    """
    u = np.asarray(u, dtype=complex)
    m = len(u)
    D = L - n + m
    base = 1j * math.pi * (2 * np.arange(1, n + 1) - n - 1) / D - float(log_fugacity)
    w = np.exp(base) if w0 is None else np.asarray(w0, dtype=complex)
    for _ in range(iterations):
        new = np.exp(base + np.log(u[None, :] - w[:, None]).sum(axis=1) / D)
        if np.abs(new - w).max() < 1e-15:
            w = new
            break
        w = new
    return w


def _second_level(u: np.ndarray, L: int, n: int, w0: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    w = first_level_roots(u, L, n, w0)
    m = len(u)
    lhs = np.log(u[:, None] - w[None, :]).sum(axis=1)
    rhs = (m - 1) * 1j * math.pi + np.log(w).sum() + m * np.log(u) - np.log(u).sum()
    return np.expm1(lhs - rhs), w


def _solve_u(L: int, n: int, m: int, u0: np.ndarray, tol: float) -> tuple[np.ndarray, np.ndarray, float]:
    from scipy.optimize import root  # scipy.optimize is heavy: loaded when a Bethe equation is solved
    state = {"w": None}

    def f(x: np.ndarray) -> np.ndarray:
        u = x[:m] + 1j * x[m:]
        r, w = _second_level(u, L, n, state["w"])
        return np.concatenate([r.real, r.imag])

    sol = root(f, np.concatenate([u0.real, u0.imag]), method="hybr", options={"xtol": tol})
    u = sol.x[:m] + 1j * sol.x[m:]
    w = first_level_roots(u, L, n)
    return w, u, float(np.abs(bethe_residuals(w, u, L)).max())


def _distinct(roots: np.ndarray) -> bool:
    """No two roots coincide (coinciding roots solve the equations but give no Bethe vector)."""
    return len(roots) < 2 or bool(np.min(np.abs(roots[:, None] - roots[None, :]) + np.eye(len(roots))) >= 1e-6)


def _is_ground_state(w: np.ndarray, u: np.ndarray, tol: float = 1e-8) -> bool:
    if abs(np.prod(w) - 1) > tol:
        return False
    if not (_distinct(u) and _distinct(w)):
        return False
    return abs(np.prod(u).imag) < 1e-8 * max(1.0, abs(np.prod(u)))


def _random_u(m: int, rng: np.random.Generator) -> np.ndarray:
    r, r2, th = rng.uniform(0.3, 2.5), rng.uniform(0.3, 2.5), rng.uniform(0, 1.5)
    pairs = [r * np.exp(1j * th * (k + 1) / max(1, m // 2)) for k in range(m // 2)]
    u = pairs + [np.conj(p) for p in pairs] + ([r2] if m % 2 else [])
    return np.array(u, dtype=complex)


RANDOM_TRIES = 3000  # random starts before the search gives up (bethe_sector.random_starts_seconds prices them)


@_one_blas_thread
def solve_ground_state(L: int, n: int, m: int, guess: np.ndarray | None = None, tries: int = RANDOM_TRIES,
                       seed: int = 0, tol: float = 1e-14) -> BetheSolution:
    """The translation-invariant solution with the largest eigenvalue found.

    Only the ``m`` rapidities ``u`` are unknowns; the ``w`` follow from
    :func:`first_level_roots`.

    Parameters
    ----------
    L, n, m : int
        Width, particles per row, left-movers among them (``1 <= m < n < L``).
    guess : array of ``m`` complex, optional
        Starting rapidities (from a smaller system, see
        :func:`ground_state_sequence`); without it, up to ``tries`` random
        starts symmetric about the real axis.

    Raises
    ------
    ConvergenceError
        If no ground-state-like solution converged (never silent).
    """
    L, n, m = check_int(L, "L", 3), check_int(n, "n", 2), check_int(m, "m", 1)
    if not (1 <= m < n < L):
        raise ArgumentError(f"(L, n, m) = ({L}, {n}, {m}) is out of range: need 1 <= m < n < L")
    rng = np.random.default_rng(seed)
    best = None
    starts = [np.asarray(guess, dtype=complex)] if guess is not None else []
    found = 0
    for k in range(tries + len(starts)):
        u0 = starts[k] if k < len(starts) else _random_u(m, rng)
        with np.errstate(all="ignore"):
            try:
                w, u, res = _solve_u(L, n, m, u0, tol)
            except (ValueError, FloatingPointError, np.linalg.LinAlgError):
                continue
        if np.isfinite(res) and res < 1e-10 and _is_ground_state(w, u):
            found += 1
            if best is None or np.prod(u).real > np.prod(best[1]).real:
                best = (w, u, res)
            if guess is not None or found >= 20:
                break
    if best is None:
        raise ConvergenceError(f"no ground-state solution of the Bethe equations converged for (L, n, m) = ({L}, {n}, {m})")
    w, u, res = best
    return BetheSolution(L, n, m, w[np.argsort(np.angle(w))], u[np.argsort(np.angle(u))], res)


def _resample(values: np.ndarray, size: int) -> np.ndarray:
    """Interpolate roots sorted by argument to a new count (quantile matching)."""
    old = np.linspace(0, 1, len(values))
    new = np.linspace(0, 1, size)
    return np.interp(new, old, values.real) + 1j * np.interp(new, old, values.imag)


def _jacobian(L: int, w: np.ndarray, u: np.ndarray) -> np.ndarray:
    """Jacobian of the log form of both sets of equations with respect to ``(w, u)``."""
    n, m = len(w), len(u)
    D = L - n + m
    J = np.zeros((n + m, n + m), dtype=complex)
    duw = 1.0 / (u[None, :] - w[:, None])  # (n, m): 1/(u_l - w_k)
    J[:n, :n] = -1.0 / w[None, :]
    J[np.arange(n), np.arange(n)] += -duw.sum(axis=1) - D / w
    J[:n, n:] = duw
    J[n:, :n] = -duw.T - 1.0 / w[None, :]
    J[n:, n:] = 1.0 / u[None, :]
    J[n + np.arange(m), n + np.arange(m)] += duw.sum(axis=0) - m / u
    return J


@_one_blas_thread
def newton_polish(L: int, w0: np.ndarray, u0: np.ndarray, iterations: int = 50, tol: float = 1e-14, log_fugacity: float = 0.0,
                  log_hop: float = 0.0) -> tuple[np.ndarray, np.ndarray, float, int]:
    """Complex Newton on the log form of both sets of equations, analytic Jacobian.

    The branches (multiples of ``2 pi i``) are fixed at the starting point,
    so the solution keeps the starting point's quantum numbers.  Returns
    ``(w, u, residual, iterations used)``; raises :class:`~forcenet.core.errors.ConvergenceError` if the
    iteration does not converge (never silent).

    ``log_fugacity = mu`` weighs every horizontal bond (photon) by
    ``tau = e^mu``.  A gauge transformation of the label amplitudes turns
    this into a twist: ``W`` becomes ``W tau^L`` on the right of both sets of
    equations, and ``Lambda = prod u`` unchanged (checked against
    :func:`forcenet.numeric.chicken_wire.transfer.sector_matrix` with ``photon_fugacity``).

    ``log_hop = log t`` weighs every label hop (one Y and one inverted Y
    vertex) by ``t``: the gauge ``t^(sum of label indices)`` leaves the twists
    ``t^m`` on the first set and ``t^n`` on the second (notes/chicken_wire.md,
    Sec. 9; checked against ``sector_matrix`` with ``hop_fugacity``).
    """
    w = np.asarray(w0, dtype=complex).copy()
    u = np.asarray(u0, dtype=complex).copy()
    n, m = len(w), len(u)
    D = L - n + m
    twist1, twist2 = _twists(L, n, m, log_fugacity, log_hop)

    def F(w: np.ndarray, u: np.ndarray) -> np.ndarray:
        lw, lu = np.log(w), np.log(u)
        f1 = np.log(u[None, :] - w[:, None]).sum(axis=1) - lw.sum() - D * lw - twist1
        f2 = np.log(u[:, None] - w[None, :]).sum(axis=1) - lw.sum() - m * lu + lu.sum() - twist2
        return np.concatenate([f1, f2])

    target = F(w, u)
    base = np.concatenate([np.full(n, (n - 1) * 1j * math.pi), np.full(m, (m - 1) * 1j * math.pi)])
    branch = base + 2j * math.pi * np.round((target - base).imag / (2 * math.pi))
    for it in range(1, iterations + 1):
        r = F(w, u) - branch
        if np.abs(r).max() < tol:
            return w, u, float(np.abs(r).max()), it
        step = np.linalg.solve(_jacobian(L, w, u), -r)
        w, u = w + step[:n], u + step[n:]
    r = float(np.abs(F(w, u) - branch).max())
    if r > 1e-10:
        raise ConvergenceError(f"Newton did not converge for L={L}, n={n}, m={m}: residual {r:.3g} after {iterations} steps")
    return w, u, r, iterations


@_one_blas_thread
def ground_state_sequence(k_max: int, ratio: tuple[int, int, int] = (6, 2, 1), start: int = 2, progress: Progress = None,
                          seeds: list[BetheSolution] | None = None) -> list[BetheSolution]:
    """Ground states along ``(L, n, m) = k * ratio`` for ``k = start..k_max`` by continuation.

    The first one comes from :func:`solve_ground_state`; each next one from
    :func:`newton_polish` started at the previous roots, resampled by
    argument to the new counts (the ``w`` angles rescaled by the exponent
    ``L - n + m``).  Each solution is checked to be translation invariant
    with a real eigenvalue.

    ``seeds``: solutions of earlier steps to continue from (the last two,
    for the parity of ``m``); they are not returned.

    Returns a list of :class:`BetheSolution`.
    """
    a, b, c = ratio
    out, prev = [], None
    if seeds:
        out, prev = list(seeds[-2:]), seeds[-1]
    n_seeds = len(out)
    for k in range(start, k_max + 1):
        L, n, m = a * k, b * k, c * k
        if prev is None:
            prev = solve_ground_state(L, n, m)
        else:
            # seed from the last solution whose m has the same parity (the odd-m states carry one real u)
            seed = next((s for s in reversed(out) if (s.m - m) % 2 == 0), prev)
            u0 = _resample(seed.u, m)
            with np.errstate(all="ignore"):
                w0 = first_level_roots(u0, L, n)  # distinct: one root per branch
                try:
                    w, u, res, _ = newton_polish(L, w0, u0)
                    ok = _is_ground_state(w, u)
                except (ConvergenceError, np.linalg.LinAlgError):
                    ok = False
            if ok:
                prev = BetheSolution(L, n, m, w[np.argsort(np.angle(w))], u[np.argsort(np.angle(u))], res)
            else:
                prev = solve_ground_state(L, n, m, guess=u0, tries=100)
        out.append(prev)
        if progress is not None:
            progress(1)
    return out[n_seeds:]


# ------------------------------------------------ the isotropic line (photon fugacity)


def photon_density(L: int, w: np.ndarray, u: np.ndarray) -> float:
    """Horizontal bonds per site, ``(1/L) d log(Lambda) / d mu``, of a solution at fugacity ``e^mu``.

    Implicit differentiation of the twisted equations: every equation's
    right side carries ``L mu``, so ``J dx/dmu = L`` and
    ``d log Lambda = sum du/u``.
    """
    w = np.asarray(w, dtype=complex)
    u = np.asarray(u, dtype=complex)
    du = _tangent(L, w, u)[len(w):]
    return float((du / u).sum().real) / L


def _twists(L: int, n: int, m: int, log_fugacity: float, log_hop: float) -> tuple[float, float]:
    """Logs of the twists of the two sets of equations: ``(L mu + m log t, L mu + n log t)``."""
    return L * float(log_fugacity) + m * float(log_hop), L * float(log_fugacity) + n * float(log_hop)


def _tangent(L: int, w: np.ndarray, u: np.ndarray, hop: bool = False) -> np.ndarray:
    """``d(w, u)/d mu`` (or ``d/d log t``) along a solution: ``J dx`` = the derivative of the twists."""
    n, m = len(w), len(u)
    rhs = np.concatenate([np.full(n, m if hop else L), np.full(m, n if hop else L)]).astype(complex)
    return np.linalg.solve(_jacobian(L, w, u), rhs)


def y_density(L: int, w: np.ndarray, u: np.ndarray) -> float:
    """Y vertices (one kind) per site, ``y = (1/L) d log Lambda / d log t`` at a solution.

    Implicit differentiation of the hop twists (:func:`newton_polish`).  It
    equals ``Q_R Q_L + Q_L Q_H + Q_H Q_R`` for every solution, so ``3 Q^2`` on
    the isotropic line (notes/chicken_wire.md, Sec. 9, where it is also proven
    on every torus configuration).

    Examples
    --------
    >>> sol = solve_ground_state(9, 4, 2)
    >>> qh = photon_density(9, sol.w, sol.u)
    >>> abs(y_density(9, sol.w, sol.u) - (2 * 2 / 81 + (2 / 9 + 2 / 9) * qh)) < 1e-12
    True
    """
    w = np.asarray(w, dtype=complex)
    u = np.asarray(u, dtype=complex)
    du = _tangent(L, w, u, hop=True)[len(w):]
    return float((du / u).sum().real) / L


@_one_blas_thread
def follow_fugacity(L: int, w: np.ndarray, u: np.ndarray, mu_from: float, mu_to: float,
                    max_twist_step: float = 0.5) -> tuple[np.ndarray, np.ndarray]:
    """Carry a solution from photon fugacity ``e^mu_from`` to ``e^mu_to``.

    Euler predictor along ``dx/dmu`` and Newton corrector, with steps of at
    most ``max_twist_step`` in ``L mu``; a failed step is halved (up to 12
    times) and then reported as :class:`~forcenet.core.errors.ConvergenceError`.
    """
    w = np.asarray(w, dtype=complex).copy()
    u = np.asarray(u, dtype=complex).copy()
    n = len(w)
    mu, step = float(mu_from), max_twist_step / L
    halvings = 0
    while abs(mu_to - mu) > 1e-15:
        h = max(-step, min(step, mu_to - mu))
        with np.errstate(all="ignore"):
            try:
                dx = _tangent(L, w, u)
                w1, u1, _, _ = newton_polish(L, w + h * dx[:n], u + h * dx[n:], log_fugacity=mu + h)
                ok = bool(np.all(np.isfinite(w1)) and np.all(np.isfinite(u1)))
            except (ConvergenceError, np.linalg.LinAlgError):
                ok = False
        if ok:
            w, u, mu = w1, u1, mu + h
            step = min(step * 1.5, max_twist_step / L * 4)
        else:
            halvings += 1
            step /= 2
            if halvings > 12:
                raise ConvergenceError(f"lost the Bethe solution at L={L} between mu={mu:.6g} and {mu + h:.6g}")
    return w, u


@dataclass
class IsotropicPoint:
    """A sector ``(L, n = 2m, m)`` at the photon fugacity where all three densities are ``m/L``."""

    L: int
    n: int
    m: int
    log_fugacity: float
    photon_density: float
    entropy_per_site: float
    w: np.ndarray
    u: np.ndarray

    @property
    def Q(self) -> float:
        """Density of left-moving particles per site (= right = horizontal)."""
        return self.m / self.L


@_one_blas_thread
def isotropic_state(L: int, n: int, m: int, w: np.ndarray, u: np.ndarray, mu: float = 0.0, tol: float = 1e-12, iterations: int = 40) -> IsotropicPoint:
    """Solve for the fugacity at which the photon density equals ``m/L`` (isotropy).

    Densities per site: right movers ``(n-m)/L``, left movers ``m/L`` and
    horizontal bonds ``rho_H(mu)`` (:func:`photon_density`).  With
    ``n = 2m`` the first two agree; a secant iteration on ``mu`` makes the
    third agree.  The entropy per site is the Legendre transform
    ``v = log(Lambda)/L - mu rho_H`` (Sec. 7.4.1, the isotropic case of
    Eq. 7.1).  Raises :class:`~forcenet.core.errors.ConvergenceError` if the iteration fails.
    """
    if n != 2 * m:
        raise ArgumentError(f"(n, m) = ({n}, {m}): the isotropic line needs n = 2m")
    target = m / L
    w = np.asarray(w, dtype=complex)
    u = np.asarray(u, dtype=complex)
    w, u, _, _ = newton_polish(L, w, u, log_fugacity=mu)
    g = photon_density(L, w, u) - target
    mu_prev: float | None = None
    g_prev = 0.0
    for _ in range(iterations):
        if abs(g) < tol:
            break
        if mu_prev is None:
            new = mu - g * 4.0  # d rho_H / d mu is of order 1/4 (measured); the secant takes over
        else:
            new = mu - g * (mu - mu_prev) / (g - g_prev)
        w, u = follow_fugacity(L, w, u, mu, new)
        mu_prev, g_prev, mu = mu, g, new
        g = photon_density(L, w, u) - target
    else:
        raise ConvergenceError(f"isotropy not reached at (L, n, m) = ({L}, {n}, {m}): |rho_H - Q| = {abs(g):.3g}")
    log_lambda = float(np.sum(np.log(u)).real)
    rho_h = g + target
    return IsotropicPoint(L, n, m, mu, rho_h, log_lambda / L - mu * rho_h, w, u)


@_one_blas_thread
def isotropic_sequence(k_values: Iterable[int], ratio: tuple[int, int, int] = (6, 2, 1),
                       progress: Progress = None) -> list[IsotropicPoint]:
    """Isotropic points along ``(L, n, m) = k * ratio`` (``n = 2m``), by continuation in ``k``.

    At each width the fugacity-1 ground state comes from the continuation of
    :func:`ground_state_sequence` (from ``k = 2``, also when the first ``k``
    asked for is larger), and is carried to the isotropic fugacity by
    :func:`follow_fugacity`, starting at the previous width's fugacity.
    Above the maximum (the previous width's ``mu > 0``) the isotropic points
    are continued in ``k`` themselves, at that fugacity: there the fugacity-1
    ground state ends in coinciding roots (``Q = 1/5`` at ``L = 125``) while
    the isotropic state goes on (``tests/test_bethe.py``).
    Returns a list of :class:`IsotropicPoint`; a lost ground state raises
    :class:`~forcenet.core.errors.ConvergenceError`.

    Examples
    --------
    >>> pts = isotropic_sequence([2, 3], ratio=(6, 2, 1))
    >>> [(p.L, round(p.photon_density, 12)) for p in pts]
    [(12, 0.166666666667), (18, 0.166666666667)]
    """
    a, b, c = ratio
    if b != 2 * c:
        raise ArgumentError(f"ratio={ratio!r}: the isotropic line needs n = 2m")
    out: list[IsotropicPoint] = []
    k_values = list(k_values)
    bases: list[BetheSolution] = []  # fugacity-1 ground states, continued in k as in ground_state_sequence
    for k in k_values:
        L, n, m = a * k, b * k, c * k
        mu0 = out[-1].log_fugacity if out else 0.0
        if mu0 > 0:
            # above the maximum the fugacity-1 ground state ends in coinciding roots (Q = 1/5 at L = 125,
            # notes/chicken_wire.md) while the isotropic state goes on: continue the isotropic points themselves
            w, u = _continue_at_fugacity(out, L, n, m, mu0)
        else:
            # the fugacity-1 ground state by the continuation of ground_state_sequence, then the fugacity
            if not bases:
                # the fugacity-1 state by continuation from k = 2 (random starts fail at large L)
                bases += ground_state_sequence(k, ratio, start=2) if k > 2 else [solve_ground_state(L, n, m)]
            else:
                bases += ground_state_sequence(k, ratio, start=k, seeds=bases)
            sol = bases[-1]
            w, u = follow_fugacity(L, sol.w, sol.u, 0.0, mu0) if mu0 else (sol.w, sol.u)
        out.append(isotropic_state(L, n, m, w, u, mu=mu0))
        if progress is not None:
            progress(1)
    return out


def _continue_at_fugacity(points: list[IsotropicPoint], L: int, n: int, m: int, mu: float) -> tuple[np.ndarray, np.ndarray]:
    """The roots of ``(L, n, m)`` at the fugacity ``e^mu`` of the last isotropic point, continued from it.

    As in :func:`ground_state_sequence`, but at ``mu`` (``W = tau^(m-n)``): the
    ``u`` of the last point with ``m`` of the same parity, resampled, the ``w``
    from :func:`first_level_roots` at ``mu``, then :func:`newton_polish`.
    Raises :class:`~forcenet.core.errors.ConvergenceError` if the roots
    coincide or the eigenvalue is not real.
    """
    seed = next((p for p in reversed(points) if (p.m - m) % 2 == 0), points[-1])
    u0 = _resample(seed.u, m)
    with np.errstate(all="ignore"):
        w0 = first_level_roots(u0, L, n, log_fugacity=mu)
        try:
            w, u, _, _ = newton_polish(L, w0, u0, log_fugacity=mu)
        except np.linalg.LinAlgError:
            raise ConvergenceError(f"lost the isotropic state at (L, n, m) = ({L}, {n}, {m})") from None
    if not (_distinct(w) and _distinct(u) and abs(np.prod(u).imag) < 1e-8 * max(1.0, abs(np.prod(u)))):
        raise ConvergenceError(f"lost the isotropic state at (L, n, m) = ({L}, {n}, {m}): coinciding roots")
    return w, u
