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
