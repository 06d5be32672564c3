"""The sampler's sparse routes (issue 55): random directions in Ker A by sparse projection, with no basis
("sparse") or made into an orthonormal basis ("projected"); exact in distribution (checked against the exact
means), the projector and the projected basis equal to the SVD basis's, checkpoints as dense; the compiled sweeps
called once per chunk record the same states as one call per state."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import linalg

import forcenet
from forcenet.exact.contact_network.geometries import rectangular_packing, triangle
from forcenet.exact.contact_network.polytope import balance, float_system
from forcenet.numeric.contact_network import hit_and_run
from forcenet.numeric.contact_network.hit_and_run import HitAndRun
from forcenet.numeric.contact_network.kernel_projection import KernelProjector


@pytest.mark.parametrize("route", ["sparse", "projected"])
@pytest.mark.parametrize("geometry", [triangle(5), rectangular_packing(2, 2)], ids=["frictionless", "frictional"])
def test_the_sparse_routes_sample_the_exact_means(geometry, route):
    """10000 states along projected random directions, or along a basis made of them: every varying force within
    4 error bars of the exact mean (Normaliz), the forces balance alone fixes exactly at theirs."""
    pytest.importorskip("PyNormaliz")
    exact = np.array([float(x) for x in forcenet.network(geometry.network, exact=True).exact_mean])
    walk = HitAndRun(geometry.network, basis=route)
    assert walk.route == route
    assert walk.projector is not None and walk.dimension == np.linalg.matrix_rank(
        linalg.null_space(float_system(balance(geometry.network))[0].toarray()))
    mean, error, _ = walk.run(10000, seed=2).statistics()
    varying = error > 0
    assert np.abs((mean - exact)[varying] / error[varying]).max() < 4.0
    assert np.allclose(mean[~varying], exact[~varying])


def test_the_projector_is_the_svd_bases_and_its_directions_are_isotropic():
    """P g (sparse LU of A A^T) equals K K^T g (K: the SVD's orthonormal kernel basis) to rounding; the
    directions' covariance in the basis's coordinates is the identity (isotropic: Smith's direction law)."""
    A = float_system(balance(triangle(5).network))[0]
    K = linalg.null_space(A.toarray())
    projector = KernelProjector(A)
    g = np.random.default_rng(3).standard_normal((5, A.shape[1]))
    projected = g - (projector.AT @ np.asarray(projector.lu.solve(A @ g.T))).T
    assert np.abs(projected - g @ K @ K.T).max() < 1e-10
    coordinates = projector.directions(np.random.default_rng(4), 20000) @ K
    assert np.abs(np.cov(coordinates.T) - np.eye(K.shape[1])).max() < 0.06


def test_dependent_balance_rows_are_dropped_before_the_factorization():
    """Two grains on a floor pressed together, no side walls: a sideways translation of both is a zero mode, so
    their x rows are dependent (A A^T singular): the dependent row is found (shift-invert null vectors) and
    dropped, and the sparse walk keeps the forces balance fixes. A grain whose contacts are all vertical is a
    local dependence (removed grain by grain); an unknown basis is refused in one line."""
    from forcenet.numeric.contact_network.kernel_projection import independent_rows, reduced_rows

    net = forcenet.contact_network(2, [[0, None, 0, -1], [1, None, 0, -1], [0, 1, 1, 0]], [[0, 1, -1], [1, -1, -1]])
    A, b, _ = float_system(balance(net))
    R, r = reduced_rows(A, b, 2)
    assert independent_rows(R, r)[0].shape[0] == R.shape[0] - 1
    walk = HitAndRun(net, basis="sparse")
    assert walk.dimension == 0 and np.allclose(walk.run(10, seed=1).samples, [1.0, 1.0, 1.0])
    vertical = forcenet.contact_network(1, [[0, None, 0, -1], [0, None, 0, -1]], [[0, 0, -1]])
    chain = HitAndRun(vertical, basis="sparse").run(2000, seed=1)
    assert np.allclose(chain.samples.sum(axis=1), 1) and abs(chain.samples[:, 0].mean() - 0.5) < 0.05
    with pytest.raises(forcenet.ArgumentError, match="basis must be one of"):
        HitAndRun(vertical, basis="qr")


@pytest.mark.parametrize("basis_bytes", [hit_and_run.BASIS_BYTES, 0], ids=["projected", "sparse"])
def test_auto_takes_a_sparse_route_on_large_networks_and_resumes_bit_for_bit(tmp_path, monkeypatch, basis_bytes):
    monkeypatch.setattr(hit_and_run, "SPARSE_FROM", 20)
    monkeypatch.setattr(hit_and_run, "BASIS_BYTES", basis_bytes)
    walk = HitAndRun(triangle(4).network)
    assert walk.projector is not None and walk.route == ("projected" if basis_bytes else "sparse")
    whole = walk.run(300, seed=5, burn_in=20, block=100).samples

    def stop(k: int, done: list[int] = [0]) -> None:  # noqa: B006 (the count of one run)
        done[0] += k
        if done[0] >= 150:
            raise RuntimeError("interrupted")

    with pytest.raises(RuntimeError):
        walk.run(300, seed=5, burn_in=20, block=100, checkpoint=str(tmp_path), progress=stop)
    assert np.array_equal(HitAndRun(triangle(4).network).run(300, seed=5, burn_in=20, block=100,
                                                             checkpoint=str(tmp_path)).samples, whole)


def test_the_projected_basis_is_orthonormal_and_spans_the_svd_kernel():
    """K from d projected normal vectors and QR: K^T K = I, A K = 0 and K K^T = the SVD basis's projector, to
    rounding; the forces balance alone fixes are zero rows of both."""
    for network in (triangle(5).network, rectangular_packing(2, 2).network):
        A = float_system(balance(network))[0].toarray()
        walk = HitAndRun(network, basis="projected")
        K, svd = walk.K, linalg.null_space(A)
        assert K.shape == svd.shape
        assert np.abs(K.T @ K - np.eye(K.shape[1])).max() < 1e-12 and np.abs(A @ K).max() < 1e-12
        assert np.abs(K @ K.T - svd @ svd.T).max() < 1e-10
        assert np.array_equal(walk.fixed, np.linalg.norm(svd, axis=1) < 1e-10)


def test_auto_takes_the_projected_route_while_the_basis_fits_and_the_sparse_one_beyond(monkeypatch):
    assert hit_and_run.route_for(500, 50) == "dense"
    monkeypatch.setattr(hit_and_run, "SPARSE_FROM", 20)
    assert HitAndRun(triangle(4).network).route == "projected"
    monkeypatch.setattr(hit_and_run, "BASIS_BYTES", 8 * hit_and_run.BASIS_COPIES * 6 * 26 - 1)  # d = 6, 26 forces
    assert HitAndRun(triangle(4).network).route == "sparse"


@pytest.mark.parametrize("thin", [1, 3])
def test_one_call_per_chunk_records_what_one_call_per_state_records(thin):
    """The compiled sweeps called once for 40 states (every thin-th sweep recorded) and called once per state
    (thin - 1 sweeps unrecorded, then one recorded) from the same state and generator: the same bits."""
    walk = HitAndRun(rectangular_packing(2, 2).network)
    once, per_state = np.empty((40, walk.balance.variables)), np.empty((40, walk.balance.variables))
    z0, s0 = walk._projected(walk.start.copy())
    z, s, rng = z0.copy(), s0.copy(), np.random.default_rng(7)
    hit_and_run.hit_and_run_sweeps(z, s, walk.KT, walk.GKT, walk.same, rng, 40 * thin, once, True, thin)
    z, s, rng = z0.copy(), s0.copy(), np.random.default_rng(7)
    scratch = np.empty((1, walk.balance.variables))
    for k in range(40):
        hit_and_run.hit_and_run_sweeps(z, s, walk.KT, walk.GKT, walk.same, rng, thin - 1, scratch, False, 1)
        hit_and_run.hit_and_run_sweeps(z, s, walk.KT, walk.GKT, walk.same, rng, 1, per_state[k:k + 1], True, 1)
    assert np.array_equal(once, per_state) and len(np.unique(once[:, 0])) > 30


@pytest.mark.parametrize("thin", [0, -1])
def test_a_thin_below_one_is_refused_naming_it(thin):
    """The kernel records every thin-th sweep: thin <= 0 would record nothing and return uninitialised rows."""
    with pytest.raises(forcenet.ArgumentError, match="thin"):
        HitAndRun(triangle(3).network).run(5, seed=1, thin=thin, burn_in=0)
