"""The edge of the lattice directions (notes/scaling_limit.md Secs. 1 and 5): closed forms, two routes, exact data."""

import json
import pathlib
from fractions import Fraction

import mpmath
import numpy as np
import pytest
import sympy
from hypothesis import given, settings
from hypothesis import strategies as st

from forcenet.cli import main
from forcenet.exact.limit_shape.closed_forms import (
    bulk_edge_coefficient as bulk_edge_expr,
)
from forcenet.exact.limit_shape.closed_forms import (
    edge_density_coefficient,
    kesten_mckay_edge_coefficient,
    lattice_direction_limit,
)
from forcenet.exact.limit_shape.closed_forms import (
    edge_scale as edge_scale_expr,
)
from forcenet.numeric.limit_shape.edge import (
    EDGE_EXPONENT,
    bulk_edge_coefficient,
    edge_amplitude,
    edge_scale,
    edge_sd_amplitude,
    tracy_widom_moments,
)
from forcenet.numeric.limit_shape.surface import bulk_response, lattice_response, level_curve_slope

DIGEST = pathlib.Path(__file__).resolve().parents[1] / "notes" / "data" / "lattice_columns.json"


def test_two_routes_to_the_edge_density_agree_symbolically():
    # level curves of the Pittel-Romik surface vs the floor's arcsine law compressed freely (Kesten-McKay)
    z = sympy.Symbol("z", positive=True)
    assert sympy.simplify(kesten_mckay_edge_coefficient(z) - edge_density_coefficient(z)) == 0
    for q in (sympy.Rational(1, 3), sympy.Rational(1, 2), sympy.Rational(7, 9)):  # c = A^(-2/3)
        assert sympy.simplify(edge_scale_expr(q) ** 3 * edge_density_coefficient(q) ** 2 - 1) == 0


@settings(max_examples=8, deadline=None)
@given(st.integers(1, 48).map(lambda k: Fraction(k, 49)))
def test_edge_density_from_the_level_curve_slope(q):
    # dj/ds = (N/2) dh_s/ds near the end of the level curves, divided by N sqrt(s - e) / pi, tends to A(z)
    with mpmath.workdps(60):
        z = mpmath.mpf(q.numerator) / q.denominator
        e = (1 - mpmath.sqrt(z * (2 - z))) / 2
        y = mpmath.mpf(10) ** -30
        numeric = level_curve_slope(e + y, z - 1, dps=50) / 2 * mpmath.pi / mpmath.sqrt(y)
        closed = mpmath.mpf(str(sympy.N(edge_density_coefficient(sympy.Rational(q.numerator, q.denominator)), 50)))
        assert abs(numeric / closed - 1) < mpmath.mpf(10) ** -25
        # the edge itself is the lattice-direction limit
        assert abs(e - lattice_response(z, dps=50)) < mpmath.mpf(10) ** -45
        limit = sympy.N(lattice_direction_limit(sympy.Rational(q.numerator, q.denominator)), 50)
        assert abs(e - mpmath.mpf(str(limit))) < mpmath.mpf(10) ** -45


@settings(max_examples=10, deadline=None)
@given(st.fractions(min_value=Fraction(1, 1000), max_value=Fraction(999, 1000), max_denominator=10**6))
def test_numeric_edge_scale_and_bulk_coefficient_equal_the_closed_forms(q):
    zq = sympy.Rational(q.numerator, q.denominator)
    for numeric, closed in ((edge_scale, edge_scale_expr), (bulk_edge_coefficient, bulk_edge_expr)):
        value = numeric(q, dps=40)
        with mpmath.workdps(50):
            assert abs(value - mpmath.mpf(str(sympy.N(closed(zq), 50)))) < mpmath.mpf(10) ** -37 * abs(value)


