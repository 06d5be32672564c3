"""The front door for one load's law (``forcenet.law``, ``forcenet.law_plan``, ``forcenet.Law``): ``forcenet dist``'s
request and bytes, planned once, refusals that name what works, moments against the tables (a second route).
"""

from __future__ import annotations

import contextlib
import io
from fractions import Fraction

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import forcenet
from forcenet.cli import main
from forcenet.exact import law_registry, routes
from forcenet.exact.triangle.de_bruijn import floor
from forcenet.exact.triangle.free_fermion import fluctuations


def _cli(*args: str) -> str:
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        assert main(["dist", *args]) == 0
    return out.getvalue()


# ------------------------------------------------------------------ one request, the command line's bytes


@pytest.mark.parametrize("argv, request_, fmt, grid", [
    (["--N", "8", "--grain", "8,4"], {"N": 8, "grain": (8, 4)}, "text", None),
    (["--N", "6", "--grain", "6,3", "--format", "json", "--grid", "4"], {"N": 6, "grain": (6, 3)}, "json", 4),
    (["--N", "7", "--layer", "5", "--format", "csv"], {"N": 7, "layer": 5}, "csv", None),
    (["--N", "6", "--layer", "6", "--format", "csv", "--grid", "3"], {"N": 6, "layer": 6}, "csv", 3),
    (["--N", "7", "--grain", "5,2", "--contact", "F1", "--format", "latex"],
     {"N": 7, "grain": (5, 2), "contact": "F1"}, "latex", None),
    (["--N", "6", "--ensemble", "--format", "latex", "--grid", "2"], {"N": 6}, "latex", 2),
    (["--N", "5", "--ensemble", "--format", "json"], {"N": 5}, "json", None),
    (["--N", "6", "--layer", "3", "--grid", "5"], {"N": 6, "layer": 3}, "text", 5),
])
def test_the_law_renders_dist_s_bytes(argv, request_, fmt, grid):
    law = forcenet.law(**request_)
    assert _cli(*argv) == getattr(law, f"to_{fmt}")(grid) + "\n"


def test_the_law_is_the_command_lines_route_and_the_plans_choice():
    assert forcenet.law(12, (12, 6)).method == routes.choose_law(routes.law_request(12, (12, 6))).route == "ideals"
    p = forcenet.law_plan(40, layer=40)
    assert (p.method, p.runnable, p.over_primes) == ("floor", True, True) and "floor" in p.why
    assert forcenet.law_plan(64, (64, 1)).method == "pfaffian" and not forcenet.law_plan(64, (64, 1)).over_primes
    assert forcenet.law_plan(40).method == "pfaffians"
    assert forcenet.law_plan(9, layer=4, method="ideals").why == ""


# ------------------------------------------------------------------ planned once


@pytest.fixture
def route_calls(monkeypatch):
    """Every call of the three route functions (the engines' plans of a law), counted."""
    calls: list[str] = []

    def counted(module, name):
        real = getattr(module, name)
        monkeypatch.setattr(module, name, lambda *a, **k: calls.append(name) or real(*a, **k))

    counted(law_registry, "grain_route")  # the law's policy calls them where it imported them
    counted(law_registry, "layer_route")
    counted(law_registry, "ensemble_route")
    return calls


@pytest.mark.parametrize("request_, argv", [
    ({"N": 7, "grain": (7, 3)}, ["--N", "7", "--grain", "7,3"]),
    ({"N": 7, "layer": 4}, ["--N", "7", "--layer", "4", "--format", "json"]),
    ({"N": 6}, ["--N", "6", "--ensemble", "--format", "csv"]),
])
def test_the_plan_is_made_once_per_run(route_calls, request_, argv):
    plan = forcenet.law_plan(**request_)
    assert len(route_calls) == 1
    law = plan.run()
    assert len(route_calls) == 1, "a run does not plan again"
    forcenet.law(**request_)
    assert len(route_calls) == 2
    out = _cli(*argv)
    assert len(route_calls) == 3 and out.startswith(("N = ", "{", "lo,hi"))
    assert law.moment(0) == 1


def test_the_command_lines_checkpoint_does_not_plan_again(route_calls, tmp_path, capsys):
    """``--checkpoint`` on a route without primes is refused as before, after one plan, the directory untouched."""
    code = main(["dist", "--N", "9", "--layer", "9", "--checkpoint", str(tmp_path / "ck")])
    assert code == 2 and "--checkpoint applies to the de Bruijn Pfaffians" in capsys.readouterr().err
    assert route_calls == ["layer_route"] and not (tmp_path / "ck").exists()


# ------------------------------------------------------------------ refusals name what works


