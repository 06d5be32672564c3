"""Clusters of large forces (numeric.force_chains.newman_ziff) and finite-size scaling (finite_size_scaling).

The one-pass union-find against scipy's connected components at random thresholds (hypothesis), the wrapping
flag against known structures and the universal wrapping probability of critical bond percolation, the
collapse on exactly scaling curves, and the percolation control: a quick default run and the slow acceptance run
through the users'-data route (CSV files)."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

import forcenet
from forcenet.numeric.force_chains.finite_size_scaling import SizeBlocks, analyse, collapse_cost
from forcenet.numeric.force_chains.newman_ziff import (
    LATTICES,
    cluster_sizes,
    critical_threshold,
    periodic_lattice,
    size_distribution,
    sweep_lattice,
    sweep_samples,
)


def _reference(sites, head, tail, force, threshold):
    """Sum of s^2 but the largest and the largest, by scipy's connected components (an independent route)."""
    keep = force > threshold
    if not keep.any():
        return 0, 0
    graph = coo_matrix((np.ones(keep.sum()), (head[keep], tail[keep])), shape=(sites, sites))
    _, label = connected_components(graph, directed=False)
    sizes = np.bincount(label[head[keep]])
    return int((sizes**2).sum() - sizes.max() ** 2), int(sizes.max())


@settings(max_examples=30, deadline=None)
@given(lattice=st.sampled_from(LATTICES), L=st.integers(2, 9), seed=st.integers(0, 2**32 - 1),
       thresholds=st.lists(st.floats(-0.1, 1.1), min_size=1, max_size=6))
def test_one_pass_agrees_with_connected_components(lattice, L, seed, thresholds):
    lat = periodic_lattice(lattice, L)
    forces = np.random.default_rng(seed).random((2, lat.bonds))
    stats = sweep_lattice(lat, forces, np.array(thresholds))
    for r in range(2):
        for t, f in enumerate(thresholds):
            assert (stats.total[r, t], stats.largest[r, t]) == _reference(lat.sites, lat.head, lat.tail, forces[r], f)


@settings(max_examples=20, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), samples=st.integers(1, 4))
def test_ragged_samples_agree_with_connected_components(seed, samples):
    rng = np.random.default_rng(seed)
    starts, sites, head, tail, force = [0], [], [], [], []
    for _ in range(samples):  # random graphs with repeated bonds and loops
        n, m = int(rng.integers(1, 12)), int(rng.integers(1, 25))
        head.append(rng.integers(0, n, m))
        tail.append(rng.integers(0, n, m))
        force.append(rng.exponential(size=m))
        sites.append(n)
        starts.append(starts[-1] + m)
    head, tail, force = np.concatenate(head), np.concatenate(tail), np.concatenate(force)
    levels = np.array([0.0, 0.3, 1.0, 2.5])
    stats = sweep_samples(np.array(starts), np.array(sites), head, tail, force, levels)
    for r in range(samples):
        lo, hi = starts[r], starts[r + 1]
        for t, f in enumerate(levels):
            assert (stats.total[r, t], stats.largest[r, t]) == _reference(sites[r], head[lo:hi], tail[lo:hi], force[lo:hi], f)
            sizes = cluster_sizes(sites[r], head[lo:hi], tail[lo:hi], force[lo:hi], f)
            assert int((sizes**2).sum() - (sizes[0] ** 2 if sizes.size else 0)) == stats.total[r, t]


def test_wrapping_of_known_structures():
    L = 6
    lat = periodic_lattice("square", L)
    row0 = np.nonzero((lat.dx == 1) & (lat.head < L))[0]  # the horizontal bonds of the first row
    force = np.zeros((2, lat.bonds))
    force[0, row0] = 1.0  # a full row: wraps
    force[1, row0[:-1]] = 1.0  # the row less one bond: a path of L - 1 bonds, no wrap
    stats = sweep_lattice(lat, force, np.array([0.5]))
    assert stats.wraps[:, 0].tolist() == [1, 0]
    assert stats.largest[:, 0].tolist() == [L, L - 1]
    column = np.nonzero((lat.dy == 1) & (lat.head % L == 2))[0]  # a full column: wraps vertically
    force = np.zeros((1, lat.bonds))
    force[0, column] = 1.0
    assert sweep_lattice(lat, force, np.array([0.5])).wraps[0, 0] == 1
    # a contractible loop (one plaquette) does not wrap
    plaquette = [0, L * L + 0, L * L + 1, L]  # right of (0,0), up of (0,0), up of (1,0), right of (0,1)
    force = np.zeros((1, lat.bonds))
    force[0, plaquette] = 1.0
    stats = sweep_lattice(lat, force, np.array([0.5]))
    assert (stats.wraps[0, 0], stats.largest[0, 0]) == (0, 4)


def test_wrapping_probability_at_criticality_is_the_universal_value():
    # critical bond percolation on a square torus: a cluster wraps in either direction with probability
    # 0.690473725 (Pinson 1994; Newman and Ziff, PRE 64, 016706 (2001), Table I), whatever the lattice detail
    lat = periodic_lattice("square", 48)
    rng = np.random.default_rng(11)
    wraps = np.concatenate([sweep_lattice(lat, rng.random((100, lat.bonds)), np.array([0.5])).wraps[:, 0]
                            for _ in range(4)])
    p = wraps.mean()
    assert abs(p - 0.690473725) < 4 * math.sqrt(0.69 * 0.31 / wraps.size) + 0.02  # + finite-size correction


def test_critical_thresholds():
    assert critical_threshold("square") == 0.5
    assert abs(critical_threshold("triangular") - (1 - 2 * math.sin(math.pi / 18))) < 1e-15
    assert abs(critical_threshold("honeycomb") - 2 * math.sin(math.pi / 18)) < 1e-15


