"""forcenet.testing: the assertions, their false-alarm rate, the strategies.

The false-alarm rate is tested as promised in forcenet.numeric.agreement: over
many seeds of a correct sampler the rejection rate is at most alpha (exactly
alpha for a single value) within its binomial error (4 standard deviations,
fixed seeds). Cheap versions run by default, the long ones with -m slow.
"""

import math

import numpy as np
import pytest
from hypothesis import find, given, settings
from scipy.signal import lfilter

from forcenet.exact import mean_W, moment_table
from forcenet.numeric.autocorr import AutocorrError
from forcenet.numeric.triangle.exact_sampler import ExactSampler
from forcenet.numeric.triangle.metropolis import TriangleMetropolis, q_model_samples
from forcenet.testing import DisagreementError, assert_agrees, assert_means_agree, compare, exact_array, exact_mean_W
from forcenet.testing import strategies as fst


def ar1(rng, n, phi, columns=1):
    """Stationary AR(1) chains of unit variance, shape (n, columns); tau = (1 + phi) / (1 - phi)."""
    e = rng.normal(size=(n, columns)) * math.sqrt(1 - phi**2)
    e[0] /= math.sqrt(1 - phi**2)
    return lfilter([1.0], [1.0, -phi], e, axis=0)


def rejection_rate(runs, fails):
    rejected = sum(bool(fails(seed)) for seed in range(runs))
    return rejected / runs


def binomial_sd(p, runs):
    return math.sqrt(p * (1 - p) / runs)


def chain_rejection_rate(runs, chain, exact, alpha):
    """Rejection rate over the chains that are long enough (a refusal does not bias the others: tau is
    measured on the first quarter, the test uses the rest); returns (rate, accepted)."""
    outcomes = []
    for r in range(runs):
        try:
            outcomes.append(not compare(chain(r), exact, chain=True, alpha=alpha).passed)
        except AutocorrError:
            pass
    return sum(outcomes) / max(1, len(outcomes)), len(outcomes)


# ---------------------------------------------------------------- shapes, keys, errors


def test_ragged_exact_table_and_keys():
    W = ExactSampler(4, seed=5).sample_W(3000)
    report = compare(W, mean_W(4))
    assert report.values == 9 and len(report.fixed) == 1  # W_11 = 1 compared exactly
    assert report.keys[0] == (2, 1) and report.fixed[0][0] == (1, 1)
    assert report.passed


def test_none_entries_are_not_tested():
    W = ExactSampler(4, seed=5).sample_W(2000)
    table = [[None], [None, None], mean_W(4)[2], [None, None, None, None]]
    report = compare(W, table)
    assert report.keys == ((3, 1), (3, 2), (3, 3)) and report.passed


def test_exact_array_rejects_what_does_not_fit():
    with pytest.raises(ValueError, match="more than the samples' axis"):
        exact_array([[1, 2, 3]], (1, 2))
    with pytest.raises(ValueError, match="single number"):
        exact_array([1, 2], (2, 2))
    with pytest.raises(TypeError, match="not a number"):
        exact_array(["a"], (1,))
    with pytest.raises(ValueError, match="shape"):
        exact_array(np.zeros((2, 3)), (3, 2))


def test_bad_input():
    x = np.random.default_rng(0).normal(size=(100, 2))
    with pytest.raises(ValueError, match="alpha=0 is out of range"):
        compare(x, [0, 0], alpha=0)
    with pytest.raises(ValueError, match="keys has 1 names for 2"):
        compare(x, [0, 0], keys=["a"])
    with pytest.raises(ValueError, match="no value to test"):
        compare(x, [None, None])
    y = x.copy()
    y[3, 1] = np.nan
    with pytest.raises(ValueError, match="non-finite"):
        compare(y, [0, 0])
    with pytest.raises(TypeError, match="chain=True"):
        compare(x, [0, 0], batch_factor=5)
    with pytest.raises(ValueError, match="single number"):
        compare(np.float64(1.0), 1.0)


