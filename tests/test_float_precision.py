"""Issue 45 item 4: a binary float where an exact number is expected -- one rule (core.validation.check_float_digits).

Refused with the fix named where its digits do not reach the precision asked (or the result is exact), accepted
with a ``forcenet.PrecisionWarning`` where they do, accepted silently where the float is exactly its decimal.
"""

from __future__ import annotations

import warnings
from fractions import Fraction

import mpmath
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import forcenet
from forcenet.core.validation import check_float_digits, check_rational, float_digits
from forcenet.numeric.chicken_wire import isotropic as iso


def test_the_warning_is_exported_beside_the_errors():
    assert forcenet.PrecisionWarning is forcenet.core.errors.PrecisionWarning
    assert issubclass(forcenet.PrecisionWarning, UserWarning)
    assert "PrecisionWarning" in forcenet.__all__


def test_entropy_at_a_float_sixth_is_refused_naming_the_fix():
    with pytest.raises(forcenet.ArgumentTypeError, match=r"pass '1/6' or Fraction\(1, 6\)") as caught:
        iso.entropy(Q=1 / 6, dps=40)
    assert "Q=0.16666666666666666" in str(caught.value) and "dps=40" in str(caught.value)
    exact = iso.entropy(Q="1/6", dps=40)
    assert iso.entropy(Q=Fraction(1, 6), dps=40) == exact


def test_within_the_floats_digits_it_is_accepted_with_a_warning_and_right_to_those_digits():
    with pytest.warns(forcenet.PrecisionWarning, match=r"pass '1/6' or Fraction\(1, 6\)"):
        value = iso.entropy(Q=1 / 6, dps=12)
    assert mpmath.nstr(value, 12) == mpmath.nstr(iso.entropy(Q="1/6", dps=12), 12)


@pytest.mark.parametrize("call", [
    lambda x: iso.entropy(phi=x, dps=30),
    lambda x: iso.tiling_entropy(phi=x, dps=30),
    lambda x: iso.density_Q(x, dps=30),
    lambda x: iso.density_Q_naive(x, dps=30),
    lambda x: iso.eps_of(phi=x, dps=30),
    lambda x: iso.empty_density(phi=x, dps=30),
    lambda x: iso.chemical_potential(phi=x, dps=30),
    lambda x: iso.phi_of_density(x, dps=30),
    lambda x: iso.entropy_series_7_3(x, dps=30),
    lambda x: iso.entropy_per_grain(x, dps=30),
])
def test_every_exact_parameter_of_the_closed_forms_meets_the_rule(call):
    with pytest.raises(forcenet.ArgumentTypeError, match="is a binary float"):
        call(0.3)
    call("0.3")  # the decimal string is exact
    call(0.25)  # exactly its decimal: nothing lost, no warning
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        call(0.25)


def test_exact_results_refuse_inexact_floats_and_take_exact_ones():
    from forcenet.exact.packing.mobilized import mean_W_mobilized
    from forcenet.numeric.chicken_wire.isotropic_bethe import isotropic_limit

    with pytest.raises(forcenet.ArgumentTypeError, match=r"the result is exact: pass '1/6' or Fraction\(1, 6\)"):
        isotropic_limit(1 / 6)
    with pytest.raises(forcenet.ArgumentTypeError, match=r"pass '0.1' or Fraction\(1, 10\)"):
        mean_W_mobilized(2, 2, F=0.1, j0=1, mg=1)
    assert mean_W_mobilized(2, 2, F=0.5, j0=1, mg=1) == mean_W_mobilized(2, 2, F=Fraction(1, 2), j0=1, mg=1)


def test_numpy_floats_carry_their_own_digits():
    assert (float_digits(np.float64(0.1)), float_digits(np.float32(0.1)), float_digits(np.float16(0.1))) == (15, 6, 3)
    with pytest.raises(forcenet.ArgumentTypeError, match="good to 6 significant digits"):
        check_float_digits(np.float32(0.1), "x", 10)
    with pytest.warns(forcenet.PrecisionWarning):
        check_float_digits(np.float32(0.1), "x", 6)


def test_the_command_line_reads_every_exact_option_at_full_precision(capsys):
    from forcenet.cli import main

    with warnings.catch_warnings():
        warnings.simplefilter("error")  # strings all the way: no float on the way, no warning
        assert main(["entropy", "--Q", "0.16666666666666666", "--dps", "40", "--format", "json", "--F", "0.1"]) == 0
    out = capsys.readouterr().out
    assert "g_per_grain_7_4" in out


def test_non_floats_pass_untouched():
    for value in (1, Fraction(1, 6), "1/6", mpmath.mpf(1) / 6, None):
        assert check_float_digits(value, "x", 100) is value
    assert check_float_digits(float("nan"), "x", 100) != 0  # nan is the range checks' (refused there)
    with pytest.raises(forcenet.ArgumentTypeError):
        check_rational(True, "Q")
    with pytest.raises(forcenet.ArgumentTypeError):
        check_rational(1j, "Q")
    with pytest.raises(forcenet.ArgumentError):
        check_rational(float("inf"), "Q")


finite = st.floats(allow_nan=False, allow_infinity=False, min_value=-1e300, max_value=1e300)


@settings(max_examples=300, deadline=None)
@given(x=finite, dps=st.integers(5, 60))
def test_one_rule_for_every_float_and_precision(x, dps):
    """Silent iff the float is exactly its shortest decimal; else warned iff dps <= 15, else refused."""
    exact = Fraction(x) == Fraction(repr(x))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            assert check_float_digits(x, "x", dps) == x
            refused = False
        except forcenet.ArgumentTypeError as exc:
            refused = True
            message = str(exc)
    warned = any(issubclass(w.category, forcenet.PrecisionWarning) for w in caught)
    if exact:
        assert not refused and not warned
    elif dps <= 15:
        assert warned and not refused
    else:
        assert refused and not warned
        # the fix named reads back as the float: a fraction or decimal that is exactly what was meant
        fix = message.split("pass '", 1)[1].split("'", 1)[0]
        assert float(Fraction(fix)) == x


@settings(max_examples=200, deadline=None)
@given(p=st.integers(1, 999), q=st.integers(1, 999))
def test_a_small_fraction_typed_as_a_float_is_named_back(p, q):
    x = p / q
    if Fraction(x) == Fraction(repr(x)):
        return  # dyadic and short: exact
    with pytest.raises(forcenet.ArgumentTypeError) as caught:
        check_float_digits(x, "Q", None)
    fix = Fraction(p, q)
    text = repr(float(fix)) if all(f in (2, 5) for f in _factors(fix.denominator)) else str(fix)
    assert f"'{text}' or Fraction({fix.numerator}, {fix.denominator})" in str(caught.value)


def _factors(n):
    out, k = [], 2
    while k * k <= n:
        while n % k == 0:
            out.append(k)
            n //= k
        k += 1
    return out + ([n] if n > 1 else [])


def test_to_mpf_applies_the_rule_when_told_the_digits():
    from forcenet.core.precision import to_mpf

    with mpmath.workdps(50):
        with pytest.raises(forcenet.ArgumentTypeError, match=r"pass '1/3' or Fraction\(1, 3\)"):
            to_mpf(1 / 3, "x", dps=40)
        with pytest.warns(forcenet.PrecisionWarning):
            to_mpf(1 / 3, "x", dps=10)
        assert to_mpf(0.5, "x", dps=40) == mpmath.mpf(1) / 2
        assert to_mpf(1 / 3, "x") == mpmath.mpf(1 / 3)  # without dps: the float's exact value, as before
