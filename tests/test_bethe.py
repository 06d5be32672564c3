"""Nested Bethe ansatz (notes/chicken_wire.md Sec. 5) against the transfer matrix."""

import functools
import math

import numpy as np
import pytest
from scipy.sparse.linalg import eigs

from forcenet.core.errors import ArgumentError, ConvergenceError
from forcenet.numeric.chicken_wire.bethe import (
    bethe_residuals,
    ground_state_sequence,
    newton_polish,
    solve_ground_state,
)
from forcenet.numeric.chicken_wire.transfer import largest_eigenvalue, sector_matrix


@functools.cache
def _ground_state(L, n, m):
    """One solve per sector for the whole module: the eigenvalue, twist and photon tests share it."""
    return solve_ground_state(L, n, m)


def _tm(L, n, m):
    T = sector_matrix(L, n, m)
    if T.shape[0] <= 600:
        return float(np.linalg.eigvals(T.toarray()).real.max())
    return float(eigs(T, k=1, which="LR", tol=1e-14, return_eigenvectors=False).real.max())


@pytest.mark.parametrize(
    "L, n, m",
    [(6, 2, 1), (7, 2, 1), (8, 3, 1), pytest.param(8, 4, 2, marks=pytest.mark.slow),
     pytest.param(9, 4, 2, marks=pytest.mark.slow), (9, 5, 2), pytest.param(10, 4, 2, marks=pytest.mark.slow), (10, 5, 2),
     pytest.param(11, 6, 3, marks=pytest.mark.slow), pytest.param(12, 6, 3, marks=pytest.mark.slow)],
)  # under -m slow: the sectors whose random starts take 10-40 s (n = 2m, and L >= 11); the same equations at
# L <= 10 with m < n/2 stay in the default suite
def test_bethe_eigenvalue_equals_transfer_matrix(L, n, m):
    sol = _ground_state(L, n, m)
    assert abs(sol.eigenvalue - _tm(L, n, m)) < 1e-12
    assert np.abs(bethe_residuals(sol.w, sol.u, L)).max() < 1e-12
    assert abs(sol.momentum_factor - 1) < 1e-10


def test_sector_matrix_equals_operator_route():
    """Two transfer-matrix constructions: particle picture vs matrix product operator."""
    for L in (5, 6, 7):
        for n in range(1, L):
            best = max(_tm(L, n, m) for m in range(n + 1))
            assert best == pytest.approx(largest_eigenvalue(L, particles=n), abs=1e-11)


def test_two_particles_closed_form():
    for L in (5, 9, 13):
        assert solve_ground_state(L, 2, 1).eigenvalue == pytest.approx(2 * math.cos(math.pi / L), abs=1e-13)


@pytest.mark.slow  # ~25 s
def test_continuation_follows_the_ground_state():
    """Continuation to L = 18 and 24 agrees with the sector transfer matrix at L = 18."""
    seq = ground_state_sequence(4)
    by_L = {s.L: s for s in seq}
    assert abs(by_L[18].eigenvalue - _tm(18, 6, 3)) < 1e-10
    assert by_L[24].entropy_per_site < by_L[18].entropy_per_site < by_L[12].entropy_per_site


def test_newton_reports_failure():
    w = np.exp(1j * np.linspace(-1, 1, 4))
    with pytest.raises(ConvergenceError, match="did not converge"):  # a RuntimeError and a forcenet error
        newton_polish(12, w, np.array([5.0 + 5j, 5.0 - 5j]), iterations=1)


def test_bad_sector():
    with pytest.raises(ArgumentError, match="out of range"):
        solve_ground_state(6, 2, 2)


# ------------------------------------------------ photon fugacity (twist) and the isotropic line


def _tm_tau(L, n, m, tau):
    T = sector_matrix(L, n, m, photon_fugacity=tau)
    if T.shape[0] <= 600:
        return float(np.linalg.eigvals(T.toarray()).real.max())
    return float(eigs(T, k=1, which="LR", tol=1e-14, return_eigenvectors=False).real.max())


def test_photon_fugacity_sector_matrix_equals_operator_route():
    # two transfer matrices with weight tau per horizontal bond: H = tau, Y = inverted Y = sqrt(tau)
    for L, n, tau in [(7, 2, 0.7), (8, 4, 1.6), (9, 4, 1.3)]:
        weights = {"empty": 1, "H": tau, "R": 1, "L": 1, "Y": math.sqrt(tau), "inverted Y": math.sqrt(tau)}
        best = max(_tm_tau(L, n, m, tau) for m in range(n + 1))
        assert best == pytest.approx(largest_eigenvalue(L, weights, particles=n), abs=1e-11)


