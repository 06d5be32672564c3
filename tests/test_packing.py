"""The N x P packing (Secs. 3.2-3.3): balance, three routes to <W>, scenes, errors."""

import math
from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from forcenet.exact.packing.mobilized import mean_W_mobilized
from forcenet.numeric.autocorr import mean_and_stderr
from forcenet.numeric.packing import (
    PackingMetropolis,
    Scene,
    contact_forces,
    forces_from_lateral,
    maximin_network,
    response,
    uniform_networks,
)
from forcenet.testing import assert_agrees, exact_mean_W
from forcenet.testing import strategies as fst

S3 = math.sqrt(3)


def _balance_residuals(f, mg):
    """Horizontal and vertical force balance on every grain (contact directions of Fig. 3.2)."""
    h = f["F1"] / 2 - f["F2"] / 2 + f["F3"] - f["F4"] + f["F5"] / 2 - f["F6"] / 2
    v = (S3 / 2) * (f["F5"] + f["F6"] - f["F1"] - f["F2"]) + f["floor"] - mg
    return h, v


scenes = st.builds(
    lambda N, P, j, F, pv, mg, ph: Scene(N=N, P=P, F=F, j0=1 + j % P, pv=pv, mg=mg, ph=ph),
    st.integers(2, 7),
    st.integers(2, 9),
    st.integers(0, 20),
    st.floats(0, 100),
    st.floats(0.1, 5),
    st.floats(0, 3),
    st.floats(0.1, 50),
)


@given(scene=scenes, seed=st.integers(0, 2**32 - 1))
def test_every_grain_is_balanced(scene, seed):
    q = np.random.default_rng(seed).random((scene.N - 1, scene.P))
    f = contact_forces(q, scene)
    h, v = _balance_residuals(f, scene.mg)
    scale = 1 + scene.F + scene.pv * scene.P + scene.mg * scene.N * scene.P + scene.ph
    assert np.abs(h).max() < 1e-12 * scale * scene.N * scene.P
    assert np.abs(v).max() < 1e-12 * scale * scene.N * scene.P
    # absent contacts stay absent: left column F1, right column F6, floor layer F5/F6
    assert not f["F1"][1:, 0].any() and not f["F6"][:, -1].any() and not f["F5"][-1].any()


@given(scene=scenes, seed=st.integers(0, 2**32 - 1))
def test_q_route_equals_lateral_force_route(scene, seed):
    """(3.8)-(3.9) in q and (3.1)-(3.3) solved in the lateral forces give one network."""
    q = np.random.default_rng(seed).random((scene.N - 1, scene.P))
    f = contact_forces(q, scene)
    g = forces_from_lateral(f["F4"][:-1, :-1], scene)
    for k in ("F1", "F2", "F3", "F4", "F5", "F6"):
        np.testing.assert_allclose(g[k], f[k], rtol=1e-10, atol=1e-10 * (1 + scene.F + scene.ph))


def test_scene_validation():
    with pytest.raises(ValueError, match="P=1 is out of range"):
        Scene(N=3, P=1, mg=1)
    with pytest.raises(TypeError, match="N=2.5"):
        Scene(N=2.5, P=3, mg=1)
    with pytest.raises(ValueError, match="j0=9 is out of range"):
        Scene(N=3, P=4, j0=9, mg=1)
    with pytest.raises(ValueError, match="mg=-1 is out of range"):
        Scene(N=3, P=4, mg=-1)
    with pytest.raises(ValueError, match="ph=0 is out of range"):
        Scene(N=3, P=4, mg=1, ph=0)
    with pytest.raises(ValueError, match="triangle"):
        Scene(N=3, P=4)  # pv = mg = 0: the fully mobilized triangle
    assert Scene(N=3, P=4, mg=1).name == "gravity"
    assert Scene(N=3, P=4, pv=2, ph=2).name == "isotropic"


def test_infeasible_scene_is_reported():
    with pytest.raises(ValueError, match="no force network with all forces > 0"):
        PackingMetropolis(Scene(N=6, P=9, F=10, pv=1, ph=1), seed=0)


