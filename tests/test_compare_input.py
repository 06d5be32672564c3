"""Bad input to forcenet.testing.compare / assert_agrees (issue 45 item 6, issue 46 item 4).

Each case is refused by the exception family (``ArgumentError`` or
``ArgumentTypeError``, a ``forcenet.ForcenetError``) whose message names the
argument at fault (``samples``, ``exact``, ``alpha``, ``bounds``, ...) and
what would work: bad samples never blame ``exact``, nothing is accepted
silently. The good inputs next to them are accepted (the cases are not
refused for some other reason).
"""

from fractions import Fraction

import numpy as np
import pytest

import forcenet
from forcenet.exact import mean_W
from forcenet.numeric.triangle.exact_sampler import ExactSampler
from forcenet.testing import assert_agrees, compare

W = ExactSampler(4, seed=45).sample_W(200)
TABLE = mean_W(4)
ONE = W[:, 3, 1]  # one value, <W_42> = mean_W(4)[3][1]
NAN = W.copy()
NAN[7, 2, 1] = np.nan
INF = W.copy()
INF[3, 3, 0] = np.inf
OUTSIDE = W.copy()
OUTSIDE[5, 3, 2] = 1.5
NEGATIVE = W.copy()
NEGATIVE[9, 2, 0] = -0.25
BAD = forcenet.ArgumentError
BADTYPE = forcenet.ArgumentTypeError

CASES = [  # (id, samples, exact, options, error, words the message must hold, in order)
    ("samples empty list", [], TABLE, {}, BAD, ["samples is empty", "one row per sample"]),
    ("samples 0 rows", np.empty((0, 4, 4)), TABLE, {}, BAD, ["samples is empty", "(K, ...)"]),
    ("samples rows of no values", np.empty((5, 0)), 0.5, {}, BAD, ["samples has rows of no values"]),
    ("samples ragged", [[0.1, 0.2], [0.3]], [0.1, 0.2], {}, BAD, ["samples is ragged", "rectangular"]),
    ("samples ragged arrays", [np.zeros(3), np.zeros(2)], [0, 0, 0], {}, BAD, ["samples is ragged"]),
    ("samples strings", ["0.1", "0.2", "0.3"], 0.2, {}, BADTYPE, ["samples holds", "not numbers"]),
    ("samples a string", "0.1 0.2 0.3", 0.2, {}, BADTYPE, ["samples is a str", "one row per sample"]),
    ("samples mixed str", [0.1, "x", 0.3], 0.2, {}, BADTYPE, ["samples holds", "not numbers"]),
    ("samples None entries", np.array([0.1, None, 0.3], dtype=object), 0.2, {}, BADTYPE, ["samples holds None"]),
    ("samples None", None, 0.2, {}, BADTYPE, ["samples is a NoneType"]),
    ("samples dict", {"a": 1}, 0.2, {}, BADTYPE, ["samples is a dict"]),
    ("samples complex", np.array([0.1 + 1j, 0.2, 0.3]), 0.2, {}, BADTYPE, ["samples holds complex numbers"]),
    ("samples huge int", [10**400, 1, 2], 1, {}, BAD, ["samples holds a number too large for a float"]),
    ("samples NaN", NAN, TABLE, {}, BAD, ["samples holds nan at (7, 2, 1)", "finite"]),
    ("samples inf", INF, TABLE, {}, BAD, ["samples holds inf at (3, 3, 0)"]),
    ("samples NaN chain", NAN, TABLE, {"chain": True}, BAD, ["samples holds nan"]),
    ("samples a number", 0.5, 0.5, {}, BAD, ["samples is a single number"]),
    ("samples one row", W[:1], TABLE, {}, BAD, ["samples: 1 row", "at least 2"]),
    ("samples too small for exact", W[:, :3, :3], TABLE, {}, BAD,
     ["exact has 4 entries", "axis of length 3", "one sample has shape (3, 3)", "same table"]),
    ("samples 1-D, exact a table", ONE, TABLE, {}, BAD, ["exact", "sequence where one sample has no further axis"]),
    ("samples outside the table's bounds", OUTSIDE, TABLE, {}, BAD,
     ["samples of (4, 3): row 5 = 1.5 lies outside the bounds [0, 1]", "bounds from the exact table",
      "every W of the triangle lies in [0, 1]"]),
    ("samples below the given bounds", NEGATIVE, TABLE, {"bounds": (0, 1)}, BAD,
     ["samples of (3, 1): row 9 = -0.25 lies outside the bounds [0, 1]"]),
    ("alpha a string", W, TABLE, {"alpha": "0.001"}, BADTYPE, ["alpha='0.001' is a string", "alpha=1e-3"]),
    ("alpha 0", W, TABLE, {"alpha": 0}, BAD, ["alpha=0 is out of range", "(0, 1)"]),
    ("alpha 1", W, TABLE, {"alpha": 1}, BAD, ["alpha=1 is out of range"]),
    ("alpha negative", W, TABLE, {"alpha": -0.01}, BAD, ["alpha=-0.01 is out of range"]),
    ("alpha NaN", W, TABLE, {"alpha": float("nan")}, BAD, ["alpha=nan is out of range"]),
    ("alpha inf", W, TABLE, {"alpha": float("inf")}, BAD, ["alpha=inf is out of range"]),
    ("alpha True", W, TABLE, {"alpha": True}, BADTYPE, ["alpha=True is not a number"]),
    ("alpha None", W, TABLE, {"alpha": None}, BADTYPE, ["alpha=None is not a number"]),
    ("chain 'yes'", W, TABLE, {"chain": "yes"}, BADTYPE, ["chain='yes' is not a bool", "chain=True or False"]),
    ("chain 1", W, TABLE, {"chain": 1}, BADTYPE, ["chain=1 is not a bool"]),
    ("chain None", W, TABLE, {"chain": None}, BADTYPE, ["chain=None is not a bool"]),
    ("hotelling 'no'", W, TABLE, {"hotelling": "no"}, BADTYPE, ["hotelling='no' is not a bool"]),
    ("bounds one number", W, TABLE, {"bounds": 1}, BAD, ["bounds=1: give (lo, hi)"]),
    ("bounds three", W, TABLE, {"bounds": (0, 1, 2)}, BAD, ["bounds=(0, 1, 2): give (lo, hi)"]),
    ("bounds a string", W, TABLE, {"bounds": "01"}, BAD, ["bounds='01': give (lo, hi)"]),
    ("bounds strings", W, TABLE, {"bounds": ("0", "1")}, BADTYPE, ["bounds[0] (lo)='0' is not a number"]),
    ("bounds reversed", W, TABLE, {"bounds": (1, 0)}, BAD, ["[1, 0] must be finite with lo < hi"]),
    ("bounds equal", W, TABLE, {"bounds": (0.5, 0.5)}, BAD, ["must be finite with lo < hi"]),
    ("bounds NaN", W, TABLE, {"bounds": (float("nan"), 1)}, BAD, ["bounds[0] (lo)=nan is not finite"]),
    ("bounds inf", W, TABLE, {"bounds": (0, float("inf"))}, BAD, ["bounds[1] (hi)=inf is not finite"]),
    ("bounds table too long", W, TABLE, {"bounds": (0, [[1]] * 5)}, BAD, ["bounds[1] (hi) has 5 entries"]),
    ("bounds table missing a value", W, TABLE, {"bounds": (0, [[1], [1, 1]])}, BAD,
     ["bounds[1] (hi): a tested value has no bound"]),
    ("exact outside the bounds", W, [[2], *TABLE[1:]], {"bounds": (0, 1)}, BAD,
     ["exact value of (1, 1) = 2 lies outside its bounds [0, 1]"]),
    ("exact a string", ONE, "0.25", {}, BADTYPE, ["exact='0.25' is not a number"]),
    ("exact NaN", ONE, float("nan"), {}, BAD, ["exact=nan is not finite", "None for a value not to test"]),
    ("exact inf in a table", W, [[1], [0.5, float("inf")], *TABLE[2:]], {}, BAD, ["exact[1][1]=inf is not finite"]),
    ("exact all None", W, [[None]], {}, BAD, ["exact has no value to test"]),
    ("exact bool", ONE, True, {}, BADTYPE, ["exact=True is not a number"]),
    ("keys too few", W, TABLE, {"keys": ["a"]}, BAD, ["keys has 1 names for 10 tested values"]),
    ("keys not a sequence", W, TABLE, {"keys": 5}, BADTYPE, ["keys=5 is not a sequence"]),
    ("batch option without chain", W, TABLE, {"batch_factor": 5}, BADTYPE, ["batch options apply to chains"]),
    ("unknown option", W, TABLE, {"chain": True, "batches": 5}, BADTYPE, ["unexpected keywords ['batches']"]),
]


