"""The front door for the scaling limit of the response: :func:`limit_shape` and what it returns (:class:`LimitShape`).

``forcenet.limit_shape(x, z)`` is what ``forcenet limit --x X --z Z``
computes, to the same bytes: at reduced coordinates ``x = (2j - i - 1)/N``
and ``z = i/N`` of a large triangle, the limit of ``N <W_ij>`` in the bulk,
the limit of ``<W>`` along the lattice direction ``|x| = z``, and there the
``N^(-2/3)`` edge correction and fluctuation (Tracy-Widom GUE). The
coordinates are read at full precision (a string or a
:class:`~fractions.Fraction` keeps every digit); the engines live in
:mod:`forcenet.numeric.limit_shape` (``surface``, ``edge``).

Examples
--------
>>> import forcenet
>>> r = forcenet.limit_shape("0.2", "0.6", dps=15)
>>> r.on_lattice, r.to_dict()["N_W_bulk"], r.to_dict()["W_lattice"]
(False, '1.63349516974302', '0.041742430504416')
>>> print(r.to_text().splitlines()[0])
scaling limit at x = 0.2, z = 0.6 (15 digits)
"""

from __future__ import annotations

import math
import numbers
from decimal import Decimal
from fractions import Fraction
from typing import Any

import mpmath

from forcenet.core.errors import ArgumentError, ArgumentTypeError
from forcenet.core.validation import check_dps, check_exponent, check_float_digits, check_not_bool, is_binary_float
from forcenet.numeric.limit_shape.edge import EDGE_EXPONENT, edge_amplitude, edge_sd_amplitude
from forcenet.numeric.limit_shape.surface import bulk_response, lattice_response
from forcenet.rendering import Rendered

__all__ = ["LimitShape", "limit_shape"]

EDGE_MAX_DPS = 60  # the Tracy-Widom moments of the edge law (forcenet.numeric.limit_shape.edge)


