"""The triangle in the registry (issue 51): its table, row and law engines are objects of one registry.

Each table method, each route to one row and each route to a load's law is an engine registered under the model
``"triangle"``; the request is checked once and the engines trust it. The rows' routes are checked against the
order-ideal DP's whole table (an independent route), the law engines against the order-ideal DP's law.
"""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from forcenet.core.errors import ArgumentError, ArgumentTypeError
from forcenet.core.registry import REGISTRY, Engine
from forcenet.exact import routes
from forcenet.exact.law_registry import LAW_ENGINES, law_request, law_run
from forcenet.exact.protocol import check_table_request
from forcenet.exact.row_routes import ROW_ENGINES, row_policy
from forcenet.exact.triangle.moments import table_run


def test_every_engine_of_the_triangle_is_registered_once():
    assert REGISTRY.methods("triangle", "table") == ("fast", "thesis", "lambda", "maps", "pfaffian")
    assert REGISTRY.methods("triangle", "row")[5:] == ("apex", "covers", "lattice", "layers", "floor")
    assert REGISTRY.methods("triangle", "law") == ("ideals", "pfaffian", "floor", "layers", "pfaffians")
    for engine in routes.ENGINES:
        assert isinstance(engine, Engine) and engine.model == "triangle"
        for quantity in engine.quantities:
            assert REGISTRY.engine("triangle", quantity, engine.name) is engine
    assert "triangle" in REGISTRY.models()


def test_the_request_is_checked_once_and_frozen():
    request = routes.check_request(9, 2, "fast", row=4)
    assert (request.model, request.quantity) == ("triangle", "row")
    with pytest.raises(AttributeError):
        request.N = 10  # type: ignore[misc]
    with pytest.raises(ArgumentError, match="method='covers' is out of range: method must be one of fast, "):
        routes.check_request(9, method="covers")  # a row's route is not a method
    with pytest.raises(ArgumentTypeError, match="method=3 is not a string: method must be one of fast, "):
        routes.check_request(9, method=3)
    assert check_table_request(9).quantity == "table"


def test_auto_is_the_registrys_choice():
    request = routes.check_request(28)
    decision = REGISTRY.decide(request)
    assert decision.engine.name == routes.choose(28).method == "pfaffian"
    assert set(decision.plans) | set(decision.skipped) == {"fast", "thesis", "lambda", "maps", "pfaffian"}


@settings(max_examples=12, deadline=None)
@given(data=st.data())
def test_every_runnable_row_route_gives_the_dps_row(data):
    N = data.draw(st.integers(2, 7), label="N")
    row = data.draw(st.integers(1, N), label="row")
    moments = data.draw(st.integers(1, 3), label="moments")
    dp = table_run(N, moments)
    request = routes.check_request(N, moments, "pfaffian", row=row)
    serves = {"apex": row == 1, "covers": moments == 2 and 1 < row, "lattice": row == 2,
              "layers": 1 < row < N, "floor": 1 < row == N}  # the rows each route is asked for (row_policy)
    for engine in ROW_ENGINES:
        plan = engine.plan(request)
        if serves[engine.name] and plan.runnable:
            found = engine.run(request, plan)
            assert found == {s: dp[s][row - 1] for s in range(1, moments + 1)}, engine.name
    chosen = row_policy(REGISTRY, request)
    assert chosen.engine.run(request, chosen.plan) == {s: dp[s][row - 1] for s in range(1, moments + 1)}


def test_a_law_engine_runs_its_route_and_refuses_a_law_it_does_not_serve():
    request = law_request(6, (6, 3))
    decision = REGISTRY.decide(request)
    assert decision.engine.name == "ideals" and decision.why.startswith("auto: ideals")
    law = decision.engine.run(request, decision.plan)
    assert law.extra == law_run(request, "ideals").extra
    floor = next(engine for engine in LAW_ENGINES if engine.name == "floor")
    assert floor.plan(request).refusal == "route 'floor' does not serve this law at N=6: ideals does"
    assert REGISTRY.decide(law_request(40, layer=40)).engine.name == "floor"
    assert REGISTRY.decide(law_request(40, layer=40, method="ideals")).plan.refusal.endswith(")")
