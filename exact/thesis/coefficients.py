"""Index ranges and coefficients shared by the thesis's routes (chapter 4): one rule, one place.

* :func:`gamma`: the coefficient ``gamma^f_{s,e}`` of the central integral
  (4.14)-(4.15), exact; :func:`gamma_residues` tabulates the same formula
  modulo word-size primes for the multi-modular engines.
* :func:`upper_bound`: the index range (4.32), which is also the map range
  (4.86): ``j_1 <= 2`` and ``j_k <= k + j_{k-1}``, optionally raised on a
  defect line.
* :func:`defect_line`: the line of raised bounds of the modified maps
  (4.73)/(4.90).
"""

from __future__ import annotations

from collections.abc import Sequence
from fractions import Fraction
from math import factorial
from typing import Any

import numpy as np

from forcenet.core.errors import ArgumentError

__all__ = ["gamma", "gamma_coefficient", "gamma_residues", "upper_bound", "defect_line"]


def gamma(f: int, s: int, e: int) -> Fraction:
    """``gamma^f_{s,e} = s! e! / ((e + s - f + 1)! f!)``, Eq. (4.15); zero outside ``0 <= f <= s``, ``e >= 0``.

    It is the coefficient of ``(b - a)^(e + 1 + s - f) a^f`` in
    ``int_a^b x^s (b - x)^e dx`` (4.14).

    Examples
    --------
    >>> gamma(0, 1, 1), gamma(2, 1, 0)
    (Fraction(1, 6), Fraction(0, 1))
    """
    if f < 0 or s < 0 or e < 0 or f > s:
        return Fraction(0)
    return Fraction(factorial(s) * factorial(e), factorial(e + s - f + 1) * factorial(f))


def gamma_coefficient(m: int, n: int, k: int) -> Fraction:
    """``gamma^{m-k}_{m,n} = m! n! / ((n + k + 1)! (m - k)!)``, Eq. (4.15) as printed.

    Parameters
    ----------
    m, n : int
        The powers of ``x`` and ``b - x`` in the integral (4.14), ``>= 0``.
    k : int
        The term of the sum (4.14), ``0 <= k <= m``.

    Returns
    -------
    Fraction

    Raises
    ------
    ArgumentError
        If ``k`` is not in ``0..m``.

    Examples
    --------
    >>> gamma_coefficient(1, 1, 1)
    Fraction(1, 6)
    """
    if not 0 <= k <= m:
        raise ArgumentError(f"k={k} is out of range: k must be an integer in 0..m={m}")
    return gamma(m - k, m, n)


def gamma_residues(size: int, primes: Sequence[int]) -> np.ndarray:
    """``gamma^f_{s,e} mod p`` of :func:`gamma` for ``s, e, f < size``: shape ``(size, size, size, len(primes))``.

    Examples
    --------
    >>> table = gamma_residues(3, [7])
    >>> int(table[1, 1, 0, 0]) == Fraction(1, 6).numerator * pow(6, -1, 7) % 7
    True
    """
    table = np.zeros((size, size, size, len(primes)), dtype=np.int64)
    for a, p in enumerate(primes):
        fact = [1] * (2 * size + 1)
        for n in range(1, 2 * size + 1):
            fact[n] = fact[n - 1] * n % p
        inv = [pow(x, -1, p) for x in fact]
        for s in range(size):
            for e in range(size):
                for f in range(s + 1):
                    table[s, e, f, a] = fact[s] * fact[e] % p * inv[e + s - f + 1] % p * inv[f] % p
    return table


def upper_bound(k: int, previous: Any, raise_by: Any = 0) -> Any:
    """Largest value of the ``k``-th index given the ``(k-1)``-th: the range (4.32)/(4.86).

    ``j_1 <= 2`` and ``j_k <= k + j_{k-1}``; ``raise_by`` adds the raised bound
    of a defect line (4.73)/(4.90).  ``previous`` may be a numpy array.

    Examples
    --------
    >>> upper_bound(1, None), upper_bound(3, 2), upper_bound(3, 2, raise_by=1)
    (2, 5, 6)
    """
    return (2 if k == 1 else k + previous) + raise_by


def defect_line(N: int, q: int, r: int, amount: int = 1) -> dict:
    """Rows ``l`` -> ``{k: amount}`` on the defect line ``(N-r+t, q+t)``, ``0 <= t <= r-2`` (Eqs. 4.73, 4.90).

    Examples
    --------
    >>> defect_line(6, 2, 3)
    {3: {2: 1}, 4: {3: 1}}
    """
    line: dict[int, dict[int, int]] = {}
    for t in range(r - 1):
        l, k = N - r + t, q + t
        if 1 <= l <= N - 2:
            line.setdefault(l, {})[k] = amount
    return line