@pytest.mark.parametrize("request_, needle", [
    ({"N": 40, "layer": 40, "method": "ideals"}, "method='auto' runs it by floor (~"),
    ({"N": 40, "grain": (40, 1), "method": "ideals"}, "method='auto' runs it by pfaffian (~"),
    ({"N": 12, "grain": (12, 6), "method": "pfaffians"}, "method='auto' runs it by ideals (~"),
    ({"N": 12, "grain": (6, 3), "contact": "F5", "method": "pfaffians"}, "method='auto' runs it by ideals (~"),
    ({"N": 31, "grain": (30, 15), "contact": "F5"}, "a grain's W_ij, a layer or the ensemble run up to N=128"),
])
def test_every_refusal_names_what_works(request_, needle):
    plan = forcenet.law_plan(**request_)
    assert not plan.runnable and needle in plan.refusal
    with pytest.raises(forcenet.ArgumentError, match="runs it by|run up to"):
        forcenet.law(**request_)
    named = plan.refusal.rsplit("runs it by ", 1)[-1].split(" ")[0]
    if named in routes.LAW_ROUTES:  # the route named runs it
        assert forcenet.law_plan(**{k: v for k, v in request_.items() if k != "method"}).method == named


def test_options_of_the_routes_over_primes_are_refused_elsewhere_naming_the_route(tmp_path):
    with pytest.raises(forcenet.ArgumentError, match=r"checkpoint= applies to the law routes over primes .*run it "
                                                      r"without"):
        forcenet.law(8, layer=8, checkpoint=tmp_path)
    assert list(tmp_path.iterdir()) == []
    with pytest.raises(forcenet.ArgumentError, match="not to route='ideals'"):
        routes.law_checkpoint(routes.law_request(8, layer=8), "ideals", tmp_path)
    kept = forcenet.law_plan(40, layer=40, checkpoint=tmp_path / "ck")  # the floor's route over primes
    assert kept.checkpoint.request["route"] == "pfaffian-floor" and kept.seconds == forcenet.law_plan(40, layer=40).seconds
    with pytest.raises(forcenet.ArgumentError, match="keeps its checkpoint already"):
        kept.with_options(checkpoint=tmp_path)


@pytest.mark.parametrize("kwargs, error", [
    ({"N": 6, "grain": (1, 1)}, forcenet.ArgumentError),
    ({"N": 6, "grain": (3, 2), "layer": 3}, forcenet.ArgumentError),
    ({"N": 6, "layer": 3, "contact": "F5"}, forcenet.ArgumentError),
    ({"N": 6, "grain": (6, 3), "contact": "F9"}, forcenet.ArgumentError),
    ({"N": 6, "grain": (6, 3), "contact": "F5"}, forcenet.ArgumentError),  # the floor's lower contact: not random
    ({"N": 6, "grain": (6, 3), "contact": 5}, forcenet.ArgumentTypeError),
    ({"N": 6, "grain": (7, 1)}, forcenet.ArgumentError),
    ({"N": 6, "grain": "6,3"}, forcenet.ArgumentTypeError),
    ({"N": 6, "layer": 1}, forcenet.ArgumentError),
    ({"N": 129}, forcenet.ArgumentError),
    ({"N": 6, "method": "fast"}, forcenet.ArgumentError),
    ({"N": 6, "method": 1}, forcenet.ArgumentTypeError),
    ({"N": 6, "checkpoint": 3}, forcenet.ArgumentError),  # the DP: no checkpoints at all
    ({"N": 6, "memory_bytes": 0}, forcenet.ArgumentError),
])
def test_bad_requests_are_refused_by_the_family(kwargs, error):
    with pytest.raises(error):
        forcenet.law_plan(**kwargs)


def test_the_limits_are_the_engines():
    from forcenet.exact.triangle.gaps import CONTACT_KINDS, gap_laws_plan

    assert routes.LAW_MAX_N == fluctuations.MAX_LAW_N == floor.MAX_FLOOR_N
    assert routes.LAW_CONTACTS == CONTACT_KINDS
    assert "out of range" in gap_laws_plan(routes.LAW_DP_MAX_N + 1).refusal
    assert "out of range" not in (gap_laws_plan(routes.LAW_DP_MAX_N).refusal or "")
    assert forcenet.law_plan(routes.LAW_MAX_N).request.N == routes.LAW_MAX_N


# ------------------------------------------------------------------ exact numbers, two routes


@settings(max_examples=25, deadline=None)
@given(data=st.data(), N=st.integers(2, 7), s=st.integers(1, 3))
def test_a_grains_moments_are_the_tables(data, N, s):
    """The gap law's Bernstein density integrated piece by piece against the order-ideal path sums of the table."""
    i = data.draw(st.integers(2, N), label="i")
    j = data.draw(st.integers(1, i), label="j")
    law = forcenet.law(N, (i, j))
    table = forcenet.table(N, moments=s)
    assert law.moment(s) == table.moment(s)[i - 1][j - 1]
    assert law.moment(0) == 1 and law.cdf_at(1) == 1 and law.cdf_at(0) == 0
    assert law.extra["mean"] == law.mean and law.extra["second_moment"] == law.moment(2)