def test_tracy_widom_moments_match_the_literature():
    # Bornemann (2010), Table 1 (16 digits): E chi = -1.7710868074116017, Var chi = 0.8131947928329578
    mean, var = tracy_widom_moments(15)
    assert abs(mean - mpmath.mpf("-1.7710868074116017")) < 1e-14
    assert abs(var - mpmath.mpf("0.8131947928329578")) < 1e-14


@pytest.mark.slow
def test_tracy_widom_moments_converge_with_the_quadrature():
    low, high = tracy_widom_moments(22), tracy_widom_moments(30)
    for a, b in zip(low, high):
        assert abs(a - b) < mpmath.mpf(10) ** -21


@pytest.mark.parametrize("z", ["0.25", "0.5", "0.75"])
def test_bulk_response_diverges_like_the_inverse_cube_root_at_the_lattice_direction(z):
    # G(x, z) (z - |x|)^(1/3) -> C(z); the relative error falls like (z - |x|)^(2/3) (the next term of h_a - |u|)
    C = bulk_edge_coefficient(z, dps=30)
    errors = []
    for k in (6, 9, 12):
        delta = mpmath.mpf(10) ** -k
        with mpmath.workdps(40):
            x = -mpmath.mpf(z) + delta
            G = bulk_response(x, z, dps=30)
            errors.append(abs(G * mpmath.cbrt(delta) / C - 1))
    assert errors[2] < 1e-7
    for a, b in zip(errors, errors[1:]):
        assert 10 ** 1.5 < a / b < 10 ** 2.5  # (10^3)^(2/3) = 100 per step
    # not the (z - |x|)^(-1/2) of the old note: N <W> grows by 10^(1/3) per decade of z - |x|
    g6, g9 = (bulk_response(mpmath.mpf(z) * -1 + mpmath.mpf(10) ** -k, z, dps=30) for k in (6, 9))
    assert abs(g9 / g6 - 10) < 1e-2  # three decades: a factor 10 (not 10^(3/2) = 31.6)


def _deviations(z):
    data = json.loads(DIGEST.read_text())["columns"]
    Ns = np.array(sorted(int(n) for n in data), dtype=float)
    devs = []
    for N in Ns:
        i = round(z * N)
        devs.append(float(mpmath.mpf(data[str(int(N))]["W_i1"][i - 1]) - lattice_response(mpmath.mpf(i) / int(N), dps=30)))
    return Ns, np.array(devs)


@pytest.mark.parametrize("z", [0.25, 0.5, 0.75])
def test_the_amplitude_is_what_the_exact_columns_fit(z):
    # exact <W_(i,1)>, N = 32..160 (the digest): a free fit of a N^(-2/3) + four analytic-looking terms
    # brackets the derived amplitude with the four-term fit (which approaches from below)
    Ns, devs = _deviations(z)
    predicted = float(edge_amplitude(z, dps=15))
    powers = [-2 / 3, -1, -4 / 3, -5 / 3, -2]

    def fitted(k):
        A = np.array([Ns**p for p in powers[:k]]).T / devs[:, None]
        return np.linalg.lstsq(A, np.ones_like(devs), rcond=None)[0][0]

    four, five = fitted(4), fitted(5)
    assert four < predicted < five
    assert abs(five / predicted - 1) < 0.02

    # the amplitude fixed, the next four orders fitted: residual ~1e-6, and a 5 % wrong amplitude fits 4x worse
    def residual(amplitude):
        rest = devs - amplitude * Ns ** (-2 / 3)
        A = np.array([Ns**p for p in powers[1:]]).T / devs[:, None]
        coef = np.linalg.lstsq(A, rest / devs, rcond=None)[0]
        return float(np.sqrt(np.mean((rest / devs - A @ coef) ** 2)))

    best = residual(predicted)
    assert best < 5e-6
    assert residual(0.95 * predicted) > 2.5 * best and residual(1.05 * predicted) > 2.5 * best


