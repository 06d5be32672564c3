"""Issue 56: the finite-size scaling's estimate (``forcenet scaling``, ``forcenet.scaling_plan``) within 1.5x.

The plan was 3x off: the heat bath's moves planned at 5e7 a second where the kernel does ~2.4e8 (4-5x high for
the microcanonical q-model), the cluster pass at 6e6 bonds a second where it does ~1.0-1.3e7, the bootstrap
at 0.02 s per replica and size (2-3x high) and the collapse fit (~1 s, the whole of a small run) not at all.
The model is now measured (notes/benchmarks.md); here it is held to the CPU seconds of small runs (in this
process: ``workers=1``), with a factor 2 of room for a loaded machine.
"""

from __future__ import annotations

import time

import pytest

import forcenet
from forcenet.numeric.force_chains.engines import WORKER_START_SECONDS, analysis_seconds


def test_the_plan_counts_the_fit_and_the_bootstrap():
    """A run with no bootstrap still fits the collapse (a fixed part of every run); each replica adds its refit."""
    small = forcenet.scaling_plan("percolation", sizes=(8, 12, 16), samples=16, replicas=0)
    assert small.cost.seconds >= analysis_seconds(3, 0) > 0.5
    more = forcenet.scaling_plan("percolation", sizes=(8, 12, 16), samples=16, replicas=100)
    assert more.cost.seconds - small.cost.seconds == pytest.approx(analysis_seconds(3, 100) - analysis_seconds(3, 0))
    wide = forcenet.scaling_plan("percolation", sizes=(8, 12, 16, 24, 32, 48), samples=16, replicas=100)
    assert analysis_seconds(6, 100) > analysis_seconds(3, 100) and wide.cost.seconds > more.cost.seconds


CASES = [
    ("percolation", (16, 32, 64), 64, 10),
    ("q-microcanonical", (16, 24, 32), 48, 0),
]


@pytest.mark.slow
@pytest.mark.parametrize("model, sizes, samples, replicas", CASES)
def test_the_estimate_follows_the_cpu_seconds(model, sizes, samples, replicas):
    forcenet.scaling(model, sizes=(8, 12, 16), samples=32, replicas=0, blocks=4)  # the kernels loaded (or compiled)
    plan = forcenet.scaling_plan(model, sizes=sizes, samples=samples, replicas=replicas)
    start = time.process_time()
    plan.run()
    spent = time.process_time() - start
    assert 0.5 < spent / plan.cost.seconds < 2.0, f"{model}: planned {plan.cost.seconds:.2f} s, spent {spent:.2f} s"


def test_local_workers_share_the_blocks_and_pay_their_start_up():
    one = forcenet.scaling_plan("percolation", workers=1).cost.seconds
    two = forcenet.scaling_plan("percolation", workers=2).cost.seconds
    analysis = analysis_seconds(7, 100)
    assert two == pytest.approx((one - analysis) / 2 + analysis + WORKER_START_SECONDS)
