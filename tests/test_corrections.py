"""Corrections of the documentation's mathematics, each checked by an independent computation.

* The floor's corner ``|x| = z = 1`` is a lattice direction with a hard edge: ``W_(N,1) ~ Beta(1, d)``, so
  ``forcenet limit --x 1 --z 1`` reports ``edge_exponent 2`` and amplitudes 2, checked here against exact tables
  and exact laws.
* The bulk response diverges like ``(z - |x|)^(-1/3)`` at the lattice directions (tests/test_edge.py), so the
  grains next to them give the pooled ``P(f)`` a tail ``~ f^(-4)`` for ``1 << f << N^(1/3)``
  (notes/force_distribution.md Sec. 6.3), not the ``f^(-3)`` of an inverse square root: checked here by counting,
  in the continuum profile ``f = z G(x, z)``, the share of grains whose mean ``f`` exceeds a level.
"""

from __future__ import annotations

import json
from fractions import Fraction

import mpmath
import numpy as np
import pytest

import forcenet


def test_the_floor_corner_is_a_lattice_direction_with_a_hard_edge():
    shape = forcenet.limit_shape(1, 1, dps=10)
    assert shape.on_lattice and shape.corner and shape.bulk == 0
    assert shape.edge_exponent == 2 and shape.edge_amplitude == 2 and shape.edge_sd_amplitude == 2
    data = json.loads(shape.to_json())
    assert data["on_lattice_direction"] is True and data["edge_exponent"] == "2"
    assert "Beta(1, d)" in shape.to_text()
    # the soft edges inside and the bulk of the floor are unchanged
    assert forcenet.limit_shape("0.5", "0.5", dps=8).edge_exponent == Fraction(2, 3)
    assert not forcenet.limit_shape("0.5", 1, dps=8).on_lattice
    assert forcenet.limit_shape("-1", "1").corner and not forcenet.limit_shape("0.5", "0.5", dps=8).corner


@pytest.mark.parametrize("N", [4, 6, 9])
def test_the_corner_load_is_beta_1_d_exactly(N):
    """Independent routes: the exact table's corner and the corner's exact law give the moments of Beta(1, d),
    so N^2 <W_(N,1)> -> 2 and N^2 sd -> 2, the corner's amplitudes."""
    d = N * (N - 1) // 2
    table = forcenet.table(N)
    assert table.mean_W[-1][0] == table.mean_W[-1][-1] == Fraction(1, d + 1)
    law = forcenet.law(N, (N, 1))
    assert law.mean == Fraction(1, d + 1) and law.moment(2) == Fraction(2, (d + 1) * (d + 2))
    assert abs(N * N * Fraction(1, d + 1) - 2) <= Fraction(4, N)  # 2 N^(-2) (1 + O(1/N))


def _edge_share(f: mpmath.mpf, z: mpmath.mpf) -> mpmath.mpf:
    """The distance ``delta`` from the lattice direction inside which the mean ``f = z G(z - delta, z)`` exceeds
    ``f`` (G falls monotonically away from the edge, there)."""
    from forcenet.numeric.limit_shape import bulk_response

    def excess(log_delta: mpmath.mpf) -> mpmath.mpf:
        return mpmath.log(z * bulk_response(z - mpmath.exp(log_delta), z, dps=20)) - mpmath.log(f)

    from forcenet.numeric.limit_shape.edge import bulk_edge_coefficient

    guess = 3 * mpmath.log(z * bulk_edge_coefficient(z) / f)  # (z C / f)^3: the inverse cube root
    return mpmath.exp(mpmath.findroot(excess, (guess - 1, guess + 1), solver="secant"))


def test_the_pooled_tail_of_the_mean_profile_falls_like_f_to_the_minus_four():
    """Pooled over every grain, layer ``z`` has weight ``2z dz`` and the share ``delta_f(z)/z`` of its grains
    beyond ``f`` near the two edges, so ``P(F > f) = int 2 delta_f(z) dz``. With ``delta_f ~ (z C/f)^3`` this is
    ``A f^(-3)``, ``A = 2 int z^3 C(z)^3 dz``: the density ``3 A f^(-4)``."""
    from forcenet.numeric.limit_shape.edge import bulk_edge_coefficient

    with mpmath.workdps(20):
        nodes = [(mpmath.mpf(k) + mpmath.mpf(1) / 2) / 12 for k in range(12)]  # midpoints on (0, 1)
        tails = {f: sum(2 * _edge_share(mpmath.mpf(f), z) for z in nodes) / len(nodes) for f in (40, 80)}
        slope = mpmath.log(tails[40] / tails[80]) / mpmath.log(2)
        assert abs(slope - 3) < 0.05, slope  # P(F > f) ~ f^(-3), the density ~ f^(-4); an inverse square root: 2
        amplitude = sum(2 * (z * bulk_edge_coefficient(z)) ** 3 for z in nodes) / len(nodes)
        assert abs(tails[80] * 80**3 / amplitude - 1) < 0.05


