"""Fluctuations by Pfaffians (issue 27): the exact gap laws of the lattice-direction grains.

Checked against independent routes:

* the order-ideal DP's gap laws (forcenet.exact.triangle.gaps) and second moments
  (forcenet.exact.triangle.moments) for every layer, N <= 11 (N <= 20 in the slow suite);
* the pure-Python kernels;
* beyond the DP: the law's mean against the Pfaffian mean route (another functional of
  other evaluations), the mirror grain's sampled law, and the exact sampler at N = 64 (slow);
* the two-time nature of interior gaps (notes/fluctuations.md Sec. 3): a measure on
  maximal chains with the one-time marginals of the uniform one and another <g^2>.
"""

from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from forcenet.exact.triangle import law_routes
from forcenet.exact.triangle.distribution import cdf_from_gaps, density_from_gaps, moment_from_gaps
from forcenet.exact.triangle.free_fermion import _kernels_python, engine, route
from forcenet.exact.triangle.free_fermion import fluctuations as fl
from forcenet.exact.triangle.gaps import layer_gap_counts
from forcenet.exact.triangle.moments import moment_table
from forcenet.exact.triangle.staircase import count

PRIME = 8388593


@pytest.mark.parametrize("N", range(2, 12))
def test_lattice_gap_laws_equal_the_dp(N):
    laws = fl.lattice_gap_laws(N, workers=1)
    assert sorted(laws) == list(range(2, N + 1))
    for i in range(2, N + 1):
        dp = layer_gap_counts(N, i)
        assert laws[i] == dp[0]
        assert laws[i].counts == dp[-1].counts  # the mirror grain W_{i,i}


@pytest.mark.slow
@pytest.mark.parametrize("N", range(12, 21))
def test_lattice_gap_laws_equal_the_dp_slow(N):
    laws = fl.lattice_gap_laws(N)
    for i in range(2, N + 1):
        assert laws[i] == layer_gap_counts(N, i)[0]


@settings(max_examples=10, deadline=None)
@given(N=st.integers(min_value=3, max_value=12), data=st.data())
def test_one_grain_equals_the_dp_and_the_whole_table(N, data):
    i = data.draw(st.integers(min_value=2, max_value=N))
    j = data.draw(st.sampled_from([1, i]))
    law = fl.grain_gap_law(N, (i, j), workers=1)
    assert law == layer_gap_counts(N, i)[j - 1]
    assert law == fl.lattice_gap_laws(N, workers=1)[i]


def test_interior_grains_are_refused():
    with pytest.raises(ValueError, match=r"grain=\(6, 3\) is out of range.*two-time"):
        fl.grain_gap_law(6, (6, 3))
    with pytest.raises(ValueError, match="out of range"):
        fl.grain_gap_law(6, (1, 1))
    with pytest.raises(ValueError, match="i="):
        fl.lattice_gap_laws(6, layers=[1])


@settings(max_examples=8, deadline=None)
@given(N=st.integers(min_value=2, max_value=10))
def test_lattice_mean_W2_equals_the_dp_moment(N):
    """<W_{i,1}^2> against the DP's marked-chain moment pass (a different DP from the gap laws')."""
    table = moment_table(N, 2)
    assert fl.lattice_mean_W2(N, workers=1) == [row[0] for row in table]


@pytest.mark.parametrize("N", [3, 5, 6])
def test_pure_python_backend(N):
    p = PRIME
    with engine._oracle_kernels(_kernels_python):
        oracle = fl.edge_level_residues(N, p)
    assert (oracle == fl.edge_level_residues(N, p)).all()


@pytest.mark.parametrize("N", [22, 26])
def test_law_mean_is_the_pfaffian_mean_beyond_the_dp(N):
    """E[g]/(d+1) of the interpolated laws = the mean route's functional of its own evaluations."""
    laws = fl.lattice_gap_laws(N)
    column = route.lattice_direction(N)
    d = N * (N - 1) // 2
    total = count(N)
    for i in range(2, N + 1):
        law = laws[i]
        assert law.total == total and sum(law.counts) == total
        assert all(c >= 0 for c in law.counts)
        assert law.mean() / (d + 1) == column[i - 1]
        assert law.counts[: N - i + 1] == (0,) * (N - i + 1)  # T(1, m) >= m: the cells (1, 1..m-1) come first


