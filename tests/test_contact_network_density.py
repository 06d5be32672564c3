"""The exact one-force density of a contact network (issue 55): the triangulation's piecewise polynomial, checked
by independent routes (its integral and moments, forcenet.law on the chapter-4 triangle, slice volumes)."""

from __future__ import annotations

import json
from fractions import Fraction

import numpy as np
import pytest
import sympy

import forcenet
from forcenet.cli import main
from forcenet.exact.contact_network.geometries import rectangular_packing, snooker, square_packing, triangle
from forcenet.exact.contact_network.polytope import exact_polytope

pytest.importorskip("PyNormaliz")

from forcenet.exact.contact_network.marginal_density import evaluate, force_densities, integrate
from forcenet.exact.contact_network.triangulation_moments import (
    density_at,
    moments_by_triangulation,
    moments_by_volumes,
)


def _law_on(pieces, law_pieces, unit=1):
    """Each piece's polynomial equals the law's on the law's piece holding its midpoint (law in units ``unit``)."""
    w = law_pieces[0].poly.gens[0]
    for piece in pieces:
        middle = (piece.lo + piece.hi) / 2 / unit
        (match,) = [q for q in law_pieces if q.lo <= middle < q.hi]
        f = sympy.Symbol("f")
        expected = sympy.expand(match.poly.as_expr().subs(w, f / unit) / unit)
        assert sympy.simplify(piece.poly.as_expr() - expected) == 0


@pytest.mark.parametrize("N", [3, 4, 5])
def test_the_triangle_density_is_forcenet_laws(N):
    """Chapter 4's triangle (Sec. 4.2): every floor load's and one contact force's density equals forcenet.law's
    exact density (Eqs. (4.5)-(4.9), sorted uniforms), piece by piece; contact forces in units of 2/sqrt(3)."""
    geo = triangle(N)
    poly = exact_polytope(geo.network)
    floor = [geo.contact[("floor", N, j)] for j in range(1, N + 1)]
    inner = geo.contact[("left", N - 1, 2)]
    densities = force_densities(poly, [*floor, inner])
    for j, k in enumerate(floor, start=1):
        _law_on(densities[k], forcenet.law(N, (N, j)).density)
    _law_on(densities[inner], forcenet.law(N, (N - 1, 2), contact="F6").density, 2 / sympy.sqrt(3))


@pytest.mark.parametrize("geometry", [triangle(4), snooker(3), rectangular_packing(2, 2), square_packing(2, 2)],
                         ids=["triangle", "snooker", "frictional", "frictional-square"])
def test_the_density_integrates_to_one_with_the_exact_moments(geometry):
    """Two routes: the density's integral is 1 and its first two moments are the triangulation's moments and the
    volume route's (lifted polytopes); at a few points it equals the slice-volume density (density_at)."""
    poly = exact_polytope(geometry.network)
    varying = [k for k, label in enumerate(poly.labels) if label.startswith("f") and any(poly.K[k])]
    densities = force_densities(poly, varying)
    moments = moments_by_triangulation(poly)
    for k, pieces in densities.items():
        assert integrate(pieces) == 1
        assert sympy.radsimp(integrate(pieces, 1) - moments.mean[k]) == 0
        assert sympy.radsimp(integrate(pieces, 2) - moments.second[k]) == 0
    k = varying[0]
    if not geometry.network.frictional:
        by_volumes = moments_by_volumes(poly, 2, [k])
        assert (integrate(densities[k], 1), integrate(densities[k], 2)) == (by_volumes.mean[k], by_volumes.second[k])
    points = [poly.scale[k] * Fraction(n, 7) for n in (1, 3, 5)]
    assert [evaluate(densities[k], x) for x in points] == density_at(poly, k, points)


def test_density_at_the_command_line_and_beside_the_sampled_histogram(tmp_path, capsys):
    """``forcenet network FILE --exact --density``: every varying force's pieces in text and json; in Python the
    exact pooled P(f) lies within the sampled histogram's error bars and is drawn beside it."""
    import matplotlib

    matplotlib.use("Agg")
    geo = triangle(4).network
    path = tmp_path / "net.json"
    path.write_text(json.dumps({"grains": geo.grains, "loads": [[g, str(x), str(y)] for g, (x, y, _) in
                                                                enumerate(geo.loads)],
                                "contacts": [[i, j, str(nx), str(ny)] for i, j, nx, ny in geo.contacts]}))
    assert main(["network", str(path), "--exact", "--density", "--format", "json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert all("density" in c for c in out["contacts"])  # no force of the triangle is fixed by balance alone
    assert main(["network", str(path), "--exact", "--density", "0", "--format", "text"]) == 0
    assert "density on [0, " in capsys.readouterr().out
    assert main(["network", str(path), "--exact", "--density", "99"]) == 2
    assert "density" in capsys.readouterr().err
    result = forcenet.network(geo, exact=True, density=True, samples=20000, seed=1)
    edges, density, error = result.force_distribution(12)
    centres = (edges[1:] + edges[:-1]) / 2
    width = edges[1] - edges[0]
    fine = np.linspace(0, 1, 201)
    exact = np.array([result.exact_force_distribution(e + width * fine).mean() for e in edges[:-1]])
    assert np.abs(density - exact).max() < 5 * error.max() + 0.02
    assert len(centres) == 12
    fig = result.plot_force_distribution(12)
    assert [line.get_label() for line in fig.axes[0].get_lines()][-1] == "exact (triangulation)"
