"""The command line contract of the exact core."""

import json
import os
import subprocess
import sys
from fractions import Fraction

import pytest

from forcenet.cli import main
from forcenet.exact import count, count_by_hooks, mean_W, moment_table, normalization
from forcenet.exact.packing.mobilized import mean_W_mobilized


def _assert_within_5_sigma(data, exact):
    """Every sampled mean of a `forcenet sample` JSON within 5 of its standard errors of the exact table."""
    for i, row in enumerate(exact):
        for j, value in enumerate(row):
            err = data["stderr_W"][i][j]
            if err > 0:
                assert abs(data["mean_W"][i][j] - float(value)) < 5 * err

def run(argv, capsys):
    code = main(argv)
    out, err = capsys.readouterr()
    return code, out, err


def test_count_prints_one_integer(capsys):
    code, out, _ = run(["count", "--N", "40"], capsys)
    assert code == 0
    assert out.strip() == str(count_by_hooks(40))


def test_table_json_schema_and_values(capsys):
    code, out, _ = run(["table", "--N", "7", "--format", "json"], capsys)
    assert code == 0
    data = json.loads(out)
    assert set(data) == {"N", "count", "normalization", "mean_W"}
    assert data["N"] == 7 and int(data["count"]) == count(7)
    assert Fraction(data["normalization"]) == normalization(7)
    assert [len(r) for r in data["mean_W"]] == list(range(1, 8))
    assert [[Fraction(x) for x in r] for r in data["mean_W"]] == mean_W(7)
    assert data["mean_W"][0] == ["1"]


def test_table_json_with_second_moments(capsys):
    code, out, _ = run(["table", "--N", "5", "--format", "json", "--moments", "2"], capsys)
    data = json.loads(out)
    assert [[Fraction(x) for x in r] for r in data["mean_W2"]] == moment_table(5, 2)


def test_csv_and_latex(tmp_path, capsys):
    target = tmp_path / "t.csv"
    code, out, _ = run(["table", "--N", "4", "--format", "csv", "--out", str(target)], capsys)
    assert code == 0 and out == ""
    lines = target.read_text().splitlines()
    assert lines[0] == "i,j,mean_W" and len(lines) == 1 + 10
    assert lines[-1] == "4,4," + str(mean_W(4)[3][3])
    assert os.listdir(tmp_path) == ["t.csv"]  # no temporary file left behind
    code, out, _ = run(["table", "--N", "4", "--format", "latex"], capsys)
    assert r"\begin{tabular}" in out and r"\frac{1}{7}" in out


@pytest.mark.parametrize(
    "argv, needle",
    [
        (["table", "--N", "1"], "N=1 is out of range"),
        (["table", "--N", "x"], "N='x' is not an integer"),
        (["count", "--N", "0"], "N must be an integer >= 2"),
        (["table", "--N", "45", "--format", "json", "--method", "fast"], "N=45 is out of range"),
        (["table", "--N", "201", "--format", "json"], "N=201 is out of range for --method pfaffian"),
        (["table", "--N", "36", "--format", "json", "--method", "fast"], "N must be an integer in 2.."),
        (["table", "--N", "5", "--moments", "0"], "moments=0 is out of range"),
    ],
)
def test_bad_input_is_one_line_exit_2(argv, needle, tmp_path):
    out_file = tmp_path / "never.json"
    proc = subprocess.run(
        [sys.executable, "-m", "forcenet", *argv, "--out", str(out_file)] if argv[0] == "table" else [sys.executable, "-m", "forcenet", *argv],
        capture_output=True,
        text=True,
        check=False,
    )
    assert proc.returncode == 2
    assert needle in proc.stderr
    assert len(proc.stderr.strip().splitlines()) == 1
    assert "Traceback" not in proc.stderr
    assert not out_file.exists()


def test_main_job_writes_three_files_and_cross_checks(tmp_path, capsys):
    code, out, _ = run(["table", "--N", "6", "--out-dir", str(tmp_path), "--samples", "4000", "--seed", "7"], capsys)
    assert code == 0
    assert sorted(os.listdir(tmp_path)) == ["mean_W_N6.csv", "mean_W_N6.json", "mean_W_N6.tex"]
    data = json.loads((tmp_path / "mean_W_N6.json").read_text())
    assert [[Fraction(x) for x in r] for r in data["mean_W"]] == mean_W(6)
    assert "413/2288" in out  # <W_{6,2}>, Ostojic (2006)
    assert "agrees with the exact values" in out and "Hotelling" not in out  # plain words; --verbose: the details
    code, out, _ = run(["table", "--N", "6", "--out-dir", str(tmp_path), "--samples", "4000", "--seed", "7",
                        "--verbose"], capsys)
    assert code == 0 and "agrees at level 0.001" in out and "Hotelling" in out


