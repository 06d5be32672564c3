"""The front door of the chicken-wire model (Sec. 7.4): its transfer spectrum, Bethe ground states and entropy.

* :func:`transfer_spectrum` — the largest transfer-matrix eigenvalue of each particle sector of a cylinder
  (``forcenet transfer``);
* :func:`bethe_ground_state` — one sector's ground state from the nested Bethe ansatz (``forcenet bethe``);
* :func:`isotropic_point`, :func:`isotropic_maximum` — the entropy and its companions on the isotropic
  line, Eqs. (7.1)-(7.4), to any number of digits, with the Bethe-ansatz value if asked
  (``forcenet entropy``).

Each has its plan (``..._plan``): the request validated once, its cost (``.cost``, a
:class:`forcenet.core.plan.Plan`: what the command line announces) or its refusal, and ``.run(progress)``.
The engines stay in :mod:`forcenet.numeric.chicken_wire`; the results and their renderings are
:mod:`forcenet.chicken_wire_results`.

Examples
--------
>>> import forcenet
>>> round(forcenet.transfer_spectrum(8, particles=4).sectors[0].eigenvalue, 12)  # the golden ratio
1.61803398875
>>> p = forcenet.isotropic_point_plan(Q="1/6", bethe=True)
>>> p.cost.ticks, p.runnable
(1, True)
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from fractions import Fraction
from typing import Any

from forcenet.chicken_wire_results import BetheGroundState, BetheValue, IsotropicEntropy, Sector, TransferSpectrum
from forcenet.core.errors import ArgumentError, ArgumentTypeError, ConvergenceError
from forcenet.core.plan import Plan, combine
from forcenet.core.validation import check_dps, check_float_digits, check_int, is_binary_float
from forcenet.front_door import _Costed

__all__ = [
    "TransferSpectrumPlan", "transfer_spectrum_plan", "transfer_spectrum",
    "BetheGroundStatePlan", "bethe_ground_state_plan", "bethe_ground_state",
    "IsotropicPlan", "isotropic_point_plan", "isotropic_point", "isotropic_maximum_plan", "isotropic_maximum",
]

Progress = Callable[..., Any]


class _Bar:
    """``progress`` as a callable: itself, a tqdm bar (``True``) closed at the end, or None."""

    def __init__(self, progress: Progress | bool | None, cost: Plan, desc: str) -> None:
        self.bar = None
        self.tick: Progress | None = progress if callable(progress) else None
        if progress is True:
            from tqdm.auto import tqdm

            self.bar = tqdm(total=cost.ticks or None, desc=desc, unit=cost.unit)
            self.tick = self.bar.update

    def __enter__(self) -> Progress | None:
        return self.tick

    def __exit__(self, *exc: object) -> None:
        if self.bar is not None:
            self.bar.close()


# ------------------------------------------------------------------------ transfer matrix


@dataclass(frozen=True)
class TransferSpectrumPlan(_Costed):
    """A checked request for the transfer spectrum of a cylinder, with its cost: what :func:`transfer_spectrum_plan` returns.

    Parameters
    ----------
    L : int
        Cylinder width.
    particles : int, optional
        The one sector asked for (None: all ``L + 1``).
    cost : forcenet.core.plan.Plan
        Estimated seconds, bytes, one tick per sector, or the refusal.

    Examples
    --------
    >>> import forcenet
    >>> p = forcenet.transfer_spectrum_plan(10)
    >>> p.cost.ticks, p.seconds
    (11, 15.0)
    """

    L: int
    particles: int | None
    cost: Plan

    def run(self, progress: Progress | bool | None = None) -> TransferSpectrum:
        """Compute the sectors this plan describes.

        Parameters
        ----------
        progress : callable, bool or None
            ``progress(1)`` after each sector; ``True``: a progress bar (tqdm); None: nothing.

        Returns
        -------
        TransferSpectrum

        Raises
        ------
        ArgumentError
            If the plan is refused.

        Examples
        --------
        >>> import forcenet
        >>> forcenet.transfer_spectrum_plan(4).run().lambda_max
        2.0
        """
        from forcenet.numeric.chicken_wire.transfer import sector_entropy

        self.check()
        sectors = [self.particles] if self.particles is not None else list(range(self.L + 1))
        found = []
        with _Bar(progress, self.cost, f"transfer L={self.L}") as tick:
            for n in sectors:
                found.append(Sector(n, *sector_entropy(self.L, particles=n)))
                if tick:
                    tick()
        return TransferSpectrum(self.L, tuple(found), self.particles)


def transfer_spectrum_plan(L: int, particles: int | None = None) -> TransferSpectrumPlan:
    """What :func:`transfer_spectrum` will cost, or why it cannot run; nothing is computed.

    Parameters
    ----------
    L : int
        Cylinder width, ``2..14`` (the states of a row: ``3^L``).
    particles : int, optional
        One sector only, ``0..L`` (default: all).

    Returns
    -------
    TransferSpectrumPlan
        Refused (naming ``particles``) if the sector does not exist.

    Raises
    ------
    ArgumentError
        If ``L`` or ``particles`` is out of range (a negative particle number).
    ArgumentTypeError
        If one is not an integer.

    Examples
    --------
    >>> import forcenet
    >>> forcenet.transfer_spectrum_plan(10, particles=3).seconds
    1.3636363636363635
    >>> forcenet.transfer_spectrum_plan(6, particles=7).refusal
    'particles=7 is out of range: particles must be an integer in 0..L = 0..6'

    References
    ----------
    Sec. 7.4.1: the row-to-row transfer matrix of the chicken-wire model.
    """
    from forcenet.numeric.chicken_wire.transfer import transfer_plan

    cost = transfer_plan(L, particles)  # checks L (2..14) and particles (>= 0)
    return TransferSpectrumPlan(check_int(L, "L"), None if particles is None else check_int(particles, "particles"),
                                cost)


def transfer_spectrum(L: int, particles: int | None = None, *,
                      progress: Progress | bool | None = None) -> TransferSpectrum:
    """The largest transfer-matrix eigenvalue of each particle sector on a cylinder, as ``forcenet transfer``.

    The row-to-row transfer matrix of the chicken-wire model (Sec. 7.4.1) conserves the number of
    particles per row; each sector's largest eigenvalue ``lambda`` gives the entropy per site
    ``log(lambda)/L`` of that sector on a cylinder of width ``L`` (ARPACK on a matrix-product operator,
    floats; printed to 12 decimals).

    Parameters
    ----------
    L : int
        Cylinder width, ``2..14``.
    particles : int, optional
        One sector only, ``0..L`` (default: all ``L + 1``).
    progress : callable, bool or None
        ``progress(1)`` after each sector; ``True``: a progress bar.

    Returns
    -------
    TransferSpectrum
        The sectors, ``lambda_max``, the bulk sector; ``to_json``/``to_text`` as the command line.

    Raises
    ------
    ArgumentError
        If ``L`` or ``particles`` is out of range.

    Examples
    --------
    >>> import forcenet
    >>> s = forcenet.transfer_spectrum(6)
    >>> s.lambda_max, s.bulk.particles, round(s.bulk.eigenvalue, 12)
    (2.0, 2, 1.732050807569)

    References
    ----------
    Sec. 7.4.1; the sector entropies approach the isotropic line's Eq. (7.1) as ``L`` grows.
    """
    return transfer_spectrum_plan(L, particles).run(progress)


# ------------------------------------------------------------------------ Bethe ansatz


@dataclass(frozen=True)
class BetheGroundStatePlan(_Costed):
    """A checked request for one sector's Bethe ground state, with its cost: what :func:`bethe_ground_state_plan` returns.

    Parameters
    ----------
    L, n, m : int
        Width, particles per row, left-movers among them (defaults resolved).
    cost : forcenet.core.plan.Plan
        Estimated seconds (random starts, or the continuation ``k (6, 2, 1)``), or the refusal.

    Examples
    --------
    >>> import forcenet
    >>> p = forcenet.bethe_ground_state_plan(600)
    >>> (p.n, p.m), p.seconds
    ((200, 100), 16.0)
    """

    L: int
    n: int
    m: int
    cost: Plan

    def run(self, progress: Progress | bool | None = None) -> BetheGroundState:
        """Solve the Bethe equations of this sector (random starts, or the continuation in ``k``).

        Parameters
        ----------
        progress : callable, bool or None
            ``progress(1)`` per width of the continuation; ``True``: a progress bar (tqdm).

        Returns
        -------
        BetheGroundState

        Raises
        ------
        ArgumentError
            If the plan is refused.
        ConvergenceError
            If no ground state converged.

        Examples
        --------
        >>> import forcenet
        >>> round(forcenet.bethe_ground_state_plan(9, 4, 2).run().entropy_per_site, 12)
        0.068685583402
        """
        from forcenet.numeric.chicken_wire.bethe_sector import ground_state

        self.check()
        with _Bar(progress, self.cost, f"Bethe L={self.L}") as tick:
            return BetheGroundState(ground_state(self.L, self.n, self.m, progress=tick))


def bethe_ground_state_plan(L: int, n: int | None = None, m: int | None = None) -> BetheGroundStatePlan:
    """What :func:`bethe_ground_state` will cost, or why the sector cannot run; nothing is solved.

    Parameters
    ----------
    L : int
        Cylinder width, ``>= 3``.
    n : int, optional
        Particles per row, ``2 <= n < L`` (default ``2 round(L/6)``, the density ``Q = 1/6``).
    m : int, optional
        Left-movers among them, ``1 <= m < n`` (default ``n // 2``).

    Returns
    -------
    BetheGroundStatePlan
        Refused (naming ``(L, n, m)``) unless ``1 <= m < n < L``.

    Raises
    ------
    ArgumentError
        If ``L < 3``, ``n < 2`` or ``m < 1``.
    ArgumentTypeError
        If one is not an integer.

    Examples
    --------
    >>> import forcenet
    >>> forcenet.bethe_ground_state_plan(6, 2, 2).refusal
    '(L, n, m) = (6, 2, 2) is out of range: need 1 <= m < n < L'

    References
    ----------
    Sec. 7.4.2: the nested Bethe ansatz of the chicken-wire transfer matrix.
    """
    from forcenet.numeric.chicken_wire.bethe_sector import default_sector, ground_state_plan

    L = check_int(L, "L", 3)
    n = None if n is None else check_int(n, "n", 2)
    m = None if m is None else check_int(m, "m", 1)
    n, m = default_sector(L, n, m)
    return BetheGroundStatePlan(L, n, m, ground_state_plan(L, n, m))


def bethe_ground_state(L: int, n: int | None = None, m: int | None = None, *,
                       progress: Progress | bool | None = None) -> BetheGroundState:
    """The Bethe roots and the largest eigenvalue of one sector, as ``forcenet bethe``.

    Parameters
    ----------
    L : int
        Cylinder width, ``>= 3``.
    n : int, optional
        Particles per row (default ``2 round(L/6)``).
    m : int, optional
        Left-movers among them (default ``n // 2``).
    progress : callable, bool or None
        ``progress(1)`` per width of the continuation; ``True``: a progress bar.

    Returns
    -------
    BetheGroundState
        The roots ``w`` and ``u``, ``eigenvalue``, ``entropy_per_site``, ``residual``.

    Raises
    ------
    ArgumentError
        If the sector is out of range (``1 <= m < n < L``).
    ConvergenceError
        If no ground state converged.

    Examples
    --------
    >>> import forcenet
    >>> g = forcenet.bethe_ground_state(9, 4, 2)
    >>> round(g.eigenvalue, 12)
    1.855529779351
    >>> round(forcenet.transfer_spectrum(9, particles=4).sectors[0].eigenvalue, 12)  # the transfer matrix agrees
    1.855529779351

    References
    ----------
    Sec. 7.4.2, the Bethe equations of the two kinds of particles.
    """
    return bethe_ground_state_plan(L, n, m).run(progress)


# ------------------------------------------------------------------------ the isotropic line

# the leading term of (7.3) is shown as an approximation of v where it is one: within 1 % of v
SERIES_TOLERANCE = 0.01


@dataclass(frozen=True)
class IsotropicPlan(_Costed):
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
        with _Bar(progress, self.cost, "entropy") as tick:
            rows = self._maximum_rows() if self.maximum else self._closed_form_rows()
            value = self._bethe(rows) if self.bethe else None
            if tick:
                tick()
        return IsotropicEntropy(self.dps, tuple(rows), value)

    def _inside(self) -> bool:
        """Whether the point is strictly inside ``0 < Q < 1/3`` (``|phi| < pi/2``), decided exactly."""
        from forcenet.core.precision import within_pi

        if self.Q is not None:
            return bool(0 < self.Q < Fraction(1, 3))
        return within_pi(self.phi, strict=True, name="phi")

    def _closed_form_rows(self) -> list[tuple[str, str, Any]]:
        """Every quantity at the point, named by what it is (mpmath values)."""
        import mpmath

        from forcenet.numeric.chicken_wire import isotropic as iso

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
        import mpmath

        from forcenet.numeric.chicken_wire import isotropic as iso

        series = iso.leading_series_at(eps, self.dps, self.Q)
        what = "approximation of v by the leading term of Eq. (7.3), corrected: eps^2 (log(108/eps^2) - 3)/18"
        if not abs(series - v) <= SERIES_TOLERANCE * v:
            what += (f"; NOT VALID here: eps = {mpmath.nstr(eps, 3)} is not small, it differs from v by "
                     f"{mpmath.nstr(abs(series - v), 2)}")
        return ("v_series_7_3", what, series)

    def _maximum_rows(self) -> list[tuple[str, str, Any]]:
        from forcenet.numeric.chicken_wire import isotropic as iso

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
        from forcenet.numeric.chicken_wire.isotropic_bethe import isotropic_entropy

        Q = self.Q if self.Q is not None else float(dict((key, value) for key, _, value in rows)["Q"])
        try:
            v, err, densities = isotropic_entropy(Q, self.L_max)
        except ConvergenceError as exc:
            raise ConvergenceError(f"Bethe ansatz: {exc}") from None
        return BetheValue(v, err, tuple(densities), self.L_max)


def _mpf(value: Any) -> Any:
    """``value`` as an mpf at the current precision (a Fraction divided exactly)."""
    from forcenet.core.precision import to_mpf

    return to_mpf(value, "value")


def _real(value: Any, name: str, dps: int, keep_text: bool = True) -> str | Fraction:
    """A real argument as the engines take it, exactly: a string kept as given (stripped; ``keep_text=False``: read
    as a Fraction), any other number as its exact Fraction; a binary float by the one rule (refused where its
    digits do not reach ``dps``, else accepted at its exact value with a warning, once)."""
    import math
    from decimal import Decimal

    import mpmath

    from forcenet.core.validation import is_integer

    if isinstance(value, str):
        text = value.strip()
        if keep_text:
            return text
        try:
            if not text.isascii():
                raise ValueError(text)
            return Fraction(text)
        except (ValueError, ZeroDivisionError):
            raise ArgumentTypeError(f"{name}={value!r} is not a real number") from None
    if isinstance(value, bool):
        raise ArgumentTypeError(f"{name}={value!r} is not a real number")
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
        Largest Bethe-ansatz width, ``>= 60`` (default 240; only with ``bethe=True``).

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
    from forcenet.core.precision import check_within_pi, to_mpf

    dps = check_dps(dps)
    if (phi is None) == (Q is None):
        raise ArgumentTypeError("give exactly one of phi= and Q=")
    if L_max is not None and not bethe:
        raise ArgumentError(f"L_max={L_max} sets the widths of bethe=True: pass bethe=True or drop L_max")
    L_max = 240 if L_max is None else L_max
    if phi is not None:
        phi = check_within_pi(_real(phi, "phi", dps), "phi")
    else:
        Q = _real(Q, "Q", dps, keep_text=False)
        if not 0 <= Q <= Fraction(1, 3):
            raise ArgumentError(f"Q={_shown(Q)} is out of range: the density per direction Q must lie in [0, 1/3]")
    if side is not None:
        import mpmath

        side = _real(side, "side", dps)
        with mpmath.workdps(dps):
            if not to_mpf(side, "side") > 0:
                raise ArgumentError(f"side={_shown(side)} is out of range: the hexagon side l of Eq. (7.4) must be "
                                    "a finite number > 0")
    return IsotropicPlan(dps, _cost(dps, False, Q if isinstance(Q, Fraction) else None, bool(bethe), L_max),
                         phi, Q, side, bool(bethe), L_max)


def _shown(value: str | Fraction) -> str:
    """A value in a message: as given, or a Fraction as its float when its denominator is long (a binary float's)."""
    if isinstance(value, Fraction) and len(str(value.denominator)) > 12:
        return repr(float(value))
    return str(value)


def _cost(dps: int, maximum: bool, Q: Fraction | float | None = None, bethe: bool = False, L_max: int = 240) -> Plan:
    """The closed forms' plan, and the Bethe ansatz's after it: one announcement, as ``forcenet entropy`` makes it."""
    from forcenet.numeric.chicken_wire.isotropic import closed_form_plan

    closed = closed_form_plan(dps, maximum=maximum)
    plans = [closed]
    if bethe:
        from forcenet.numeric.chicken_wire.isotropic_bethe import isotropic_entropy_plan

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
        Largest Bethe-ansatz width, ``>= 60`` (default 240).
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
    dps = check_dps(dps)
    return IsotropicPlan(dps, _cost(dps, True))


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
