"""The front door of the chicken-wire model's isotropic line (Sec. 7.4): the entropy and its companions.

:func:`isotropic_point` (at ``phi`` or at the density ``Q``) and :func:`isotropic_maximum` (the maxima
per site and per tiling vertex) evaluate the closed forms (7.1)-(7.4) to any number of digits, and, if
asked, the independent Bethe-ansatz value of the entropy (``forcenet entropy``).  Their plans
(:class:`IsotropicPlan`) validate the point once, announce the cost (the closed forms' and the Bethe
ansatz's, one announcement) or refuse it, and run as planned.  The engines stay in
:mod:`forcenet.numeric.chicken_wire` (``isotropic``, ``isotropic_bethe``); the result is
:class:`forcenet.chicken_wire_results.IsotropicEntropy`.

Examples
--------
>>> import forcenet, mpmath
>>> mpmath.nstr(forcenet.isotropic_point(phi=0, dps=20)["s_per_tiling_vertex"], 20)  # the twelvefold point
'0.12005524931854160783'
>>> p = forcenet.isotropic_point_plan(Q="1/6", bethe=True)
>>> p.cost.ticks, p.runnable
(1, True)
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from decimal import Decimal
from fractions import Fraction
from typing import Any

import mpmath

from forcenet.chicken_wire_results import BetheValue, IsotropicEntropy
from forcenet.core.errors import ArgumentError, ArgumentTypeError, ConvergenceError
from forcenet.core.plan import Plan, combine
from forcenet.core.precision import check_within_pi, to_mpf, within_pi
from forcenet.core.validation import check_float_digits, check_not_bool, is_binary_float, is_integer
from forcenet.costed_plans import CostedPlan, Progress
from forcenet.numeric.chicken_wire import isotropic as iso
from forcenet.numeric.chicken_wire.isotropic import closed_form_plan
from forcenet.numeric.chicken_wire.isotropic_bethe import isotropic_entropy, isotropic_entropy_plan

__all__ = ["IsotropicPlan", "isotropic_point_plan", "isotropic_point", "isotropic_maximum_plan", "isotropic_maximum"]


# ------------------------------------------------------------------------ the isotropic line

# the leading term of (7.3) is shown as an approximation of v where it is one: within 1 % of v
SERIES_TOLERANCE = 0.01


@dataclass(frozen=True, repr=False)  # the plan's own words: CostedPlan.__repr__
class IsotropicPlan(CostedPlan):
    """A checked request for the quantities on the isotropic line, with its cost.

    What :func:`isotropic_point_plan` and :func:`isotropic_maximum_plan` return.

    Parameters
    ----------
    dps : int
        Decimal digits.
    cost : forcenet.core.plan.Plan
        The closed forms' cost (and the Bethe ansatz's), or the refusal.
    phi, Q : optional
        The point (exactly one; neither for the maxima), as validated: strings and Fractions keep every digit.
    side : str or number, optional
        The hexagon side ``l`` of Eq. (7.4) (None: 1).
    bethe : bool
        Also the Bethe-ansatz value of ``v``.
    L_max : int
        Largest Bethe-ansatz width.

    Examples
    --------
    >>> import forcenet
    >>> p = forcenet.isotropic_maximum_plan(dps=1000)
    >>> p.cost.what, round(p.seconds, 6)
    ('closed forms (7.1)-(7.4) to 1000 digits', 3.1)
    """

    dps: int
    cost: Plan
    phi: Any = None
    Q: Any = None
    side: Any = None
    bethe: bool = False
    L_max: int = 240

    @property
    def maximum(self) -> bool:
        """True for the maxima (:func:`isotropic_maximum_plan`), False for a point.

        Examples
        --------
        >>> import forcenet
        >>> forcenet.isotropic_maximum_plan().maximum
        True
        """
        return self.phi is None and self.Q is None

    def run(self, progress: Progress | bool | None = None) -> IsotropicEntropy:
        """Evaluate the closed forms (and the Bethe ansatz) this plan describes.

        Parameters
        ----------
        progress : callable, bool or None
            ``progress(1)`` once all is done; ``True``: a progress bar (tqdm).

        Returns
        -------
        IsotropicEntropy

        Raises
        ------
        ArgumentError
            If the plan is refused.
        ConvergenceError
            If the Bethe ansatz loses the ground state (``Bethe ansatz: ...``).

        Examples
        --------
        >>> import forcenet
        >>> import mpmath
        >>> mpmath.nstr(forcenet.isotropic_point_plan(phi=0, dps=12).run()["Q"], 12)  # 1/2 - 1/(2 sqrt3)
        '0.211324865405'
        """
        self.check()
        with self._ticks(progress, "entropy") as tick:
            rows = self._maximum_rows() if self.maximum else self._closed_form_rows()
            value = self._bethe(rows) if self.bethe else None
            if tick:
                tick()
        return IsotropicEntropy(self.dps, tuple(rows), value)

    def _inside(self) -> bool:
        """Whether the point is strictly inside ``0 < Q < 1/3`` (``|phi| < pi/2``), decided exactly."""
        if self.Q is not None:
            return bool(0 < self.Q < Fraction(1, 3))
        return within_pi(self.phi, strict=True, name="phi")

    def _closed_form_rows(self) -> list[tuple[str, str, Any]]:
        """Every quantity at the point, named by what it is (mpmath values)."""
        dps = self.dps
        point = {"phi": self.phi} if self.phi is not None else {"Q": self.Q}
        if self.phi is not None:
            Q = iso.density_Q(self.phi, dps)
            with mpmath.workdps(dps):
                phi_value = _mpf(self.phi)
        else:
            with mpmath.workdps(dps):
                Q = _mpf(self.Q)
            phi_value = iso.phi_of_density(self.Q, dps)
        eps = iso.eps_of(**point, dps=dps)
        rows = [
            ("phi", "parameter of Eqs. (7.1)-(7.2)", phi_value),
            ("Q", "bonds per site in each of the three directions, Eq. (7.2)", Q),
            ("v_per_site", "entropy per chicken-wire site, Eq. (7.1)", iso.entropy(**point, dps=dps)),
            ("empty_per_site", "empty sites per site = square-triangle tiling vertices per site, 1 - 3Q + 3Q^2",
             iso.empty_density(**point, dps=dps)),
            ("s_per_tiling_vertex", "entropy per square-triangle tiling vertex, v / e", iso.tiling_entropy(**point, dps=dps)),
        ]
        if self._inside():
            rows.append(("mu", "log-fugacity of each bond direction, -(1/3) dv/dQ", iso.chemical_potential(**point, dps=dps)))
        if eps > 0:
            rows.append(("eps", "pi/2 - phi", eps))
            rows.append(self._series_row(eps, rows[2][2]))
        side = "1" if self.side is None else self.side
        rows.append(("g_per_grain_7_4", "entropy per grain in the continuum limit, Eq. (7.4) corrected: "
                     f"log(6 l) - 3/2 at l = {side}", iso.entropy_per_grain(side, dps)))
        return rows

    def _series_row(self, eps: Any, v: Any) -> tuple[str, str, Any]:
        """The leading term of (7.3) at ``eps``, described with its deviation from ``v`` where it is no approximation."""
        series = iso.leading_series_at(eps, self.dps, self.Q)
        what = "approximation of v by the leading term of Eq. (7.3), corrected: eps^2 (log(108/eps^2) - 3)/18"
        if not abs(series - v) <= SERIES_TOLERANCE * v:
            what += (f"; NOT VALID here: eps = {mpmath.nstr(eps, 3)} is not small, it differs from v by "
                     f"{mpmath.nstr(abs(series - v), 2)}")
        return ("v_series_7_3", what, series)

    def _maximum_rows(self) -> list[tuple[str, str, Any]]:
        m = iso.maximum(self.dps)
        return [
            ("v_max_per_site", "maximal entropy per chicken-wire site (where mu = 0)", m.v_max),
            ("Q_max", "its bond density per direction", m.Q_max),
            ("phi_max", "its parameter phi", m.phi_max),
            ("s_max_per_tiling_vertex", "maximal entropy per square-triangle tiling vertex, "
             "log 108 - 2 sqrt3 log(2 + sqrt3)", m.s_max),
            ("Q0", "its bond density per direction (phi = 0, the twelvefold point), (3 - sqrt3)/6", m.Q0),
            ("v_per_site_at_Q0", "entropy per chicken-wire site there (half of s_max)", m.v_at_Q0),
            ("empty_per_site_at_Q0", "tiling vertices per site there", m.empty_per_site),
            ("Y_per_site_at_Q0", "Y vertices (one kind) per site there, 3 Q0^2", m.y_per_site),
            ("squares_per_tiling_vertex", "squares per tiling vertex there", m.squares_per_vertex),
            ("triangles_per_tiling_vertex", "triangles per tiling vertex there (half upright, half rotated)",
             m.triangles_per_vertex),
            ("squares_per_triangle", "squares per triangle there, sqrt3/4", m.squares_per_triangle),
        ]

    def _bethe(self, rows: list[tuple[str, str, Any]]) -> BetheValue:
        """The independent Bethe-ansatz value of v at the point (float, with its error)."""
        Q = self.Q if self.Q is not None else float(dict((key, value) for key, _, value in rows)["Q"])
        try:
            v, err, densities = isotropic_entropy(Q, self.L_max)
        except ConvergenceError as exc:
            raise ConvergenceError(f"Bethe ansatz: {exc}") from None
        return BetheValue(v, err, tuple(densities), self.L_max)


def _mpf(value: str | Fraction) -> Any:
    """A validated point as an mpf at the current precision (a Fraction divided exactly)."""
    return mpmath.mpf(value.numerator) / value.denominator if isinstance(value, Fraction) else mpmath.mpf(value)


def _real(value: Any, name: str, dps: int, keep_text: bool = True) -> str | Fraction:
    """A real argument as the engines take it, exactly: a string kept as given (stripped; ``keep_text=False``: read
    as a Fraction), any other number as its exact Fraction; a binary float by the one rule (refused where its
    digits do not reach ``dps``, else accepted at its exact value with a warning, once)."""
    if isinstance(value, str):
        text = value.strip()
        if keep_text:
            return text
        try:
            q = Fraction(text) if text.isascii() else None
        except (ValueError, ZeroDivisionError):
            q = None
        if q is None:
            raise ArgumentTypeError(f"{name}={value!r} is not a real number")
        return q
    check_not_bool(value, name)
    if isinstance(value, Fraction) or is_integer(value):
        return Fraction(value) if isinstance(value, Fraction) else Fraction(int(value))
    finite = (math.isfinite(value) if is_binary_float(value) or isinstance(value, Decimal)
              else mpmath.isfinite(value) if isinstance(value, mpmath.mpf) else None)
    if finite is None:
        raise ArgumentTypeError(f"{name}={value!r} is not a real number")
    if not finite:
        raise ArgumentError(f"{name}={value!r} is out of range: {name} must be a finite real number")
    if is_binary_float(value):
        check_float_digits(value, name, dps, stacklevel=4)
        return Fraction(float(value))
    if isinstance(value, Decimal):
        return Fraction(value)
    return Fraction(int(value.man)) * Fraction(2) ** int(value.exp)  # an mpf: a dyadic rational, exactly


def isotropic_point_plan(phi: Any = None, Q: Any = None, *, dps: int = 50, side: Any = None, bethe: bool = False,
                         L_max: int | None = None) -> IsotropicPlan:
    """What :func:`isotropic_point` will cost at this point, or why it cannot run; nothing is computed.

    Parameters
    ----------
    phi : str, Fraction, int or float, optional
        The parameter of Eqs. (7.1)-(7.2), ``-pi/2 <= phi <= pi/2`` (compared with pi/2 at the digits given).
    Q : str, Fraction, int or float, optional
        The bond density per direction, ``0 <= Q <= 1/3`` (give exactly one of ``phi`` and ``Q``).
    dps : int
        Decimal digits, ``5..10000``.
    side : str, Fraction, int or float, optional
        The hexagon side ``l`` (force scale) of Eq. (7.4), ``> 0`` (default 1).
    bethe : bool
        Also the independent Bethe-ansatz value of ``v`` (needs ``0 < Q < 1/3``).
    L_max : int, optional
        Largest Bethe-ansatz width, ``60..1200`` (default 240; only with ``bethe=True``).

    Returns
    -------
    IsotropicPlan
        Its cost; refused (naming ``Q`` or ``L_max``) where the Bethe ansatz cannot reach the point.

    Raises
    ------
    ArgumentError
        If the point, ``dps`` or ``side`` is out of range, or ``L_max`` is given without ``bethe``.
    ArgumentTypeError
        If neither or both of ``phi`` and ``Q`` are given, or a value is not a number (a binary float
        where its digits do not reach ``dps``).

    Examples
    --------
    >>> import forcenet
    >>> forcenet.isotropic_point_plan(Q="1/3", bethe=True).refusal
    'Q=0.333333 is out of range: the Bethe route needs 0 < Q < 1/3'
    >>> forcenet.isotropic_point_plan(phi="1.5707963267948967")
    Traceback (most recent call last):
    ...
    forcenet.core.errors.ArgumentError: phi=1.5707963267948967 is out of range: phi must lie in [-pi/2, pi/2] = [-1.5707963267948966192..., 1.5707963267948966192...]

    References
    ----------
    Eqs. (7.1)-(7.4) and Sec. 7.4.2 (the Bethe ansatz).
    """
    closed = _closed_form_plan(dps, maximum=False)  # checks dps (once: the engines' checks follow)
    dps = int(dps)
    if (phi is None) == (Q is None):
        raise ArgumentTypeError("give exactly one of phi= and Q=")
    if L_max is not None and not bethe:
        raise ArgumentError(f"L_max={L_max} sets the widths of bethe=True: pass bethe=True or drop L_max")
    L_max = 240 if L_max is None else L_max
    if phi is not None:
        phi = check_within_pi(_real(phi, "phi", dps), "phi")
    else:
        given = Q
        Q = _real(Q, "Q", dps, keep_text=False)
        if not 0 <= Q <= Fraction(1, 3):
            raise ArgumentError(f"Q={_shown(given)} is out of range: the density per direction Q must lie in [0, 1/3]")
    if side is not None:
        side = _real(side, "side", dps)
        with mpmath.workdps(dps):
            if not to_mpf(side, "side") > 0:
                raise ArgumentError(f"side={side} is out of range: the hexagon side l of Eq. (7.4) must be "
                                    "a finite number > 0")
    return IsotropicPlan(dps, _cost(closed, Q if isinstance(Q, Fraction) else None, bool(bethe), L_max),
                         phi, Q, side, bool(bethe), L_max)


def _shown(value: Any) -> str:
    """A value in a message as the caller gave it (a string without the blanks around it)."""
    return value.strip() if isinstance(value, str) else str(value)


def _closed_form_plan(dps: int, maximum: bool) -> Plan:
    return closed_form_plan(dps, maximum=maximum)


def _cost(closed: Plan, Q: Fraction | None = None, bethe: bool = False, L_max: int = 240) -> Plan:
    """The closed forms' plan, and the Bethe ansatz's after it: one announcement, as ``forcenet entropy`` makes it."""
    plans = [closed]
    if bethe:
        plans.append(isotropic_entropy_plan(Q, L_max))
    return combine(plans[-1].what if bethe else closed.what, plans, plans[-1].unit)


def isotropic_point(phi: Any = None, Q: Any = None, *, dps: int = 50, side: Any = None, bethe: bool = False,
                    L_max: int | None = None, progress: Progress | bool | None = None) -> IsotropicEntropy:
    """The entropy and its companions at one point of the isotropic line, to ``dps`` digits, as ``forcenet entropy``.

    The rows: ``phi``, ``Q``, the entropy per site ``v_per_site`` (7.1), empty sites (tiling vertices)
    per site, the entropy per tiling vertex, the log-fugacity ``mu`` (inside ``0 < Q < 1/3``), ``eps =
    pi/2 - phi`` and the leading term of (7.3) (where ``eps > 0``; flagged where it is no
    approximation), and the entropy per grain of (7.4) corrected at side ``l``.

    Parameters
    ----------
    phi : str, Fraction, int or float, optional
        The parameter of Eqs. (7.1)-(7.2), ``-pi/2 <= phi <= pi/2``; a string keeps every digit.
    Q : str, Fraction, int or float, optional
        The bond density per direction, ``0 <= Q <= 1/3`` (give exactly one of ``phi`` and ``Q``).
    dps : int
        Decimal digits, ``5..10000``.
    side : str, Fraction, int or float, optional
        The hexagon side ``l`` of Eq. (7.4), ``> 0`` (default 1).
    bethe : bool
        Also the independent Bethe-ansatz value of ``v`` (float, with its error).
    L_max : int, optional
        Largest Bethe-ansatz width, ``60..1200`` (default 240).
    progress : callable, bool or None
        ``progress(1)`` once done; ``True``: a progress bar.

    Returns
    -------
    IsotropicEntropy
        ``result[key]`` (``mpmath.mpf``), ``keys()``, ``describe(key)``, ``bethe``; ``to_json``/``to_text``.

    Raises
    ------
    ArgumentError
        If the point is out of range or its plan refused.
    ConvergenceError
        If the Bethe ansatz loses the ground state.

    Examples
    --------
    >>> import forcenet
    >>> e = forcenet.isotropic_point(Q="1/6", dps=30)
    >>> e["v_per_site"] == forcenet.entropy(Q="1/6", dps=30)
    True
    >>> import mpmath
    >>> mpmath.nstr(e["v_per_site"], 30)
    '0.0616159805393802359215413794767'

    References
    ----------
    Eqs. (7.1)-(7.4) (Sec. 7.4), with (7.3) and (7.4) as corrected in notes/.
    """
    return isotropic_point_plan(phi, Q, dps=dps, side=side, bethe=bethe, L_max=L_max).run(progress)


def isotropic_maximum_plan(dps: int = 50) -> IsotropicPlan:
    """What :func:`isotropic_maximum` will cost; nothing is computed.

    Parameters
    ----------
    dps : int
        Decimal digits, ``5..10000``.

    Returns
    -------
    IsotropicPlan

    Raises
    ------
    ArgumentError
        If ``dps`` is out of range.

    Examples
    --------
    >>> import forcenet
    >>> forcenet.isotropic_maximum_plan(3000).seconds > 10
    True

    References
    ----------
    Sec. 7.4: the maxima of Eq. (7.1) per site and per tiling vertex.
    """
    closed = _closed_form_plan(dps, maximum=True)  # checks dps
    return IsotropicPlan(int(dps), _cost(closed))


def isotropic_maximum(dps: int = 50, *, progress: Progress | bool | None = None) -> IsotropicEntropy:
    """Both maxima of the isotropic line, to ``dps`` digits, as ``forcenet entropy --max``.

    Per chicken-wire site: ``v_max`` where ``mu = 0``, with its ``Q`` and ``phi``; per square-triangle
    tiling vertex: ``s_max = log 108 - 2 sqrt3 log(2 + sqrt3)`` at the twelvefold point ``phi = 0``,
    with the tiling's composition there.

    Parameters
    ----------
    dps : int
        Decimal digits, ``5..10000``.
    progress : callable, bool or None
        ``progress(1)`` once done; ``True``: a progress bar.

    Returns
    -------
    IsotropicEntropy
        The rows ``v_max_per_site``, ``Q_max``, ``phi_max``, ``s_max_per_tiling_vertex``, ``Q0``, ...

    Raises
    ------
    ArgumentError
        If ``dps`` is out of range.

    Examples
    --------
    >>> import forcenet
    >>> m = forcenet.isotropic_maximum(dps=20)
    >>> import mpmath
    >>> mpmath.nstr(m["v_max_per_site"], 20), mpmath.nstr(m["Q_max"], 20)
    ('0.06278636828285688847', '0.184556497614421967')

    References
    ----------
    Eq. (7.1) at ``mu = 0``; the square-triangle tiling's entropy at the twelvefold point (Sec. 7.4).
    """
    return isotropic_maximum_plan(dps).run(progress)
