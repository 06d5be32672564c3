"""Nested Bethe ansatz (notes/chicken_wire.md Sec. 5) against the transfer matrix."""

import math

import numpy as np
import pytest
from scipy.sparse.linalg import eigs

from numeric.bethe import bethe_residuals, ground_state_sequence, newton_polish, solve_ground_state
from numeric.chicken_wire import largest_eigenvalue, sector_matrix


def _tm(L, n, m):
    T = sector_matrix(L, n, m)
    if T.shape[0] <= 600:
        return float(np.linalg.eigvals(T.toarray()).real.max())
    return float(eigs(T, k=1, which="LR", tol=1e-14, return_eigenvectors=False).real.max())


@pytest.mark.parametrize(
    "L, n, m",
    [(6, 2, 1), (7, 2, 1), (8, 3, 1), (8, 4, 2), (9, 4, 2), (9, 5, 2), (10, 4, 2), (10, 5, 2), (11, 6, 3), (12, 6, 3)],
)
def test_bethe_eigenvalue_equals_transfer_matrix(L, n, m):
    sol = solve_ground_state(L, n, m)
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


def test_continuation_follows_the_ground_state():
    """Continuation to L = 18 and 24 agrees with the sector transfer matrix at L = 18."""
    seq = ground_state_sequence(4)
    by_L = {s.L: s for s in seq}
    assert abs(by_L[18].eigenvalue - _tm(18, 6, 3)) < 1e-10
    assert by_L[24].entropy_per_site < by_L[18].entropy_per_site < by_L[12].entropy_per_site


def test_newton_reports_failure():
    w = np.exp(1j * np.linspace(-1, 1, 4))
    with pytest.raises(RuntimeError, match="did not converge"):
        newton_polish(12, w, np.array([5.0 + 5j, 5.0 - 5j]), iterations=1)


def test_bad_sector():
    with pytest.raises(ValueError, match="out of range"):
        solve_ground_state(6, 2, 2)
