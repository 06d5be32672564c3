"""The Pfaffian route (issue 18): exact <W> tables in polynomial time, checked against independent routes.

* the order-ideal DP (forcenet.exact.mean_W) for every N <= 16 (N <= 24 in the slow suite);
* the product formula for the count (4.1);
* the Jordan-Wigner brute force of the Majorana hopping operator (one sign for every path);
* the minor-summation identity and the point-process kernel, in exact Fractions, against subset sums;
* the compiled kernels against their pure-Python twins;
* beyond the DP's reach: unit row sums and mirror symmetry (not built into the method), and the exact sampler.
"""

import json
import random
from fractions import Fraction
from math import factorial, prod

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from forcenet.cli import main
from forcenet.exact import count, mean_W
from forcenet.exact.routes import METHODS, table_plan, table_run
from forcenet.exact.triangle.free_fermion import _dense as dense
from forcenet.exact.triangle.free_fermion import _kernels_python as kernels_python
from forcenet.exact.triangle.free_fermion import cost, engine, kernels, route, schur
from forcenet.exact.triangle.ideal_dp import survival_counts
from forcenet.exact.triangle.staircase import shifted_tableaux_count

PRIME = 8388593  # below the dense baseline's bound too
LARGE_PRIME = 33554393  # the largest prime of the route


# ------------------------------------------------------------------ the tables


@pytest.mark.parametrize("N", range(2, 17))
def test_mean_W_equals_the_order_ideal_dp(N):
    assert route.mean_W(N, workers=1) == mean_W(N)


@pytest.mark.slow
@pytest.mark.parametrize("N", range(17, 25))
def test_mean_W_equals_the_order_ideal_dp_slow(N):
    assert route.mean_W(N) == mean_W(N)


@pytest.mark.parametrize("N", range(2, 17))
def test_lattice_direction_equals_the_dp(N):
    assert route.lattice_direction(N, workers=1) == [row[0] for row in mean_W(N)]


@pytest.mark.parametrize("N", [2, 3, 5, 6])
def test_lattice_direction_pure_python(N):
    with engine._oracle_kernels(kernels_python):  # in this process: workers=1
        assert route.lattice_direction(N, workers=1) == [row[0] for row in mean_W(N)]


@settings(max_examples=10, deadline=None)
@given(N=st.integers(min_value=2, max_value=14))
def test_survival_table_equals_the_dp_survival_counts(N):
    """S[m][k] = C[k][m] - C[k+1][m]: the two routes agree before any division."""
    S, total = route.survival_table(N, workers=1)
    C, total_dp = survival_counts(N)
    n = N - 1
    assert total == total_dp
    for m in range(1, n + 1):
        assert S[m] == [C[k][m] - (C[k + 1][m] if k < n else 0) for k in range(n + 1)]


@pytest.mark.parametrize("N", [2, 3, 4, 5, 8, 13, 21, 30, 45, 60])
def test_count_is_the_product_formula(N):
    assert route.count(N) == count(N)


def test_normalization_is_eq_4_1():
    from forcenet.exact import normalization

    assert [route.normalization(N) for N in (2, 4, 9, 17)] == [normalization(N) for N in (2, 4, 9, 17)]


@pytest.mark.parametrize("N", range(2, 9))
def test_count_exact_fractions(N):
    assert schur.count_exact(N) == count(N)


@pytest.mark.parametrize("N", [3, 5, 6])
def test_pure_python_backend_end_to_end(N):
    with engine._oracle_kernels(kernels_python):
        assert route.mean_W(N, workers=1) == mean_W(N)


