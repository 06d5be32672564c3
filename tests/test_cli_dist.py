"""``forcenet dist``: formats, --grid, --plot, and bad input (exit 2, nothing written)."""

import json
from fractions import Fraction
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from forcenet.cli import main
from forcenet.exact.triangle import distribution as D
from forcenet.exact.triangle.gaps import grain_gap_counts


def run(argv, capsys):
    code = main(argv)
    out, err = capsys.readouterr()
    return code, out, err


def _files(root):
    return sorted(str(p.relative_to(root)) for p in Path(root).rglob("*"))


@pytest.fixture
def sandbox(tmp_path, monkeypatch):
    (tmp_path / "afile").write_text("a file, not a directory")
    monkeypatch.chdir(tmp_path)
    return tmp_path


def test_json_carries_the_exact_coefficients(capsys):
    code, out, _ = run(["dist", "--N", "12", "--grain", "12,6", "--format", "json"], capsys)
    data = json.loads(out)
    assert code == 0 and data["N"] == 12 and data["variable"] == "w"
    (piece,) = data["pieces"]
    exact = D.density(12, (12, 6))
    assert [Fraction(c) for c in piece["density"]] == [Fraction(str(c)) for c in reversed(exact.all_coeffs())]
    assert [Fraction(c) for c in piece["cdf"]] == [Fraction(str(c)) for c in reversed(D.cdf(12, (12, 6)).all_coeffs())]
    assert Fraction(data["mean"]) == D.moment_from_gaps(grain_gap_counts(12, (12, 6)), 1)
    assert "seconds" not in out


def test_grid_values_are_the_exact_values_rounded(capsys):
    code, out, _ = run(["dist", "--N", "6", "--grain", "4,2", "--format", "json", "--grid", "8"], capsys)
    grid = json.loads(out)["grid"]
    p, F = D.density(6, (4, 2)), D.cdf(6, (4, 2))
    assert code == 0 and len(grid) == 9 and grid[-1]["cdf"] == 1.0
    for row in grid:
        x = Fraction(row["w"])
        assert row["density"] == float(p.eval(x)) and row["cdf"] == float(F.eval(x))


def test_csv_latex_text_and_contacts(capsys):
    code, out, _ = run(["dist", "--N", "5", "--grain", "5,2", "--format", "csv"], capsys)
    lines = out.strip().splitlines()
    assert code == 0 and lines[0] == "lo,hi,power,density,cdf" and len(lines) == 1 + 11  # degree d = 10 CDF
    code, out, _ = run(["dist", "--N", "5", "--grain", "5,2", "--format", "csv", "--grid", "4"], capsys)
    assert code == 0 and out.splitlines()[0] == "w,density,cdf" and len(out.splitlines()) == 6
    code, out, _ = run(["dist", "--N", "4", "--grain", "4,2", "--format", "latex"], capsys)
    assert code == 0 and r"\begin{align*}" in out and "15 w" in out
    code, out, _ = run(["dist", "--N", "6", "--ensemble", "--format", "latex"], capsys)
    assert code == 0 and r"\begin{cases}" in out
    code, out, _ = run(["dist", "--N", "6", "--grain", "3,2", "--contact", "F1", "--format", "json"], capsys)
    data = json.loads(out)
    assert code == 0 and "F1" in data["quantity"]
    assert [Fraction(c) for c in data["pieces"][0]["density"]] == [
        Fraction(str(c)) for c in reversed(D.contact_density(6, (2, 1), "F6").all_coeffs())]
    code, out, _ = run(["dist", "--N", "7", "--layer", "7"], capsys)
    assert code == 0 and "degree 19" in out and "density at f = 0: 6/7" in out  # P_N(0) = (N-1)/N


def test_ensemble_pieces_integrate_to_one(capsys):
    code, out, _ = run(["dist", "--N", "6", "--ensemble", "--format", "json"], capsys)
    pieces = json.loads(out)["pieces"]
    assert code == 0 and [p["hi"] for p in pieces] == ["2", "3", "4", "5", "6"]
    last = pieces[-1]
    assert sum(Fraction(c) * 6**m for m, c in enumerate(last["cdf"])) == 1


