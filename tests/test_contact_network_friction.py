"""Chapter 5's frictional response (issue 55), by two routes: forcenet's hit-and-run on the contact network, and
the thesis's own procedure (Sec. 5.2.3): one tangential force T4 per grain as the coordinates (Eqs. (5.2)-(5.3):
the forces solved from the top layer down), a Metropolis walk of random-direction steps accepted when every
normal force is positive and every contact obeys Coulomb (Eq. (5.4)).

The packing of Figs. 5.1-5.2 (``geometries.rectangular_packing``): every grain touches two grains below at the
angle alpha (here cos 3/5, sin 4/5: 53 degrees, inside the thesis's 30-60 degrees, and rational), periodic
sideways, the last layer on fixed supports; a pressure p = 1 on every top grain and the overload F on one. The response G(i, j) = (<W_ij>_{p+F} - <W_ij>_p)/F
(Sec. 5.1), W_ij the vertical force grain (i, j) passes down.

Checked: (1) without friction the overload travels exactly along the two lattice directions (Sec. 5.1: "an
overload ... propagates exclusively along lattice directions"); (2) with friction the response is not the
frictionless one (Sec. 5.2.2: the set S(mu) is not symmetric under T4 -> -T4, "the response is non-trivial"):
the grain between the two lattice directions at the bottom carries a share, which grows with mu (Fig. 5.3: the
peaks broaden as mu increases, 0.1 -> 0.7 at F = 3); both samplers agree within their error bars.
"""

from __future__ import annotations

import numpy as np
import pytest
import sympy

import forcenet
from forcenet.exact.contact_network.geometries import rectangular_packing
from forcenet.exact.contact_network.polytope import balance, float_system
from forcenet.numeric.autocorr import mean_and_stderr
from forcenet.numeric.contact_network.hit_and_run import HitAndRun

C, S = sympy.Rational(3, 5), sympy.Rational(4, 5)  # cos and sin of the contact angle alpha
N, P, J0 = 3, 5, 0  # layers, grains per layer (periodic), the overloaded top grain (0-based)


def rhombic(mu, F):
    """The packing from ``geometries.rectangular_packing`` and its down contacts ``(i, j, "L"/"R") -> contact
    index`` (0-based ``i, j``)."""
    geo = rectangular_packing(N, P, friction=mu, F=F, j0=J0 + 1, p=1, angle=C)
    down = {(i, j, side): geo.contact[(kind, i + 1, j + 1)] for i in range(N) for j in range(P)
            for side, kind in (("L", "left"), ("R", "right"))}
    return geo.network, down


def former_rhombic(mu, F):
    """The lattice as this test built it before the constructor existed: contact by contact."""
    contacts = []
    for i in range(N):
        for j in range(P):
            for side, nx in (("L", -C), ("R", C)):
                other = None if i == N - 1 else (i + 1) * P + (j if side == "L" else (j + 1) % P)
                contacts.append([i * P + j, other, nx, -S])
    loads = [[j, 0, -(1 + (F if j == J0 else 0))] for j in range(P)]
    return forcenet.contact_network(N * P, contacts, loads, friction=mu, radii=[sympy.Rational(1, 2)] * (N * P))


def _W(values, labels, down, i, j, net=None):
    """The vertical force grain (i, j) passes down (Eq. (5.1)): minus the y components of its two down contacts'
    forces on the grains below (f n + t tau, tau = (-n_y, n_x), the network's convention); the normals are the
    network's (default: the angle cos 3/5)."""
    index = {label: k for k, label in enumerate(labels)}
    total = 0.0
    for side, default in (("L", (-C, -S)), ("R", (C, -S))):
        c = down[(i, j, side)]
        nx, ny = (float(x) for x in (default if net is None else net.contacts[c][2:]))
        t = values[..., index[f"t{c}"]] if f"t{c}" in index else 0.0
        total = total - (values[..., index[f"f{c}"]] * ny + t * nx)
    return total