def test_independent_rows_that_look_like_a_chain_are_refused():
    chain = ar1(np.random.default_rng(1), 10000, 0.9)
    with pytest.raises(ValueError, match="look autocorrelated.*chain=True"):
        compare(chain, [0.0])
    assert compare(chain, [0.0], chain=True).passed


def test_short_chains_are_refused_with_the_length_to_run():
    chain = ar1(np.random.default_rng(2), 1500, 0.9)  # tau = 19: 80 tau, not enough
    with pytest.raises(AutocorrError, match="run at least"):
        compare(chain, [0.0], chain=True)


def test_rounding_noise_is_a_fixed_value():
    """A column that varies only by rounding (the top row of a packing) is compared exactly, never as a chain."""
    from forcenet.numeric.packing import Scene, uniform_networks

    W, _ = uniform_networks(Scene(N=2, P=3, F=1, j0=1, mg=1), 2000, np.random.default_rng(0))
    assert np.ptp(W[:, 0], axis=0).max() > 0  # rounding in the lateral-force route
    report = compare(W, exact_mean_W(Scene(N=2, P=3, F=1, j0=1, mg=1)))
    assert report.passed and [key for key, _, _ in report.fixed] == [(1, 1), (1, 2), (1, 3)]


def test_a_fixed_value_that_differs_fails():
    W = ExactSampler(3, seed=1).sample_W(500)
    table = [[2], *mean_W(3)[1:]]  # W_11 is always 1
    report = compare(W, table)
    assert not report.passed and report.fixed_failures == (((1, 1), 1.0, 2.0),)
    with pytest.raises(DisagreementError, match=r"fixed value \(1, 1\): sampled 1.0 \(never varies\), exact 2.0"):
        assert_agrees(W, table)


def test_means_with_trusted_errors():
    assert assert_means_agree([0.5, 0.26], [0.01, 0.01], [0.5, 0.25]).passed
    with pytest.raises(DisagreementError, match="z = \\+6.00"):
        assert_means_agree([0.5, 0.31], [0.01, 0.01], [0.5, 0.25])


def test_one_value():
    W = ExactSampler(6, seed=3).sample_W(4000)
    report = assert_agrees(W[:, 5, 1], mean_W(6)[5][1])  # <W_62> = 413/2288
    assert report.keys == ("value",) and report.passed


# ---------------------------------------------------------------- power and failure messages


def test_the_q_model_is_caught_and_the_message_names_the_worst_grains():
    N = 6
    W = q_model_samples(N, 4000, np.random.default_rng(0))
    with pytest.raises(DisagreementError) as info:
        assert_agrees(W, mean_W(N))
    message = str(info.value)
    report = info.value.report
    (z, key), *_ = report.worst_values(1)
    assert f"{key}: mean" in message and f"z = {z:+.2f}" in message
    assert "DISAGREES at level 0.001" in message and abs(z) > 10


def test_a_biased_chain_is_caught_and_the_message_gives_tau():
    N = 4
    chain = TriangleMetropolis(N, seed=7).run(sweeps=3000, burn_in=100)
    assert_agrees(chain, mean_W(N), chain=True)  # the correct sampler passes
    biased = chain.copy()
    biased[:, 3, 0] += 0.04  # a bias of 0.04 on W_41 (about 10 standard errors)
    with pytest.raises(DisagreementError) as info:
        assert_agrees(biased, mean_W(N), chain=True)
    message = str(info.value)
    assert "(4, 1): mean" in message and ", tau = " in message and "batch means" in message
    assert info.value.report.worst == (4, 1)


def test_second_moments_of_the_metropolis_chain():
    N = 5
    chain = TriangleMetropolis(N, seed=11).run(sweeps=3000, burn_in=200)
    assert_agrees(chain**2, moment_table(N, 2), chain=True)


# ---------------------------------------------------------------- the false-alarm rate (cheap versions)


