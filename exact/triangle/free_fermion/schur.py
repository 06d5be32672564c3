"""Schur's Pfaffian and Pfaffian minor summation for the shifted staircase, exactly (Fractions).

The order ideals of the shifted staircase ``(n, ..., 1)``, ``n = N - 1``, are
the subsets ``A`` of ``{1..n}`` (the parts of a strict partition); the number
of tableaux through ``A`` is ``w(A) = f(A) f(A^c)`` (``notes/order_polytope.md``).
Schur's form of the shifted hook formula writes ``f(A)`` as a Pfaffian,

    f(A) = l(A)! / prod_{a in A} a!  *  Pf[(a - b)/(a + b)]_{A or A + {0}},

and Pfaffian minor summation turns the sum over all ``A`` into one Pfaffian
(``notes/free_fermions.md`` Sec. 3):

    Pf K(q, t) = sum_A q^l(A) prod_{b in A^c} t_b  w(A) / (l(A)! (d - l(A))!),

``K_ij = beta_i beta_j t_i t_j M_ij - (-1)^(i+j) alpha_i alpha_j M_ij`` on the
label list ``n, n-1, ..., 1, 0`` (and a second zero ``0'`` when ``n`` is even),
``alpha_a = q^a / a!``, ``beta_a = 1/a!``.  At ``q = 0`` it gives the
normalization (4.1): ``count = d! Pf(B)``.

This module is the exact (pure Python) reference of the route: everything
is a :class:`fractions.Fraction`, so it is meant for small ``n``.  The
multi-modular engine in :mod:`.engine` does the same arithmetic modulo
word-size primes.

Examples
--------
>>> labels(3), labels(4)
([3, 2, 1, 0], [4, 3, 2, 1, 0, 0])
>>> count_exact(6)  # d! Pf(B), Eq. (4.1)
286
>>> [str(x) for x in window_generating_function(3, 2, -1)]  # E_q[y^{N_m(B)}], m = 3, 2, 1
['47/81', '-191/729', '-11/27']
"""

from __future__ import annotations

from collections.abc import Sequence
from fractions import Fraction
from math import factorial
from typing import Any

from forcenet.core.validation import check_int, check_layers

from ..staircase import dimension

__all__ = [
    "labels",
    "schur_entry",
    "minor_summation_matrix",
    "pfaffian",
    "count_exact",
    "window_generating_function",
]


def labels(n: int) -> list[int]:
    """Values of the rows of the Pfaffians: ``n, n-1, ..., 1, 0`` and a second ``0`` when ``n`` is even.

    The list always has even length; the two zeros (``n`` even) are told apart
    by their position (see :func:`schur_entry`).
    """
    n = check_int(n, "n", 0)
    return list(range(n, 0, -1)) + ([0] if n % 2 else [0, 0])


def schur_entry(values: Sequence[int], i: int, j: int) -> Fraction:
    """Schur's ``M_ij = (a_i - a_j)/(a_i + a_j)``; between the two zeros ``+1`` above the diagonal."""
    a, b = values[i], values[j]
    if i == j:
        return Fraction(0)
    if a == 0 and b == 0:  # the entry (0, 0') of even n
        return Fraction(1 if i < j else -1)
    return Fraction(a - b, a + b)


def minor_summation_matrix(n: int, alpha: dict, beta: dict, t: dict | None = None) -> list[list[Fraction]]:
    """``K = T B T + X``: ``B_ij = beta_i beta_j M_ij``, ``X_ij = -(-1)^(i+j) alpha_i alpha_j M_ij``.

    ``alpha``, ``beta`` (and the optional ``t``, default 1) map the parts
    ``1..n`` to weights; the zero labels have ``alpha = beta = t = 1`` except
    ``alpha_0' = 0``.  Then (minor summation, proved in ``notes/free_fermions.md``)

        Pf K = sum_A prod_{a in A} alpha_a prod_{b in B} beta_b t_b  Pf(M_A') Pf(M_B'),

    ``B = {1..n} - A`` and ``A'``, ``B'`` completed by a zero to even size.
    """
    values = labels(n)
    size = len(values)
    t = t or {}

    def weights(pos: int) -> tuple[Fraction, Fraction, Fraction]:
        a = values[pos]
        if a:
            return Fraction(alpha[a]), Fraction(beta[a]), Fraction(t.get(a, 1))
        return (Fraction(0) if pos == n + 1 else Fraction(1)), Fraction(1), Fraction(1)

    w = [weights(pos) for pos in range(size)]
    K = [[Fraction(0)] * size for _ in range(size)]
    for i in range(size):
        for j in range(i + 1, size):
            m = schur_entry(values, i, j)
            sign = -1 if (i + j) % 2 == 0 else 1
            value = w[i][1] * w[j][1] * w[i][2] * w[j][2] * m + sign * w[i][0] * w[j][0] * m
            K[i][j], K[j][i] = value, -value
    return K