class LimitShape(Rendered):
    """The scaling limit of the response at one point ``(x, z)``: what :func:`limit_shape` returns.

    Its renderings are byte for byte those of ``forcenet limit``
    (:meth:`to_text`, :meth:`to_json`).

    Parameters
    ----------
    x, z : str
        The coordinates as given (the renderings show them so).
    exact : tuple of Fraction
        The coordinates' exact values ``(x, z)``.
    dps : int
        Decimal digits of every value.
    bulk : mpmath.mpf or None
        The limit of ``N <W>`` (None on a lattice direction, where it diverges).
    lattice : mpmath.mpf
        The limit of ``<W>`` along the lattice direction at depth ``z``, ``(1 - sqrt(z (2 - z)))/2``.
    edge : tuple of mpmath.mpf, optional
        On a lattice direction: the amplitudes of the ``N^(-2/3)`` correction of ``<W>`` and of its
        standard deviation.

    Examples
    --------
    >>> import forcenet
    >>> forcenet.limit_shape("0.6", "0.6", dps=10)
    LimitShape(x='0.6', z='0.6', dps=10, on_lattice=True)
    """

    def __init__(self, x: str, z: str, exact: tuple[Fraction, Fraction], dps: int, bulk: mpmath.mpf | None,
                 lattice: mpmath.mpf, edge: tuple[mpmath.mpf, mpmath.mpf] | None = None):
        self.x_text, self.z_text = x, z
        self.x, self.z = exact
        self.dps, self.bulk, self.lattice = dps, bulk, lattice
        self.edge_amplitude: mpmath.mpf | None = edge[0] if edge is not None else None
        self.edge_sd_amplitude: mpmath.mpf | None = edge[1] if edge is not None else None

    def __repr__(self) -> str:
        return f"LimitShape(x={self.x_text!r}, z={self.z_text!r}, dps={self.dps}, on_lattice={self.on_lattice})"

    @property
    def on_lattice(self) -> bool:
        """True on a lattice direction ``|x| = z``: for ``z < 1`` ``N <W>`` diverges there and ``<W>`` stays
        finite; at ``z = 1`` it is the floor's corner, a hard edge (:attr:`corner`).

        Examples
        --------
        >>> import forcenet
        >>> forcenet.limit_shape("-0.5", "0.5", dps=8).on_lattice, forcenet.limit_shape(1, 1).on_lattice
        (True, True)
        """
        return abs(self.x) == self.z

    @property
    def corner(self) -> bool:
        """True at the floor's corners ``|x| = z = 1``: the grains ``(N, 1)``, ``(N, N)``, whose load is exactly
        ``Beta(1, d)``, ``d = N(N-1)/2`` (notes/force_distribution.md): a hard edge, not the soft edge of ``z < 1``.

        Examples
        --------
        >>> import forcenet
        >>> forcenet.limit_shape(1, 1).corner, forcenet.limit_shape("0.5", "0.5", dps=8).corner
        (True, False)
        """
        return abs(self.x) == self.z == 1

    @property
    def edge_exponent(self) -> Fraction | None:
        """``2/3`` on a lattice direction ``z < 1`` (the Airy scale of a square-root edge, ``N^(-2/3)``), ``2`` at
        the floor's corner (``<W_(N,1)> = 1/(d + 1) = 2 N^(-2) + O(N^(-3))``, a hard edge); else None.

        Examples
        --------
        >>> import forcenet
        >>> forcenet.limit_shape("0.6", "0.6", dps=8).edge_exponent, forcenet.limit_shape(1, 1).edge_exponent
        (Fraction(2, 3), Fraction(2, 1))
        """
        if not self.on_lattice:
            return None
        if self.corner:
            return Fraction(2)

        return EDGE_EXPONENT

    def _digits(self, value: mpmath.mpf) -> str:
        return str(mpmath.nstr(value, self.dps))

    def to_dict(self) -> dict[str, Any]:
        """The values of ``forcenet limit --format json``, digits as strings.

        Returns
        -------
        dict
            ``x``, ``z`` (floats), ``dps``, ``N_W_bulk``, ``W_lattice``, ``on_lattice_direction``,
            ``edge_exponent``, ``edge_amplitude``, ``edge_sd_amplitude`` (None where they do not apply).

        Examples
        --------
        >>> import forcenet
        >>> forcenet.limit_shape("0", "1", dps=10).to_dict()["N_W_bulk"]
        '1.570796327'
        """
        edge = self.edge_amplitude is not None and self.edge_sd_amplitude is not None
        return {"x": _float(self.x_text, self.x), "z": _float(self.z_text, self.z), "dps": self.dps,
                "N_W_bulk": None if self.bulk is None else self._digits(self.bulk),
                "W_lattice": self._digits(self.lattice), "on_lattice_direction": self.on_lattice,
                "edge_exponent": str(self.edge_exponent) if edge else None,
                "edge_amplitude": self._digits(self.edge_amplitude) if self.edge_amplitude is not None else None,
                "edge_sd_amplitude": self._digits(self.edge_sd_amplitude)
                if self.edge_sd_amplitude is not None else None}

    def to_text(self) -> str:
        """The text ``forcenet limit`` prints (and a newline).

        Returns
        -------
        str

        Examples
        --------
        >>> import forcenet
        >>> print(forcenet.limit_shape("0.6", "0.6", dps=8).to_text())
        scaling limit at x = 0.6, z = 0.6 (8 digits)
          bulk:              N <W>  -> infinity (|x| = z is a lattice direction: <W> itself stays finite)
          lattice direction: <W>    -> 0.04174243  (= (1 - sqrt(z(2-z)))/2)
          edge correction:   <W> - limit = 0.21325536 N^(-2/3) + o(N^(-2/3)), argued O(1/N)
          edge fluctuation:  sd(W) = 0.10858189 N^(-2/3)  (Tracy-Widom GUE)
        """
        lines = [f"scaling limit at x = {self.x_text}, z = {self.z_text} ({self.dps} digits)"]
        if self.bulk is None:
            lines.append("  bulk:              N <W>  -> infinity (|x| = z is a lattice direction: <W> itself stays "
                         "finite)")
        elif self.corner:
            lines.append(f"  bulk:              N <W>  -> {self._digits(self.bulk)} (the floor's corner: |x| = z = 1)")
        else:
            lines.append(f"  bulk:              N <W>  -> {self._digits(self.bulk)}")
        lines.append(f"  lattice direction: <W>    -> {self._digits(self.lattice)}  (= (1 - sqrt(z(2-z)))/2)")
        if self.edge_amplitude is not None and self.edge_sd_amplitude is not None:
            rest, law = ("O(N^(-3))", "W ~ Beta(1, d) exactly: a hard edge") if self.corner else (
                "o(N^(-2/3)), argued O(1/N)", "Tracy-Widom GUE")
            lines.append(f"  edge correction:   <W> - limit = {self._digits(self.edge_amplitude)} "
                         f"N^(-{self.edge_exponent}) + {rest}")
            lines.append(f"  edge fluctuation:  sd(W) = {self._digits(self.edge_sd_amplitude)} "
                         f"N^(-{self.edge_exponent})  ({law})")
        return "\n".join(lines)


