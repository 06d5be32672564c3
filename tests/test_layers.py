"""Every layer's load laws by de Bruijn Pfaffians (exact/triangle/de_bruijn/layers.py) against the order-ideal DP.

Two routes: the DP counts tableaux level by level over the order ideals; the
layers' route integrates the floor out twice (a Gelfand-Tsetlin volume as a
determinant, de Bruijn's Pfaffian of it, de Bruijn again against the layer's
Vandermonde) and evaluates the result on a grid modulo primes.  They share
nothing but the count.  The kernel's closed forms are checked against their
defining integrals in sympy.
"""

from concurrent.futures import ThreadPoolExecutor
from fractions import Fraction

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from forcenet.core.errors import ArgumentError
from forcenet.exact.triangle.de_bruijn.floor import floor_primes
from forcenet.exact.triangle.de_bruijn.layers import (
    layer_gap_laws,
    layer_plan,
    layer_pooled_gap_law,
    layer_prime_residues,
    layer_prime_seconds,
    layer_tables,
)
from forcenet.exact.triangle.distribution import pool_gaps
from forcenet.exact.triangle.gaps import contact_gap_counts, grain_gap_counts, layer_gap_counts
from forcenet.exact.triangle.law_routes import (
    floor_contact_gap_law,
    layer_gap_law,
    layer_route,
    single_grain_gap_law,
    single_grain_route,
)
from forcenet.exact.triangle.staircase import count, dimension

pytestmark = pytest.mark.usefixtures("de_bruijn_compiled")


@settings(max_examples=10, deadline=None)
@given(N=st.integers(3, 10), data=st.data())
def test_pooled_layer_law_equals_the_dp(N, data):
    i = data.draw(st.integers(2, N - 1))
    assert layer_pooled_gap_law(N, i, workers=1) == pool_gaps(layer_gap_counts(N, i))


@settings(max_examples=8, deadline=None)
@given(N=st.integers(3, 9), data=st.data())
def test_every_load_of_a_layer_equals_the_dp(N, data):
    i = data.draw(st.integers(2, N - 1))
    laws = layer_gap_laws(N, i, workers=1)
    assert sorted(laws) == list(range(1, i + 1))
    assert [laws[j] for j in range(1, i + 1)] == list(layer_gap_counts(N, i))


def test_every_layer_at_N_11_by_both_routes():
    """All layers of N = 11, pooled: the three-part fugacity combination (every load) sums to the pooled route."""
    N = 11
    for i in range(2, N):
        pooled = layer_pooled_gap_law(N, i, workers=1)
        assert pooled == pool_gaps(layer_gap_counts(N, i))
        if i in (4, 10):
            assert pool_gaps(layer_gap_laws(N, i, workers=1).values()) == pooled


def test_the_structure_of_layer_laws_beyond_the_fast_dp():
    """N = 14, layer 9: the mirror symmetry, the lattice-direction grains against their one-time Pfaffian route,
    the loads summing to the overload."""
    N, i = 14, 9
    d = dimension(N)
    laws = layer_gap_laws(N, i, workers=1)
    assert all(laws[j] == laws[i + 1 - j] for j in range(1, i + 1))
    assert laws[1] == single_grain_gap_law(N, (i, 1), "pfaffian")
    assert sum(sum(g * c for g, c in enumerate(law.counts)) for law in laws.values()) == (d + 1) * count(N)
    assert all(law.counts[1] == 0 for law in laws.values())  # two cells apart on a diagonal: gap >= 2


def test_one_prime_residues_match_the_exact_law():
    N, i = 9, 5
    law = layer_pooled_gap_law(N, i, workers=1)
    for p in (floor_primes(N)[0], 4194167):
        assert layer_prime_residues(N, i, p)[0].tolist() == [c % p for c in law.counts]