def _all_tableaux_entry_sums(n):
    """Sum over every standard shifted staircase tableau of T(r, c), by explicit enumeration."""
    cells = [(r, c) for r in range(1, n + 1) for c in range(r, n + 1)]
    sums, total, T, filled = dict.fromkeys(cells, 0), 0, {}, set()

    def rec(k):
        nonlocal total
        if k > len(cells):
            total += 1
            for x in cells:
                sums[x] += T[x]
            return
        for r, c in cells:
            if (r, c) not in filled and (c == r or (r, c - 1) in filled) and (r == 1 or (r - 1, c) in filled):
                T[(r, c)] = k
                filled.add((r, c))
                rec(k + 1)
                filled.remove((r, c))

    rec(1)
    return sums, total


@pytest.mark.parametrize("N", [3, 4, 5, 6])
def test_expected_entries_against_every_tableau(N):
    sums, total = _all_tableaux_entry_sums(N - 1)
    assert total == count(N)
    E = route.expected_entries(N, workers=1)
    assert E == {x: Fraction(v, total) for x, v in sums.items()}


# ------------------------------------------------------------------ the mathematics, exactly


def _jordan_wigner_amplitudes(n):
    """<full, a| H'^d |empty, 0> for H' = sum_a c+_{a+1} c_a + gamma_0 c+_1 (modes 0 = auxiliary, 1..n)."""

    def apply(state):
        out = {}
        for s, v in state.items():
            for a in range(1, n):  # hop a -> a+1: empty Jordan-Wigner string between neighbours
                if s >> a & 1 and not s >> (a + 1) & 1:
                    t = s ^ (1 << a) ^ (1 << (a + 1))
                    out[t] = out.get(t, 0) + v
            if not s >> 1 & 1:  # gamma_0 c+_1: c+_1 has the string (-1)^{n_0}, then gamma_0 flips n_0
                sign = -1 if s & 1 else 1
                t = s ^ 2 ^ 1
                out[t] = out.get(t, 0) + sign * v
        return {k: v for k, v in out.items() if v}

    state, d = {0: 1}, n * (n + 1) // 2
    for _ in range(d):
        state = apply(state)
    full = ((1 << n) - 1) << 1
    return {a: state.get(full | a, 0) for a in (0, 1)}


