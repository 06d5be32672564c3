"""A table for a paper, for a terminal, and back from its files (issue 53, items 3 and 9)."""

from __future__ import annotations

import subprocess
import sys
from decimal import ROUND_HALF_EVEN, Decimal, localcontext
from fractions import Fraction

import pytest
from hypothesis import given
from hypothesis import strategies as st

import forcenet
from forcenet.table_formats import abbreviated, decimal, latex, scientific


@given(st.fractions(), st.integers(0, 30))
def test_decimals_are_the_exact_value_correctly_rounded(x, digits):
    """Two routes: integer rounding of the exact fraction, and Decimal's quantize at ample precision."""
    with localcontext() as ctx:
        ctx.prec = 200
        expected = (Decimal(x.numerator) / Decimal(x.denominator)).quantize(Decimal(1).scaleb(-digits),
                                                                             rounding=ROUND_HALF_EVEN)
    text = decimal(x, digits)
    assert Decimal(text) == expected and (digits == 0 or len(text.split(".")[1]) == digits)


@given(st.fractions().filter(lambda x: x != 0))
def test_scientific_reads_back_within_its_last_digit(x):
    text = scientific(x)
    mantissa, exponent = text.split("e")
    assert 1 <= abs(float(mantissa)) < 10 and len(mantissa.lstrip("-").replace(".", "")) == 7
    assert abs(Fraction(mantissa) * Fraction(10) ** int(exponent) - x) <= Fraction(10) ** (int(exponent) - 6) / 2


def test_latex_is_booktabs_with_digits_and_rows():
    t = forcenet.table(8)
    text = t.to_latex(digits=4, rows=[1, 8])
    lines = text.splitlines()
    assert lines[2:5] == [r"\toprule", r"$i \backslash j$ & 1 & 2 & 3 & 4 & 5 & 6 & 7 & 8 \\", r"\midrule"]
    assert lines[5].startswith("1 & $1.0000$ &") and lines[6].startswith("8 & $0.0345$ & ")
    assert lines[-2:] == [r"\bottomrule", r"\end{tabular}"] and "hline" not in text
    exact = t.to_latex()
    assert exact.count(r"\frac") + exact.count("$1$") == 36  # every grain, exact by default
    with pytest.raises(forcenet.ArgumentError, match="rows"):
        t.to_latex(rows=[9])
    with pytest.raises(forcenet.ArgumentTypeError, match="rows"):
        t.to_latex(rows="1,2")
    with pytest.raises(forcenet.ArgumentError, match="digits"):
        t.to_latex(digits=-1)


def test_a_long_row_is_one_cell_per_line():
    from forcenet.exact import mean_W

    table = {"N": 16, "mean_W": mean_W(16)}
    text = latex(table)
    assert max(map(len, text.splitlines())) < 120 and text.count("\n  & ") > 100
    assert max(map(len, latex(table, digits=4).splitlines())) < 600


def test_from_json_and_read_give_the_table_back(tmp_path):
    t = forcenet.table(6, moments=2)
    assert forcenet.Table.from_json(t.to_json()) == t and forcenet.Table.from_json(t.to_json()).method == "json"
    (tmp_path / "t.csv").write_text(t.to_csv())
    (tmp_path / "t.json").write_text(t.to_json())
    assert forcenet.Table.read(tmp_path / "t.csv") == t == forcenet.Table.read(str(tmp_path / "t.json"))
    assert forcenet.Table.from_json(forcenet.table(5).to_json()) != t
    with pytest.raises(forcenet.ArgumentError, match="row i of i values"):
        forcenet.Table.from_json('{"N": 2, "mean_W": [["1"], ["1/2"]]}')
    with pytest.raises(forcenet.ArgumentError, match="not JSON"):
        forcenet.Table.from_json("{")
    with pytest.raises(forcenet.ArgumentError, match="one row's"):
        forcenet.Table.from_json(forcenet.row(4, 2).to_json())


