"""Contact networks (issue 55): the model's refusals, the polytope, the exact route by two routes and a reference."""

from __future__ import annotations

import random
from fractions import Fraction

import pytest
import sympy

import forcenet
from forcenet.core.errors import ArgumentError
from forcenet.exact.contact_network.geometries import triangle
from forcenet.exact.contact_network.model import contact_network, parse_json
from forcenet.exact.contact_network.polytope import check_polytope, exact_polytope
from forcenet.exact.reference.polytope_moments import polytope_moments

pytest.importorskip("PyNormaliz")

from forcenet.exact.contact_network.triangulation_moments import (
    moments_by_triangulation,
    moments_by_volumes,
)

# rational unit normals (Pythagorean triples), so that random networks have rational data
NORMALS = [(1, 0), (0, 1), (Fraction(3, 5), Fraction(4, 5)), (Fraction(4, 5), Fraction(3, 5)),
           (Fraction(5, 13), Fraction(12, 13)), (Fraction(12, 13), Fraction(5, 13)), (Fraction(8, 17), Fraction(15, 17))]


def random_network(seed: int, grains: int, contacts: int) -> forcenet.exact.contact_network.model.ContactNetwork:
    """Random contacts with rational normals, loaded by minus the forces of a random positive network (so a
    strictly positive network exists: the polytope has an interior point)."""
    rng = random.Random(seed)
    chosen = []
    for _ in range(contacts):
        i = rng.randrange(grains)
        j = rng.choice([None] + [g for g in range(grains) if g != i])
        nx, ny = rng.choice(NORMALS)
        chosen.append([i, j, nx * rng.choice((-1, 1)), ny * rng.choice((-1, 1))])
    load = [[Fraction(0), Fraction(0)] for _ in range(grains)]
    for i, j, nx, ny in chosen:
        f = Fraction(rng.randint(1, 5))
        load[i][0] += f * nx
        load[i][1] += f * ny
        if j is not None:
            load[j][0] -= f * nx
            load[j][1] -= f * ny
    return contact_network(grains, chosen, [[g, *xy] for g, xy in enumerate(load)])


def bounded_networks(dimension: int, grains: int, contacts: int, count: int) -> list:
    found = []
    for seed in range(2000):
        net = random_network(seed, grains, contacts)
        try:
            check_polytope(net)
        except ArgumentError:
            continue
        if exact_polytope(net).dimension == dimension:
            found.append(net)
            if len(found) == count:
                return found
    raise AssertionError("no network found")


def _reference(poly):
    """Means and second moments of every variable from the reference route (vertices, pulling triangulation)."""
    _, mean, second = polytope_moments([list(r) for r in poly.H], list(poly.h))
    d = poly.dimension
    out_mean, out_second = [], []
    for k in range(len(poly.z0)):
        a, c = poly.K[k], poly.z0[k]
        m1 = c + sum(a[i] * mean[i] for i in range(d))
        m2 = c * c + 2 * c * sum(a[i] * mean[i] for i in range(d)) + sum(
            a[i] * a[j] * second[i][j] for i in range(d) for j in range(d))
        out_mean.append(sympy.radsimp(poly.scale[k] * sympy.Rational(m1)))
        out_second.append(sympy.radsimp(poly.scale[k] ** 2 * sympy.Rational(m2)))
    return out_mean, out_second


@pytest.mark.parametrize("dimension, grains, contacts", [(5, 3, 11), pytest.param(8, 4, 16, marks=pytest.mark.slow)])
def test_exact_moments_equal_the_reference_route(dimension, grains, contacts):
    """Acceptance: rational data, dimension 5 and 8: Normaliz's two routes equal vertex enumeration + pulling."""
    for net in bounded_networks(dimension, grains, contacts, 2 if dimension == 5 else 1):
        poly = exact_polytope(net)
        tri = moments_by_triangulation(poly)
        mean, second = _reference(poly)
        assert list(tri.mean) == mean and list(tri.second) == second
        vol = moments_by_volumes(poly, 2, [0, 1])
        assert vol.mean[:2] == tri.mean[:2] and vol.second[:2] == tri.second[:2]


