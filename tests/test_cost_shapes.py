"""The shapes of cost models refitted against measured runs (issue 53: estimates within 1.5x of the actual).

No timing runs here: each test pins a model's structure to the measured ratios recorded in
``notes/benchmarks.md`` ("Estimates against the actual"), so a model that drifts from the measured shape fails
while the machine's speed does not matter. ``benchmarks/estimates_vs_actual.py`` measures the plans again.
"""

from __future__ import annotations

import dataclasses
import math

import pytest

from forcenet.contact_network_engines import KERNEL_CALL_SECONDS
from forcenet.contact_networks import network_plan
from forcenet.exact.contact_network.geometries import triangle
from forcenet.exact.triangle.de_bruijn.floor import floor_prime_seconds
from forcenet.exact.triangle.de_bruijn.layers import layer_prime_seconds
from forcenet.exact.triangle.staircase import free_force_count
from forcenet.numeric.contact_network import hit_and_run
from forcenet.numeric.contact_network.hit_and_run import HitAndRun
from forcenet.numeric.force_chains.engines import (
    DEFAULTS,
    WORKER_START_SECONDS,
    HeatBathEngine,
    ScalingRequest,
    UnionFindEngine,
    analysis_seconds,
    lattice_for,
)

# CPU seconds of one prime of the floor's every-load route, measured 2026-12-06 (benchmarks/estimates_vs_actual.py's
# session; /tmp scripts timing floor_prime_residues(N, p, grains=True) after a warm-up call)
FLOOR_GRAINS_PRIME = {16: 0.034, 24: 0.415, 32: 2.987, 40: 14.359}


def test_the_floor_model_grows_with_N_as_the_measured_primes():
    """The ratio of a prime at N = 40 to one at N = 16 (422 measured) within 15 %; each size's ratio to N = 24
    too. The old constants (pivot 66 ns, row 0.77 ns) gave 328: the pivot's share was three times too large."""
    model = {N: floor_prime_seconds(N, grains=True) for N in FLOOR_GRAINS_PRIME}
    for N in (16, 32, 40):
        measured = FLOOR_GRAINS_PRIME[N] / FLOOR_GRAINS_PRIME[24]
        assert model[N] / model[24] == pytest.approx(measured, rel=0.15), N
    assert model[40] / model[16] == pytest.approx(FLOOR_GRAINS_PRIME[40] / FLOOR_GRAINS_PRIME[16], rel=0.15)


