"""Second moments of every partial sum by the mean's Pfaffian evaluations (notes/fluctuations.md Sec. 1, issue 27).

Checked against independent routes:

* the linear extensions, enumerated by networkx (N <= 6): the ranks of the partial sums;
* the order-ideal DP's second moments and two-point functions, ``S^2 = (sum_l W_l)^2`` (N <= 9);
* beyond the DP: the lattice-direction laws (other residues: the level polynomial interpolated) for
  ``S_{i,1} = W_{i,1}`` and ``S_{i,i-1} = 1 - W_{i,i}``, and the mean route's table for the first moments;
* the pure-Python kernels, and a checkpointed rerun.
"""

from fractions import Fraction

import networkx as nx
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from forcenet.core.errors import ArgumentError
from forcenet.exact.reference.linear_extensions import partial_sum_poset
from forcenet.exact.triangle.free_fermion import _kernels_python, engine, fluctuations, partial_sums, route
from forcenet.exact.triangle.moments import correlation, moment
from forcenet.exact.triangle.staircase import count

PRIME = 8388593


def _enumerated(N):
    """``(E[S_ij], E[S_ij^2])`` for the free partial sums, from every linear extension's ranks."""
    d = N * (N - 1) // 2
    sums, number = {}, 0
    for extension in nx.all_topological_sorts(partial_sum_poset(N)):
        number += 1
        for rank, cell in enumerate(extension, start=1):
            first, second = sums.get(cell, (0, 0))
            sums[cell] = first + rank, second + rank * (rank + 1)
    return {cell: (Fraction(a, number * (d + 1)), Fraction(b, number * (d + 1) * (d + 2)))
            for cell, (a, b) in sums.items()}


@pytest.mark.parametrize("N", [2, 3, 4, 5, 6])
def test_partial_sum_moments_equal_the_linear_extensions(N):
    moments = partial_sums.partial_sum_moments(N, workers=1)
    expected = _enumerated(N)
    assert len(expected) == N * (N - 1) // 2
    for (i, j), (first, second) in expected.items():
        assert (moments[1][i - 1][j - 1], moments[2][i - 1][j - 1]) == (first, second)
    assert all(row[-1] == 1 for table in moments.values() for row in table)


@settings(max_examples=6, deadline=None)
@given(data=st.data())
def test_partial_sum_second_moment_equals_the_dp(data):
    N = data.draw(st.integers(3, 9), label="N")
    i = data.draw(st.integers(2, N), label="i")
    j = data.draw(st.integers(1, i - 1), label="j")
    loads = [(i, l) for l in range(1, j + 1)]
    expected = sum(moment(N, g, 2) for g in loads) + 2 * sum(
        correlation(N, g, h) for a, g in enumerate(loads) for h in loads[a + 1:])
    assert partial_sums.partial_sum_moments(N, workers=1)[2][i - 1][j - 1] == expected


@pytest.mark.parametrize("N", [14, 22])
def test_lattice_partial_sums_equal_the_lattice_route(N):
    second = partial_sums.partial_sum_moments(N)[2]
    W2 = fluctuations.lattice_mean_W2(N)
    mean = route.lattice_direction(N)
    for i in range(2, N + 1):
        assert second[i - 1][0] == W2[i - 1]  # S_{i,1} = W_{i,1}
        assert second[i - 1][i - 2] == 1 - 2 * mean[i - 1] + W2[i - 1]  # S_{i,i-1} = 1 - W_{i,i}


@pytest.mark.parametrize("N", [12, 20])
def test_first_moments_are_the_mean_tables_partial_sums_and_the_mirror_holds(N):
    moments = partial_sums.partial_sum_moments(N)
    table = route.mean_W(N)
    for i in range(2, N + 1):
        assert moments[1][i - 1] == [sum(table[i - 1][:j]) for j in range(1, i + 1)]
        for j in range(1, i):  # S_{i,j} and 1 - S_{i,i-j} have one law
            assert moments[2][i - 1][j - 1] == 1 - 2 * moments[1][i - 1][i - j - 1] + moments[2][i - 1][i - j - 1]
            assert moments[2][i - 1][j - 1] > moments[1][i - 1][j - 1] ** 2  # a variance, never zero


@pytest.mark.parametrize("N", [3, 5, 6])
def test_pure_python_kernels_give_the_same_second_residues(N):
    with engine._oracle_kernels(_kernels_python):
        oracle = engine.prime_residues(N, PRIME, second=True)
    assert (engine.prime_residues(N, PRIME, second=True) == oracle).all()


def test_entry_moments_and_the_checked_rows(tmp_path):
    N = 7
    moments = partial_sums.entry_moments(N, workers=1, checkpoint=tmp_path)
    S, S2, total = partial_sums.second_survival_tables(N, workers=1, checkpoint=tmp_path)  # from the records
    assert total == count(N)
    assert any(tmp_path.rglob("*"))
    d = N * (N - 1) // 2
    for first, second in moments.values():
        assert 1 <= first <= d and first**2 <= second <= d * d
    n = N - 1  # certain entries: the cells comparable with every other, T = 1, 2, d - 1, d
    assert {x for x, (a, b) in moments.items() if b == a * a} == {(1, 1), (1, 2), (n - 1, n), (n, n)}
    with pytest.raises(ArithmeticError):
        engine.prime_residues(N, PRIME, total_mod_p=(count(N) + 1) % PRIME, second=True)


def test_plan():
    plan = partial_sums.partial_sum_moments_plan(40)
    assert plan.runnable and plan.unit == "prime"
    assert plan.ticks > route.mean_plan(40).ticks
    with pytest.raises(ArgumentError, match="N"):
        partial_sums.partial_sum_moments_plan(201)


@pytest.mark.slow
def test_partial_sums_agree_with_the_exact_sampler_at_N64():
    """<S_ij> and <S_ij^2> at depths and positions across the triangle against 20000 exact samples (alpha = 1e-3).

    The bounded test (every partial sum of a row summing to 1 lies in [0, 1]): without bounds the t route cannot
    judge 20000 rows here (``S_{64,1}^2`` has skewness about 8: its tail is trusted from about 54000 rows on)."""
    import numpy as np

    from forcenet.numeric.agreement import compare_samples
    from forcenet.numeric.triangle.exact_sampler import ExactSampler

    N, samples = 64, 20000
    moments = partial_sums.partial_sum_moments(N)
    probes = [(i, j) for i in (8, 16, 32, 48, 63, 64) for j in (1, i // 4, i // 2, i - 1)]
    sampler, columns, drawn = ExactSampler(N, seed=6401), [], 0
    while drawn < samples:
        W = sampler.sample_W(min(sampler.batch, samples - drawn))
        S = np.cumsum(W, axis=2)  # S[:, i-1, j-1] = S_ij
        columns.append(np.stack([S[:, i - 1, j - 1] for i, j in probes], axis=1))
        drawn += W.shape[0]
    X = np.concatenate(columns)
    data = np.concatenate([X, X**2], axis=1)
    expected = ([float(moments[1][i - 1][j - 1]) for i, j in probes]
                + [float(moments[2][i - 1][j - 1]) for i, j in probes])
    keys = [f"S_{i},{j}" for i, j in probes] + [f"S2_{i},{j}" for i, j in probes]
    assert data.min() >= 0 and data.max() <= 1 + 1e-12
    result = compare_samples(data, expected, keys=keys, alpha=1e-3, bounds=(0, 1))
    assert result.passed, result.summary()