def test_plot_writes_a_png_and_the_output(sandbox, capsys):
    code, out, err = run(["dist", "--N", "6", "--ensemble", "--plot", "p.png", "--samples", "400", "--sweeps", "400",
                          "--bins", "10", "--format", "json", "--out", "p.json"], capsys)
    assert code == 0, err
    assert (sandbox / "p.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert json.loads((sandbox / "p.json").read_text())["N"] == 6
    assert "chi2" in err and out == ""
    assert _files(sandbox) == ["afile", "p.json", "p.png"]  # no temporary file left


@pytest.mark.parametrize("argv, needle", [
    (["dist", "--N", "12", "--grain", "13,6"], "grain=(13, 6) is out of range"),
    (["dist", "--N", "12", "--grain", "x"], "grain"),
    (["dist", "--N", "12", "--grain", "1,1"], "overload"),
    (["dist", "--N", "12", "--grain", "12,1", "--contact", "F5"], "floor"),
    (["dist", "--N", "12", "--contact", "F5", "--ensemble"], "--contact needs --grain"),
    (["dist", "--N", "12", "--layer", "13"], "layer=13 is out of range"),
    (["dist", "--N", "12", "--layer", "1"], "layer=1 is out of range"),
    (["dist", "--N", "129", "--ensemble"], "N=129 is out of range"),
    (["dist", "--N", "31", "--grain", "30,15", "--contact", "F5"], "N=31 is out of range"),
    (["dist", "--N", "12"], "one of the arguments"),
    (["dist", "--N", "12", "--grain", "3,2", "--layer", "3"], "not allowed with"),
    (["dist", "--N", "6", "--grain", "3,2", "--plot", "x.png"], "--ensemble or --layer"),
    (["dist", "--N", "6", "--ensemble", "--plot", "x.pdf"], ".png"),
    (["dist", "--N", "6", "--ensemble", "--plot", "missing/x.png"], "does not exist"),
    (["dist", "--N", "6", "--ensemble", "--plot", "afile/x.png"], "does not exist"),
    (["dist", "--N", "6", "--ensemble", "--plot", "x.png", "--out", "x.png"], "same file"),
    (["dist", "--N", "6", "--ensemble", "--samples", "100"], "--plot"),
    (["dist", "--N", "6", "--ensemble", "--plot", "x.png", "--samples", "1"], "samples=1 is out of range"),
    (["dist", "--N", "6", "--ensemble", "--plot", "x.png", "--f-max", "nan"], "f-max=nan"),
    (["dist", "--N", "6", "--grain", "3,2", "--grid", "0"], "grid=0 is out of range"),
    (["dist", "--N", "6", "--grain", "3,2", "--out", "missing/x.json"], "does not exist"),
    (["dist", "--N", "24", "--ensemble"], "--force"),
])
def test_bad_input_is_one_line_and_writes_nothing(argv, needle, sandbox, capsys):
    code, out, err = run(argv, capsys)
    assert code == 2 and needle in err and len(err.strip().splitlines()) == 1, err
    assert out == "" and _files(sandbox) == ["afile"]


def test_a_failed_write_leaves_neither_file(sandbox, capsys, monkeypatch):
    from forcenet.cli import output as common

    calls = []

    def second_fails(src, dst):
        if calls:
            raise PermissionError(13, "Permission denied", dst)
        calls.append(dst)
        import os

        os.rename(src, dst)

    monkeypatch.setattr(common.os, "replace", second_fails)
    code, _, err = run(["dist", "--N", "5", "--ensemble", "--plot", "p.png", "--samples", "200", "--sweeps", "300",
                        "--format", "json", "--out", "p.json", "--quiet"], capsys)
    assert code == 2 and "Permission denied" in err
    assert _files(sandbox) == ["afile"]


def test_a_short_metropolis_chain_is_flagged_not_hidden(sandbox, capsys):
    code, _, err = run(["dist", "--N", "6", "--ensemble", "--plot", "p.png", "--samples", "200", "--sweeps", "20",
                        "--bins", "8"], capsys)
    assert code == 0 and "error bars unreliable" in err and (sandbox / "p.png").exists()


@settings(max_examples=25, deadline=None)
@given(b=st.lists(st.integers(min_value=-10**40, max_value=10**40) | st.just(0), min_size=1, max_size=40))
def test_bernstein_to_monomial_equals_the_binomial_expansion(b):
    """The Taylor-shift conversion (FLINT) against the literal expansion of sum_k b_k w^k (1-w)^(n-k)."""
    from math import comb

    from forcenet.exact.triangle.pieces import bernstein_to_monomial

    n = len(b) - 1
    literal = [0] * (n + 1)
    for k, x in enumerate(b):
        for t in range(n - k + 1):
            literal[k + t] += x * comb(n - k, t) * (-1) ** t
    assert bernstein_to_monomial(b) == literal
