"""Counts and normalization: product formula vs hooks vs enumeration vs integration."""

from fractions import Fraction
from math import factorial

import networkx as nx
import pytest
from hypothesis import given
from hypothesis import strategies as st

from forcenet.exact.reference.integration import integrate_moment
from forcenet.exact.reference.linear_extensions import partial_sum_poset
from forcenet.exact.triangle.staircase import (
    cell_to_grain,
    check_layers,
    count,
    count_by_hooks,
    grain_to_cell,
    normalization,
    shifted_tableaux_count,
)

# OEIS A003121 and the thesis's Lambda sums (published): N = 3..8
A003121 = [1, 2, 12, 286, 33592, 23178480]


def test_count_matches_published_sequence():
    assert [count(N) for N in range(3, 9)] == A003121


@given(st.integers(min_value=2, max_value=30))
def test_product_formula_equals_hook_formula(N):
    assert count(N) == count_by_hooks(N)


@pytest.mark.parametrize("N", [2, 3, 4, 5, 6, 7])
def test_count_equals_number_of_linear_extensions(N):
    G = partial_sum_poset(N)
    extensions = sum(1 for _ in nx.all_topological_sorts(G)) if G.number_of_nodes() else 1
    assert extensions == count(N)


@pytest.mark.parametrize("N", [2, 3, 4, 5])
def test_normalization_equals_symbolic_volume(N):
    assert integrate_moment(N) == normalization(N)


@given(st.integers(min_value=2, max_value=60))
def test_normalization_is_count_over_d_factorial(N):
    d = N * (N - 1) // 2
    assert normalization(N) == Fraction(count(N), factorial(d))
    # closed form prod k!/(2k+1)!
    closed = Fraction(1)
    for k in range(N - 1):
        closed *= Fraction(factorial(k), factorial(2 * k + 1))
    assert normalization(N) == closed


def test_count_large_N_is_an_int_with_the_right_size():
    from math import lgamma, log

    c = count(300)
    assert isinstance(c, int)
    n = 299
    d = n * (n + 1) // 2
    log2 = (lgamma(d + 1) + sum(lgamma(k + 1) - lgamma(2 * k + 2) for k in range(n))) / log(2)
    assert abs(c.bit_length() - log2) < 2


@given(st.integers(min_value=2, max_value=12), st.data())
def test_grain_cell_roundtrip(N, data):
    i = data.draw(st.integers(min_value=2, max_value=N))
    j = data.draw(st.integers(min_value=1, max_value=i - 1))
    assert cell_to_grain(N, *grain_to_cell(N, i, j)) == (i, j)


def test_hook_formula_small_shapes():
    assert shifted_tableaux_count((3, 1)) == 2
    assert shifted_tableaux_count((1,)) == 1
    with pytest.raises(ValueError, match="parts"):
        shifted_tableaux_count((2, 2))


@pytest.mark.parametrize("bad, exc", [(1, ValueError), (0, ValueError), (-3, ValueError), (2.5, TypeError), ("5", TypeError), (True, TypeError)])
def test_bad_layers_are_rejected_with_a_clear_message(bad, exc):
    with pytest.raises(exc, match=r"N=.*N must be an integer >= 2"):
        check_layers(bad)
    with pytest.raises(exc):
        count(bad)
