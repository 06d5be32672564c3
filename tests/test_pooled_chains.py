"""Pooled statistics of independent chains (numeric.autocorr.pool_means, pool_chains, all_finite).

Checked against the statistics of the concatenated samples (mean, spread) and against exact
rational arithmetic (the error in quadrature, sum n_k / tau_k).
"""

import math
from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from forcenet.core.errors import ArgumentError
from forcenet.numeric.autocorr import all_finite, pool_chains, pool_means

values = st.floats(-1e3, 1e3, allow_nan=False)
chains = st.lists(st.lists(values, min_size=2, max_size=30), min_size=1, max_size=5)


@given(chains, st.data())
def test_pool_chains_is_the_statistics_of_the_concatenated_samples(xs, data):
    arrays = [np.array(x) for x in xs]
    n = [len(x) for x in xs]
    stderrs = [data.draw(st.floats(0, 10)) for _ in xs]
    taus = [data.draw(st.floats(1, 50)) for _ in xs]
    pooled = pool_chains(n, [a.mean() for a in arrays], stderrs, [a.std(ddof=1) for a in arrays], taus)
    everything = np.concatenate(arrays)
    scale = 1 + float(np.abs(everything).max())
    assert math.isclose(float(pooled.mean), float(everything.mean()), rel_tol=1e-9, abs_tol=1e-9 * scale)
    assert math.isclose(float(pooled.std), float(everything.std(ddof=1)), rel_tol=1e-7, abs_tol=1e-7 * scale)
    total = sum(n)
    exact_var = sum(Fraction(k, total) ** 2 * Fraction(s) ** 2 for k, s in zip(n, stderrs))
    assert math.isclose(float(pooled.stderr) ** 2, float(exact_var), rel_tol=1e-9, abs_tol=1e-300)
    assert math.isclose(float(pooled.effective_samples), float(sum(Fraction(k) / Fraction(t) for k, t in zip(n, taus))),
                        rel_tol=1e-12)


def test_pool_means_keeps_the_shape_of_the_components():
    m, e = pool_means([2, 6], [np.zeros((2, 2)), np.ones((2, 2))], [np.ones((2, 2)), np.zeros((2, 2))])
    assert m.shape == e.shape == (2, 2)
    assert m.tolist() == [[0.75, 0.75], [0.75, 0.75]] and e.tolist() == [[0.25, 0.25], [0.25, 0.25]]


def test_one_chain_is_its_own_pool():
    std, tau = np.array([0.3, 0.4]), np.array([2.0, 4.0])
    pooled = pool_chains([10], [np.array([1.0, 2.0])], [np.array([0.1, 0.2])], [std], [tau])
    assert pooled.mean.tolist() == [1.0, 2.0] and pooled.std.tolist() == std.tolist()
    assert pooled.effective_samples.tolist() == [5.0, 2.5]


@pytest.mark.parametrize("n, means", [([], []), ([3, 4], [1.0])])
def test_pool_means_refuses_mismatched_or_no_chains(n, means):
    with pytest.raises(ArgumentError, match="per chain"):
        pool_means(n, means, means)


@given(st.lists(st.lists(st.floats(allow_nan=True, allow_infinity=True), max_size=6), max_size=4))
def test_all_finite_is_isfinite_of_every_entry(xs):
    assert all_finite([np.array(x) for x in xs]) == all(math.isfinite(v) for x in xs for v in x)
