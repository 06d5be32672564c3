"""Issue 24, items 3, 5 (the limit) and 6: documented values answered, no traceback, never a nan."""

import json
import math
from fractions import Fraction

import mpmath
import pytest

from forcenet.cli import main
from forcenet.exact.chicken_wire.closed_form import EPS, entropy_series_eps


def run(argv, capsys):
    code = main(argv)
    out, err = capsys.readouterr()
    return code, out, err


# ------------------------------------------------------------------ item 3: entropy at the ends of its domain


def test_3_Q_one_third_is_the_documented_end_point(capsys):
    code, out, err = run(["entropy", "--Q", "1/3", "--format", "json", "--dps", "30"], capsys)
    data = json.loads(out)
    assert code == 0 and err == ""
    assert mpmath.mpf(data["v_per_site"]) == 0 and data["phi"].startswith("-1.5707963267948966192")
    assert mpmath.mpf(data["eps"]) == mpmath.mpf(mpmath.nstr(mpmath.pi, 30))
    assert "mu" not in data  # mu diverges at the ends
    # the leading term of (7.3) at eps = pi, from the exact series (an independent evaluation), flagged as invalid
    with mpmath.workdps(40):
        assert abs(mpmath.mpf(data["v_series_7_3"]) - sympy_value()) < mpmath.mpf(10) ** -28
    assert mpmath.mpf(data["v_series_7_3"]) < 0 and "NOT VALID" in data["v_series_7_3_note"]


def sympy_value():
    import sympy

    return mpmath.mpf(str(sympy.N(entropy_series_eps(2).subs(EPS, sympy.pi), 45)))


@pytest.mark.parametrize("phi, valid", [("1.57", True), ("1.5", False), ("0.3", False), ("-1.5707963267948966", False)])
def test_3_the_series_says_where_it_is_no_approximation(phi, valid, capsys):
    code, out, _ = run(["entropy", "--phi", phi, "--dps", "20"], capsys)
    lines = out.splitlines()  # a value's note continues on the lines indented below it (80 columns)
    start = next(k for k, line in enumerate(lines) if line.startswith("v_series_7_3"))
    end = next((k for k in range(start + 1, len(lines)) if not lines[k].startswith(" ")), len(lines))
    line = " ".join(lines[start:end])
    v = mpmath.mpf(next(line for line in out.splitlines() if line.startswith("v_per_site")).split("=")[1].split()[0])
    s = mpmath.mpf(line.split("=")[1].split()[0])
    assert code == 0 and ("NOT VALID" not in line) == valid == (abs(s - v) <= v / 100)


def test_3_the_stated_phi_range_is_the_real_one(capsys):
    inside = "-1.5707963267948966"  # pi/2 = 1.57079632679489661923...
    code, out, _ = run(["entropy", "--phi", inside, "--dps", "10"], capsys)
    assert code == 0
    for outside in ("-1.5707963267948967", "1.570796326794896619231321691639751442098584699688"):
        code, _, err = run(["entropy", "--phi", outside], capsys)
        assert code == 2 and f"phi={outside} is out of range: phi must lie in [-pi/2, pi/2]" in err
        assert "1e-12" not in err and "1.5707963267958966" not in err  # no padded bound


# ------------------------------------------------------------------ item 5: the limit at tiny depth


@pytest.mark.parametrize("z", ["1e-30", "1e-100", "1e-300"])
def test_5_tiny_depth_has_the_diffusive_answer(z, capsys):
    code, out, err = run(["limit", "--x", "0", "--z", z, "--format", "json", "--dps", "15"], capsys)
    data = json.loads(out)
    assert code == 0 and "Traceback" not in err
    # near the apex the load spreads diffusively: N <W> -> pi / (2 sqrt(2 z)) (1 + O(z)), a second route
    with mpmath.workdps(40):
        expected = mpmath.pi / (2 * mpmath.sqrt(2 * mpmath.mpf(z)))
        assert abs(mpmath.mpf(data["N_W_bulk"]) / expected - 1) < mpmath.mpf(10) ** -13
        lattice = (1 - mpmath.sqrt(mpmath.mpf(z) * (2 - mpmath.mpf(z)))) / 2
        assert abs(mpmath.mpf(data["W_lattice"]) - lattice) < mpmath.mpf(10) ** -15


# ------------------------------------------------------------------ item 6: huge and tiny loads


def test_6_the_triangle_scales_with_any_finite_F(capsys):
    base = ["sample", "--N", "5", "--sampler", "metropolis", "--samples", "1500", "--seed", "3", "--format", "json", "--quiet"]
    code, out, _ = run(base, capsys)
    one = json.loads(out)
    for F in ("1e300", "1e-300"):
        code, out, err = run(base + ["--F", F], capsys)
        data = json.loads(out)
        assert code == 0 and "nan" not in out and "Warning" not in err
        f = float(F)
        for key in ("mean_W", "stderr_W", "std_W"):
            for row, row1 in zip(data[key], one[key]):
                assert all(math.isclose(a, b * f, rel_tol=1e-12) for a, b in zip(row, row1))
        assert data["effective_samples"] == one["effective_samples"]


def test_6_the_text_summary_stays_readable_at_any_F(capsys):
    """At F = 1e300 the bottom row is printed in significant digits, not as 300-digit fixed-point numbers."""
    base = ["sample", "--N", "5", "--sampler", "metropolis", "--samples", "1500", "--seed", "3", "--quiet"]
    for F, marker in (("1e300", "e+"), ("1e-300", "e-"), ("1", ".")):
        code, out, _ = run(base + ["--F", F], capsys)
        row = out.split("bottom row <W_N,j>:", 1)[1].split()  # the row wraps at 80 columns (issue 53)
        assert code == 0 and len(row) == 5 and all(marker in cell and len(cell) < 25 for cell in row), row


@pytest.mark.parametrize("argv, needle", [
    (["--P", "3", "--mg", "1e300"], "mg=1e+300 is out of range: with --P the loads"),
    (["--P", "3", "--mg", "1", "--F", "1e-300"], "F=1e-300 is out of range"),
    (["--ph", "1e300", "--F", "1e-10"], "the ratio ph/F must lie in"),
])
def test_6_loads_that_overflow_are_refused_before_the_run(argv, needle, capsys):
    code, out, err = run(["sample", "--N", "4", "--sampler", "metropolis", "--samples", "100"] + argv, capsys)
    assert code == 2 and needle in err and out == "" and len(err.splitlines()) == 1


def test_6_a_nan_result_is_refused(capsys, monkeypatch):
    from forcenet.numeric import parallel_chains

    real = parallel_chains._combine_chains

    def overflowing(parts):
        mean, stderr, extra = real(parts)
        return mean, stderr * math.nan, extra

    monkeypatch.setattr(parallel_chains, "_combine_chains", overflowing)
    code, out, err = run(["sample", "--N", "4", "--sampler", "metropolis", "--samples", "600", "--quiet"], capsys)
    assert code == 2 and "non-finite" in err and out == ""


def test_3_Q_fraction_kept_exact():
    from forcenet.cli.chicken_wire import _density

    assert _density("1/3") == Fraction(1, 3)