@settings(max_examples=4)
@given(
    NP=st.sampled_from([(2, 3), (3, 3), (2, 4), (2, 5)]),
    j=st.integers(0, 10),
    F=st.integers(0, 4),
    mg=st.sampled_from([Fraction(1), Fraction(1, 2)]),
    seed=st.integers(0, 2**32 - 1),
)
def test_exact_means_match_uniform_rejection(NP, j, F, mg, seed):
    """Exact polynomial integration in q against uniform rejection in the lateral forces."""
    N, P = NP
    exact = np.array(mean_W_mobilized(N, P, F=F, j0=1 + j % P, mg=mg), dtype=object)
    assert all(sum(row) == F + (i + 1) * P * mg for i, row in enumerate(exact))  # load conservation
    scene = Scene(N=N, P=P, F=F, j0=1 + j % P, mg=float(mg))
    W, _ = uniform_networks(scene, 20000, np.random.default_rng(seed))
    assert_agrees(W, exact, alpha=1e-4)  # the top row never varies: compared exactly


def test_metropolis_matches_exact_gravity_scene():
    scene = Scene(N=3, P=4, F=10, j0=2, mg=1)
    chain = PackingMetropolis(scene, seed=2006).run(sweeps=8000, burn_in=200)
    assert_agrees(chain, mean_W_mobilized(3, 4, F=10, j0=2, mg=1), chain=True)  # the top row is compared exactly


@settings(max_examples=5)
@given(fst.packing_scenes(exact_means=True), fst.seeds())
def test_metropolis_matches_exact_means_on_any_solvable_scene(scene, seed):
    """Any fully mobilized scene with (N-1)(P-1) <= 8: the chain's whole table against the exact one."""
    chain = PackingMetropolis(scene, seed=seed).run(sweeps=3000, burn_in=100)
    assert_agrees(chain, exact_mean_W(scene), chain=True, alpha=1e-4)


def test_metropolis_matches_rejection_isotropic_scene():
    """With F4 >= 0 binding (p_h = p_v): Metropolis in q against rejection in F4."""
    scene = Scene(N=3, P=3, F=1, pv=1, ph=1)
    assert maximin_network(scene)[1] > 0
    W, rate = uniform_networks(scene, 20000, np.random.default_rng(7))
    assert rate < 0.9  # the constraints do cut the box
    ref, ref_err = W.mean(axis=0), W.std(axis=0, ddof=1) / math.sqrt(len(W))
    sampler = PackingMetropolis(scene, seed=11)
    chain = sampler.run(sweeps=12000, burn_in=300)
    assert sampler.rejected_by_constraint > 0
    mean, err, _ = mean_and_stderr(chain)
    sigma = np.hypot(err, ref_err)
    free = sigma > 0
    z = (mean - ref)[free] / sigma[free]
    assert np.abs(z).max() < 5, z


def test_hard_gravity_scene_large_overload():
    """F/(m g) = 1000 with gravity (Sec. 3.3.2): finite forces, sensible acceptance, load conserved."""
    scene = Scene(N=10, P=19, F=1000, mg=1)
    sampler = PackingMetropolis(scene, seed=5)
    chain = sampler.run(sweeps=60, burn_in=20)
    assert np.isfinite(chain).all() and (chain > 0).all()
    assert 0.2 < sampler.acceptance_rate < 1
    layer_load = chain.sum(axis=2)
    np.testing.assert_allclose(layer_load, np.broadcast_to(1000 + np.arange(1, 11) * 19.0, layer_load.shape), rtol=1e-12)
    finite = Scene(N=10, P=19, F=1000, mg=1, ph=600)
    sampler = PackingMetropolis(finite, seed=5)
    chain = sampler.run(sweeps=30, burn_in=10)
    assert np.isfinite(chain).all() and 0.02 < sampler.acceptance_rate < 1


def test_response_carries_the_overload_in_every_layer():
    scene = Scene(N=4, P=7, F=5, pv=1, ph=4)
    G, err, info = response(scene, sweeps=1500, burn_in=100, seed=3)
    np.testing.assert_allclose(G.sum(axis=1), 1.0, atol=1e-9)  # sum_j G(i, j) = 1 exactly
    assert np.isfinite(err).all() and (err[1:] > 0).any()
    assert G[0, scene.j0 - 1] == pytest.approx(1.0)
