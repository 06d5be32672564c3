"""The front door of the chicken-wire model's sectors (Sec. 7.4): the transfer spectrum and Bethe ground states.

* :func:`transfer_spectrum` — the largest transfer-matrix eigenvalue of each particle sector of a cylinder
  (``forcenet transfer``);
* :func:`bethe_ground_state` — one sector's ground state from the nested Bethe ansatz (``forcenet bethe``).

Each has its plan (``..._plan``): the request validated once, its cost (``.cost``, a
:class:`forcenet.core.plan.Plan`: what the command line announces) or its refusal, and ``.run(progress)``.
The engines stay in :mod:`forcenet.numeric.chicken_wire`; the results and their renderings are
:mod:`forcenet.chicken_wire_results`; the isotropic line's closed forms are :mod:`forcenet.chicken_wire_isotropic`.

Examples
--------
>>> import forcenet
>>> round(forcenet.transfer_spectrum(8, particles=4).sectors[0].eigenvalue, 12)  # the golden ratio
1.61803398875
>>> forcenet.bethe_ground_state_plan(600).cost.unit
'width'
"""

from __future__ import annotations

from dataclasses import dataclass

from forcenet.chicken_wire_results import BetheGroundState, Sector, TransferSpectrum
from forcenet.core.plan import Plan
from forcenet.core.validation import check_int
from forcenet.costed_plans import CostedPlan, Progress
from forcenet.numeric.chicken_wire.bethe_sector import MAX_WIDTH, default_sector, ground_state, ground_state_plan
from forcenet.numeric.chicken_wire.transfer import sector_entropy, transfer_plan

__all__ = [
    "TransferSpectrumPlan", "transfer_spectrum_plan", "transfer_spectrum",
    "BetheGroundStatePlan", "bethe_ground_state_plan", "bethe_ground_state",
]



# ------------------------------------------------------------------------ transfer matrix


@dataclass(frozen=True, repr=False)  # the plan's own words: CostedPlan.__repr__
class TransferSpectrumPlan(CostedPlan):
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
        self.check()
        sectors = [self.particles] if self.particles is not None else list(range(self.L + 1))
        found = []
        with self._ticks(progress, f"transfer L={self.L}") as tick:
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


@dataclass(frozen=True, repr=False)  # the plan's own words: CostedPlan.__repr__
class BetheGroundStatePlan(CostedPlan):
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
        >>> round(forcenet.bethe_ground_state_plan(8, 3, 1).run().entropy_per_site, 12)
        0.055851550279
        """
        self.check()
        with self._ticks(progress, f"Bethe L={self.L}") as tick:
            return BetheGroundState(ground_state(self.L, self.n, self.m, progress=tick))


def bethe_ground_state_plan(L: int, n: int | None = None, m: int | None = None) -> BetheGroundStatePlan:
    """What :func:`bethe_ground_state` will cost, or why the sector cannot run; nothing is solved.

    Parameters
    ----------
    L : int
        Cylinder width, ``3..5000`` (the plan grows as ``L^3``: about 14 days at 5000).
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
    L = check_int(L, "L", 3, MAX_WIDTH)
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
        Cylinder width, ``3..5000`` (the plan grows as ``L^3``: about 14 days at 5000).
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
    >>> g = forcenet.bethe_ground_state(8, 3, 1)
    >>> round(g.eigenvalue, 12)
    1.563320996252
    >>> round(forcenet.transfer_spectrum(8, particles=3).sectors[0].eigenvalue, 12)  # the transfer matrix agrees
    1.563320996252

    References
    ----------
    Sec. 7.4.2, the Bethe equations of the two kinds of particles.
    """
    return bethe_ground_state_plan(L, n, m).run(progress)
