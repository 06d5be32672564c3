"""Exact moments over Q(sqrt(3)) without rescaling (issue 55): Normaliz's algebraic polytopes (e-antic), checked
against the rationalizing route where both apply."""

from __future__ import annotations

import pytest

import forcenet
from forcenet.exact.contact_network.geometries import hexagonal_packing, triangle
from forcenet.exact.contact_network.polytope import exact_polytope

pytest.importorskip("PyNormaliz")

from forcenet.exact.contact_network.number_field import field_polytope, moments_in_number_field
from forcenet.exact.contact_network.triangulation_moments import moments_by_triangulation


@pytest.mark.parametrize("geometry", [triangle(3), hexagonal_packing(2, 3, F=1, p_v=1)], ids=["triangle", "hexagonal"])
def test_the_number_field_route_equals_the_rationalizing_route(geometry):
    """The hexagonal lattice's sqrt(3) kept in the field (row reduction over QQ<sqrt(3)>, Normaliz's algebraic
    triangulation) gives the same exact means and second moments as rescaling to rationals."""
    in_field = moments_in_number_field(geometry.network)
    rescaled = moments_by_triangulation(exact_polytope(geometry.network))
    assert in_field.mean == rescaled.mean and in_field.second == rescaled.second
    assert in_field.dimension == rescaled.dimension > 0


def test_data_outside_the_field_are_refused_in_one_line():
    net = forcenet.contact_network(1, [[0, None, "-sqrt(2)/2", "-sqrt(2)/2"], [0, None, "sqrt(2)/2", "-sqrt(2)/2"]],
                                   [[0, 0, -1]])
    with pytest.raises(forcenet.ArgumentError, match="not in Q\\(sqrt\\(3\\)\\)"):
        field_polytope(net)