@settings(max_examples=15, deadline=None)
@given(data=st.data(), N=st.integers(2, 7), s=st.integers(1, 3))
def test_a_layers_moments_are_the_tables(data, N, s):
    """``f = i W_ij``, ``j`` uniform: ``E[f^s] = i^s mean_j <W_ij^s>``, from the table."""
    i = data.draw(st.integers(2, N), label="i")
    law = forcenet.law(N, layer=i)
    row = forcenet.table(N, moments=s).moment(s)[i - 1]
    assert law.moment(s) == Fraction(i**s) * sum(row) / i
    assert law.mean == 1 and law.support == (0, i)


def test_the_ensemble_pools_every_layer():
    """The ensemble's ``P(f)`` is every layer's, weighted by its ``i`` grains among the ``N(N+1)/2 - 1``."""
    N = 5
    grains = N * (N + 1) // 2 - 1
    pooled = sum((Fraction(i, grains) * forcenet.law(N, layer=i).moment(2) for i in range(2, N + 1)), Fraction(0))
    assert forcenet.law(N).moment(2) == pooled


def test_values_at_a_point_are_exact():
    law = forcenet.law(3, (3, 2))  # p(w) = 6 w (1 - w)
    assert law.density_at(Fraction(1, 3)) == Fraction(4, 3) and law.density_at("1/3") == Fraction(4, 3)
    assert law.density_at(0.1) == float(6 * Fraction(0.1) * (1 - Fraction(0.1)))
    assert law.cdf_at(-1) == 0 and law.cdf_at(2) == 1 and law.density_at(2) == 0
    pooled = forcenet.law(5)
    for piece in pooled.density[1:]:  # continuous at the breaks: the two pieces agree there
        assert pooled.density_at(piece.lo) == piece.poly.eval(piece.lo)


def test_the_law_object(tmp_path):
    import matplotlib

    matplotlib.use("Agg")
    law = forcenet.law(6, layer=6)
    assert repr(law) == "Law(N=6, quantity='P(f), f = 6 W_{6,j} (layer 6)', method='ideals')"
    assert "layer 6" in law._repr_html_() and law._repr_latex_().startswith("$p(f) = ")
    x, p, F = law.grid(6)
    assert x.tolist() == [0, 1, 2, 3, 4, 5, 6] and F[-1] == 1.0 and p[0] == float(law.density_at(0))
    ax = law.plot()
    assert ax.get_xlabel() == "f" and len(ax.lines[0].get_xdata()) == 401
    assert isinstance(law, forcenet.Law) and isinstance(forcenet.law_plan(6), forcenet.LawPlan)


@pytest.mark.slow
def test_the_ensemble_by_every_layers_pfaffians_is_the_dps_and_checkpoints(monkeypatch, tmp_path):
    """The Pfaffian route (chosen by hand at N = 8, where the plans pick the DP) gives the DP's law; the checkpoint
    directory holds one request per layer, and a rerun plans once and reuses them."""
    from forcenet.core.plan import Plan

    dp = forcenet.law(8)
    chosen = ("pfaffians", Plan("every layer", 1.0))
    monkeypatch.setattr(law_registry, "ensemble_route", lambda N, memory=None, **_: chosen)
    by_pfaffians = forcenet.law(8, checkpoint=tmp_path)
    assert by_pfaffians.method == "pfaffians" and by_pfaffians.to_json() == dp.to_json()
    assert len(list(tmp_path.iterdir())) == 7
    assert forcenet.law_plan(8, checkpoint=tmp_path).checkpoint == str(tmp_path)


def test_a_laws_plan_counts_the_clusters_workers():
    """Issue 46: ``dist --scheduler`` planned as if the cluster were this machine; the law's plan (and so the
    command line's announcement and refusals) now divides the primes among the executor's workers."""
    from concurrent.futures import ThreadPoolExecutor

    from forcenet.core.execution import declare_workers

    with declare_workers(ThreadPoolExecutor(1), 1) as one, declare_workers(ThreadPoolExecutor(16), 16) as many:
        for request in ({"layer": 40}, {"layer": 20}, {"grain": (39, 20)}, {}):
            alone = forcenet.law_plan(40, **request, executor=one)
            wide = forcenet.law_plan(40, **request, executor=many)
            assert alone.method == wide.method != "ideals", request
            assert wide.seconds < alone.seconds / 4, (request, alone.seconds, wide.seconds)


def test_a_plan_given_a_cluster_afterwards_counts_its_workers():
    """The command line plans first, then connects to ``--scheduler`` for a route over primes: the plan it
    announces is the chosen route's on the cluster's workers, not this machine's."""
    from concurrent.futures import ThreadPoolExecutor

    from forcenet.core.execution import declare_workers

    local = forcenet.law_plan(40, layer=20)
    with declare_workers(ThreadPoolExecutor(16), 16) as many:
        on_cluster = local.with_options(executor=many)
        direct = forcenet.law_plan(40, layer=20, executor=many)
    assert on_cluster.method == local.method == direct.method
    assert on_cluster.seconds == direct.seconds < local.seconds / 4