def test_density_integrates_to_one_with_the_exact_mean():
    N, i = 22, 11
    law = fl.lattice_gap_laws(N)[i]
    f = density_from_gaps(law)
    assert f.integrate().eval(1) - f.integrate().eval(0) == 1
    w = f.gen
    assert (f * w).integrate().eval(1) - (f * w).integrate().eval(0) == route.lattice_direction(N)[i - 1]
    assert cdf_from_gaps(law).eval(1) == 1


def test_residue_checks_and_arguments():
    E = fl.edge_level_residues(6, PRIME)
    assert (E[1:, 0] == count(6) % PRIME).all() and (E[1:, -1] == 0).all()
    with pytest.raises(ValueError, match="N=129"):
        fl.lattice_gap_laws(129)
    with pytest.raises(ValueError, match="p="):
        fl.edge_level_residues(6, 8388592)
    with pytest.raises(ValueError, match="inner size"):
        fl._matmul_mod(np.zeros((2, 8192), dtype=np.int64), np.zeros((8192, 1)), PRIME)


def test_blas_products_are_exact():
    rng = np.random.default_rng(27)
    p = 33554393
    A = rng.integers(0, p, size=(40, 3000))
    B = rng.integers(0, p, size=(3000, 7))
    exact = [[sum(int(a) * int(b) for a, b in zip(A[r], B[:, c])) % p for c in range(7)] for r in range(40)]
    assert fl._matmul_mod(A, B, p).tolist() == exact


def test_plan():
    plan = fl.lattice_gap_laws_plan(64)
    assert plan.runnable and plan.unit == "prime" and plan.ticks > 100
    assert fl.lattice_gap_laws_plan(129).refusal.startswith("N=129 is out of range")
    assert fl.lattice_gap_laws_plan(100, memory_bytes=2**20).refusal is not None
    assert fl.lattice_gap_laws_plan(64, layers=1).seconds < plan.seconds


