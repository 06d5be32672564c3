"""The samplers' uniformity (every one, one test), and the exact sampler against exact moments."""


import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from forcenet.exact import mean_W, moment_table
from forcenet.exact.reference.linear_extensions import partial_sum_poset
from forcenet.numeric.triangle.exact_sampler import ExactSampler, removal_probabilities, sample_tableaux
from forcenet.numeric.triangle.metropolis import TriangleMetropolis, q_model_samples
from forcenet.testing import DisagreementError, assert_agrees
from forcenet.testing import strategies as fst


def _linear_extensions(N):
    """The orders of the partial sums ``S_{i,j} = W_{i,1} + ... + W_{i,j}`` (``j < i``) the triangle allows:
    the linear extensions of their poset (forcenet.exact.reference), enumerated independently of every sampler."""
    import networkx as nx

    return [tuple(e) for e in nx.all_topological_sorts(partial_sum_poset(N))]


def _extension_indicators(W, extensions):
    """One row per sample: the indicator of the linear extension its partial sums follow (ranks by size)."""
    N = W.shape[1]
    cells = [(i, j) for i in range(2, N + 1) for j in range(1, i)]
    S = np.cumsum(W, axis=2)
    values = np.stack([S[:, i - 1, j - 1] for i, j in cells], axis=1)
    index = {e: k for k, e in enumerate(extensions)}
    out = np.zeros((W.shape[0], len(extensions)))
    for row, order in enumerate(np.argsort(values, axis=1, kind="stable")):
        out[row, index[tuple(cells[c] for c in order)]] = 1.0  # KeyError: an order the poset forbids
    return out


def _metropolis(move):
    def run(N, K, seed):
        return TriangleMetropolis(N, seed=seed, move=move).run(K, burn_in=200)

    return run


# (sampler, its samples form a chain); the q-model (independent uniform q, no weight) is not the ensemble:
# the test must reject it (at N = 5; at N = 4 the two orders are mirror images, equally likely by symmetry)
SAMPLERS = {
    "exact sampler, Schur weights": (lambda N, K, seed: ExactSampler(N, seed=seed, kernel="python").sample_W(K), False),
    "exact sampler, hook walk": (lambda N, K, seed: ExactSampler(N, seed=seed, kernel="compiled").sample_W(K), False),
    "Metropolis": (_metropolis("metropolis"), True),
    "Metropolis, slice move": (_metropolis("slice"), True),
    "q-model": (lambda N, K, seed: q_model_samples(N, K, np.random.default_rng(seed)), False),
}
CASES = [(name, N, K) for name in SAMPLERS if name != "q-model" for N, K in ((4, 6000), (5, 30000))]


@pytest.mark.parametrize("sampler, N, K", CASES + [("q-model", 5, 20000)])
def test_partial_sum_orders_are_uniform(sampler, N, K):
    # A uniform force network orders its partial sums as a uniform linear extension (a uniform standard
    # shifted staircase tableau, Sec. 4.2): every order has frequency 1/E.  The whole table of frequencies
    # through forcenet.testing, which fails a correct sampler with probability at most alpha (bounded test for
    # independent samples, spaced batch means for a chain); 1e-4 per table keeps the 8 runs under 0.1%.
    draw, chain = SAMPLERS[sampler]
    extensions = _linear_extensions(N)
    frequencies = _extension_indicators(draw(N, K, 12345 + N), extensions)
    expected = np.full(len(extensions), 1 / len(extensions))
    if sampler == "q-model":
        with pytest.raises(DisagreementError, match="DISAGREE"):
            assert_agrees(frequencies, expected, bounds=(0, 1), alpha=1e-4)
        return
    assert_agrees(frequencies, expected, chain=chain, bounds=(0, 1), alpha=1e-4)


@given(st.lists(st.integers(min_value=1, max_value=12), min_size=1, max_size=6, unique=True))
def test_removal_probabilities_sum_to_one(parts):
    parts = sorted(parts, reverse=True)
    p = removal_probabilities(np.array([parts + [0] * (6 - len(parts))]))
    assert abs(p.sum() - 1) < 1e-12
    assert (p >= 0).all()


