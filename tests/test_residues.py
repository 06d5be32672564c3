"""The one modular Gaussian elimination of the Pfaffian route (exact/triangle/pfaffian/residues.py) against Python integers."""

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from sympy import prevprime

from forcenet.exact.triangle.pfaffian.engine import prime_limit
from forcenet.exact.triangle.pfaffian.residues import SOLVE_SLACK, inv_mod, lazy_rounds, red, solve

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


@settings(max_examples=30, deadline=None)
@given(st.integers(min_value=1, max_value=12), st.integers(min_value=1, max_value=4),
       st.sampled_from([prevprime(TOP), prevprime(2**23), 8388593, 101, 7]), st.integers(min_value=0, max_value=2**32 - 1))
def test_solve_is_the_exact_inverse_times_the_right_side(s, m, p, seed):
    rng = np.random.default_rng(seed)
    K = rng.integers(0, p, size=(s, s)).astype(np.float64)
    Rhs = rng.integers(0, p, size=(s, m)).astype(np.float64)
    got = solve(K, Rhs, float(p), 1.0 / p)
    want = _solve_exact(K.tolist(), Rhs.tolist(), p)
    if want is None:
        assert got is None
    else:
        assert got.astype(np.int64).tolist() == want


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
