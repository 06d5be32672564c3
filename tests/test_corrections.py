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