def test_interrupted_write_leaves_nothing(tmp_path, monkeypatch):
    from forcenet.exact.triangle import tables

    def interrupted(src, dst):
        raise KeyboardInterrupt

    monkeypatch.setattr(tables.os, "replace", interrupted)
    with pytest.raises(KeyboardInterrupt):
        tables.write_atomic(tmp_path / "table.json", "{}")
    assert os.listdir(tmp_path) == []


def test_maps_command(capsys):
    from forcenet.exact.thesis import lambda_table

    code, out, _ = run(["maps", "--N", "6", "--format", "json"], capsys)
    data = json.loads(out)
    assert int(data["Z"]) == count(6)
    assert {tuple(r["bottom_row"]): int(r["maps"]) for r in data["by_bottom_row"]} == lambda_table(4)
    code, out, _ = run(["maps", "--N", "5"], capsys)
    assert out.startswith("Z_3 = 12")
    assert main(["maps", "--N", "11"]) == 2


def test_sample_command_json(capsys):
    code, out, _ = run(["sample", "--N", "5", "--samples", "3000", "--seed", "3", "--format", "json"], capsys)
    data = json.loads(out)
    assert data["sampler"] == "exact" and data["samples"] == 3000
    _assert_within_5_sigma(data, mean_W(5))
    code, out, _ = run(["sample", "--N", "5", "--sampler", "metropolis", "--samples", "2000", "--format", "json"], capsys)
    data = json.loads(out)
    assert data["sampler"] == "metropolis" and 0 < data["acceptance"] <= 1 and data["tau_max"] >= 1


def test_sample_refuses_short_chains_and_bad_options(capsys):
    assert main(["sample", "--N", "6", "--sampler", "metropolis", "--samples", "50"]) == 2
    assert "too short" in capsys.readouterr().err
    assert main(["sample", "--N", "6", "--samples", "1"]) == 2
    assert main(["sample", "--N", "6", "--ph", "0.5"]) == 2


@pytest.mark.parametrize("method, N", [("thesis", 7), ("maps", 6), ("lambda", 8), ("lambda", 10)])
def test_table_methods_print_the_same_json(method, N, capsys):
    code, out, _ = run(["table", "--N", str(N), "--format", "json", "--method", method], capsys)
    assert code == 0
    other = json.loads(out)
    code, out, _ = run(["table", "--N", str(N), "--format", "json"], capsys)
    assert json.loads(out) == other


@pytest.mark.parametrize("method", ["thesis", "maps"])
def test_table_methods_with_higher_moments(method, capsys):
    # <W^2>, <W^3> by the nested integration (s-th order defects) or by map counting
    # (tableau bijection) equal the fast method's
    code, out, _ = run(["table", "--N", "6", "--format", "json", "--method", method, "--moments", "3"], capsys)
    assert code == 0
    other = json.loads(out)
    code, out, _ = run(["table", "--N", "6", "--format", "json", "--moments", "3"], capsys)
    assert json.loads(out) == other and "mean_W3" in other


@pytest.mark.parametrize(
    "argv, needle",
    [
        (["--N", "9", "--method", "thesis"], "--force"),
        (["--N", "8", "--method", "thesis", "--moments", "4"], "moments=4 is out of range"),
        (["--N", "10", "--method", "thesis", "--force"], "N=10 is out of range"),
        (["--N", "8", "--method", "maps"], "--force"),
        (["--N", "9", "--method", "maps"], "days"),
        (["--N", "10", "--method", "maps", "--force"], "N=10 is out of range"),
        (["--N", "11", "--method", "lambda"], "--force"),
        (["--N", "13", "--method", "lambda", "--force"], "N=13 is out of range"),
    ],
)
def test_table_methods_refuse_beyond_reach(argv, needle, capsys):
    assert main(["table", *argv, "--format", "json"]) == 2
    assert needle in capsys.readouterr().err