@pytest.mark.parametrize("n", range(1, 8))
def test_majorana_hopping_counts_tableaux_with_one_sign(n):
    """|<full|H'^d|empty>| = count(n + 1), every path with the sign (-1)^(n(n-1)/2): no sign problem."""
    amp = _jordan_wigner_amplitudes(n)
    assert amp[n % 2] == (-1) ** (n * (n - 1) // 2) * count(n + 1)
    assert amp[1 - n % 2] == 0


def _schur_product(parts):
    parts = sorted(parts, reverse=True) + ([0] if len(parts) % 2 else [])
    return prod((Fraction(a - b, a + b) for i, a in enumerate(parts) for b in parts[i + 1 :]), start=Fraction(1))


@pytest.mark.parametrize("n", range(1, 8))
def test_minor_summation_identity(n):
    """Pf K = sum_A prod alpha_A prod beta_B Pf(M_A') Pf(M_B') for random rational weights."""
    rng = random.Random(n)
    alpha = {a: Fraction(rng.randint(-9, 9), rng.randint(1, 9)) for a in range(1, n + 1)}
    beta = {a: Fraction(rng.randint(-9, 9), rng.randint(1, 9)) for a in range(1, n + 1)}
    total = Fraction(0)
    for mask in range(1 << n):
        A = [a for a in range(1, n + 1) if mask >> (a - 1) & 1]
        B = [a for a in range(1, n + 1) if not mask >> (a - 1) & 1]
        total += prod((alpha[a] for a in A), start=Fraction(1)) * prod((beta[b] for b in B), start=Fraction(1)) \
            * _schur_product(A) * _schur_product(B)
    assert schur.pfaffian(schur.minor_summation_matrix(n, alpha, beta)) == total


def _window_brute(n, q, y):
    d = n * (n + 1) // 2
    f = lambda A: shifted_tableaux_count(tuple(sorted(A, reverse=True))) if A else 1  # noqa: E731
    terms = []
    for mask in range(1 << n):
        A = [a for a in range(1, n + 1) if mask >> (a - 1) & 1]
        B = [a for a in range(1, n + 1) if not mask >> (a - 1) & 1]
        l = sum(A)
        terms.append((B, Fraction(f(A) * f(B), factorial(l) * factorial(d - l)) * Fraction(q) ** l))
    Z = sum(w for _, w in terms)
    return [sum(w * Fraction(y) ** sum(b >= m for b in B) for B, w in terms) / Z for m in range(n, 0, -1)]


@pytest.mark.parametrize("n", range(1, 6))
@pytest.mark.parametrize("q, y", [(2, -1), (Fraction(3, 2), Fraction(-2, 5)), (Fraction(1, 7), 3)])
def test_point_process_kernel_equals_subset_sums(n, q, y):
    assert schur.window_generating_function(n, q, y) == _window_brute(n, q, y)


def test_complement_symmetry_of_the_kernel():
    """R(1/q, y, m) = y^(n-m+1) R(q, 1/y, m): the symmetry that halves the level points."""
    n, q, y = 4, Fraction(5, 3), Fraction(-3, 2)
    left = schur.window_generating_function(n, 1 / q, y)
    right = schur.window_generating_function(n, q, 1 / y)
    assert left == [y ** (k + 1) * r for k, r in enumerate(right)]


# ------------------------------------------------------------------ the kernels


@pytest.mark.parametrize("N", range(2, 9))
def test_compiled_prime_residues_equal_pure_python(N):
    with engine._oracle_kernels(kernels_python):
        oracle = engine.prime_residues(N, PRIME)
    assert (engine.prime_residues(N, PRIME) == oracle).all()


@pytest.mark.parametrize("n", [1, 2, 3, 4, 5, 9, 16, 17])
def test_lazy_pair_elimination_equals_textbook_elimination(n):
    rng = np.random.default_rng(n)
    M = rng.integers(0, PRIME, (2 * n, 2 * n))
    M = (M - M.T) % PRIME
    ref = kernels_python._pair_pfaffians([[int(x) for x in r] for r in M], PRIME, False)
    A = np.zeros((2 * n, (2 * n + 7) // 8 * 8))
    A[:, : 2 * n] = np.triu(M, 1)
    out, c = np.zeros(n), np.zeros((4, 2 * n))
    assert dense._eliminate(A, n, float(PRIME), 1 / PRIME, c[0], c[1], c[2], c[3], out)
    assert out.astype(np.int64).tolist() == ref


def test_interpolation_weights():
    points = np.array([2.0, 3.0, 5.0, 11.0])
    g = np.array([7.0, 1.0, 0.0, 4.0])
    for K in (kernels, kernels_python):
        lam = K.dual_weights(points, g, float(PRIME)).astype(np.int64)
        assert [sum(int(l) * pow(int(x), k, PRIME) for l, x in zip(lam, points)) % PRIME for k in range(4)] == [7, 1, 0, 4]
        L = K.lagrange_matrix(points, float(PRIME)).astype(np.int64)
        V = np.array([[pow(int(x), k, PRIME) for k in range(4)] for x in points], dtype=np.int64)
        assert ((V @ L) % PRIME == np.eye(4, dtype=np.int64)).all()


def test_compiled_edge_values_equal_pure_python():
    n, p = 6, PRIME
    B, X1, expo = engine.setup_matrices(n, p)
    R1, R2 = np.zeros((2, n)), np.zeros((2, n))
    assert kernels.edge_values(B, X1, expo, 5.0, n, float(p), R1)
    assert kernels_python.edge_values(B, X1, expo, 5.0, n, float(p), R2)
    assert (R1 == R2).all()


def test_edge_residues_are_the_first_column():
    for N in (3, 7, 12):
        assert (engine.edge_residues(N, PRIME)[1:] == engine.prime_residues(N, PRIME)[1:, 0]).all()


def test_a_zero_pivot_moves_the_point(monkeypatch):
    """Evaluation points that fail modulo p are replaced; the result does not change."""
    real = kernels.point_values
    calls = []

    def flaky(B, X1, expo, c, us, n, p, R, BC=None):
        calls.append(c)
        return False if len(calls) % 3 == 0 else real(B, X1, expo, c, us, n, p, R, BC)

    expected = engine.prime_residues(7, PRIME)
    monkeypatch.setattr(kernels, "point_values", flaky)
    assert (engine.prime_residues(7, PRIME) == expected).all()
    assert len(calls) > cost.level_points(21) // 2
    real_edge, calls[:] = kernels.edge_values, []

    def flaky_edge(B, X1, expo, c, n, p, R, BC=None):
        calls.append(c)
        return False if len(calls) % 3 == 0 else real_edge(B, X1, expo, c, n, p, R, BC)

    edge = engine.edge_residues(7, PRIME)
    monkeypatch.setattr(kernels, "edge_values", flaky_edge)
    assert (engine.edge_residues(7, PRIME) == edge).all()


def test_prime_limits_keep_the_word_arithmetic_exact():
    for n in (1, 10, 63, 99, 199):
        p = cost.prime_limit(n) - 1  # the displacement kernels: loose residues below 2p, sums below 8 p^2
        assert 8 * p * p < 2**53
        p = cost.dense_prime_limit(n)  # the dense baseline: lazily reduced rows
        assert p + 2 * (n - 1) * p * p < 2**53 and 64 * p * p < 2**53
    assert cost.route_primes(10, 33554393) == (33554393, 33554383)  # the product must exceed the bound


@pytest.mark.parametrize("N", [2, 3, 4, 5, 6, 7, 10, 17, 24])
@pytest.mark.parametrize("c", [2, 5, 1234567])
def test_displacement_generators_equal_the_dense_kernel(N, c):
    """Sec. 4.1: (x_i + x_j) W_ij = F_i0 F_j1 - F_i1 F_j0 for every i < j, and the pair entries, from four solves.

    The dense kernel (inverse and products) is the independent route; the
    check covers every entry, so it also checks the lemma that the
    displacement has rank two.
    """
    p, n = LARGE_PRIME, N - 1
    size = 2 * n
    B, X1, expo = engine.setup_matrices(n, p)
    Wt = np.zeros((size, size))
    assert dense._kernel_matrix(B, X1, expo, float(c), n, float(p), Wt)
    F, Wd = np.zeros((size, 2)), np.zeros(n)
    assert kernels._kernel_generators(B, X1, expo, float(c), n, float(p), F, Wd,
                                      kernels.kernel_constants(B, expo, n, float(p)))
    x = [(n - i // 2) * (1 if i % 2 == 0 else -1) for i in range(size)]
    F = F.astype(np.int64).tolist()
    for i in range(size):
        for j in range(i + 1, size):
            assert (x[i] + x[j]) * int(Wt[i, j]) % p == (F[i][0] * F[j][1] - F[i][1] * F[j][0]) % p
    assert [int(v) for v in Wd] == [int(Wt[2 * b, 2 * b + 1]) for b in range(n)]
    G = np.zeros((size, 2))  # the generators read off the dense displacement agree as a form
    assert dense.displacement_generators(Wt, n, float(p), G)


@pytest.mark.parametrize("n", [1, 2, 3, 4, 5, 9, 16, 17, 30, 99])
def test_displacement_elimination_equals_the_dense_elimination(n):
    """Every y of :func:`point_values` (groups of 8 and a narrower last group) against the dense pair elimination."""
    p = PRIME  # below both bounds
    B, X1, expo = engine.setup_matrices(n, p)
    us = np.array([(3 + 7 * j) % p for j in range(n + 3)], dtype=np.float64)
    R1, R2 = np.zeros((len(us), n)), np.zeros((len(us), n))
    assert kernels.point_values(B, X1, expo, 5.0, us, n, float(p), R1)
    assert dense.point_values_dense(B, X1, expo, 5.0, us, n, float(p), R2)
    assert (R1 == R2).all()


@pytest.mark.parametrize("N", [2, 5, 8, 13])
def test_dense_backend_gives_the_same_residues(N):
    """The benchmarks' baseline (dense elimination of every (q, y)) is the same route, term by term."""
    with engine._oracle_kernels(dense):
        baseline = engine.prime_residues(N, PRIME)
    assert (baseline == engine.prime_residues(N, PRIME)).all()


@pytest.mark.parametrize("N", [3, 6, 9])
def test_large_primes_agree_with_pure_python(N):
    """Primes near 2^25, where the loose residues come closest to 2^53."""
    with engine._oracle_kernels(kernels_python):
        oracle = engine.prime_residues(N, LARGE_PRIME)
    assert (engine.prime_residues(N, LARGE_PRIME) == oracle).all()


def test_fraction_free_elimination_at_a_large_prime_and_many_pivots():
    """n = 60 pivots at a prime near 2^25: the scaled (fraction-free) state against textbook elimination."""
    n, p = 60, LARGE_PRIME
    B, X1, expo = engine.setup_matrices(n, p)
    us = np.array([p - 2.0, 12345.0])
    R1, R2 = np.zeros((2, n)), np.zeros((2, n))
    assert kernels.point_values(B, X1, expo, 7.0, us, n, float(p), R1)
    assert kernels_python.point_values(B, X1, expo, 7.0, us, n, float(p), R2)
    assert (R1 == R2).all()


@pytest.mark.parametrize("bad, error", [(1.5, TypeError), (8388592, ValueError), (7, ValueError), (2**25 + 15, ValueError)])
def test_prime_residues_checks_its_arguments(bad, error):
    with pytest.raises(error):
        engine.prime_residues(5, bad)


@pytest.mark.parametrize("call", [lambda: route.mean_W(1), lambda: route.mean_W(201), lambda: route.count(True),
                                  lambda: route.survival_table(5, workers=0), lambda: route.survival_table(5, backend="c"),
                                  lambda: engine.prime_residues(5, PRIME, backend="python")])
def test_bad_arguments(call):
    with pytest.raises((TypeError, ValueError)):
        call()


# ------------------------------------------------------------------ beyond the DP


@pytest.mark.slow
@pytest.mark.parametrize("N", [30, 34])
def test_row_sums_and_mirror_symmetry_beyond_the_dp(N):
    W = route.mean_W(N)
    assert route.lattice_direction(N) == [row[0] for row in W]
    assert all(sum(row) == 1 for row in W)
    assert all(W[i][j] == W[i][i - j] for i in range(N) for j in range(i + 1))  # not built into the route
    assert all(w > 0 for row in W for w in row)


def _sampler_agreement(N, samples, seed, bounds=None):
    from forcenet.numeric.agreement import compare_samples
    from forcenet.numeric.triangle.exact_sampler import ExactSampler

    exact = route.mean_W(N)
    grains = [(i, j) for i in range(2, N + 1) for j in range(1, i)]  # W_ii = 1 - the others
    sampler, rows = ExactSampler(N, seed=seed), []
    while sum(len(r) for r in rows) < samples:
        W = sampler.sample_W(min(sampler.batch, samples - sum(len(r) for r in rows)))
        rows.append(np.stack([W[:, i - 1, j - 1] for i, j in grains], axis=1))
    # Hotelling chi-square and Bonferroni max |z|, each at alpha = 1e-3 (about 5 sigma for the max over ~10^3 grains)
    return compare_samples(np.concatenate(rows), [exact[i - 1][j - 1] for i, j in grains], keys=grains, alpha=1e-3,
                           bounds=bounds)


@pytest.mark.slow
def test_exact_sampler_agrees_at_N40():
    """The bounded test (every W_ij in [0, 1]): at 4000 rows the t route cannot judge, W_(40,1) being skewed
    (sample skewness 1.7: its tail is trusted from about 6100 rows on)."""
    result = _sampler_agreement(40, 4000, seed=18, bounds=(0, 1))
    assert result.passed, result.summary()
    assert result.max_z < 5.5


@pytest.mark.slow
def test_lattice_direction_agrees_with_the_exact_sampler_at_N64():
    from forcenet.numeric.agreement import compare_samples
    from forcenet.numeric.triangle.exact_sampler import ExactSampler

    N, samples = 64, 20000
    column = route.lattice_direction(N)
    sampler, rows, drawn = ExactSampler(N, seed=64), [], 0
    while drawn < samples:
        W = sampler.sample_W(min(sampler.batch, samples - drawn))
        rows.append(W[:, 1:, 0])
        drawn += W.shape[0]
    result = compare_samples(np.concatenate(rows), column[1:], keys=list(range(2, N + 1)), alpha=1e-3)
    assert result.passed, result.summary()


@pytest.mark.slow
def test_exact_sampler_agrees_at_N64():
    """The whole N = 64 table (2016 grains; ~2 min on two cores) against exact samples."""
    result = _sampler_agreement(64, 8000, seed=64)
    assert result.passed, result.summary()


@pytest.mark.slow
def test_exact_sampler_agrees_at_N100():  # pragma: no cover - ~35 min on two cores (notes/benchmarks.md)
    import os

    if os.environ.get("FORCENET_HOURS") != "1":
        pytest.skip("the N = 100 table takes ~35 min on the 2-core machine; set FORCENET_HOURS=1 to run it")
    result = _sampler_agreement(100, 8000, seed=100)
    assert result.passed, result.summary()


# ------------------------------------------------------------------ plan, routes, command line


def test_registered_route():
    assert "pfaffian" in METHODS
    assert [str(x) for x in table_run("pfaffian", 5)[1][-1]] == ["1/11", "1/4", "7/22", "1/4", "1/11"]


def test_plan_and_refusals():
    plan = table_plan("pfaffian", 24)
    assert plan.runnable and plan.unit == "prime" and 0 < plan.seconds < 60
    assert table_plan("pfaffian", 10, moments=2).runnable  # every load's gap law by de Bruijn Pfaffians
    assert "N must be an integer in 2..128" in table_plan("pfaffian", 129, moments=2).refusal
    assert "N must be an integer in 2..200" in table_plan("pfaffian", 201).refusal
    assert "GiB of memory" in table_plan("pfaffian", 40, memory_bytes=2**20).refusal
    big = table_plan("pfaffian", 64)
    assert big.runnable and big.seconds > 60  # the command line asks for --force


def test_lattice_direction_plan():
    plan = route.lattice_direction_plan(100)
    assert plan.runnable and plan.unit == "prime" and plan.seconds < table_plan("pfaffian", 100).seconds / 3
    assert "N must be an integer in 2..200" in route.lattice_direction_plan(300).refusal


def test_ticks_are_primes():
    ticks = []
    route.survival_table(12, workers=1, progress=ticks.append)
    assert sum(ticks) == table_plan("pfaffian", 12).ticks


def test_worker_processes_give_the_same_table():
    assert route.mean_W(14, workers=2) == route.mean_W(14, workers=1)


def test_command_line_json_equals_the_fast_route(capsys):
    outputs = []
    for method in ("fast", "pfaffian"):
        assert main(["table", "--N", "11", "--format", "json", "--method", method, "--quiet"]) == 0
        outputs.append(capsys.readouterr().out)
    assert outputs[0] == outputs[1]
    assert json.loads(outputs[1])["count"] == str(count(11))


def test_command_line_refuses_a_long_run_without_force(capsys):
    # --no-checkpoint: records of this request in the user's default checkpoint folder would make it short
    assert main(["table", "--N", "64", "--format", "json", "--method", "pfaffian", "--no-checkpoint"]) == 2
    assert "--force" in capsys.readouterr().err