@pytest.mark.parametrize("k", [1, 2, 3, 5])
def test_the_kernel_tables_are_their_defining_integrals(k):
    """kappa, L_r, w of layer N - k against sympy: K(x, y) = int int_(p<q) [f_x(p) f_y(q) - f_y(p) f_x(q)],
    f_x(p) = (p - x)_+^(k-1), on x < y; L_r(x) = int int_(p<q) [f_x(p) q^r - p^r f_x(q)]; in a = 1 - x."""
    import sympy as sp

    x, y, pp, q, a, b = sp.symbols("x y p q a b")
    f = lambda var, at: (var - at) ** (k - 1)  # noqa: E731
    t1 = (sp.integrate(f(pp, x), (pp, x, y)) * sp.integrate(f(q, y), (q, y, 1))
          + sp.integrate(f(pp, x) * sp.integrate(f(q, y), (q, pp, 1)), (pp, y, 1)))
    t2 = sp.integrate(f(pp, y) * sp.integrate(f(q, x), (q, pp, 1)), (pp, y, 1))
    K = sp.Poly(sp.expand((t1 - t2).subs({x: 1 - a, y: 1 - b})), a, b)
    N, prime = k + 6, 4194301
    kappa, lam, w, iota = layer_tables(N, N - k, prime)
    mod = lambda c: int(sp.Rational(c).p * pow(int(sp.Rational(c).q), -1, prime) % prime)  # noqa: E731
    assert [mod(K.coeff_monomial(a**al * b ** (2 * k - al))) for al in range(k + 1)] == [int(c) for c in kappa]
    assert K.is_homogeneous and K.total_degree() == 2 * k
    for r in range(k):
        L = sp.expand(sp.integrate(f(pp, x) * sp.integrate(q**r, (q, pp, 1)), (pp, x, 1))
                      - sp.integrate(f(q, x) * sp.integrate(pp**r, (pp, 0, q)), (q, x, 1)))
        La = sp.Poly(sp.expand(L.subs(x, 1 - a)), a)
        assert [mod(La.coeff_monomial(a**g)) for g in range(2 * k + 2)] == [int(c) for c in lam[r]]
    m = N - k - 1
    assert [int(c) for c in w] == [sum(int(kappa[al]) * pow(c + 2 * k - al + 1, -1, prime) for al in range(k + 1))
                                   % prime for c in range(m)]


def test_the_contacts_above_the_floor_equal_the_dp():
    """F5, F6 of layer N - 1 pooled: the uniform position of the floor point between its two neighbours."""
    for N in range(3, 10):
        contacts = contact_gap_counts(N)
        dp = pool_gaps([contacts[(N - 1, j, kind)] for j in range(1, N) for kind in ("F5", "F6")])
        assert floor_contact_gap_law(N) == dp
    N = 8
    law = floor_contact_gap_law(N)
    assert Fraction(law.d * law.counts[1], law.total) / (2 * (N - 1)) == Fraction(4143, 4199)  # P(0), Sec. 6.2
    with pytest.raises(ArgumentError, match="layer N-1's pooled gap law"):
        floor_contact_gap_law(N, pool_gaps(layer_gap_counts(N, N - 2)))
    with pytest.raises(ArgumentError, match="N >= 3"):
        floor_contact_gap_law(2)


@pytest.mark.parametrize("N", [13, 17])
def test_layer_N_minus_1_sum_of_squares_beyond_the_dp(N):
    """sum_j <W_(N-1,j)^2> = 3/(2N - 1) (proved in notes/force_distribution.md Sec. 6.2: the uniform floor point,
    the unitary corner's moments, Aomoto and a loop equation of the Legendre ensemble): the DP's table at N = 7,
    and the Pfaffian route's layer N - 1 law where the test does not run the DP."""
    from forcenet.exact import routes
    from forcenet.exact.triangle.distribution import moment_from_gaps

    assert sum(routes.table_run("fast", 7, 2)[2][5]) == Fraction(3, 13)
    law = layer_pooled_gap_law(N, N - 1, workers=1)
    assert moment_from_gaps(law, 2) * (N - 1) == Fraction(3, 2 * N - 1)


