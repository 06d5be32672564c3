"""The command line's promise: no traceback, no file left behind on failure, costs announced.

A property-based test draws argument vectors from a grammar of every
subcommand (valid, boundary and invalid values, non-ASCII digits, repeated
and contradictory options; destinations that are devices, FIFOs-free links,
dangling links, read-only files, empty names, names ending in '/'; standard
output open, closed or full); then one regression test per numbered item of
issue 15.  Issue 24's items are in ``test_cli_output.py`` and ``test_cli_values.py``.
"""

import json
import math
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from forcenet.cli import main
from forcenet.exact import count


def _files(root):
    return sorted(str(p.relative_to(root)) for p in Path(root).rglob("*"))


def run(argv, capsys):
    code = main(argv)
    out, err = capsys.readouterr()
    return code, out, err


# ------------------------------------------------------------------ the grammar

NUMBERS = st.sampled_from(["-1", "0", "1", "2", "3", "5", "nan", "inf", "-inf", "x", "", "1e400", "2.5", "1/3", "10000000000000000000000",
                          "\u0663", "\uff15", "1e300", "1e-300"])
SMALL = st.integers(min_value=-3, max_value=7).map(str)


def _opt(name, values):
    return st.one_of(st.just([]), values.map(lambda v: [name, v]))


def _req(name, values):
    """A required option: present nine times out of ten."""
    present = values.map(lambda v: [name, v])
    return st.one_of(*([present] * 9), st.just([]))