@pytest.mark.slow
def test_lattice_laws_agree_with_the_exact_sampler_at_N64():
    """<W_{i,1}^2> and P(W_{i,1} <= median-ish w) of every layer against 20000 exact samples (alpha = 1e-3).

    The bounded test (every sample in [0, 1]): without bounds the t route cannot judge 20000 rows here
    (``W_{64,1}^2`` has skewness about 7: its tail is trusted from about 54000 rows on)."""
    from scipy.stats import binom

    from forcenet.numeric.agreement import compare_samples
    from forcenet.numeric.triangle.exact_sampler import ExactSampler

    N, samples = 64, 20000
    laws = fl.lattice_gap_laws(N)
    second = [moment_from_gaps(laws[i], 2) for i in range(2, N + 1)]
    column = [None] + [laws[i].mean() / (N * (N - 1) // 2 + 1) for i in range(2, N + 1)]
    sampler, rows, drawn = ExactSampler(N, seed=2764), [], 0
    while drawn < samples:
        W = sampler.sample_W(min(sampler.batch, samples - drawn))
        rows.append(W[:, 1:, 0])
        drawn += W.shape[0]
    X = np.concatenate(rows)
    cuts = [float(column[i - 1]) for i in range(2, N + 1)]  # P(W <= <W>): the Beta mixture at w = <W>
    d = N * (N - 1) // 2
    exact_cdf = []
    for i, w in zip(range(2, N + 1), cuts):  # I_w(g, d+1-g) = P(Binomial(d, w) >= g); floats only at this edge
        law = laws[i]
        exact_cdf.append(sum(float(Fraction(c, law.total)) * binom.sf(g - 1, d, w) for g, c in enumerate(law.counts) if c))
    data = np.concatenate([X**2, (X <= np.array(cuts)).astype(float)], axis=1)
    expected = [float(x) for x in second] + exact_cdf
    keys = [f"W2_{i}" for i in range(2, N + 1)] + [f"cdf_{i}" for i in range(2, N + 1)]
    assert X.min() >= 0 and X.max() <= 1
    result = compare_samples(data, expected, keys=keys, alpha=1e-3, bounds=(0, 1))
    assert result.passed, result.summary()


# ------------------------------------------- interior gaps are two-time quantities


def _successors(A, n):
    """The ideals one cell above ``A`` (a sorted tuple of parts): a part ``a`` moves to ``a + 1``, or a part 1 appears."""
    parts = set(A)
    out = [parts - {a} | {a + 1} for a in A if a + 1 <= n and a + 1 not in parts]
    if 1 not in parts:
        out.append(parts | {1})
    return [tuple(sorted(B, reverse=True)) for B in out]


def _chains(n):
    """Every maximal chain of order ideals of the staircase, as the tuple of its ideals."""
    full, out = tuple(range(n, 0, -1)), []

    def grow(chain):
        if chain[-1] == full:
            out.append(tuple(chain))
        for B in _successors(chain[-1], n):
            grow(chain + [B])

    grow([()])
    return out


def _gap(chain, N, i, j):
    """The rank gap of ``W_{i,j}``: the number of ideals of the chain with ``N_m = j - 1``, ``m = N - i + 1``."""
    m = N - i + 1
    return sum(1 for A in chain if sum(a >= m for a in A) == j - 1)


def _swap_quadruple(chains, N, n):
    """``(C1, C2, C3, C4, i, j)``: C2 (C4) is C1 (C3) with the two cells added at levels l+1, l+2 swapped, C1 and C3
    through the same ideals at l and l+2 but different ones at l+1, and <g_ij^2> changes when C1, C3 move to C2, C4."""
    swaps = {}
    for c in chains:
        for l in range(len(c) - 2):
            for D in _successors(c[l], n):
                if D != c[l + 1] and c[l + 2] in _successors(D, n):
                    swaps.setdefault((l, c[l], c[l + 2]), []).append((c, c[: l + 1] + (D,) + c[l + 2 :]))
    grains = [(i, j) for i in range(3, N + 1) for j in range(2, i)]
    for (l, _, _), members in swaps.items():
        for c1, c2 in members:
            for c3, c4 in members:
                if c3[l + 1] == c1[l + 1] or c3 in (c1, c2):
                    continue
                for i, j in grains:
                    g = [_gap(c, N, i, j) for c in (c1, c2, c3, c4)]
                    if g[1] ** 2 - g[0] ** 2 + g[3] ** 2 - g[2] ** 2:
                        return c1, c2, c3, c4, i, j
    return None


def test_one_time_marginals_do_not_determine_the_second_moment():
    """notes/fluctuations.md Sec. 3: a measure on maximal chains with every one-time marginal of the uniform one.

    C1 = (alpha, x, y, beta) -> C2 = (alpha, y, x, beta) and C3 = (alpha', y, x, beta') -> C4 = (alpha', x, y, beta')
    (the same ideals at the levels l and l + 2): the masses of A+x and A+y at level l + 1 are restored, so the law of
    I_l is the uniform measure's for every l, hence <g> of every grain too; <g^2> of an interior grain is not.
    """
    N = 6
    n, d = N - 1, N * (N - 1) // 2
    chains = _chains(n)
    assert len(chains) == count(N)
    found = _swap_quadruple(chains, N, n)
    assert found is not None
    c1, c2, c3, c4, i, j = found
    uniform = {c: Fraction(1, len(chains)) for c in chains}
    new = dict(uniform)
    for lose, gain in ((c1, c2), (c3, c4)):
        new[lose] -= Fraction(1, len(chains))
        new[gain] += Fraction(1, len(chains))
    assert min(new.values()) >= 0 and sum(new.values()) == 1

    def marginal(mu, l):
        out = {}
        for c, w in mu.items():
            out[c[l]] = out.get(c[l], 0) + w
        return {A: w for A, w in out.items() if w}

    def mean(mu, f):
        return sum(w * f(c) for c, w in mu.items())

    assert all(marginal(new, l) == marginal(uniform, l) for l in range(d + 1))
    for jj in range(1, i + 1):
        assert mean(new, lambda c, jj=jj: _gap(c, N, i, jj)) == mean(uniform, lambda c, jj=jj: _gap(c, N, i, jj))
    second = mean(uniform, lambda c: _gap(c, N, i, j) ** 2)
    law = layer_gap_counts(N, i)[j - 1]  # the enumeration is the DP's law
    assert second * law.total == sum(g * g * k for g, k in enumerate(law.counts))
    assert mean(new, lambda c: _gap(c, N, i, j) ** 2) != second


# ------------------------------------------------ the floor is a Legendre orthogonal ensemble


@pytest.mark.parametrize("N", [3, 4, pytest.param(5, marks=pytest.mark.slow)])
def test_floor_partial_sums_have_the_vandermonde_density(N):
    """notes/fluctuations.md Sec. 5: the free partial sums of the floor have density prod_{a<b} (v_b - v_a) / Z.

    Every moment <W_{N,j}^s> (s = 1, 2) of the floor from that density (sympy, ordered simplex) equals the DP's.
    """
    import sympy

    n = N - 1
    v = sympy.symbols(f"v1:{n + 1}")
    vand = sympy.prod(v[b] - v[a] for a in range(n) for b in range(a + 1, n))

    def ordered_integral(f):
        for k in range(n):  # v_1 in (0, v_2), ..., v_n in (0, 1)
            f = sympy.integrate(f, (v[k], 0, v[k + 1] if k + 1 < n else 1))
        return f

    Z = ordered_integral(vand)
    volume = sympy.Rational(count(N), sympy.factorial(N * (N - 1) // 2))  # (4.1)
    assert Z / sympy.prod(sympy.factorial(k) for k in range(1, n)) == volume  # the GT patterns above: Delta / prod k!
    points = (0,) + v + (1,)
    for s in (1, 2):
        table = moment_table(N, s)
        for j in range(1, N + 1):
            value = ordered_integral(vand * (points[j] - points[j - 1]) ** s) / Z
            assert Fraction(int(value.p), int(value.q)) == table[N - 1][j - 1]


@pytest.mark.parametrize("N", [4, 5])
def test_two_time_formula_gives_the_second_moment(N):
    """notes/fluctuations.md Sec. 4: <W^2> = 2 int_{s<t} P(N_m(I(s)) = N_m(I(t)) = j - 1), with the integrand

    (d!/count) [y^(j-1)] <full| e^{(1-t) H} e^{(t-s) H_m} y^{N_m} e^{s H} |empty>, H the covering moves of the
    ideal lattice and H_m the same without the moves across m - 1 -> m (exact polynomials in s, t; sympy).
    """
    from math import factorial

    import sympy

    n, d = N - 1, N * (N - 1) // 2
    s, t, y = sympy.symbols("s t y")
    ideals = sorted({A for c in _chains(n) for A in c}, key=lambda A: (sum(A), A))
    where = {A: k for k, A in enumerate(ideals)}
    size = len(ideals)

    def moves(m=None):
        H = sympy.zeros(size, size)
        for A in ideals:
            for B in _successors(A, n):
                crossing = m is not None and sum(b >= m for b in B) > sum(a >= m for a in A)
                if not crossing:
                    H[where[B], where[A]] = 1
        return H

    def expm(H, x):  # H is nilpotent (it raises the level): a polynomial
        out, term = sympy.eye(size), sympy.eye(size)
        for k in range(1, d + 1):
            term = term * H * x / k
            out += term
        return out

    H = moves()
    start, end = where[()], where[tuple(range(n, 0, -1))]
    table = moment_table(N, 2)
    for i in range(3, N + 1):
        m = N - i + 1
        Y = sympy.diag(*[y ** sum(a >= m for a in A) for A in ideals])
        amplitude = (expm(H, 1 - t) * expm(moves(m), t - s) * Y * expm(H, s))[end, start]
        poly = sympy.Poly(sympy.expand(amplitude), y)
        for j in range(2, i):
            integrand = poly.coeff_monomial(y ** (j - 1)) * factorial(d) / count(N)
            value = 2 * sympy.integrate(sympy.integrate(integrand, (s, 0, t)), (t, 0, 1))
            assert Fraction(int(value.p), int(value.q)) == table[i - 1][j - 1]


# ------------------------------------------------ one grain's law by the faster route (forcenet dist --grain)


def test_single_grain_route_takes_pfaffians_only_where_they_reach():
    assert law_routes.single_grain_route(8, (8, 4))[0] == "ideals"  # interior, small N: the DP is the faster
    route_name, plan = law_routes.single_grain_route(64, (64, 64))
    assert route_name == "pfaffian" and plan.runnable and plan.unit == "prime"
    route_name, plan = law_routes.single_grain_route(40, (39, 20))  # interior beyond the DP: the layer's de Bruijn Pfaffians
    assert route_name == "layers" and plan.runnable and "every load of layer 39" in plan.what
    with pytest.raises(ValueError, match="N=129 is out of range"):
        law_routes.single_grain_route(129, (129, 1))
    with pytest.raises(ValueError, match="route='x'"):
        law_routes.single_grain_gap_law(5, (5, 1), "x")


@settings(max_examples=8, deadline=None)
@given(N=st.integers(min_value=3, max_value=11), data=st.data())
def test_single_grain_gap_law_is_the_same_by_both_routes(N, data):
    i = data.draw(st.integers(min_value=2, max_value=N))
    j = data.draw(st.sampled_from([1, i]))
    assert law_routes.single_grain_gap_law(N, (i, j), "pfaffian") == law_routes.single_grain_gap_law(N, (i, j), "ideals")


def test_dist_beyond_the_dp_gives_the_lattice_grain_law(cli):
    """``forcenet dist --N 34 --grain 34,1``: beyond the DP's N = 30, by Pfaffians; its mean against the mean route."""
    import json

    code, out, _ = cli(["dist", "--N", "34", "--grain", "34,1", "--format", "json", "--quiet"])
    assert code == 0
    data = json.loads(out)
    assert Fraction(data["mean"]) == route.lattice_direction(34, workers=1)[-1]  # <W_{34,1}>, another functional
    (piece,) = data["pieces"]
    assert len(piece["density"]) == 34 * 33 // 2  # degree d - 1
    assert sum(Fraction(c) / (k + 1) for k, c in enumerate(piece["density"])) == 1  # a density on [0, 1]
    code, _, err = cli(["dist", "--N", "34", "--grain", "33,17"])  # above the floor: the layer's Pfaffians, hours
    assert code == 2 and "every load of layer 33" in err and "--force" in err
    code, _, err = cli(["dist", "--N", "34", "--grain", "34,17"])  # a floor load: de Bruijn Pfaffians, over an hour
    assert code == 2 and "de Bruijn Pfaffians" in err and "--force" in err


# ------------------------------------------------ the floor load's law from the Legendre ensemble (de Bruijn)


def _gap_pfaffian_tools():
    """What the two de Bruijn checks share, in sympy: with ``chi = zeta 1[x <= s] + 1[x > t]``,
    ``double(f) = int int_{x<y} f chi(x) chi(y)``, ``single(f) = int f chi``, a Pfaffian by expansion, and the
    load's density from the Pfaffian ``P``: ``G = [zeta^(j-1)] P / P(zeta = 1, t = s)``,
    ``E[(W - w)_+] = int_0^(1-w) G(s, s + w) ds``, its second derivative in ``w``."""
    import sympy as sp

    s, t, z, w, x, y = sp.symbols("s t zeta w x y")

    def double(f):
        low = sp.integrate(sp.integrate(f, (x, 0, y)), (y, 0, s))
        split = sp.integrate(sp.integrate(f, (x, 0, s)), (y, t, 1))
        high = sp.integrate(sp.integrate(f, (x, t, y)), (y, t, 1))
        return sp.expand(z**2 * low + z * split + high)

    def single(f):
        return sp.expand(z * sp.integrate(f, (x, 0, s)) + sp.integrate(f, (x, t, 1)))

    def pfaffian(A):
        if A.shape[0] == 0:
            return sp.Integer(1)
        rest = range(1, A.shape[0])
        return sp.expand(sum((-1) ** (k + 1) * A[0, k] * pfaffian(A.extract([r for r in rest if r != k], [r for r in rest if r != k]))
                             for k in rest))

    def load_density(P, j):
        G = P.coeff(z, j - 1) / P.subs({z: 1, t: s})
        F = sp.integrate(G.subs(t, s + w), (s, 0, 1 - w))
        return sp.Poly(sp.expand(sp.diff(F, w, 2)), w)

    return sp, x, y, double, single, pfaffian, load_density


def _floor_density_by_de_bruijn(N, j):
    """Density of ``W_{N,j}`` from the floor's Vandermonde density alone (notes/fluctuations.md Sec. 5).

    ``E[(W - w)_+] = int_0^(1-w) G(s, s + w) ds`` with ``G(s, t) = P(j - 1 floor points in [0, s],
    none in (s, t])``, and ``G`` is ``[zeta^(j-1)]`` of de Bruijn's Pfaffian of
    ``int int_{x<y} (x^i y^k - x^k y^i) phi(x) phi(y)``, ``phi = zeta 1[x <= s] + 1[x > t]``
    (bordered by ``int x^i phi`` when ``n`` is odd), over its value at ``zeta = 1``, ``t = s``.
    """
    sp, x, y, double, single, pfaffian, load_density = _gap_pfaffian_tools()
    n = N - 1
    size = n + n % 2
    A = sp.zeros(size, size)
    for i in range(n):
        for k in range(i + 1, n):
            A[i, k] = double(x**i * y**k - x**k * y**i)
            A[k, i] = -A[i, k]
        if n % 2:
            A[i, n] = single(x**i)
            A[n, i] = -A[i, n]
    return load_density(pfaffian(A), j)


def _layer_above_floor_density_by_pfaffian(N, j):
    """Density of ``W_{N-1,j}`` (the layer above the floor) from a de Bruijn-type Pfaffian (notes/fluctuations.md Sec. 6).

    The free partial sums ``u`` of layer ``N - 1`` (``m = N - 2`` points) and the
    floor ``v`` have the joint density ``Delta(u) 1[u interlaces v]``.  The floor
    integrates out to ``Phi(u) = prod of the gaps of (0, u, 1)``, a Pfaffian
    with the kernel ``K(x, y) = x (y - x)`` (``x < y``, antisymmetric), the row
    ``x (1 - x)`` against a constant row (and, ``m`` even, the border ``x`` and a
    ``1``); de Bruijn's integration against ``Delta(u)`` then gives
    ``G(s, t) = [zeta^(j-1)] Pf[[A, B], [-B^T, C]] / (the same at zeta = 1, t = s)`` with
    ``A_kl = int int x^k y^l K(x, y) chi chi``, ``B_k = int x^k (x (1 - x), x) chi``,
    ``chi = zeta 1[x <= s] + 1[x > t]``.
    """
    sp, x, y, double, single, pfaffian, load_density = _gap_pfaffian_tools()
    m = N - 2
    constant_rows = 1 if m % 2 else 2
    A = sp.zeros(m + constant_rows, m + constant_rows)
    for k in range(m):
        for l in range(k + 1, m):
            A[k, l] = double((x**k * y**l - x**l * y**k) * x * (y - x))
            A[l, k] = -A[k, l]
        A[k, m] = single(x**k * x * (1 - x))
        A[m, k] = -A[k, m]
        if constant_rows == 2:
            A[k, m + 1] = single(x**k * x)
            A[m + 1, k] = -A[k, m + 1]
    if constant_rows == 2:
        A[m, m + 1], A[m + 1, m] = 1, -1
    return load_density(pfaffian(A), j)


@pytest.mark.parametrize("N", [3, 4, 5])
def test_the_layer_above_the_floor_is_a_pfaffian_ensemble_too(N):
    """Every load of layer N - 1 from the Pfaffian with the kernel x (y - x): the DP's density, exactly."""
    from forcenet.exact.triangle.distribution import density

    for j in range(1, N):
        assert _layer_above_floor_density_by_pfaffian(N, j).all_coeffs() == density(N, (N - 1, j)).all_coeffs()


@pytest.mark.parametrize("N", [3, 4, 5])
def test_a_floor_load_law_from_de_bruijn_equals_the_dp(N):
    from forcenet.exact.triangle.distribution import density

    for j in range(1, N + 1):
        dp = density(N, (N, j))
        assert _floor_density_by_de_bruijn(N, j).all_coeffs() == dp.all_coeffs()


def _two_time_functional(a, b, j, c):
    """``sum_j c_j L_j`` on the monomial ``s^a t^b zeta^j``: ``c_j Integral Integral_(s<t) s^a t^b``."""
    return Fraction(c[j], (a + 1) * (a + b + 2))


def _rank(rows):
    """Exact rank over Q (python-flint)."""
    import flint

    matrix = flint.fmpq_mat(len(rows), len(rows[0]), [flint.fmpq(x.numerator, x.denominator)
                                                      for row in rows for x in row])
    return matrix.rref()[1]


def _exact_weights_exist(nodes, monomials, c):
    """Whether weights ``w`` with ``sum_nu w_nu s^a t^b z^j = L(s^a t^b z^j)`` exist for every monomial (exact)."""
    lhs = [[s**a * t**b * z**j for (s, t, z) in nodes] for (a, b, j) in monomials]
    augmented = [row + [_two_time_functional(a, b, j, c)] for row, (a, b, j) in zip(lhs, monomials)]
    return _rank(lhs) == _rank(augmented)


def _monomials(d, m):
    return [(a, b, j) for a in range(d + 1) for b in range(d + 1 - a) for j in range(m + 1)]


def _bound(d, m):
    k, h = d // 2, m // 2
    return (k + 1) * (k + 2) // 2 * (h + 1)


@settings(max_examples=3, deadline=None)
@given(seed=st.integers(0, 2**32 - 1))
def test_the_two_time_form_has_the_rank_of_the_bound(seed):
    """notes/fluctuations.md Sec. 6.1: the form l(G H) on V_k (x) U_h is the Gram form (x) the Hankel form, of rank
    ``(k+1)(k+2)/2 (floor(m/2)+1)``: any rule, whatever its nodes, needs that many (a rule with r nodes makes the
    form ``sum_nu w_nu v(x_nu) v(x_nu)^T``, of rank <= r).  Here d = 8, m = 3: 30 against 180 monomials."""
    d, m = 8, 3
    k, h = d // 2, m // 2
    rng = np.random.default_rng(seed)
    c = [int(x) for x in rng.integers(1, 50, size=m + 1)]
    basis = [(a, b, j) for a in range(k + 1) for b in range(k + 1 - a) for j in range(h + 1)]
    form = [[_two_time_functional(p[0] + q[0], p[1] + q[1], p[2] + q[2], c) for q in basis] for p in basis]
    assert _rank(form) == _bound(d, m) == len(basis) == 30
    assert 6 * _bound(d, m) == len(_monomials(d, m))


@settings(max_examples=4, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), m=st.sampled_from([3, 5]))
def test_rules_below_the_two_time_bound_fail_and_at_it_exist(seed, m):
    """The bound is attained where a rule with that many nodes is known, and nodes that reach it are special.

    ``d = 2``: the edge midpoints of the triangle ``0 < s < t < 1`` (weights 1/6) integrate every quadratic, and
    for a layer functional ``c_j = sum_nu omega_nu z_nu^j`` with ``floor(m/2) + 1`` atoms the ``zeta``-rule with
    those atoms is exact: their product is a rule with exactly the bound's ``3 (floor(m/2) + 1)`` nodes (9 against
    36 monomials at m = 5).  Dropping any one node leaves no exact weights, as the bound says for every set of
    fewer nodes; random nodes fail at the bound itself (so a random failure below it shows nothing).
    """
    d = 2
    rng = np.random.default_rng(seed)
    h = m // 2
    atoms = [Fraction(int(z), 7) for z in rng.choice(np.arange(-20, 21), size=h + 1, replace=False)]
    masses = [Fraction(int(w), 5) for w in rng.integers(1, 20, size=h + 1)]
    c = [sum(w * z**j for w, z in zip(masses, atoms)) for j in range(m + 1)]
    monomials = _monomials(d, m)
    bound = _bound(d, m)
    half = Fraction(1, 2)
    rule = [(s, t, z) for (s, t) in ((0, half), (half, 1), (half, half)) for z in atoms]
    assert len(rule) == bound and 4 * bound <= len(monomials)
    weights = [Fraction(1, 6) * w for _ in range(3) for w in masses]  # the product rule, checked monomial by monomial
    for a, b, j in monomials:
        assert sum(w * s**a * t**b * z**j for w, (s, t, z) in zip(weights, rule)) == _two_time_functional(a, b, j, c)
    assert _exact_weights_exist(rule, monomials, c)
    for drop in range(bound):
        assert not _exact_weights_exist(rule[:drop] + rule[drop + 1:], monomials, c)

    def random_nodes(r):
        return [tuple(Fraction(int(x), 97) for x in rng.integers(1, 97, size=3)) for _ in range(r)]

    assert not _exact_weights_exist(random_nodes(bound), monomials, c)
    assert not _exact_weights_exist(random_nodes(bound - 1), monomials, c)
