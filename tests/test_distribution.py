"""Exact force distributions (issue 16): the gap-law DP against independent routes.

(a) moments of the exact density = ``moment()`` (the marked-chain DP) for every grain, s <= 4, N <= 12;
(b) the density = sympy integration over the polytope (``exact.reference.integration``) for N <= 4
    (moments 0..d-1 fix a polynomial of degree d-1; one more moment checks it), and the indicator
    integrated directly at N = 3;
(c) gap laws of W, F5, F6 and the joint laws of q = enumeration of the linear extensions of the
    partial-sum poset (networkx), with the partial sums themselves, no cells and no DP;
(d) the exact sampler, statistically (5 sigma).
"""

from collections import Counter
from fractions import Fraction
from functools import cache

import networkx as nx
import numpy as np
import pytest
import sympy
from hypothesis import given, settings
from hypothesis import strategies as st

from forcenet.exact import count, mean_W, moment
from forcenet.exact.reference.integration import integrate_moment
from forcenet.exact.reference.linear_extensions import partial_sum_poset
from forcenet.exact.triangle import distribution as D
from forcenet.exact.triangle import gaps as G
from forcenet.exact.triangle.joint_gaps import joint_gap_counts, q_gap_counts

w, f = D.W_SYMBOL, D.F_SYMBOL


def poly_moment(poly: sympy.Poly, s: int) -> Fraction:
    """``int_0^1 x^s poly(x) dx`` exactly from the coefficients."""
    return sum((Fraction(int(c.p), int(c.q)) / (m + s + 1) for (m,), c in poly.terms()), Fraction(0))


def integral(poly, lo, hi, power=0):
    F = (poly * sympy.Poly(poly.gens[0] ** power, poly.gens[0], domain="QQ")).integrate()
    return F.eval(hi) - F.eval(lo)


def grains(N, first_layer=2):
    return [(i, j) for i in range(first_layer, N + 1) for j in range(1, i + 1)]


@st.composite
def grain_of(draw, N_min=2, N_max=12):
    N = draw(st.integers(min_value=N_min, max_value=N_max))
    i = draw(st.integers(min_value=2, max_value=N))
    return N, (i, draw(st.integers(min_value=1, max_value=i)))


# ---------------------------------------------------------------- route (a): moment()


@pytest.mark.parametrize("N", [2, 3, 4, 5, 6, 7, 8, 9, 10, pytest.param(11, marks=pytest.mark.slow),
                               pytest.param(12, marks=pytest.mark.slow)])  # N <= 10 by default
def test_density_moments_equal_the_moment_dp_for_every_grain(N):
    for grain in grains(N):
        p = D.density(N, grain)
        assert poly_moment(p, 0) == 1
        gaps = G.grain_gap_counts(N, grain)
        for s in range(1, 5):
            expected = moment(N, grain, s)
            assert poly_moment(p, s) == expected
            assert D.moment_from_gaps(gaps, s) == expected


@settings(max_examples=15)
@given(grain_of(9, 12), st.integers(min_value=1, max_value=4))
def test_density_moments_equal_the_moment_dp_hypothesis(case, s):
    N, grain = case
    assert poly_moment(D.density(N, grain), s) == moment(N, grain, s)


@pytest.mark.parametrize("N", [10, 12])
def test_gap_means_reproduce_the_mean_table(N):
    d = N * (N - 1) // 2
    table = mean_W(N)
    for i in range(2, N + 1):
        for j, gaps in enumerate(G.layer_gap_counts(N, i), start=1):
            assert gaps.mean() / (d + 1) == table[i - 1][j - 1]


# ---------------------------------------------------------------- route (b): sympy over the polytope