def test_dimension_8_the_two_normaliz_routes_agree():
    """Dimension 8 by default (the reference route's check at dimension 8 is slow): triangulation = volumes."""
    net = bounded_networks(8, 4, 16, 1)[0]
    poly = exact_polytope(net)
    tri = moments_by_triangulation(poly)
    chosen = [0, 5, 11]
    vol = moments_by_volumes(poly, 2, chosen)
    assert [vol.mean[k] for k in chosen] == [tri.mean[k] for k in chosen]
    assert [vol.second[k] for k in chosen] == [tri.second[k] for k in chosen]


@pytest.mark.parametrize("N", [2, 3, 4, 5, 6, 7])
def test_the_triangle_as_a_contact_network_equals_forcenet_table(N):
    """Chapter 4's triangle built from contacts: every <W_ij> and the floor's <W_Nj^2> equal forcenet.table."""
    geo = triangle(N)
    poly = exact_polytope(geo.network)
    assert poly.dimension == N * (N - 1) // 2
    m = moments_by_triangulation(poly)
    table = forcenet.table(N, moments=2)
    for i in range(1, N):
        for j in range(1, i + 1):
            W = sympy.sqrt(3) / 2 * (m.mean[geo.contact[("left", i, j)]] + m.mean[geo.contact[("right", i, j)]])
            assert sympy.nsimplify(sympy.radsimp(W)) == sympy.Rational(table.mean_W[i - 1][j - 1])
    for j in range(1, N + 1):
        floor = geo.contact[("floor", N, j)]
        assert m.mean[floor] == sympy.Rational(table.mean_W[N - 1][j - 1])
        assert m.second[floor] == sympy.Rational(table.moment(2)[N - 1][j - 1])


def test_the_volume_route_equals_the_triangulation_on_the_triangle():
    geo = triangle(5)
    poly = exact_polytope(geo.network)
    chosen = [geo.contact[("floor", 5, 2)], geo.contact[("left", 2, 1)], geo.contact[("side", 3, 1)]]
    vol = moments_by_volumes(poly, 2, chosen)
    tri = moments_by_triangulation(poly)
    assert [vol.mean[k] for k in chosen] == [tri.mean[k] for k in chosen]
    assert [vol.second[k] for k in chosen] == [tri.second[k] for k in chosen]


BAD = {
    "missing grain": ('{"grains": 2, "contacts": [[0, 3, 1, 0]], "loads": []}', "grain 3 does not exist"),
    "not unit": ('{"grains": 1, "contacts": [[0, null, "1", "1"]], "loads": []}', "not 1"),
    "nan": ('{"grains": 1, "contacts": [[0, null, 1, 0]], "loads": [[0, NaN, 0]]}', "not a finite number"),
    "nan text": ('{"grains": 1, "contacts": [[0, null, 1, 0]], "loads": [[0, "nan", 0]]}', "not a finite number"),
    "not json": ('{"grains": 1, ', "is not JSON"),
    "unbalanced": ('{"grains": 2, "contacts": [[0, 1, 1, 0]], "loads": [[0, "1", 0]]}', "net force is (1, 0)"),
    "tensile": ('{"grains": 1, "contacts": [[0, null, 0, -1]], "loads": [[0, 0, 1]]}', "infeasible"),
    "self-stress": ('{"grains": 2, "contacts": [[0, 1, 1, 0], [0, null, -1, 0], [1, null, 1, 0], [0, null, 0, -1], '
                    '[1, null, 0, -1]], "loads": [[0, 0, -1], [1, 0, -1]]}', "unbounded"),
}


@pytest.mark.parametrize("case", sorted(BAD))
def test_every_bad_network_is_one_clear_line(case):
    text, message = BAD[case]
    with pytest.raises(ArgumentError) as info:
        check_polytope(parse_json(text))
    assert message in str(info.value) and "\n" not in str(info.value)


def test_sqrt3_needs_scaling_and_irrational_mixtures_are_refused():
    net = contact_network(1, [[0, None, "-sqrt(2)/2", "-sqrt(2)/2"], [0, None, "1/2", "-sqrt(3)/2"],
                              [0, None, 0, -1]], [[0, 0, -1]])
    with pytest.raises(ArgumentError, match="--samples"):
        exact_polytope(net)
    floats = contact_network(1, [[0, None, 0.0, -1.0], [0, None, 0, -1]], [[0, 0, -1]])
    with pytest.raises(ArgumentError, match="exact data"):
        exact_polytope(floats)