def test_executor_and_checkpoint_give_the_same_law(tmp_path):
    N, i = 12, 7
    plain = layer_pooled_gap_law(N, i, workers=1)
    with ThreadPoolExecutor(2) as pool:
        assert layer_pooled_gap_law(N, i, executor=pool) == plain
    ticks = []
    assert layer_pooled_gap_law(N, i, workers=1, checkpoint=tmp_path, progress=ticks.append) == plain
    assert len(ticks) == len(floor_primes(N)) and any(tmp_path.iterdir())
    assert layer_pooled_gap_law(N, i, workers=1, checkpoint=tmp_path) == plain  # from the records
    other = layer_pooled_gap_law(N, i + 1, workers=1, checkpoint=tmp_path)  # another layer: its own records
    assert other == pool_gaps(layer_gap_counts(N, i + 1))


def test_routes_and_plans():
    assert layer_route(40, 20)[0] == "layers" and layer_route(40, 40)[0] == "floor" and layer_route(10, 5)[0] == "ideals"
    assert single_grain_route(40, (39, 20))[0] == "layers" and single_grain_route(10, (9, 4))[0] == "ideals"
    assert single_grain_gap_law(9, (8, 4), "layers") == grain_gap_counts(9, (8, 4))
    assert layer_gap_law(8, 5, "layers") == layer_gap_law(8, 5, "ideals")
    with pytest.raises(ArgumentError, match="route='layers' is out of range for layer 8"):
        layer_gap_law(8, 8, "layers")
    with pytest.raises(ArgumentError, match="i=8 is out of range"):
        layer_pooled_gap_law(8, 8)
    plan = layer_plan(40, 39)
    assert plan.runnable and plan.unit == "prime" and plan.ticks == len(floor_primes(40))
    assert layer_plan(30, 15, grains=True).seconds > 5 * layer_plan(30, 15).seconds
    assert layer_prime_seconds(40, 20) > layer_prime_seconds(30, 15)


def test_cli_layer_above_the_floor_beyond_the_dp(cli):
    """``forcenet dist --N 20 --layer 19``: the plans choose the layers' Pfaffians; the density integrates to 1 and
    its mean is 1/i (f = i W has mean 1)."""
    import json

    code, out, _ = cli(["dist", "--N", "20", "--layer", "19", "--format", "json", "--quiet"])
    assert code == 0 and layer_route(20, 19)[0] == "layers"
    (piece,) = json.loads(out)["pieces"]
    coeffs = [Fraction(c) for c in piece["density"]]
    hi = Fraction(piece["hi"])
    moment = lambda k: sum(c * hi ** (m + k + 1) / (m + k + 1) for m, c in enumerate(coeffs))  # noqa: E731
    assert moment(0) == 1 and moment(1) == 1


@settings(max_examples=6, deadline=None)
@given(N=st.integers(2, 8), moments=st.integers(2, 4))
def test_moment_tables_by_pfaffians_equal_the_dp(N, moments):
    """``table --method pfaffian --moments s``: every load's gap law, layer by layer, against the order-ideal DP."""
    from forcenet.exact import routes

    assert routes.table_run("pfaffian", N, moments) == routes.table_run("fast", N, moments)


def test_cli_table_second_moments_by_pfaffians(cli, tmp_path):
    """The issue's command at a size the default run affords: mean_W2 equal to the DP's; checkpoints per layer."""
    import json

    ck = tmp_path / "ck"
    code, out, err = cli(["table", "--N", "9", "--method", "pfaffian", "--moments", "2", "--format", "json",
                          "--checkpoint", str(ck)])
    assert code == 0 and "one request per layer" in err
    code, dp, _ = cli(["table", "--N", "9", "--method", "fast", "--moments", "2", "--format", "json"])
    assert json.loads(out)["mean_W2"] == json.loads(dp)["mean_W2"] and json.loads(out)["mean_W"] == json.loads(dp)["mean_W"]
    assert len([p for p in ck.iterdir()]) == 8  # one request per layer 2..9
    code, again, _ = cli(["table", "--N", "9", "--method", "pfaffian", "--moments", "2", "--format", "json",
                          "--checkpoint", str(ck)])
    assert code == 0 and again == out


