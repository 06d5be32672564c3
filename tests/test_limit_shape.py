"""The scaling limit: closed forms, internal consistency, convergence of exact tables."""

import mpmath
import pytest
import sympy
from hypothesis import given, settings
from hypothesis import strategies as st

from forcenet.cli import main
from forcenet.exact import mean_W
from forcenet.exact.limit_shape.closed_forms import (
    bottom_row_limit,
    diagonal_limit,
    edge_profile,
    lattice_direction_limit,
)
from forcenet.numeric.limit_shape.surface import (
    bulk_response,
    lattice_response,
    level_curve,
    level_curve_slope,
    limit_surface,
)

DPS = 40


@given(st.fractions(min_value=0, max_value=1))
def test_lattice_direction_matches_closed_form(z):
    if z == 0:
        return
    with mpmath.workdps(DPS + 10):
        _check_lattice(z)


def _check_lattice(z):
    numeric = lattice_response(mpmath.mpf(z.numerator) / z.denominator, dps=DPS)
    closed = sympy.N(lattice_direction_limit(sympy.Rational(z.numerator, z.denominator)), DPS + 5)
    assert abs(numeric - mpmath.mpf(str(closed))) < mpmath.mpf(10) ** (-DPS + 3)


@given(st.fractions(min_value=-1, max_value=1))
def test_bottom_row_and_diagonal(x):
    with mpmath.workdps(DPS + 10):
        _check_bottom(x)


def _check_bottom(x):
    xq = mpmath.mpf(x.numerator) / x.denominator
    closed = sympy.N(bottom_row_limit(sympy.Rational(x.numerator, x.denominator)), DPS + 5)
    assert abs(bulk_response(xq, 1, dps=DPS) - mpmath.mpf(str(closed))) < mpmath.mpf(10) ** (-DPS + 3)
    t = (1 + xq) / 2  # the diagonal point (t, t): u = 0, v = 2t
    closed_L = sympy.N(diagonal_limit(sympy.Rational(x.numerator + x.denominator, 2 * x.denominator)), DPS + 5)
    assert abs(limit_surface(0, 2 * t, dps=DPS) - mpmath.mpf(str(closed_L))) < mpmath.mpf(10) ** (-DPS + 3)


@given(st.floats(min_value=0.05, max_value=0.95), st.floats(min_value=-0.9, max_value=0.9))
def test_slope_formula_equals_finite_difference(a, u):
    if u * u >= 4 * a * (1 - a) * 0.98:
        return
    with mpmath.workdps(50):
        h = mpmath.mpf("1e-20")
        numeric = (level_curve(a + h, u, 50) - level_curve(a - h, u, 50)) / (2 * h)
        assert abs(numeric - level_curve_slope(a, u, 50)) < mpmath.mpf("1e-15")


@settings(max_examples=5)
@given(st.floats(min_value=0.1, max_value=1.0))
def test_every_layer_carries_the_overload_in_the_limit(z):
    # sum_j <W_ij> = 1  ->  (1/2) int G dx + 2 * lattice value = 1
    with mpmath.workdps(20):
        integral = mpmath.quad(lambda x: bulk_response(x, z, dps=15), [-z, 0, z])
        assert abs(integral / 2 + 2 * lattice_response(z, dps=15) - 1) < 1e-8


def test_edge_profile_is_the_level_curve_end():
    y = sympy.Rational(3, 5)
    a = edge_profile(y)
    assert sympy.simplify(4 * a * (1 - a) - y**2) == 0


def test_symmetry():
    assert abs(bulk_response(0.3, 0.7, dps=30) - bulk_response(-0.3, 0.7, dps=30)) < mpmath.mpf(10) ** -28


def test_exact_tables_approach_the_edge_law_from_above():
    # N^(2/3) (<W_(N/2,1)> - e) falls towards the derived amplitude |E chi| c(1/2) and stays above it
    # (N = 8..20, exact core; notes/scaling_limit.md Sec. 5)
    from forcenet.numeric.limit_shape.edge import edge_amplitude

    amplitude = float(edge_amplitude("0.5", dps=10))
    previous = None
    for N in (8, 12, 16, 20):
        i = N // 2
        dev = float(mean_W(N)[i - 1][0]) - float(lattice_response(i / N))
        scaled = dev * N ** (2 / 3)
        assert scaled > amplitude
        if previous is not None:
            assert scaled < previous
        previous = scaled


def test_out_of_range():
    with pytest.raises(ValueError, match="x="):
        bulk_response(0.8, 0.5)
    with pytest.raises(ValueError, match="z="):
        lattice_response(1.5)
    assert main(["limit", "--x", "0.9", "--z", "0.6"]) == 2


def test_cli_limit_json(capsys):
    import json

    assert main(["limit", "--x", "0", "--z", "1", "--format", "json", "--dps", "30"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert abs(mpmath.mpf(data["N_W_bulk"]) - mpmath.pi / 2) < mpmath.mpf(10) ** -28
    assert mpmath.mpf(data["W_lattice"]) == 0
