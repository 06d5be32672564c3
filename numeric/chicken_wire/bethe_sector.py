"""The ground state of one sector of the nested Bethe ansatz, with its cost: ``forcenet bethe``.

:func:`ground_state_plan` announces the cost (or refuses the sector) before
the work; :func:`ground_state` solves by random starts
(:func:`.bethe.solve_ground_state`) or, for ``(L, n, m) = k (6, 2, 1)`` beyond
``L = 24``, by the continuation in ``k`` (:func:`.bethe.ground_state_sequence`).
"""

from __future__ import annotations

from forcenet.core.plan import Plan
from forcenet.core.validation import check_int

from .bethe import RANDOM_TRIES, BetheSolution, Progress, ground_state_sequence, solve_ground_state

__all__ = ["MAX_WIDTH", "RANDOM_TRIES", "default_sector", "ground_state_plan", "ground_state", "random_starts_seconds"]


def default_sector(L: int, n: int | None = None, m: int | None = None) -> tuple[int, int]:
    """``(n, m)`` with the defaults of the ground state at width ``L``: ``n = 2 round(L/6)``, ``m = n // 2``.

    The defaults are the density ``Q = 1/6`` of the continuation ``(L, n, m) = k (6, 2, 1)``.

    Parameters
    ----------
    L : int
        Cylinder width.
    n, m : int, optional
        Particles per row and left-movers among them; kept when given.

    Returns
    -------
    tuple of int
        ``(n, m)``.

    Examples
    --------
    >>> default_sector(60), default_sector(9, 4)
    ((20, 10), (4, 2))
    """
    n = n if n is not None else 2 * max(1, round(L / 6))
    return n, m if m is not None else n // 2


MAX_WIDTH = 5000  # the widest cylinder planned (ground_state_plan prices random starts there in years)


def _continued(L: int, n: int, m: int) -> bool:
    """Whether the sector is reached by the continuation ``k (6, 2, 1)`` from ``L = 12`` (random starts fail at large ``L``)."""
    return L > 24 and L % 6 == 0 and n == L // 3 and m == n // 2


def ground_state_plan(L: int, n: int, m: int) -> Plan:
    """The cost of :func:`ground_state` in the sector ``(L, n, m)``.

    Continuation ``k (6, 2, 1)`` to ``L = 6k``: measured 16 s at ``L = 600``
    with single-threaded BLAS (2-core machine), ``3 + 1.3e-5 k^3`` seconds,
    one tick per width; otherwise random starts (:func:`random_starts_seconds`).

    Parameters
    ----------
    L, n, m : int
        Width, particles per row, left-movers among them.

    Returns
    -------
    Plan
        Refused (naming ``(L, n, m)``) unless ``1 <= m < n < L``.

    Raises
    ------
    ArgumentTypeError
        If an argument is not an integer.

    Examples
    --------
    >>> ground_state_plan(600, 200, 100).seconds
    16.0
    >>> ground_state_plan(6, 2, 2).refusal
    '(L, n, m) = (6, 2, 2) is out of range: need 1 <= m < n < L'
    """
    L, n, m = check_int(L, "L"), check_int(n, "n"), check_int(m, "m")
    what = f"Bethe ansatz L={L}, n={n}, m={m}"
    if not (1 <= m < n < L):
        return Plan(what, 0, refusal=f"(L, n, m) = ({L}, {n}, {m}) is out of range: need 1 <= m < n < L")
    if _continued(L, n, m):
        k = L // 6
        return Plan(what + " (continuation from L = 12)", 3.0 + 1.3e-5 * k**3, 100 * 2**20, k - 1, "width")
    return Plan(what + " (random starts)", random_starts_seconds(L, m), 100 * 2**20, 0, "width")


def random_starts_seconds(L: int, m: int) -> float:
    """Estimated CPU seconds of the random starts' search for a sector's ground state (20 converged, or
    :data:`RANDOM_TRIES` tries and a refusal).

    Measured (2026-12-06, CPU s, tries): ``(9, 4, 2)`` 4.5 s, 31; ``(12, 4, 2)`` 5.9, 29; ``(24, 8, 2)`` 6.6, 32;
    ``(24, 8, 3)`` 7.5, 100; ``(30, 10, 4)`` 7.9, 94; ``(42, 14, 4)`` 5.5, 84; ``(60, 20, 4)`` 4.8, 82;
    ``(48, 16, 6)`` 33.9, 349; ``(60, 20, 8)`` not done in 9 minutes. The cost grows with the left-movers ``m``
    (fewer random starts converge to the ground state), about ``5 + 0.009 * 4^m`` seconds, and is at most every
    try's: :data:`RANDOM_TRIES` times a mean try of ``3.5 * (0.01 + 1e-4 L m^1.5)`` seconds (median tries measured
    12 ms at ``(12, 4, 2)``, 42 ms at ``(60, 20, 4)``, 122 ms at ``(60, 20, 8)``, 554 ms at ``(120, 40, 16)``;
    the mean is about 3.5 times the median: the tries that do not converge are the slow ones).

    Examples
    --------
    >>> round(random_starts_seconds(30, 4)), round(random_starts_seconds(48, 6))
    (7, 42)
    >>> random_starts_seconds(60, 8) > 540  # measured: not done after 540 s
    True
    """
    every_try = RANDOM_TRIES * 3.5 * (0.01 + 1e-4 * L * m**1.5)
    return min(5.0 + 0.009 * 4.0 ** min(m, 60), every_try)


def ground_state(L: int, n: int, m: int, progress: Progress = None) -> BetheSolution:
    """The ground state of the sector ``(L, n, m)``, by continuation where :func:`ground_state_plan` says so.

    Parameters
    ----------
    L, n, m : int
        Width, particles per row, left-movers among them (``1 <= m < n < L``).
    progress : callable, optional
        Called once per width of the continuation.

    Returns
    -------
    BetheSolution

    Raises
    ------
    ArgumentError
        If ``(L, n, m)`` is out of range.
    ConvergenceError
        If no ground state converged.

    Examples
    --------
    >>> round(ground_state(9, 4, 2).eigenvalue, 12)
    1.855529779351
    """
    if _continued(L, n, m):
        return ground_state_sequence(L // 6, progress=progress)[-1]
    return solve_ground_state(L, n, m)
