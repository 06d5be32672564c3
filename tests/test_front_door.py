"""The front door (``forcenet.table``, ``forcenet.plan``, ``forcenet.Table``): one request, the command line's bytes.

Every exact number is checked against an independent route (the plain dictionary dynamic program and the
linear-extension enumeration of :mod:`forcenet.exact.reference`); the renderings against the command line run
in this process; the refusals by the registry's plans.
"""

from __future__ import annotations

import contextlib
import io
import json
import subprocess
import sys
from fractions import Fraction

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import forcenet
from forcenet.cli import main
from forcenet.exact.reference.dictionary_dp import mean_W_dictionary
from forcenet.exact.reference.linear_extensions import linear_extension_moments


def _cli(*args: str) -> str:
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        assert main(list(args)) == 0
    return out.getvalue()


@settings(max_examples=12, deadline=None)
@given(N=st.integers(2, 8), method=st.sampled_from(["auto", "fast", "lambda", "pfaffian"]))
def test_the_mean_table_equals_the_dictionary_dp(N, method):
    t = forcenet.table(N, method=method)
    assert t.mean_W == mean_W_dictionary(N)
    assert all(isinstance(x, Fraction) for row in t.mean_W for x in row)
    assert t.method in ("fast", "thesis", "lambda", "maps", "pfaffian") and (method == "auto") == bool(t.why)


@pytest.mark.parametrize("N", [3, 4, 5])
def test_second_moments_equal_the_linear_extension_enumeration(N):
    t = forcenet.table(N, moments=2)
    _, reference, _ = linear_extension_moments(N, s_max=2)
    for i in range(1, N + 1):
        for j in range(1, i + 1):
            assert t.moment(2)[i - 1][j - 1] == reference[2][(i, j)], (i, j)


def test_count_and_normalization_are_eq_4_1():
    t = forcenet.table(6)
    from math import factorial

    assert t.count == forcenet.count(6) == 286
    assert t.normalization == Fraction(t.count, factorial(15)) == forcenet.normalization(6)


@pytest.mark.parametrize("fmt", ["json", "csv", "latex"])
@pytest.mark.parametrize("N, moments", [(7, 1), (5, 2)])
def test_renderings_are_the_command_lines_bytes(fmt, N, moments):
    t = forcenet.table(N, moments=moments)
    text = {"json": t.to_json, "csv": t.to_csv, "latex": t.to_latex}[fmt]()
    printed = _cli("table", "--N", str(N), "--moments", str(moments), "--format", fmt)
    assert printed == (text if text.endswith("\n") else text + "\n")
    if fmt == "json":
        assert json.loads(text)["mean_W"][-1] == [str(x) for x in t.mean_W[-1]]


def test_auto_is_the_command_lines_choice():
    request = forcenet.plan(40)
    assert request.method == "pfaffian" and request.runnable and "auto chose pfaffian" in request.why
    assert forcenet.plan(9).method == forcenet.table(9).method


def test_an_explicit_method_out_of_reach_names_the_route_that_works():
    with pytest.raises(forcenet.ArgumentError, match=r"method='auto' runs it by pfaffian"):
        forcenet.table(40, method="fast")
    refused = forcenet.plan(13, method="lambda")
    assert not refused.runnable and "N=13" in refused.refusal and "method='auto'" in refused.refusal


@pytest.mark.parametrize("kwargs, error", [
    ({"N": 1}, forcenet.ArgumentError),
    ({"N": 5.0}, forcenet.ArgumentTypeError),
    ({"N": 5, "moments": 0}, forcenet.ArgumentError),
    ({"N": 5, "method": "fastest"}, forcenet.ArgumentError),
    ({"N": 5, "method": 3}, forcenet.ArgumentTypeError),
    ({"N": 5, "checkpoint": 7}, forcenet.ArgumentTypeError),
])
def test_bad_requests_are_refused_by_the_family(kwargs, error):
    with pytest.raises(error):
        forcenet.plan(**kwargs)


