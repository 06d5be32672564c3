"""Multi-modular arithmetic: word-size primes and Chinese remaindering.

Exact big-integer sums are computed as residues modulo several primes below
2**31 (so that a product of two residues fits in a signed 64-bit integer) and
reconstructed exactly with the Chinese remainder theorem.  The number of primes
is always chosen from a *proven* upper bound on the result, so the
reconstruction is exact, never probabilistic.

Examples
--------
>>> from forcenet.exact.modular import primes_below, crt
>>> ps = primes_below(2**31, 3)
>>> x = 123456789012345678901234567
>>> crt([x % p for p in ps], ps)
123456789012345678901234567
"""

from __future__ import annotations

from collections.abc import Iterable
from functools import cache

from forcenet.core.errors import ArgumentError

__all__ = ["is_prime", "primes_below", "primes_for_bound", "crt", "crt_many"]

# Deterministic Miller-Rabin bases for n < 3.3e24 (Sorenson & Webster).
_MR_BASES = (2, 3, 5, 7, 11, 13, 17, 19, 23, 29, 31, 37, 41)


def is_prime(n: int) -> bool:
    """Deterministic primality test for ``n < 3.3e24``.

    Examples
    --------
    >>> [p for p in range(20) if is_prime(p)]
    [2, 3, 5, 7, 11, 13, 17, 19]
    """
    if n < 2:
        return False
    for p in _MR_BASES:
        if n % p == 0:
            return n == p
    d, s = n - 1, 0
    while d % 2 == 0:
        d //= 2
        s += 1
    for a in _MR_BASES:
        x = pow(a, d, n)
        if x in (1, n - 1):
            continue
        for _ in range(s - 1):
            x = x * x % n
            if x == n - 1:
                break
        else:
            return False
    return True


@cache
def primes_below(limit: int, count: int) -> tuple[int, ...]:
    """The ``count`` largest primes strictly below ``limit``.

    Examples
    --------
    >>> primes_below(100, 3)
    (97, 89, 83)
    """
    out: list[int] = []
    candidate = limit - 1
    while len(out) < count:
        if candidate < 2:
            raise ArgumentError(f"count={count}: fewer primes than that below limit={limit}")
        if is_prime(candidate):
            out.append(candidate)
        candidate -= 1
    return tuple(out)


def primes_for_bound(bound: int, limit: int = 2**31, smallest: int = 2) -> tuple[int, ...]:
    """The largest primes below ``limit``, as few as make their product exceed ``bound``.

    A non-negative integer ``x <= bound`` is then determined by its residues:
    :func:`crt` returns the unique ``y`` in ``[0, P)`` with ``y = x (mod p)``
    for every prime, ``P`` their product, and ``0 <= x <= bound < P`` puts
    ``x`` itself in that range, so ``y = x``.  (A *signed* value with
    ``|x| <= bound`` would need ``P > 2 bound``; every caller reconstructs a
    count or a sum of counts, non-negative, so the product only has to exceed
    ``bound``: one convention for the whole package.)

    Parameters
    ----------
    bound : int
        A proven upper bound on the non-negative integers to reconstruct.
    limit : int
        The primes lie below ``limit`` (default ``2**31``: a product of two
        residues fits a signed 64-bit integer).
    smallest : int
        Refuse primes ``<= smallest`` (a route whose arithmetic needs the
        prime to exceed a size).

    Returns
    -------
    tuple of int
        The primes, largest first.

    Raises
    ------
    ArgumentError
        If ``bound < 0``, or the primes in ``(smallest, limit)`` run out.

    Examples
    --------
    >>> len(primes_for_bound(10**20))
    3
    >>> primes_for_bound(96, limit=100), primes_for_bound(97, limit=100)
    ((97,), (97, 89))
    """
    if bound < 0:
        raise ArgumentError(f"bound={bound} is out of range: bound must be an integer >= 0")
    out: list[int] = []
    product, candidate = 1, limit - 1
    while product <= bound:
        if candidate <= smallest:
            raise ArgumentError(f"bound={bound} is out of range: the primes in ({smallest}, {limit}) run out")
        if is_prime(candidate):
            out.append(candidate)
            product *= candidate
        candidate -= 1
    return tuple(out)


def crt(residues: Iterable[int], primes: Iterable[int]) -> int:
    """The least non-negative integer with the given residues (Garner's algorithm).

    Examples
    --------
    >>> crt([2, 3, 2], [3, 5, 7])
    23
    """
    x, modulus = 0, 1
    for r, p in zip(residues, primes):
        r = int(r) % p
        # x + modulus * t == r (mod p)
        t = (r - x) * pow(modulus, -1, p) % p
        x += modulus * t
        modulus *= p
    return x


def crt_many(residue_rows: Iterable[Iterable[int]], primes: Iterable[int]) -> list[int]:
    """:func:`crt` applied to each row of a 2-D array of residues (row ``i``: one integer's residues).

    The basis ``e_k = (P / p_k) ((P / p_k)^-1 mod p_k)`` is computed once,
    so each row costs ``len(primes)`` products and one reduction modulo
    ``P``: ``x = sum_k r_k e_k mod P``.

    Examples
    --------
    >>> crt_many([[2, 3, 2], [0, 0, 1]], [3, 5, 7])
    [23, 15]
    """
    primes = [int(p) for p in primes]
    modulus = 1
    for p in primes:
        modulus *= p
    basis = []
    for p in primes:
        rest = modulus // p
        basis.append(rest * pow(rest % p, -1, p))
    return [sum(int(r) * e for r, e in zip(row, basis)) % modulus for row in residue_rows]
