"""Exact values as text, however long: Python's limit on int/str conversion (4300 digits) never applies.

The lattice column at N = 160 has denominators past the limit; its run failed
in the final conversion (2026-11-27) until :func:`integer_text` and
:func:`fraction_from_text` took over.  The CLI lifts the limit for its own
process, so these tests set it explicitly.
"""

import json
import random
import sys
from contextlib import contextmanager
from fractions import Fraction

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from forcenet.core.errors import ArgumentError
from forcenet.exact.triangle.tables import fraction_from_text, fraction_str, integer_text, to_csv, to_json, to_latex


@contextmanager
def _limit(digits: int):
    """Python's int/str limit set to ``digits`` (0: none) inside the block, restored after."""
    old = sys.get_int_max_str_digits()
    sys.set_int_max_str_digits(digits)
    try:
        yield
    finally:
        sys.set_int_max_str_digits(old)


@pytest.fixture
def default_limit():
    """The interpreter's default limit (4300 digits), restored afterwards."""
    with _limit(4300):
        yield 4300


def _unlimited_str(n: int) -> str:
    with _limit(0):
        return str(n)


def _big(seed: int, bits: int) -> int:
    rng = random.Random(seed)
    return rng.choice((-1, 1)) * rng.getrandbits(bits)


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 2**32), bits=st.integers(1, 60000))
def test_integer_text_is_str_without_the_limit(seed, bits):
    with _limit(4300):
        n = _big(seed, bits)
        text = integer_text(n)
        assert text == _unlimited_str(n)
        assert fraction_from_text(text) == n


@settings(max_examples=30, deadline=None)
@given(seed=st.integers(0, 2**32), bits=st.integers(1, 40000), den_bits=st.integers(1, 40000))
def test_fractions_round_trip_through_their_text(seed, bits, den_bits):
    with _limit(4300):
        x = Fraction(_big(seed, bits), abs(_big(seed + 1, den_bits)) or 1)
        assert fraction_from_text(fraction_str(x)) == x


def test_the_default_limit_is_in_force_and_would_refuse(default_limit):
    n = 7**10000  # 8451 digits
    with pytest.raises(ValueError):
        str(n)
    assert len(integer_text(n)) == 8451 and integer_text(n) == _unlimited_str(n)


def test_a_table_past_the_limit_renders_in_every_format(default_limit):
    big = 3**10000 * 5  # 4773 digits, past the limit
    table = {"N": 2, "count": big, "normalization": Fraction(1, big), "mean_W": [[Fraction(1)], [Fraction(big - 1, big), Fraction(1, big)]]}
    data = json.loads(to_json(table))
    assert fraction_from_text(data["count"]) == big
    assert [[fraction_from_text(x) for x in row] for row in data["mean_W"]] == table["mean_W"]
    assert to_csv(table).splitlines()[2] == f"2,1,{_unlimited_str(big - 1)}/{_unlimited_str(big)}"
    assert _unlimited_str(big) in to_latex(table)


@pytest.mark.parametrize("text", ["", "/", "12/", "/3", "1/0", "abc", "1_000", "1.5", "--3", "3/-4", "1/2/3"])
def test_malformed_text_names_the_argument(text):
    with pytest.raises(ArgumentError, match="text"):
        fraction_from_text(text)


def test_malformed_long_text_names_the_argument(default_limit):
    with pytest.raises(ArgumentError, match="text"):
        fraction_from_text("1" * 5000 + "x" + "2" * 5000)
