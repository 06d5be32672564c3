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

# the floats' exact binary values (a bare float is refused at 50 digits: the one rule of core.validation)
phis = st.floats(min_value=-1.5707, max_value=1.5707, allow_nan=False).map(Fraction)


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


# ------------------------------------------------ the closed form (7.1), issue 13

from forcenet.exact.chicken_wire import closed_form as cf  # noqa: E402


def _log_factor_coefficients(pairs, T, prefactor=1):
    """``sum c log(arg)`` as ``{monic irreducible factor: coefficient}`` plus the constant logs (key 1).

    Valid on the domain 1/sqrt3 < T < sqrt3 where every argument is positive:
    each factor is oriented to be positive there, and constants enter as log|c|.
    """
    s3 = sympy.sqrt(3)
    out = {}
    for c, arg in pairs:
        num, den = sympy.fraction(sympy.factor(sympy.together(arg), extension=s3))
        for poly, sign in ((num, 1), (den, -1)):
            const, factors = sympy.factor_list(poly, T, extension=s3)
            for f, mult in [(sympy.Integer(1) * const, 1)] + factors:
                f = sympy.expand(f)
                if f.has(T):
                    lc = sympy.Poly(f, T).LC()
                    if (f / lc).subs(T, sympy.Rational(6, 5)) < 0:
                        lc = -lc
                    key = sympy.expand(f / lc)
                    out[key] = out.get(key, 0) + sign * mult * c * prefactor
                    out[1] = out.get(1, 0) + sign * mult * c * prefactor * sympy.log(abs(lc))
                else:
                    out[1] = out.get(1, 0) + sign * mult * c * prefactor * sympy.log(abs(f))
    return out


def test_phi_Q_elimination_is_an_identity():
    """(7.1) in phi equals the algebraic v(Q(phi)), proven by matching the coefficients of independent logs.

    With T = tan(pi/4 + phi/6) in (1/sqrt3, sqrt3): Q = 1/2 - T/(2 sqrt3), 1 - sin(phi/3) = 2/(1+T^2),
    cos(pi/6 +- phi/3) and cos(phi) are rational in T (multiple-angle formulas, checked numerically below),
    tan(pi/12 + phi/6) = (sqrt3 T - 1)/(sqrt3 + T), tan(pi/12 - phi/6) = (sqrt3 - T)/(1 + sqrt3 T).
    """
    T = sympy.Symbol("T", positive=True)
    s3 = sympy.sqrt(3)
    cos2a, sin2a = (1 - T**2) / (1 + T**2), 2 * T / (1 + T**2)
    cos_phi = -sympy.im(sympy.expand((1 + sympy.I * T) ** 6)) / (1 + T**2) ** 3
    c_plus, c_minus = cos2a / 2 + s3 * sin2a / 2, -cos2a / 2 + s3 * sin2a / 2
    one_minus_sin = 2 / (1 + T**2)
    tan_p, tan_m = (s3 * T - 1) / (s3 + T), (s3 - T) / (1 + s3 * T)
    # the substitutions, at 40 digits at five points of the domain
    phi = sympy.Symbol("phi")
    for value in ("-1.4", "-0.7", "0", "0.4", "1.5"):
        x = sympy.Float(value, 50)
        t = sympy.tan(sympy.pi / 4 + x / 6)
        for expr_T, expr_phi in ((cos_phi, sympy.cos(phi)), (c_plus, sympy.cos(sympy.pi / 6 + phi / 3)),
                                 (c_minus, sympy.cos(sympy.pi / 6 - phi / 3)), (one_minus_sin, 1 - sympy.sin(phi / 3)),
                                 (tan_p, sympy.tan(sympy.pi / 12 + phi / 6)), (tan_m, sympy.tan(sympy.pi / 12 - phi / 6)),
                                 (cf.density_Q(phi), sympy.Rational(1, 2) - T / (2 * s3))):
            assert abs(sympy.N(expr_T.subs(T, t) - expr_phi.subs(phi, x), 45)) < 1e-40 if expr_phi.has(phi) else True
        assert abs(sympy.N(cf.density_Q(x) - (sympy.Rational(1, 2) - t / (2 * s3)), 45)) < 1e-40
    # (7.1): log(6 sqrt3/cos phi) + c+ log(tan(pi/4+phi/6) tan(pi/12+phi/6)) + c- log(tan(pi/4-phi/6) tan(pi/12-phi/6))
    left = _log_factor_coefficients([(1, 6 * s3 / cos_phi), (c_plus, T * tan_p), (c_minus, tan_m / T)], T, 1 / one_minus_sin)
    q = sympy.Rational(1, 2) - T / (2 * s3)
    e = 1 - 3 * q + 3 * q**2
    right = _log_factor_coefficients([(6 * e, e), (2 * e, 4), (-3 * q**2, q), (-3 * (1 - q) ** 2, 1 - q),
                                      (-3 * (1 - 2 * q) ** 2, 1 - 2 * q), (-((1 - 3 * q) ** 2), 1 - 3 * q),
                                      (-((2 - 3 * q) ** 2), 2 - 3 * q)], T)
    assert set(left) == set(right)
    for key in left:
        difference = sympy.simplify(sympy.expand_log(sympy.together(left[key] - right[key]), force=True))
        assert difference == 0, (key, difference)