def hit_and_run_response(mu, samples, seed):
    """G(N, j) and its error from forcenet's sampler (independent runs with and without F: errors add)."""
    means = []
    for F in (0, 3):
        net, down = rhombic(mu, F)
        result = forcenet.network(net, samples=samples, seed=seed + F, thin=2)
        W = np.stack([_W(result.samples, result.labels, down, N - 1, j) for j in range(P)], axis=1)
        means.append(mean_and_stderr(W)[:2])
    return (means[1][0] - means[0][0]) / 3, np.hypot(means[1][1], means[0][1]) / 3


def _forces_top_down(T, F, mu):
    """The thesis's parametrization: every grain's down-right tangential force ``T[..., i, j]`` (T4) chosen, its
    other down forces solved from torque balance (the four tangential forces sum to zero, equal radii) and force
    balance (a 2 x 2 system in the two normal forces), layer by layer from the top (Eqs. (5.2)-(5.3)).
    Returns normal and tangential forces ``(f, t)`` of shape ``(..., N, P, 2)`` (L, R) and whether they obey
    Eq. (5.4)."""
    c, s = float(C), float(S)
    nL, nR = np.array([-c, -s]), np.array([c, -s])
    tL, tR = np.array([s, -c]), np.array([s, c])  # tau = (-n_y, n_x)
    inverse = np.linalg.inv(np.stack([nL, nR], axis=1))
    shape = T.shape[:-2]
    f = np.zeros((*shape, N, P, 2))
    t = np.zeros((*shape, N, P, 2))
    for i in range(N):
        load = np.zeros((*shape, P, 2))
        t_up = np.zeros((*shape, P))
        if i == 0:  # the pressure p = 1 on every top grain, the overload on (1, j0)
            load[..., 1] = -1.0
            load[..., J0, 1] -= F
        else:  # forces from the grains above: (i-1, j)'s L contact and (i-1, j-1)'s R contact push on (i, j)
            for side, shift, n, tau in ((0, 0, nL, tL), (1, 1, nR, tR)):
                fu = np.roll(f[..., i - 1, :, side], shift, axis=-1)
                tu = np.roll(t[..., i - 1, :, side], shift, axis=-1)
                load += fu[..., None] * n + tu[..., None] * tau
                t_up += tu
        t[..., i, :, 1] = T[..., i, :]
        t[..., i, :, 0] = -(T[..., i, :] + t_up)  # torque balance
        # the grain exerts f n + t tau on each grain below, so feels minus that: f_L nL + f_R nR = rest
        rest = load - t[..., i, :, 0, None] * tL - t[..., i, :, 1, None] * tR
        solved = rest @ inverse.T
        f[..., i, :, 0], f[..., i, :, 1] = solved[..., 0], solved[..., 1]
    ok = ((f >= 0) & (np.abs(t) <= mu * f)).all(axis=(-3, -2, -1))
    return f, t, ok


def thesis_walk_response(mu, walkers, steps, seed, delta=0.08):
    """G(N, j) by the thesis's Metropolis walk in the T4 coordinates (Sec. 5.2.3), many independent walkers
    from T4 = 0 (the frictionless network, feasible), the last state of each recorded."""
    rng = np.random.default_rng(seed)
    out = []
    for F in (0.0, 3.0):
        T = np.zeros((walkers, N, P))
        for _ in range(steps):
            step = rng.standard_normal((walkers, N, P))
            step *= delta / np.linalg.norm(step.reshape(walkers, -1), axis=1)[:, None, None]
            _, _, ok = _forces_top_down(T + step, F, mu)
            T[ok] += step[ok]
        f, t, ok = _forces_top_down(T, F, mu)
        assert ok.all()
        c, s = float(C), float(S)
        W = s * (f[:, N - 1, :, 0] + f[:, N - 1, :, 1]) + c * (t[:, N - 1, :, 0] - t[:, N - 1, :, 1])
        out.append((W.mean(axis=0), W.std(axis=0, ddof=1) / np.sqrt(walkers)))
    return (out[1][0] - out[0][0]) / 3, np.hypot(out[1][1], out[0][1]) / 3


