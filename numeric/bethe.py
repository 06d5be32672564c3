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

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["BetheSolution", "bethe_residuals", "first_level_roots", "solve_ground_state", "newton_polish", "ground_state_sequence"]


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


def first_level_roots(u: np.ndarray, L: int, n: int, w0=None, iterations: int = 200) -> np.ndarray:
    """The ``n`` ground-state roots ``w`` of the first set of equations for given ``u`` (with ``W = 1``).

    Log form: ``w_k = exp(i pi (2k - n - 1)/D) (prod_l (u_l - w_k))^(1/D)``,
    ``D = L - n + m``, iterated to a fixed point (a contraction for
    ``m << D``; quadratic Newton polish at the end).
    """
    u = np.asarray(u, dtype=complex)
    m = len(u)
    D = L - n + m
    base = 1j * math.pi * (2 * np.arange(1, n + 1) - n - 1) / D
    w = np.exp(base) if w0 is None else np.asarray(w0, dtype=complex)
    for _ in range(iterations):
        new = np.exp(base + np.log(u[None, :] - w[:, None]).sum(axis=1) / D)
        if np.abs(new - w).max() < 1e-15:
            w = new
            break
        w = new
    return w


def _second_level(u, L, n, w0=None):
    w = first_level_roots(u, L, n, w0)
    m = len(u)
    lhs = np.log(u[:, None] - w[None, :]).sum(axis=1)
    rhs = (m - 1) * 1j * math.pi + np.log(w).sum() + m * np.log(u) - np.log(u).sum()
    return np.expm1(lhs - rhs), w


def _solve_u(L, n, m, u0, tol):
    from scipy.optimize import root

    state = {"w": None}

    def f(x):
        u = x[:m] + 1j * x[m:]
        r, w = _second_level(u, L, n, state["w"])
        return np.concatenate([r.real, r.imag])

    sol = root(f, np.concatenate([u0.real, u0.imag]), method="hybr", options={"xtol": tol})
    u = sol.x[:m] + 1j * sol.x[m:]
    w = first_level_roots(u, L, n)
    return w, u, float(np.abs(bethe_residuals(w, u, L)).max())


def _is_ground_state(w, u, tol=1e-8) -> bool:
    if abs(np.prod(w) - 1) > tol:
        return False
    for roots in (u, w):  # coinciding roots solve the equations but give no Bethe vector
        if len(roots) > 1 and np.min(np.abs(roots[:, None] - roots[None, :]) + np.eye(len(roots))) < 1e-6:
            return False
    return abs(np.prod(u).imag) < 1e-8 * max(1.0, abs(np.prod(u)))


def _random_u(m, rng):
    r, r2, th = rng.uniform(0.3, 2.5), rng.uniform(0.3, 2.5), rng.uniform(0, 1.5)
    pairs = [r * np.exp(1j * th * (k + 1) / max(1, m // 2)) for k in range(m // 2)]
    u = pairs + [np.conj(p) for p in pairs] + ([r2] if m % 2 else [])
    return np.array(u, dtype=complex)


def solve_ground_state(L: int, n: int, m: int, guess=None, tries: int = 3000, seed: int = 0, tol: float = 1e-14):
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
    RuntimeError
        If no ground-state-like solution converged (never silent).
    """
    for name, v in (("L", L), ("n", n), ("m", m)):
        if isinstance(v, bool) or not isinstance(v, int):
            raise TypeError(f"{name}={v!r}: must be an integer")
    if not (1 <= m < n < L):
        raise ValueError(f"(L, n, m) = ({L}, {n}, {m}) is out of range: need 1 <= m < n < L")
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
        raise RuntimeError(f"no ground-state solution of the Bethe equations converged for (L, n, m) = ({L}, {n}, {m})")
    w, u, res = best
    return BetheSolution(L, n, m, w[np.argsort(np.angle(w))], u[np.argsort(np.angle(u))], res)


def _resample(values: np.ndarray, size: int) -> np.ndarray:
    """Interpolate roots sorted by argument to a new count (quantile matching)."""
    old = np.linspace(0, 1, len(values))
    new = np.linspace(0, 1, size)
    return np.interp(new, old, values.real) + 1j * np.interp(new, old, values.imag)


def newton_polish(L: int, w0, u0, iterations: int = 50, tol: float = 1e-14):
    """Complex Newton on the log form of both sets of equations, analytic Jacobian.

    The branches (multiples of ``2 pi i``) are fixed at the starting point,
    so the solution keeps the starting point's quantum numbers.  Returns
    ``(w, u, residual, iterations used)``; raises ``RuntimeError`` if the
    iteration does not converge (never silent).
    """
    w = np.asarray(w0, dtype=complex).copy()
    u = np.asarray(u0, dtype=complex).copy()
    n, m = len(w), len(u)
    D = L - n + m

    def F(w, u):
        lw, lu = np.log(w), np.log(u)
        f1 = np.log(u[None, :] - w[:, None]).sum(axis=1) - lw.sum() - D * lw
        f2 = np.log(u[:, None] - w[None, :]).sum(axis=1) - lw.sum() - m * lu + lu.sum()
        return np.concatenate([f1, f2])

    target = F(w, u)
    base = np.concatenate([np.full(n, (n - 1) * 1j * math.pi), np.full(m, (m - 1) * 1j * math.pi)])
    branch = base + 2j * math.pi * np.round((target - base).imag / (2 * math.pi))
    for it in range(1, iterations + 1):
        r = F(w, u) - branch
        if np.abs(r).max() < tol:
            return w, u, float(np.abs(r).max()), it
        J = np.zeros((n + m, n + m), dtype=complex)
        duw = 1.0 / (u[None, :] - w[:, None])  # (n, m): 1/(u_l - w_k)
        J[:n, :n] = -1.0 / w[None, :]
        J[np.arange(n), np.arange(n)] += -duw.sum(axis=1) - D / w
        J[:n, n:] = duw
        J[n:, :n] = -duw.T - 1.0 / w[None, :]
        J[n:, n:] = 1.0 / u[None, :]
        J[n + np.arange(m), n + np.arange(m)] += duw.sum(axis=0) - m / u
        step = np.linalg.solve(J, -r)
        w, u = w + step[:n], u + step[n:]
    r = float(np.abs(F(w, u) - branch).max())
    if r > 1e-10:
        raise RuntimeError(f"Newton did not converge for L={L}, n={n}, m={m}: residual {r:.3g} after {iterations} steps")
    return w, u, r, iterations


def ground_state_sequence(k_max: int, ratio=(6, 2, 1), start: int = 2, progress=None):
    """Ground states along ``(L, n, m) = k * ratio`` for ``k = start..k_max`` by continuation.

    The first one comes from :func:`solve_ground_state`; each next one from
    :func:`newton_polish` started at the previous roots, resampled by
    argument to the new counts (the ``w`` angles rescaled by the exponent
    ``L - n + m``).  Each solution is checked to be translation invariant
    with a real eigenvalue.

    Returns a list of :class:`BetheSolution`.
    """
    a, b, c = ratio
    out, prev = [], None
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
                except (RuntimeError, np.linalg.LinAlgError):
                    ok = False
            if ok:
                prev = BetheSolution(L, n, m, w[np.argsort(np.angle(w))], u[np.argsort(np.angle(u))], res)
            else:
                prev = solve_ground_state(L, n, m, guess=u0, tries=100)
        out.append(prev)
        if progress is not None:
            progress(1)
    return out
