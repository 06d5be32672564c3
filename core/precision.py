"""Precision is a parameter: the one way every arbitrary-precision function here evaluates.

* inputs are converted inside ``mpmath.workdps`` (:func:`to_mpf`: strings keep
  all their digits, Fractions are divided exactly, ``bool``, ``nan`` and
  ``inf`` are refused);
* :func:`guarded` computes at ``dps + GUARD`` digits and returns the result
  rounded to ``dps``;
* :func:`converged` raises the working precision until two evaluations agree
  to ``dps + 3`` digits relative to the result, for quantities whose
  cancellations depend on the point (so they cost precision, never digits);
* no global precision is ever set.

Examples
--------
>>> mpmath.nstr(guarded(lambda: to_mpf("0.1", "x") * 3, 30), 30)
'0.3'
>>> mpmath.nstr(converged(lambda: mpmath.exp(to_mpf("1e-30", "x")) - 1, 10), 10)  # no digit lost
'1.0e-30'
"""

from __future__ import annotations

from collections.abc import Callable
from fractions import Fraction
from typing import TypeAlias

import mpmath

from forcenet.core.errors import ArgumentError, ArgumentTypeError, ConvergenceError
from forcenet.core.validation import check_float_digits, check_not_bool, check_real, is_binary_float, is_integer

__all__ = ["GUARD", "RealLike", "to_mpf", "guarded", "converged", "within_pi", "check_within_pi"]

RealLike: TypeAlias = int | float | str | Fraction  # a real argument (or an mpmath.mpf): strings and Fractions keep every digit

GUARD = 10  # guard digits
MAX_EXTRA = 5000  # digits beyond dps before giving up on convergence


def to_mpf(value: RealLike, name: str, dps: int | None = None) -> mpmath.mpf:
    """``value`` as an mpf at the current precision (call inside ``mpmath.workdps``).

    With ``dps`` (the digits the caller's result promises), a binary float
    meets the one rule of :func:`forcenet.core.validation.check_float_digits`:
    refused naming the fix where its digits do not reach ``dps``, else accepted
    with a ``PrecisionWarning`` (silent when it is exactly its decimal).  A
    function converting at several working precisions applies the rule once,
    at its boundary, instead (:mod:`forcenet.numeric.chicken_wire.isotropic`).

    Examples
    --------
    >>> with mpmath.workdps(30):
    ...     mpmath.nstr(to_mpf(Fraction(1, 3), "Q"), 30)
    '0.333333333333333333333333333333'
    >>> to_mpf(1 / 3, "Q", dps=30)
    Traceback (most recent call last):
    ...
    forcenet.core.errors.ArgumentTypeError: Q=0.3333333333333333 is a binary float, good to 15 significant digits, but dps=30 digits were asked: pass '1/3' or Fraction(1, 3) (a string or a Fraction keeps every digit)
    """
    check_not_bool(value, name)
    if dps is not None and is_binary_float(value):
        check_float_digits(value, name, dps, stacklevel=3)
    try:
        x = mpmath.mpf(value.numerator) / value.denominator if isinstance(value, Fraction) else mpmath.mpf(value)
    except (TypeError, ValueError):
        raise ArgumentTypeError(f"{name}={value!r} is not a real number") from None
    if not mpmath.isfinite(x):
        raise ArgumentError(f"{name}={value!r} is out of range: {name} must be a finite real number")
    return x


def _digits(value: object) -> int:
    """Decimal digits that decide a comparison of ``value`` with an irrational constant: more than it carries."""
    if isinstance(value, str):
        return len(value) + 20
    if isinstance(value, Fraction):
        return len(str(value.numerator)) + len(str(value.denominator)) + 20
    if is_integer(value):
        return len(str(int(value))) + 20  # type: ignore[call-overload]  # anything with __index__
    if isinstance(value, mpmath.mpf):  # an mpf is exact at the precision of its mantissa
        return int(value.man).bit_length() // 3 + mpmath.mp.dps + 20
    return 40  # a binary float (53 bits: exact at 17 digits) or another number type


def _pi_text(multiple: Fraction) -> str:
    """``pi/2``, ``pi``, ``3pi/2``: the multiple of pi as a message writes it."""
    top = "pi" if multiple.numerator == 1 else f"{multiple.numerator}pi"
    return top if multiple.denominator == 1 else f"{top}/{multiple.denominator}"


