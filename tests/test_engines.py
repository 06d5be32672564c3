"""The engine protocol of ``forcenet table`` (issue 25): one plan/run pair per method, memory honoured, auto.

Every table method is a module with ``table_plan``/``table_run`` taking the same arguments; ``method="auto"``
picks the fastest runnable plan and gives the same exact table as the method it names; the Chinese remainder
bound of :mod:`forcenet.exact.modular` is ``product > bound`` (tested at the edge).
"""

from __future__ import annotations

import ast
import inspect
import sys
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import pytest
from hypothesis import given
from hypothesis import strategies as st

from forcenet.core.errors import ArgumentError
from forcenet.core.registry import REGISTRY
from forcenet.exact import routes
from forcenet.exact.modular import crt, crt_many, primes_for_bound
from forcenet.exact.triangle.moments import mean_W

ROOT = Path(__file__).resolve().parents[1]


@pytest.mark.parametrize("method", [engine.name for engine in routes.TABLE_ENGINES])
def test_every_method_has_the_same_plan_and_run(method):
    engine = sys.modules[type(REGISTRY.engine("triangle", "table", method)).__module__]  # its module's user faces
    assert engine.ENGINE.name == method and "table" in engine.ENGINE.quantities
    plan = inspect.signature(engine.table_plan).parameters
    run = inspect.signature(engine.table_run).parameters
    assert list(plan)[:2] == list(run)[:2] == ["N", "moments"]
    for name in ("memory_bytes", "executor"):
        assert plan[name].kind is run[name].kind is inspect.Parameter.KEYWORD_ONLY and plan[name].default is None
    assert run["progress"].kind is inspect.Parameter.KEYWORD_ONLY


@pytest.mark.parametrize("method, N", [("fast", 6), ("thesis", 5), ("lambda", 10), ("pfaffian", 6)])
def test_memory_bytes_is_honoured_by_plan_and_run(method, N):
    plan = routes.table_plan(method, N)
    assert plan.runnable and plan.nbytes > 0
    assert routes.table_plan(method, N, memory_bytes=2 * plan.nbytes).runnable  # the DP keeps 1/4 for the rest
    refused = routes.table_plan(method, N, memory_bytes=plan.nbytes - 1)
    assert "GiB" in refused.refusal
    with pytest.raises(ArgumentError, match="GiB"):  # refused before any work
        routes.table_run(method, N, memory_bytes=plan.nbytes - 1)


def test_the_map_route_streams_its_maps():
    """maps holds one map at a time (O(N^2) accumulators): its plan needs no memory a budget could refuse."""
    assert routes.table_plan("maps", 7, 2, memory_bytes=1).runnable


def test_auto_picks_the_pfaffian_route_for_large_N_and_the_dp_for_higher_moments():
    # at N = 28 the order-ideal DP takes minutes, the Pfaffian route seconds (kernels compiled or not)
    choice = routes.choose(28)
    assert choice.method == "pfaffian" and choice.plan.runnable
    assert choice.why.startswith("auto chose pfaffian: the fastest by the plans (")
    assert "auto chose pfaffian" in routes.table_plan("auto", 28).what
    assert routes.choose(16, moments=2).method == "fast"  # the Pfaffian route's second moments cost a grid per layer


@pytest.mark.parametrize("moments", [1, 2, 3])
def test_auto_never_chooses_an_unrunnable_plan(moments):
    for N in (2, 3, 5, 8, 9, 10, 13, 20, 25, 36, 41, 64):
        choice = routes.choose(N, moments, memory_bytes=2**33)
        plans = {e.name: e.plan(routes.check_request(N, moments, e.name, memory_bytes=2**33))
                 for e in routes.TABLE_ENGINES}
        runnable = {m: p.seconds for m, p in plans.items() if p.runnable}
        assert choice.plan.runnable == bool(runnable)
        if runnable:
            assert choice.plan.seconds == min(runnable.values())
        else:
            assert choice.plan.refusal.startswith("no method can run it: ")


@pytest.mark.parametrize("N, moments", [(2, 1), (3, 2), (5, 1), (6, 2), (7, 3), (12, 1)])
def test_auto_gives_the_explicit_methods_table(N, moments):
    method = routes.choose(N, moments).method
    auto = routes.table_run("auto", N, moments)
    assert auto == routes.table_run(method, N, moments)
    assert auto[1] == mean_W(N)  # and the order-ideal DP's, an independent route when auto chose another


def test_engine_options_restrict_auto_to_the_methods_taking_them():
    assert routes.choose(8, workers=1).method == "pfaffian"
    with pytest.raises(ArgumentError, match="method='pfaffian' only"):
        routes.table_plan("fast", 8, workers=1)


@pytest.mark.parametrize("method, N, moments", [("fast", 6, 3), ("thesis", 4, 2), ("maps", 5, 2), ("lambda", 5, 1),
                                                 ("pfaffian", 6, 1)])
def test_an_executor_runs_the_independent_tasks_with_the_same_result(method, N, moments):
    ticks = []
    with ThreadPoolExecutor(2) as pool:
        tables = routes.table_run(method, N, moments, progress=ticks.append, executor=pool)
    assert tables == routes.table_run(method, N, moments)
    assert sum(ticks) == pytest.approx(routes.table_plan(method, N, moments).ticks)


def test_the_crt_bound_is_product_greater_than_bound():
    """x <= bound < product: crt gives back x; at bound = product one more prime is needed."""
    primes = primes_for_bound(10**12)
    product = 1
    for p in primes:
        product *= p
    assert product > 10**12 and primes_for_bound(product - 1) == primes
    assert len(primes_for_bound(product)) == len(primes) + 1  # x = product would read as 0 with these primes
    for x in (0, 1, product - 1):
        assert crt([x % p for p in primes], primes) == x == crt_many([[x % p for p in primes]], primes)[0]
    assert crt([product % p for p in primes], primes) == 0  # why the product must exceed the bound


@given(st.integers(0, 10**60))
def test_crt_many_equals_crt(x):
    primes = primes_for_bound(x)
    assert crt_many([[x % p for p in primes]], primes) == [crt([x % p for p in primes], primes)] == [x]


def test_map_counting_and_recursions_import_no_circle():
    def imports(path):
        tree = ast.parse((ROOT / path).read_text())
        return {node.module for node in ast.walk(tree) if isinstance(node, ast.ImportFrom) and node.module}

    assert "map_counting" not in imports("exact/thesis/recursions.py")
    assert "recursions" in imports("exact/thesis/map_counting.py")


def test_the_command_line_computes_no_cross_check():
    source = (ROOT / "src/forcenet/cli/table.py").read_text()
    assert "compare(" not in source and "ExactSampler" not in source and "SECONDS_PER_VALUE" not in source