def _float(text: str, value: Fraction) -> float:
    """The coordinate as the JSON's float: the string's own reading (``-0`` stays ``-0.0``), else the exact value's."""
    try:
        return float(text)
    except ValueError:  # '1/3': correctly rounded from the exact value
        return float(value)


def _coordinate(value: Any, name: str, dps: int) -> tuple[str, Fraction, Any]:
    """``(text, exact value, what the engines take)`` of a coordinate; a binary float meets the one rule."""
    check_not_bool(value, name)
    if is_binary_float(value):
        if not math.isfinite(value):
            raise ArgumentError(f"{name}={value} is out of range: {name} must be a finite number")
        check_float_digits(value, name, dps, stacklevel=4)
        return repr(float(value)), Fraction(float(value)), Fraction(float(value))
    if isinstance(value, str):
        text = check_exponent(value, name).strip()
        try:
            exact = Fraction(text)
        except (ValueError, ZeroDivisionError):
            raise ArgumentTypeError(f"{name}={value!r} is not a number: give a decimal string ('0.25'), a fraction "
                                    "('1/4', Fraction(1, 4)) or an int") from None
        return text, exact, text  # the engines read the string inside mpmath.workdps: every digit counts
    if isinstance(value, (numbers.Rational, Decimal)):  # int, Fraction: exact
        try:
            exact = Fraction(value)
        except (ValueError, OverflowError):  # a Decimal nan or inf
            raise ArgumentError(f"{name}={value} is out of range: {name} must be a finite number") from None
        exact = Fraction(int(exact.numerator), int(exact.denominator))  # numpy's integers become Python's
        return str(value), exact, exact
    raise ArgumentTypeError(f"{name}={value!r} is not a real number: give a decimal string ('0.25'), a fraction "
                            "('1/4', Fraction(1, 4)) or an int")


NEAR_LATTICE = Fraction(1, 10**7)  # closer to |x| = z, the bulk response costs about one digit per digit of the gap
MAX_DPS = 10000  # forcenet.core.validation.check_dps's bound, the engines'


