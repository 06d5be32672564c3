"""Contact networks at the front door and on the command line (issue 55): plans, renderings, refusals, sampler."""

from __future__ import annotations

import json

import numpy as np
import pytest

import forcenet
from forcenet.cli import main
from forcenet.exact.contact_network.geometries import triangle

pytest.importorskip("PyNormaliz")

SMALL = {"grains": 1, "contacts": [[0, None, "-3/5", "-4/5"], [0, None, "3/5", "-4/5"], [0, None, 0, -1]],
         "loads": [[0, 0, -1]]}


def test_exact_json_in_the_input_order(tmp_path, capsys):
    path = tmp_path / "net.json"
    path.write_text(json.dumps(SMALL))
    assert main(["network", str(path), "--exact", "--moments", "2", "--format", "json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["dimension"] == 1
    assert [(c["i"], c["j"], c["mean"], c["second"]) for c in out["contacts"]] == [
        (0, None, "5/16", "25/192"), (0, None, "5/16", "25/192"), (0, None, "1/2", "1/3")]


def test_sampled_means_lie_within_their_error_bars_of_the_exact_ones():
    """Acceptance: --samples 20000 gives means within their error bars of the exact ones (a 4-sigma band over
    the 40 forces of the triangle N = 5; the second moments too)."""
    result = forcenet.network(triangle(5).network, exact=True, moments=2, samples=20000, seed=2)
    exact = np.array([float(x) for x in result.exact_mean])
    z = (result.sampled_mean - exact) / result.sampled_error
    assert np.abs(z).max() < 4.0
    second = np.array([float(x) for x in result.exact_second])
    assert np.abs((result.sampled_second - second) / result.second_error).max() < 4.0


BAD = {
    "missing grain": ({"grains": 2, "contacts": [[0, 3, 1, 0]], "loads": []}, "grain 3 does not exist"),
    "not unit": ({"grains": 1, "contacts": [[0, None, "1", "1"]], "loads": []}, "not 1"),
    "nan": ({"grains": 1, "contacts": [[0, None, 1, 0]], "loads": [[0, "nan", 0]]}, "not a finite number"),
    "unbalanced": ({"grains": 2, "contacts": [[0, 1, 1, 0]], "loads": [[0, "1", 0]]}, "not balanced"),
    "tensile": ({"grains": 1, "contacts": [[0, None, 0, -1]], "loads": [[0, 0, 1]]}, "infeasible"),
    "self-stress": ({"grains": 2, "contacts": [[0, 1, 1, 0], [0, None, -1, 0], [1, None, 1, 0], [0, None, 0, -1],
                                               [1, None, 0, -1]], "loads": [[0, 0, -1], [1, 0, -1]]}, "unbounded"),
}


@pytest.mark.parametrize("case", sorted(BAD))
def test_every_bad_network_is_one_line_and_exit_2(case, tmp_path, capsys):
    document, message = BAD[case]
    path = tmp_path / "bad.json"
    path.write_text(json.dumps(document))
    assert main(["network", str(path), "--exact"]) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1


def test_a_file_that_is_not_json(tmp_path, capsys):
    path = tmp_path / "bad.json"
    path.write_text("grains: 2")
    assert main(["network", str(path)]) == 2
    assert "is not JSON" in capsys.readouterr().err


def test_floats_are_refused_by_the_exact_route_and_sampled(tmp_path, capsys):
    document = dict(SMALL, contacts=[[0, None, -0.6, -0.8], [0, None, 0.6, -0.8], [0, None, 0, -1]])
    path = tmp_path / "floats.json"
    path.write_text(json.dumps(document))
    assert main(["network", str(path), "--exact"]) == 2
    assert "--samples" in capsys.readouterr().err
    assert main(["network", str(path), "--samples", "3000", "--format", "csv", "--quiet"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[0] == "contact,kind,i,j,mean,error" and len(lines) == 4
    mean, error = (float(x) for x in lines[3].split(",")[4:6])
    assert abs(mean - 0.5) < 5 * error


def test_the_plan_chooses_and_names_its_engines():
    plan = forcenet.network_plan(triangle(4).network, exact=True, samples=100, seed=0)
    assert plan.methods == ("triangulation", "hit-and-run") and plan.runnable
    volumes = forcenet.network_plan(triangle(3).network, method="volumes", moments=2)
    assert volumes.methods == ("volumes",)
    assert volumes.run().exact_second == forcenet.network(triangle(3).network, moments=2).exact_second


def test_the_response_of_the_hexagonal_geometry_is_exact_and_balanced():
    from forcenet.exact.contact_network.geometries import hexagonal_packing

    geo = hexagonal_packing(2, 3, F=0, p_v=1)
    response = forcenet.network_response(geo.network, geo.grain[(1, 2)], (0, -1), exact=True)
    floors = [response[geo.contact[("floor", 2, j)]] for j in (1, 2, 3)]
    assert sum(floors) == 1  # the floor takes the whole extra load


def test_the_frictional_rectangular_packing_exact_equals_reference_and_sampler():
    """Chapter 5's rectangular packing with friction (normal and tangential forces, torque balance): the
    triangulation equals the reference route, and the sampler agrees within its error bars."""
    import sys
    from pathlib import Path

    sys.path.insert(0, str(Path(__file__).parent))
    from test_contact_network import _reference

    from forcenet.exact.contact_network.geometries import rectangular_packing
    from forcenet.exact.contact_network.polytope import exact_polytope

    geo = rectangular_packing(2, 2, friction="1/2")
    poly = exact_polytope(geo.network)
    result = forcenet.network(geo.network, exact=True, moments=2, samples=20000, seed=3)
    mean, second = _reference(poly)
    assert list(result.exact_mean) == mean and list(result.exact_second) == second
    assert any(label.startswith("t") for label in result.labels)
    exact = np.array([float(x) for x in result.exact_mean])
    varying = result.sampled_error > 0
    assert np.abs((result.sampled_mean - exact)[varying] / result.sampled_error[varying]).max() < 4.0
    assert np.allclose(result.sampled_mean[~varying], exact[~varying])
    assert "tangential" in result.to_dict()["contacts"][0]


def _delaunay(n: int, seed: int):
    from scipy.spatial import ConvexHull, Delaunay

    rng = np.random.default_rng(seed)
    pts = rng.random((n, 2))
    edges = sorted({tuple(sorted((int(s[a]), int(s[b])))) for s in Delaunay(pts).simplices
                    for a in range(3) for b in range(a + 1, 3)})
    contacts = [[i, j, *((pts[j] - pts[i]) / np.linalg.norm(pts[j] - pts[i])).tolist()] for i, j in edges]
    loads = []
    for a, b in ConvexHull(pts).simplices:  # a uniform pressure on the hull, each edge's share on its ends
        edge = pts[b] - pts[a]
        normal = np.array([edge[1], -edge[0]])
        normal = normal if normal @ (pts[a] - pts.mean(axis=0)) > 0 else -normal
        loads += [[int(a), *(-normal / 2).tolist()], [int(b), *(-normal / 2).tolist()]]
    return forcenet.contact_network(n, contacts, loads)


def test_delaunay_contacts_of_random_points_are_refused_plainly():
    """Most Delaunay networks of random points under a uniform pressure on their hull have no compressive
    force network (the issue's warning): the refusal says what the network is not and what to do."""
    refused = 0
    for seed in range(10):
        try:
            forcenet.network_plan(_delaunay(10, seed), samples=100)
        except forcenet.ArgumentError as exc:
            refused += 1
            assert "not a packing in mechanical equilibrium" in str(exc) and "relaxed_packing" in str(exc)
    assert refused >= 3


def test_a_relaxed_soft_disk_packing_is_sampled_with_error_bars():
    from forcenet.numeric.contact_network.soft_disks import relaxed_packing

    packing = relaxed_packing(40, seed=3)
    assert packing.residual < 1e-9
    result = forcenet.network(packing.network(), samples=3000, seed=1)
    assert result.dimension > 0 and np.isfinite(result.sampled_error).all()
    assert (result.sampled_mean > -1e-12).all()
    edges, density, error = result.force_distribution(20)
    assert abs((density * np.diff(edges)).sum() - 1) < 1e-9


@pytest.mark.slow
def test_independent_chains_on_an_executor_are_pooled():
    """chains=K on an executor (here threads; a Dask client's executor the same way): K seeds, one pooled
    result within its error bars of the exact means."""
    from concurrent.futures import ThreadPoolExecutor

    with ThreadPoolExecutor(2) as pool:
        result = forcenet.network(triangle(4).network, exact=True, samples=6000, chains=2, seed=5, executor=pool)
    exact = np.array([float(x) for x in result.exact_mean])
    assert result.samples.shape[0] == 6000
    assert np.abs((result.sampled_mean - exact) / result.sampled_error).max() < 4.0


def test_the_response_on_the_hexagonal_packing_is_chapter_3s():
    """Ch. 3's response (the mean loads with an overload minus without) from network_response equals the
    difference of today's packing route's exact means."""
    import sympy

    from forcenet.exact.contact_network.geometries import hexagonal_packing
    from forcenet.exact.packing.mobilized import mean_W_mobilized

    N, P = 3, 3
    geo = hexagonal_packing(N, P, F=0, p_v=1, p_h="100*sqrt(3)")
    response = forcenet.network_response(geo.network, geo.grain[(1, 2)], (0, -1), exact=True)
    with_load, without = mean_W_mobilized(N, P, F=1, j0=2, pv=1), mean_W_mobilized(N, P, F=0, pv=1)
    for j in range(1, P + 1):
        expected = with_load[N - 1][j - 1] - without[N - 1][j - 1]
        assert response[geo.contact[("floor", N, j)]] == sympy.Rational(expected)
