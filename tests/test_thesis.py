"""Chapter 4's route against the exact core: Lambda, (4.67), maps and the bijection."""

from fractions import Fraction

import networkx as nx
import numpy as np
import pytest
import sympy
from hypothesis import given, settings
from hypothesis import strategies as st

from forcenet.exact import count, mean_W, normalization
from forcenet.exact.reference.linear_extensions import partial_sum_poset
from forcenet.exact.thesis import (
    boundary_mean_W,
    count_lambda,
    count_maps,
    gamma_coefficient,
    index_tuples,
    integral_I,
    is_map,
    lambda_table,
    map_from_tableau,
    maps,
    maps_by_bottom_row,
    normalization_lambda,
)
from forcenet.exact.triangle.staircase import grain_to_cell


@given(st.integers(min_value=0, max_value=5), st.integers(min_value=0, max_value=5))
def test_integral_4_14_equals_symbolic_integral(m, n):
    x, a, b = sympy.symbols("x a b")
    direct = sympy.integrate(x**m * (b - x) ** n, (x, a, b))
    via_4_14 = integral_I(m, n, a, b)
    assert sympy.expand(direct - sympy.nsimplify(via_4_14)) == 0


def test_gamma_coefficient_range():
    assert gamma_coefficient(2, 3, 0) == Fraction(2 * 6, 24 * 2)
    with pytest.raises(ValueError, match="k="):
        gamma_coefficient(2, 3, 3)


def test_index_range_4_32():
    for p in range(1, 6):
        tuples = list(index_tuples(p))
        assert len(set(tuples)) == len(tuples)
        for j in tuples:
            assert j[0] in (1, 2)
            assert all(1 <= j[l] <= (l + 1) + j[l - 1] for l in range(1, p))


@pytest.mark.parametrize("N", range(2, 11))
def test_lambda_sum_is_the_tableaux_count(N):
    assert count_lambda(N) == count(N)
    assert normalization_lambda(N) == normalization(N)


def literal_lambda(p):
    """Eq. (4.50) summed term by term (no prefix sums), p <= 5."""
    table = {(1,): 1}
    for q in range(1, p):
        new = {}
        for j in index_tuples(q + 1):
            if j[-1] != 1:
                continue
            s = sum(v for k, v in table.items() if all(j[l + 1] >= k[l] for l in range(q)))
            if s:
                new[j] = s
        table = new
    return table


@pytest.mark.parametrize("p", [1, 2, 3, 4, 5])
def test_prefix_sum_lambda_equals_literal_nested_sum(p):
    assert lambda_table(p) == literal_lambda(p)


@pytest.mark.parametrize("N", range(2, 10))
def test_boundary_formula_4_67_equals_exact_core(N):
    table = mean_W(N)
    for q in range(N):
        assert boundary_mean_W(N, q) == table[N - q - 1][0]


@pytest.mark.parametrize("N", [3, 4, 5, 6, 7])
def test_maps_count_and_bottom_rows(N):
    assert count_maps(N) == count(N)
    assert dict(maps_by_bottom_row(N)) == lambda_table(N - 2)
    assert all(is_map(h, N - 2) for h in maps(N))


def all_tableaux(N):
    G = partial_sum_poset(N)
    for ext in nx.all_topological_sorts(G):
        yield {grain_to_cell(N, *g): k + 1 for k, g in enumerate(ext)}


@pytest.mark.parametrize("N", [3, 4, 5, 6])
def test_map_from_tableau_is_a_bijection(N):
    images = [map_from_tableau(N, T) for T in all_tableaux(N)]
    keys = {tuple(sorted(h.items())) for h in images}
    assert len(keys) == len(images) == count_maps(N)
    assert all(is_map(h, N - 2) for h in images)


@given(st.integers(min_value=4, max_value=12), st.integers(min_value=0, max_value=2**32 - 1))
def test_random_tableaux_map_to_valid_maps_with_first_row_code(N, seed):
    import numpy as np

    from forcenet.numeric.triangle.exact_sampler import sample_tableaux

    T_arr = sample_tableaux(N, 1, np.random.default_rng(seed))[0]
    n = N - 1
    T = {(r, c): int(T_arr[r, c]) for r in range(1, n + 1) for c in range(r, n + 1)}
    h = map_from_tableau(N, T)
    assert is_map(h, N - 2)
    # the first tableau row is Eq. (4.67)'s statistic of the last map row
    for q in range(1, N - 1):
        j = 1 if q == 1 else h[N - 2][q - 2]
        assert T[(1, q + 1)] == q * (q + 1) // 2 + 2 - j


