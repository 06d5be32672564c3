"""The floor's Pfaffians by their displacement structure (floor_displacement.py) against the explicit matrices.

Two routes to every residue: the displacement kernel carries four generator
columns and two border columns; the lazy elimination of floor_kernels.py and
the pivoting Pfaffian of kernels.py work on the explicit de Bruijn matrix.
"""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from forcenet.core.errors import ArgumentError
from forcenet.exact.triangle.de_bruijn.floor import (
    de_bruijn_constants,
    floor_gap_laws,
    floor_pooled_gap_law,
    floor_prime_residues,
    floor_primes,
)
from forcenet.exact.triangle.de_bruijn.floor_displacement import bordered_pfaffians, inverse_table, lane_buffer
from forcenet.exact.triangle.de_bruijn.floor_kernels import fill_pair, grid, grid_pairs, pfaffian_pair
from forcenet.exact.triangle.residues import dual_weights

P = 4194301


def _upper(n, s, t, y, p, C, iota):
    """fill_pair's bordered matrix (upper triangle, unreduced) at ``(s, t, y)``."""
    size = n + n % 2
    M = np.zeros((size + 2, size + 2))
    fill_pair(M, n, float(s), float(t), float(y), C, iota, np.empty(2 * n + 1), np.empty(2 * n + 1), p, 1 / p)
    return M


def _explicit(n, s, t, y, p):
    """fill_pair's bordered matrix, both halves, reduced."""
    M = np.triu(_upper(n, s, t, y, p, *de_bruijn_constants(n, p)) % p, 1)
    return ((M - M.T) % p).astype(np.int64)


def _by_elimination(n, s, t, y, p, C, iota):
    """``(Pf Y, S, ok)`` by the lazy elimination of the explicit matrix (the other route)."""
    return pfaffian_pair(_upper(n, s, t, y, p, C, iota), n + n % 2, p, 1 / p)


@settings(max_examples=25)
@given(st.integers(1, 40), st.integers(0, P - 1), st.integers(0, P - 1), st.integers(0, P - 1))
def test_the_block_is_cauchy_like_with_four_generators(n, s, t, y):
    """(x_k + x_m) Y_km = G_k Omega G_m^T, G = [rho, 1 + t^x, y sigma, s^x]: the structure the kernel relies on."""
    M = _explicit(n, s, t, y, P)
    x = np.arange(1, n + 1)
    inv = [pow(int(v), P - 2, P) for v in x]
    S1 = [pow(s, int(v), P) for v in x]
    T1 = [pow(t, int(v), P) for v in x]
    rho = [inv[k] * (1 - T1[k]) % P for k in range(n)]
    sig = [inv[k] * S1[k] % P for k in range(n)]
    for k in range(n):
        for m in range(n):
            generated = rho[k] * (1 + T1[m]) - (1 + T1[k]) * rho[m] + y * (sig[k] * S1[m] - S1[k] * sig[m])
            assert (int(x[k] + x[m]) * int(M[k, m]) - generated) % P == 0


@settings(max_examples=30)
@given(st.integers(1, 45), st.lists(st.tuples(st.integers(0, P - 1), st.integers(0, P - 1), st.integers(0, P - 1)),
                                    min_size=1, max_size=5))
def test_bordered_pfaffians_equal_the_lazy_elimination(n, lanes):
    """Every lane's (Pf Y, S) equals pfaffian_pair's on the explicit matrix, lanes with their own (s, t, y)."""
    ss, ts, ys = (np.array([float(v[i]) for v in lanes]) for i in range(3))
    L = len(lanes)
    pf, S, ok = np.empty(L), np.empty(L), np.empty(L, dtype=np.bool_)
    bordered_pfaffians(n, ss, ts, ys, inverse_table(n, P), P, lane_buffer(L), pf, S, ok)
    C, iota = de_bruijn_constants(n, P)
    for l, (s, t, y) in enumerate(lanes):
        pf1, S1, ok1 = _by_elimination(n, s, t, y, P, C, iota)
        assert bool(ok[l]) == ok1
        if ok1:
            assert (pf[l], S[l]) == (pf1, S1)


