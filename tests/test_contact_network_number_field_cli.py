"""The exact route at the command line over Q(sqrt(3)) (issue 55): a network whose balance equations mix
sqrt(3) with rationals so that no rescaling of equations and forces makes them rational (one grain with the
normals (-1/2, -sqrt(3)/2) and (3/5, -4/5) in the same balance equations) is no longer refused by
``forcenet network FILE --exact``: it falls back to Normaliz's triangulation over the number field.

Checked against two independent routes: the exact moments by sympy's iterated integration over the polygon
(d = 2: the other forces solved by sympy in two chosen forces, the polygon's vertices by intersecting its edges'
lines, the integral slab by slab between the vertices' abscissae), and hit-and-run within its error bars.
"""

from __future__ import annotations

import itertools
import json
import subprocess
import sys

import numpy as np
import pytest
import sympy
from hypothesis import assume, given, settings
from hypothesis import strategies as st

import forcenet
from forcenet.exact.contact_network.geometries import rectangular_packing
from forcenet.exact.contact_network.number_field import in_number_field
from forcenet.exact.contact_network.polytope import balance, exact_polytope

pytest.importorskip("PyNormaliz")

SQ = sympy.sqrt(3)
CONTACTS = [[0, None, "-1/2", "-sqrt(3)/2"], [0, None, "3/5", "-4/5"], [0, None, "-3/5", "-4/5"],
            [0, None, "1/2", "-sqrt(3)/2"]]
LOADS = [[0, "1/10", -1]]
DOCUMENT = {"grains": 1, "contacts": CONTACTS, "loads": LOADS}


def _network():
    return forcenet.contact_network(1, CONTACTS, LOADS)


def _iterated_integral_moments(net, moments=2):
    """Every force's exact <f> and <f^2> by sympy: forces 0..d-1 of A f = b solved in terms of the last two
    (x, y), the polygon {f >= 0} cut into slabs between its vertices' x, and integrate(f dy dx) per slab."""
    x, y = sympy.symbols("x y", real=True)
    n = len(net.contacts)
    f = sympy.symbols(f"f0:{n}", real=True)
    equations = [sum(f[c] * net.contacts[c][2 + axis] for c in range(n)) - net.loads[0][axis]
                 for axis in (0, 1)]  # a wall contact pushes the grain by -f n: sum_c -f_c n_c + load = 0
    solution = sympy.solve(equations, f[: n - 2], dict=True)[0]
    force = [sympy.expand(solution.get(f[c], f[c]).subs({f[n - 2]: x, f[n - 1]: y})) for c in range(n)]
    lines = [(sympy.expand(g).coeff(x), sympy.expand(g).coeff(y), sympy.expand(g).subs({x: 0, y: 0})) for g in force]
    vertices = []
    for (a1, b1, c1), (a2, b2, c2) in itertools.combinations(lines, 2):
        det = sympy.radsimp(a1 * b2 - a2 * b1)
        if det == 0:
            continue
        point = (sympy.radsimp((b1 * c2 - b2 * c1) / det), sympy.radsimp((a2 * c1 - a1 * c2) / det))
        if all(sympy.radsimp(g.subs({x: point[0], y: point[1]})) >= 0 for g in force):
            vertices.append(point)
    xs = sorted(set(sympy.nsimplify(sympy.radsimp(v[0])) for v in vertices), key=float)
    volume, first, second = 0, [0] * n, [0] * n
    for lo_x, hi_x in zip(xs, xs[1:]):
        middle = (lo_x + hi_x) / 2
        lower = [-(a * x + c) / b for a, b, c in lines if b > 0]  # a x + b y + c >= 0
        upper = [-(a * x + c) / b for a, b, c in lines if b < 0]
        lo_y = max(lower, key=lambda e: float(e.subs(x, middle)))
        hi_y = min(upper, key=lambda e: float(e.subs(x, middle)))

        def integral(expression, lo_y=lo_y, hi_y=hi_y, lo_x=lo_x, hi_x=hi_x):
            return sympy.integrate(sympy.integrate(expression, (y, lo_y, hi_y)), (x, lo_x, hi_x))

        volume += integral(sympy.Integer(1))
        for c in range(n):
            first[c] += integral(force[c])
            if moments >= 2:
                second[c] += integral(force[c] ** 2)
    return [v / volume for v in first], [v / volume for v in second], len(vertices)


def _same(a, b):
    """Exact equality of two numbers of Q(sqrt(3)) written in any form."""
    return sympy.expand(sympy.radsimp(sympy.expand(a - b))) == 0


def test_no_rescaling_makes_this_network_rational_but_it_lies_in_the_field():
    net = _network()
    with pytest.raises(forcenet.ArgumentError, match="no rescaling removes"):
        exact_polytope(net)
    plan = forcenet.network_plan(net, exact=True, moments=2)
    assert plan.runnable and plan.methods == ("triangulation",)
    assert "Q(sqrt(3))" in plan.cost.what and 0 < plan.cost.seconds < 5
    refused = forcenet.network_plan(net, exact=True, method="volumes")
    assert not refused.runnable and "triangulation" in refused.cost.refusal


