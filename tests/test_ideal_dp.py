"""The order-ideal engine: complement lemma, chunking, blocking, self-checks."""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import forcenet.exact.triangle.ideal_dp as dp
from forcenet.exact.reference.dictionary_dp import chain_counts
from forcenet.exact.triangle.staircase import count, shifted_tableaux_count


def mask_to_shape(mask, n):
    return tuple(p for p in range(n, 0, -1) if mask >> (p - 1) & 1)


@given(st.integers(min_value=1, max_value=8))
def test_complement_lemma(n):
    forward, backward = chain_counts(n)
    for shape, b in backward.items():
        complement = tuple(p for p in range(n, 0, -1) if p not in shape)
        assert b == forward[complement]


@given(st.integers(min_value=1, max_value=9))
def test_forward_counts_are_shifted_tableaux_counts(n):
    primes = (2147483647,)
    f = dp.forward_counts_mod(n, primes)
    for mask in range(1 << n):
        shape = mask_to_shape(mask, n)
        expected = shifted_tableaux_count(shape) if shape else 1
        assert int(f[mask, 0]) == expected % primes[0]


@pytest.mark.parametrize("N", [2, 5, 9, 12])
def test_prime_chunks_and_blocks_do_not_change_the_result(N, monkeypatch):
    reference = dp.survival_counts(N)
    monkeypatch.setattr(dp, "_BLOCK_BITS", 2)
    dp._popcount_groups.cache_clear()
    try:
        one_prime_per_chunk = dp.survival_counts(N, memory_bytes=1)
    finally:
        dp._popcount_groups.cache_clear()
    assert one_prime_per_chunk == reference


def test_survival_totals():
    for N in range(2, 12):
        C, total = dp.survival_counts(N)
        d = N * (N - 1) // 2
        assert total == count(N)
        assert C[0][1] == (d + 1) * total


def test_levels_partition_all_masks():
    order, bounds = dp.ideal_levels(6)
    assert sorted(order.tolist()) == list(range(64))
    sizes = [sum(p for p in range(1, 7) if m >> (p - 1) & 1) for m in order.tolist()]
    for k in range(len(bounds) - 1):
        assert set(sizes[bounds[k] : bounds[k + 1]]) <= {k}


def test_cost_estimate_grows_and_is_positive():
    small, big = dp.estimate_survival_cost(10), dp.estimate_survival_cost(20)
    assert 0 < small.nbytes < big.nbytes and 0 <= small.seconds < big.seconds
    assert "GiB" in str(big)


def test_parts_table_sorted_descending():
    lam = dp.parts_table(5)
    for mask in range(32):
        parts = [int(x) for x in lam[mask, 1:] if x]
        assert parts == sorted(parts, reverse=True) == list(mask_to_shape(mask, 5))
    assert np.all(lam[:, 0] == 6)