def test_a_plan_computes_nothing_and_runs_as_planned(monkeypatch):
    from forcenet.exact import routes

    calls, plans = [], []
    engine = routes.TABLE_ENGINES[1]  # thesis
    real, real_plan = routes.run_request, engine.table_plan
    from forcenet import front_door

    monkeypatch.setattr(front_door, "run_request", lambda *a, **k: calls.append(a) or real(*a, **k))  # its name there
    monkeypatch.setattr(engine, "table_plan", lambda *a, **k: plans.append(a) or real_plan(*a, **k))
    request = forcenet.plan(6, method="thesis")
    assert calls == [] and len(plans) == 1
    ticks: list[int] = []
    table = request.run(progress=lambda k=1: ticks.append(k))
    checked, choice = calls[0][:2]
    assert (checked.N, checked.moments, choice.method) == (6, 1, "thesis") and choice.plan is request.cost
    assert len(plans) == 1  # run as planned: not planned again
    assert table.mean_W == mean_W_dictionary(6) and table.method == "thesis"


def test_the_table_object():
    t = forcenet.table(5, moments=2)
    assert repr(t) == f"Table(N=5, moments=2, method={t.method!r})"
    with pytest.raises(forcenet.ArgumentError, match=r"moments=3"):
        t.moment(3)
    array = t.to_numpy()
    assert array.shape == (5, 5) and float(t.mean_W[4][2]) == array[4, 2]
    import numpy as np

    assert np.isnan(array[0, 1]) and not np.isnan(array[4, 4])
    assert "<table>" in t._repr_html_() and "7/22" in t._repr_html_()
    assert r"\frac{7}{22}" in t._repr_latex_()
    assert forcenet.table(12)._repr_latex_() is None  # too wide to typeset; the HTML shows it


def test_plot_draws_every_grain():
    import matplotlib

    matplotlib.use("Agg")
    ax = forcenet.table(6).plot()
    assert len(ax.collections[0].get_offsets()) == 21


def test_import_forcenet_loads_nothing_heavy_and_every_front_door_name_resolves():
    code = ("import sys, forcenet; heavy = [m for m in ('forcenet.exact', 'numpy', 'sympy', 'numba') if m in sys.modules];"
            "print(heavy); [getattr(forcenet, n) for n in forcenet.__all__]; print(sorted(set(forcenet.__all__) - set(dir(forcenet))));"
            "print(sorted(set(forcenet.__all__) ^ {*forcenet._FRONT_DOOR, '__version__'}))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.splitlines()
    assert out == ["[]", "[]", "[]"]


def test_the_table_carries_its_bounds_to_compare():
    from forcenet.numeric.triangle.exact_sampler import ExactSampler
    from forcenet.testing import compare

    t = forcenet.table(5, moments=2)
    assert t.mean_W.bounds == t.moment(2).bounds == (0, 1)
    samples = ExactSampler(5, seed=3).sample_W(30)  # 30 samples: the bounded test, valid at any size
    assert compare(samples, t.mean_W).method == "bounded"
    assert compare(samples, [list(row) for row in t.mean_W]).method == "t"  # a plain table carries no bounds


# ------------------------------------------------------------------ one return type per function: a row has its own


@pytest.mark.parametrize("N, i, moments", [(5, 3, 1), (7, 6, 2), (6, 1, 2), (6, 6, 1)])
def test_a_row_is_the_tables_row_by_its_own_function(N, i, moments):
    r, t = forcenet.row(N, i, moments), forcenet.table(N, moments)
    assert isinstance(r, forcenet.Row) and isinstance(t, forcenet.Table)
    assert r.mean_W == t.mean_W[i - 1]
    assert all(r.moment(s) == t.moment(s)[i - 1] for s in range(1, moments + 1))
    p = forcenet.row_plan(N, i, moments)
    assert isinstance(p, forcenet.RowPlan) and not isinstance(p, forcenet.TablePlan)
    assert p.run().to_json() == r.to_json()


def test_the_row_argument_still_works_with_a_deprecation_warning():
    with pytest.warns(DeprecationWarning, match=r"forcenet\.row\(N, i"):
        old = forcenet.table(6, 2, row=5)
    assert old.to_json() == forcenet.row(6, 5, 2).to_json()
    with pytest.warns(DeprecationWarning, match=r"forcenet\.row_plan\(N, i"):
        old_plan = forcenet.plan(6, 2, row=5)
    assert isinstance(old_plan, forcenet.RowPlan) and old_plan.method == forcenet.row_plan(6, 5, 2).method


def test_a_row_out_of_range_is_refused_naming_it():
    with pytest.raises(forcenet.ArgumentError, match="row=9"):
        forcenet.row_plan(6, 9)