def test_the_cli_exact_moments_equal_sympys_integral_and_the_sampler(tmp_path):
    """``forcenet network FILE --exact --moments 2 --format json`` (a subprocess): the JSON's exact strings equal
    the iterated integrals exactly, and hit-and-run's means lie within 4 error bars of them."""
    path = tmp_path / "network.json"
    path.write_text(json.dumps(DOCUMENT))
    done = subprocess.run([sys.executable, "-m", "forcenet", "network", str(path), "--exact", "--moments", "2",
                           "--format", "json"], capture_output=True, text=True, check=False)
    assert done.returncode == 0, done.stderr
    output = json.loads(done.stdout)
    mean, second, vertices = _iterated_integral_moments(_network())
    assert output["dimension"] == 2 and vertices == 4  # 4 forces, 2 equations; a quadrilateral, not one simplex
    got_mean = [sympy.sympify(c["mean"]) for c in output["contacts"]]
    got_second = [sympy.sympify(c["second"]) for c in output["contacts"]]
    assert any(not v.is_rational for v in got_mean)  # sqrt(3) is in the answer
    assert all(_same(a, b) for a, b in zip(got_mean + got_second, mean + second))
    sampled = forcenet.network(_network(), samples=20000, seed=5)
    exact = np.array([float(v) for v in mean])
    assert np.all(np.abs(sampled.sampled_mean - exact) < 4 * sampled.sampled_error + 1e-12)


def test_numbers_outside_the_field_are_still_refused_naming_samples(tmp_path):
    document = {"grains": 1, "contacts": [[0, None, "-sqrt(2)/2", "-sqrt(2)/2"], [0, None, "3/5", "-4/5"],
                                          [0, None, "-1/2", "-sqrt(3)/2"]], "loads": [[0, 0, -1]]}
    path = tmp_path / "network.json"
    path.write_text(json.dumps(document))
    done = subprocess.run([sys.executable, "-m", "forcenet", "network", str(path), "--exact"], capture_output=True,
                          text=True, check=False)
    assert done.returncode == 2 and "--samples" in done.stderr and len(done.stderr.strip().splitlines()) == 1
    assert not in_number_field(balance(forcenet.contact_network(1, document["contacts"], document["loads"])))


def test_chapter_5s_packing_at_60_degrees_is_exact_through_the_field():
    """The frictional rectangular packing at alpha = 60 degrees (cos 1/2, sin sqrt(3)/2): its Coulomb cones
    ``mu f +- t >= 0`` need the normal and tangential forces in units of rational ratio, its balance equations
    in a ratio in sqrt(3) Q, so the rescaling refuses; the field route gives the exact means, and hit-and-run
    agrees within 4 error bars (forces fixed by balance alone: exactly)."""
    net = rectangular_packing(2, 2, friction="1/2", F=3, j0=1, angle="1/2").network
    with pytest.raises(forcenet.ArgumentError, match="no rescaling removes"):
        exact_polytope(net)
    result = forcenet.network(net, exact=True, samples=20000, seed=7)
    assert result.dimension == 4 and any(not sympy.sympify(v).is_rational for v in result.exact_mean)
    exact = np.array([float(v) for v in result.exact_mean])
    varying = result.sampled_error > 0
    assert np.abs((result.sampled_mean - exact)[varying] / result.sampled_error[varying]).max() < 4.0
    assert np.allclose(result.sampled_mean[~varying], exact[~varying])


def test_a_large_field_network_is_refused_before_the_field_arithmetic():
    """36 grains at 60 degrees: 144 unknowns, 108 equations, so the dimension is at least 36 > 26; the plan
    refuses (naming --samples) without the field's row reduction, and the sampler's plan runs."""
    net = rectangular_packing(6, 6, angle="1/2").network
    plan = forcenet.network_plan(net, exact=True)
    assert not plan.runnable and "at least 36" in plan.cost.refusal and "--samples" in plan.cost.refusal
    assert forcenet.network_plan(net, samples=100, seed=1).runnable


# unit normals pointing down from a grain to a wall, in Q(sqrt(3)): the two lattices' and the 3-4-5 triangle's
NORMALS = [("-1/2", "-sqrt(3)/2"), ("1/2", "-sqrt(3)/2"), ("-sqrt(3)/2", "-1/2"), ("sqrt(3)/2", "-1/2"),
           ("-3/5", "-4/5"), ("3/5", "-4/5"), ("-4/5", "-3/5"), ("4/5", "-3/5"), ("0", "-1")]


@settings(max_examples=6, deadline=None, derandomize=True)
@given(normals=st.lists(st.sampled_from(NORMALS), min_size=4, max_size=4, unique=True),
       fx=st.fractions(-1, 1, max_denominator=10))
def test_the_exact_route_equals_the_iterated_integral_on_random_field_networks(normals, fx):
    """Property (hypothesis): one grain on four walls with normals drawn from Q(sqrt(3)) and a load (fx, -1):
    whichever exact route the front door takes (rescaled rationals, or the number field when no rescaling
    works), the means and second moments equal sympy's iterated integral over the polygon exactly."""
    net = forcenet.contact_network(1, [[0, None, *n] for n in normals], [[0, str(fx), -1]])
    try:
        plan = forcenet.network_plan(net, exact=True, moments=2)
    except forcenet.ArgumentError:  # infeasible or unbounded for this draw
        assume(False)
    x_y = sympy.Matrix([[net.contacts[c][2 + axis] for c in (0, 1)] for axis in (0, 1)])
    assume(sympy.radsimp(x_y.det()) != 0)  # the integral's helper solves for the first two forces
    result = plan.run()
    mean, second, _ = _iterated_integral_moments(net)
    assert all(_same(a, b) for a, b in zip(result.exact_mean + result.exact_second, mean + second))


def test_a_density_over_the_number_field_is_refused_naming_what_works():
    """``--density`` on a Q(sqrt(3)) network that no rescaling rationalizes: one line saying the moments are exact
    without it (not the rescaling's "mixes irrational numbers" refusal, which would send the user to sampling)."""
    with pytest.raises(forcenet.ArgumentError, match=r"Q\(sqrt\(3\)\) only .* drop --density"):
        forcenet.network(_network(), exact=True, density=True)
