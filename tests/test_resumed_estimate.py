"""Issue 56: a resumed run's first announcement counts every fixed part the run still pays.

A run over primes pays, whatever its checkpoint holds, this process's start-up, its workers' start-up (when it
starts a pool) and the Chinese remaindering over all the primes; only the primes still to compute scale.  A run of
one request per layer (the table's higher moments) pays each unfinished layer's own cost: the layers run in order
and cost more with ``i``, so the records an interrupted run leaves are the cheap ones, and discounting the whole
plan by the share of primes held (as before) was ~1.4x low at half of N = 40.  These tests pin the structure on
plans alone (record files planted; nothing is computed).
"""

from __future__ import annotations

import os
from math import ceil

import pytest

import forcenet
from forcenet.core.checkpoints import resumed_plan
from forcenet.core.plan import Plan
from forcenet.exact.triangle.de_bruijn.floor import floor_cost, floor_primes
from forcenet.exact.triangle.de_bruijn.layers import layer_cost
from forcenet.exact.triangle.free_fermion.cost import prime_seconds, route_primes
from forcenet.exact.triangle.free_fermion.route import CRT_SECONDS, mean_plan
from forcenet.exact.triangle.prime_tasks import STARTUP_SECONDS, checkpoint_store
from forcenet.exact.triangle.staircase import dimension, tableau_count


def _plant(store, primes) -> None:
    """Record files for ``primes`` (the plan counts files; their content is checked only when a run loads them)."""
    os.makedirs(store.path, exist_ok=True)
    for p in primes:
        open(store._file(p), "wb").close()


@pytest.mark.parametrize("share", [0.0, 0.25, 0.5, 0.75, 1.0])
def test_a_resumed_tables_plan_keeps_every_fixed_part(share, tmp_path):
    N = 52
    primes = route_primes(N, (dimension(N) + 1) * tableau_count(N))
    held = int(share * len(primes))
    _plant(checkpoint_store(tmp_path, "table", N), primes[:held])  # an interrupted run records the first primes
    full = mean_plan(N, workers=2)
    resumed = forcenet.plan(N, method="pfaffian", checkpoint=tmp_path, memory_bytes=2**34).cost
    todo = len(primes) - held
    workers = 2 if prime_seconds(N) * todo >= 2 * STARTUP_SECONDS else 1
    fixed = STARTUP_SECONDS * (1 + (workers > 1)) + CRT_SECONDS * (N - 1) ** 2 * len(primes) ** 2
    assert f"{held} of {len(primes)} primes recorded" in resumed.what
    assert resumed.seconds - resumed.compile_seconds >= STARTUP_SECONDS + CRT_SECONDS * (N - 1) ** 2 * len(primes) ** 2
    expected = fixed + ceil(todo / workers) * prime_seconds(N)
    assert resumed.seconds - resumed.compile_seconds == pytest.approx(expected, rel=1e-9)
    if 0 < held < len(primes) and workers == 2:  # the fixed part is the full run's: never scaled by the share
        assert resumed.seconds - resumed.compile_seconds > (full.seconds - full.compile_seconds) * todo / len(primes)


def test_a_resumed_moments_plan_counts_each_layers_own_cost(tmp_path):
    """Layers 2..k recorded (an interrupted run's order): the plan is the rest's, layer by layer, not a share."""
    N, k = 12, 7
    primes = floor_primes(N)
    for i in range(2, k + 1):
        _plant(checkpoint_store(tmp_path, "layer-grains", N, layer=i), primes)
    full = forcenet.plan(N, moments=2, method="pfaffian", memory_bytes=2**34).cost
    resumed = forcenet.plan(N, moments=2, method="pfaffian", checkpoint=tmp_path, memory_bytes=2**34).cost
    rest = [layer_cost(N, i, True, 2**34) for i in range(k + 1, N)] + [floor_cost(N, True, 2**34)]
    expected = STARTUP_SECONDS + sum(p.seconds - p.compile_seconds - STARTUP_SECONDS for p in rest)
    held = (k - 1) * len(primes)
    assert f"{held} of {full.ticks} primes recorded" in resumed.what
    assert resumed.seconds - resumed.compile_seconds == pytest.approx(expected, rel=1e-9)
    share = (full.seconds - full.compile_seconds) * (full.ticks - held) / full.ticks
    assert resumed.seconds - resumed.compile_seconds > share  # the held layers were the cheap ones


def test_resumed_plan_keeps_the_fixed_seconds(tmp_path):
    plan = Plan("x", 20.0, 0, 10, "prime")
    _plant(checkpoint_store(tmp_path, "floor", 5), range(101, 106))  # 5 of 10
    assert resumed_plan(plan, tmp_path, 5, ("pfaffian-floor",)).seconds == 10.0
    assert resumed_plan(plan, tmp_path, 5, ("pfaffian-floor",), fixed=STARTUP_SECONDS).seconds == pytest.approx(
        STARTUP_SECONDS + (20.0 - STARTUP_SECONDS) / 2)
