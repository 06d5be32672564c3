"""The floor's load laws by de Bruijn Pfaffians (exact/triangle/de_bruijn/floor.py) against the order-ideal DP.

Two routes: the DP counts tableaux level by level over the order ideals; the
Pfaffian route integrates the Legendre ensemble's gap probability over a grid
of (s, w) nodes modulo word-size primes.  They share nothing but the count.
"""

import json
from concurrent.futures import ThreadPoolExecutor
from fractions import Fraction

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from forcenet.core.errors import ArgumentError
from forcenet.exact.triangle.de_bruijn.floor import (
    MAX_FLOOR_N,
    floor_gap_laws,
    floor_plan,
    floor_pooled_gap_law,
    floor_prime_residues,
    floor_prime_seconds,
    floor_primes,
)
from forcenet.exact.triangle.distribution import layer_pieces, layer_pieces_from_gaps, moment_from_gaps, pool_gaps
from forcenet.exact.triangle.gaps import layer_gap_counts
from forcenet.exact.triangle.law_routes import layer_gap_law, layer_route, single_grain_gap_law, single_grain_route
from forcenet.exact.triangle.staircase import count, dimension

pytestmark = pytest.mark.usefixtures("de_bruijn_compiled")


@settings(max_examples=8)
@given(st.integers(2, 10))
def test_pooled_floor_law_equals_the_dp(N):
    assert floor_pooled_gap_law(N, workers=1) == pool_gaps(layer_gap_counts(N, N))


@settings(max_examples=6)
@given(st.integers(2, 9))
def test_every_floor_load_law_equals_the_dp(N):
    laws = floor_gap_laws(N, workers=1)
    assert sorted(laws) == list(range(1, N + 1))
    assert [laws[j] for j in range(1, N + 1)] == list(layer_gap_counts(N, N))


def test_the_fugacity_route_sums_to_the_pooled_route_beyond_the_fast_dp():
    """N = 13: zeta = 0..n interpolated against zeta = 1 alone, and the exact structure of the floor."""
    N = 13
    laws = floor_gap_laws(N, workers=1)
    assert pool_gaps(laws[j] for j in range(1, N + 1)) == floor_pooled_gap_law(N, workers=1)
    d = dimension(N)
    assert all(laws[j] == laws[N + 1 - j] for j in range(1, N + 1))  # the mirror symmetry
    assert laws[1].counts[1] == count(N)  # the corner: T(1, 1) = 1, W_{N,1} ~ Beta(1, d)
    assert all(law.counts[1] == 0 for j, law in laws.items() if 1 < j < N)  # a cell lies between two diagonal cells
    assert sum(sum(g * c for g, c in enumerate(law.counts)) for law in laws.values()) == (d + 1) * count(N)


def test_one_prime_residues_match_the_exact_law():
    N = 9
    law = floor_pooled_gap_law(N, workers=1)
    for p in (floor_primes(N)[0], 4194167):
        assert floor_prime_residues(N, p)[0].tolist() == [c % p for c in law.counts]


def test_executor_and_checkpoint_give_the_same_law(tmp_path):
    N = 12
    plain = floor_pooled_gap_law(N, workers=1)
    with ThreadPoolExecutor(2) as pool:
        assert floor_pooled_gap_law(N, executor=pool) == plain
    ticks = []
    assert floor_pooled_gap_law(N, workers=1, checkpoint=tmp_path, progress=ticks.append) == plain
    assert len(ticks) == len(floor_primes(N)) and any(tmp_path.iterdir())
    assert floor_pooled_gap_law(N, workers=1, checkpoint=tmp_path) == plain  # from the records


def test_layer_route_picks_the_faster_runnable_route():
    assert layer_route(40, 40)[0] == "floor" and layer_route(8, 8)[0] == "ideals"
    route, plan = layer_route(40, 39)  # above the floor beyond the DP: the layer's de Bruijn Pfaffians
    assert route == "layers" and plan.runnable and "de Bruijn" in plan.what
    assert layer_gap_law(8, 8, "floor") == layer_gap_law(8, 8, "ideals")
    with pytest.raises(ArgumentError, match="route='floor' is out of range for layer 7"):
        layer_gap_law(8, 7, "floor")
    assert floor_plan(MAX_FLOOR_N + 1).refusal.startswith(f"N={MAX_FLOOR_N + 1} is out of range for the floor route")
    # n + 1 fugacities in (n + 2)/2 pairs, one bordered Pfaffian each
    assert floor_prime_seconds(30, grains=True) == pytest.approx(15 * floor_prime_seconds(30))
    assert floor_plan(30, grains=True).seconds > floor_plan(30).seconds


def test_single_grain_route_takes_the_floor_for_a_floor_load():
    assert single_grain_route(36, (36, 18))[0] == "floor"
    assert single_grain_route(12, (12, 6))[0] == "ideals"
    assert single_grain_gap_law(9, (9, 4), "floor") == single_grain_gap_law(9, (9, 4), "ideals")
    with pytest.raises(ArgumentError, match="route='floor' is not a route to grain"):
        single_grain_gap_law(9, (8, 4), "floor")