@pytest.mark.parametrize("samples, exact, options, error, words", [case[1:] for case in CASES],
                         ids=[case[0] for case in CASES])
@pytest.mark.parametrize("function", [compare, assert_agrees])
def test_bad_input_is_refused_by_the_family_naming_the_argument(function, samples, exact, options, error, words):
    with pytest.raises(error) as info:
        function(samples, exact, **options)
    assert isinstance(info.value, forcenet.ForcenetError)
    message = str(info.value)
    at = 0
    for word in words:
        found = message.find(word, at)
        assert found >= 0, (word, message)
        at = found + len(word)
    if "samples" in words[0]:
        assert not message.startswith("exact"), message  # bad samples never blame exact


def test_there_are_enough_cases():
    assert len(CASES) >= 30


@pytest.mark.parametrize("samples, exact, options", [
    (W, TABLE, {}),                                     # the table's own bounds
    (W, TABLE, {"bounds": False}),                      # none: the t route (too few rows: cannot judge)
    (W.astype(np.float32), TABLE, {}),
    ((W > 0.5), [[1], [0.5, 0.5]], {"bounds": False}),  # booleans are numbers (an indicator)
    (ONE, TABLE[3][1], {"alpha": np.float64(0.01)}),
    (ONE, Fraction(TABLE[3][1]), {"alpha": Fraction(1, 100), "chain": np.bool_(False), "hotelling": None}),
    ([[1, 2], [3, 4], [2, 3]], [2, 3], {"bounds": (0, 5)}),  # integers
    (np.array([Fraction(1, 2), Fraction(1, 3), 1], dtype=object), Fraction(11, 18), {"bounds": (0, 1)}),
])
def test_good_input_next_to_the_bad_is_accepted(samples, exact, options):
    assert compare(samples, exact, **options).verdict in ("agrees", "cannot judge")