def test_sample_packing_scenes(capsys):
    args = ["sample", "--N", "3", "--P", "5", "--mg", "1", "--F", "20", "--sampler", "metropolis"]
    code, out, _ = run(args + ["--samples", "3000", "--seed", "2", "--format", "json", "--response"], capsys)
    data = json.loads(out)
    assert data["scene"] == "gravity" and data["P"] == 5 and data["j0"] == 3
    assert len(data["mean_W"]) == 3 and all(len(row) == 5 for row in data["mean_W"])
    exact = mean_W_mobilized(3, 5, F=20, j0=3, mg=1)
    for i in range(3):
        assert abs(sum(data["mean_W"][i]) - float(sum(exact[i]))) < 1e-9  # load conservation
        assert abs(sum(data["G"][i]) - 1) < 1e-9
        for j in range(5):
            err = data["stderr_W"][i][j]
            assert abs(data["mean_W"][i][j] - float(exact[i][j])) <= 5 * err + 1e-9
    assert main(["sample", "--N", "4", "--mg", "1"]) == 2
    assert "--P" in capsys.readouterr().err
    assert main(["sample", "--N", "4", "--P", "5", "--mg", "1"]) == 2  # exact sampler: triangle only
    assert main(["sample", "--N", "6", "--P", "9", "--pv", "1", "--ph", "1", "--F", "10", "--sampler", "metropolis"]) == 2
    assert "no force network" in capsys.readouterr().err


def test_transfer_command(capsys):
    import math

    code, out, _ = run(["transfer", "--L", "7", "--format", "json"], capsys)
    data = json.loads(out)
    assert data["L"] == 7 and len(data["sectors"]) == 8
    two = [r for r in data["sectors"] if r["particles"] == 2][0]
    assert abs(two["lambda"] - 2 * math.cos(math.pi / 7)) < 1e-11
    assert data["bulk"]["entropy_per_site"] == max(r["entropy_per_site"] for r in data["sectors"][1:])
    assert main(["transfer", "--L", "1"]) == 2
    assert main(["transfer", "--L", "5", "--particles", "9"]) == 2


@pytest.mark.slow  # ~12 s; the numbers are tests/test_bethe.py's, the command's run test_cli_contract's (L = 6)
def test_bethe_command(capsys):
    code, out, _ = run(["bethe", "--L", "9", "--n", "4", "--m", "2", "--format", "json"], capsys)
    data = json.loads(out)
    code2, out2, _ = run(["transfer", "--L", "9", "--particles", "4", "--format", "json"], capsys)
    assert abs(data["eigenvalue"] - json.loads(out2)["lambda_max"]) < 1e-12
    assert len(data["u"]) == 2 and len(data["w"]) == 4
    assert main(["bethe", "--L", "6", "--n", "2", "--m", "2"]) == 2


def test_entropy_command_closed_forms(capsys):
    import mpmath

    from forcenet.numeric.chicken_wire.isotropic import density_Q, entropy_per_grain

    code, out, _ = run(["entropy", "--phi", "0.25", "--dps", "50", "--format", "json", "--F", "3"], capsys)
    assert code == 0
    data = json.loads(out)
    with mpmath.workdps(60):
        assert abs(mpmath.mpf(data["Q"]) - density_Q("0.25", 55)) < mpmath.mpf(10) ** -48
        assert abs(mpmath.mpf(data["g_per_grain_7_4"]) - entropy_per_grain(3, 55)) < mpmath.mpf(10) ** -48
    assert len(data["Q"].replace("0.", "", 1)) >= 45  # 50 significant digits asked for
    assert "v_bethe" not in data


@pytest.mark.slow  # two Bethe-ansatz runs, ~30 s; the errors are also drawn by tests/test_cli_contract.py
def test_entropy_command_bethe_and_errors(capsys):
    from forcenet.numeric.chicken_wire.bethe import isotropic_sequence

    code, out, _ = run(["entropy", "--Q", "1/6", "--bethe", "--L-max", "60", "--quiet", "--format", "json"], capsys)
    assert code == 0
    data = json.loads(out)
    pts = isotropic_sequence(range(4, 11), ratio=(6, 2, 1))  # L = 24..60, as the command uses
    assert abs(data["v_bethe"] - pts[-1].entropy_per_site) < 20 * data["v_bethe_error"] + abs(
        pts[-1].entropy_per_site - pts[-2].entropy_per_site
    ) * 10  # the extrapolation moves the last width's value by less than a few widths' spread
    assert main(["entropy", "--phi", "2"]) == 2
    assert main(["entropy", "--phi", "0.1", "--dps", "3"]) == 2
    assert main(["entropy", "--Q", "1/6", "--L-max", "10"]) == 2
    assert main(["entropy", "--Q", "1/2"]) == 2
    assert main(["entropy"]) == 2


