"""Nested-matrix integration (thesis Secs. 4.3-4.5) against the exact core."""

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from exact import correlation, mean_W, moment, normalization
from exact.nested import integrate_layers, moment_nested, normalization_nested


@pytest.mark.parametrize("N", [2, 3, 4, 5, 6])
def test_normalization(N):
    assert normalization_nested(N) == normalization(N)


@pytest.mark.parametrize("N", [3, 4, 5, 6])
def test_mean_table(N):
    table = mean_W(N)
    for i in range(1, N + 1):
        for j in range(1, i + 1):
            assert moment_nested(N, {(i, j): 1}) == table[i - 1][j - 1]


@settings(max_examples=15)
@given(st.integers(min_value=2, max_value=5), st.data())
def test_higher_moments(N, data):
    i = data.draw(st.integers(min_value=1, max_value=N))
    j = data.draw(st.integers(min_value=1, max_value=i))
    s = data.draw(st.integers(min_value=1, max_value=3))
    assert moment_nested(N, {(i, j): s}) == moment(N, (i, j), s)


@settings(max_examples=15)
@given(st.integers(min_value=2, max_value=5), st.data())
def test_correlations(N, data):
    g1 = (i := data.draw(st.integers(min_value=1, max_value=N)), data.draw(st.integers(min_value=1, max_value=i)))
    g2 = (k := data.draw(st.integers(min_value=1, max_value=N)), data.draw(st.integers(min_value=1, max_value=k)))
    powers = {g1: 1} if g1 == g2 else {g1: 1, g2: 1}
    if g1 == g2:
        powers = {g1: 2}
    assert moment_nested(N, powers) == correlation(N, g1, g2)


def test_bad_powers():
    with pytest.raises(ValueError, match="powers"):
        integrate_layers(4, {(5, 1): 1})
    with pytest.raises(ValueError, match="powers"):
        integrate_layers(4, {(2, 1): -1})


@pytest.mark.slow
def test_mean_table_N7_and_moments():
    N = 7
    table = mean_W(N)
    for i in range(1, N + 1):
        for j in range(1, i + 1):
            assert moment_nested(N, {(i, j): 1}) == table[i - 1][j - 1]
    for grain in [(7, 3), (5, 2), (6, 6)]:
        for s in (2, 3):
            assert moment_nested(N, {grain: s}) == moment(N, grain, s)
    assert moment_nested(N, {(7, 3): 1, (6, 2): 1}) == correlation(N, (7, 3), (6, 2))