def test_random_networks_exact_route_and_sampler_agree_by_forcenet_testing():
    """Random small rational networks (hypothesis): the sampler's chain agrees with the exact means by
    forcenet.testing (spaced batch means of a Markov chain, a correct sampler fails at most at alpha)."""
    hypothesis = pytest.importorskip("hypothesis")
    import numpy as np
    from hypothesis import strategies as st

    from forcenet.numeric.contact_network.hit_and_run import HitAndRun
    from forcenet.testing import assert_agrees

    @hypothesis.settings(max_examples=4, deadline=None, derandomize=True)
    @hypothesis.given(seed=st.integers(0, 10**6), grains=st.integers(1, 3), extra=st.integers(1, 4))
    def check(seed, grains, extra):
        net = random_network(seed, grains, 2 * grains + extra)
        try:
            check_polytope(net)
        except ArgumentError:
            hypothesis.assume(False)
        walk = HitAndRun(net)
        hypothesis.assume(walk.dimension >= 1)
        exact = [float(x) for x in moments_by_triangulation(exact_polytope(net), 1).mean]
        chain = walk.run(6000, seed=seed)
        varying = ~walk.fixed
        assert np.allclose(chain.samples[:, ~varying].mean(axis=0), np.array(exact)[~varying])
        assert_agrees(chain.samples[:, varying], list(np.array(exact)[varying]), chain=True, alpha=1e-3, bounds=False)

    check()


@pytest.mark.parametrize("N", [2, 3, 4])
def test_the_snooker_packing_has_the_thesis_dimension_and_the_reference_moments(N):
    """Sec. 7.2.1's snooker triangle: dimension N(N-1)/2 (the thesis's), exact moments = the reference route."""
    from forcenet.exact.contact_network.geometries import snooker

    poly = exact_polytope(snooker(N).network)
    assert poly.dimension == N * (N - 1) // 2
    tri = moments_by_triangulation(poly)
    if N <= 3:
        assert (list(tri.mean), list(tri.second)) == _reference(poly)
    vol = moments_by_volumes(poly, 2, [0])
    assert (vol.mean[0], vol.second[0]) == (tri.mean[0], tri.second[0])


def test_one_force_exact_density_equals_forcenet_law():
    """The exact density by slice volumes equals forcenet.law's (an independent exact route): a floor load and
    a contact force of the triangle (in units of 2/sqrt(3), as forcenet.law gives contact forces)."""
    from forcenet.exact.contact_network.triangulation_moments import density_at

    geo = triangle(4)
    poly = exact_polytope(geo.network)
    points = [Fraction(1, 5), Fraction(1, 3), Fraction(1, 2)]
    floor = density_at(poly, geo.contact[("floor", 4, 2)], points)
    assert floor == [sympy.Rational(forcenet.law(4, (4, 2)).density_at(x)) for x in points]
    unit = 2 / sympy.sqrt(3)
    force = density_at(poly, geo.contact[("left", 3, 2)], [x * unit for x in points])
    expected = [sympy.Rational(forcenet.law(4, (3, 2), contact="F6").density_at(x)) for x in points]
    assert [sympy.radsimp(f * unit) for f in force] == expected


@pytest.mark.parametrize("loads", [{"F": 1, "g": 1}, {"F": 0, "p_v": 1, "g": "1/2"}, {"F": 2, "p_v": 1}])
def test_the_hexagonal_packing_equals_todays_packing_route(loads):
    """The N x P packing of Secs. 3.2-3.3 as a contact network (left wall's p_h large: fully mobilized) has
    the <W_ij> of forcenet.exact.packing.mobilized (integration of prod W over the q-cube, Eq. (3.10))."""
    from forcenet.exact.contact_network.geometries import hexagonal_packing
    from forcenet.exact.packing.mobilized import mean_W_mobilized

    N, P = 3, 3
    geo = hexagonal_packing(N, P, p_h="100*sqrt(3)", **loads)
    m = moments_by_triangulation(exact_polytope(geo.network), 1).mean

    def W(i, j):
        if i == N:
            return m[geo.contact[("floor", i, j)]]
        right = m[geo.contact[("right", i, j)]] if j < P else 0
        return sympy.radsimp(sympy.sqrt(3) / 2 * (m[geo.contact[("left", i, j)]] + right))

    reference = mean_W_mobilized(N, P, F=loads.get("F", 1), pv=loads.get("p_v", 0), mg=loads.get("g", 0))
    assert [[W(i, j) for j in range(1, P + 1)] for i in range(1, N + 1)] == [
        [sympy.Rational(x) for x in row] for row in reference]
