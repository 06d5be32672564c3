"""Argument checks shared by the whole package (library and command line).

One policy, one place:

* :class:`~forcenet.core.errors.ArgumentTypeError` (a ``TypeError``) when
  the argument has the wrong type: an integer argument accepts every type
  with ``__index__`` (``int``, ``numpy.int64``, ...) but not ``bool`` and not
  floats, even integral ones;
* :class:`~forcenet.core.errors.ArgumentError` (a ``ValueError``) when the
  value lies outside the allowed range;
* the message names the argument, its value and the allowed range, e.g.
  ``N=1 is out of range: N must be an integer >= 2``.

This module imports nothing from the package but :mod:`.errors`; every other module validates
through it (``tests/test_architecture.py`` fails on a module that writes its
own integer check).

Examples
--------
>>> check_int(5, "N", minimum=2)
5
>>> check_int(True, "N", minimum=2)
Traceback (most recent call last):
...
forcenet.core.errors.ArgumentTypeError: N=True is not an integer: N must be an integer >= 2
>>> check_real("0.5", "z", low=0, high=1, low_open=True)
0.5
"""

from __future__ import annotations

import math
import numbers
from fractions import Fraction
from .errors import ArgumentError, ArgumentTypeError

__all__ = [
    "is_integer",
    "check_int",
    "check_layers",
    "check_moments",
    "MAX_MOMENTS",
    "check_grain",
    "check_real",
    "check_dps",
    "check_not_bool",
    "int_range_text",
]


def is_integer(value) -> bool:
    """True for ``int``-like values (anything with ``__index__``), False for ``bool``.

    Examples
    --------
    >>> import numpy as np
    >>> is_integer(np.int64(3)), is_integer(3.0), is_integer(False)
    (True, False, False)
    """
    return not isinstance(value, bool) and hasattr(type(value), "__index__")


def int_range_text(minimum=None, maximum=None) -> str:
    """``'>= 2'``, ``'in 2..9'``, ``'<= 5'`` or ``'any integer'``."""
    if minimum is not None and maximum is not None:
        return f"in {minimum}..{maximum}"
    if minimum is not None:
        return f">= {minimum}"
    if maximum is not None:
        return f"<= {maximum}"
    return "any integer"


def check_int(value, name: str, minimum: int | None = None, maximum: int | None = None) -> int:
    """Validate an integer argument; returns it as a Python ``int``.

    Parameters
    ----------
    value : object
        The argument as given.
    name : str
        Its name, used in the message.
    minimum, maximum : int, optional
        Inclusive bounds.

    Examples
    --------
    >>> check_int(7, "L", 2, 13)
    7
    >>> check_int(20, "L", 2, 13)
    Traceback (most recent call last):
    ...
    forcenet.core.errors.ArgumentError: L=20 is out of range: L must be an integer in 2..13
    >>> check_int(2.0, "s", 1)
    Traceback (most recent call last):
    ...
    forcenet.core.errors.ArgumentTypeError: s=2.0 is not an integer: s must be an integer >= 1
    """
    if type(value) is int and (minimum is None or value >= minimum) and (maximum is None or value <= maximum):
        return value  # the common case, decided without building the message
    allowed = int_range_text(minimum, maximum)
    if not is_integer(value):
        raise ArgumentTypeError(f"{name}={value!r} is not an integer: {name} must be an integer {allowed}")
    value = int(value.__index__())
    if (minimum is not None and value < minimum) or (maximum is not None and value > maximum):
        raise ArgumentError(f"{name}={value} is out of range: {name} must be an integer {allowed}")
    return value


def check_layers(N, *, name: str = "N", minimum: int = 2, maximum: int | None = None) -> int:
    """Validate a number of layers (an integer ``>= 2`` unless told otherwise).

    Examples
    --------
    >>> check_layers(5)
    5
    >>> check_layers(1)
    Traceback (most recent call last):
    ...
    forcenet.core.errors.ArgumentError: N=1 is out of range: N must be an integer >= 2
    """
    return check_int(N, name, minimum, maximum)


MAX_MOMENTS = 50  # the highest moment s of W^s a table route takes (forcenet table --moments)


