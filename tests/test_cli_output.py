"""Issue 24, items 1, 5 (stdout), 7-11, 14: where results go, and what a newcomer reads.

Devices are nodes created with ``os.mknod`` in a temporary directory (never
``/dev`` itself); FIFOs have a reader thread.  Most tests call ``main()`` in
this process; the few that need a real closed or full standard output run a
subprocess.
"""

import errno
import json
import os
import stat
import subprocess
import sys
import threading
from pathlib import Path

import pytest

from forcenet.cli import main
from forcenet.exact import count


def make_device(path, minor):
    """A character device like /dev/null (minor 3) or /dev/full (minor 7), or skip (needs root)."""
    try:
        os.mknod(path, stat.S_IFCHR | 0o666, os.makedev(1, minor))
    except (PermissionError, AttributeError):
        pytest.skip("creating device nodes needs root")
    return path


@pytest.fixture
def sandbox(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    return tmp_path


# ------------------------------------------------------------ item 1: what --out must not destroy


def test_1_a_full_device_is_written_in_place_and_fails(sandbox, cli, files):
    full = make_device(sandbox / "full", 7)
    for argv in (["count", "--N", "10", "--out", "full"], ["table", "--N", "5", "--format", "json", "--out", "full"]):
        code, out, err = cli(argv)
        assert code == 2 and err == "forcenet: error: --out=full: No space left on device\n"
        assert stat.S_ISCHR(os.lstat(full).st_mode) and files(sandbox) == ["full"]


def test_1_a_null_device_stays_a_device(sandbox, cli, files):
    null = make_device(sandbox / "null", 3)
    code, out, err = cli(["count", "--N", "10", "--out", "null"])
    assert code == 0 and out == "" and stat.S_ISCHR(os.lstat(null).st_mode)
    code, _, _ = cli(["dist", "--N", "5", "--ensemble", "--plot", "null", "--samples", "200", "--sweeps", "300",
                      "--quiet"])
    assert code == 2  # a PNG needs a .png name; the device is untouched
    assert stat.S_ISCHR(os.lstat(null).st_mode) and files(sandbox) == ["null"]


def test_1_a_fifo_is_written_in_place(sandbox, cli, files):
    fifo = sandbox / "pipe"
    os.mkfifo(fifo)
    received = []
    reader = threading.Thread(target=lambda: received.append(Path(fifo).read_text()), daemon=True)
    reader.start()
    code, _, err = cli(["count", "--N", "12", "--out", str(fifo)])
    reader.join(timeout=30)
    if reader.is_alive() and stat.S_ISFIFO(os.lstat(fifo).st_mode):  # never written: release the reader
        os.close(os.open(fifo, os.O_WRONLY | os.O_NONBLOCK))
    assert code == 0 and received == [f"{count(12)}\n"]
    assert stat.S_ISFIFO(os.lstat(fifo).st_mode) and files(sandbox) == ["pipe"]


def test_1_a_link_is_followed_and_stays(sandbox, cli, files):
    (sandbox / "data").mkdir()
    target = sandbox / "data" / "n.txt"
    target.write_text("old\n")
    os.chmod(target, 0o640)
    os.symlink("data/n.txt", sandbox / "link")
    code, _, _ = cli(["count", "--N", "9", "--out", "link"])
    assert code == 0 and os.path.islink(sandbox / "link") and os.readlink(sandbox / "link") == "data/n.txt"
    assert target.read_text() == f"{count(9)}\n" and stat.S_IMODE(os.stat(target).st_mode) == 0o640  # mode kept
    os.symlink("data/new.json", sandbox / "dangling")  # a link to a file not yet there: created at the target
    code, _, _ = cli(["table", "--N", "4", "--out", "dangling"])
    assert code == 2  # no extension: the format must be given
    code, _, _ = cli(["table", "--N", "4", "--format", "json", "--out", "dangling"])
    assert code == 0 and os.path.islink(sandbox / "dangling") and json.loads((sandbox / "data" / "new.json").read_text())["N"] == 4
    assert files(sandbox) == ["dangling", "data", "data/n.txt", "data/new.json", "link"]


@pytest.mark.parametrize("argv, path", [
    (["count", "--N", "9", "--out", "ro.txt"], "ro.txt"),
    (["dist", "--N", "5", "--ensemble", "--plot", "ro.png", "--samples", "200", "--sweeps", "300"], "ro.png"),
    (["table", "--N", "5", "--samples", "0", "--out-dir", "tables"], "tables/mean_W_N5.csv"),
])
def test_1_a_read_only_file_is_refused_even_as_root(argv, path, sandbox, monkeypatch, cli):
    from forcenet.cli import common

    (sandbox / "tables").mkdir()
    (sandbox / path).write_text("keep me\n")
    os.chmod(sandbox / path, 0o444)
    monkeypatch.setattr(common, "run_planned", _no_work)
    code, out, err = cli(argv)
    assert code == 2 and f"{path}: is read-only (mode 444)" in err and len(err.splitlines()) == 1
    assert (sandbox / path).read_text() == "keep me\n" and stat.S_IMODE(os.stat(sandbox / path).st_mode) == 0o444


def _no_work(*args, **kwargs):
    raise AssertionError("the computation ran before the destination was checked")


# ------------------------------------------------------ item 7: destinations checked before the work


@pytest.mark.parametrize("argv, needle", [
    (["bethe", "--L", "600", "--out", "nonexistent/b.txt"], "--out=nonexistent/b.txt: the directory"),
    (["entropy", "--Q", "1/6", "--bethe", "--out", "nonexistent/e.txt"], "--out=nonexistent/e.txt: the directory"),
    (["table", "--N", "12", "--out-dir", ""], "--out-dir='': an empty directory name"),
    (["table", "--N", "12", "--out-dir", "nonexistent/t"], "its parent"),
    (["count", "--N", "12", "--out", "newdir/"], "--out=newdir/: ends in '/'"),
    (["count", "--N", "12", "--out", ""], "--out='': an empty file name"),
    (["sample", "--N", "5", "--out", "."], "--out=.: is a directory"),
    (["limit", "--x", "0", "--z", "0.5", "--out", "nonexistent/l.txt"], "the directory"),
    (["transfer", "--L", "5", "--out", "nonexistent/t.txt"], "the directory"),
    (["dist", "--N", "5", "--ensemble", "--plot", "nonexistent/p.png"], "--plot=nonexistent/p.png: the directory"),
])
def test_7_every_destination_before_any_computation(argv, needle, sandbox, monkeypatch, cli, files):
    from forcenet.cli import chicken_wire, dist, sample, table

    for module in (chicken_wire, dist, sample, table):
        monkeypatch.setattr(module, "run_planned", _no_work)
    code, out, err = cli(argv)
    assert code == 2 and needle in err and len(err.splitlines()) == 1 and ".tmp-" not in err
    assert files(sandbox) == []


# ------------------------------------------------------ item 8: messages name the user's path


def test_8_a_failed_write_names_the_users_path(sandbox, monkeypatch, cli, files):
    from forcenet.cli import output

    def full(fd):
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(output.os, "fsync", full)
    code, _, err = cli(["count", "--N", "10", "--out", "c.txt"])
    assert code == 2 and err == "forcenet: error: --out=c.txt: No space left on device\n"
    assert files(sandbox) == []


def test_8_9_a_full_stdout_is_named_and_the_main_job_keeps_no_file(sandbox, capsys, monkeypatch, files, full_stream):
    (sandbox / "tables").mkdir()
    old = sandbox / "tables" / "mean_W_N5.json"
    old.write_text("an earlier table\n")
    monkeypatch.setattr(sys, "stdout", full_stream)
    code = main(["count", "--N", "10"])
    assert code == 2 and capsys.readouterr().err == "forcenet: error: standard output: No space left on device\n"
    code = main(["table", "--N", "5", "--samples", "40", "--out-dir", "tables", "--quiet"])
    assert code == 2 and "standard output: No space left on device" in capsys.readouterr().err
    assert files(sandbox) == ["tables", "tables/mean_W_N5.json"] and old.read_text() == "an earlier table\n"
    code = main(["table", "--N", "5", "--samples", "40", "--out-dir", "new", "--quiet"])
    assert code == 2 and not (sandbox / "new").exists()


def test_5_8_9_real_closed_and_full_stdout(sandbox, files):
    """Subprocesses with file descriptor 1 closed, and on a full device (a node made here)."""
    env = dict(os.environ)  # the installed forcenet, as a user runs it
    cmd = [sys.executable, "-m", "forcenet", "table", "--N", "12", "--format", "json"]
    closed = subprocess.run(cmd, stderr=subprocess.PIPE, text=True, env=env, pass_fds=(), close_fds=True,
                            preexec_fn=lambda: os.close(1), check=False)
    assert closed.returncode == 2 and closed.stderr.startswith("forcenet: error: standard output is closed")
    assert len(closed.stderr.splitlines()) == 1
    full = make_device(sandbox / "full", 7)
    with open(full, "w") as stdout:
        proc = subprocess.run([sys.executable, "-m", "forcenet", "table", "--N", "6", "--samples", "40", "--quiet"],
                              stdout=stdout, stderr=subprocess.PIPE, text=True, env=env, check=False)
    assert proc.returncode == 2 and proc.stderr == "forcenet: error: standard output: No space left on device\n"
    assert files(sandbox) == ["full"]  # no forcenet-tables/ left


def test_1_dev_stdout_is_written_in_place(sandbox, files):
    env = dict(os.environ)  # the installed forcenet, as a user runs it
    log = sandbox / "log.txt"
    log.write_text("before\n")
    with open(log, "a") as stdout:
        proc = subprocess.run([sys.executable, "-m", "forcenet", "count", "--N", "9", "--out", "/dev/stdout"],
                              stdout=stdout, stderr=subprocess.PIPE, text=True, env=env, check=False)
    assert proc.returncode == 0 and log.read_text() == f"before\n{count(9)}\n"  # appended, the file not replaced
    assert files(sandbox) == ["log.txt"]


# ------------------------------------------------------ item 10: contradictions


@pytest.mark.parametrize("argv, needle", [
    (["table", "--N", "5", "--format", "json", "--out", "t.csv"], "--format json and --out=t.csv contradict"),
    (["dist", "--N", "5", "--ensemble", "--format", "csv", "--out", "x.json"], "--format csv and --out=x.json contradict"),
    (["sample", "--N", "5", "--format", "text", "--out", "s.json"], "--format text and --out=s.json contradict"),
    (["table", "--N", "5", "--out", "t.json", "--out-dir", "d"], "--out-dir and --out contradict"),
    (["table", "--N", "5", "--format", "json", "--out-dir", "d"], "--out-dir and --format contradict"),
    (["table", "--N", "5", "--format", "json", "--seed", "3"], "--seed and --format contradict"),
    (["table", "--N", "5", "--out", "t.json", "--samples", "50"], "--samples and --out contradict"),
    (["table", "--N", "5", "--samples", "0", "--seed", "3"], "--seed and --samples contradict"),
    (["dist", "--N", "5", "--ensemble", "--seed", "3"], "--seed set the sampled histograms of --plot"),
    (["sample", "--N", "5", "--burn-in", "10"], "--burn-in applies to --sampler metropolis only"),
    (["sample", "--N", "5", "--timing"], "--timing and --format text contradict"),
    (["entropy", "--max", "--F", "2"], "--max and --F contradict"),
    (["entropy", "--phi", "0.3", "--L-max", "100"], "--L-max sets the widths of --bethe"),
    (["count", "--N", "5", "--N", "6"], "--N given twice"),
    (["sample", "--N", "5", "--seed", "1", "--seed", "1"], "--seed given twice"),
    (["table", "--N", "5", "--quiet", "--quiet"], "--quiet given twice"),
    (["count", "--N", "\u0661\u0662"], "is not an integer: use the ASCII digits 0-9"),
    (["limit", "--x", "0", "--z", "\u0660.\u0665"], "is not a number: use the ASCII digits 0-9"),
    (["entropy", "--Q", "\u0661/\u0666"], "is not a number"),
    (["dist", "--N", "5", "--grain", "\u0663,2"], "is not an integer"),
])
def test_10_contradictions_are_refused_in_one_line(argv, needle, sandbox, cli, files):
    code, out, err = cli(argv)
    assert code == 2 and needle.replace(" set", "") in err.replace(", --seed", " --seed").replace(" set", "") and out == ""
    assert len(err.splitlines()) == 1 and files(sandbox) == []


def test_10_agreeing_arguments_still_run(sandbox, cli):
    code, _, _ = cli(["table", "--N", "4", "--format", "csv", "--out", "t.csv"])
    assert code == 0 and (sandbox / "t.csv").read_text().startswith("i,j,mean_W")
    code, out, _ = cli(["table", "--N", "4", "--format", "json", "--out", "t.txt"])  # no format implied
    assert code == 0 and json.loads((sandbox / "t.txt").read_text())["N"] == 4


# ------------------------------------------------------ item 11: progress in log files


def _planned(seconds, ticks, capsys, monkeypatch, tty):
    from forcenet.cli.common import run_planned
    from forcenet.core.plan import Plan

    monkeypatch.setattr(sys.stderr, "isatty", lambda: tty, raising=False)

    def work(progress):
        for _ in range(ticks):
            if progress is not None:  # None: nothing is shown
                progress(1)
        return "done"

    assert run_planned(Plan("a test run", seconds, 1, ticks, "step"), work, force=True) == "done"
    return capsys.readouterr().err


def test_11_off_a_terminal_plain_lines_only(capsys, monkeypatch):
    err = _planned(300, 1000, capsys, monkeypatch, tty=False)
    lines = err.splitlines()
    assert "\r" not in err and lines[0].startswith("forcenet: a test run: estimated")
    assert [line.split(": ")[2].split(" ")[0] for line in lines[1:-1]] == [str(10 * k) for k in range(1, 10)]
    assert lines[-1].startswith("forcenet: a test run: done in")
    err = _planned(30, 1000, capsys, monkeypatch, tty=False)  # under a minute: the announcement and the final line only
    assert "\r" not in err and len(err.splitlines()) == 2


def test_11_on_a_terminal_the_bar_animates(capsys, monkeypatch):
    err = _planned(30, 50, capsys, monkeypatch, tty=True)
    assert "\r" in err and "a test run" in err


# ------------------------------------------------------ item 14: help a newcomer understands


def test_14_help(capsys):
    assert main(["--help"]) == 0
    out = capsys.readouterr().out
    for command in ("count", "table", "maps", "limit", "sample", "transfer", "bethe", "entropy", "dist"):
        assert f"  forcenet {command} --" in out, command
    assert "README" in out
    assert main(["table", "--help"]) == 0
    out = " ".join(capsys.readouterr().out.split())
    assert "three files into ./forcenet-tables/" in out and "20000" in out and "--seed affects only that cross-check" in out
    assert "order ideals (sets of grains closed upwards)" in out
    assert main(["sample", "--help"]) == 0
    assert "(default)" in " ".join(capsys.readouterr().out.split()).split("--sampler {exact,metropolis}")[-1].split("--samples")[0]
    assert main(["count", "--help"]) == 0
    assert "d! * normalization (4.1) (d = N(N-1)/2 free forces" in " ".join(capsys.readouterr().out.split())
    assert main(["entropy", "--help"]) == 0
    assert "0.3 is exactly 3/10" in " ".join(capsys.readouterr().out.split())


@pytest.mark.parametrize("line", [
    "forcenet count --N 12", "forcenet table --N 12 --format json", "forcenet maps --N 7", "forcenet limit --x 0.2 --z 0.6",
    "forcenet sample --N 10 --samples 2000", "forcenet transfer --L 6", "forcenet bethe --L 6 --n 2 --m 1",
    "forcenet entropy --phi 0.3", "forcenet dist --N 12 --grain 12,6",
])
def test_14_the_help_examples_run(line, cli):
    from forcenet.cli import _EXAMPLES

    assert line in _EXAMPLES
    code, out, _ = cli(line.split()[1:] + ["--quiet"] * (line.split()[1] in ("sample", "transfer", "bethe", "entropy")))
    assert code == 0 and out


def test_a_folder_that_cannot_be_made_is_one_line_naming_the_argument(tmp_path, monkeypatch):
    """An OSError of the command line's own file operation is a user error (exit 2), never an internal one."""
    import errno

    from forcenet.cli.common import UsageError
    from forcenet.cli.output import write_files

    def read_only(path, *args):
        raise OSError(errno.EROFS, "Read-only file system")

    monkeypatch.setattr("os.mkdir", read_only)
    folder = tmp_path / "tables"
    with pytest.raises(UsageError, match=r"--out=.*tables: cannot create the folder \(Read-only file system\)"):
        write_files({str(folder / "a.json"): "{}"}, make_dir=str(folder))
    assert not folder.exists()


def test_a_failed_rollback_keeps_the_first_failure_and_the_old_content(tmp_path, monkeypatch):
    """Two files all or none: the second fails; restoring the first fails too; the first failure is reported and
    the first file's old content is still on disk (its backup)."""
    import errno

    from forcenet.core import atomic_files

    a, b = tmp_path / "a", tmp_path / "b"
    a.write_text("old a")
    real_replace, real_rename = os.replace, os.rename

    def replace(src, dst):
        if str(dst) == str(b):
            raise OSError(errno.ENOSPC, "No space left on device")
        return real_replace(src, dst)

    def rename(src, dst):
        if str(dst) == str(a):
            raise OSError(errno.EIO, "Input/output error")
        return real_rename(src, dst)

    monkeypatch.setattr(atomic_files.os, "replace", replace)
    monkeypatch.setattr(atomic_files.os, "rename", rename)
    with pytest.raises(OSError, match="No space"):
        atomic_files.write_all([(atomic_files.resolve(a), b"new a"), (atomic_files.resolve(b), b"new b")])
    kept = [p.read_text() for p in tmp_path.iterdir()]
    assert "old a" in kept and not b.exists()