def density_from_polytope(N, grain):
    """The polynomial of degree <= d - 1 with the moments 0..d-1 of sympy's polytope integrals.

    The density of a linear functional of a uniform point of a polytope is a polynomial
    between consecutive images of vertices; an order polytope has 0/1 vertices, where
    W = S_a - S_b is 0 or 1, so on (0, 1) it is one polynomial of degree <= d - 1, fixed
    by its first d moments (the Hilbert matrix is invertible).
    """
    d = N * (N - 1) // 2
    moments = [sympy.Integer(1)] + [sympy.Rational(str(integrate_moment(N, {grain: s}))) for s in range(1, d)]
    H = sympy.Matrix(d, d, lambda s, k: sympy.Rational(1, s + k + 1))
    a = H.LUsolve(sympy.Matrix(moments))
    return sympy.Poly(sum(a[k] * w**k for k in range(d)), w, domain="QQ"), d


# N = 4 (~10 s) under -m slow: the integration route stays by default at N = 2, 3 and N = 5 (one grain)
@pytest.mark.parametrize("N", [2, 3, pytest.param(4, marks=pytest.mark.slow)])
def test_density_equals_sympy_integration_over_the_polytope(N):
    for grain in grains(N):
        expected, d = density_from_polytope(N, grain)
        assert D.density(N, grain) == expected
        assert poly_moment(expected, d) == integrate_moment(N, {grain: d})  # one moment more than needed
        assert D.cdf(N, grain) == expected.integrate()


def test_density_equals_sympy_integration_N5_one_grain():
    expected, _ = density_from_polytope(5, (4, 1))
    assert D.density(5, (4, 1)) == expected


def test_cdf_of_N3_by_integrating_the_indicator():
    # N = 3: the free partial sums S_31 < S_21 < S_32 fill the simplex x1 < x2 < x3 (volume 1/6);
    # P(W_32 <= t), W_32 = x3 - x1: integrate x3 from x2 to min(1, x1 + t), symbolically in t
    x1, x2, x3 = sympy.symbols("x1 x2 x3")
    for t in (sympy.Rational(1, 3), sympy.Rational(3, 4)):
        inner = sympy.Piecewise((x1 + t - x2, x1 + t <= 1), (1 - x2, True))
        vol = sympy.integrate(sympy.integrate(inner, (x2, x1, sympy.Min(1, x1 + t))), (x1, 0, 1))
        assert sympy.simplify(6 * sympy.piecewise_fold(vol)) == D.cdf(3, (3, 2)).eval(t)


# ---------------------------------------------------------------- route (c): linear extensions


@cache
def extension_laws(N):
    """Gap laws of W, F5, F6 and the joint (g5, g6) of q from every linear extension."""
    d = N * (N - 1) // 2
    laws, joint, number = {}, {}, 0
    for ext in nx.all_topological_sorts(partial_sum_poset(N)) if d else [[]]:
        number += 1
        rank = {v: k + 1 for k, v in enumerate(ext)}

        def S(i, j, rank=rank):  # rank of S_{i,j}, boundaries 0 and d + 1
            return 0 if j == 0 else d + 1 if j == i else rank[(i, j)]

        for i in range(2, N + 1):
            for j in range(1, i + 1):
                laws.setdefault((i, j, "W"), Counter())[S(i, j) - S(i, j - 1)] += 1
        for i in range(1, N):
            for j in range(1, i + 1):
                g5, g6 = S(i + 1, j) - S(i, j - 1), S(i, j) - S(i + 1, j)
                laws.setdefault((i, j, "F5"), Counter())[g5] += 1
                laws.setdefault((i, j, "F6"), Counter())[g6] += 1
                joint.setdefault((i, j), Counter())[(g5, g6)] += 1
    return number, laws, joint


@pytest.mark.parametrize("N", [2, 3, 4, 5, 6])
def test_gap_laws_equal_linear_extension_enumeration(N):
    number, laws, _ = extension_laws(N)
    assert number == count(N)
    d = N * (N - 1) // 2
    contacts = G.contact_gap_counts(N, mirror=False)
    for (i, j, kind), counter in laws.items():
        gaps = G.grain_gap_counts(N, (i, j)) if kind == "W" else contacts[(i, j, kind)]
        assert gaps.total == number
        assert gaps.counts == tuple(counter.get(g, 0) for g in range(d + 2))


@pytest.mark.parametrize("N", [3, 4, 5, 6])
def test_joint_q_gaps_equal_linear_extension_enumeration(N):
    for (i, j), counter in extension_laws(N)[2].items():
        counts, total = q_gap_counts(N, (i, j))
        assert total == count(N)
        assert {(a, b): c for a, row in enumerate(counts) for b, c in enumerate(row) if c} == dict(counter)