def _random_map(N, data):
    """A map of Sec. 4.6 drawn row by row inside (4.86) and (4.89), never through a tableau."""
    h = {}
    for l in range(1, N - 1):
        row = []
        for k in range(1, l):
            top = 2 if k == 1 else k + row[-1]  # (4.86)
            low = 1 if (l == 1 or k == 1) else h[l - 1][k - 2]  # (4.89): h(l-1, k-1) <= h(l, k)
            row.append(data.draw(st.integers(min_value=low, max_value=top)))
        row.append(1)  # h(l, l) = 1
        h[l] = tuple(row)
    return h


def _is_standard_shifted_tableau(N, T):
    n = N - 1
    cells = [(r, c) for r in range(1, n + 1) for c in range(r, n + 1)]
    return (sorted(T.values()) == list(range(1, len(cells) + 1))
            and all(T[(r, c)] < T[(r, c + 1)] for (r, c) in cells if c < n)
            and all(T[(r, c)] < T[(r + 1, c)] for (r, c) in cells if r < c))


@settings(max_examples=40, deadline=None)
@given(st.integers(min_value=3, max_value=12), st.data())
def test_every_map_has_a_tableau(N, data):
    """Surjectivity of the bijection, for maps drawn from the inequalities alone (proof in notes/chapter4.md)."""
    from forcenet.exact.thesis import tableau_from_map

    h = _random_map(N, data)
    assert is_map(h, N - 2)
    T = tableau_from_map(N, h)
    assert _is_standard_shifted_tableau(N, T)
    assert map_from_tableau(N, T) == h


def test_bad_q():
    with pytest.raises(ValueError, match="q=7"):
        boundary_mean_W(5, 7)


@pytest.mark.parametrize("N", [3, 4, 5, 6])
def test_inverse_bijection(N):
    from forcenet.exact.thesis import tableau_from_map

    for h in maps(N):
        assert map_from_tableau(N, tableau_from_map(N, h)) == h
    for T in all_tableaux(N):
        assert tableau_from_map(N, map_from_tableau(N, T)) == T


@pytest.mark.parametrize("N", [2, 3, 4, 5, 6, 7])
def test_maps_route_full_table(N):
    from forcenet.exact.thesis import mean_W_by_maps

    assert mean_W_by_maps(N) == mean_W(N)


def test_tableau_from_invalid_map_raises():
    from forcenet.exact.thesis import tableau_from_map

    with pytest.raises(ValueError, match="not a map"):
        tableau_from_map(5, {1: (1,), 2: (2, 1), 3: (1, 1, 1)})  # violates (4.89)


@pytest.mark.parametrize("N", [2, 3, 4, 5, 6, pytest.param(7, marks=pytest.mark.slow)])  # N <= 6 by default
def test_thesis_map_formula_4_91_full_table(N):
    from forcenet.exact.thesis import mean_W_thesis_maps

    assert mean_W_thesis_maps(N) == mean_W(N)


@pytest.mark.slow
def test_thesis_map_formula_4_91_full_table_N8():
    """All 21 bulk grains at N = 8 by enumerating the modified maps (~35 min)."""
    from forcenet.exact.thesis import mean_W_thesis_maps

    assert mean_W_thesis_maps(8) == mean_W(8)


@given(st.integers(min_value=3, max_value=16))
def test_bottom_layer_is_the_average_of_the_layer_above(N):
    # the last layer's q's are uniform and independent (they do not enter Eq. 3.10)
    table = mean_W(N)
    for r in range(1, N + 1):
        left = table[N - 2][r - 2] if r >= 2 else 0
        right = table[N - 2][r - 1] if r <= N - 1 else 0
        assert table[N - 1][r - 1] == (left + right) / 2


@pytest.mark.parametrize("N", range(2, 10))
def test_gamma_recursion_full_table(N):
    from forcenet.exact.thesis import mean_W_gamma

    assert mean_W_gamma(N) == mean_W(N)