def test_false_alarm_rate_of_one_value_is_alpha():
    alpha, runs = 0.1, 2000
    rate = rejection_rate(runs, lambda s: not compare(np.random.default_rng(s).normal(size=30), 0.0, alpha=alpha).passed)
    assert abs(rate - alpha) < 4 * binomial_sd(alpha, runs), rate


@pytest.mark.parametrize("rho", [0.0, 0.5, 0.95])
def test_false_alarm_rate_of_a_table_is_at_most_alpha(rho):
    """20 normal values, equicorrelated: at most alpha whatever rho; not far below when independent."""
    alpha, runs, G = 0.1, 800, 20

    def fails(seed):
        rng = np.random.default_rng(seed)
        x = math.sqrt(1 - rho) * rng.normal(size=(300, G)) + math.sqrt(rho) * rng.normal(size=(300, 1))
        return not compare(x, np.zeros(G), alpha=alpha).passed

    rate = rejection_rate(runs, fails)
    assert rate < alpha + 4 * binomial_sd(alpha, runs), rate
    if rho == 0.0:
        assert rate > 0.5 * alpha, rate  # the union bound is not far from tight for independent values


def test_false_alarm_rate_of_one_chain_value_is_alpha():
    """AR(1) with tau = 9 at 600 tau: the spaced batch means give the stated rate."""
    alpha, runs, phi = 0.1, 600, 0.8
    chains = ar1(np.random.default_rng(2006), 5400, phi, columns=runs)
    rate, accepted = chain_rejection_rate(runs, lambda r: chains[:, r], 0.0, alpha)
    assert accepted > 0.9 * runs
    assert abs(rate - alpha) < 4 * binomial_sd(alpha, accepted), rate


def test_false_alarm_rate_of_the_exact_sampler_table():
    alpha, runs, N = 0.1, 300, 4
    table = mean_W(N)
    rate = rejection_rate(runs, lambda s: not compare(ExactSampler(N, seed=s).sample_W(500), table, alpha=alpha).passed)
    assert rate < alpha + 4 * binomial_sd(alpha, runs), rate


def test_false_alarm_rate_of_the_metropolis_table():
    alpha, runs, N = 0.2, 50, 3
    rate, accepted = chain_rejection_rate(runs, lambda s: TriangleMetropolis(N, seed=s).run(sweeps=1500), mean_W(N), alpha)
    assert accepted > 0.8 * runs
    assert rate < alpha + 4 * binomial_sd(alpha, accepted), rate


# ---------------------------------------------------------------- the false-alarm rate (long versions)


@pytest.mark.slow
def test_false_alarm_rate_at_the_default_level():
    """alpha = 1e-3 on 30 independent normal values, 20000 runs: at most ~20 false alarms."""
    alpha, runs = 1e-3, 20000
    rate = rejection_rate(runs, lambda s: not compare(np.random.default_rng(s).normal(size=(400, 30)), np.zeros(30)).passed)
    assert rate < alpha + 4 * binomial_sd(alpha, runs), rate


@pytest.mark.slow
@pytest.mark.parametrize("phi, n_over_tau", [(0.9, 210), (0.9, 1000), (0.5, 400)])
def test_false_alarm_rate_of_chains_long(phi, n_over_tau):
    """One value, AR(1), alpha = 0.01 and 0.05, from just above the refusal length to long chains."""
    tau = (1 + phi) / (1 - phi)
    n, runs = int(n_over_tau * tau), 6000
    for alpha in (0.05, 0.01):
        rate, accepted = chain_rejection_rate(runs, lambda r: ar1(np.random.default_rng(r), n, phi)[:, 0], 0.0, alpha)
        assert accepted > runs / 2
        assert abs(rate - alpha) < 4 * binomial_sd(alpha, accepted), (alpha, rate, accepted)


@pytest.mark.slow
def test_false_alarm_rate_of_the_exact_sampler_long():
    alpha, runs, N = 0.01, 5000, 6
    table = mean_W(N)
    rate = rejection_rate(runs, lambda s: not compare(ExactSampler(N, seed=s).sample_W(1000), table, alpha=alpha).passed)
    assert rate < alpha + 4 * binomial_sd(alpha, runs), rate