# ---------------------------------------------------------------- contacts: F1, F2, F5, F6


@pytest.mark.parametrize("N", [5, 8, 11])
def test_mirror_symmetry_and_the_two_routes_around_a_square(N):
    contacts = G.contact_gap_counts(N, mirror=False)
    for i in range(2, N + 1):
        laws = G.layer_gap_counts(N, i)
        for j in range(1, i + 1):
            assert laws[j - 1] == laws[i - j]  # W_{i,j} ~ W_{i,i+1-j}
            # W_{i,j} = (sqrt3/2)(F1 + F2): spacings F6^{(i-1,j-1)} + F5^{(i-1,j)}, in mean
            upper = [contacts[(i - 1, j - 1, "F6")]] if j >= 2 else []
            upper += [contacts[(i - 1, j, "F5")]] if j <= i - 1 else []
            assert sum(g.mean() for g in upper) == laws[j - 1].mean()
    for i in range(1, N):
        for j in range(1, i + 1):
            assert contacts[(i, j, "F5")] == contacts[(i, i + 1 - j, "F6")]  # columns vs rows
            lower = contacts[(i, j, "F5")].mean() + contacts[(i, j, "F6")].mean()
            assert lower == (G.grain_gap_counts(N, (i, j)).mean() if i >= 2 else N * (N - 1) // 2 + 1)


def test_mirror_shortcut_equals_the_column_passes():
    assert G.contact_gap_counts(9, mirror=True) == G.contact_gap_counts(9, mirror=False)


@pytest.mark.parametrize("N", [4, 7])
def test_contact_api_follows_eq_3_4(N):
    contacts = G.contact_gap_counts(N)
    for i, j in grains(N, 1):
        for kind in ("F5", "F6"):
            if i < N:
                assert G.contact_gap_law(N, (i, j), kind) == contacts[(i, j, kind)]
                assert D.contact_density(N, (i, j), kind) == D.density_from_gaps(contacts[(i, j, kind)])
        if i >= 2 and j >= 2:
            assert G.contact_gap_law(N, (i, j), "F1") == contacts[(i - 1, j - 1, "F6")]
        if i >= 2 and j <= i - 1:
            assert G.contact_gap_law(N, (i, j), "F2") == contacts[(i - 1, j, "F5")]
    with pytest.raises(ValueError, match="overload"):
        G.contact_gap_law(N, (1, 1), "F1")
    with pytest.raises(ValueError, match="identically 0"):
        G.contact_gap_law(N, (3, 1), "F1")
    with pytest.raises(ValueError, match="floor"):
        G.contact_gap_law(N, (N, 2), "F5")
    with pytest.raises(ValueError, match="lateral"):
        G.contact_gap_law(N, (2, 1), "F3")


@pytest.mark.parametrize("N", [4, 7, 10])
def test_order_of_vanishing_at_zero(N):
    d = N * (N - 1) // 2
    for i, j in grains(N):
        gaps = G.grain_gap_counts(N, (i, j))
        g0 = min(g for g, c in enumerate(gaps.counts) if c)
        assert g0 == (N - i + 1 if j in (1, i) else 2 if i == N else 3)  # lattice directions / floor / bulk
        p = D.density(N, (i, j))
        assert min(m for (m,), c in p.terms() if c) == g0 - 1
        assert p.eval(0) == d * Fraction(gaps.counts[1], gaps.total)
    for (i, j, kind), gaps in G.contact_gap_counts(N).items():
        g0 = min(g for g, c in enumerate(gaps.counts) if c)
        edge = (kind == "F5" and j == 1) or (kind == "F6" and j == i)
        assert g0 == (N - i if edge else 1)  # inner contacts are cover relations: finite p(0) > 0


# ---------------------------------------------------------------- structure


@given(grain_of(2, 9))
def test_cdf_is_the_antiderivative_of_the_density(case):
    N, grain = case
    p, F = D.density(N, grain), D.cdf(N, grain)
    assert F.diff(w) == p and F.eval(0) == 0 and F.eval(1) == 1


@pytest.mark.parametrize("N", [3, 5, 8])
def test_pooled_densities_are_normalized_with_unit_mean(N):
    for i in range(2, N + 1):
        P = D.layer_force_density(N, i)
        assert integral(P, 0, i) == 1 and integral(P, 0, i, 1) == 1  # f = i W has mean exactly 1
        assert P.eval(0) == (sympy.Rational(N - 1, N) if i == N else 0)
    pieces = D.triangle_force_density(N)
    assert sum(integral(pc.poly, pc.lo, pc.hi) for pc in pieces) == 1
    assert sum(integral(pc.poly, pc.lo, pc.hi, 1) for pc in pieces) == 1
    assert sum(D.bin_probabilities(pieces, [0, Fraction(1, 3), 1, N])) == 1
    assert D.piecewise_cdf(pieces)[-1].poly.eval(N) == 1
    for i in range(1, N):
        C = D.contact_layer_force_density(N, i)
        assert integral(C, 0, 2 * i) == 1 and integral(C, 0, 2 * i, 1) == 1


def test_a_single_polynomial_needs_its_support():
    P = D.layer_force_density(5, 5)
    with pytest.raises(ValueError, match="support"):
        D.bin_probabilities(P, [0, 1])
    assert sum(D.bin_probabilities(P, [0, 1, 5], support=(0, 5))) == 1


def test_grain_scaled_pool_has_unit_mean():
    pieces = D.grain_scaled_pool_density(6, [(6, j) for j in range(1, 7)])
    assert sum(integral(pc.poly, pc.lo, pc.hi) for pc in pieces) == 1
    assert sum(integral(pc.poly, pc.lo, pc.hi, 1) for pc in pieces) == 1


def test_bad_input_is_refused_with_the_argument_named():
    with pytest.raises(ValueError, match="increase strictly"):
        G.chain_gap_counts(5, [(2, 3), (1, 4)])
    with pytest.raises(ValueError, match="not in the staircase"):
        G.chain_gap_counts(5, [(3, 2)])
    with pytest.raises(TypeError, match="chain"):
        G.chain_gap_counts(5, [(1.5, 2)])
    with pytest.raises(ValueError, match="overload"):
        D.density(5, (1, 1))
    with pytest.raises(ValueError, match="grain"):
        D.density(5, (6, 1))
    with pytest.raises(TypeError, match="N=True"):
        D.density(True, (1, 1))
    with pytest.raises(ValueError, match="i=1 is out of range"):
        D.layer_force_density(5, 1)
    with pytest.raises(ValueError, match="bottom layer"):
        q_gap_counts(5, (5, 2))
    assert G.grain_gap_counts(5, (1, 1)).counts[-1] == count(5)  # W_11 = 1: gap d + 1


def test_a_chain_that_skips_cells_sums_the_layer_gaps():
    N = 7
    full = G.chain_gap_counts(N, G.layer_chain(N, 5))
    sub = G.chain_gap_counts(N, [G.layer_chain(N, 5)[1]])
    assert sub[0].mean() == full[0].mean() + full[1].mean()
    assert sub[1].mean() == sum(g.mean() for g in full[2:])


@pytest.mark.parametrize("N", [7, 9])
def test_joint_q_law_marginals_are_the_contact_and_load_laws(N):
    contacts = G.contact_gap_counts(N)
    d = N * (N - 1) // 2
    for i in range(1, N):
        for j in range(1, i + 1):
            counts, total = q_gap_counts(N, (i, j))
            assert tuple(sum(row) for row in counts) == contacts[(i, j, "F5")].counts
            assert tuple(sum(counts[a][b] for a in range(d + 2)) for b in range(d + 2)) == contacts[(i, j, "F6")].counts
            gw = [0] * (d + 2)
            for a, row in enumerate(counts):
                for b, c in enumerate(row):
                    if c:
                        gw[a + b] += c
            assert tuple(gw) == G.grain_gap_counts(N, (i, j)).counts


@pytest.mark.parametrize("N", [4, 6, 9])
def test_q_above_the_floor_is_exactly_uniform(N):
    # given layer N-1, each S_{N,j} is uniform on [S_{N-1,j-1}, S_{N-1,j}] independently
    for j in range(1, N):
        assert D.q_density(N, (N - 1, j)) == sympy.Poly(1, sympy.Symbol("q"), domain="QQ")


def test_joint_law_of_any_two_consecutive_intervals():
    counts, total = joint_gap_counts(6, G.layer_chain(6, 6), 2)
    laws = G.layer_gap_counts(6, 6)
    assert tuple(sum(row) for row in counts) == laws[2].counts
    assert tuple(sum(col) for col in zip(*counts)) == laws[3].counts


def test_plan_grows_and_refuses():
    assert D.distribution_plan(12, "all").seconds < 5  # the N = 12 target: every grain in under a minute
    assert D.distribution_plan(16, "ensemble").seconds < D.distribution_plan(20, "ensemble").seconds
    assert not G.gap_laws_plan(31).runnable
    assert not D.distribution_plan(26, "grain", memory_bytes=2**20).runnable


# ---------------------------------------------------------------- floating point and route (d)


@given(grain_of(3, 12), st.floats(min_value=0, max_value=1))
def test_float_evaluation_matches_the_exact_polynomial(case, x):
    from forcenet.numeric.triangle.force_distribution import cdf_values, density_values, piecewise_values

    N, grain = case
    gaps = G.grain_gap_counts(N, grain)
    exact_p = float(D.density(N, grain).eval(sympy.Rational(x)))
    exact_F = float(D.cdf(N, grain).eval(sympy.Rational(x)))
    assert abs(float(density_values(gaps, x)) - exact_p) <= 1e-9 * max(1.0, abs(exact_p))
    assert abs(float(cdf_values(gaps, x)) - exact_F) <= 1e-9
    assert float(piecewise_values(D.density(N, grain), x, support=(0, 1))) == exact_p  # exact evaluation, rounded once


def test_exact_sampler_matches_the_cdf():
    from forcenet.numeric.triangle.exact_sampler import ExactSampler
    from forcenet.numeric.triangle.force_distribution import cdf_values

    N, samples = 6, 20000
    W = ExactSampler(N, seed=11).sample_W(samples)
    for i, j in [(6, 1), (6, 3), (4, 2), (5, 5)]:
        gaps = G.grain_gap_counts(N, (i, j))
        for x in (0.05, 0.15, 0.3, 0.5):
            prob = float(cdf_values(gaps, x))
            est = float((W[:, i - 1, j - 1] <= x).mean())
            assert abs(est - prob) < 5 * max(np.sqrt(prob * (1 - prob) / samples), 1e-4)


def test_q_density_against_the_sampler():
    from forcenet.numeric.triangle.exact_sampler import ExactSampler, q_from_W

    N, samples = 7, 20000
    q = q_from_W(ExactSampler(N, seed=5).sample_W(samples))
    for i, j in [(3, 1), (4, 2), (5, 3)]:
        F = D.q_density(N, (i, j)).integrate()
        for x in (0.2, 0.5, 0.8):
            prob = float(F.eval(sympy.Rational(str(x))) - F.eval(0))
            est = float((q[:, i - 1, j - 1] <= x).mean())
            assert abs(est - prob) < 5 * max(np.sqrt(prob * (1 - prob) / samples), 1e-4)


def test_sampled_histograms_agree_with_the_exact_pool():
    from forcenet.numeric.triangle.force_distribution import chi_square, exact_sampler_histogram, metropolis_histogram

    N = 7
    edges = np.linspace(0, 3, 16)
    exact = D.bin_probabilities(D.triangle_force_density(N), edges)
    h = exact_sampler_histogram(N, 4000, edges, seed=3)
    chi2, bins, p = chi_square(h, exact)
    assert bins == 15 and p > 1e-4  # a false alarm 1 time in 10^4
    m = metropolis_histogram(N, 3000, edges, seed=3)
    assert m.reliable and m.tau < 20
    assert chi_square(m, exact)[2] > 1e-4