def test_gamma_sums_count_modified_maps():
    from forcenet.exact.thesis import gamma_sums

    N, q, r = 6, 1, 3
    line = {N - r + j: {q + j} for j in range(r - 1) if N - r + j <= N - 2}
    mods = list(maps(N, line))
    Z, S1, S0 = gamma_sums(N, q, r)
    assert Z == len(mods)
    N, q, r = 7, 2, 3
    line = {N - r + j: {q + j} for j in range(r - 1) if N - r + j <= N - 2}
    mods = list(maps(N, line))
    Z, S1, S0 = gamma_sums(N, q, r)
    assert (Z, S1, S0) == (len(mods), sum(h[N - r][q - 2] for h in mods), sum(h[N - r - 1][q - 2] for h in mods))


@settings(max_examples=20)
@given(st.integers(min_value=3, max_value=7), st.data())
def test_sth_order_defects_moments(N, data):
    from forcenet.exact import moment
    from forcenet.exact.thesis import moment_thesis_maps

    i = data.draw(st.integers(min_value=1, max_value=N - 1))
    j = data.draw(st.integers(min_value=1, max_value=i))
    s = data.draw(st.integers(min_value=1, max_value=3))
    assert moment_thesis_maps(N, (i, j), s) == moment(N, (i, j), s)


def test_sth_order_defects_refuse_bottom_layer():
    from forcenet.exact.thesis import moment_thesis_maps

    with pytest.raises(ValueError, match="bottom layer"):
        moment_thesis_maps(5, (5, 2), 2)


@pytest.mark.parametrize("N", [5, 6, 7, 8, 9, 10])
def test_lambda_chain_equals_whole_table(N):
    from forcenet.exact.thesis.recursions import _lambda_sum_mod, _lambda_weighted_sums_box

    prime = 2147483647
    reference = [x % prime for x in _lambda_weighted_sums_box(N)]
    chain = [_lambda_sum_mod(N, prime)] + [_lambda_sum_mod(N, prime, k) for k in range(1, N - 2)]
    assert chain == reference


@pytest.mark.slow
def test_lambda_normalization_N12():
    from forcenet.exact.thesis import count_lambda

    assert count_lambda(12) == count(12)


@pytest.mark.parametrize("N", [3, 4, 5, 6, pytest.param(7, marks=pytest.mark.slow)])  # N <= 6 by default
def test_maps_route_moments_every_grain(N):
    # map counting (through the tableau bijection) against the exact core, s <= 3, bottom layer included
    from forcenet.exact import moment
    from forcenet.exact.thesis import moments_by_maps

    Z, moments, _ = moments_by_maps(N, s_max=3)
    assert Z == count_lambda(N)
    for s in (2, 3):
        for (i, j), value in moments[s].items():
            if N == 7 and (i + j) % 3:  # N = 7: a third of the grains keeps the exact core quick
                continue
            assert value == moment(N, (i, j), s), (N, i, j, s)


@settings(max_examples=10, deadline=None)  # 10 derandomized examples (~30 s for 25 on the shared machine)
@given(st.integers(min_value=2, max_value=7), st.data())
def test_maps_route_correlations(N, data):
    from forcenet.exact import correlation
    from forcenet.exact.thesis import moments_by_maps

    def grain():
        i = data.draw(st.integers(min_value=1, max_value=N))
        return (i, data.draw(st.integers(min_value=1, max_value=i)))

    pairs = [(grain(), grain()) for _ in range(3)]
    _, _, corr = moments_by_maps(N, 1, pairs)
    for g1, g2 in pairs:
        assert corr[(g1, g2)] == correlation(N, g1, g2)


@settings(max_examples=10, deadline=None)
@given(st.integers(min_value=3, max_value=5), st.data())
def test_maps_route_equals_nested_integration(N, data):
    # two thesis routes: map counting and the nested-matrix integration (4.14)-(4.46)
    from forcenet.exact.thesis import moments_by_maps
    from forcenet.exact.thesis.nested import moment_nested

    i1 = data.draw(st.integers(min_value=1, max_value=N))
    g1 = (i1, data.draw(st.integers(min_value=1, max_value=i1)))
    i2 = data.draw(st.integers(min_value=1, max_value=N))
    g2 = (i2, data.draw(st.integers(min_value=1, max_value=i2)))
    s = data.draw(st.integers(min_value=1, max_value=3))
    _, moments, corr = moments_by_maps(N, s, [(g1, g2)])
    assert moments[s][g1] == moment_nested(N, {g1: s})
    powers = {g1: 1, g2: 1} if g1 != g2 else {g1: 2}
    assert corr[(g1, g2)] == moment_nested(N, powers)


def test_maps_route_bad_input():
    from forcenet.exact.thesis import moments_by_maps

    with pytest.raises(ValueError, match="s_max"):
        moments_by_maps(4, 0)
    with pytest.raises(ValueError, match="pairs"):
        moments_by_maps(4, 1, [((5, 1), (1, 1))])