def test_empty_density_forms_agree_exactly():
    phi = cf.PHI
    T = sympy.Symbol("T", positive=True)
    # 1 - sin(phi/3) = 2/(1+T^2) and Q = 1/2 - T/(2 sqrt3): e = (1 + T^2)/4 both ways
    q = sympy.Rational(1, 2) - T / (2 * sympy.sqrt(3))
    assert sympy.expand(cf.empty_density_Q(q) - (1 + T**2) / 4) == 0
    x = sympy.Rational(7, 10)
    assert abs(sympy.N(cf.empty_density_phi(x) - cf.empty_density_Q(cf.density_Q(x)), 50)) < 1e-45
    assert cf.empty_density_phi(0) == sympy.Rational(1, 2)
    assert sympy.simplify(phi - phi) == 0


def test_square_triangle_anchor_to_50_digits():
    anchor = sympy.N(cf.tiling_entropy_maximum(), 60)
    with mpmath.workdps(60):
        assert abs(iso.tiling_entropy(phi=0, dps=50) - mpmath.mpf(str(anchor))) < mpmath.mpf(10) ** -49
        assert abs(2 * iso.entropy(phi=0, dps=50) - mpmath.mpf(str(anchor))) < mpmath.mpf(10) ** -49
    # s(phi) is even and largest at phi = 0 (the twelvefold point)
    for x in ("0.1", "0.5", "1.2"):
        a, b = iso.tiling_entropy(phi=x, dps=30), iso.tiling_entropy(phi="-" + x, dps=30)
        assert abs(a - b) < mpmath.mpf(10) ** -28 and a < iso.tiling_entropy(phi=0, dps=30)


@pytest.mark.parametrize("Q", [pytest.param(Fraction(1, 8), marks=pytest.mark.slow), Fraction(1, 7),
                               pytest.param(Fraction(1, 6), marks=pytest.mark.slow)])  # the route at Q = 1/7 by default
def test_closed_form_equals_the_bethe_ansatz(Q):
    """v and mu = -(1/3) dv/dQ of (7.1) against the Bethe ansatz extrapolated from L <= 120 (independent route)."""
    lim = isotropic_bethe.isotropic_limit(Q, L_max=120, L_min=48)
    v, mu = iso.entropy(Q=Q, dps=20), iso.chemical_potential(Q=Q, dps=20)
    assert lim.v_err < 1e-6 and lim.mu_err < 1e-4  # the route is accurate enough for the test to mean something
    assert abs(lim.v - float(v)) < 5 * lim.v_err + 1e-12
    assert abs(lim.mu - float(mu)) < 5 * lim.mu_err + 1e-10