# ------------------------------------------------------------------------------------------------ fluctuations Sec. 6.1


def _integral(a: int, b: int) -> Fraction:
    """``Integral Integral_(0 < s < t < 1) s^a t^b ds dt``."""
    return Fraction(1, (a + 1) * (a + b + 2))


def _L(j: int, a: int, b: int, c: int) -> Fraction:
    """``L_j`` on the monomial ``s^a t^b zeta^c``: the coefficient of ``zeta^j``, integrated over ``s < t``."""
    return _integral(a, b) if c == j else Fraction(0)


def _rank(rows: list[list[Fraction]]) -> int:
    import flint

    matrix = flint.fmpq_mat(len(rows), len(rows[0]), [flint.fmpq(x.numerator, x.denominator) for row in rows for x in row])
    return int(matrix.rref()[1])


def _monomials(d: int, m: int) -> list[tuple[int, int, int]]:
    return [(a, b, c) for a in range(d + 1) for b in range(d + 1 - a) for c in range(m + 1)]


def _weights_exist(nodes, d: int, m: int, functional) -> bool:
    """Whether weights make ``sum_nu w_nu F(x_nu)`` equal ``functional(F)`` for every F of the degrees (exact)."""
    monomials = _monomials(d, m)
    lhs = [[s**a * t**b * z**c for (s, t, z) in nodes] for (a, b, c) in monomials]
    augmented = [row + [functional(a, b, c)] for row, (a, b, c) in zip(lhs, monomials)]
    return _rank(lhs) == _rank(augmented)


def _all_L(nodes, d: int, m: int) -> bool:
    """Whether one set of nodes gives every ``L_j``, ``j = 0..m`` (each with its own weights)."""
    return all(_weights_exist(nodes, d, m, lambda a, b, c, j=j: _L(j, a, b, c)) for j in range(m + 1))


@pytest.mark.parametrize("d, m", [(2, 3), (8, 3), (4, 5)])
def test_the_full_task_form_has_rank_gram_times_m_plus_one(d, m):
    """notes/fluctuations.md Sec. 6.1, the full task: every ``L_j``, not one combination.  The form
    ``beta(A, H e_j) = L_j(A H)`` on ``(V_k (x) Z_m) x (V_k (x) Q^(m+1))`` is the Gram form of ``s < t`` on ``V_k``
    tensored with the identity of ``Q^(m+1)``: rank ``(k+1)(k+2)/2 (m+1)``; a route answering from ``r`` values
    makes it a sum of ``r`` terms of rank one in ``A``, so ``r`` is at least that."""
    k = d // 2
    A = [(a, b, c) for a in range(k + 1) for b in range(k + 1 - a) for c in range(m + 1)]
    H = [(a, b, j) for a in range(k + 1) for b in range(k + 1 - a) for j in range(m + 1)]
    form = [[_L(j, a + a2, b + b2, c) for (a2, b2, j) in H] for (a, b, c) in A]
    assert _rank(form) == (k + 1) * (k + 2) // 2 * (m + 1) == len(A)


def test_the_full_task_bound_is_attained_by_midpoints_times_m_plus_one_zetas_and_not_below():
    """d = 2, m = 3: the bound is 3 * 4 = 12.  The three edge midpoints of ``0 < s < t < 1`` times four distinct
    ``zeta`` give every ``L_j``; nine nodes of that form (three ``zeta``) or eleven random nodes do not.  The six
    nodes that attain the single combination's bound give that combination and not every ``L_j``: "attained"
    holds for one combination only."""
    d, m = 2, 3
    half = Fraction(1, 2)
    midpoints = [(Fraction(0), half), (half, Fraction(1)), (half, half)]
    zetas = [Fraction(z) for z in (-2, -1, 1, 3)]
    assert _all_L([(s, t, z) for s, t in midpoints for z in zetas], d, m)
    assert not _all_L([(s, t, z) for s, t in midpoints for z in zetas[:3]], d, m)
    rng = np.random.default_rng(54)
    random_nodes = [tuple(Fraction(int(x), 97) for x in rng.integers(1, 97, size=3)) for _ in range(11)]
    assert not _all_L(random_nodes, d, m)
    # one combination sum_j c_j L_j with c_j = sum of two atoms' powers: its bound 3 * (floor(m/2) + 1) = 6 is met
    atoms, masses = [Fraction(2), Fraction(-1, 3)], [Fraction(1), Fraction(5, 2)]
    c = [sum(w * z**j for w, z in zip(masses, atoms)) for j in range(m + 1)]
    six = [(s, t, z) for s, t in midpoints for z in atoms]
    assert _weights_exist(six, d, m, lambda a, b, cc: c[cc] * _integral(a, b))
    assert not _all_L(six, d, m)
