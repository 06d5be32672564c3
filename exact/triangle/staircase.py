"""The shifted staircase: tableau counts and the map from grains to cells.

The fully mobilized triangle of Sec. 4.2 with N layers is, in partial sums
``S[i][j] = W[i][1] + ... + W[i][j]``, the order polytope of the shifted
staircase shape ``(n, n-1, ..., 1)`` with ``n = N - 1`` (proof in
``notes/order_polytope.md``).  Grain partial sum ``S[i][j]`` (``2 <= i <= N``,
``1 <= j <= i - 1``) is the tableau cell in row ``r = j`` and column
``c = N - i + j`` (rows and columns of the shifted diagram start at 1, row
``r`` occupies columns ``r..n``).

References
----------
.. [1] S. Ostojic, *Statistical Mechanics of Static Granular Matter*, PhD
   thesis, Amsterdam (2006), Eqs. (4.1), (4.5)-(4.13), (4.51).
.. [2] OEIS A003121: number of standard shifted Young tableaux of staircase
   shape, 1, 1, 1, 2, 12, 286, 33592, 23178480, ...
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable
from fractions import Fraction
from functools import lru_cache
from math import factorial, prod
from typing import Any

import flint
import numpy as np

from forcenet.core.errors import ArgumentError
from forcenet.core.plan import Plan
from forcenet.core.validation import available_memory, check_layers

__all__ = [
    "dimension",
    "free_force_count",
    "grain_to_cell",
    "cell_to_grain",
    "staircase_cells",
    "count",
    "tableau_count",
    "count_digits",
    "count_plan",
    "count_by_hooks",
    "normalization",
    "ensemble_volume",
    "shifted_hook_lengths",
    "shifted_tableaux_count",
]


def dimension(N: int) -> int:
    """Dimension ``d = N (N - 1) / 2`` of the force network ensemble (Eq. 4.3).

    Parameters
    ----------
    N : int
        Number of layers, ``N >= 1``.

    Returns
    -------
    int
        The number of free forces.

    Raises
    ------
    ArgumentError
        If ``N`` is not an integer ``>= 1``.

    Examples
    --------
    >>> dimension(5)
    10
    """
    return free_force_count(check_layers(N, minimum=1))


def free_force_count(N: int) -> int:
    """The number of free forces ``d = N (N - 1) / 2`` of a checked ``N`` (a request's): the one place the formula
    (4.3) is written.

    The engines call it inside, on the ``N`` their request carries (checked
    once, when the request was built); :func:`dimension` is the user's face,
    which checks ``N`` first.

    Examples
    --------
    >>> free_force_count(5)
    10
    """
    return N * (N - 1) // 2


def grain_to_cell(N: int, i: int, j: int) -> tuple[int, int]:
    """Tableau cell ``(r, c)`` of the partial sum ``S[i][j]``.

    Parameters
    ----------
    N : int
        Number of layers.
    i, j : int
        The partial sum ``S[i][j]``, ``2 <= i <= N``, ``1 <= j <= i - 1``.

    Returns
    -------
    (int, int)
        Row ``r = j`` and column ``c = N - i + j`` of the shifted staircase.

    Raises
    ------
    ArgumentError
        If ``(i, j)`` is not a free partial sum.

    Examples
    --------
    >>> grain_to_cell(5, 5, 1), grain_to_cell(5, 5, 4), grain_to_cell(5, 2, 1)
    ((1, 1), (4, 4), (1, 4))
    """
    if not (2 <= i <= N and 1 <= j <= i - 1):
        raise ArgumentError(f"(i, j)=({i}, {j}): need 2 <= i <= N={N} and 1 <= j <= i - 1")
    return j, N - i + j


def cell_to_grain(N: int, r: int, c: int) -> tuple[int, int]:
    """Inverse of :func:`grain_to_cell`.

    Parameters
    ----------
    N : int
        Number of layers.
    r, c : int
        A cell of the shifted staircase, ``1 <= r <= c <= N - 1``.

    Returns
    -------
    (int, int)
        The partial sum ``(i, j) = (N - c + r, r)``.

    Raises
    ------
    ArgumentError
        If ``(r, c)`` is not a cell of the staircase.

    Examples
    --------
    >>> cell_to_grain(5, 1, 4)
    (2, 1)
    """
    n = N - 1
    if not (1 <= r <= c <= n):
        raise ArgumentError(f"(r, c)=({r}, {c}): need 1 <= r <= c <= N - 1 = {n}")
    return N - c + r, r


def staircase_cells(n: int) -> list[tuple[int, int]]:
    """Cells ``(r, c)``, ``1 <= r <= c <= n``, of the shifted staircase.

    Examples
    --------
    >>> staircase_cells(2)
    [(1, 1), (1, 2), (2, 2)]
    """
    return [(r, c) for r in range(1, n + 1) for c in range(r, n + 1)]


def shifted_hook_lengths(parts: Iterable[int]) -> dict[tuple[int, int], int]:
    """Shifted hook lengths of a strict partition (Thrall; Sagan 1979).

    The hook of cell ``(r, c)`` is the cells to its right in row ``r``, below it
    in column ``c``, and, when column ``c + 1`` reaches down to the diagonal
    cell ``(c + 1, c + 1)``, the whole row ``c + 1`` as well.

    Examples
    --------
    >>> sorted(shifted_hook_lengths((2, 1)).values())
    [1, 2, 3]
    """
    parts = tuple(parts)
    if any(a <= b for a, b in zip(parts, parts[1:])) or (parts and parts[-1] <= 0):
        raise ArgumentError(f"parts={parts}: must be strictly decreasing positive integers")
    rows = len(parts)
    last_col = {r + 1: r + parts[r] for r in range(rows)}  # row r spans columns r..last_col[r]
    hooks: dict[tuple[int, int], int] = {}
    for r in range(1, rows + 1):
        for c in range(r, last_col[r] + 1):
            arm = last_col[r] - c
            leg = sum(1 for r2 in range(r + 1, rows + 1) if r2 <= c <= last_col[r2])
            extra = parts[c] if c + 1 <= rows else 0  # row c+1, when it exists
            hooks[(r, c)] = arm + leg + 1 + extra
    return hooks


def shifted_tableaux_count(parts: Iterable[int]) -> int:
    """Number of standard shifted Young tableaux of a strict partition.

    Uses the shifted hook length formula ``g = |lambda|! / prod(hooks)``.

    Examples
    --------
    >>> shifted_tableaux_count((4, 3, 2, 1))
    12
    """
    hooks = shifted_hook_lengths(parts)
    total = factorial(len(hooks))
    denominator = prod(hooks.values())
    if total % denominator:
        raise ArithmeticError(f"hook formula not integral for {parts}")
    return total // denominator


def count_by_hooks(N: int) -> int:
    """``d! * normalization`` from the shifted hook length formula (a second route).

    Parameters
    ----------
    N : int
        Number of layers, ``N >= 2``.

    Returns
    -------
    int
        The number of standard shifted tableaux of staircase shape ``(N-1, ..., 1)``.

    Raises
    ------
    ArgumentError
        If ``N`` is not an integer ``>= 2``.

    Examples
    --------
    >>> [count_by_hooks(N) for N in range(3, 8)]
    [1, 2, 12, 286, 33592]
    """
    N = check_layers(N)
    return shifted_tableaux_count(tuple(range(N - 1, 0, -1)))


def _primes_upto(top: int) -> Any:
    sieve = np.ones(top + 1, dtype=bool)
    sieve[:2] = False
    for p in range(2, int(top**0.5) + 1):
        if sieve[p]:
            sieve[p * p :: p] = False
    return np.flatnonzero(sieve).astype(np.int64)


def _exponents_of_denominator(n: int, primes: Any) -> Any:
    """``v_p`` of ``D = prod_{k<n} (2k+1)!/k!`` for each prime (``normalization = 1/D``)."""
    ks = np.arange(n, dtype=np.int64)
    exps = np.zeros(primes.size, dtype=np.int64)
    for idx in np.flatnonzero(primes <= max(2 * n - 1, 1)):
        p = int(primes[idx])
        q = p
        while q <= 2 * n:
            exps[idx] += int(((2 * ks + 1) // q).sum() - (ks // q).sum())
            q *= p
    return exps


def _prime_exponents_of_count(N: int) -> list[tuple[int, int]]:
    """Prime factorisation of ``count = d! / D`` (Legendre's formula)."""
    n, d = N - 1, free_force_count(N)
    primes = _primes_upto(max(d, 2 * n, 2))
    exps = np.zeros(primes.size, dtype=np.int64)
    power = primes.copy()
    alive = power <= d
    while alive.any():  # v_p(d!) = sum_k floor(d / p^k), all primes at once
        exps[alive] += d // power[alive]
        power[alive] *= primes[alive]
        alive &= power <= d
    exps -= _exponents_of_denominator(n, primes)
    keep = exps > 0
    return list(zip(primes[keep].tolist(), exps[keep].tolist()))


def _product_tree(factors: Iterable[Any]) -> Any:
    factors = list(factors) or [1]
    while len(factors) > 1:
        nxt = [factors[k] * factors[k + 1] for k in range(0, len(factors) - 1, 2)]
        if len(factors) % 2:
            nxt.append(factors[-1])
        factors = nxt
    return factors[0]


def _prime_power_product(factorisation: Any) -> int:
    """``prod p**e`` by binary splitting of the exponents (python-flint if installed)."""
    make: Callable[[int], Any]
    try:
        make = flint.fmpz
    except ImportError:  # pure Python fallback
        make = int
    factorisation = [(p, e) for p, e in factorisation if e]
    if not factorisation:
        return 1
    result = make(1)
    for bit in range(max(e for _, e in factorisation).bit_length() - 1, -1, -1):
        result = result * result
        chosen = [make(p) for p, e in factorisation if e >> bit & 1]
        if chosen:
            result *= _product_tree(chosen)
    return int(result)


def count_digits(N: int) -> int:
    """Number of decimal digits of :func:`count` (from log-gamma; exact to +-1).

    Examples
    --------
    >>> count_digits(9), len(str(count(9)))
    (12, 12)
    """
    return _count_digits(check_layers(N))


def _count_digits(N: int) -> int:
    n, d = N - 1, free_force_count(N)
    log10 = (math.lgamma(d + 1) - sum(math.lgamma(2 * k + 2) - math.lgamma(k + 1) for k in range(n))) / math.log(10)
    return int(log10) + 1


def count_plan(N: int, memory_bytes: int | None = None) -> Plan:
    """The cost of computing :func:`count` and printing it in decimal.

    Measured on the 2-core machine: N = 4000 (2.3e7 digits) 8 s, N = 8000
    (1.0e8 digits) 40 s; memory ~ 24 bytes per cell of the staircase (the
    sieve) and a few bytes per digit.

    Examples
    --------
    >>> count_plan(1000).seconds < 2
    True
    >>> count_plan(10**6, memory_bytes=24 * 2**30).runnable  # 2.7e12 digits
    False
    """
    return _count_plan(check_layers(N), memory_bytes)


def _count_plan(N: int, memory_bytes: int | None) -> Plan:
    """:func:`count_plan` for ``N`` already checked."""
    if N > _COUNT_MAX_N:
        return Plan(f"count N={N}", 0, refusal=f"N={N} is out of range for count: N must be an integer in 2..{_COUNT_MAX_N} "
                                                "(beyond, the integer has more than 10^12 digits)")
    d = free_force_count(N)
    digits = _count_digits(N)
    plan = Plan(f"count N={N} ({float(digits):.3g} digits)", 2.2e-7 * d**1.1, 24 * d + 4 * digits)
    return plan.within_memory(memory_bytes)


_COUNT_MAX_N = 10**6


def _within_memory(N: Any, what: str) -> int:
    """``N`` checked, and refused before any work where the integer cannot fit in the memory available now
    (:func:`count_plan`; the denominator of :func:`normalization` has about twice the digits of the count)."""
    N = check_layers(N)
    memory = available_memory()
    plan = _count_plan(N, None if memory is None else memory // (1 if what == "count" else 2))
    if not plan.runnable:
        raise ArgumentError(f"{what}(N={N}) is refused: {plan.refusal}; N = 8000 (1e8 digits) takes ~40 s and "
                            "~1.2 GiB; count_digits(N) gives the size of any count at once")
    return N


@lru_cache(maxsize=64)
def count(N: int) -> int:
    """Number of standard shifted tableaux of staircase shape ``(N-1, ..., 1)``.

    This is ``d! * normalization(N)`` with ``d = N (N - 1) / 2``: the number of
    linear extensions of the poset of partial sums, i.e. the integer sum of the
    Lambda recursion in Eq. (4.1).  Closed form
    ``d! * prod_{k=0}^{N-2} k! / (2k + 1)!``, evaluated from its prime
    factorisation (python-flint's multiplication when installed).

    Parameters
    ----------
    N : int
        Number of layers, ``N >= 2``.

    Returns
    -------
    int

    Raises
    ------
    ArgumentError
        If ``N`` is not an integer ``>= 2``.

    Examples
    --------
    >>> [count(N) for N in range(2, 9)]
    [1, 1, 2, 12, 286, 33592, 23178480]
    >>> count(9)
    108995910720

    References
    ----------
    Ostojic (2006), Eq. (4.1); OEIS A003121.
    """
    return tableau_count(_within_memory(N, "count"))


@lru_cache(maxsize=64)
def tableau_count(N: int) -> int:
    """The tableaux count of Eq. (4.1) for a checked ``N`` (a request's); :func:`count` is the user's face, which
    checks ``N`` and the memory first.

    Examples
    --------
    >>> tableau_count(5)
    12
    """
    return _prime_power_product(_prime_exponents_of_count(N))


@lru_cache(maxsize=64)
def normalization(N: int) -> Fraction:
    """Volume of the force network ensemble of the triangle in W-coordinates.

    Eq. (4.1)/(4.51): ``normalization = count(N) / d!``, which equals
    ``prod_{k=0}^{N-2} k! / (2k + 1)! = 1 / D`` with the integer
    ``D = prod_k (k+1)(k+2)...(2k+1)``.

    Parameters
    ----------
    N : int
        Number of layers, ``N >= 2``.

    Returns
    -------
    Fraction
        ``1 / D``.

    Raises
    ------
    ArgumentError
        If ``N`` is not an integer ``>= 2``.

    Examples
    --------
    >>> normalization(4)
    Fraction(1, 360)
    >>> normalization(5)
    Fraction(1, 302400)
    """
    return ensemble_volume(_within_memory(N, "normalization"))


@lru_cache(maxsize=64)
def ensemble_volume(N: int) -> Fraction:
    """The ensemble's volume ``1 / D`` of Eq. (4.1)/(4.51) for a checked ``N`` (a request's); :func:`normalization`
    is the user's face, which checks ``N`` and the memory first.

    Examples
    --------
    >>> ensemble_volume(4)
    Fraction(1, 360)
    """
    n = N - 1
    primes = _primes_upto(max(2 * n, 2))
    exps = _exponents_of_denominator(n, primes)
    return Fraction(1, _prime_power_product(zip(primes.tolist(), exps.tolist())))
