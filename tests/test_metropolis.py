"""The Metropolis sampler and the autocorrelation machinery against exact values."""

from fractions import Fraction

import numpy as np
import pytest
import sympy
from hypothesis import given, settings
from hypothesis import strategies as st

from forcenet.exact import mean_W, moment_table
from forcenet.exact.triangle.configuration import contact_forces
from forcenet.numeric.autocorr import AutocorrError, integrated_time
from forcenet.numeric.triangle.metropolis import TriangleMetropolis, forces_from_q, lateral_forces, q_model_samples
from forcenet.testing import CannotJudgeError, DisagreementError, assert_agrees
from forcenet.testing import strategies as fst


@settings(max_examples=6)
@given(fst.layers(3, 6), fst.seeds())
def test_metropolis_moments_agree_with_exact_tables(N, seed):
    # whole tables of <W> and <W^2> through spaced batch means (forcenet.testing);
    # 1e-3 per table keeps a run of 2 x 6 tables under 1.2% false alarms. W^2 is skewed (3.4 at the corners of
    # N = 5): its batch means keep their level from ~40000 steps on at N = 6, so below that "cannot judge" is right
    chain = TriangleMetropolis(N, seed=seed).run(sweeps=16000, burn_in=300)
    assert_agrees(chain, mean_W(N), chain=True, alpha=1e-3)
    try:
        assert_agrees(chain**2, moment_table(N, 2), chain=True, alpha=1e-3)
    except CannotJudgeError as error:
        assert N >= 5 and "run a longer chain" in error.report.reason


def test_lateral_forces_match_exact_contact_forces():
    rng = np.random.default_rng(4)
    N = 5
    q = np.tril(rng.integers(0, 9, size=(N - 1, N - 1)) / 8)
    W = forces_from_q(q)
    F4 = lateral_forces(q, W, 2.0)
    W_exact = [[Fraction(float(W[i, j])).limit_denominator(2**20) for j in range(i + 1)] for i in range(N)]
    exact = contact_forces(W_exact, p_h=sympy.Integer(2))
    for (i, j), forces in exact.items():
        assert abs(float(forces[3]) - F4[i - 1, j - 1]) < 1e-9


def test_finite_side_pressure_keeps_forces_positive():
    sampler = TriangleMetropolis(6, seed=5, ph=0.3)
    chain = sampler.run(sweeps=300, burn_in=50)
    assert sampler.rejected_by_constraint > 0
    assert (lateral_forces(sampler.q, sampler.W, 0.3) >= -1e-12).all()
    assert np.allclose(chain.sum(axis=2), 1.0)


def test_q_model_is_single_peaked_and_differs_from_the_ensemble():
    N = 12
    W = q_model_samples(N, 20000, np.random.default_rng(0))
    bottom = W[:, -1, :].mean(axis=0)
    peak = int(np.argmax(bottom))
    assert peak in (N // 2 - 1, N // 2)  # central peak: diffusive response
    assert np.all(np.diff(bottom[: peak + 1]) > 0) and np.all(np.diff(bottom[peak:]) < 0)
    with pytest.raises(DisagreementError, match="DISAGREE"):
        assert_agrees(W, mean_W(N))


def test_integrated_time_raises_on_short_chains():
    rng = np.random.default_rng(1)
    x = np.cumsum(rng.normal(size=200))  # a random walk: tau ~ chain length
    with pytest.raises(AutocorrError, match="too short"):
        integrated_time(x)
    with pytest.warns(RuntimeWarning):
        integrated_time(x, quiet=True)


@given(st.integers(min_value=0, max_value=2**32 - 1))
def test_integrated_time_of_independent_samples_is_one(seed):
    x = np.random.default_rng(seed).normal(size=(5000, 3))
    tau = integrated_time(x)
    assert np.all(tau < 1.5)


def test_bad_parameters():
    with pytest.raises(ValueError, match="ph"):
        TriangleMetropolis(4, ph=-1.0)
    with pytest.raises(ValueError, match="sweeps"):
        TriangleMetropolis(4).run(0)
    with pytest.raises(ValueError, match="ph=0.01"):
        TriangleMetropolis(4, ph=0.01, q0=np.tril(np.full((3, 3), 0.5)))  # this start violates F4 >= 0


@pytest.mark.parametrize("ph", [0.01, 0.1, 1.0])
def test_small_side_pressure_runs_cleanly(ph):
    # p_h/F -> 0 (Fig. 3.6): no NaN, moves still accepted, every lateral force stays >= 0
    sampler = TriangleMetropolis(10, seed=1, ph=ph)
    chain = sampler.run(sweeps=300, burn_in=100)
    assert np.isfinite(chain).all()
    assert 0 < sampler.acceptance_rate < 1
    assert (lateral_forces(sampler.q, sampler.W, ph) >= -1e-12).all()


def test_vanishing_side_pressure_sends_the_load_down_the_lattice_directions():
    edge_load = []
    for ph in (0.01, 1.0):
        chain = TriangleMetropolis(10, seed=2, ph=ph).run(sweeps=400, burn_in=200)
        edge_load.append((chain[:, -1, 0] + chain[:, -1, 9]).mean())
    assert edge_load[0] > 0.3 > edge_load[1]


@settings(max_examples=20, deadline=None)
@given(n=st.integers(60, 400), columns=st.integers(1, 40), block=st.integers(1, 12), seed=st.integers(0, 2**32 - 1))
def test_integrated_time_in_column_blocks_equals_the_whole_arrays(n, columns, block, seed):
    """The columns' transforms in blocks (bounded memory: 10^4 forces x 4000 states took 3 GB at once) give the same
    times as one transform of the whole array, to rounding (each column's FFT is its own; pocketfft's vectorized
    path over several columns may round differently from one column's)."""
    from forcenet.numeric import autocorr

    rng = np.random.default_rng(seed)
    x = np.cumsum(rng.standard_normal((n, columns)), axis=0) * 0.1 + rng.standard_normal((n, columns))
    whole = integrated_time(x, quiet=True, tol=0)
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(autocorr, "COLUMN_BLOCK_BYTES", 64 * n * block)
        assert np.allclose(integrated_time(x, quiet=True, tol=0), whole, rtol=1e-12, atol=0)


def test_integrated_time_of_no_columns_is_empty_and_of_no_samples_is_refused():
    assert integrated_time(np.zeros((100, 0))).shape == (0,)
    with pytest.raises(AutocorrError, match="no samples"):
        integrated_time(np.zeros((0, 3)))
