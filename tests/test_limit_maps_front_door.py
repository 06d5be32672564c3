"""The front door of `forcenet limit`, `forcenet maps`, `forcenet count` and the main job's summary.

Each face's result equals its engine's, and renders byte for byte what the command line prints
(through forcenet.cli.main); refusals raise the exception family with the command line's message.
"""

import os
import warnings
from decimal import Decimal
from fractions import Fraction

import mpmath
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import forcenet
from forcenet.cli import main
from forcenet.exact.thesis.recursions import lambda_table
from forcenet.exact.triangle.staircase import count_plan as staircase_count_plan
from forcenet.exact.triangle.tables import integer_text
from forcenet.numeric.limit_shape.edge import EDGE_EXPONENT, edge_amplitude, edge_sd_amplitude
from forcenet.numeric.limit_shape.surface import bulk_response, lattice_response
from forcenet.table_formats import scientific


def _cli(capsys, *argv: str) -> tuple[int, str, str]:
    code = main(list(argv))
    captured = capsys.readouterr()
    return code, captured.out, captured.err


# ------------------------------------------------------------------------------------------------ limit_shape


@pytest.mark.parametrize("x, z, dps", [("0.2", "0.6", 20), ("0", "1", 30), ("-0.35", "0.5", 12), ("1", "1", 20),
                                       ("-0", "0.25", 15)])
def test_limit_shape_is_the_engines_and_the_command_lines(capsys, x, z, dps):
    r = forcenet.limit_shape(x, z, dps=dps)
    # the floor's corner |x| = z = 1 is a lattice direction with a hard edge (tests/test_corrections.py)
    assert r.on_lattice == r.corner == (x == z == "1")
    assert r.corner or (r.edge_exponent is None and r.edge_amplitude is None)
    assert r.bulk == bulk_response(x, z, dps=dps) and r.lattice == lattice_response(z, dps=dps)
    assert (r.x, r.z) == (Fraction(x), Fraction(z))
    for fmt, text in (("json", r.to_json()), ("text", r.to_text())):
        assert _cli(capsys, "limit", "--x", x, "--z", z, "--dps", str(dps), "--format", fmt) == (0, text + "\n", "")


@pytest.mark.parametrize("x", ["0.6", "-0.6"])
def test_on_a_lattice_direction_the_edge_law(capsys, x):
    r = forcenet.limit_shape(x, "0.6", dps=10)
    assert r.on_lattice and r.bulk is None and r.edge_exponent == EDGE_EXPONENT == Fraction(2, 3)
    assert r.edge_amplitude == edge_amplitude("0.6", dps=10)
    assert r.edge_sd_amplitude == edge_sd_amplitude("0.6", dps=10)
    assert r.lattice == lattice_response("0.6", dps=10)
    for fmt, text in (("json", r.to_json()), ("text", r.to_text())):
        assert _cli(capsys, "limit", "--x", x, "--z", "0.6", "--dps", "10", "--format", fmt) == (0, text + "\n", "")
    assert '"N_W_bulk": null' in r.to_json() and "-> infinity" in r.to_text()


@settings(max_examples=15, deadline=None)
@given(st.integers(1, 100), st.data())
def test_a_fraction_a_decimal_string_and_a_decimal_give_the_same_limit(k, data):
    m = data.draw(st.integers(-k, k))
    x, z = Fraction(m, 100), Fraction(k, 100)  # |x| <= z
    exact = forcenet.limit_shape(x, z, dps=12)
    as_text = forcenet.limit_shape(str(Decimal(m) / 100), str(Decimal(k) / 100), dps=12)
    assert exact.to_dict() == as_text.to_dict() == forcenet.limit_shape(Decimal(m) / 100, Decimal(k) / 100,
                                                                        dps=12).to_dict()
    assert exact.on_lattice == (abs(m) == k) and (exact.bulk is None) == (abs(m) == k < 100)  # the corner: Beta(1, d)


