"""Issue 45 item 6 (its --checkpoint, dist and Python API part) and issue 46: a hostile but fair fuzz, each case
listed with its verdict.

A case is one line of a table: the input, and what must come of it -- an exit code (2: one line on stderr, no
traceback) or, in Python, the ``forcenet.ForcenetError`` subclass whose message names the argument (or the
value computed, or the ``PrecisionWarning``).  Every case runs in this process within a bound of seconds; none
may hang, print a traceback or end in an internal error.  Device nodes are made with ``os.mknod`` in a
temporary folder (never ``/dev``); a full file system is simulated by making the checkpoint writer fail with
``ENOSPC`` (mounting a small file system needs root-only mounts).
"""

from __future__ import annotations

import errno
import os
import stat
import subprocess
import sys
import time
import warnings
from fractions import Fraction

import numpy as np
import pytest

import forcenet
from forcenet.cli import main
from forcenet.core.errors import ArgumentError, ArgumentTypeError, PrecisionWarning

ROOT = os.geteuid() == 0 if hasattr(os, "geteuid") else False


@pytest.fixture
def sandbox(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    return tmp_path


def _cli(argv, capsys, bound=30.0):
    start = time.monotonic()
    code = main(argv)
    elapsed = time.monotonic() - start
    out, err = capsys.readouterr()
    assert elapsed < bound, f"{argv}: {elapsed:.1f} s"
    assert "Traceback" not in err and "internal error" not in err, err
    if code == 2:
        assert len(err.splitlines()) == 1, err
    return code, out, err


def _device(path, minor=5):
    try:
        os.mknod(path, stat.S_IFCHR | 0o666, os.makedev(1, minor))  # /dev/zero (5), /dev/null (3)
    except (PermissionError, AttributeError):
        pytest.skip("creating a device node needs CAP_MKNOD")
    return path


# ------------------------------------------------------------------- dist: grains, contacts, grids, layers, N

DIST = [
    # (argv after "dist", exit code, a piece of the one line on stderr)
    (["--N", "6", "--grain", "-1,1"], 2, "grain i=-1 is out of range"),
    (["--N", "6", "--grain", "-3,-1"], 2, "grain i=-3 is out of range"),
    (["--N", "6", "--grain", "0,0"], 2, "grain i=0 is out of range"),
    (["--N", "6", "--grain", "7,1"], 2, "grain=(7, 1) is out of range"),
    (["--N", "6", "--grain", "3,4"], 2, "grain=(3, 4) is out of range"),
    (["--N", "6", "--grain", "1,1"], 2, "W_11 = 1 is the overload"),
    (["--N", "6", "--grain", "a,b"], 2, "is not an integer"),
    (["--N", "6", "--grain", "3"], 2, "give it as i,j"),
    (["--N", "6", "--grain", "3,2,1"], 2, "give it as i,j"),
    (["--N", "6", "--grain", ""], 2, "give it as i,j"),
    (["--N", "6", "--grain", "\uff13,1"], 2, "ASCII"),
    (["--N", "6", "--grain", "99999999999999999999999,1"], 2, "is out of range"),
    (["--N", "6", "--grain", "3.0,1"], 2, "is not an integer"),
    (["--N", "6", "--grain", "6,3", "--contact", "F9"], 2, "invalid choice"),
    (["--N", "6", "--grain", "6,3", "--contact", "F5"], 2, "presses on the floor"),
    (["--N", "6", "--contact", "F5"], 2, "one of the arguments --grain --layer --ensemble is required"),
    (["--N", "6", "--layer", "4", "--contact", "F5"], 2, "--contact needs --grain"),
    (["--N", "6", "--grain", "6,3", "--grid", "0"], 2, "grid=0 is out of range"),
    (["--N", "6", "--grain", "6,3", "--grid", "-5"], 2, "grid=-5 is out of range"),
    (["--N", "6", "--grain", "6,3", "--grid", "1000000000"], 2, "grid=1000000000 is out of range"),
    (["--N", "6", "--grain", "6,3", "--grid", "1.5"], 2, "is not an integer"),
    (["--N", "6", "--grain", "6,3", "--grid", "nan"], 2, "is not an integer"),
    (["--N", "6", "--layer", "0"], 2, "layer=0 is out of range"),
    (["--N", "6", "--layer", "1"], 2, "layer=1 is out of range"),
    (["--N", "6", "--layer", "-1"], 2, "layer=-1 is out of range"),
    (["--N", "6", "--layer", "7"], 2, "layer"),
    (["--N", "6", "--layer", "3", "--grain", "3,1"], 2, "not allowed with argument"),
    (["--N", "1", "--ensemble"], 2, "N=1 is out of range"),
    (["--N", "129", "--ensemble"], 2, "N=129 is out of range"),
    (["--N", "10000000000", "--grain", "2,1"], 2, "is out of range"),
    (["--N", "128", "--ensemble"], 2, "add --force"),  # large N: refused by its plan, at once
    (["--N", "40", "--ensemble"], 2, "add --force"),
    (["--N", "6", "--ensemble", "--samples", "100"], 2, "set the sampled histograms of --plot"),
    (["--N", "6", "--ensemble", "--plot", "x.png", "--bins", "0"], 2, "bins=0 is out of range"),
    (["--N", "6", "--ensemble", "--plot", "x.png", "--f-max", "nan"], 2, "f-max=nan is out of range"),
    (["--N", "6", "--ensemble", "--plot", "x.png", "--f-max", "-1"], 2, "f-max=-1 is out of range"),
    (["--N", "6", "--ensemble", "--plot", "x.svg"], 2, "give a file name ending in .png"),
    (["--N", "6", "--grain", "6,3", "--plot", "x.png"], 2, "use it with --ensemble or --layer"),
    (["--N", "6", "--ensemble", "--plot", "no/such/dir/x.png"], 2, "--plot"),
    (["--N", "6", "--grain", "6,3", "--format", "xml"], 2, "invalid choice"),
    (["--N", "6", "--grain", "6,3", "--out", "no/such/dir/x.json", "--format", "json"], 2, "--out"),
    (["--N", "6", "--grain", "6,3", "--format", "json"], 0, ""),
    (["--N", "6", "--grain", "5,3", "--contact", "F1", "--grid", "1"], 0, ""),
    (["--N", "5", "--layer", "5", "--format", "json"], 0, ""),
]


@pytest.mark.parametrize("argv, code, piece", DIST, ids=[" ".join(a) for a, _, _ in DIST])
def test_dist(argv, code, piece, sandbox, capsys):
    got, out, err = _cli(["dist", *argv], capsys)
    assert got == code and piece in err, err
    if code == 2:
        assert out == "" and os.listdir(sandbox) == []  # no file, no directory


# -------------------------------------------------------------------------------------- dist --plot destinations

_PLOT = ["dist", "--N", "5", "--ensemble", "--samples", "200", "--sweeps", "200", "--bins", "10", "--quiet"]


def _plot_destination(kind, root):
    path = root / "p.png"
    if kind == "directory":
        path.mkdir()
    elif kind == "read-only file":
        path.write_bytes(b"old")
        path.chmod(0o444)
    elif kind == "device node":
        _device(path, 3)
    elif kind == "symlink":
        (root / "target.png").write_bytes(b"old")
        path.symlink_to("target.png")
    elif kind == "dangling symlink":
        path.symlink_to("missing/target.png")
    return path


PLOTS = [  # (the destination, exit code, a piece of stderr, what must hold of it afterwards)
    ("directory", 2, "--plot", lambda p: p.is_dir()),
    ("read-only file", 2, "read-only", lambda p: p.read_bytes() == b"old"),
    ("device node", 0, "", lambda p: stat.S_ISCHR(os.lstat(p).st_mode)),  # written in place, never replaced
    ("symlink", 0, "", lambda p: p.is_symlink() and (p.parent / "target.png").read_bytes()[:4] == b"\x89PNG"),
    ("dangling symlink", 2, "--plot", lambda p: p.is_symlink()),
]


@pytest.mark.parametrize("kind, code, piece, after", PLOTS, ids=[k for k, *_ in PLOTS])
def test_dist_plot_destinations(kind, code, piece, after, sandbox, capsys):
    path = _plot_destination(kind, sandbox)
    got, _, err = _cli([*_PLOT, "--plot", str(path)], capsys, bound=60)
    assert got == code and piece in err, err
    assert after(path)


# ------------------------------------------------------------------------------------------------- --checkpoint

_TABLE = ["table", "--N", "6", "--method", "pfaffian", "--format", "json", "--quiet"]


def _expected_table(capsys):
    code, out, _ = _cli(["table", "--N", "6", "--format", "json", "--method", "fast"], capsys)
    assert code == 0
    return out


def _records(directory):
    return sorted(os.path.join(d, f) for d, _, files in os.walk(directory) for f in files if f.endswith(".rec"))


def _prepare(kind, root, capsys):
    """The --checkpoint argument for case ``kind``; returns (argument, what stderr must mention)."""
    ck = root / "ck"
    if kind == "a file":
        ck.write_text("x")
        return str(ck), "--checkpoint"
    if kind == "missing parent":
        return str(root / "no" / "such"), "--checkpoint"
    if kind == "empty name":
        return "", "an empty directory name"
    if kind == "dev-like name":
        return str(_device(root / "node")), "--checkpoint"
    ck.mkdir()
    if kind == "fresh directory":
        return str(ck), ""
    # a finished run's records, then the fault
    assert _cli([*_TABLE, "--checkpoint", str(ck)], capsys)[0] == 0
    records = [r for r in _records(ck) if "pfaffian-table-N6" in r]
    first = records[0]
    if kind == "resume":
        return str(ck), ""
    if kind == "another request's records":
        other = root / "other"
        other.mkdir()
        assert _cli(["table", "--N", "7", "--method", "pfaffian", "--format", "json", "--quiet", "--checkpoint",
                     str(other)], capsys)[0] == 0
        for record in _records(other):
            folder = os.path.basename(os.path.dirname(record)).replace("-N7-", "-N6-")
            os.replace(record, os.path.join(ck, folder, os.path.basename(record)))
        return str(ck), ""
    if kind == "truncated record":
        with open(first, "r+b") as handle:
            handle.truncate(20)
        return str(ck), "truncated"
    if kind == "plausible but wrong record":
        from forcenet.core.checkpoints import CheckpointStore

        store = CheckpointStore(ck, "pfaffian-table", 6)
        key = int(os.path.basename(first)[1:-4])
        value = store.load(key).copy()
        value.flat[value.size // 2 + 1] = (value.flat[value.size // 2 + 1] + 1) % key
        open(first, "wb").write(store.encode(key, value))
        for record in _records(ck):
            os.utime(record, (1e9, 1e9))
        return str(ck), "valid checksum but wrong content"
    os.unlink(first)
    if kind == "FIFO record":
        os.mkfifo(first)
        return str(ck), "a FIFO"
    if kind == "device record":
        _device(first, 5)
        return str(ck), "a character device"
    if kind == "symlink record":
        os.symlink(next(r for r in _records(ck) if r != first), first)  # a valid record of another prime
        return str(ck), "a symbolic link"
    if kind == "directory record":
        os.mkdir(first)
        return str(ck), "a directory"
    if kind == "huge record":
        with open(first, "wb") as handle:
            handle.truncate(2**31 + 1)  # sparse: nothing is written
        return str(ck), "more than any record"
    raise AssertionError(kind)


CHECKPOINTS = [  # (case, exit code)
    ("a file", 2), ("missing parent", 2), ("empty name", 2), ("dev-like name", 2), ("fresh directory", 0),
    ("resume", 0), ("another request's records", 0), ("truncated record", 0), ("plausible but wrong record", 0),
    ("FIFO record", 0), ("device record", 0), ("symlink record", 0), ("directory record", 0), ("huge record", 0),
]


@pytest.mark.parametrize("kind, code", CHECKPOINTS, ids=[k for k, _ in CHECKPOINTS])
def test_checkpoint(kind, code, sandbox, capsys):
    expected = _expected_table(capsys)
    argument, piece = _prepare(kind, sandbox, capsys)
    got, out, err = _cli([*_TABLE, "--checkpoint", argument], capsys)
    assert got == code and piece in err, err
    if code == 0:
        assert out == expected  # the same bytes, whatever the store held
        assert len(err.splitlines()) <= 3, err


def test_checkpoint_read_only_directory(sandbox, capsys):
    ck = sandbox / "ck"
    ck.mkdir()
    ck.chmod(0o500)
    try:
        got, _, err = _cli([*_TABLE, "--checkpoint", str(ck)], capsys)
    finally:
        ck.chmod(0o700)
    assert got == (0 if ROOT else 2)  # root writes anywhere; anyone else is told before the work
    assert ROOT or "--checkpoint" in err


def test_checkpoint_on_a_full_file_system(sandbox, capsys, monkeypatch):
    """Simulated: every byte the checkpoint writer writes fails with ENOSPC (no mount needed)."""
    from forcenet.core import checkpoints

    def full(fd, data):
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(checkpoints, "_write", full)
    expected = _expected_table(capsys)
    got, out, err = _cli([*_TABLE, "--checkpoint", str(sandbox)], capsys)
    assert got == 0 and out == expected
    assert len([line for line in err.splitlines() if "the disk is full" in line]) == 1, err


@pytest.mark.parametrize("argv, piece", [
    (["--checkpoint", "ck", "--no-checkpoint"], "contradict"),
    (["--method", "fast", "--checkpoint", "."], "--checkpoint applies to --method pfaffian only"),
])
def test_checkpoint_options(argv, piece, sandbox, capsys):
    got, _, err = _cli(["table", "--N", "6", "--format", "json", *argv], capsys)
    assert got == 2 and piece in err


@pytest.mark.slow  # two fresh processes: ~17 s on the loaded 2-core machine
def test_two_runs_on_one_checkpoint_directory(sandbox):
    """Two processes, one request, one directory: both finish with the same bytes; every record is whole."""
    argv = [sys.executable, "-m", "forcenet", *_TABLE, "--checkpoint", "ck"]
    (sandbox / "ck").mkdir()
    runs = [subprocess.Popen(argv, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True) for _ in range(2)]
    results = [run.communicate(timeout=120) for run in runs]
    assert [run.returncode for run in runs] == [0, 0], results
    assert results[0][0] == results[1][0] and all("Traceback" not in err for _, err in results)
    from forcenet.core.checkpoints import CheckpointStore

    store = CheckpointStore(sandbox / "ck", "pfaffian-table", 6, report=lambda line: pytest.fail(line))
    assert all(store.load(int(os.path.basename(r)[1:-4])) is not None for r in _records(store.path))


def test_a_resumed_run_with_one_request_per_layer_announces_its_records(sandbox, capsys, monkeypatch):
    from forcenet.cli import table as table_cli

    announced = []
    real = table_cli.run_planned

    def spy(plan, run, **kwargs):
        announced.append(plan)
        return real(plan, run, **kwargs)

    monkeypatch.setattr(table_cli, "run_planned", spy)
    argv = ["table", "--N", "5", "--method", "pfaffian", "--moments", "2", "--format", "json", "--quiet",
            "--checkpoint", "ck", "--force"]  # --force: a cold kernel cache's compile time is not this test's subject
    assert _cli(argv, capsys, bound=60)[0] == 0
    assert _cli(argv, capsys, bound=60)[0] == 0
    first, second = announced
    assert "recorded" not in first.what and f"{first.ticks} of {first.ticks} primes recorded" in second.what
    assert second.seconds < first.seconds


# ------------------------------------------------------------------------------------------------- Python API

from forcenet.exact import correlation, count, mean_W, mean_W_grain, moment, normalization  # noqa: E402
from forcenet.exact.triangle import density  # noqa: E402
from forcenet.numeric.chicken_wire import isotropic as iso  # noqa: E402


def _sampler():
    from forcenet.numeric.triangle.exact_sampler import ExactSampler

    return ExactSampler


def _metropolis():
    from forcenet.numeric.triangle.metropolis import TriangleMetropolis

    return TriangleMetropolis


API = [
    # (label, call, expected: an exception class, PrecisionWarning, or a callable checking the value; name in message)
    ("count(np.int64)", lambda: count(np.int64(6)), lambda v: v == 286, ""),
    ("count(np.int32)", lambda: count(np.int32(6)), lambda v: v == 286, ""),
    ("count(np.uint8)", lambda: count(np.uint8(6)), lambda v: v == 286, ""),
    ("count(np.bool_)", lambda: count(np.bool_(True)), ArgumentTypeError, "N="),
    ("count(True)", lambda: count(True), ArgumentTypeError, "N=True"),
    ("count(5.0)", lambda: count(5.0), ArgumentTypeError, "N=5.0"),
    ("count(np.float64)", lambda: count(np.float64(5.0)), ArgumentTypeError, "N="),
    ("count(5+0j)", lambda: count(5 + 0j), ArgumentTypeError, "N=(5+0j)"),
    ("count('5')", lambda: count("5"), ArgumentTypeError, "N='5'"),
    ("count(None)", lambda: count(None), ArgumentTypeError, "N=None"),
    ("count(nan)", lambda: count(float("nan")), ArgumentTypeError, "N=nan"),
    ("count(-3)", lambda: count(-3), ArgumentError, "N=-3"),
    ("count(1)", lambda: count(1), ArgumentError, "N=1"),
    ("count(10**100)", lambda: count(10**100), ArgumentError, "2..1000000"),
    ("count(10**6)", lambda: count(10**6), ArgumentError, "count_digits(N)"),
    ("normalization(10**7)", lambda: normalization(10**7), ArgumentError, "2..1000000"),
    ("normalization(np.int16)", lambda: normalization(np.int16(4)), lambda v: v == Fraction(1, 360), ""),
    ("mean_W(10**100)", lambda: mean_W(10**100), ArgumentError, "pfaffian"),
    ("mean_W(41)", lambda: mean_W(41), ArgumentError, "pfaffian"),
    ("mean_W(35)", lambda: mean_W(35), ArgumentError, "N = 100 ~36 min"),
    ("mean_W(5.0)", lambda: mean_W(5.0), ArgumentTypeError, "N=5.0"),
    ("mean_W(np.int64)", lambda: mean_W(np.int64(5)), lambda v: [str(x) for x in v[-1]][0] == "1/11", ""),
    ("mean_W_grain float j", lambda: mean_W_grain(6, 6.0, 2), ArgumentTypeError, "grain="),
    ("mean_W_grain out", lambda: mean_W_grain(6, 7, 1), ArgumentError, "grain=(7, 1)"),
    ("mean_W_grain 10**100", lambda: mean_W_grain(10**100, 1, 1), ArgumentError, "pfaffian"),
    ("moment s=0", lambda: moment(5, (5, 1), 0), ArgumentError, "s=0"),
    ("moment s=2.0", lambda: moment(5, (5, 1), 2.0), ArgumentTypeError, "s=2.0"),
    ("moment list grain", lambda: moment(5, [5, 1], 2), lambda v: v == Fraction(1, 66), ""),
    ("moment np grain", lambda: moment(5, np.array([5, 1]), 2), lambda v: v == Fraction(1, 66), ""),
    ("moment 3-grain", lambda: moment(5, (5, 1, 1), 2), ArgumentTypeError, "grain="),
    ("moment huge N", lambda: moment(10**100, (1, 1), 2), ArgumentError, "pfaffian"),
    ("correlation short grain", lambda: correlation(4, (4, 1), (4,)), ArgumentTypeError, "grain2="),
    ("correlation bool grain", lambda: correlation(4, (4, 1), (True, 1)), ArgumentTypeError, "grain2="),
    ("density string grain", lambda: density(4, "42"), ArgumentTypeError, "grain="),
    ("entropy Q=1/6 dps=40", lambda: iso.entropy(Q=1 / 6, dps=40), ArgumentTypeError, "pass '1/6' or Fraction(1, 6)"),
    ("entropy Q=1/6 dps=12", lambda: iso.entropy(Q=1 / 6, dps=12), PrecisionWarning, "Fraction(1, 6)"),
    ("entropy Q=0.125 dps=60", lambda: iso.entropy(Q=0.125, dps=60), lambda v: v > 0, ""),
    ("entropy phi=float32", lambda: iso.entropy(phi=np.float32(0.3), dps=10), ArgumentTypeError, "6 significant"),
    ("entropy Q=nan", lambda: iso.entropy(Q=float("nan")), ArgumentError, "Q=nan"),
    ("entropy Q=inf", lambda: iso.entropy(Q=float("inf")), ArgumentError, "Q=inf"),
    ("entropy Q='abc'", lambda: iso.entropy(Q="abc"), ArgumentTypeError, "Q='abc'"),
    ("entropy both", lambda: iso.entropy(Q="1/6", phi=0), ArgumentTypeError, "exactly one of phi= and Q="),
    ("entropy Q out", lambda: iso.entropy(Q="0.4"), ArgumentError, "Q=0.4"),
    ("entropy dps np", lambda: iso.entropy(Q="1/6", dps=np.int64(20)), lambda v: v > 0, ""),
    ("entropy dps bool", lambda: iso.entropy(Q="1/6", dps=True), ArgumentTypeError, "dps=True"),
    ("entropy dps 4", lambda: iso.entropy(Q="1/6", dps=4), ArgumentError, "dps=4"),
    ("entropy dps huge", lambda: iso.entropy(Q="1/6", dps=10**6), ArgumentError, "dps=1000000"),
    ("per grain l=0.1 dps=30", lambda: iso.entropy_per_grain(0.1, dps=30), ArgumentTypeError, "l=0.1"),
    ("density beyond the DP", lambda: density(45, (45, 3)), ArgumentError, "forcenet dist --N N --grain i,j"),
    ("ExactSampler huge N", lambda: _sampler()(10**100, seed=1), ArgumentError, "N="),
    ("ExactSampler seed -1", lambda: _sampler()(5, seed=-1), ArgumentError, "seed=-1"),
    ("ExactSampler seed bool", lambda: _sampler()(5, seed=True), ArgumentTypeError, "seed=True"),
    ("ExactSampler seed 1.5", lambda: _sampler()(5, seed=1.5), ArgumentTypeError, "seed=1.5"),
    ("ExactSampler np seed", lambda: _sampler()(5, seed=np.uint64(3)).sample_W(np.int64(2)), lambda v: v.shape == (2, 5, 5), ""),
    ("sample_W huge", lambda: _sampler()(5, seed=1).sample_W(10**100), ArgumentError, "sample_W(size="),
    ("sample_W 2.0", lambda: _sampler()(5, seed=1).sample_W(2.0), ArgumentTypeError, "size=2.0"),
    ("sample_W -1", lambda: _sampler()(5, seed=1).sample_W(-1), ArgumentError, "size=-1"),
    ("Metropolis huge N", lambda: _metropolis()(10**100, seed=1), ArgumentError, "N="),
    ("Metropolis run huge", lambda: _metropolis()(5, seed=1).run(10**100), ArgumentError, "run(sweeps="),
    ("Metropolis seed -2", lambda: _metropolis()(5, seed=-2), ArgumentError, "seed=-2"),
    ("bethe density float", lambda: __import__("forcenet.numeric.chicken_wire.isotropic_bethe",
                                               fromlist=["x"]).isotropic_limit(1 / 6), ArgumentTypeError, "Q="),
]


@pytest.mark.parametrize("label, call, expected, piece", API, ids=[a[0] for a in API])
def test_python_api(label, call, expected, piece):
    start = time.monotonic()
    if expected is PrecisionWarning:
        with pytest.warns(PrecisionWarning, match=piece.replace("(", r"\(").replace(")", r"\)")):
            call()
    elif isinstance(expected, type):
        with pytest.raises(expected) as caught:
            call()
        assert isinstance(caught.value, forcenet.ForcenetError)
        assert piece in str(caught.value), str(caught.value)
        assert "\n" not in str(caught.value)
    else:
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            assert expected(call())
    assert time.monotonic() - start < 10
