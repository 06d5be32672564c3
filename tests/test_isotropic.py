"""Closed forms (7.2)-(7.4) and the Bethe-ansatz entropy on the isotropic line (numeric/chicken_wire/isotropic.py)."""

from fractions import Fraction

import mpmath
import numpy as np
import pytest
import sympy
from hypothesis import given, settings
from hypothesis import strategies as st

from forcenet.numeric.chicken_wire import isotropic as iso
from forcenet.numeric.chicken_wire import isotropic_bethe

phis = st.floats(min_value=-1.5707, max_value=1.5707, allow_nan=False)


@given(phis)
def test_density_tan_form_equals_printed_form(phi):
    # cos x / (1 - sin x) = tan(pi/4 + x/2): two forms of Eq. (7.2)
    with mpmath.workdps(60):
        naive = iso.density_Q_naive(phi, dps=60)
    assert abs(iso.density_Q(phi, dps=50) - naive) < mpmath.mpf(10) ** -48


def test_printed_form_cancels_where_one_minus_sin_vanishes():
    # at phi -> 3 pi/2 (1 - sin(phi/3) -> 0) the printed form loses digits; the tan form does not
    for delta in ("1e-6", "1e-10"):
        with mpmath.workdps(30):
            phi = 3 * mpmath.pi / 2 - mpmath.mpf(delta)  # the same 30-digit phi for every evaluation
            naive = iso.density_Q_naive(phi, dps=30)
            stable = mpmath.mpf(1) / 2 - mpmath.tan(mpmath.pi / 4 + phi / 6) / (2 * mpmath.sqrt(3))
        with mpmath.workdps(100):
            exact = mpmath.mpf(1) / 2 - mpmath.tan(mpmath.pi / 4 + phi / 6) / (2 * mpmath.sqrt(3))
            digits_naive = -mpmath.log10(abs(naive - exact) / abs(exact))
            digits_stable = -mpmath.log10(abs(stable - exact) / abs(exact) + mpmath.mpf(10) ** -60)
        k = mpmath.log10(1 / mpmath.mpf(delta))
        # Q has a pole at phi = 3 pi/2, so every form loses log10(1/delta) digits (conditioning);
        # the printed form loses about twice that (the cancellation in 1 - sin)
        assert digits_stable > 30 - k - 1
        assert digits_naive < 30 - 1.5 * k


def test_density_end_points():
    with mpmath.workdps(60):
        assert abs(iso.density_Q(-mpmath.pi / 2, dps=50) - mpmath.mpf(1) / 3) < mpmath.mpf(10) ** -49
        assert abs(iso.density_Q(mpmath.pi / 2, dps=50)) < mpmath.mpf(10) ** -49


@given(st.fractions(min_value=0, max_value=Fraction(1, 3)))
def test_phi_of_density_inverts_7_2(Q):
    with mpmath.workdps(50):
        phi = iso.phi_of_density(Q, dps=40)
        q = mpmath.mpf(Q.numerator) / Q.denominator
        assert abs(iso.density_Q(phi, dps=40) - q) < mpmath.mpf(10) ** -38


def test_density_series_near_the_empty_lattice():
    # sympy series of the printed (7.2) at phi = pi/2 - eps: Q = sqrt3 eps / 9 + O(eps^2) (text: eps ~ sqrt3 / l)
    eps = sympy.Symbol("eps", positive=True)
    phi = sympy.pi / 2 - eps
    Q = sympy.Rational(1, 2) - sympy.cos(phi / 3) / (2 * sympy.sqrt(3) * (1 - sympy.sin(phi / 3)))
    series = sympy.series(Q, eps, 0, 3).removeO()
    c1 = sympy.nsimplify(series.coeff(eps, 1))
    assert sympy.simplify(c1 - sympy.sqrt(3) / 9) == 0
    with mpmath.workdps(60):
        for e in ("1e-4", "1e-6"):
            e = mpmath.mpf(e)
            value = iso.density_Q(mpmath.pi / 2 - e, dps=50)
            approx = mpmath.mpf(sympy.N(series.subs(eps, sympy.Float(str(e), 60)), 60))
            assert abs(value - approx) < 10 * e**3


def test_closed_forms_reject_bad_input():
    with pytest.raises(ValueError, match="phi="):
        iso.density_Q(2)
    with pytest.raises(ValueError, match="dps="):
        iso.density_Q(0, dps=2)
    with pytest.raises(ValueError, match="Q="):
        iso.phi_of_density(Fraction(1, 2))
    with pytest.raises(ValueError, match="eps="):
        iso.entropy_series_7_3(0)
    with pytest.raises(ValueError, match="l="):
        iso.entropy_per_grain(-1)


def test_entropy_per_grain_grows_by_log_of_the_force_scale():
    # (7.4): one degree of freedom per grain, so g(F) - g(1) = log F
    for F in ("2", "10", "0.5"):
        assert abs(iso.entropy_per_grain(F) - iso.entropy_per_grain(1) - mpmath.log(mpmath.mpf(F))) < mpmath.mpf(10) ** -45


def test_extrapolate_recovers_a_known_limit():
    Ls = np.arange(60, 241, 12)
    for c in (0.1, -0.3):
        values = 0.0625 + c / Ls**2 + 0.7 / Ls**4
        v, err = isotropic_bethe.extrapolate(list(Ls), list(values))
        assert abs(v - 0.0625) < 1e-12 and err < 1e-6
    with pytest.raises(ValueError, match="at least 4"):
        isotropic_bethe.extrapolate([60, 72], [0.1, 0.1])


def test_bracketing_fractions():
    lo, hi = isotropic_bethe.bracketing_fractions(0.18)
    assert lo <= 0.18 <= hi and lo.denominator <= 16 and hi.denominator <= 16
    assert not any(lo < Fraction(c, a) < hi for a in range(3, 17) for c in range(1, a))


@pytest.mark.slow
def test_legendre_structure_dv_dQ_is_minus_three_mu():
    # v(Q2) - v(Q1) = -3 int mu dQ: each of the three densities has the chemical potential mu
    lims = [isotropic_bethe.isotropic_limit(Fraction(1, a), L_max=240, L_min=60) for a in (8, 7, 6)]
    qs = np.array([float(l.Q) for l in lims])
    mus = np.array([l.mu for l in lims])
    P = np.polyint(np.polyfit(qs, mus, 2))
    predicted = -3 * (np.polyval(P, qs[-1]) - np.polyval(P, qs[0]))
    # quadratic-interpolation error of the integral, estimated from the trapezoid rule on the two halves
    trap = -3 * sum((mus[i] + mus[i + 1]) / 2 * (qs[i + 1] - qs[i]) for i in range(2))
    tol = abs(predicted - trap) / 4 + 5 * sum(l.v_err + 3 * l.mu_err * 0.05 for l in lims)
    assert abs((lims[-1].v - lims[0].v) - predicted) < tol
