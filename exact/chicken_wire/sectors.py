"""Exact characteristic polynomials of the chicken-wire transfer matrix per particle sector.

The unweighted row-to-row transfer matrix (:mod:`.model`) is an integer
matrix that conserves the number of particles per row.  Its characteristic
polynomial, restricted to a sector, is computed exactly with python-flint
and factored over the integers.  The Perron root itself is a real number:
it is isolated from these factors by
:func:`forcenet.numeric.chicken_wire.transfer.perron_root` (``exact`` returns
no floats).

Examples
--------
>>> [-2, 0, 0, 1] in [c for c, _ in sector_polynomial_factors(6, particles=3)]  # x^3 - 2: Perron root 2^(1/3)
True
"""

from __future__ import annotations

from itertools import product

import flint

from forcenet.core.validation import check_int

from .model import EMPTY, LEFT, RIGHT, row_transitions

__all__ = ["sector_polynomial_factors"]

MAX_WIDTH = 6  # the dense integer matrix has 3^L rows


def sector_polynomial_factors(L: int, particles: int | None = None) -> list[tuple[list[int], int]]:
    """Irreducible integer factors of a sector's characteristic polynomial (transfer matrix, Sec. 7.4.1).

    Parameters
    ----------
    L : int
        Cylinder width, ``2 <= L <= 6``.
    particles : int, optional
        Particles per row, ``0..L``; ``None`` takes the whole matrix.

    Returns
    -------
    list of (coefficients, multiplicity)
        Coefficients constant term first, Python ints; sorted by degree, then
        coefficients.

    Raises
    ------
    ArgumentError
        If ``L`` is outside ``2..6`` or ``particles`` outside ``0..L``.
    ArgumentTypeError
        If ``L`` or ``particles`` is not an integer.

    Examples
    --------
    >>> sector_polynomial_factors(4, particles=2)
    [([-1, 1], 8), ([0, 1], 8), ([1, 1], 2), ([-2, 0, 1], 1), ([1, 0, 1], 1), ([2, 0, 1], 1)]
    """
    L = check_int(L, "L", 2, MAX_WIDTH)
    if particles is not None:
        particles = check_int(particles, "particles", 0, L)
    states = [st for st in product((EMPTY, RIGHT, LEFT), repeat=L) if particles is None or L - st.count(EMPTY) == particles]
    index = {st: k for k, st in enumerate(states)}
    T = [[0] * len(states) for _ in states]
    for D in states:
        for nxt, _ in row_transitions(L)[D]:
            T[index[nxt]][index[D]] += 1

    _, factors = flint.fmpz_mat(T).charpoly().factor()
    out = [([int(c) for c in f.coeffs()], int(e)) for f, e in factors]
    return sorted(out, key=lambda fe: (len(fe[0]), fe[0]))