def test_layer_pieces_from_gaps_is_layer_pieces():
    assert layer_pieces_from_gaps(pool_gaps(layer_gap_counts(7, 7)), 7) == layer_pieces(7, 7)


def test_cli_layer_takes_the_floor_route_beyond_the_dp(cli):
    """N = 19: the plans choose the Pfaffians; the density is the DP's (N = 19 by the DP: about a minute, so the
    check is against the Pfaffian law's own exact second moment and the normalizations)."""
    code, out, _ = cli(["dist", "--N", "19", "--layer", "19", "--format", "json"])
    assert code == 0 and layer_route(19, 19)[0] == "floor"
    data = json.loads(out)
    (piece,) = data["pieces"]
    coeffs = [Fraction(c) for c in piece["density"]]

    def moment(k):  # Integral_0^19 f^k P(f) df, exactly
        return sum(c * Fraction(19) ** (m + k + 1) / (m + k + 1) for m, c in enumerate(coeffs))

    assert moment(0) == 1 and moment(1) == 1
    assert moment(2) == moment_from_gaps(floor_pooled_gap_law(19), 2) * 19 * 19

@pytest.mark.slow
@pytest.mark.parametrize("N", [14, 16, 18])
def test_pooled_floor_law_equals_the_dp_slow(N):
    assert floor_pooled_gap_law(N) == pool_gaps(layer_gap_counts(N, N))


@settings(max_examples=20)
@given(st.integers(1, 9), st.integers(0, 4194300), st.integers(0, 4194300), st.integers(0, 4194300))
def test_one_bordered_elimination_gives_both_fugacities(n, s, t, zeta):
    """Pf X(+-zeta) = Pf Y (1 -+ zeta S) (the pair kernel) against two direct Pfaffians with pivoting."""
    import numpy as np

    from forcenet.exact.triangle.de_bruijn.floor import de_bruijn_constants
    from forcenet.exact.triangle.de_bruijn.floor_kernels import fill, fill_pair, pfaffian_pair
    from forcenet.exact.triangle.residues import pfaffian_mod

    p = 4194301
    C, iota = de_bruijn_constants(n, p)
    size = n + n % 2
    direct = []
    for z in (zeta, (p - zeta) % p):
        A = np.zeros((size, size))
        fill(A, n, size, float(s), float(t), float(z), C, iota, np.empty(2 * n + 1), np.empty(2 * n + 1), p, 1 / p, True)
        direct.append(int(pfaffian_mod(A, p)))
    M = np.zeros((size + 2, size + 2))
    fill_pair(M, n, float(s), float(t), float(zeta * zeta % p), C, iota, np.empty(2 * n + 1), np.empty(2 * n + 1), p, 1 / p)
    pf, S, ok = pfaffian_pair(M, size, p, 1 / p)
    if ok:  # a vanishing pivot of Y sends the kernel to the pivoting fallback
        assert [int(pf) * (1 - zeta * int(S)) % p, int(pf) * (1 + zeta * int(S)) % p] == direct


def test_dist_floor_checkpoints_and_refuses_them_elsewhere(cli, tmp_path):
    """--checkpoint on the floor's route: a rerun reuses every prime and prints the same bytes; on the DP it is refused."""
    ck = tmp_path / "ck"
    code, first, err = cli(["dist", "--N", "19", "--layer", "19", "--format", "json", "--checkpoint", str(ck)])
    assert code == 0 and "reused 0 of" in err
    code, again, err = cli(["dist", "--N", "19", "--layer", "19", "--format", "json", "--checkpoint", str(ck)])
    assert code == 0 and again == first and "computed 0" in err
    code, plain, _ = cli(["dist", "--N", "19", "--layer", "19", "--format", "json", "--no-checkpoint"])
    assert code == 0 and plain == first
    code, out, err = cli(["dist", "--N", "12", "--layer", "12", "--checkpoint", str(tmp_path / "other")])
    assert code == 2 and out == "" and "--checkpoint applies to the de Bruijn Pfaffians of a layer" in err
    assert not (tmp_path / "other").exists()
    with pytest.raises(ArgumentError, match="checkpoint"):
        single_grain_gap_law(9, (9, 4), "ideals", checkpoint=tmp_path)
    with pytest.raises(ArgumentError, match="belong to the Pfaffian routes"):
        layer_gap_law(9, 9, "ideals", checkpoint=tmp_path)


@pytest.mark.slow
def test_floor_laws_agree_with_the_exact_sampler(against_the_sampler):
    """Every floor load's <W^2> and P(W <= <W>) at N = 28 against 20000 exact samples (alpha = 1e-3)."""
    N = 28
    result = against_the_sampler(floor_gap_laws(N), N, N)
    assert result.passed, result.summary()