def _grammar(tmp):
    bad_paths = [str(tmp / "missing" / "x.json"), str(tmp), "/proc/forcenet-test.json", str(tmp / "afile" / "x.json"),
                 "", "newdir/", "readonly.json", "readonly.png"]
    special = ["null", "full", "link.json", "dangling.json", "link.png"]  # devices (when root), links
    paths = st.sampled_from(bad_paths + special + [str(tmp / "out.json"), str(tmp / "t.csv")])
    common_out = _opt("--out", paths)
    count = st.tuples(st.just(["count"]), _req("--N", st.one_of(SMALL, NUMBERS, st.just("1000000"))), common_out)
    table = st.tuples(
        st.just(["table"]), _req("--N", st.one_of(SMALL, NUMBERS, st.sampled_from(["201", "1000"]))),  # beyond every route
        _opt("--format", st.sampled_from(["json", "csv", "latex", "xml"])), common_out,
        _opt("--moments", st.one_of(st.sampled_from(["0", "1", "2", "51", "-1", "x"]))),
        _opt("--samples", st.sampled_from(["0", "1", "2", "-7", "50", "x"])), _opt("--seed", st.sampled_from(["-1", "0", "5", "x", "1e3"])),
        _opt("--out-dir", st.sampled_from([str(tmp / "tables"), str(tmp / "afile"), str(tmp / "afile" / "sub"), str(tmp / "missing" / "sub")])),
        _opt("--method", st.sampled_from(["auto", "fast", "thesis", "lambda", "maps", "magic"])), st.just(["--quiet"]),
    )
    maps = st.tuples(st.just(["maps"]), _req("--N", st.one_of(SMALL, NUMBERS)), _opt("--format", st.sampled_from(["text", "json", "x"])), common_out)
    limit = st.tuples(st.just(["limit"]), _req("--x", st.one_of(NUMBERS, st.sampled_from(["0.2", "-0.5", "0.5"]))),
                      _req("--z", st.one_of(NUMBERS, st.sampled_from(["0.5", "0.6", "1"]))), _opt("--dps", st.sampled_from(["4", "20", "1001", "x"])),
                      _opt("--format", st.sampled_from(["text", "json"])), common_out)
    sample = st.tuples(
        st.just(["sample"]), _req("--N", st.one_of(SMALL, st.sampled_from(["100000", "x", "nan"]))),
        _opt("--sampler", st.sampled_from(["exact", "metropolis", "gibbs"])), _opt("--samples", st.sampled_from(["-7", "0", "1", "2", "60", "x"])),
        _opt("--seed", st.sampled_from(["-1", "0", "3", "x"])), _opt("--F", st.one_of(NUMBERS, st.just("2"))),
        _opt("--ph", st.sampled_from(["-1", "0", "1", "nan"])), _opt("--P", st.sampled_from(["1", "3", "x"])),
        _opt("--mg", st.sampled_from(["-1", "1", "inf"])), _opt("--j0", st.sampled_from(["0", "2", "9"])),
        st.sampled_from([[], ["--response"]]), _opt("--format", st.sampled_from(["text", "json"])), common_out, st.just(["--quiet"]),
    )
    transfer = st.tuples(st.just(["transfer"]), _req("--L", st.sampled_from(["1", "2", "5", "14", "x"])),
                         _opt("--particles", st.sampled_from(["-1", "0", "3", "9"])), _opt("--format", st.sampled_from(["text", "json"])), common_out)
    bethe = st.tuples(st.just(["bethe"]), _req("--L", st.sampled_from(["2", "6", "9", "5000", "x"])), _opt("--n", st.sampled_from(["2", "4", "0"])),
                      _opt("--m", st.sampled_from(["1", "2", "5"])), _opt("--format", st.sampled_from(["text", "json"])), st.just(["--quiet"]))
    entropy = st.tuples(
        st.just(["entropy"]),
        st.one_of(_req("--phi", st.one_of(NUMBERS, st.sampled_from(["0.3", "1.5707963267948966", "-1.5707963267948966", "2"]))),
                  _req("--Q", st.sampled_from(["1/6", "0", "1/3", "1/2", "0.1", "-1", "x", "nan"])), st.sampled_from([["--max"], []])),
        _opt("--dps", st.sampled_from(["4", "5", "30", "10001", "x"])), _opt("--F", st.one_of(NUMBERS, st.just("2"))),
        _opt("--L-max", st.sampled_from(["10", "60", "x"])), _opt("--format", st.sampled_from(["text", "json"])), common_out, st.just(["--quiet"]),
    )
    dist = st.tuples(
        st.just(["dist"]), _req("--N", st.one_of(SMALL, NUMBERS, st.sampled_from(["12", "30", "31"]))),
        st.one_of(_req("--grain", st.sampled_from(["3,2", "1,1", "7,7", "2,3", "x", "3", "3,2,1", "-1,1", "4,nan"])),
                  _req("--layer", st.sampled_from(["1", "2", "5", "9", "x"])), st.just(["--ensemble"])),
        _opt("--contact", st.sampled_from(["F1", "F2", "F5", "F6", "F3"])), _opt("--grid", st.sampled_from(["0", "1", "5", "x"])),
        _opt("--format", st.sampled_from(["text", "json", "csv", "latex", "xml"])), common_out,
        _opt("--plot", st.sampled_from([str(tmp / "p.png"), str(tmp / "p.pdf"), str(tmp / "missing" / "p.png"), str(tmp / "out.json"),
                                        "readonly.png", "link.png", "full"])),
        _opt("--samples", st.sampled_from(["1", "50", "x"])), _opt("--sweeps", st.sampled_from(["0", "120"])),
        _opt("--bins", st.sampled_from(["0", "5"])), _opt("--f-max", st.sampled_from(["-1", "inf", "3"])), st.just(["--quiet"]),
    )
    command = st.one_of(count, table, maps, limit, sample, transfer, bethe, entropy, dist)
    return st.tuples(command.map(lambda parts: [token for part in parts for token in part]), st.integers(0, 9)).map(_repeat)


def _repeat(drawn):
    """One time in ten, an option given twice (refused: "--X given twice")."""
    argv, k = drawn
    options = [i for i, token in enumerate(argv) if token.startswith("--")]
    if k or not options:
        return argv
    i = options[0]
    end = i + 2 if i + 1 < len(argv) and not argv[i + 1].startswith("--") else i + 1
    return argv + argv[i:end]