def within_pi(value: RealLike | mpmath.mpf, multiple: Fraction = Fraction(1, 2), *, strict: bool = False,
              name: str = "value") -> bool:
    """Whether ``|value| <= multiple * pi`` (``<`` if ``strict``), decided with more digits than ``value`` carries.

    A decimal string that rounds to the bound at double precision is not taken for it: the comparison runs
    with 20 digits beyond those given.

    Parameters
    ----------
    value : int, str, Fraction, float or mpmath.mpf
        A finite real number (a string keeps every digit).
    multiple : Fraction
        The bound in units of pi (default 1/2).
    strict : bool
        Compare with ``<`` instead of ``<=``.
    name : str
        The argument's name in the messages.

    Returns
    -------
    bool

    Raises
    ------
    ArgumentTypeError
        If ``value`` is not a real number.
    ArgumentError
        If ``value`` is not finite.

    Examples
    --------
    >>> within_pi("1.5707963267948966"), within_pi("1.5707963267948967"), within_pi(Fraction(-3, 2), strict=True)
    (True, False, True)
    """
    if not (isinstance(value, (str, Fraction, float, mpmath.mpf)) or is_integer(value)):  # is_integer: no bool
        raise ArgumentTypeError(f"{name}={value!r} is not a real number")
    with mpmath.workdps(_digits(value)):
        try:  # converted here, not by to_mpf: the command line's --phi meets one check (tests/test_walks.py)
            x = mpmath.mpf(value.numerator) / value.denominator if isinstance(value, Fraction) else mpmath.mpf(value)
        except (TypeError, ValueError):
            raise ArgumentTypeError(f"{name}={value!r} is not a real number") from None
        if not mpmath.isfinite(x):
            raise ArgumentError(f"{name}={value!r} is out of range: {name} must be a finite real number")
        limit = mpmath.pi * multiple.numerator / multiple.denominator
        return bool(abs(x) < limit if strict else abs(x) <= limit)


def check_within_pi(value: RealLike | mpmath.mpf, name: str, multiple: Fraction = Fraction(1, 2)) -> RealLike | mpmath.mpf:
    """``value`` itself when ``|value| <= multiple * pi`` (:func:`within_pi`); else ``ArgumentError`` naming the range.

    Parameters
    ----------
    value : int, str, Fraction, float or mpmath.mpf
        A finite real number (a string keeps every digit).
    name : str
        The argument's name in the message.
    multiple : Fraction
        The bound in units of pi (default 1/2).

    Returns
    -------
    int, str, Fraction, float or mpmath.mpf
        ``value``, unchanged.

    Raises
    ------
    ArgumentError
        If ``value`` lies outside ``[-multiple pi, multiple pi]`` (or is not finite).
    ArgumentTypeError
        If ``value`` is not a number.

    Examples
    --------
    >>> check_within_pi("1.6", "phi")
    Traceback (most recent call last):
    ...
    forcenet.core.errors.ArgumentError: phi=1.6 is out of range: phi must lie in [-pi/2, pi/2] = [-1.5707963267948966192..., 1.5707963267948966192...]
    """
    check_real(value, name)  # a finite number (the messages of every real argument)
    if not within_pi(value, multiple, name=name):
        shown = value.strip() if isinstance(value, str) else value  # the number, without the blanks around it
        pi_text = _pi_text(multiple)
        with mpmath.workdps(30):
            bound = mpmath.nstr(mpmath.pi * multiple.numerator / multiple.denominator, 20)
        raise ArgumentError(f"{name}={shown} is out of range: {name} must lie in [-{pi_text}, {pi_text}] "
                            f"= [-{bound}..., {bound}...]")
    return value


def guarded(compute: Callable[[], mpmath.mpf], dps: int) -> mpmath.mpf:
    """``compute()`` at ``dps + GUARD`` digits, returned rounded to ``dps`` digits.

    ``dps`` is trusted: the public function that calls this has checked it
    (:func:`~forcenet.core.validation.check_dps`, once per call).
    """
    with mpmath.workdps(dps + GUARD):
        value = compute()
    with mpmath.workdps(dps):
        return +value


def converged(compute: Callable[[], mpmath.mpf], dps: int) -> mpmath.mpf:
    """``compute()`` at increasing precision until two evaluations agree to ``dps + 3`` relative digits.

    ``dps`` is trusted, as in :func:`guarded`.

    Raises
    ------
    forcenet.core.errors.ConvergenceError
        If the evaluations still differ at ``dps + MAX_EXTRA`` digits (also a ``RuntimeError``).
    """
    prec = dps + GUARD
    with mpmath.workdps(prec):
        previous = compute()
    while True:
        prec = 2 * prec
        with mpmath.workdps(prec):
            current = compute()
            if current == 0 or abs(current - previous) <= abs(current) * mpmath.mpf(10) ** (-(dps + 3)):
                break
        if prec > dps + MAX_EXTRA:
            raise ConvergenceError(f"no convergence to {dps} digits within {MAX_EXTRA} extra digits")
        previous = current
    with mpmath.workdps(dps):
        return +current