def test_cli_reports_the_edge_law(capsys):
    assert main(["limit", "--x", "0.5", "--z", "0.5", "--format", "json", "--dps", "15"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["edge_exponent"] == "2/3" == str(EDGE_EXPONENT)
    assert data["edge_amplitude"] == mpmath.nstr(edge_amplitude("0.5", dps=15), 15)
    assert data["edge_sd_amplitude"] == mpmath.nstr(edge_sd_amplitude("0.5", dps=15), 15)
    assert main(["limit", "--x", "0.1", "--z", "0.5", "--format", "json", "--dps", "15"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["edge_exponent"] is None and data["edge_amplitude"] is None
    assert main(["limit", "--x", "-0.5", "--z", "0.5", "--dps", "12"]) == 0
    assert "N^(-2/3)" in capsys.readouterr().out


def test_edge_law_refuses_the_ends():
    for z in (0, 1, "1.5"):
        with pytest.raises(ValueError, match="z="):
            edge_amplitude(z, dps=10)
    with pytest.raises(ValueError, match="dps"):
        tracy_widom_moments(61)


def _gt_volume(top):
    """Volume of the Gelfand-Tsetlin polytope with top row ``top`` (sympy symbols), by nested integration."""
    n = len(top)
    levels = [list(top)]
    variables = []
    for m in range(n - 1, 0, -1):
        row = [sympy.Symbol(f"x_{m}_{k}") for k in range(m)]
        variables.append([(row[k], levels[-1][k], levels[-1][k + 1]) for k in range(m)])
        levels.append(row)
    integrand = sympy.Integer(1)
    for bounds in reversed(variables):  # innermost level first
        for var, lo, hi in bounds:
            integrand = sympy.integrate(integrand, (var, lo, hi))
    return sympy.factor(integrand)


def test_given_the_floor_the_rows_above_are_a_uniform_gelfand_tsetlin_pattern():
    # the floor's marginal density is the GT volume prod_{j<k} (l_k - l_j) / prod_{k<n} k!: checked by integration ...
    for n in (3, 4):
        top = sympy.symbols(f"l0:{n}")
        vandermonde = sympy.prod([top[k] - top[j] for j in range(n) for k in range(j + 1, n)])
        norm = sympy.prod([sympy.factorial(k) for k in range(1, n)])
        assert sympy.simplify(_gt_volume(top) - vandermonde / norm) == 0
    # ... so the floor is the beta = 1 Legendre ensemble: its Selberg integral is the ensemble's volume (4.1)
    from forcenet.exact.triangle.staircase import normalization

    half = sympy.Rational(1, 2)
    for N in range(3, 13):
        n = N - 1
        selberg = sympy.prod([sympy.gamma(1 + j * half) ** 2 * sympy.gamma(1 + (j + 1) * half)
                              / (sympy.gamma(2 + (n + j - 1) * half) * sympy.gamma(1 + half)) for j in range(n)])
        ordered = selberg / sympy.factorial(n) / sympy.prod([sympy.factorial(k) for k in range(1, n)])
        assert sympy.simplify(ordered - sympy.Rational(normalization(N).numerator, normalization(N).denominator)) == 0


@pytest.mark.parametrize("dps", [59, 60])
def test_the_edge_amplitudes_take_every_precision_they_offer(dps, monkeypatch):
    """``dps`` up to 60 (the face's limit): the amplitudes ask the Tracy-Widom moments for 2 guard digits more,
    62, which the public ``tracy_widom_moments`` refuses; they were refused as ``dps=62`` (a number the user did
    not give). The quadrature itself is held by the test above; here it is replaced by its digits at 60."""
    from forcenet.numeric.limit_shape import edge

    mean, variance = edge.tracy_widom_moments(15)
    asked = []

    def moments(digits):
        asked.append(digits)
        return mpmath.nstr(mean, 15), mpmath.nstr(variance, 15)

    monkeypatch.setattr(edge, "_tw_moments", moments)
    assert mpmath.almosteq(edge_amplitude("0.3", dps=dps), edge_amplitude("0.3", dps=15), 1e-13)
    assert asked[0] == dps + 2