def test_to_pandas():
    frame = forcenet.table(5, moments=2).to_pandas()
    assert list(frame.columns) == ["mean_W", "mean_W2"] and len(frame) == 15
    assert frame.loc[(5, 3), "mean_W"] == float(Fraction(7, 22))
    assert forcenet.table(5).to_pandas(exact=True).loc[(5, 3), "mean_W"] == Fraction(7, 22)


def test_the_summary_of_a_large_table_is_abbreviated():
    """N = 16: the first and last three values of the bottom row, decimals, the fractions' sizes; 80 columns."""
    summary = forcenet.table(16).summary()
    lines = summary.splitlines()
    assert "    ..." in lines and sum(line.startswith("    j =") for line in lines) == 6
    assert max(map(len, lines)) <= 80 and "digits" in summary
    assert "units of the overload" in summary and "rows sum to 1" in summary
    assert abbreviated(Fraction(1, 7)) == "1/7"


def test_the_main_job_speaks_plainly_and_details_under_verbose(tmp_path):
    def run(*extra):
        return subprocess.run([sys.executable, "-m", "forcenet", "table", "--N", "6", "--quiet", *extra],
                              capture_output=True, text=True, cwd=tmp_path, check=False)

    plain, verbose = run("--samples", "3000"), run("--samples", "3000", "--verbose")
    assert plain.returncode == verbose.returncode == 0
    assert "agrees with the exact values" in plain.stdout and "Bonferroni" not in plain.stdout
    assert "Bonferroni" in verbose.stdout and "RMS" in verbose.stdout
    assert max(map(len, plain.stdout.splitlines())) <= 80
    done = run("--format", "latex", "--digits", "2", "--rows", "1,6")
    assert done.returncode == 0 and done.stdout.splitlines()[6].startswith("6 & $0.") and "toprule" in done.stdout
    bad = run("--format", "latex", "--rows", "1,x")
    assert bad.returncode == 2 and "--rows" in bad.stderr
    assert run("--format", "csv", "--digits", "3").returncode == 2


def test_dir_shows_the_front_door_only():
    names = dir(forcenet)
    assert {"table", "Table", "law", "testing", "__version__"} <= set(names)
    assert not {"Any", "TYPE_CHECKING", "annotations", "version", "PackageNotFoundError", "_FRONT_DOOR"} & set(names)


def test_plots_read_as_a_paper_figure():
    import matplotlib

    matplotlib.use("Agg")
    ax = forcenet.table(10).plot()
    assert type(ax.collections[0].norm).__name__ == "LogNorm"
    ax = forcenet.law(8, (8, 4)).plot()
    assert ax.get_title() == "N = 8: $W_{8,4}$" and ax.get_legend() is not None


def test_a_rows_latex_takes_digits_too(tmp_path):
    row = forcenet.row(5, 4, moments=2)
    text = row.to_latex(digits=4)
    assert r"\toprule" in text and "$0.1818$" in text and text.splitlines()[-3].startswith("2 & $")
    assert row.to_latex().count(r"\frac") == 8
    done = subprocess.run([sys.executable, "-m", "forcenet", "table", "--N", "5", "--row", "4", "--format", "latex",
                           "--digits", "2", "--quiet"], capture_output=True, text=True, cwd=tmp_path, check=False)
    assert done.returncode == 0 and "$0.18$" in done.stdout


@pytest.mark.slow
def test_the_issues_latex_at_n_40():
    """The acceptance: ``forcenet.table(40).to_latex(digits=4)`` has no line over 600 characters (the exact one
    was 416 KB with lines of 20,009), and the JSON reads back equal."""
    t = forcenet.table(40)
    assert max(map(len, t.to_latex(digits=4).splitlines())) <= 600
    assert max(map(len, t.to_latex().splitlines())) <= 1000
    assert forcenet.Table.from_json(t.to_json()) == t
