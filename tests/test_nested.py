"""Nested-matrix integration (thesis Secs. 4.3-4.5) against the exact core."""

from fractions import Fraction
from math import factorial

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from forcenet.exact import correlation, mean_W, moment, normalization
from forcenet.exact.thesis.nested import integrate_layers, mean_W_nested, moment_nested, normalization_nested


@pytest.mark.parametrize("N", [2, 3, 4, 5, 6])
def test_normalization(N):
    assert normalization_nested(N) == normalization(N)


@pytest.mark.parametrize("N", [3, 4, 5, 6])
def test_mean_table(N):
    table = mean_W(N)
    for i in range(1, N + 1):
        for j in range(1, i + 1):
            assert moment_nested(N, {(i, j): 1}) == table[i - 1][j - 1]


@settings(max_examples=15, deadline=None)
@given(st.integers(min_value=2, max_value=7), st.data())
def test_higher_moments(N, data):
    i = data.draw(st.integers(min_value=1, max_value=N))
    j = data.draw(st.integers(min_value=1, max_value=i))
    s = data.draw(st.integers(min_value=1, max_value=3))
    assert moment_nested(N, {(i, j): s}) == moment(N, (i, j), s)


@settings(max_examples=15, deadline=None)
@given(st.integers(min_value=2, max_value=7), st.data())
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
    with pytest.raises(TypeError, match=r"powers\[\(2, 1\)\]=0.5 is not an integer"):
        integrate_layers(4, {(2, 1): 0.5})
    with pytest.raises(TypeError, match=r"powers\[\(2, 1\)\]='1' is not an integer"):
        integrate_layers(4, {(2, 1): "1"})
    with pytest.raises(TypeError, match="powers"):
        integrate_layers(4, [(2, 1)])
    with pytest.raises(TypeError, match="powers key"):
        integrate_layers(4, {3: 1})
    with pytest.raises(ValueError, match="arithmetic"):
        integrate_layers(4, arithmetic="float")


def _random_powers(data, N, grains):
    powers = {}
    for _ in range(grains):
        i = data.draw(st.integers(min_value=1, max_value=N))
        j = data.draw(st.integers(min_value=1, max_value=i))
        powers[(i, j)] = data.draw(st.integers(min_value=0, max_value=3))
    return powers


@settings(max_examples=30, deadline=None)
@given(st.integers(min_value=2, max_value=6), st.integers(min_value=0, max_value=3), st.data())
def test_modular_equals_literal_recursion(N, grains, data):
    """The integer-indexed multi-modular engine equals the literal Fraction/dict recursion."""
    powers = _random_powers(data, N, grains)
    assert integrate_layers(N, powers, "modular") == integrate_layers(N, powers, "fraction")


@settings(max_examples=30, deadline=None)
@given(st.integers(min_value=2, max_value=5), st.integers(min_value=0, max_value=3), st.data())
def test_scaled_integral_is_an_integer_in_range(N, grains, data):
    """(d + s)! I is an integer in [0, (d + s)!]: what the modular reconstruction relies on.

    Computed with Fractions, never reduced modulo anything.
    """
    powers = _random_powers(data, N, grains)
    d = N * (N - 1) // 2
    scale = factorial(d + sum(e for g, e in powers.items() if g != (1, 1)))
    scaled = integrate_layers(N, powers, "fraction") * scale
    assert isinstance(scaled, Fraction) and scaled.denominator == 1
    assert 0 < scaled <= scale


@settings(max_examples=10, deadline=None)
@given(st.integers(min_value=3, max_value=6), st.integers(min_value=1, max_value=50), st.data())
def test_chunked_absorption_equals_one_chunk(N, chunk, data):
    """Integrating the last site in small chunks changes nothing."""
    import forcenet.exact.thesis.nested as nested

    powers = _random_powers(data, N, 2)
    whole = integrate_layers(N, powers)
    saved = nested._ABSORB_CHUNK
    try:
        nested._ABSORB_CHUNK = chunk
        assert integrate_layers(N, powers) == whole
    finally:
        nested._ABSORB_CHUNK = saved


@pytest.mark.parametrize("N", [7, pytest.param(8, marks=pytest.mark.slow)])  # N = 7 by default (and all routes at N = 7)
def test_mean_table_modular_N7_N8(N):
    assert mean_W_nested(N) == mean_W(N)


@pytest.mark.slow  # ~20 s; the nested route stays in the default suite at N = 7 (test_mean_table_modular_N7_N8)
def test_N9_normalization_and_a_bulk_grain():
    """N = 9, beyond the literal version's memory: ~10 s and ~1.5 GB per integration."""
    N = 9
    volume = integrate_layers(N)
    assert volume == normalization(N)
    assert integrate_layers(N, {(5, 3): 1}) / volume == mean_W(N)[4][2]


def test_mean_table_progress_counts_grains():
    calls = []
    mean_W_nested(4, progress=lambda: calls.append(1))
    assert len(calls) == 10


def test_all_routes_N7_higher_moments_and_correlations():
    """<W^2>, <W^3> of every grain and a set of correlations at N = 7: nested = maps = exact core."""
    from forcenet.exact.thesis import moments_by_maps

    N = 7
    grains = [(i, j) for i in range(1, N + 1) for j in range(1, i + 1)]
    pairs = [((7, 3), (6, 2)), ((4, 1), (7, 7)), ((5, 3), (5, 3)), ((2, 1), (6, 4)), ((7, 1), (7, 2))]
    _, by_maps, corr_maps = moments_by_maps(N, 3, pairs)
    for s in (2, 3):
        for g in grains:
            core = moment(N, g, s)
            assert moment_nested(N, {g: s}) == core == by_maps[s][g]
    for g1, g2 in pairs:
        powers = {g1: 2} if g1 == g2 else {g1: 1, g2: 1}
        assert moment_nested(N, powers) == correlation(N, g1, g2) == corr_maps[(g1, g2)]


@pytest.mark.slow
def test_mean_table_N9():
    """Every grain at N = 9 (46 integrations, ~12 min, under 2 GB each)."""
    assert mean_W_nested(9) == mean_W(9)