@pytest.mark.parametrize("L, n, m, tau", [pytest.param(9, 4, 2, 1.5, marks=pytest.mark.slow), pytest.param(10, 4, 2, 0.75, marks=pytest.mark.slow),
                                          (10, 5, 2, 0.75),
                                          pytest.param(11, 6, 3, 1.3, marks=pytest.mark.slow),
                                          pytest.param(12, 6, 3, 0.8, marks=pytest.mark.slow), (10, 5, 2, 1.4)])
# default: tau < 1 and tau > 1 at (10, 5, 2) (both twists); the other sectors under -m slow
def test_twisted_bethe_equations_equal_transfer_matrix(L, n, m, tau):
    from forcenet.numeric.chicken_wire.bethe import follow_fugacity

    sol = _ground_state(L, n, m)
    w, u = follow_fugacity(L, sol.w, sol.u, 0.0, math.log(tau))
    assert abs(np.prod(u).real - _tm_tau(L, n, m, tau)) < 1e-11
    assert abs(np.prod(w) - tau ** (m - n)) < 1e-10  # the translation-invariant state under the twist


@pytest.mark.parametrize("L, n, m, tau", [(10, 5, 2, 1.0), pytest.param(10, 4, 2, 1.0, marks=pytest.mark.slow),
                                          pytest.param(9, 4, 2, 0.8, marks=pytest.mark.slow),
                                          pytest.param(12, 4, 2, 1.2, marks=pytest.mark.slow)])
# default: (10, 5, 2); the twisted fugacities are test_twisted_bethe_equations_equal_transfer_matrix's
def test_photon_density_is_the_derivative_of_the_transfer_matrix(L, n, m, tau):
    from forcenet.numeric.chicken_wire.bethe import follow_fugacity, photon_density

    sol = _ground_state(L, n, m)
    w, u = follow_fugacity(L, sol.w, sol.u, 0.0, math.log(tau))
    h = 1e-4
    fd = (math.log(_tm_tau(L, n, m, tau * math.exp(h))) - math.log(_tm_tau(L, n, m, tau * math.exp(-h)))) / (2 * h * L)
    assert photon_density(L, w, u) == pytest.approx(fd, abs=1e-7)


@pytest.mark.slow  # ~15 s; the isotropic state's entropy stays checked by tests/test_isotropic.py (Bethe vs closed form)
def test_isotropic_point_equals_transfer_matrix_legendre_transform():
    from forcenet.numeric.chicken_wire.bethe import isotropic_state

    L, n, m = 12, 4, 2
    sol = solve_ground_state(L, n, m)
    p = isotropic_state(L, n, m, sol.w, sol.u)
    assert p.photon_density == pytest.approx(m / L, abs=1e-11)
    tau = math.exp(p.log_fugacity)
    h = 1e-4
    lam = _tm_tau(L, n, m, tau)
    rho_h = (math.log(_tm_tau(L, n, m, tau * math.exp(h))) - math.log(_tm_tau(L, n, m, tau * math.exp(-h)))) / (2 * h * L)
    assert rho_h == pytest.approx(m / L, abs=1e-7)  # the transfer matrix agrees that all three densities are Q
    assert p.entropy_per_site == pytest.approx(math.log(lam) / L - p.log_fugacity * rho_h, abs=1e-9)


def test_isotropic_bad_input():
    from forcenet.numeric.chicken_wire.bethe import isotropic_sequence, isotropic_state

    sol = solve_ground_state(10, 5, 2)
    with pytest.raises(ValueError, match="n = 2m"):
        isotropic_state(10, 5, 2, sol.w, sol.u)
    with pytest.raises(ValueError, match="ratio"):
        isotropic_sequence([2], ratio=(6, 3, 1))


# ------------------------------------------- the Y density (hop fugacity), issue 13


def _follow_hop(L, w, u, log_t, steps=10):
    from forcenet.numeric.chicken_wire.bethe import _tangent

    n = len(w)
    for k in range(1, steps + 1):
        h = log_t / steps
        dx = _tangent(L, w, u, hop=True)
        w, u, _, _ = newton_polish(L, w + h * dx[:n], u + h * dx[n:], log_hop=k * h)
    return w, u


def _top(M):
    return eigs(M, k=1, which="LR", return_eigenvectors=False).real.max()