def test_collapse_recovers_exact_scaling():
    f = np.linspace(0.0, 1.0, 401)
    truth = (0.7, 2.5, 0.43)
    data = [SizeBlocks.from_curve(S, S, f, S * S ** truth[0] * np.exp(-((f - truth[2]) * S ** (1 / (2 * truth[1])) - 0.4) ** 2))
            for S in (100.0, 400.0, 1600.0, 6400.0)]
    fit = analyse(data, replicas=0)
    assert [round(fit.value[k], 3) for k in ("gamma_2", "nu", "f_c")] == list(truth)
    curves = [(d.S, d.thresholds, d.s2()) for d in data]
    assert collapse_cost(truth, curves, (-1.0, 1.0)) < 1e-6 < collapse_cost((0.7, 2.0, 0.43), curves, (-1.0, 1.0))


def test_percolation_control_quick():
    """Small sizes, seconds: the control must land near the exact values (it could fail: a biased estimator)."""
    r = forcenet.scaling("percolation", sizes=(16, 24, 32, 48, 64), samples=(800, 600, 400, 300, 200), seed=4,
                         replicas=20, thresholds=400)
    v, e = r.fit.value, r.fit.error
    assert abs(v["f_c"] - 0.5) < 0.02
    assert abs(v["gamma_2"] - 43 / 48) < 0.08
    assert abs(v["nu"] - 4 / 3) < 0.45
    assert all(e[k] > 0 for k in e)
    assert abs(r.fit.estimators["f_c_crossing"] - 0.5) < 0.02
    assert abs(r.fit.estimators["nu_width"] - 4 / 3) < 0.3


def _write_csv(path, lattice, L, K, rng):
    lat = periodic_lattice(lattice, L)
    rows = [np.column_stack([np.full(lat.bonds, k), lat.head, lat.tail, rng.random(lat.bonds)]) for k in range(K)]
    np.savetxt(path, np.concatenate(rows), fmt=["%d", "%d", "%d", "%.9f"], delimiter=",", header="sample,i,j,f",
               comments="")


def test_users_data_route_reads_csv_and_arrays(tmp_path):
    rng = np.random.default_rng(3)
    paths = []
    for L, K in ((8, 60), (12, 40), (16, 30)):
        paths.append(tmp_path / f"L{L}.csv")
        _write_csv(paths[-1], "square", L, K, rng)
    r = forcenet.clusters([str(p) for p in paths], replicas=0)
    assert [s["M"] for s in r.summary()["sizes"]] == [128, 288, 512]
    arrays = [np.loadtxt(p, delimiter=",", skiprows=1) for p in paths]
    r2 = forcenet.clusters(arrays, replicas=0)
    assert r2.fit.value == r.fit.value  # the same numbers by either input
    with pytest.raises(forcenet.ArgumentError, match="at least 3"):
        forcenet.clusters([str(paths[0])])


def _networks(lattice, L, K, rng):
    lat = periodic_lattice(lattice, L)
    return np.concatenate([np.column_stack([np.full(lat.bonds, k), lat.head, lat.tail, rng.random(lat.bonds)])
                           for k in range(K)])


@pytest.mark.slow
@pytest.mark.parametrize("lattice, sizes, samples", [
    ("square", (24, 32, 48, 64, 96, 128), (1600, 1200, 800, 500, 300, 200)),
    ("triangular", (20, 28, 40, 56, 80, 112), (1600, 1200, 800, 500, 300, 200)),
])
def test_percolation_exponents_from_users_data(tmp_path, lattice, sizes, samples):
    """The acceptance: independent uniform forces as users' data (the smallest size a CSV file, the others
    arrays: ~0.8 GB in memory), read by forcenet.clusters; the exact values within the stated bounds and
    within the reported errors (two of them: the errors are one-sigma)."""
    rng = np.random.default_rng(52)
    sources = []
    for L, K in zip(sizes, samples):
        if not sources:
            sources.append(str(tmp_path / f"{lattice}{L}.csv"))
            _write_csv(sources[-1], lattice, L, K, rng)
        else:
            sources.append(_networks(lattice, L, K, rng))
    r = forcenet.clusters(sources, replicas=40, thresholds=800)
    v, e = r.fit.value, r.fit.error
    fc = critical_threshold(lattice)
    assert abs(v["f_c"] - fc) < 0.015
    assert abs(v["gamma_2"] - 43 / 48) < 0.04
    assert abs(v["nu"] - 4 / 3) < 0.25
    assert abs(v["f_c"] - fc) < 2 * e["f_c"] + 1e-3
    assert abs(v["gamma_2"] - 43 / 48) < 2 * e["gamma_2"]
    assert abs(v["nu"] - 4 / 3) < 2 * e["nu"]
    print(lattice, r.to_text())


def test_size_distribution_counts_every_cluster():
    rng = np.random.default_rng(17)
    lat = periodic_lattice("square", 16)
    forces = rng.random((5, lat.bonds))
    starts = np.arange(6) * lat.bonds
    lower, n_s = size_distribution(starts, np.full(5, lat.sites), np.tile(lat.head, 5), np.tile(lat.tail, 5),
                                   forces.ravel(), 0.5)
    every = np.concatenate([cluster_sizes(lat.sites, lat.head, lat.tail, f, 0.5) for f in forces])
    assert np.isclose((n_s * lower * forces.size).sum(), every.size)  # every cluster counted once
    assert np.isclose(n_s[0] * forces.size, np.sum(every == 1))
    stats = sweep_lattice(lat, forces, np.array([0.5]))
    assert every.max() == stats.largest[:, 0].max()