@pytest.mark.slow
def test_false_alarm_rate_of_the_metropolis_long():
    alpha, runs, N = 0.05, 300, 4
    rate, accepted = chain_rejection_rate(runs, lambda s: TriangleMetropolis(N, seed=s).run(sweeps=2500), mean_W(N), alpha)
    assert accepted > 0.9 * runs
    assert rate < alpha + 4 * binomial_sd(alpha, accepted), rate


# ---------------------------------------------------------------- strategies


@given(fst.layers_and_grains(2, 12))
def test_grains_lie_in_their_triangle(case):
    N, (i, j) = case
    assert 2 <= N <= 12 and 1 <= j <= i <= N


@settings(max_examples=15)
@given(fst.force_networks(fst.layers(2, 7)))
def test_force_networks_are_points_of_the_ensemble(W):
    N = W.shape[0]
    assert np.allclose(W.sum(axis=1), 1.0) and (W >= 0).all() and not np.triu(W, 1).any()
    S = np.concatenate([np.zeros((N, 1)), np.cumsum(W, axis=1)], axis=1)
    for i in range(1, N):  # interlacing of the partial sums, Eqs. (4.8)-(4.9)
        assert (S[i - 1, : i] - 1e-12 <= S[i, 1 : i + 1]).all() and (S[i, 1 : i + 1] <= S[i - 1, 1 : i + 1] + 1e-12).all()


def test_force_networks_reproduce_and_shrink():
    W = find(fst.force_networks(fst.layers(2, 8), size=3), lambda W: W.shape[1] >= 5)
    assert W.shape == (3, 5, 5)
    again = find(fst.force_networks(fst.layers(2, 8), size=3), lambda W: W.shape[1] >= 5)
    assert np.array_equal(W, again)


@settings(max_examples=15)
@given(fst.packing_scenes(side_pressure=True))
def test_finite_pressure_scenes_are_feasible(scene):
    from forcenet.numeric.packing import PackingMetropolis

    sampler = PackingMetropolis(scene, seed=0)  # raises on a scene without a repulsive network
    sampler.run(sweeps=2)
    assert scene.ph is not None and (sampler.W > 0).all()


@settings(max_examples=10)
@given(fst.packing_scenes(exact_means=True))
def test_exactly_solvable_scenes_conserve_the_load(scene):
    table = exact_mean_W(scene)
    load = scene.F + scene.pv * scene.P
    assert [float(sum(row)) for row in table] == pytest.approx([load + (i + 1) * scene.P * scene.mg for i in range(scene.N)])


def test_scene_strategy_arguments():
    with pytest.raises(ValueError, match="exact_means=True needs"):
        fst.packing_scenes(exact_means=True, side_pressure=True)
    with pytest.raises(ValueError, match="max_layers=1 is out of range"):
        fst.packing_scenes(min_layers=2, max_layers=1)


@settings(max_examples=20)
@given(fst.chicken_wire_configurations(max_sites=9))
def test_chicken_wire_configurations_are_valid(config):
    assert config.L * config.M <= 9 and not config.invalid_sites()


def test_every_configuration_of_a_torus_can_be_drawn():
    from forcenet.exact.chicken_wire.model import count_torus

    seen = {find(fst.chicken_wire_configurations(3, 3), lambda c: True).key()}
    assert len(seen) == 1 and count_torus(3, 3) == 25
    strategy = fst.chicken_wire_configurations(2, 2)
    keys = set()

    @settings(max_examples=200, database=None)
    @given(strategy)
    def collect(config):
        keys.add(config.key())

    collect()
    assert len(keys) == count_torus(2, 2)


def test_strategies_are_reached_lazily():
    import forcenet.testing as ft

    assert ft.strategies is fst
    with pytest.raises(AttributeError):
        ft.nothing
