"""The exception family of forcenet: one base, argument errors that are also ``ValueError``/``TypeError``.

The rule (notes/architecture.md, "Errors"): the library raises only this family
for an expected failure (a bad argument, a refused plan, a sampler that cannot
judge its own error bar); the command line catches only this family and turns
it into one line on stderr and exit code 2.  Anything else that escapes is a
bug: exit code 1, ``forcenet: internal error``, the traceback under
``--debug`` or in a file named on stderr.

* :class:`ForcenetError` -- the base of every expected failure;
* :class:`ArgumentError` -- a value out of range or otherwise not allowed;
  also a ``ValueError``, so ``except ValueError`` keeps working;
* :class:`ArgumentTypeError` -- an argument of the wrong type; also a
  ``TypeError``;
* :class:`ConvergenceError` -- an iterative method did not converge for the
  arguments given (choose others); also a ``RuntimeError``;
* :class:`ClusterError` -- a cluster run cannot go on (its scheduler went
  away, every worker left, or the workers cannot import forcenet).

Beside the family, one warning: :class:`PrecisionWarning` (a ``UserWarning``),
for a binary float accepted where an exact number was expected because its
digits suffice for the precision asked
(:func:`forcenet.core.validation.check_float_digits`, the one rule).

The family is exported from the top of the package (``forcenet.ForcenetError``,
...).  This module imports nothing.

Examples
--------
>>> from forcenet.core.validation import check_int
>>> try:
...     check_int(1, "N", minimum=2)
... except ForcenetError as exc:
...     print(type(exc).__name__, isinstance(exc, ValueError), exc)
ArgumentError True N=1 is out of range: N must be an integer >= 2
"""

from __future__ import annotations

__all__ = ["ForcenetError", "ArgumentError", "ArgumentTypeError", "ConvergenceError", "ClusterError", "PrecisionWarning"]


class ForcenetError(Exception):
    """The base of every expected failure raised by forcenet (the command line: one line, exit code 2).

    Catch it to handle every expected failure at once; anything else forcenet raises is a bug.

    Examples
    --------
    >>> import forcenet
    >>> try:
    ...     forcenet.table(1)
    ... except forcenet.ForcenetError as exc:
    ...     print(type(exc).__name__, "-", exc)
    ArgumentError - N=1 is out of range: N must be an integer >= 2
    """


class ArgumentError(ForcenetError, ValueError):
    """An argument's value is out of range or not allowed; the message names the argument and the range.

    ``argument`` names the argument at fault where one alone is (``"N"``), so the command line can report the
    error as its parser would, against the option (``argument --N: ...``), when it left that check to the front door.

    Parameters
    ----------
    *args : object
        The message (one line: the argument, its range and what would work), as for any exception.
    argument : str, optional
        The argument at fault, without dashes (``"N"``); None when the message names several.

    Examples
    --------
    >>> ArgumentError("N=1 is out of range: N must be an integer >= 2", argument="N").argument
    'N'
    """

    def __init__(self, *args: object, argument: str | None = None) -> None:
        super().__init__(*args)
        self.argument = argument


class ArgumentTypeError(ForcenetError, TypeError):
    """An argument has the wrong type; the message names the argument and the type expected.

    Examples
    --------
    >>> import forcenet
    >>> try:
    ...     forcenet.count(1.5)
    ... except TypeError as exc:  # also a TypeError, so ``except TypeError`` keeps working
    ...     print(isinstance(exc, forcenet.ArgumentTypeError), exc)
    True N=1.5 is not an integer: N must be an integer >= 2
    """


class ConvergenceError(ForcenetError, RuntimeError):
    """An iterative method (Newton, a continuation) did not converge for these arguments; the message says where.

    Examples
    --------
    >>> import numpy as np
    >>> from forcenet.numeric.chicken_wire.bethe import newton_polish
    >>> w = np.exp(1j * np.linspace(-1, 1, 4))  # one Newton step from a poor start: the Bethe equations
    >>> try:
    ...     newton_polish(12, w, np.array([5.0 + 5j, 5.0 - 5j]), iterations=1)
    ... except ConvergenceError as exc:
    ...     print(isinstance(exc, RuntimeError), str(exc).split(":")[0])
    True Newton did not converge for L=12, n=4, m=2
    """


class ClusterError(ForcenetError):
    """A cluster run cannot go on: the scheduler went away, every worker left, or workers cannot run forcenet.

    Also a local process pool's worker that died or could not start (``concurrent.futures``'
    ``BrokenProcessPool``, chained as the cause).

    Examples
    --------
    >>> issubclass(ClusterError, ForcenetError)  # the command line: one line, exit code 2
    True
    """


class PrecisionWarning(UserWarning):
    """A binary float was accepted where an exact number was expected: its digits suffice for the precision asked,
    but the result is the value at the float (pass a string or a ``Fraction`` for the number you mean).

    Examples
    --------
    >>> import warnings
    >>> import forcenet
    >>> with warnings.catch_warnings(record=True) as caught:
    ...     warnings.simplefilter("always")
    ...     value = forcenet.entropy(phi=0.3, dps=15)
    >>> [w.category.__name__ for w in caught]
    ['PrecisionWarning']
    >>> forcenet.entropy(phi=0.3, dps=40)  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    forcenet.core.errors.ArgumentTypeError: phi=0.3 is a binary float...
    """