def _special_files(root):
    """Device nodes (root only), links and read-only files the commands must leave as they are."""
    import stat

    made = {}
    for name, minor in (("null", 3), ("full", 7)):
        try:
            os.mknod(root / name, stat.S_IFCHR | 0o666, os.makedev(1, minor))
            made[name] = "char"
        except (PermissionError, AttributeError):
            pass
    (root / "linked").mkdir()
    (root / "linked" / "target.json").write_text("old")
    os.symlink("linked/target.json", root / "link.json")
    os.symlink("linked/target.png", root / "link.png")
    os.symlink("linked/nothing.json", root / "dangling.json")
    for name in ("readonly.json", "readonly.png"):
        (root / name).write_text("keep")
        os.chmod(root / name, 0o444)
    return made


def _kinds(root):
    """What must survive any command: device nodes, links (as links), read-only files (content and mode)."""
    import stat

    out = {}
    for name in ("null", "full", "link.json", "link.png", "dangling.json", "readonly.json", "readonly.png"):
        path = root / name
        if os.path.lexists(path):
            st = os.lstat(path)
            out[name] = (stat.S_IFMT(st.st_mode), stat.S_IMODE(st.st_mode), path.read_text() if name.startswith("readonly") else None)
    return out


@pytest.fixture
def sandbox(tmp_path, monkeypatch):
    (tmp_path / "afile").write_text("a file, not a directory")
    monkeypatch.chdir(tmp_path)
    return tmp_path


@pytest.fixture
def special_sandbox(sandbox):
    _special_files(sandbox)
    return sandbox


def _check_one(argv, root, capsys, stdout="open", full_stream=None):
    before, kinds = _files(root), _kinds(root)
    real = sys.stdout
    sys.stdout = {"open": real, "closed": None, "full": full_stream}[stdout]
    try:
        code = main(argv)  # an exception escaping main() is a bug: the test fails with its traceback
    finally:
        sys.stdout = real
    out, err = capsys.readouterr()
    assert code in (0, 2), (argv, code, err)
    assert "Traceback" not in err and "Traceback" not in out, argv
    assert _kinds(root) == kinds, argv  # devices, links and read-only files untouched
    assert not [f for f in _files(root) if os.path.basename(f).startswith((".tmp-", ".bak-"))], argv
    if stdout != "open" and "--out" not in argv and "--help" not in argv and code == 0:
        raise AssertionError(f"{argv}: exit 0 with standard output {stdout}")
    if code == 2:
        assert err.startswith(("forcenet: error:", "usage:", "forcenet ")) or "error:" in err, (argv, err)
        assert len([line for line in err.splitlines() if "error" in line]) == 1, (argv, err)
        assert _files(root) == before, (argv, err)
        assert ".tmp-" not in err, err  # the user's path, never a temporary file


_STDOUT = st.sampled_from(["open"] * 8 + ["closed", "full"])


@settings(max_examples=120, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])
@given(data=st.data())
def test_every_command_line_ends_cleanly(special_sandbox, capsys, full_stream, data):
    argv = data.draw(_grammar(special_sandbox))
    _check_one(argv, special_sandbox, capsys, data.draw(_STDOUT), full_stream)


@pytest.mark.slow
@settings(max_examples=1500, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])
@given(data=st.data())
def test_every_command_line_ends_cleanly_long(special_sandbox, capsys, full_stream, data):
    argv = data.draw(_grammar(special_sandbox))
    _check_one(argv, special_sandbox, capsys, data.draw(_STDOUT), full_stream)


# ------------------------------------------------- regression tests, issue 15 items


def test_1_huge_counts_print_whole(capsys):
    code, out, err = run(["count", "--N", "90"], capsys)
    assert code == 0 and out.strip() == str(count(90)) and len(out.strip()) > 4300


def test_2_count_refuses_what_memory_cannot_hold(capsys):
    code, out, err = run(["count", "--N", "1000000"], capsys)
    assert code == 2 and "GiB of memory" in err and out == ""


def test_3_sample_refuses_what_memory_cannot_hold(capsys):
    code, _, err = run(["sample", "--N", "100000", "--samples", "2"], capsys)
    assert code == 2 and "GiB of memory" in err