def test_the_floor_model_is_nodes_times_pairs_times_a_quadratic_in_the_order():
    """One bordered Pfaffian per node of half the grid and per pair of fugacities, each ``a n^2 + b n``: the
    measured cost per Pfaffian grows as n^1.49 from N = 16 to 40; the old model's as n^1.22 (its pivot term
    ``b n`` too heavy)."""
    def per_pfaffian(N: int) -> float:
        n, d = N - 1, free_force_count(N)
        return floor_prime_seconds(N, grains=True) / ((d // 2 + 1) * (d + 3) * ((n + 2) // 2))

    exponent = math.log(per_pfaffian(40) / per_pfaffian(16)) / math.log(39 / 15)
    assert 1.4 < exponent < 1.6


# CPU seconds of the default scaling runs' blocks per size, measured 2026-12-06 (engines.block_task after a warm-up)
HEAT_BATH_BLOCKS = {12: 0.06, 16: 0.09, 24: 0.16, 32: 0.42, 48: 1.17, 64: 3.04}


def _one_size(model: str, L: int) -> ScalingRequest:
    sizes, samples = DEFAULTS[model]
    k = samples[sizes.index(L)]
    return ScalingRequest(model, (L, L, L), (k, k, k), seed=0, lattice="square", thresholds=600, replicas=0, blocks=32)


def test_the_heat_bath_model_grows_with_L_as_the_measured_blocks():
    """The default sizes' blocks: L = 64 over L = 32 (7.2 measured) and over L = 24 (19) within 20 %; the old
    constants (5e7 moves/s, 6e6 bonds/s) gave 8.7 and 25."""
    engine = HeatBathEngine()
    model = {L: engine.seconds(_one_size("q-microcanonical", L)) for L in HEAT_BATH_BLOCKS}
    for L in (24, 32, 48):
        assert model[64] / model[L] == pytest.approx(HEAT_BATH_BLOCKS[64] / HEAT_BATH_BLOCKS[L], rel=0.2), L


def test_a_scaling_plan_is_its_blocks_then_the_analysis_per_replica_and_size():
    """The structure: the blocks' seconds over the workers, the analysis by replicas and sizes, the workers' start;
    the union-find blocks cost the same per bond whatever the model (measured: 1.0e-7 CPU s per bond for
    percolation and the independent q-model alike)."""
    for model in ("percolation", "q-independent"):
        engine, (sizes, samples) = UnionFindEngine(model), DEFAULTS[model]
        base = ScalingRequest(model, sizes, samples, seed=0, lattice="square", thresholds=600, replicas=0, blocks=32)
        bonds = sum(lattice_for(model, "square", L).bonds * k for L, k in zip(sizes, samples))
        assert engine.seconds(base) == pytest.approx(bonds * engine.seconds(base) / bonds)
        for workers, replicas in ((1, 0), (2, 0), (1, 100), (4, 50)):
            request = dataclasses.replace(base, workers=workers, replicas=replicas)
            assert engine.plan(request).seconds == pytest.approx(
                engine.seconds(base) / workers + analysis_seconds(len(sizes), replicas)
                + (WORKER_START_SECONDS if workers > 1 else 0.0))
    per_bond = {model: UnionFindEngine(model).seconds(_one_size(model, DEFAULTS[model][0][-1]))
                / (3 * lattice_for(model, "square", DEFAULTS[model][0][-1]).bonds * DEFAULTS[model][1][-1])
                for model in ("percolation", "q-independent")}
    assert per_bond["percolation"] == pytest.approx(per_bond["q-independent"])


# CPU seconds of one prime of every load of layer N/2, measured 2026-12-06 (layer_prime_residues after a warm-up)
LAYER_GRAINS_PRIME = {24: 1.947, 32: 13.241}


def test_the_layers_model_grows_with_N_as_the_measured_primes():
    """Layer N/2, every load: a prime at N = 32 over one at N = 24 (6.8 measured) within 20 %."""
    model = {N: layer_prime_seconds(N, N // 2, grains=True) for N in LAYER_GRAINS_PRIME}
    assert model[32] / model[24] == pytest.approx(LAYER_GRAINS_PRIME[32] / LAYER_GRAINS_PRIME[24], rel=0.2)


def test_a_sampled_network_plan_prices_its_sweeps_and_only_the_sparse_routes_calls(monkeypatch):
    """The dense and projected routes call the compiled sweeps once per chunk of recorded samples (measured: the
    triangle N = 5, 200000 samples in 0.21 s CPU, planned 0.21 s; per recorded sample they took 1.85 s): the plan
    grows by the sweeps alone, twice as fast when thinned by 2. The sparse route still calls them per recorded
    sample (and per batch of directions), and its plan counts those calls."""
    pytest.importorskip("PyNormaliz")
    net = triangle(5).network
    per = HitAndRun(net).sweep_seconds()

    def plans() -> dict[tuple[int, int], float]:
        return {(k, thin): network_plan(net, samples=k, thin=thin, burn_in=0, seed=0).seconds
                for k in (20000, 40000) for thin in (1, 2)}

    dense = plans()
    assert dense[40000, 1] - dense[20000, 1] == pytest.approx(20000 * per, rel=0.05)
    assert dense[20000, 2] - dense[20000, 1] == pytest.approx(20000 * per, rel=0.05)
    monkeypatch.setattr(hit_and_run, "SPARSE_FROM", 1)
    monkeypatch.setattr(hit_and_run, "BASIS_BYTES", 0)  # no basis fits: fresh directions
    sparse = plans()
    calls = 20000 * KERNEL_CALL_SECONDS
    assert sparse[40000, 1] - sparse[20000, 1] > calls
    assert sparse[20000, 2] - sparse[20000, 1] > calls