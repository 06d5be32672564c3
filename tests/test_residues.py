"""The one modular Gaussian elimination of the Pfaffian route (exact/triangle/residues.py) against Python integers."""

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from sympy import prevprime

from forcenet.exact.triangle.free_fermion.cost import prime_limit
from forcenet.exact.triangle.residues import SOLVE_SLACK, inv_mod, lazy_rounds, red, skew_solve, solve

TOP = prime_limit(1)  # the route's primes are below 2^25


def _solve_exact(K, Rhs, p):
    """``K^{-1} Rhs mod p`` by textbook elimination on Python ints (None if singular)."""
    s, m = len(K), len(Rhs[0])
    M = [[int(x) % p for x in K[i]] + [int(x) % p for x in Rhs[i]] for i in range(s)]
    for c in range(s):
        r = next((i for i in range(c, s) if M[i][c]), None)
        if r is None:
            return None
        M[c], M[r] = M[r], M[c]
        f = pow(M[c][c], p - 2, p)
        M[c] = [x * f % p for x in M[c]]
        for i in range(s):
            if i != c and M[i][c]:
                g = M[i][c]
                M[i] = [(x - g * y) % p for x, y in zip(M[i], M[c])]
    return [row[s : s + m] for row in M]


def _agrees_with_python_integers(solver, K, Rhs, p):
    """``solver`` (float64 residues) and :func:`_solve_exact` give the same solution, or both say singular."""
    got = solver(np.asarray(K, dtype=np.float64), np.asarray(Rhs, dtype=np.float64), float(p), 1.0 / p)
    want = _solve_exact(np.asarray(K).tolist(), np.asarray(Rhs).tolist(), p)
    if want is None:
        assert got is None
    else:
        assert got.astype(np.int64).tolist() == want


@settings(max_examples=30, deadline=None)
@given(st.integers(min_value=1, max_value=12), st.integers(min_value=1, max_value=4),
       st.sampled_from([prevprime(TOP), prevprime(2**23), 8388593, 101, 7]), st.integers(min_value=0, max_value=2**32 - 1))
def test_solve_is_the_exact_inverse_times_the_right_side(s, m, p, seed):
    rng = np.random.default_rng(seed)
    K = rng.integers(0, p, size=(s, s)).astype(np.float64)
    Rhs = rng.integers(0, p, size=(s, m)).astype(np.float64)
    _agrees_with_python_integers(solve, K, Rhs, p)


def test_solve_of_the_identity_is_the_inverse_and_sees_a_singular_matrix():
    p = prevprime(TOP)
    K = np.array([[2.0, 3.0], [5.0, 7.0]])
    Ki = solve(K, np.eye(2), float(p), 1.0 / p).astype(np.int64)
    assert ((np.array([[2, 3], [5, 7]]) @ Ki) % p).tolist() == [[1, 0], [0, 1]]
    assert solve(np.array([[1.0, 2.0], [2.0, 4.0]]), np.eye(2), float(p), 1.0 / p) is None


@given(st.integers(min_value=3, max_value=TOP - 1))
def test_the_lazy_bound_keeps_every_value_exact_and_reducible(q):
    """The proof in lazy_rounds' docstring, in integers: after L rounds an entry x < p + L (p-1)^2, and x + p <= 2^53."""
    p = int(prevprime(q + 1))
    L = lazy_rounds(float(p))
    assert L >= 1
    assert (p - 1) + L * (p - 1) ** 2 + p <= 2**53
    assert SOLVE_SLACK >= 2 * p  # the slack covers the correction of red() for every prime of the route


def test_red_and_inv_mod_on_the_largest_prime():
    p = prevprime(TOP)
    x = float((p - 1) * (p - 1) * 8)  # a sum of eight products of residues, below 2^53
    assert int(red(x, float(p), 1.0 / p)) == (p - 1) * (p - 1) * 8 % p
    assert int(inv_mod(12345.0, float(p), 1.0 / p)) * 12345 % p == 1


def _skew(rng, s, p, density, zero_block):
    K = rng.integers(0, p, size=(s, s)) * (rng.random((s, s)) < density)
    if zero_block:  # a zero leading block: the first pivot row must look past it, and exchanges happen
        K[: s // 2, : s // 2] = 0
    K = np.triu(K, 1)
    return (K - K.T) % p


@settings(max_examples=60, deadline=None)
@given(st.integers(min_value=1, max_value=24), st.integers(min_value=1, max_value=4),
       st.sampled_from([prevprime(TOP), 8388593, 101, 7, 3]), st.sampled_from([1.0, 0.3, 0.1]), st.booleans(),
       st.integers(min_value=0, max_value=2**32 - 1))
def test_skew_solve_is_the_exact_inverse_times_the_right_side(s, m, p, density, zero_block, seed):
    """Bunch's elimination on skew-symmetric matrices against textbook elimination on Python ints (singular ones too)."""
    rng = np.random.default_rng(seed)
    K = _skew(rng, s, p, density, zero_block)
    Rhs = rng.integers(0, p, size=(s, m))
    _agrees_with_python_integers(skew_solve, K, Rhs, p)


def test_skew_solve_reads_only_the_upper_triangle_and_sees_odd_sizes_singular():
    p = prevprime(TOP)
    rng = np.random.default_rng(7)
    K = _skew(rng, 10, p, 1.0, False)
    Rhs = rng.integers(0, p, size=(10, 3)).astype(np.float64)
    upper = np.triu(K, 1).astype(np.float64)
    want = solve(K.astype(np.float64), Rhs, float(p), 1.0 / p)
    assert want is not None
    assert skew_solve(upper, Rhs, float(p), 1.0 / p).tolist() == want.tolist()
    assert skew_solve(_skew(rng, 9, p, 1.0, False).astype(np.float64), Rhs[:9], float(p), 1.0 / p) is None


def test_skew_solve_solves_the_routes_kernels_as_the_general_elimination_does():
    """The kernel K(c) = B + Q X1 Q of the Pfaffian route (skew-symmetric), at several N, c and primes."""
    from forcenet.exact.triangle.free_fermion.engine import setup_matrices

    for N, p in ((5, 8388593), (12, prevprime(TOP)), (31, 1000003)):
        n = N - 1
        B, X1, expo = setup_matrices(n, p)
        rng = np.random.default_rng(N)
        for c in (2, 12345, p - 3):
            q = np.array([pow(c, int(e), p) for e in expo], dtype=object)
            K = (B.astype(np.int64).astype(object) + (q[:, None] * X1.astype(np.int64).astype(object) % p) * q[None, :]) % p
            K = K.astype(np.float64)
            assert (K + K.T).astype(np.int64).__mod__(p).max() == 0  # skew-symmetric modulo p
            Rhs = rng.integers(0, p, size=(K.shape[0], 4)).astype(np.float64)
            want, got = solve(K, Rhs, float(p), 1.0 / p), skew_solve(K, Rhs, float(p), 1.0 / p)
            assert (want is None) == (got is None)
            if want is not None:
                assert got.tolist() == want.tolist()


@given(st.integers(min_value=3, max_value=TOP - 1))
def test_the_skew_elimination_stays_within_the_lazy_bound(q):
    """skew_solve reduces every lazy_rounds // 2 pivot pairs, two products per pair and entry."""
    p = int(prevprime(q + 1))
    pairs = max(1, lazy_rounds(float(p)) // 2)
    assert (p - 1) + 2 * pairs * (p - 1) ** 2 + p <= 2**53