def test_a_vanishing_pivot_is_reported_on_the_same_lanes():
    """Modulo a small prime pivots vanish often: the kernel flags exactly the lanes the elimination cannot pivot."""
    p, n = 101, 6
    rng = np.random.default_rng(5)
    lanes = rng.integers(0, p, size=(400, 3)).astype(np.float64)
    pf, S, ok = np.empty(400), np.empty(400), np.empty(400, dtype=np.bool_)
    bordered_pfaffians(n, lanes[:, 0].copy(), lanes[:, 1].copy(), lanes[:, 2].copy(), inverse_table(n, p), p,
                       lane_buffer(400), pf, S, ok)
    C, iota = de_bruijn_constants(n, p)
    flagged = 0
    for l in range(400):
        pf1, S1, ok1 = _by_elimination(n, *lanes[l], p, C, iota)
        assert bool(ok[l]) == ok1 and (not ok1 or (pf[l], S[l]) == (pf1, S1))
        flagged += not ok1
    assert 0 < flagged < 400  # both branches ran


@pytest.mark.parametrize("n", [5, 6])
def test_the_grids_agree_through_their_fallbacks(n):
    """At a small prime some nodes need the pivoting fallback: both kernels' grids still give the same sums."""
    p = 211
    d = n * (n + 1) // 2
    C, iota = de_bruijn_constants(n, p)
    nodes = np.array([b * pow(d, p - 2, p) % p for b in range(d + 1)], dtype=np.float64)
    lam = dual_weights(nodes, np.array([pow(k + 1, p - 2, p) for k in range(d + 1)], dtype=np.float64), float(p))
    invx = inverse_table(n, p)
    pooled = [grid(n, d, p, lam, C, iota, invx, flag) for flag in (True, False)]
    assert pooled[0][2] > 0  # the fallback ran
    assert all((a == b).all() for a, b in zip(pooled[0][:2], pooled[1][:2]))
    zpos, with_zero = np.arange(1.0, (n + 1 - (1 - n % 2)) // 2 + 1), 1 - n % 2
    pairs = [grid_pairs(n, d, p, zpos, with_zero, lam, C, iota, invx, flag) for flag in (True, False)]
    assert pairs[0][2] > 0 and pairs[0][2] == pairs[1][2]
    assert all((a == b).all() for a, b in zip(pairs[0][:2], pairs[1][:2]))


@settings(max_examples=6, deadline=None)
@given(st.integers(2, 14), st.booleans())
def test_both_kernels_give_the_same_prime_residues(N, grains):
    p = floor_primes(N)[-1]
    assert (floor_prime_residues(N, p, grains) == floor_prime_residues(N, p, grains, kernel="elimination")).all()


def test_the_kernel_is_named_or_refused():
    with pytest.raises(ArgumentError, match="kernel='gko' is out of range"):
        floor_prime_residues(5, floor_primes(5)[0], kernel="gko")


def test_laws_by_the_displacement_kernel_match_the_mirror_and_the_pool():
    """N = 12: every load's law (displacement) pools to the pooled law, and W_{N,j} has the law of W_{N,N+1-j}."""
    laws = floor_gap_laws(12, workers=1)
    pooled = floor_pooled_gap_law(12, workers=1)
    assert all(laws[j] == laws[13 - j] for j in range(1, 13))
    assert tuple(sum(law.counts[g] for law in laws.values()) for g in range(len(pooled.counts))) == pooled.counts


@pytest.mark.parametrize("n", [126, 127])
def test_the_kernel_holds_at_the_routes_largest_order(n):
    """N = 127, 128: the stride's padding and the bounds at the largest order the route allows."""
    rng = np.random.default_rng(n)
    lanes = rng.integers(0, P, size=(3, 3)).astype(np.float64)
    pf, S, ok = np.empty(3), np.empty(3), np.empty(3, dtype=np.bool_)
    bordered_pfaffians(n, lanes[:, 0].copy(), lanes[:, 1].copy(), lanes[:, 2].copy(), inverse_table(n, P), P,
                       lane_buffer(3), pf, S, ok)
    C, iota = de_bruijn_constants(n, P)
    for l in range(3):
        assert _by_elimination(n, *lanes[l], P, C, iota) == (pf[l], S[l], bool(ok[l]))
