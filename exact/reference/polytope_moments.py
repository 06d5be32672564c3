"""Reference route: a polytope's exact moments by vertex enumeration and a pulling triangulation (fractions).

The contact networks' exact route (:mod:`forcenet.exact.contact_network.triangulation_moments`)
asks Normaliz; this module checks it from the definitions alone, for small
polytopes ``{x : H x + h >= 0}`` of full dimension ``d``:

1. vertices: every ``d`` inequalities whose rows are independent, made
   tight, solved exactly; kept when every inequality holds there;
2. a pulling triangulation (the first vertex ``v`` of a face, joined to the
   triangulations of the face's facets that miss ``v``), facets found as the
   vertex sets of one more tight inequality of one less dimension;
3. each simplex's volume ``|det(v_i - v_0)| / d!``, its centroid and second
   moment matrix ``(sum v_i v_i^T + s s^T)/((d+1)(d+2))`` with ``s = sum v_i``.

Independence: plain ``Fraction`` arithmetic, nothing of ``forcenet.exact``;
cost ``C(#inequalities, d)`` solves, for tests (``d <= 8``, a few dozen rows).

Examples
--------
>>> from fractions import Fraction as F
>>> H, h = [[F(1), F(0)], [F(0), F(1)], [F(-1), F(-1)]], [F(0), F(0), F(1)]  # the unit triangle
>>> volume, mean, second = polytope_moments(H, h)
>>> volume, mean, second[0][0], second[0][1]
(Fraction(1, 2), [Fraction(1, 3), Fraction(1, 3)], Fraction(1, 6), Fraction(1, 12))
"""

from __future__ import annotations

from fractions import Fraction
from itertools import combinations
from math import factorial

__all__ = ["vertices", "pulling_triangulation", "polytope_moments"]

Matrix = list[list[Fraction]]


def _solve(rows: Matrix, rhs: list[Fraction]) -> list[Fraction] | None:
    """The solution of a square system, or None when it is singular (Gauss-Jordan in fractions)."""
    n = len(rows)
    m = [list(row) + [b] for row, b in zip(rows, rhs)]
    for col in range(n):
        pivot = next((r for r in range(col, n) if m[r][col] != 0), None)
        if pivot is None:
            return None
        m[col], m[pivot] = m[pivot], m[col]
        for r in range(n):
            if r != col and m[r][col] != 0:
                factor = m[r][col] / m[col][col]
                m[r] = [a - factor * b for a, b in zip(m[r], m[col])]
    return [m[r][n] / m[r][r] for r in range(n)]


def _rank(rows: Matrix) -> int:
    m = [list(row) for row in rows]
    rank, cols = 0, len(m[0]) if m else 0
    for col in range(cols):
        pivot = next((r for r in range(rank, len(m)) if m[r][col] != 0), None)
        if pivot is None:
            continue
        m[rank], m[pivot] = m[pivot], m[rank]
        for r in range(rank + 1, len(m)):
            if m[r][col] != 0:
                factor = m[r][col] / m[rank][col]
                m[r] = [a - factor * b for a, b in zip(m[r], m[rank])]
        rank += 1
    return rank


def _affine_dimension(points: list[list[Fraction]]) -> int:
    if len(points) <= 1:
        return 0
    return _rank([[a - b for a, b in zip(p, points[0])] for p in points[1:]])


def vertices(H: Matrix, h: list[Fraction]) -> list[list[Fraction]]:
    """The vertices of ``{x : H x + h >= 0}`` (full-dimensional, bounded), by brute force.

    Examples
    --------
    >>> from fractions import Fraction as F
    >>> sorted(map(tuple, vertices([[F(1)], [F(-1)]], [F(0), F(2)])))
    [(Fraction(0, 1),), (Fraction(2, 1),)]
    """
    d = len(H[0])
    found: list[list[Fraction]] = []
    for subset in combinations(range(len(H)), d):
        x = _solve([H[r] for r in subset], [-h[r] for r in subset])
        if x is None or x in found:
            continue
        if all(sum((a * xi for a, xi in zip(row, x)), Fraction(0)) + c >= 0 for row, c in zip(H, h)):
            found.append(x)
    return found


def pulling_triangulation(H: Matrix, h: list[Fraction], points: list[list[Fraction]]) -> list[tuple[int, ...]]:
    """Simplices (vertex indices) of the pulling triangulation of the polytope with vertices ``points``.

    Examples
    --------
    >>> from fractions import Fraction as F
    >>> square = [[F(1), F(0)], [F(0), F(1)], [F(-1), F(0)], [F(0), F(-1)]], [F(0), F(0), F(1), F(1)]
    >>> len(pulling_triangulation(*square, vertices(*square)))
    2
    """
    tight = [frozenset(r for r, (row, c) in enumerate(zip(H, h))
                       if sum((a * xi for a, xi in zip(row, p)), Fraction(0)) + c == 0) for p in points]

    def triangulate(face: tuple[int, ...], dimension: int) -> list[tuple[int, ...]]:
        if dimension == 0:
            return [face[:1]]
        apex = face[0]
        on_face = frozenset.intersection(*(tight[v] for v in face))
        facets = set()
        for r in set().union(*(tight[v] for v in face)) - on_face:
            facet = tuple(v for v in face if r in tight[v])
            if apex not in facet and _affine_dimension([points[v] for v in facet]) == dimension - 1:
                facets.add(facet)
        return [(apex, *simplex) for facet in sorted(facets) for simplex in triangulate(facet, dimension - 1)]

    return triangulate(tuple(range(len(points))), len(H[0]))


def polytope_moments(H: Matrix, h: list[Fraction]) -> tuple[Fraction, list[Fraction], Matrix]:
    """Volume, mean and second moment matrix ``E[x x^T]`` of the uniform measure on ``{x : H x + h >= 0}``.

    Examples
    --------
    >>> from fractions import Fraction as F
    >>> polytope_moments([[F(1)], [F(-1)]], [F(0), F(2)])
    (Fraction(2, 1), [Fraction(1, 1)], [[Fraction(4, 3)]])
    """
    d = len(H[0])
    points = vertices(H, h)
    total = Fraction(0)
    first = [Fraction(0)] * d
    second = [[Fraction(0)] * d for _ in range(d)]
    for simplex in pulling_triangulation(H, h, points):
        v = [points[k] for k in simplex]
        volume = abs(_determinant([[a - b for a, b in zip(p, v[0])] for p in v[1:]])) / factorial(d)
        s = [sum((p[i] for p in v), Fraction(0)) for i in range(d)]
        total += volume
        for i in range(d):
            first[i] += volume * s[i] / (d + 1)
            for j in range(d):
                outer = sum((p[i] * p[j] for p in v), Fraction(0)) + s[i] * s[j]
                second[i][j] += volume * outer / ((d + 1) * (d + 2))
    return total, [x / total for x in first], [[x / total for x in row] for row in second]


def _determinant(rows: Matrix) -> Fraction:
    m = [list(row) for row in rows]
    n, det = len(m), Fraction(1)
    for col in range(n):
        pivot = next((r for r in range(col, n) if m[r][col] != 0), None)
        if pivot is None:
            return Fraction(0)
        if pivot != col:
            m[col], m[pivot] = m[pivot], m[col]
            det = -det
        det *= m[col][col]
        for r in range(col + 1, n):
            factor = m[r][col] / m[col][col]
            m[r] = [a - factor * b for a, b in zip(m[r], m[col])]
    return det