@pytest.mark.parametrize("argv", [["sample", "--N", "5", "--seed", "-1"], ["sample", "--N", "5", "--sampler", "metropolis", "--seed", "-1"],
                                  ["table", "--N", "5", "--seed", "-1", "--out-dir", "sneg"]])
def test_4_negative_seed_named_and_nothing_written(argv, sandbox, capsys):
    code, _, err = run(argv, capsys)
    assert code == 2 and "seed=-1 is out of range" in err
    assert _files(sandbox) == ["afile"]


def test_5_one_sample_is_refused_before_any_file(sandbox, capsys):
    code, _, err = run(["table", "--N", "5", "--samples", "1", "--out-dir", "s1"], capsys)
    assert code == 2 and "samples=1" in err and _files(sandbox) == ["afile"]


@pytest.mark.parametrize("argv, needle", [
    (["table", "--N", "5", "--format", "json", "--out", "/proc/forcenet-test.json"], "/proc"),
    (["table", "--N", "5", "--format", "json", "--out", "."], "is a directory"),
    (["table", "--N", "5", "--out-dir", "afile"], "not a directory"),
    (["table", "--N", "5", "--out-dir", "afile/sub"], "does not exist or is not a directory"),
    (["table", "--N", "5", "--format", "json", "--out", "afile/x.json"], "does not exist"),
    (["table", "--N", "5", "--format", "json", "--out", "missing/dir/x.json"], "does not exist"),
])
def test_6_file_system_errors_are_one_line(argv, needle, sandbox, capsys):
    code, _, err = run(argv, capsys)
    assert code == 2 and needle in err and len(err.strip().splitlines()) == 1
    assert _files(sandbox) == ["afile"]  # in particular missing/dir was not created


def test_6_permission_errors_during_the_write_leave_nothing(sandbox, capsys, monkeypatch):
    from forcenet.cli import output as common

    def denied(src, dst):
        raise PermissionError(13, "Permission denied", dst)

    monkeypatch.setattr(common.os, "replace", denied)
    code, _, err = run(["table", "--N", "5", "--samples", "0", "--out-dir", "tables"], capsys)
    assert code == 2 and "Permission denied" in err and len(err.strip().splitlines()) == 1
    assert _files(sandbox) == ["afile"]  # no temporary file, no directory


def test_6_interruption_during_the_write_leaves_nothing(sandbox, capsys, monkeypatch):
    from forcenet.cli import output as common

    calls = []

    def interrupted(src, dst):
        if calls:
            raise KeyboardInterrupt
        calls.append(dst)
        os.rename(src, dst)

    monkeypatch.setattr(common.os, "replace", interrupted)
    code, _, err = run(["table", "--N", "5", "--samples", "0", "--out-dir", "tables"], capsys)
    assert code == 130 and "interrupted" in err
    assert _files(sandbox) == ["afile"]  # the first file written was removed again, and the directory


@pytest.mark.parametrize("x", ["0.5", "-0.5"])
def test_7_lattice_directions_report_the_finite_value(x, capsys):
    code, out, _ = run(["limit", "--x", x, "--z", "0.5", "--format", "json"], capsys)
    data = json.loads(out)
    assert code == 0 and data["N_W_bulk"] is None and data["on_lattice_direction"]
    assert abs(float(data["W_lattice"]) - (1 - math.sqrt(0.75)) / 2) < 1e-15
    code, out, _ = run(["limit", "--x", x, "--z", "0.5"], capsys)
    assert "infinity" in out and "j" not in out.replace("direction", "")


def test_8_out_without_format_follows_the_extension(sandbox, capsys):
    code, out, _ = run(["table", "--N", "5", "--out", "x.json"], capsys)
    assert code == 0 and out == "" and json.loads((sandbox / "x.json").read_text())["N"] == 5
    code, _, err = run(["table", "--N", "5", "--out", "x.txt"], capsys)
    assert code == 2 and "--format" in err and not (sandbox / "x.txt").exists()


def test_9_moments_are_bounded_and_planned(capsys):
    from forcenet.exact.routes import table_plan

    code, _, err = run(["table", "--N", "12", "--moments", "100", "--format", "json"], capsys)
    assert code == 2 and "moments=100 is out of range" in err
    plan = table_plan("fast", 18, 2)
    assert 20 < plan.seconds < 120 and plan.nbytes > 2**30  # measured: 34 s, 2.9 GB