def check_moments(moments) -> int:
    """Validate the highest moment ``s`` of ``W^s`` of a table, an integer in ``1..MAX_MOMENTS``.

    Examples
    --------
    >>> check_moments(2)
    2
    >>> check_moments(0)
    Traceback (most recent call last):
    ...
    forcenet.core.errors.ArgumentError: moments=0 is out of range: moments must be an integer in 1..50
    """
    return check_int(moments, "moments", 1, MAX_MOMENTS)


def check_grain(N: int, grain, name: str = "grain") -> tuple[int, int]:
    """Validate a grain ``(i, j)`` of the ``N``-layer triangle, ``1 <= j <= i <= N``.

    Examples
    --------
    >>> check_grain(4, (3, 2))
    (3, 2)
    >>> check_grain(4, (3, 4))
    Traceback (most recent call last):
    ...
    forcenet.core.errors.ArgumentError: grain=(3, 4) is out of range: need 1 <= i <= N=4 and 1 <= j <= i
    """
    try:
        i, j = grain
    except (TypeError, ValueError):
        raise ArgumentTypeError(f"{name}={grain!r} is not a grain: {name} must be a pair of integers (i, j)") from None
    if not (is_integer(i) and is_integer(j)):
        raise ArgumentTypeError(f"{name}={grain!r} is not a grain: {name} must be a pair of integers (i, j)")
    i, j = int(i.__index__()), int(j.__index__())
    if not (1 <= i <= N and 1 <= j <= i):
        raise ArgumentError(f"{name}={grain!r} is out of range: need 1 <= i <= N={N} and 1 <= j <= i")
    return i, j


def _interval_text(low, high, low_open, high_open) -> str:
    if low is not None and high is not None:
        return f"in {'(' if low_open else '['}{low}, {high}{')' if high_open else ']'}"
    if low is not None:
        return f"{'>' if low_open else '>='} {low}"
    if high is not None:
        return f"{'<' if high_open else '<='} {high}"
    return "finite"


def check_real(value, name: str, low=None, high=None, *, low_open: bool = False, high_open: bool = False) -> float:
    """Validate a real argument (a finite number, or a string of one); returns a float.

    For exact or high-precision work convert the original value yourself
    (inside ``mpmath.workdps``) after this check; the float is for the test
    and for floating-point callers.

    Examples
    --------
    >>> check_real(0.3, "x", -1, 1)
    0.3
    >>> check_real(float("nan"), "F", 0, low_open=True)
    Traceback (most recent call last):
    ...
    forcenet.core.errors.ArgumentError: F=nan is out of range: F must be a finite number > 0
    >>> check_real("abc", "phi")
    Traceback (most recent call last):
    ...
    forcenet.core.errors.ArgumentTypeError: phi='abc' is not a number: phi must be a finite number
    """
    allowed = _interval_text(low, high, low_open, high_open)
    allowed = "a finite number" + ("" if allowed == "finite" else f" {allowed}")
    if isinstance(value, bool):
        raise ArgumentTypeError(f"{name}={value!r} is not a number: {name} must be {allowed}")
    try:
        if isinstance(value, (str, numbers.Real)) or hasattr(type(value), "__float__"):
            x = float(Fraction(value)) if isinstance(value, Fraction) else float(value)
        else:
            raise ArgumentTypeError
    except (TypeError, ValueError, OverflowError):
        raise ArgumentTypeError(f"{name}={value!r} is not a number: {name} must be {allowed}") from None
    if isinstance(value, complex):
        raise ArgumentTypeError(f"{name}={value!r} is not a number: {name} must be {allowed}")
    bad = not math.isfinite(x)
    if not bad and low is not None:
        bad = x <= low if low_open else x < low
    if not bad and high is not None:
        bad = x >= high if high_open else x > high
    if bad:
        raise ArgumentError(f"{name}={value} is out of range: {name} must be {allowed}")
    return x


def check_not_bool(value, name: str):
    """:class:`ArgumentTypeError` for ``True``/``False`` where a number is due (they would pass as 1 and 0).

    Examples
    --------
    >>> check_not_bool(0.5, "x")
    0.5
    """
    if isinstance(value, bool):
        raise ArgumentTypeError(f"{name}={value!r} is not a number")
    return value


def check_dps(dps, name: str = "dps", minimum: int = 5, maximum: int = 10000) -> int:
    """Validate a number of decimal digits.

    Examples
    --------
    >>> check_dps(50)
    50
    """
    return check_int(dps, name, minimum, maximum)
