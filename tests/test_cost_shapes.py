"""The shapes of cost models refitted against measured runs (issue 53: estimates within 1.5x of the actual).

No timing runs here: each test pins a model's structure to the measured ratios recorded in
``notes/benchmarks.md`` ("Estimates against the actual"), so a model that drifts from the measured shape fails
while the machine's speed does not matter. ``benchmarks/estimates_vs_actual.py`` measures the plans again.
"""

from __future__ import annotations

import math

import pytest

from forcenet.exact.triangle.de_bruijn.floor import floor_prime_seconds
from forcenet.exact.triangle.staircase import free_force_count

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