@pytest.mark.parametrize("sampler", ["exact", "metropolis"])
def test_sample_workers_are_reproducible(sampler, capsys):
    argv = ["sample", "--N", "5", "--sampler", sampler, "--samples", "3000", "--seed", "4", "--format", "json",
            "--workers", "2", "--quiet"]
    code, first, _ = run(argv, capsys)
    code, second, _ = run(argv, capsys)
    assert code == 0 and first == second  # identical bytes for a given seed and number of workers
    data = json.loads(first)
    assert data["workers"] == 2 and "seconds" not in data
    assert 0 < data["effective_samples"] <= 3000
    _assert_within_5_sigma(data, mean_W(5))
    code, one, _ = run(argv[:-3] + ["--quiet"], capsys)
    assert json.loads(one)["workers"] == 1 and one != first


def test_sample_timing_is_opt_in(capsys):
    code, out, err = run(["sample", "--N", "5", "--samples", "500", "--format", "json", "--timing"], capsys)
    data = json.loads(out)
    assert data["seconds"] > 0 and data["effective_samples_per_second"] > 0
    assert "effective samples in" in err
    assert main(["sample", "--N", "5", "--samples", "3", "--workers", "4"]) == 2
    assert "--workers=4" in capsys.readouterr().err
    assert main(["sample", "--N", "5", "--workers", "0"]) == 2


def test_sample_packing_response_with_workers(capsys):
    args = ["sample", "--N", "3", "--P", "5", "--mg", "1", "--F", "20", "--sampler", "metropolis", "--response",
            "--samples", "3000", "--seed", "2", "--format", "json", "--workers", "2", "--quiet"]
    code, out, _ = run(args, capsys)
    data = json.loads(out)
    for i in range(3):
        assert abs(sum(data["G"][i]) - 1) < 1e-9
    exact = mean_W_mobilized(3, 5, F=20, j0=3, mg=1)
    for i in range(3):
        for j in range(5):
            assert abs(data["mean_W"][i][j] - float(exact[i][j])) <= 5 * data["stderr_W"][i][j] + 1e-9


def test_sample_slice_move(capsys):
    argv = ["sample", "--N", "6", "--sampler", "metropolis", "--move", "slice", "--samples", "4000", "--seed", "1",
            "--format", "json", "--quiet"]
    code, out, _ = run(argv, capsys)
    data = json.loads(out)
    assert code == 0 and data["move"] == "slice" and data["acceptance"] == 1.0
    _assert_within_5_sigma(data, mean_W(6))
    assert main(["sample", "--N", "6", "--move", "slice"]) == 2  # exact sampler: no move to choose


@pytest.mark.parametrize("argv, needed", [
    (["entropy", "--phi", "0.3", "--bethe", "--L-max", "60"], "at least 80"),  # any bracketing a <= 16 may come
    (["entropy", "--Q", "1/60", "--bethe"], "at least 300"),  # k = 2..5 widths of 60
])
def test_bethe_widths_are_refused_by_the_plan_before_any_work(argv, needed, capsys):
    """The plan counts the widths of every density the Bethe route will solve: a too small --L-max is refused
    in one line naming the L_max that works, before the closed forms run (it used to fail after them)."""
    from forcenet.numeric.chicken_wire import isotropic_bethe

    code = main(argv)
    _, err = capsys.readouterr()
    assert code == 2 and needed in err and "L_max=" in err and "closed forms" not in err
    L = int(needed.split()[-1])  # the L_max named is the smallest that works
    Q = Fraction(1, 60) if "1/60" in argv else None
    assert isotropic_bethe.isotropic_entropy_plan(Q, L).runnable
    assert not isotropic_bethe.isotropic_entropy_plan(Q, L - 1).runnable
