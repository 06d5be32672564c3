"""Issue 56: the law grid's degree-based refusal comes when the request is checked, before any law is computed.

``forcenet dist --grid K`` plans ``K + 1`` exact evaluations of the law's degree (at most ``d = N(N-1)/2``,
``LawRequest.degree``); a grid planned over ``GRID_SECONDS`` is refused in one line, exit 2, naming the ``K``
that fits.  Before, the refusal came from ``Law.grid`` after the law was computed (``--N 40 --layer 40
--grid 100000``: the floor's Pfaffians first).
"""

from __future__ import annotations

import time

import pytest

import forcenet
import forcenet.laws
from forcenet.cli import dist, main
from forcenet.core.errors import ArgumentError
from forcenet.exact.routes import law_request
from forcenet.law_results import GRID_MAX, GRID_POINT_SECONDS, GRID_SECONDS, check_grid

CASES = [
    # (argv after dist, the K that fits for that N's degree bound)
    (["--N", "40", "--layer", "40", "--grid", "100000"], 985),
    (["--N", "60", "--ensemble", "--grid", "1000"], 190),
    (["--N", "128", "--grain", "128,64", "--grid", "9"], 8),
    (["--N", "20", "--grain", "12,6", "--contact", "F1", "--grid", "99999"], 16619),
]


@pytest.fixture
def no_law(monkeypatch):
    """Any computation of a law fails the test: the refusal must come before."""
    def computed(*args, **kwargs):
        raise AssertionError("a law was computed before the grid was refused")

    monkeypatch.setattr(forcenet.laws.LawPlan, "run", computed)
    monkeypatch.setattr(dist, "run_planned", computed)


@pytest.mark.parametrize("argv, fits", CASES, ids=[" ".join(a) for a, _ in CASES])
def test_a_grid_too_costly_is_refused_before_the_law(argv, fits, no_law, capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    start = time.monotonic()
    code = main(["dist", *argv, "--format", "json"])
    elapsed = time.monotonic() - start
    out, err = capsys.readouterr()
    assert code == 2 and out == "" and len(err.splitlines()) == 1, err
    assert f"grid must be an integer in 1..{fits} for this law" in err and "Traceback" not in err
    assert elapsed < 10.0


def test_a_grid_that_fits_is_not_refused():
    """The largest K that fits passes the request's check; one more is refused."""
    plan = forcenet.law_plan(40, layer=40)
    assert plan.check_grid(985) == 985
    with pytest.raises(ArgumentError, match="grid=986 is out of range here"):
        plan.check_grid(986)


@pytest.mark.parametrize("N", [4, 5, 6, 7])
def test_the_requests_degree_bounds_every_laws_degree(N):
    """The check before the law uses ``d``; the law's own pieces never exceed it (a layer's may be ``d - 1``), so
    a grid the request accepts is never refused by ``Law.grid`` afterwards."""
    for target in [dict(grain=(N, 2)), dict(layer=N), dict(layer=N - 1), {}, dict(grain=(N - 1, 2), contact="F1")]:
        law = forcenet.law(N, target.get("grain"), layer=target.get("layer"), contact=target.get("contact"))
        degree = max(max(p.poly.degree() for p in pieces) for pieces in (law.density, law.cdf))
        bound = law_request(N, target.get("grain"), layer=target.get("layer"), contact=target.get("contact")).degree
        assert degree <= bound == N * (N - 1) // 2 and degree >= bound - 1


def test_check_grid_names_the_largest_K_within_the_budget():
    for degree in (10, 190, 780, 8128):
        per_point = GRID_POINT_SECONDS * degree**2
        fits = min(GRID_MAX, max(1, int(GRID_SECONDS / per_point) - 1))
        assert check_grid(fits, degree) == fits
        if fits < GRID_MAX:
            with pytest.raises(ArgumentError, match=f"in 1..{fits} for this law"):
                check_grid(fits + 1, degree)