def test_10_one_force_policy(capsys):
    code, _, err = run(["table", "--N", "30", "--format", "json", "--method", "fast"], capsys)
    assert code == 2 and ("--force" in err or "GiB" in err)  # over a minute, or (on a busy machine) over memory
    code, _, err = run(["bethe", "--L", "5000"], capsys)
    assert code == 2 and "--force" in err
    code, _, err = run(["transfer", "--L", "13"], capsys)
    assert code == 2 and "--force" in err


@pytest.mark.parametrize("argv", [
    ["sample", "--N", "6", "--samples", "300", "--seed", "4", "--format", "json"],
    ["sample", "--N", "5", "--sampler", "metropolis", "--samples", "400", "--seed", "4", "--format", "json"],
    ["transfer", "--L", "6", "--format", "json"],
    ["bethe", "--L", "6", "--n", "2", "--m", "1", "--format", "json"],
    ["entropy", "--phi", "0.3", "--format", "json"],
])
def test_11_identical_runs_give_identical_bytes(argv):
    outs = [subprocess.run([sys.executable, "-m", "forcenet", *argv], capture_output=True, text=True, check=False).stdout
            for _ in range(2)]
    assert outs[0] == outs[1] and outs[0]
    assert "seconds" not in json.loads(outs[0])


def test_12_consistent_messages(capsys):
    for value in ("0", "-7", "1"):
        code, _, err = run(["sample", "--N", "5", "--samples", value], capsys)
        assert code == 2 and "samples must be an integer >= 2" in err
    code, _, err = run(["entropy", "--phi", "0.3", "--F", "inf"], capsys)
    assert code == 2 and "F=inf is out of range" in err
    code, _, err = run(["sample", "--N", "5", "--F", "inf"], capsys)
    assert code == 2 and "F=inf is out of range" in err


def test_13_every_documented_command_states_its_cost():
    # the examples with their costs are on the site's command-line page (the README links to it), rendered from the
    # performance page's data file (docs/_data/performance.json) by the docs' own extension
    import runpy

    docs = Path(__file__).resolve().parents[1] / "docs"
    assert ".. forcenet-command-costs::" in (docs / "command_line.rst").read_text()
    extension = runpy.run_path(str(docs / "_ext" / "performance_data.py"))
    lines = extension["command_cost_lines"](json.loads((docs / "_data" / "performance.json").read_text()))
    assert len(lines) >= 30
    for line in lines:
        assert re.search(r"(\d+(\.\d+)?\s*(s|min|h)\b|instant)", line.split("#", 1)[-1]), f"no cost stated: {line}"


def test_14_the_cross_check_has_a_stated_false_alarm_rate(sandbox, capsys, monkeypatch):
    code, out, _ = run(["table", "--N", "6", "--samples", "4000", "--seed", "2006", "--out-dir", "t"], capsys)
    assert code == 0 and "fails this check at most 0.10% of the time" in out  # in plain words (issue 53)
    code, out, _ = run(["table", "--N", "6", "--samples", "4000", "--seed", "2006", "--out-dir", "t", "--verbose"],
                       capsys)
    assert code == 0 and "Hotelling chi2" in out and "Bonferroni p" in out and "fails at most" in out
    # a wrong table is caught
    from fractions import Fraction

    from forcenet import front_door
    from forcenet.exact import routes

    real_run = routes.run_request

    def biased(request, choice, progress=None):
        tables = real_run(request, choice, progress)
        tables[1][request.N - 1][0] += Fraction(1, 50)
        tables[1][request.N - 1][1] -= Fraction(1, 50)
        return tables

    monkeypatch.setattr(front_door, "run_request", biased)  # the name the front door runs
    code, out, _ = run(["table", "--N", "6", "--samples", "4000", "--seed", "2006", "--out-dir", "t2"], capsys)
    assert code == 3 and "DISAGREES" in out  # 3: DISAGREES, never confused with a bug (1)