@pytest.mark.parametrize("angle", ["3/5", "1/2", "sqrt(2)/2"])
def test_without_friction_the_overload_travels_along_the_lattice_directions(angle):
    """Sec. 5.1: frictionless, two forces per grain and two balance equations; the response lies exactly on the
    lattice directions from (1, j0): at the bottom layer on j0 and j0 + 2, nothing between (exact route), for
    any angle (Fig. 5.1: it "does not influence the results"; sqrt(3)/2 and sqrt(2)/2 by rescaling)."""
    geo = rectangular_packing(N, P, friction=0, F=0, j0=J0 + 1, angle=angle)
    down = {(i, j, side): geo.contact[(kind, i + 1, j + 1)] for i in range(N) for j in range(P)
            for side, kind in (("L", "left"), ("R", "right"))}
    response = forcenet.network_response(geo.network, J0, (0, -3), exact=True)
    labels = forcenet.network(geo.network, exact=True).labels
    G = [_W(np.array([float(x) for x in response]), labels, down, N - 1, j, geo.network) / 3 for j in range(P)]
    assert np.allclose(G, [0.5, 0, 0.5, 0, 0], atol=1e-12)
    assert all(isinstance(x, sympy.Expr) for x in response)  # exact values, not floats


@pytest.mark.parametrize("mu, F", [(0, 0), (sympy.Rational(1, 2), 3), (sympy.Rational(7, 10), 0)])
def test_the_constructor_is_the_former_lattice(mu, F):
    """``geometries.rectangular_packing`` gives the balance equations and Coulomb cones this test built contact
    by contact before the constructor existed (same numbering of grains and contacts)."""
    assert balance(rhombic(mu, F)[0]) == balance(former_rhombic(mu, F))


def test_the_constructor_refuses_a_float_or_an_angle_out_of_range():
    with pytest.raises(forcenet.ArgumentTypeError, match="float"):
        rectangular_packing(2, 3, angle=0.6)
    with pytest.raises(forcenet.ArgumentError, match=r"\[1/2, sqrt\(3\)/2\]"):
        rectangular_packing(2, 3, angle="9/10")
    with pytest.raises(forcenet.ArgumentError, match="P"):
        rectangular_packing(2, 1)


def test_the_thesis_parametrization_is_the_networks_polytope():
    """Route 2's top-down solve gives balanced networks of route 1's polytope: the dimension is one T4 per
    grain (Sec. 5.2.1), and a solved network satisfies A z = b."""
    net, down = rhombic(sympy.Rational(1, 2), 3)
    assert HitAndRun(net).dimension == N * P
    T = np.random.default_rng(1).uniform(-0.05, 0.05, (N, P))
    f, t, ok = _forces_top_down(T, 3.0, 0.5)
    bal = balance(net)
    z = np.zeros(bal.variables)
    for (i, j, side), c in down.items():
        z[bal.labels.index(f"f{c}")] = f[i, j, "LR".index(side)]
        z[bal.labels.index(f"t{c}")] = t[i, j, "LR".index(side)]
    A, b, _ = float_system(bal)
    assert np.abs(A @ z - b).max() < 1e-12


@pytest.mark.slow
@pytest.mark.parametrize("mu", [0.1, 0.7])
def test_friction_broadens_the_response_by_two_routes(mu):
    """Fig. 5.3 (F = 3, p = 1): at mu = 0.1 two sharp peaks on the lattice directions carry nearly all the
    overload; at mu = 0.7 the grain between them at the bottom takes a clear share (Sec. 5.2.2's asymmetry:
    the response is not the frictionless one); hit-and-run and the thesis's Metropolis walk agree within 4 error
    bars on every bottom grain (3 s each measured on the 2-core machine at load 3, ~50 s when first measured at load 5-8)."""
    ours, ours_err = hit_and_run_response(sympy.Rational(str(mu)), 6000, seed=1)
    theirs, theirs_err = thesis_walk_response(mu, walkers=400, steps=1500, seed=2)
    assert np.abs(ours - theirs).max() < 4 * np.hypot(ours_err, theirs_err).max() + 0.01
    assert abs(ours.sum() - 1) < 0.05  # the floor takes the whole overload
    if mu < 0.5:  # measured: the centre 0.03 +- 0.015 at mu = 0.1
        assert ours[0] + ours[2] > 0.85
    else:  # the centre (j0 + 1 at depth 3 lies between the lattice lines j0, j0 + 2)
        assert ours[1] > 4 * ours_err[1]