def _bulk(bulk_response: Any, x_text: str, z_text: str, x: Fraction, z: Fraction, x_value: Any, z_value: Any,
          dps: int) -> mpmath.mpf:
    """The bulk response to ``dps`` digits; within ``10^-7`` of a lattice direction computed with the gap's
    digits added (the level curve's slope cancels there) and rounded to ``dps``."""
    gap = z - abs(x)
    if not (0 < gap < NEAR_LATTICE and z < 1):  # the corners x = +-z = +-1 are no lattice direction: no divergence
        return bulk_response(x_value, z_value, dps=dps)
    digits = int((gap.denominator // gap.numerator).bit_length() * 0.30103) + 1  # ~ -log10(gap)
    if dps + digits + 3 > MAX_DPS:
        raise ArgumentError(f"x={x_text} lies within 10^-{digits - 1} of the lattice direction |x| = z = {z_text}: "
                            f"the bulk response there needs over {MAX_DPS} digits; give |x| = z exactly for the "
                            "lattice direction's law, or an x farther from it")
    value = bulk_response(x_value, z_value, dps=dps + digits + 3)
    with mpmath.workdps(dps):
        return +value


def limit_shape(x: str | Fraction | int | float | Decimal, z: str | Fraction | int | float | Decimal, *,
                dps: int = 20) -> LimitShape:
    """The scaling limit of the response of a large triangle at reduced coordinates ``(x, z)``.

    Grain ``(i, j)`` of a triangle of ``N`` layers sits at depth ``z = i/N``
    and horizontal coordinate ``x = (2j - i - 1)/N``, ``|x| <= z``. As
    ``N -> infinity``, ``N <W_ij>`` tends to the bulk response (the slope of the
    limit surface, Sec. 4.2's triangle in the continuum), except on the
    lattice directions ``|x| = z < 1``, where ``<W>`` itself tends to
    ``(1 - sqrt(z (2 - z)))/2`` and approaches it as ``N^(-2/3)``: the
    amplitudes of that correction and of the fluctuation (Tracy-Widom GUE)
    are given there. What ``forcenet limit`` prints, byte for byte.

    Parameters
    ----------
    x : str, Fraction, int or Decimal
        Horizontal coordinate, ``-z <= x <= z``, read at full precision. A
        binary float is refused where its 15 digits do not reach ``dps`` and
        accepted with a :class:`~forcenet.PrecisionWarning` where they do
        (silently when it is exactly its decimal, like ``0.5``).
    z : str, Fraction, int or Decimal
        Depth, ``0 < z <= 1``, read as ``x`` is.
    dps : int
        Decimal digits of every value, ``5..10000``; on a lattice direction
        ``5..60`` (the edge law: 20 digits take ~3 s, 60 digits minutes).
        Within ``10^-7`` of a lattice direction the bulk is computed with the
        gap's digits added (it diverges as ``(z - |x|)^(-1/3)``).

    Returns
    -------
    LimitShape
        ``bulk`` (None on a lattice direction), ``lattice``, ``on_lattice``,
        ``edge_amplitude``, ``edge_sd_amplitude``, ``edge_exponent``; ``to_text``, ``to_json``.

    Raises
    ------
    ArgumentError
        If ``z`` is not in ``(0, 1]``, ``x`` not in ``[-z, z]``, or ``dps`` out of range.
    ArgumentTypeError
        If a coordinate is not a number, or a binary float whose digits do not reach ``dps``.

    Examples
    --------
    >>> import forcenet
    >>> r = forcenet.limit_shape("0", "1", dps=30)  # the bottom's middle: N <W> -> pi/2
    >>> r.to_dict()["N_W_bulk"], r.on_lattice
    ('1.57079632679489661923132169164', False)
    >>> forcenet.limit_shape("0.9", "0.6")
    Traceback (most recent call last):
    ...
    forcenet.core.errors.ArgumentError: x=0.9 is out of range: x must lie in [-z, z] = [-0.6, 0.6]

    References
    ----------
    Ostojic (2006), Sec. 4.2 (the fully mobilized triangle, its response
    ``<W_ij>``); the limit surface of Pittel and Romik (2007) on the half
    square (Linusson, Potka and Sulzgruber 2020): notes/scaling_limit.md
    Sec. 1 (the bulk and the lattice directions) and Sec. 5 (the edge).
    """
    dps = check_dps(dps)
    z_text, z_exact, z_value = _coordinate(z, "z", dps)
    if not 0 < z_exact <= 1:
        raise ArgumentError(f"z={z_text} is out of range: z must be a finite number in (0, 1]")
    x_text, x_exact, x_value = _coordinate(x, "x", dps)
    if not abs(x_exact) <= z_exact:
        raise ArgumentError(f"x={x_text} is out of range: x must lie in [-z, z] = [-{z_text}, {z_text}]")
    on_lattice = abs(x_exact) == z_exact and z_exact < 1  # the bulk density diverges there
    corner = abs(x_exact) == z_exact == 1  # W_(N,1) ~ Beta(1, d): <W> = 1/(d + 1) = 2 N^(-2) + O(N^(-3)), the same sd

    if on_lattice:
        dps = check_dps(dps, maximum=EDGE_MAX_DPS)
    lattice = lattice_response(z_value, dps=dps)
    bulk = None if on_lattice else _bulk(bulk_response, x_text, z_text, x_exact, z_exact, x_value, z_value, dps)
    # the N^(-2/3) edge correction of <W_(i,1)> (Tracy-Widom GUE at the end of the level curves)
    edge = (edge_amplitude(z_value, dps=dps), edge_sd_amplitude(z_value, dps=dps)) if on_lattice else None
    if corner:  # sd Beta(1, d) = sqrt(d / (d + 2)) / (d + 1) = 2 N^(-2) (1 + O(1/N)), d = N(N-1)/2
        edge = (mpmath.mpf(2), mpmath.mpf(2))
    return LimitShape(x_text, z_text, (x_exact, z_exact), dps, bulk, lattice, edge)