@given(fst.force_networks(fst.layers(3, 9), size=4000))
def test_sampled_moments_agree_with_exact_tables(W):
    # whole tables of <W> and <W^2> (forcenet.testing: false alarms at most alpha per table;
    # 1e-4 keeps a whole hypothesis run of 2 x 25 tables under 1%)
    N = W.shape[1]
    assert_agrees(W, mean_W(N), alpha=1e-4)
    assert_agrees(W**2, moment_table(N, 2), alpha=1e-4)


def test_moments_method_agrees_with_the_samples():
    sampler, again = ExactSampler(5, seed=4), ExactSampler(5, seed=4)
    mean, stderr = sampler.mean_W(3000)
    W = again.sample_W(3000)
    np.testing.assert_allclose(mean, W.mean(axis=0), atol=1e-12)
    np.testing.assert_allclose(stderr, W.std(axis=0, ddof=1) / np.sqrt(3000), atol=1e-12)


def test_samples_are_points_of_the_ensemble():
    N = 6
    W = ExactSampler(N, seed=3).sample_W(50)
    for w in W:
        S = [np.concatenate([[0.0], np.cumsum(w[i - 1, :i])]) for i in range(1, N + 1)]
        for i in range(2, N + 1):
            assert abs(S[i - 1][i] - 1) < 1e-12  # the row carries the overload
            for j in range(1, i):  # interlacing S_{i-1,j-1} <= S_{i,j} <= S_{i-1,j}
                assert S[i - 2][j - 1] - 1e-12 <= S[i - 1][j] <= S[i - 2][j] + 1e-12


def test_too_few_samples_for_an_error_bar():
    with pytest.raises(ValueError, match="samples"):
        ExactSampler(4, seed=0).mean_W(1)


@pytest.mark.parametrize("N", [8, 15, 25])
def test_incremental_weights_equal_full_recomputation(N):
    # refresh=1 recomputes every removal weight from Schur's formula at every step
    a = sample_tableaux(N, 40, np.random.default_rng(99), refresh=1)
    b = sample_tableaux(N, 40, np.random.default_rng(99))
    assert np.array_equal(a, b)


def test_full_weights_equal_removal_probabilities():
    from forcenet.numeric.triangle.exact_sampler import _full_phi

    rng = np.random.default_rng(3)
    n = 12
    for _ in range(20):
        parts = np.sort(rng.choice(np.arange(1, n + 1), size=rng.integers(1, n), replace=False))[::-1]
        row = np.concatenate([parts, np.zeros(n - parts.size, dtype=int)])[None, :]
        logtab = np.log(np.maximum(np.arange(2 * n + 2, dtype=float), 1.0))
        phi = _full_phi(row, logtab)
        nxt = np.concatenate([row[:, 1:], [[0]]], axis=1)
        removable = (row > 0) & ~((nxt > 0) & (nxt == row - 1))
        w = np.where(removable, np.exp(phi) * row, 0.0)
        assert np.allclose(w / w.sum(), removal_probabilities(row))


def test_q_from_W_inverts_the_forward_map():
    from forcenet.numeric.triangle.exact_sampler import q_from_W
    from forcenet.numeric.triangle.metropolis import forces_from_q

    rng = np.random.default_rng(8)
    q = np.tril(rng.random((7, 7)))
    W = forces_from_q(q)[None]
    back = q_from_W(W)[0]
    mask = np.tril(np.ones((7, 7), dtype=bool))
    assert np.allclose(back[mask], q[mask])


@pytest.mark.parametrize("N", [6, 12])
def test_last_layer_q_are_uniform(N):
    # q_{N-1,j} does not enter the weight prod W (Eq. 3.10): independent uniforms (Sec. 3.3.1)
    from forcenet.numeric.triangle.exact_sampler import q_from_W

    W = ExactSampler(N, seed=21).sample_W(4000)
    q = q_from_W(W)[:, N - 2, : N - 1]
    for j in range(N - 1):
        x = np.sort(q[:, j])
        ks = np.max(np.abs(np.arange(1, x.size + 1) / x.size - x))
        assert ks < 2.0 / np.sqrt(x.size)  # Kolmogorov-Smirnov at about p = 1e-3.5
    # while a q higher up is not uniform (its density is ~ W-weighted)
    top = np.sort(q_from_W(W)[:, 0, 0])
    assert np.max(np.abs(np.arange(1, top.size + 1) / top.size - top)) > 5.0 / np.sqrt(top.size)
