"""The symbolic nested layers (issue 16 part 3) against plain sympy integration and the exact core."""

import pytest
import sympy
from hypothesis import given, settings
from hypothesis import strategies as st

from forcenet.exact import moment, normalization
from forcenet.exact.reference.integration import polytope_bounds, w_symbols
from forcenet.exact.thesis.symbolic import integrate_layer_step, moment_symbolic, nested_layers, w_symbol


def _direct(N, m):
    """J_m: plain sympy integration of the layers below m over the bounds (4.9), bottom up, decreasing j."""
    W, B = w_symbols(N), polytope_bounds(N)
    expr = sympy.Integer(1)
    for i in range(N, m, -1):
        for j in range(i - 1, 0, -1):
            expr = sympy.integrate(expr, (W[(i, j)], *B[(i, j)]))
    return sympy.expand(expr)


@pytest.mark.parametrize("N", [2, 3, 4, 5])
def test_every_layer_equals_direct_integration(N):
    W = w_symbols(N)
    layers = nested_layers(N)
    assert [layer.m for layer in layers] == list(range(N, 0, -1))
    for layer in layers:
        m = layer.m
        # the matrix product uses W_{m,m} as a variable; on the polytope it is 1 - the others
        J = layer.integrand().subs({w_symbol(m, m): W[(m, m)]} if m > 1 else {w_symbol(1, 1): 1})
        assert sympy.expand(J - _direct(N, m)) == 0
    assert layers[-1].normalization() == sympy.Rational(normalization(N).numerator, normalization(N).denominator)


@settings(max_examples=10)
@given(st.integers(min_value=2, max_value=5), st.data(), st.integers(min_value=1, max_value=3))
def test_defects_give_the_moments(N, data, s):
    i = data.draw(st.integers(min_value=1, max_value=N))
    j = data.draw(st.integers(min_value=1, max_value=i))
    value = moment(N, (i, j), s)
    assert moment_symbolic(N, (i, j), s) == sympy.Rational(value.numerator, value.denominator)


def test_bad_input():
    with pytest.raises(ValueError, match="N=7 is out of range"):
        nested_layers(7)
    with pytest.raises(ValueError, match="top layer"):
        integrate_layer_step(nested_layers(3)[-1])
