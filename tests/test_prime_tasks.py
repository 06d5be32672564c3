"""The one plan of a run over primes (forcenet.exact.triangle.prime_tasks.primes_plan) and every plan built on it.

Every route over primes (the free-fermion mean, lattice laws and partial sums; the de Bruijn floor and layers; the
moments table; the law routes) plans with the same formula, so an executor's workers count the same way in each
(issue 46: ``forcenet dist --scheduler`` planned as if the cluster were not there).
"""

from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor
from math import ceil

import pytest

from forcenet.exact.triangle import law_routes, pfaffian_table
from forcenet.exact.triangle.de_bruijn.floor import floor_plan, floor_prime_seconds, floor_primes
from forcenet.exact.triangle.de_bruijn.layers import layer_plan, layer_prime_seconds
from forcenet.exact.triangle.free_fermion import fluctuations, partial_sums, route
from forcenet.exact.triangle.prime_tasks import CLIENT_TASK_SECONDS, STARTUP_SECONDS, WORKER_TASK_SECONDS, primes_plan


@pytest.fixture(scope="module")
def pools():
    """Executors of 1, 3 and 8 workers, declared (nothing is submitted: the plans only count them)."""
    from forcenet.core.execution import declare_workers

    made = {k: declare_workers(ThreadPoolExecutor(max_workers=k), k) for k in (1, 3, 8)}
    yield made
    for pool in made.values():
        pool.shutdown()


def _on(per_prime: float, nprimes: int, k: int) -> float:
    """The formula on ``k`` workers of an executor: rounds of a prime plus the scheduler's cost per task."""
    work = max(ceil(nprimes / k) * (per_prime + WORKER_TASK_SECONDS), CLIENT_TASK_SECONDS * nprimes)
    return STARTUP_SECONDS * (1 + (k > 1)) + work


@pytest.mark.parametrize("k", [1, 3, 8])
def test_primes_plan_counts_the_executors_workers(pools, k):
    plan = primes_plan("x", 2.0, 10, 2**20, executor=pools[k])
    assert plan.seconds == pytest.approx(_on(2.0, 10, k))
    assert f"on {k} worker" in plan.what and "ThreadPoolExecutor" in plan.what
    assert plan.nbytes == 2**20  # a cluster's workers hold their share on their own machines
    assert not plan.compiling  # nor do they compile here
    local = primes_plan("x", 2.0, 10, 2**20, workers=k)
    assert local.seconds == pytest.approx(STARTUP_SECONDS * (1 + (k > 1)) + ceil(10 / k) * 2.0)
    assert local.nbytes == k * 2**20


def test_an_undeclared_pool_is_planned_as_one_worker():
    """A pool forcenet did not make and was not told about: its worker count is unknown (no private attribute is
    read), so the plan is the conservative one worker's (the run itself is not throttled)."""
    with ThreadPoolExecutor(max_workers=8) as pool:
        plan = primes_plan("x", 0.5, 40, 10**6, executor=pool)
    assert "on 1 worker" in plan.what


def test_primes_plan_refuses_beyond_memory_and_counts_reused_primes():
    assert not primes_plan("x", 1.0, 4, 2**30, workers=2, memory_bytes=2**30).runnable
    fresh, half = primes_plan("x", 1.0, 8, 1, workers=1), primes_plan("x", 1.0, 8, 1, workers=1, reused=4)
    assert fresh.seconds - half.seconds == pytest.approx(4.0) and half.ticks == fresh.ticks == 8


@pytest.mark.parametrize("k", [1, 3, 8])
def test_the_de_bruijn_plans_count_the_executor_as_the_formula_does(pools, k):
    N = 40
    n = len(floor_primes(N))
    for grains in (False, True):
        plan = floor_plan(N, grains, executor=pools[k])
        assert plan.seconds == pytest.approx(_on(floor_prime_seconds(N, grains), n, k))
        assert f"on {k} worker" in plan.what
        plan = layer_plan(N, 20, grains, executor=pools[k])
        assert plan.seconds == pytest.approx(_on(layer_prime_seconds(N, 20, grains), n, k))
    assert floor_plan(N).seconds != floor_plan(N, executor=pools[k]).seconds


def test_every_plan_over_primes_takes_the_executor(pools):
    """The cluster's workers shorten every route's plan (8 workers against 1), the routing functions' included."""
    one, eight = pools[1], pools[8]
    plans = [
        lambda ex: route.mean_plan(64, executor=ex),
        lambda ex: route.lattice_direction_plan(100, executor=ex),
        lambda ex: partial_sums.partial_sum_moments_plan(40, executor=ex),
        lambda ex: fluctuations.lattice_gap_laws_plan(64, executor=ex),
        lambda ex: pfaffian_table.table_plan(24, 2, executor=ex),
        lambda ex: law_routes.layer_route(40, 40, executor=ex)[1],
        lambda ex: law_routes.layer_route(40, 20, executor=ex)[1],
        lambda ex: law_routes.ensemble_route(40, executor=ex)[1],
        lambda ex: law_routes.single_grain_route(64, (64, 1), executor=ex)[1],
        lambda ex: law_routes.single_grain_route(40, (39, 20), executor=ex)[1],
    ]
    for plan in plans:
        assert plan(eight).seconds < plan(one).seconds


def test_the_routes_choose_with_the_executor(pools):
    """The DP runs here; the Pfaffians on the executor: the same choice, the Pfaffians' plan on its workers."""
    name, plan = law_routes.layer_route(40, 20, executor=pools[3])
    assert name == "layers" and plan.seconds == layer_plan(40, 20, executor=pools[3]).seconds
    assert law_routes.layer_route(12, 12, executor=pools[3])[0] == "ideals"
