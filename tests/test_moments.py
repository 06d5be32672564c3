"""Higher moments and correlations: DP vs linear extensions vs symbolic integration."""

import pytest
from hypothesis import given
from hypothesis import strategies as st

from forcenet.exact import correlation, covariance, mean_W, moment, moment_table, variance_table
from forcenet.exact.reference.integration import integrate_moment
from forcenet.exact.reference.linear_extensions import linear_extension_moments


@pytest.fixture(scope="module")
def extensions6():
    pairs = [((6, 2), (5, 3)), ((6, 1), (6, 6)), ((4, 2), (6, 3)), ((3, 1), (3, 2))]
    return linear_extension_moments(6, s_max=4, pairs=pairs)


@pytest.mark.parametrize("N", [2, 3, 4, 5, 6])
def test_second_moment_table_equals_linear_extensions(N):
    _, moments, _ = linear_extension_moments(N, s_max=2)
    table = moment_table(N, 2)
    for (i, j), value in moments[2].items():
        assert table[i - 1][j - 1] == value


def test_second_moment_table_equals_symbolic_integration_N4():
    table = moment_table(4, 2)
    for i in range(2, 5):
        for j in range(1, i + 1):
            assert table[i - 1][j - 1] == integrate_moment(4, {(i, j): 2})


def test_symbolic_N5_second_moment_and_correlation():
    assert moment(5, (5, 2), 2) == integrate_moment(5, {(5, 2): 2})
    assert correlation(5, (5, 2), (4, 3)) == integrate_moment(5, {(5, 2): 1, (4, 3): 1})


@given(st.data())
def test_moments_up_to_4_equal_linear_extensions(extensions6, data):
    _, moments, _ = extensions6
    i = data.draw(st.integers(min_value=1, max_value=6))
    j = data.draw(st.integers(min_value=1, max_value=i))
    s = data.draw(st.integers(min_value=1, max_value=4))
    assert moment(6, (i, j), s) == moments[s][(i, j)]


def test_correlations_equal_linear_extensions(extensions6):
    _, _, correlations = extensions6
    for (g1, g2), value in correlations.items():
        assert correlation(6, g1, g2) == value
        assert correlation(6, g2, g1) == value


@given(st.integers(min_value=2, max_value=8), st.data())
def test_moment_inequalities(N, data):
    i = data.draw(st.integers(min_value=1, max_value=N))
    j = data.draw(st.integers(min_value=1, max_value=i))
    m1, m2, m3 = (moment(N, (i, j), s) for s in (1, 2, 3))
    assert m2 >= m1 * m1  # Jensen
    assert m1 >= m2 >= m3 >= 0  # 0 <= W <= 1


@given(st.integers(min_value=2, max_value=7), st.data())
def test_correlation_of_a_grain_with_itself_is_its_second_moment(N, data):
    i = data.draw(st.integers(min_value=1, max_value=N))
    j = data.draw(st.integers(min_value=1, max_value=i))
    assert correlation(N, (i, j), (i, j)) == moment(N, (i, j), 2)


@given(st.integers(min_value=2, max_value=7), st.data())
def test_row_covariances_sum_to_zero(N, data):
    # sum_j W_ij = 1 exactly, so sum_j Cov(W_ij, W_kl) = 0
    i = data.draw(st.integers(min_value=1, max_value=N))
    k = data.draw(st.integers(min_value=1, max_value=N))
    l = data.draw(st.integers(min_value=1, max_value=k))
    assert sum(covariance(N, (i, j), (k, l)) for j in range(1, i + 1)) == 0


def test_variance_table_matches_moments():
    var = variance_table(5)
    means = mean_W(5)
    for i in range(1, 6):
        for j in range(1, i + 1):
            assert var[i - 1][j - 1] == moment(5, (i, j), 2) - means[i - 1][j - 1] ** 2
            assert var[i - 1][j - 1] >= 0


@pytest.mark.parametrize("s, exc", [(0, ValueError), (-1, ValueError), (1.5, TypeError)])
def test_bad_order(s, exc):
    with pytest.raises(exc, match="s"):
        moment(4, (4, 1), s)


def test_moment_refuses_runs_that_do_not_fit():
    with pytest.raises(ValueError, match="N=40 is out of range"):
        moment(40, (20, 5), 2)
    with pytest.raises(ValueError, match="N=40 is out of range"):
        correlation(40, (20, 5), (30, 2))