@pytest.mark.parametrize("N", [3, 4, 5, 6, 7])
def test_printed_fundamental_relations_give_the_normalization(N):
    # (4.28)-(4.31) and (4.46) read literally: L t(W=1) R over the index tuples (4.32)
    from forcenet.exact.thesis import normalization_fundamental

    assert normalization_fundamental(N) == normalization(N)


@pytest.mark.parametrize("p", [2, 3, 4, 5])
def test_right_vector_is_lambda_over_factorials_4_49(p):
    from math import factorial

    from forcenet.exact.thesis import right_vector

    R = right_vector(p)
    lam = lambda_table(p)
    for j in index_tuples(p):
        exps = [l + j[l - 2] - j[l - 1] for l in range(2, p + 1)]
        expected = Fraction(0)
        if all(e >= 0 for e in exps) and lam.get(j, 0):
            d = 1
            for e in exps:
                d *= factorial(e)
            expected = Fraction(lam[j], d)
        assert R.get(j, Fraction(0)) == expected, j


@given(st.integers(min_value=1, max_value=4), st.data())
def test_psi_is_a_product_of_central_integral_coefficients(p, data):
    # (4.30) recursively equals (4.29) as a product; the first factor is (4.25)'s psi^{2-i1}_{1,2-j1}
    from forcenet.exact.thesis import psi_fundamental

    tuples = list(index_tuples(p))
    i = data.draw(st.sampled_from(tuples))
    j = data.draw(st.sampled_from(tuples))
    value = psi_fundamental(i, j)
    if p == 1:
        assert value == gamma_coefficient(1, 2 - j[0], i[0] - 1)
    else:
        last = psi_fundamental(i[:-1], j[:-1])
        l, ip, jp, il, jl = p, i[-2], j[-2], i[-1], j[-1]
        s, e, f = l + ip - jp, l + jp - jl, l + ip - il
        factor = gamma_coefficient(s, e, s - f) if (il >= jp and 0 <= f <= s and e >= 0) else 0
        assert value == last * factor


@settings(max_examples=40, deadline=None)
@given(st.integers(min_value=4, max_value=9), st.data())
def test_gamma_bulk_integer_equals_three_gamma_sums(N, data):
    """One combined modular pass (last row as a chain) = the three object-array sums."""
    from forcenet.exact.thesis import gamma_bulk_integer, gamma_sums

    q = data.draw(st.integers(min_value=1, max_value=N - 2))
    r = data.draw(st.integers(min_value=2, max_value=N - q))
    Z, S1, S0 = gamma_sums(N, q, r)
    assert gamma_bulk_integer(N, q, r) == (q + 1) * Z + S1 - S0


@settings(max_examples=60, deadline=None)
@given(st.integers(min_value=2, max_value=7), st.data())
def test_last_row_chain_equals_built_row(p, data):
    """The chain sum over row p equals building row p (_transfer) and summing it, any raised bounds and weight."""
    from forcenet.exact.thesis.recursions import _last_row_chain, _mod_reducer, _transfer

    prime = 1_000_003
    reduce = _mod_reducer(prime)
    raised = [frozenset(data.draw(st.sets(st.integers(min_value=1, max_value=l - 1)))) if l >= 2 else frozenset()
              for l in range(1, p + 1)]
    box = np.ones((), dtype=np.int64)
    for l in range(2, p):
        box = _transfer(box, l - 1, raised[l - 1], reduce)
    weight = data.draw(st.one_of(st.none(), st.integers(min_value=1, max_value=p - 1)))
    built = _transfer(box, p - 1, raised[p - 1], reduce)
    if weight is not None:
        values = np.arange(1, built.shape[weight - 1] + 1).reshape([-1 if ax == weight - 1 else 1 for ax in range(built.ndim)])
        built = built * values
    assert _last_row_chain(box, p, raised[p - 1], reduce, weight) % prime == int(built.sum()) % prime


def test_gamma_bulk_integer_rejects_bad_grains():
    from forcenet.exact.thesis import gamma_bulk_integer

    with pytest.raises(ValueError, match=r"r=5 is out of range: r must be an integer in 2\.\.4"):
        gamma_bulk_integer(7, 3, 5)
    with pytest.raises(ValueError, match="q=0 is out of range"):
        gamma_bulk_integer(7, 0, 2)