@settings(max_examples=25, deadline=None)
@given(st.one_of(st.fractions(min_value=0, max_value=Fraction(1, 3)),
                 st.sampled_from(["1e-12", "1e-40", "0.33333333333333333", "0.1845564976144219", "0.33"])))
def test_no_silent_loss_of_digits(Q):
    """dps D and 2D agree to D digits, relative, everywhere (Q -> 0, Q -> 1/3, mu near the maximum)."""
    D = 25
    for f in (iso.entropy, iso.tiling_entropy, iso.empty_density):
        a, b = f(Q=Q, dps=D), f(Q=Q, dps=2 * D)
        with mpmath.workdps(3 * D):
            assert abs(a - b) <= abs(b) * mpmath.mpf(10) ** (-D + 1)
    if 0 < Fraction(Q) < Fraction(1, 3):
        a, b = iso.chemical_potential(Q=Q, dps=D), iso.chemical_potential(Q=Q, dps=2 * D)
        with mpmath.workdps(3 * D):
            assert abs(a - b) <= abs(b) * mpmath.mpf(10) ** (-D + 1)


def test_series_and_closed_form_overlap():
    """Below the crossover the exact series of v(Q) takes over; on the overlap both agree to the working precision."""
    with mpmath.workdps(80):
        for q in ("1e-2", "1e-4", "1e-8"):
            q = mpmath.mpf(q)
            closed = iso._v(q)
            series = iso._v_series(q, 60)
            assert abs(closed - series) < abs(closed) * mpmath.mpf(10) ** -50
    # the series is what entropy() uses at tiny Q, and it still equals -3 Q^2 log Q + ... there
    v = iso.entropy(Q="1e-300", dps=30)
    with mpmath.workdps(40):
        q = mpmath.mpf("1e-300")
        assert abs(v - (-3 * q**2 * mpmath.log(q) + (3 * mpmath.log(2) - mpmath.mpf(9) / 2) * q**2)) < v * mpmath.mpf(10) ** -28


def test_series_coefficients_equal_sympy_series():
    exact = sympy.series(cf.entropy_Q(), cf.Q, 0, 11).removeO()
    assert sympy.simplify(sympy.expand(cf.entropy_series_Q(10) - exact)) == 0


def test_corrected_7_3_and_its_next_orders():
    """v = eps^2 (log(108/eps^2) - 3)/18 + O(eps^3 log eps): each added order shrinks the error like eps^(order+1)."""
    eps = cf.EPS
    assert sympy.simplify(cf.entropy_series_eps(2) - eps**2 * (sympy.log(108 / eps**2) - 3) / 18) == 0
    for e in ("0.01", "0.001"):
        with mpmath.workdps(60):
            phi = mpmath.nstr(mpmath.pi / 2 - mpmath.mpf(e), 55)
        exact = iso.entropy(phi=phi, dps=40)
        errors = [abs(iso.entropy_series_7_3(e, order, 40) - exact) for order in (2, 3, 4)]
        with mpmath.workdps(40):
            x = mpmath.mpf(e)
            assert errors[0] < 2 * x**3 * abs(mpmath.log(x))
            assert errors[1] < 2 * x**4 * abs(mpmath.log(x))
            assert errors[2] < 2 * x**5 * abs(mpmath.log(x)) ** 2
    # the thesis's limit: v/(3Q^2) + log Q -> log 2 - 3/2 (not + 3/2)
    with mpmath.workdps(30):
        q = mpmath.mpf("1e-6")
        value = iso.entropy(Q="1e-6", dps=25) / (3 * q**2) + mpmath.log(q)
        assert abs(value - (mpmath.log(2) - mpmath.mpf(3) / 2)) < 1e-5


