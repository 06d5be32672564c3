"""<W_ij>: fast DP vs dictionary DP vs linear extensions vs symbolic integration."""

from fractions import Fraction

import pytest
from hypothesis import given

from forcenet.exact import mean_W, mean_W_grain, moment
from forcenet.exact.reference.dictionary_dp import mean_W_dictionary
from forcenet.exact.reference.integration import integrate_moment
from forcenet.exact.reference.linear_extensions import linear_extension_moments
from forcenet.testing import strategies as fst

layers = fst.layers(2, 14)


@given(fst.layers(2, 9))
def test_fast_dp_equals_dictionary_dp(N):
    assert mean_W(N) == mean_W_dictionary(N)


@pytest.mark.parametrize("N", [2, 3, 4, 5, 6])
def test_fast_dp_equals_linear_extension_average(N):
    _, moments, _ = linear_extension_moments(N, s_max=1)
    table = mean_W(N)
    for (i, j), value in moments[1].items():
        assert table[i - 1][j - 1] == value


@pytest.mark.parametrize("N", [2, 3, 4])
def test_fast_dp_equals_symbolic_integration_full_table(N):
    table = mean_W(N)
    for i in range(2, N + 1):
        for j in range(1, i + 1):
            assert table[i - 1][j - 1] == integrate_moment(N, {(i, j): 1})


@pytest.mark.parametrize("grain", [(5, 1), (5, 3), (4, 2), (3, 2)])
def test_symbolic_integration_N5(grain):
    assert mean_W_grain(5, *grain) == integrate_moment(5, {grain: 1})


def test_published_values():
    # values quoted as published in issue #2: N = 5 bottom row and <W_{6,2}>
    assert mean_W(5)[-1] == [Fraction(1, 11), Fraction(1, 4), Fraction(7, 22), Fraction(1, 4), Fraction(1, 11)]
    assert mean_W_grain(6, 6, 2) == Fraction(413, 2288)


@given(layers)
def test_rows_sum_to_one_and_values_in_unit_interval(N):
    for row in mean_W(N):
        assert sum(row) == 1
        assert all(0 <= x <= 1 for x in row)


@given(layers)
def test_left_right_symmetry(N):
    for row in mean_W(N):
        assert row == row[::-1]


@given(fst.layers(3, 16))
def test_boundary_identities(N):
    table = mean_W(N)
    assert table[N - 1][0] == table[N - 2][0] / 2
    assert table[N - 2][0] == Fraction(4, N * (N - 1) + 2)


@given(fst.layers_and_grains(2, 14))
def test_single_grain_equals_table_entry(case):
    N, (i, j) = case
    assert mean_W_grain(N, i, j) == mean_W(N)[i - 1][j - 1]


@pytest.mark.parametrize("grain, exc", [((0, 1), ValueError), ((3, 4), ValueError), (("a", 1), TypeError), ((1,), TypeError)])
def test_bad_grain(grain, exc):
    with pytest.raises(exc, match="grain"):
        moment(3, grain, 1)


@pytest.mark.slow
@pytest.mark.parametrize("N", [7])
def test_linear_extensions_N7(N):
    _, moments, _ = linear_extension_moments(N, s_max=1)
    table = mean_W(N)
    assert all(table[i - 1][j - 1] == v for (i, j), v in moments[1].items())


@pytest.mark.slow
def test_dictionary_dp_N12():
    assert mean_W(12) == mean_W_dictionary(12)


def test_mean_table_refuses_runs_that_do_not_fit():
    from forcenet.exact.triangle.ideal_dp import survival_counts

    with pytest.raises(ValueError, match="N=45 is out of range"):
        mean_W(45)
    with pytest.raises(ValueError, match="N=33 is out of range"):
        survival_counts(33, memory_bytes=2**30)
