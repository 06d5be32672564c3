"""The force network ensemble's models of Table 7.1 (Sec. 7.2): snooker, disordered, averaged.

The sampler (hit-and-run along local self-stresses) is checked against the exact route (the contact-network
polytope's moments by triangulation) and, where the exact route cannot go (floating-point soft-disk packings),
against the dense coordinate hit-and-run, an independent sampler.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import forcenet
from forcenet.cli import main
from forcenet.exact.contact_network.geometries import snooker, square_packing
from forcenet.exact.contact_network.polytope import balance, exact_polytope, float_system
from forcenet.exact.contact_network.triangulation_moments import moments_by_triangulation
from forcenet.numeric.autocorr import mean_and_stderr
from forcenet.numeric.contact_network.hit_and_run import HitAndRun
from forcenet.numeric.contact_network.soft_disks import relaxed_packing
from forcenet.numeric.force_chains.local_hit_and_run import LocalHitAndRun, local_directions
from forcenet.numeric.force_chains.network_ensembles import ensemble_networks, network_size


@pytest.mark.parametrize("N", [3, 4])
def test_local_hit_and_run_has_the_exact_moments_of_the_snooker_polytope(N):
    net = snooker(N).network
    exact = moments_by_triangulation(exact_polytope(net), 2)
    mean = np.array([float(v) for v in exact.mean])
    second = np.array([float(v) for v in exact.second])
    walk = LocalHitAndRun(net)
    assert walk.dimension == exact.dimension and walk.radius == 1
    x = walk.run(12000, thin=1, burn_in=100, seed=N)
    m1, e1, _ = mean_and_stderr(x)
    m2, e2, _ = mean_and_stderr(x**2)
    assert np.all(np.abs(m1 - mean) < 5 * e1)
    assert np.all(np.abs(m2 - second) < 5 * e2)
    A, b, _ = float_system(balance(net))
    assert np.abs(A @ x[-1] - b).max() < 1e-10 and x.min() >= -1e-12  # balanced and repulsive throughout


def test_the_wheels_span_the_snooker_kernel():
    for N in (5, 9, 14):
        net = snooker(N).network
        contacts, moves = network_size("snooker", N)
        assert contacts == len(net.contacts)
        d = local_directions(net, float_system(balance(net))[0], len(net.contacts) - 2 * net.grains)
        assert d.radius == 1 and d.count == moves  # the wheel of every grain not on the walls, and 3 more
        assert exact_polytope(net).dimension == d.dimension


@settings(max_examples=8, deadline=None)
@given(st.integers(3, 9), st.integers(0, 2**32 - 1), st.booleans())
def test_every_direction_is_a_self_stress_and_every_state_is_a_force_network(N, seed, disordered):
    net = relaxed_packing(N * N, pressure=0.1, seed=seed).network() if disordered else snooker(N).network
    walk = LocalHitAndRun(net, max_radius=1 if disordered else 2)
    A, b, _ = float_system(balance(net))
    d = walk.directions
    for k in range(d.count):
        v = np.zeros(len(net.contacts))
        v[d.index[d.indptr[k]:d.indptr[k + 1]]] = d.value[d.indptr[k]:d.indptr[k + 1]]
        assert np.abs(A @ v).max() < 1e-9
    x = walk.run(20, thin=2, burn_in=5, seed=seed)
    assert np.abs(A @ x.T - b[:, None]).max() < 1e-9 and x.min() >= -1e-12


def test_disordered_packing_agrees_with_the_dense_sampler():
    net = relaxed_packing(16, seed=2).network()
    local = LocalHitAndRun(net)
    dense = HitAndRun(net)
    assert local.dimension == dense.dimension
    x = local.run(8000, thin=1, burn_in=200, seed=1)
    moving = ~dense.fixed  # forces balance alone fixes (a grain with two contacts) stay at their value
    assert np.allclose(x[:, ~moving], local.start[~moving], atol=1e-9)
    m1, e1, _ = mean_and_stderr(x[:, moving])
    m2, e2, _ = dense.run(8000, seed=2).statistics()
    assert np.all(np.abs(m1 - m2[moving]) < 5 * np.hypot(e1, e2[moving]))


def test_averaged_networks_are_averages_and_narrower():
    one = ensemble_networks("snooker", 8, 400, np.random.default_rng(0))[0]
    four = ensemble_networks("averaged", 8, 400, np.random.default_rng(0), average=4)[0]
    assert one.shape == four.shape
    assert abs(one.mean() - four.mean()) < 0.02  # the same centre of mass
    assert four.std() < 0.7 * one.std()  # P = 4: the weight moves from the boundary to the bulk (Fig. 7.3 b)
    assert (four < 0.02).mean() < 0.2 * (one < 0.02).mean()  # vanishing forces become rare


def test_refusals_are_one_line_in_the_family():
    with pytest.raises(forcenet.ArgumentError, match="frictionless"):
        LocalHitAndRun(square_packing(2, 2).network)
    with pytest.raises(forcenet.ArgumentError, match="average"):
        forcenet.scaling_plan("averaged", average=0)
    with pytest.raises(forcenet.ArgumentError, match="sizes"):
        forcenet.scaling_plan("snooker", sizes=(3, 8, 12))
    with pytest.raises(forcenet.ArgumentError, match="snooker, disordered, averaged"):
        forcenet.scaling_plan("snook")
    for model in ("snooker", "disordered", "averaged"):
        plan = forcenet.scaling_plan(model)
        assert plan.runnable and plan.cost_method == "local-hit-and-run" and plan.cost.seconds < 600
    big = forcenet.scaling_plan("snooker", sizes=(20, 40, 84), samples=800)
    assert 300 < big.cost.seconds < 3000  # the Table 7.1 sizes: planned, not run here


def test_checkpointed_snooker_run_resumes(tmp_path):
    options = dict(sizes=(6, 8, 10), samples=32, replicas=0, blocks=4, checkpoint=tmp_path / "ck")
    first = forcenet.scaling("snooker", **options)
    second = forcenet.scaling("snooker", **options)
    assert first.details["checkpoint_records_reused"] == 0 and second.details["checkpoint_records_reused"] == 12
    assert first.fit.value == second.fit.value
    assert [d.M for d in first.data] == [network_size("snooker", L)[0] for L in (6, 8, 10)]
    assert first.details["thin_sweeps"] == [30, 40, 50] and len(first.details["tau_recorded"]) == 3
    other = forcenet.scaling("averaged", **options)  # another model: its own records
    assert other.details["checkpoint_records_reused"] == 0 and other.details["average"] == 4


def test_cli_scaling_of_the_ensemble_models(capsys):
    code = main(["scaling", "--model", "averaged", "--average", "2", "--sizes", "6,8,10", "--samples", "32",
                 "--replicas", "2", "--format", "json", "--quiet"])
    out = json.loads(capsys.readouterr().out)
    assert code == 0 and {"f_c", "nu", "gamma_2", "sizes"} <= set(out)
    assert main(["scaling", "--model", "snooker", "--sizes", "5,6,7", "--average", "0"]) == 2
    assert "average" in capsys.readouterr().err
    assert main(["scaling", "--model", "snooker", "--sizes", "2,6,7", "--quiet"]) == 2
    assert "sizes" in capsys.readouterr().err


@pytest.mark.slow
def test_disordered_scaling_runs_and_reports_its_decorrelation():
    r = forcenet.scaling("disordered", sizes=(5, 6, 7), samples=32, replicas=0, blocks=4)
    assert all(t < 3 for t in r.details["tau_recorded"])
    assert [d.M for d in r.data] == sorted(d.M for d in r.data)


@pytest.mark.slow
def test_the_snooker_result_does_not_depend_on_the_workers():
    options = dict(sizes=(6, 8, 10), samples=32, replicas=3, blocks=4)
    one = forcenet.scaling("snooker", **options)
    two = forcenet.scaling("snooker", workers=2, **options)
    assert [d.total.tolist() for d in one.data] == [d.total.tolist() for d in two.data]
    assert one.fit.value == two.fit.value