@pytest.mark.parametrize("L, n, m", [pytest.param(9, 4, 2, marks=pytest.mark.slow), (10, 5, 2),
                                     pytest.param(11, 4, 2, marks=pytest.mark.slow)])  # default: L = 10
def test_hop_twist_equals_the_hop_weighted_matrix(L, n, m):
    """A weight t per Y vertex: twists t^m (first set), t^n (second set); Lambda against the sector matrix."""
    sol = _ground_state(L, n, m)
    for log_t in (0.2, -0.15):
        w, u = _follow_hop(L, sol.w, sol.u, log_t)
        assert abs(np.prod(u).real - _top(sector_matrix(L, n, m, hop_fugacity=math.exp(log_t)))) < 1e-10


def test_hop_weighted_matrix_equals_the_vertex_weighted_mpo():
    # weight t on Y (one per hop) in the matrix-product-operator route, maximized over m
    t, L, n = 1.3, 8, 4
    best = max(np.linalg.eigvals(sector_matrix(L, n, m, hop_fugacity=t).toarray()).real.max() for m in range(n + 1))
    assert abs(best - largest_eigenvalue(L, weights={"Y": t}, particles=n)) < 1e-10


def test_y_density_is_the_pair_sum_and_a_derivative():
    from forcenet.numeric.chicken_wire.bethe import photon_density, y_density

    L, n, m = 10, 5, 2
    sol = _ground_state(L, n, m)
    y = y_density(L, sol.w, sol.u)
    h = 1e-4
    lam = [_top(sector_matrix(L, n, m, hop_fugacity=math.exp(s))) for s in (-h, h)]
    assert abs(y - (math.log(lam[1]) - math.log(lam[0])) / (2 * h) / L) < 1e-7
    qh, qr, ql = photon_density(L, sol.w, sol.u), (n - m) / L, m / L
    assert abs(y - (qr * ql + ql * qh + qh * qr)) < 1e-13


@pytest.mark.slow  # ~10 s; 3Q^2 is the pair sum at equal densities: test_y_density_is_the_pair_sum_and_a_derivative
def test_y_density_on_the_isotropic_line_is_3Q2():
    from forcenet.numeric.chicken_wire.bethe import isotropic_sequence, y_density

    for p in isotropic_sequence(range(8, 11), ratio=(6, 2, 1)):  # Q = 1/6, L = 48..60
        assert abs(y_density(p.L, p.w, p.u) - 3 * p.Q**2) < 1e-11


# ------------------------------------------- above the maximum: continuation at the isotropic fugacity


@pytest.mark.slow  # ~30 s of CPU (the fugacity-1 continuation from L = 10 twice)
def test_isotropic_continuation_at_the_fugacity_equals_the_fugacity_one_route():
    """Q = 1/5 (above the maximum, mu > 0): the widths after the first are continued at the isotropic fugacity;
    the same point from the fugacity-1 ground state carried to that fugacity (the route used below the maximum)."""
    from forcenet.numeric.chicken_wire.bethe import follow_fugacity, isotropic_sequence, isotropic_state

    pts = isotropic_sequence([8, 9, 10], ratio=(5, 2, 1))
    assert all(p.log_fugacity > 0 for p in pts)
    last = pts[-1]
    base = ground_state_sequence(10, ratio=(5, 2, 1))[-1]
    w, u = follow_fugacity(50, base.w, base.u, 0.0, pts[-2].log_fugacity)
    direct = isotropic_state(50, 20, 10, w, u, mu=pts[-2].log_fugacity)
    assert direct.log_fugacity == pytest.approx(last.log_fugacity, abs=1e-11)
    assert direct.entropy_per_site == pytest.approx(last.entropy_per_site, abs=1e-13)


@pytest.mark.slow
def test_isotropic_line_past_the_end_of_the_fugacity_one_continuation():
    """Q = 1/5 beyond L = 125, where the fugacity-1 ground state ends in coinciding roots (it used to raise
    ConvergenceError there): the extrapolated v and mu agree with the closed form within 5 error bars."""
    from fractions import Fraction

    from forcenet.numeric.chicken_wire import isotropic as iso
    from forcenet.numeric.chicken_wire.isotropic_bethe import isotropic_limit

    lim = isotropic_limit(Fraction(1, 5), L_max=160, L_min=100)
    assert max(lim.L) > 125
    assert abs(lim.v - float(iso.entropy(Q=Fraction(1, 5), dps=20))) < 5 * lim.v_err + 1e-12
    assert abs(lim.mu - float(iso.chemical_potential(Q=Fraction(1, 5), dps=20))) < 5 * lim.mu_err + 1e-10