@settings(max_examples=5, deadline=None)
@given(N=st.integers(2, 9))
def test_the_ensemble_by_pfaffians_is_the_dps(N):
    from forcenet.exact.triangle.law_routes import ensemble_pieces

    assert ensemble_pieces(N, "pfaffians") == ensemble_pieces(N, "ideals")


def _ensemble_moments(out):
    """Integral and mean of the ensemble density in ``dist --format json``'s output, exactly."""
    import json

    total = mean = Fraction(0)
    for piece in json.loads(out)["pieces"]:
        lo, hi = Fraction(piece["lo"]), Fraction(piece["hi"])
        for m, c in enumerate(piece["density"]):
            total += Fraction(c) * (hi ** (m + 1) - lo ** (m + 1)) / (m + 1)
            mean += Fraction(c) * (hi ** (m + 2) - lo ** (m + 2)) / (m + 2)
    return total, mean


def test_cli_ensemble_by_the_pfaffians_is_the_dps_output(cli, tmp_path, monkeypatch):
    """``dist --ensemble`` on the Pfaffians' route (chosen here by hand at N = 8, where the plans pick the DP) prints
    the DP's bytes; checkpoints: one request per layer; the DP refuses --checkpoint."""
    from forcenet.core.plan import Plan
    from forcenet.exact.triangle import law_routes as layers

    code, dp, _ = cli(["dist", "--N", "8", "--ensemble", "--format", "json"])
    assert code == 0 and layers.ensemble_route(8)[0] == "ideals"
    from forcenet.exact import law_registry  # the law's policy asks the route function where it imported it

    monkeypatch.setattr(law_registry, "ensemble_route", lambda N, memory=None, **_: ("pfaffians",
                                                                                  Plan("every layer's Pfaffians", 1.0)))
    ck = tmp_path / "ck"
    code, out, err = cli(["dist", "--N", "8", "--ensemble", "--format", "json", "--checkpoint", str(ck)])
    assert code == 0 and out == dp and "one request per layer" in err
    assert len(list(ck.iterdir())) == 7
    monkeypatch.undo()
    code, _, err = cli(["dist", "--N", "8", "--ensemble", "--checkpoint", str(ck)])
    assert code == 2 and "--checkpoint applies to the de Bruijn Pfaffians" in err


@pytest.mark.slow
def test_cli_ensemble_beyond_the_dps_reach_takes_the_pfaffians(cli, tmp_path):
    """``dist --N 19 --ensemble``: the plans choose every layer's Pfaffians (the DP's 18 passes are slower); the
    density integrates to 1, its mean is 1 (f = i W has mean 1 in every layer)."""
    from forcenet.exact.triangle.law_routes import ensemble_route

    assert ensemble_route(19)[0] == "pfaffians"
    code, out, err = cli(["dist", "--N", "19", "--ensemble", "--format", "json", "--quiet"])
    assert code == 0 and _ensemble_moments(out) == (1, 1)


@pytest.mark.slow
@pytest.mark.parametrize("N", [14, 16])
def test_second_moment_table_by_pfaffians_equals_the_dp_slow(N):
    from forcenet.exact import routes

    assert routes.table_run("pfaffian", N, 2)[2] == routes.table_run("fast", N, 2)[2]


@pytest.mark.slow
@pytest.mark.parametrize("N,i", [(14, 13), (16, 8), (16, 3)])
def test_pooled_layer_law_equals_the_dp_slow(N, i):
    assert layer_pooled_gap_law(N, i) == pool_gaps(layer_gap_counts(N, i))


@pytest.mark.slow
@pytest.mark.parametrize("N,i", [(28, 27), (28, 14)])
def test_layer_laws_agree_with_the_exact_sampler(against_the_sampler, N, i):
    """Every load of layer N - 1 and of the middle layer at N = 28 against 20000 exact samples (alpha = 1e-3)."""
    result = against_the_sampler(layer_gap_laws(N, i), N, i)
    assert result.passed, result.summary()