def pfaffian(A: Any) -> Fraction:
    """Pfaffian of a skew-symmetric matrix of Fractions (pair elimination with pivoting).

    Examples
    --------
    >>> pfaffian([[0, 1, 2, 3], [-1, 0, 4, 5], [-2, -4, 0, 6], [-3, -5, -6, 0]])  # 1*6 - 2*5 + 3*4
    Fraction(8, 1)
    """
    A = [[Fraction(x) for x in row] for row in A]
    size = len(A)
    if size % 2:
        return Fraction(0)
    result = Fraction(1)
    for k in range(0, size, 2):
        pivot = next((j for j in range(k + 1, size) if A[k][j] != 0), None)
        if pivot is None:
            return Fraction(0)
        if pivot != k + 1:  # swap rows and columns k+1 <-> pivot: the Pfaffian changes sign
            A[k + 1], A[pivot] = A[pivot], A[k + 1]
            for row in A:
                row[k + 1], row[pivot] = row[pivot], row[k + 1]
            result = -result
        a = A[k][k + 1]
        result *= a
        for i in range(k + 2, size):
            ci, di = A[i][k], A[i][k + 1]
            if ci == 0 and di == 0:
                continue
            for j in range(k + 2, size):
                A[i][j] += (ci * A[k + 1][j] - di * A[k][j]) / a
    return result


def _inverse(A: list[list[Fraction]]) -> list[list[Fraction]]:
    size = len(A)
    M = [list(row) + [Fraction(int(i == j)) for j in range(size)] for i, row in enumerate(A)]
    for c in range(size):
        r = next(r for r in range(c, size) if M[r][c] != 0)
        M[c], M[r] = M[r], M[c]
        inv = 1 / M[c][c]
        M[c] = [x * inv for x in M[c]]
        for r in range(size):
            if r != c and M[r][c] != 0:
                f = M[r][c]
                M[r] = [x - f * y for x, y in zip(M[r], M[c])]
    return [row[size:] for row in M]


def _matmul(A: Sequence[Sequence[Fraction | int]], B: Sequence[Sequence[Fraction | int]]) -> list[list[Fraction | int]]:
    return [[sum(A[i][k] * B[k][j] for k in range(len(B))) for j in range(len(B[0]))] for i in range(len(A))]


def count_exact(N: int) -> int:
    """``count(N) = d! Pf(B)``, ``B_ab = M_ab / (a! b!)``: the normalization (4.1) as a Pfaffian, in Fractions.

    Examples
    --------
    >>> [count_exact(N) for N in range(2, 8)]
    [1, 1, 2, 12, 286, 33592]
    """
    N = check_layers(N)
    n, d = N - 1, dimension(N)
    beta = {a: Fraction(1, factorial(a)) for a in range(1, n + 1)}
    K = minor_summation_matrix(n, {a: 0 for a in beta}, beta)  # q = 0: X = 0
    value = pfaffian(K) * factorial(d)
    if value.denominator != 1:  # pragma: no cover - would contradict Schur's formula
        raise ArithmeticError("d! Pf(B) is not an integer")
    return int(value)


def window_generating_function(n: int, q: int | Fraction, y: int | Fraction) -> list[Fraction]:
    """``E_q[y^{N_m(B)}]`` for ``m = n, n-1, ..., 1`` through the Pfaffian point-process kernel (exact).

    Under the weight ``q^l(A) w(A) / (l! (d-l)!)`` the complement ``B`` of the
    ideal is a Pfaffian point process; with ``u = y - 1`` on the window
    ``{m..n}``, ``E_q[y^{N_m(B)}]`` is the leading ``2(n-m+1)``-square Pfaffian
    of ``J + D_u W D_u`` (``notes/free_fermions.md`` Sec. 3 (iv)).  The
    multi-modular engine evaluates exactly this, modulo primes.

    Parameters
    ----------
    n : int
        ``N - 1``, at least 1.
    q, y : int or Fraction
        Level fugacity (``q != -1``) and window fugacity.

    Returns
    -------
    list of Fraction
        Entry ``k`` is the window ``{n-k..n}``.
    """
    n = check_int(n, "n", 1)
    q, y = Fraction(q), Fraction(y)
    alpha = {a: q**a / factorial(a) for a in range(1, n + 1)}
    beta = {a: Fraction(1, factorial(a)) for a in range(1, n + 1)}
    K = minor_summation_matrix(n, alpha, beta)
    zero = {a: 0 for a in beta}
    B = minor_summation_matrix(n, zero, beta)
    Ki = _inverse(K)
    BKi = _matmul(B, Ki)
    BKiB = _matmul(BKi, B)
    u = y - 1
    size = 2 * n
    G = [[Fraction(0)] * size for _ in range(size)]
    for a in range(n):
        for b in range(n):
            # W = -G0^{-1}, G0^{-1} = [[B - B K^-1 B, -B K^-1], [K^-1 B, K^-1]] (copies interleaved)
            G[2 * a][2 * b] = (BKiB[a][b] - B[a][b]) * u * u
            G[2 * a][2 * b + 1] = BKi[a][b] * u
            G[2 * a + 1][2 * b] = -BKi[b][a] * u  # -(K^-1 B)_ab = -(B K^-1)_ba (both skew)
            G[2 * a + 1][2 * b + 1] = -Ki[a][b]
        G[2 * a][2 * a + 1] += 1
        G[2 * a + 1][2 * a] -= 1
    return [pfaffian([row[: 2 * k] for row in G[: 2 * k]]) for k in range(1, n + 1)]