def test_corrected_7_4_per_grain():
    """g = 3 l^2 v at Q = 1/(3l) tends to log(6 l) - 3/2, with corrections O(1/l)."""
    previous = None
    for l in (10, 100, 1000, 10000):
        with mpmath.workdps(40):
            g = 3 * l**2 * iso.entropy(Q=Fraction(1, 3 * l), dps=30)
            gap = abs(g - iso.entropy_per_grain(l, dps=30))
        assert gap * l < 10
        if previous is not None:
            assert gap < previous
        previous = gap


def test_maximum_is_where_mu_vanishes():
    m = iso.maximum(dps=40)
    with mpmath.workdps(50):
        assert abs(iso.chemical_potential(Q=mpmath.nstr(m.Q_max, 45), dps=20)) < mpmath.mpf(10) ** -35
        for dq in ("1e-3", "-1e-3"):
            assert iso.entropy(Q=m.Q_max + mpmath.mpf(dq), dps=30) < m.v_max
        assert abs(m.squares_per_triangle - mpmath.sqrt(3) / 4) < mpmath.mpf(10) ** -38
        assert abs(m.empty_per_site - mpmath.mpf(1) / 2) < mpmath.mpf(10) ** -38
        assert abs(m.v_at_Q0 - m.s_max / 2) < mpmath.mpf(10) ** -38
    assert mpmath.mp.dps == 15  # no global precision was set


def test_closed_form_rejects_bad_points():
    with pytest.raises(ValueError, match="Q="):
        iso.entropy(Q="0.4")
    with pytest.raises(ValueError, match="phi="):
        iso.entropy(phi="1.6")
    with pytest.raises(TypeError, match="exactly one"):
        iso.entropy()
    with pytest.raises(ValueError, match="mu needs"):
        iso.chemical_potential(Q=0)
    with pytest.raises(TypeError, match="dps="):
        iso.entropy(Q="0.1", dps=2.5)


# ------------------------------------------------- the numeric v(Q) is derived from the exact one


densities = st.fractions(min_value=Fraction(1, 10**6), max_value=Fraction(1, 3) - Fraction(1, 10**6))


@settings(max_examples=25, deadline=None)
@given(densities, st.sampled_from([15, 40, 120]))
def test_compiled_closed_forms_agree_with_sympy_evaluation(Q, dps):
    """v and mu (lambdified from exact/chicken_wire/closed_form.py) equal sympy's own evaluation of the
    same expressions at a rational point to every requested digit (sympy.N manages its precision itself)."""
    from forcenet.exact.chicken_wire import closed_form as cf

    q = sympy.Rational(Q.numerator, Q.denominator)
    for value, expr in ((iso.entropy(Q=Q, dps=dps), cf.entropy_Q(q)),
                        (iso.chemical_potential(Q=Q, dps=dps), cf.chemical_potential_Q(q))):
        with mpmath.workdps(dps + 20):
            exact = mpmath.mpf(str(sympy.N(expr, dps + 20)))
            assert abs(value - exact) <= abs(exact) * mpmath.mpf(10) ** (1 - dps)


def test_compiled_closed_forms_agree_with_the_phi_route():
    """v(Q) compiled from the elimination equals (7.1) at phi(Q), evaluated by sympy (a different formula)."""
    from forcenet.exact.chicken_wire import closed_form as cf

    for Q in (Fraction(1, 7), Fraction(1, 5), Fraction(3, 10)):
        q = sympy.Rational(Q.numerator, Q.denominator)
        with mpmath.workdps(70):
            by_phi = mpmath.mpf(str(sympy.N(cf.entropy_phi(cf.phi_of_Q(q)), 70)))
            assert abs(iso.entropy(Q=Q, dps=50) - by_phi) <= by_phi * mpmath.mpf(10) ** -49


def test_dmu_is_the_derivative_of_mu():
    """The compiled d mu/dQ (Newton at the maximum) against a numerical derivative of the compiled mu."""
    with mpmath.workdps(40):
        for q in (mpmath.mpf("0.05"), mpmath.mpf("0.1845"), mpmath.mpf("0.3")):
            assert abs(iso._dmu(q) - mpmath.diff(iso._mu, q)) < mpmath.mpf(10) ** -30
