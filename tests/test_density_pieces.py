"""The density pieces, grids and histogram edges the command line renders (issue 25 item 2).

grain_pieces and layer_pieces against independent routes: the grain's moments against ``moment()``
(the marked-chain DP), the CDF's derivative and ends, the layer's mean force 1 (f = F/<F>) and its
CDF against exact bin masses; density_grid against exact rational evaluation of the pieces;
histogram_edges against its defining properties.
"""

from fractions import Fraction

import numpy as np
import pytest
import sympy
from hypothesis import given
from hypothesis import strategies as st

from forcenet.core.errors import ArgumentError
from forcenet.exact import moment
from forcenet.exact.triangle import distribution as D
from forcenet.exact.triangle.gaps import contact_gap_law, grain_gap_counts
from forcenet.numeric.triangle.force_distribution import density_grid, histogram_edges

w, f = D.W_SYMBOL, D.F_SYMBOL


def _frac(x) -> Fraction:
    x = sympy.Rational(x)
    return Fraction(int(x.p), int(x.q))


@pytest.mark.parametrize("N, grain", [(3, (2, 1)), (4, (3, 2)), (5, (5, 1)), (6, (4, 4))])
def test_grain_pieces_moments_match_the_moment_dp(N, grain):
    p, F = D.grain_pieces(grain_gap_counts(N, grain))
    assert len(p) == len(F) == 1 and (p[0].lo, p[0].hi) == (0, 1) == (F[0].lo, F[0].hi)
    assert F[0].poly.diff(w) == p[0].poly
    assert F[0].poly.eval(0) == 0 and F[0].poly.eval(1) == 1
    for s in (1, 2, 3):
        assert _frac((p[0].poly * sympy.Poly(w**s, w)).integrate().eval(1)) == moment(N, grain, s)


def test_grain_pieces_of_a_contact_is_a_density_on_the_unit_interval():
    p, F = D.grain_pieces(contact_gap_law(5, (3, 2), "F5"))
    assert F[0].poly.diff(w) == p[0].poly
    assert F[0].poly.eval(0) == 0 and F[0].poly.eval(1) == 1


@pytest.mark.parametrize("N, i", [(3, 2), (4, 3), (5, 5)])
def test_layer_pieces_mean_force_is_one_and_cdf_is_the_bin_mass(N, i):
    p, F = D.layer_pieces(N, i)
    assert (p[0].lo, p[0].hi) == (0, i)
    poly = p[0].poly
    assert _frac((poly * sympy.Poly(f, f)).integrate().eval(i)) == 1  # f = F/<F>: mean 1
    for x in (Fraction(1, 3), Fraction(1), Fraction(i, 2), Fraction(i)):
        assert _frac(F[0].poly.eval(sympy.Rational(x.numerator, x.denominator))) == D.bin_probabilities(p, [0, x])[0]


def test_layer_pieces_refuses_a_layer_out_of_range():
    with pytest.raises(ArgumentError, match="i"):
        D.layer_pieces(4, 5)


@given(st.integers(1, 40))
def test_density_grid_is_the_exact_pieces_rounded_once(K):
    pieces = D.triangle_force_density(4)
    cdf = D.piecewise_cdf(pieces)
    x, p, F = density_grid(pieces, cdf, K)
    assert x.tolist() == [4.0 * k / K for k in range(K + 1)]
    for a, b, c in zip(x.tolist(), p.tolist(), F.tolist()):
        fa = Fraction(a)
        piece = next(q for q in pieces if q.lo <= fa <= q.hi)
        assert b == float(_frac(piece.poly.eval(sympy.Rational(fa.numerator, fa.denominator))))
        assert c == (0.0 if a == 0 else float(sum(D.bin_probabilities(pieces, [0, fa]))))


def test_density_grid_refuses_an_empty_grid():
    p, F = D.layer_pieces(3, 3)
    with pytest.raises(ArgumentError, match="K"):
        density_grid(p, F, 0)


@given(st.floats(1e-6, 1e6), st.integers(1, 500))
def test_histogram_edges_are_equal_bins_from_zero(f_max, bins):
    edges = histogram_edges(f_max, bins)
    assert edges.shape == (bins + 1,) and edges[0] == 0.0 and edges[-1] == f_max
    assert np.all(np.diff(edges) > 0)
    assert np.allclose(np.diff(edges), f_max / bins, rtol=1e-9, atol=0)


@pytest.mark.parametrize("f_max, bins, name", [(0.0, 4, "f_max"), (float("inf"), 4, "f_max"), (float("nan"), 4, "f_max"),
                                                (1.0, 0, "bins")])
def test_histogram_edges_refuses_bad_ranges(f_max, bins, name):
    with pytest.raises(ArgumentError, match=name):
        histogram_edges(f_max, bins)