def test_the_range_is_checked_exactly(capsys):
    message = "x=0.30000000000000000001 is out of range: x must lie in [-z, z] = [-0.3, 0.3]"
    with pytest.raises(forcenet.ArgumentError, match=message.replace("[", r"\[").replace("]", r"\]")):
        forcenet.limit_shape("0.30000000000000000001", "0.3")
    assert _cli(capsys, "limit", "--x", "0.30000000000000000001", "--z", "0.3") == (2, "", f"forcenet: error: {message}\n")
    # just inside: the bulk, not the lattice direction (a float comparison took it for |x| = z), to every digit
    for dps in (8, 20):
        near = forcenet.limit_shape("0.29999999999999999999", "0.3", dps=dps)
        truth = bulk_response("0.29999999999999999999", "0.3", dps=80)  # the gap's 20 digits and more
        assert not near.on_lattice and near.to_dict()["N_W_bulk"] == mpmath.nstr(truth, dps)
    with pytest.raises(forcenet.ArgumentError, match=r"^x=0\.49{10000} lies within 10\^-10001 of the lattice direction "
                                                     r"\|x\| = z = 0\.5: the bulk response there needs over 10000 digits"):
        forcenet.limit_shape("0.4" + "9" * 10000, "0.5")


def test_refusals_name_the_argument_and_the_range(capsys):
    with pytest.raises(forcenet.ArgumentError, match=r"^x=0\.9 is out of range: x must lie in \[-z, z\] = \[-0\.6, 0\.6\]$"):
        forcenet.limit_shape("0.9", "0.6")
    assert _cli(capsys, "limit", "--x", "0.9", "--z", "0.6")[::2] == (
        2, "forcenet: error: x=0.9 is out of range: x must lie in [-z, z] = [-0.6, 0.6]\n")
    with pytest.raises(forcenet.ArgumentError, match=r"^z=0 is out of range: z must be a finite number in \(0, 1\]$"):
        forcenet.limit_shape(0, 0)
    with pytest.raises(forcenet.ArgumentError, match=r"^z=1\.01 is out of range"):
        forcenet.limit_shape("0", "1.01")
    with pytest.raises(forcenet.ArgumentError, match=r"^dps=61 is out of range: dps must be an integer in 5\.\.60$"):
        forcenet.limit_shape("0.5", "0.5", dps=61)
    assert _cli(capsys, "limit", "--x", "0.5", "--z", "0.5", "--dps", "61")[::2] == (
        2, "forcenet limit: error: argument --dps: dps=61 is out of range: dps must be an integer in 5..60\n")
    with pytest.raises(forcenet.ArgumentTypeError, match=r"^x='abc' is not a number"):
        forcenet.limit_shape("abc", "0.5")
    with pytest.raises(forcenet.ArgumentTypeError, match="x=True"):
        forcenet.limit_shape(True, "0.5")
    with pytest.raises(forcenet.ArgumentTypeError, match="z="):
        forcenet.limit_shape("0", [1])


def test_a_binary_float_is_refused_or_warned_about():
    with pytest.raises(forcenet.ArgumentTypeError, match=r"z=0\.6 is a binary float.*pass '0\.6' or Fraction\(3, 5\)"):
        forcenet.limit_shape("0", 0.6, dps=20)
    with pytest.warns(forcenet.PrecisionWarning, match="z=0.6"):
        r = forcenet.limit_shape("0", 0.6, dps=10)
    assert r.z == Fraction(0.6) and r.to_text().startswith("scaling limit at x = 0, z = 0.6 (10 digits)")
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # 0.5 is exactly its decimal: nothing is lost, nothing said
        assert forcenet.limit_shape(0.5, 1, dps=30).bulk == bulk_response("0.5", "1", dps=30)


# ------------------------------------------------------------------------------------------------------- maps


@pytest.mark.parametrize("N", range(3, 9))
def test_maps_are_the_recursion_and_sum_to_the_count(N):
    m = forcenet.maps(N)
    assert m.by_bottom_row == lambda_table(N - 2) and list(m.by_bottom_row) == sorted(m.by_bottom_row)
    assert m.Z == forcenet.count(N) and m.N == N
    assert all(j[-1] == 1 and len(j) == N - 2 for j in m.by_bottom_row)  # Lambda vanishes unless j_p = 1


@pytest.mark.parametrize("N", [3, 6, 7])
def test_maps_render_as_the_command_line(capsys, N):
    m = forcenet.maps(N)
    assert _cli(capsys, "maps", "--N", str(N)) == (0, m.to_text() + "\n", "")
    assert _cli(capsys, "maps", "--N", str(N), "--format", "json") == (0, m.to_json() + "\n", "")


def test_maps_refuse_what_the_command_line_refuses(capsys):
    from forcenet.cli import table as table_cli
    from forcenet.map_counts import MAPS_MAX_N

    assert forcenet.MapCounts.MAX_N == MAPS_MAX_N and not hasattr(table_cli, "MAPS_MAX_N")  # no copy: the front door's
    for N in (2, MAPS_MAX_N + 1):
        message = f"N={N} is out of range: N must be an integer in 3..{MAPS_MAX_N}"
        with pytest.raises(forcenet.ArgumentError, match=f"^{message}$"):
            forcenet.maps(N)
        assert _cli(capsys, "maps", "--N", str(N))[::2] == (2, f"forcenet maps: error: argument --N: {message}\n")
    with pytest.raises(forcenet.ArgumentTypeError):
        forcenet.maps(5.0)


