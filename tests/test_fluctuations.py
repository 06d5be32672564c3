"""Fluctuations by Pfaffians (issue 27): the exact gap laws of the lattice-direction grains.

Checked against independent routes:

* the order-ideal DP's gap laws (forcenet.exact.triangle.gaps) and second moments
  (forcenet.exact.triangle.moments) for every layer, N <= 11 (N <= 20 in the slow suite);
* the pure-Python kernels;
* beyond the DP: the law's mean against the Pfaffian mean route (another functional of
  other evaluations), the mirror grain's sampled law, and the exact sampler at N = 64 (slow);
* the two-time nature of interior gaps (notes/fluctuations.md Sec. 3): a measure on
  maximal chains with the one-time marginals of the uniform one and another <g^2>.
"""

from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from forcenet.exact.triangle.distribution import cdf_from_gaps, density_from_gaps, moment_from_gaps
from forcenet.exact.triangle.gaps import layer_gap_counts
from forcenet.exact.triangle.moments import moment_table
from forcenet.exact.triangle.pfaffian import fluctuations as fl
from forcenet.exact.triangle.pfaffian import route
from forcenet.exact.triangle.staircase import count

PRIME = 8388593


@pytest.mark.parametrize("N", range(2, 12))
def test_lattice_gap_laws_equal_the_dp(N):
    laws = fl.lattice_gap_laws(N, workers=1)
    assert sorted(laws) == list(range(2, N + 1))
    for i in range(2, N + 1):
        dp = layer_gap_counts(N, i)
        assert laws[i] == dp[0]
        assert laws[i].counts == dp[-1].counts  # the mirror grain W_{i,i}


@pytest.mark.slow
@pytest.mark.parametrize("N", range(12, 21))
def test_lattice_gap_laws_equal_the_dp_slow(N):
    laws = fl.lattice_gap_laws(N)
    for i in range(2, N + 1):
        assert laws[i] == layer_gap_counts(N, i)[0]


@settings(max_examples=8, deadline=None)
@given(N=st.integers(min_value=2, max_value=10))
def test_lattice_mean_W2_equals_the_dp_moment(N):
    """<W_{i,1}^2> against the DP's marked-chain moment pass (a different DP from the gap laws')."""
    table = moment_table(N, 2)
    assert fl.lattice_mean_W2(N, workers=1) == [row[0] for row in table]


@pytest.mark.parametrize("N", [3, 5, 6])
def test_pure_python_backend(N):
    p = PRIME
    assert (fl.edge_level_residues(N, p, "python") == fl.edge_level_residues(N, p)).all()


@pytest.mark.parametrize("N", [22, 26])
def test_law_mean_is_the_pfaffian_mean_beyond_the_dp(N):
    """E[g]/(d+1) of the interpolated laws = the mean route's functional of its own evaluations."""
    laws = fl.lattice_gap_laws(N)
    column = route.lattice_direction(N)
    d = N * (N - 1) // 2
    total = count(N)
    for i in range(2, N + 1):
        law = laws[i]
        assert law.total == total and sum(law.counts) == total
        assert all(c >= 0 for c in law.counts)
        assert law.mean() / (d + 1) == column[i - 1]
        assert law.counts[: N - i + 1] == (0,) * (N - i + 1)  # T(1, m) >= m: the cells (1, 1..m-1) come first


def test_density_integrates_to_one_with_the_exact_mean():
    N, i = 22, 11
    law = fl.lattice_gap_laws(N)[i]
    f = density_from_gaps(law)
    assert f.integrate().eval(1) - f.integrate().eval(0) == 1
    w = f.gen
    assert (f * w).integrate().eval(1) - (f * w).integrate().eval(0) == route.lattice_direction(N)[i - 1]
    assert cdf_from_gaps(law).eval(1) == 1


def test_residue_checks_and_arguments():
    E = fl.edge_level_residues(6, PRIME)
    assert (E[1:, 0] == count(6) % PRIME).all() and (E[1:, -1] == 0).all()
    with pytest.raises(ValueError, match="N=129"):
        fl.lattice_gap_laws(129)
    with pytest.raises(ValueError, match="p="):
        fl.edge_level_residues(6, 8388592)
    with pytest.raises(ValueError, match="inner size"):
        fl._matmul_mod(np.zeros((2, 8192), dtype=np.int64), np.zeros((8192, 1)), PRIME)


def test_blas_products_are_exact():
    rng = np.random.default_rng(27)
    p = 33554393
    A = rng.integers(0, p, size=(40, 3000))
    B = rng.integers(0, p, size=(3000, 7))
    exact = [[sum(int(a) * int(b) for a, b in zip(A[r], B[:, c])) % p for c in range(7)] for r in range(40)]
    assert fl._matmul_mod(A, B, p).tolist() == exact


def test_plan():
    plan = fl.lattice_gap_laws_plan(64)
    assert plan.runnable and plan.unit == "prime" and plan.ticks > 100
    assert fl.lattice_gap_laws_plan(129).refusal.startswith("N=129 is out of range")
    assert fl.lattice_gap_laws_plan(100, memory_bytes=2**20).refusal is not None


@pytest.mark.slow
def test_lattice_laws_agree_with_the_exact_sampler_at_N64():
    """<W_{i,1}^2> and P(W_{i,1} <= median-ish w) of every layer against 20000 exact samples (alpha = 1e-3)."""
    from forcenet.numeric.agreement import compare_samples
    from forcenet.numeric.triangle.exact_sampler import ExactSampler

    N, samples = 64, 20000
    laws = fl.lattice_gap_laws(N)
    second = fl.lattice_mean_W2(N)
    column = route.lattice_direction(N)
    sampler, rows, drawn = ExactSampler(N, seed=2764), [], 0
    while drawn < samples:
        W = sampler.sample_W(min(sampler.batch, samples - drawn))
        rows.append(W[:, 1:, 0])
        drawn += W.shape[0]
    X = np.concatenate(rows)
    cuts = [float(column[i - 1]) for i in range(2, N + 1)]  # P(W <= <W>) from the exact CDF
    exact_cdf = [cdf_from_gaps(laws[i]).eval(Fraction(cuts[i - 2])) for i in range(2, N + 1)]
    data = np.concatenate([X**2, (X <= np.array(cuts)).astype(float)], axis=1)
    expected = second[1:] + exact_cdf
    keys = [f"W2_{i}" for i in range(2, N + 1)] + [f"cdf_{i}" for i in range(2, N + 1)]
    result = compare_samples(data, expected, keys=keys, alpha=1e-3)
    assert result.passed, result.summary()
