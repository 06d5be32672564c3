"""Coordinates of one configuration: W <-> q <-> S <-> contact forces, exactly."""

import random
from fractions import Fraction

import networkx as nx
import pytest
import sympy
from hypothesis import given
from hypothesis import strategies as st

from forcenet.exact.reference.linear_extensions import partial_sum_poset
from forcenet.exact.triangle.configuration import (
    W_from_partial_sums,
    W_from_q,
    bounds,
    contact_forces,
    in_ensemble,
    partial_sums,
    q_from_W,
)


def random_configuration(N, seed):
    """An exact rational point of the polytope: random order ideal chain + rational values."""
    rng = random.Random(seed)
    G = partial_sum_poset(N)
    order = list(nx.topological_sort(G))  # a valid linear extension; then perturb by swaps
    for _ in range(3 * len(order)):
        k = rng.randrange(len(order) - 1) if len(order) > 1 else 0
        if len(order) > 1 and not G.has_edge(order[k], order[k + 1]):
            order[k], order[k + 1] = order[k + 1], order[k]
    values = sorted(Fraction(rng.randrange(1, 10**6), 10**6) for _ in order)
    S = [[Fraction(0)] + [None] * (i - 1) + [Fraction(1)] for i in range(1, N + 1)]
    for (i, j), v in zip(order, values):
        S[i - 1][j] = v
    return W_from_partial_sums(S)


@given(st.integers(min_value=2, max_value=9), st.integers(min_value=0, max_value=10**6))
def test_random_points_are_in_the_ensemble_and_roundtrip(N, seed):
    W = random_configuration(N, seed)
    assert in_ensemble(W)
    q = q_from_W(W)
    assert all(v is None or 0 <= v <= 1 for v in q.values())
    q = {k: (v if v is not None else Fraction(1, 2)) for k, v in q.items()}
    assert W_from_q(q, N) == W
    assert W_from_partial_sums(partial_sums(W)) == W


@given(st.integers(min_value=2, max_value=9), st.integers(min_value=0, max_value=10**6))
def test_interlacing_equals_thesis_bounds(N, seed):
    W = random_configuration(N, seed)
    S = partial_sums(W)
    for i in range(2, N + 1):
        for j in range(1, i):
            a, b = bounds(W, i, j)
            # (4.8)-(4.9) <=> S_{i-1,j-1} <= S_{i,j} <= S_{i-1,j}
            assert a == S[i - 2][j - 1] - S[i - 1][j - 1]
            assert b == S[i - 2][j] - S[i - 1][j - 1]


@given(st.integers(min_value=2, max_value=7), st.data())
def test_any_q_in_unit_cube_gives_a_valid_configuration(N, data):
    q = {
        (i, j): Fraction(data.draw(st.integers(min_value=0, max_value=8)), 8)
        for i in range(1, N)
        for j in range(1, i + 1)
    }
    W = W_from_q(q, N)
    assert in_ensemble(W)


def test_points_outside_are_rejected():
    W = [[Fraction(1)], [Fraction(1, 2), Fraction(1, 2)], [Fraction(3, 4), Fraction(0), Fraction(1, 4)]]
    assert not in_ensemble(W)  # W_31 > b_31 = W_21
    with pytest.raises(ValueError, match="q"):
        W_from_q({(1, 1): Fraction(3, 2)}, 2)
    with pytest.raises(ValueError, match="row 2"):
        q_from_W([[1], [Fraction(1)]])


@given(st.integers(min_value=2, max_value=5), st.integers(min_value=0, max_value=10**6))
def test_contact_forces_balance_every_grain(N, seed):
    W = random_configuration(N, seed)
    forces = contact_forces(W)
    s3 = sympy.sqrt(3)
    for (i, j), (F1, F2, F3, F4, F5, F6) in forces.items():
        horizontal = F1 / 2 - F2 / 2 + F3 - F4 + F5 / 2 - F6 / 2
        vertical = s3 / 2 * (F5 + F6 - F1 - F2)
        assert sympy.simplify(horizontal) == 0
        assert sympy.simplify(vertical) == 0
        # the vertical load handed on is W_ij (Eq. 3.9 with g = 0)
        assert sympy.simplify(s3 / 2 * (F5 + F6) - W[i - 1][j - 1]) == 0
    # action-reaction (3.4): F3 of (i, j+1) is F4 of (i, j)
    for (i, j) in forces:
        if (i, j + 1) in forces:
            assert forces[(i, j + 1)][2] == forces[(i, j)][3]