# ------------------------------------------------------------------------------------------------------ count


@settings(max_examples=20, deadline=None)
@given(st.integers(2, 400))
def test_the_count_plan_runs_the_count_and_prints_its_digits(N):
    plan = forcenet.count_plan(N)
    assert plan.runnable and plan.N == N and plan.cost == staircase_count_plan(N, 2**40)
    result = plan.run()
    assert int(result) == result.value == forcenet.count(N) and result.N == N
    assert result.to_text() == integer_text(forcenet.count(N))  # a second conversion (split by powers of ten)


def test_the_count_renders_as_the_command_line(capsys):
    for N in (2, 12, 84):  # 84: 4323 digits, beyond Python's default limit of str(int)
        text = forcenet.count_plan(N).run().to_text()
        assert _cli(capsys, "count", "--N", str(N), "--quiet") == (0, text + "\n", "")
    assert len(text) == 4323 and text.startswith("2061050853528590121489")


def test_the_count_plan_refuses_before_the_work(capsys):
    plan = forcenet.count_plan(10**7)
    assert not plan.runnable and plan.refusal.startswith("N=10000000 is out of range for count: N must be an integer in")
    with pytest.raises(forcenet.ArgumentError, match="^N=10000000 is out of range for count"):
        plan.run()
    assert _cli(capsys, "count", "--N", str(10**7))[::2] == (2, f"forcenet: error: {plan.refusal}\n")
    small = forcenet.count_plan(20000, memory_bytes=2**20)
    assert not small.runnable and "GiB of memory but 0.0 GiB is available" in small.refusal
    with pytest.raises(forcenet.ArgumentError, match="^N=1 is out of range"):
        forcenet.count_plan(1)
    with pytest.raises(forcenet.ArgumentError, match="memory_bytes=0"):
        forcenet.count_plan(5, memory_bytes=0)
    assert forcenet.count_plan(3000).seconds < forcenet.count_plan(6000).seconds  # the cost grows with N


# ---------------------------------------------------------------------------------------- the main job's summary


def test_the_main_jobs_summary_is_the_tables(capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    table = forcenet.table(7)
    code, out, _ = _cli(capsys, "table", "--N", "7", "--samples", "0")
    lines = table.summary().splitlines()
    assert code == 0 and out.splitlines()[:len(lines)] == lines and len(lines) == 5 + 7
    assert lines[0] == "Fully mobilized triangle, N = 7 layers, d = 21 free forces"
    assert "units of the overload" in lines[1]  # what W is (issue 53)
    assert lines[2].endswith(f": {forcenet.count(7)}") and lines[3].endswith(f"1/{1 / forcenet.normalization(7)}")
    assert os.path.exists(tmp_path / "forcenet-tables" / "mean_W_N7.json")
    for j, line in enumerate(lines[5:], start=1):
        value = table.mean_W[-1][j - 1]
        assert line == f"    j = {j:2d}: {float(value):.10f}  = {value}"


@pytest.mark.slow  # ~5 s: a table whose normalization has over 640 digits
def test_the_summary_does_not_depend_on_pythons_limit_of_str_int():
    import sys

    table = forcenet.table(31)  # ~3 s: its normalization's denominator has over 640 digits
    digits = len(integer_text(table.normalization.denominator))
    limit = sys.get_int_max_str_digits()
    sys.set_int_max_str_digits(640)  # the smallest limit Python allows; the denominator is longer
    try:
        assert digits > 640
        lines = table.summary().splitlines()
    finally:
        sys.set_int_max_str_digits(limit)
    # the summary abbreviates numbers this long (issue 53): the same text under any limit, and sizes that are right
    assert lines == table.summary().splitlines()
    count = forcenet.count_plan(31).run()
    count_line = next(line for line in lines if "tableaux count" in line)
    norm_line = next(line for line in lines if "normalization (Eq. 4.1)" in line)
    assert count_line.endswith(f"{scientific(Fraction(int(count)))} ({len(integer_text(int(count)))} digits)")
    assert norm_line.endswith(f"{scientific(table.normalization)} (p/q of 1/{digits} digits)")
