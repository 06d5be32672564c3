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
>>> check_float_digits(1 / 6, "Q", dps=40)
Traceback (most recent call last):
...
forcenet.core.errors.ArgumentTypeError: Q=0.16666666666666666 is a binary float, good to 15 significant digits, but dps=40 digits were asked: pass '1/6' or Fraction(1, 6) (a string or a Fraction keeps every digit)
"""

from __future__ import annotations

import math
import numbers
import warnings
from concurrent.futures import Executor
from fractions import Fraction
from typing import Any, TypeVar

from .errors import ArgumentError, ArgumentTypeError, PrecisionWarning

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
    "is_binary_float",
    "float_digits",
    "check_float_digits",
    "check_rational",
    "check_exponent",
    "available_memory",
    "check_fits_memory",
    "check_seed",
    "check_executor",
    "check_progress",
]

T = TypeVar("T")  # a value returned unchanged by its check


def is_integer(value: object) -> bool:
    """True for ``int``-like values (anything with ``__index__``), False for ``bool``.

    Examples
    --------
    >>> import numpy as np
    >>> is_integer(np.int64(3)), is_integer(3.0), is_integer(False)
    (True, False, False)
    """
    return not isinstance(value, bool) and hasattr(type(value), "__index__")


def int_range_text(minimum: int | None = None, maximum: int | None = None) -> str:
    """``'>= 2'``, ``'in 2..9'``, ``'<= 5'`` or ``'any integer'``."""
    if minimum is not None and maximum is not None:
        return f"in {minimum}..{maximum}"
    if minimum is not None:
        return f">= {minimum}"
    if maximum is not None:
        return f"<= {maximum}"
    return "any integer"


def check_int(value: Any, name: str, minimum: int | None = None, maximum: int | None = None) -> int:
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
        raise ArgumentError(f"{name}={value} is out of range: {name} must be an integer {allowed}", argument=name)
    return value


def check_layers(N: Any, *, name: str = "N", minimum: int = 2, maximum: int | None = None) -> int:
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


def check_moments(moments: Any) -> int:
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


def check_grain(N: int, grain: Any, name: str = "grain") -> tuple[int, int]:
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


def _interval_text(low: float | None, high: float | None, low_open: bool, high_open: bool) -> str:
    if low is not None and high is not None:
        return f"in {'(' if low_open else '['}{low}, {high}{')' if high_open else ']'}"
    if low is not None:
        return f"{'>' if low_open else '>='} {low}"
    if high is not None:
        return f"{'<' if high_open else '<='} {high}"
    return "finite"


def check_real(value: Any, name: str, low: float | None = None, high: float | None = None, *, low_open: bool = False, high_open: bool = False) -> float:
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


def check_not_bool(value: T, name: str) -> T:
    """:class:`ArgumentTypeError` for ``True``/``False`` where a number is due (they would pass as 1 and 0).

    Examples
    --------
    >>> check_not_bool(0.5, "x")
    0.5
    """
    if isinstance(value, bool):
        raise ArgumentTypeError(f"{name}={value!r} is not a number")
    return value


def check_dps(dps: Any, name: str = "dps", minimum: int = 5, maximum: int = 10000) -> int:
    """Validate a number of decimal digits.

    Examples
    --------
    >>> check_dps(50)
    50
    """
    return check_int(dps, name, minimum, maximum)


# ------------------------------------------------- binary floats where digits matter (one rule)


def is_binary_float(value: object) -> bool:
    """True for a binary floating-point number: ``float`` (``numpy.float64`` included) and every ``numpy.floating``.

    Examples
    --------
    >>> import numpy as np
    >>> is_binary_float(0.5), is_binary_float(np.float32(0.5)), is_binary_float("0.5"), is_binary_float(Fraction(1, 2))
    (True, True, False, False)
    """
    if isinstance(value, float):
        return True
    kind = type(value)
    return kind.__module__ == "numpy" and any(base.__name__ == "floating" for base in kind.__mro__)


def float_digits(value: float) -> int:
    """Significant decimal digits a binary float of ``value``'s type carries exactly: 15 for a double
    (``sys.float_info.dig``), 6 for ``numpy.float32``, 3 for ``numpy.float16``, 18 for an x87 ``longdouble``.

    Examples
    --------
    >>> import numpy as np
    >>> float_digits(0.1), float_digits(np.float32(0.1)), float_digits(np.float16(0.1))
    (15, 6, 3)
    """
    if isinstance(value, float):
        return 15
    # numpy's half, single, double; a longer numpy float is the x87 extended type (64-bit mantissa) at least
    return {2: 3, 4: 6, 8: 15}.get(int(getattr(value, "itemsize", 8)), 18)


def _shortest_text(value: float) -> str:
    """The shortest decimal that reads back as ``value`` (``repr``; numpy's ``str`` for its own types)."""
    return repr(float(value)) if isinstance(value, float) else str(value)


def _exact_fix(value: float) -> str:
    """What to pass instead of the float ``value``: the small fraction it rounds (as a decimal string when it is
    one), else its shortest decimal as a string."""
    exact = Fraction(float(value))
    guess = exact.limit_denominator(10**4)
    if guess != exact and type(value)(float(guess)) == value:
        q = guess.denominator
        while q % 2 == 0:
            q //= 2
        while q % 5 == 0:
            q //= 5
        text = _shortest_text(value) if q == 1 and not isinstance(value, float) else (
            repr(float(guess)) if q == 1 else str(guess))
        return f"'{text}' or Fraction({guess.numerator}, {guess.denominator})"
    text = _shortest_text(value)
    return f"'{text}' or Fraction('{text}')"


def check_float_digits(value: Any, name: str, dps: int | None = None, *, stacklevel: int = 2) -> Any:
    """The one rule for a binary float given where an exact (rational) number is expected.

    A float is a binary fraction of 53 bits (about 17 significant digits, of
    which 15 survive a round trip through decimal); ``1/6`` typed in Python
    is ``0.1666666666666666574...``, wrong from the 17th digit on.

    * not a binary float (int, ``Fraction``, a string, sympy, ``mpmath.mpf``):
      returned unchanged, this rule does not apply;
    * a float exactly equal to its shortest decimal (``0.5``, ``0.375``,
      ``2.0``, ``1e20``: dyadic and short): returned unchanged, nothing is lost;
    * otherwise, if ``dps`` digits are asked and the float's type carries
      them (``dps <= 15`` for a double, :func:`float_digits`): accepted with a
      :class:`~forcenet.core.errors.PrecisionWarning` naming the exact
      alternative (the result is good to ``dps`` digits, but is the result at
      the binary value, not at the number you meant);
    * otherwise (more digits asked, or ``dps=None``: an exact result) refused
      with :class:`~forcenet.core.errors.ArgumentTypeError` naming the fix
      (``pass '1/6' or Fraction(1, 6)``).

    Parameters
    ----------
    value : object
        The argument as given.
    name : str
        Its name, used in the messages.
    dps : int, optional
        The decimal digits of the result asked for; None for an exact result.
    stacklevel : int
        Where the warning points, as for :func:`warnings.warn` called by the caller (2: the caller's caller).

    Returns
    -------
    object
        ``value`` itself (the caller converts it as before).

    Raises
    ------
    ArgumentTypeError
        For an inexact float where its digits do not suffice.

    Examples
    --------
    >>> check_float_digits(0.375, "Q", dps=100)  # exactly 3/8: nothing lost
    0.375
    >>> check_float_digits("1/6", "Q", dps=100)
    '1/6'
    >>> import warnings
    >>> with warnings.catch_warnings(record=True) as caught:
    ...     warnings.simplefilter("always")
    ...     check_float_digits(0.3, "phi", dps=15)
    ...     print(caught[0].category.__name__)
    0.3
    PrecisionWarning
    >>> check_float_digits(0.1, "q", None)
    Traceback (most recent call last):
    ...
    forcenet.core.errors.ArgumentTypeError: q=0.1 is a binary float (0.1000000000000000055511151231257827...), not the exact number, and the result is exact: pass '0.1' or Fraction(1, 10) (a string or a Fraction keeps every digit)
    """
    if not is_binary_float(value) or not math.isfinite(value):
        return value  # not this rule's (nan and inf are refused by the range checks)
    text = _shortest_text(value)
    if Fraction(float(value)) == Fraction(text):
        return value  # the float is exactly the decimal it prints as
    digits = float_digits(value)
    fix = _exact_fix(value)
    if dps is not None and dps <= digits:
        warnings.warn(PrecisionWarning(
            f"{name}={text} is a binary float: the result is good to the dps={dps} digits asked, but it is "
            f"the value at the float, not at the number you meant; for that pass {fix}"), stacklevel=stacklevel + 1)
        return value
    if dps is None:
        binary = f"{Fraction(float(value)).numerator / Fraction(float(value)).denominator:.34g}"
        raise ArgumentTypeError(f"{name}={text} is a binary float ({binary}...), not the exact number, and the result "
                                f"is exact: pass {fix} (a string or a Fraction keeps every digit)")
    raise ArgumentTypeError(f"{name}={text} is a binary float, good to {digits} significant digits, but dps={dps} digits "
                            f"were asked: pass {fix} (a string or a Fraction keeps every digit)")


MAX_EXPONENT = 4000  # a number string's decimal exponent: Fraction("1e999999999") would build 10**999999999


def check_exponent(text: str, name: str) -> str:
    """``text`` unchanged unless its decimal exponent (``"1e-5"``) passes ``+-MAX_EXPONENT``: parsing it would
    build an integer of that many digits (no answer in minutes, or out of memory).

    Examples
    --------
    >>> check_exponent("2.5e-3", "x")
    '2.5e-3'
    >>> check_exponent("1e99999999", "x")
    Traceback (most recent call last):
    ...
    forcenet.core.errors.ArgumentError: x='1e99999999' is out of range: its decimal exponent passes +-4000
    """
    _, _, exponent = text.strip().lower().partition("e")
    if exponent.lstrip("+-").isdigit() and abs(int(exponent)) > MAX_EXPONENT:
        raise ArgumentError(f"{name}={text!r} is out of range: its decimal exponent passes +-{MAX_EXPONENT}")
    return text


def check_rational(value: Any, name: str) -> Fraction:
    """An exact rational argument as a ``Fraction``: an int, a ``Fraction``, a string such as ``'1/6'`` or
    ``'0.3'``, a sympy Rational; a binary float only when it is exactly its decimal (:func:`check_float_digits`).

    Examples
    --------
    >>> check_rational("1/6", "Q"), check_rational(0.25, "Q")
    (Fraction(1, 6), Fraction(1, 4))
    >>> check_rational(True, "Q")
    Traceback (most recent call last):
    ...
    forcenet.core.errors.ArgumentTypeError: Q=True is not a number: Q must be an exact rational (an int, a Fraction or a string such as '1/6')
    """
    kind = "an exact rational (an int, a Fraction or a string such as '1/6')"
    if isinstance(value, bool) or isinstance(value, complex):
        raise ArgumentTypeError(f"{name}={value!r} is not a number: {name} must be {kind}")
    check_float_digits(value, name, None)
    if is_binary_float(value) and not math.isfinite(value):
        raise ArgumentError(f"{name}={value} is out of range: {name} must be a finite number")
    try:
        if hasattr(value, "p") and hasattr(value, "q") and not isinstance(value, str):  # sympy Rational/Integer
            return Fraction(int(value.p), int(value.q))
        if isinstance(value, str):
            check_exponent(value, name)
        return Fraction(float(value)) if is_binary_float(value) else Fraction(value)
    except (TypeError, ValueError, ZeroDivisionError):
        raise ArgumentTypeError(f"{name}={value!r} is not a number: {name} must be {kind}") from None


def available_memory() -> int | None:
    """Bytes of memory available now (Linux ``MemAvailable``), None where unknown: the bound a Python function's
    argument is checked against before work that could not fit (the command line's plans use the same figure).

    Examples
    --------
    >>> memory = available_memory()
    >>> memory is None or memory > 0
    True
    """
    try:
        with open("/proc/meminfo") as handle:
            for line in handle:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        return None
    return None


def check_fits_memory(nbytes: int, what: str, fix: str) -> None:
    """:class:`ArgumentError` before the work if ``what`` needs more than the memory available now; ``fix`` says
    what would fit.

    Examples
    --------
    >>> check_fits_memory(10**30, "an array of 1e29 floats", "ask for fewer")
    Traceback (most recent call last):
    ...
    forcenet.core.errors.ArgumentError: an array of 1e29 floats needs ~9.31e+20 GiB of memory, more than is available: ask for fewer
    """
    memory = available_memory()
    if nbytes > (memory if memory is not None else 2**50):
        raise ArgumentError(f"{what} needs ~{nbytes / 2**30:.3g} GiB of memory, more than is available: {fix}")


def check_seed(seed: T, name: str = "seed") -> T | int:
    """A seed for ``numpy.random.default_rng``: None, a ``numpy.random.Generator`` (or ``SeedSequence``), or an
    integer ``>= 0`` (numpy types included; never ``bool`` or a float).

    Examples
    --------
    >>> check_seed(7), check_seed(None)
    (7, None)
    >>> check_seed(-1)
    Traceback (most recent call last):
    ...
    forcenet.core.errors.ArgumentError: seed=-1 is out of range: seed must be an integer >= 0
    """
    if seed is None or type(seed).__name__ in ("Generator", "SeedSequence", "BitGenerator") or hasattr(seed, "bit_generator"):
        return seed
    return check_int(seed, name, 0)


def check_executor(executor: T, name: str = "executor") -> T:
    """``executor`` unchanged when it can run tasks: None, a ``concurrent.futures.Executor`` not shut down, or a
    Dask ``Client`` (``get_executor()``) not closed.

    Examples
    --------
    >>> from concurrent.futures import ThreadPoolExecutor
    >>> pool = ThreadPoolExecutor(1)
    >>> check_executor(pool) is pool
    True
    >>> pool.shutdown()
    >>> check_executor(pool)  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    forcenet.core.errors.ArgumentError: executor=<...ThreadPoolExecutor...> is shut down: give a running executor, or None (this machine's processes)
    """
    if executor is None:
        return executor
    if not isinstance(executor, Executor) and not callable(getattr(executor, "get_executor", None)):
        raise ArgumentTypeError(f"{name}={executor!r} is not a concurrent.futures.Executor (nor a Dask Client)")
    # the standard pools' flags (ProcessPoolExecutor, ThreadPoolExecutor), a Dask Client's status
    if getattr(executor, "_shutdown_thread", False) is True or getattr(executor, "_shutdown", False) is True \
            or getattr(executor, "status", None) in ("closing", "closed"):
        raise ArgumentError(f"{name}={executor!r} is shut down: give a running executor, or None (this machine's "
                            "processes)")
    return executor


def check_progress(progress: T, name: str = "progress") -> T:
    """``progress`` unchanged when a run can report to it: None, a bool (``True``: a progress bar) or a callable
    (``progress(k)``).

    Examples
    --------
    >>> check_progress(True), check_progress(print) is print
    (True, True)
    >>> check_progress("yes")
    Traceback (most recent call last):
    ...
    forcenet.core.errors.ArgumentTypeError: progress='yes' is neither a callable nor a bool: give progress(k), True (a progress bar) or None
    """
    if progress is not None and not isinstance(progress, bool) and not callable(progress):
        raise ArgumentTypeError(f"{name}={progress!r} is neither a callable nor a bool: give progress(k), True (a "
                                "progress bar) or None")
    return progress
