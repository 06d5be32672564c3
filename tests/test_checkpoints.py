"""Checkpoints of the per-prime tasks (exact/checkpoints.py): atomic, checksummed, per request, under faults.

Every damaged record must be detected, reported in one line and recomputed;
a run killed with SIGKILL at any point resumes to the same bytes, reusing
what was recorded; two writers never corrupt each other; a full disk stops
the checkpoints, never the run.
"""

import errno
import multiprocessing
import os
import random
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

from forcenet.cli import main
from forcenet.core.checkpoints import FORMAT_VERSION, CheckpointStore, default_directory
from forcenet.exact.triangle.free_fermion import route


def _store(tmp_path, N=12, route_name="pfaffian-table", lines=None):
    return CheckpointStore(tmp_path, route_name, N, report=None if lines is None else lines.append)


def test_round_trip_and_missing(tmp_path):
    store = _store(tmp_path)
    value = np.arange(-3, 9, dtype=np.int64).reshape(3, 4) * (2**40)
    store.save(7, value)
    assert store.load(7).tolist() == value.tolist()
    assert store.load(11) is None
    store.save(5, 123)  # an integer (a count residue) is a 0-d array
    assert int(store.load(5)) == 123 and store.load(5).shape == ()
    assert (store.saved, store.reused, store.damaged) == (2, 3, 0)  # three loads of a whole record


def test_truncated_records_are_reported_and_refused(tmp_path):
    lines = []
    store = _store(tmp_path, lines=lines)
    store.save(7, np.arange(12).reshape(3, 4))
    path = store._file(7)
    whole = open(path, "rb").read()
    for length in (0, 5, len(whole) // 2, len(whole) - 1):
        with open(path, "wb") as handle:
            handle.write(whole[:length])
        assert store.load(7) is None
    assert store.damaged == 4 and len(lines) == 4
    assert all("\n" not in line and path in line and "recomputing" in line for line in lines)


def test_every_flipped_bit_is_detected(tmp_path):
    store = _store(tmp_path, lines=[])
    store.save(7, np.arange(6).reshape(2, 3))
    path = store._file(7)
    whole = bytearray(open(path, "rb").read())
    rng = random.Random(26)
    positions = sorted(rng.sample(range(len(whole) * 8), 200)) + [0, len(whole) * 8 - 1]
    for bit in positions:
        flipped = bytearray(whole)
        flipped[bit // 8] ^= 1 << (bit % 8)
        with open(path, "wb") as handle:
            handle.write(flipped)
        assert store.load(7) is None, bit
    assert store.damaged == len(positions) and store.reused == 0


def test_records_of_another_request_are_ignored(tmp_path):
    lines = []
    other = CheckpointStore(tmp_path, "pfaffian-table", 13)
    other.save(7, np.arange(4))
    store = _store(tmp_path, lines=lines)
    os.makedirs(store.path)
    os.replace(other._file(7), store._file(7))  # a whole, valid record of N = 13 under N = 12's name
    assert store.load(7) is None and store.ignored == 1 and store.damaged == 0 and lines == []
    # another format version, and another prime's record under this prime's name
    store.request = dict(store.request, format=FORMAT_VERSION + 1)
    store.save(7, np.arange(4))
    store.request = dict(store.request, format=FORMAT_VERSION)
    assert store.load(7) is None and store.ignored == 2
    store.save(11, np.arange(4))
    os.replace(store._file(11), store._file(7))
    assert store.load(7) is None and store.ignored == 3


def test_damaged_records_of_a_run_are_recomputed_to_the_same_table(tmp_path):
    expected = route.mean_W(14)
    assert route.mean_W(14, checkpoint=tmp_path) == expected
    lines = []
    store = CheckpointStore(tmp_path, "pfaffian-table", 14, report=lines.append)
    files = sorted(os.listdir(store.path))
    first, second, third = (os.path.join(store.path, f) for f in files[:3])
    with open(first, "r+b") as handle:  # truncated
        handle.truncate(os.path.getsize(first) - 10)
    data = bytearray(open(second, "rb").read())  # one bit flipped in the payload
    data[-40] ^= 0x10
    open(second, "wb").write(bytes(data))
    other = CheckpointStore(tmp_path, "pfaffian-table", 15)  # a record of another request
    open(third, "wb").write(other.encode(int(files[2][1:-4]), np.zeros((13, 14), dtype=np.int64)))
    assert route.mean_W(14, checkpoint=store) == expected
    assert (store.damaged, store.ignored, store.reused) == (2, 1, len(files) - 3)
    assert len(lines) == 2
    again = CheckpointStore(tmp_path, "pfaffian-table", 14)  # the recomputed records replaced the bad ones
    assert route.mean_W(14, checkpoint=again) == expected and again.reused == len(files) and again.damaged == 0


def test_full_disk_stops_checkpoints_not_the_run(tmp_path, monkeypatch):
    from forcenet.core import checkpoints

    route.count(16, checkpoint=tmp_path)  # the count's records first: below, only the table's records are written
    lines = []
    store = CheckpointStore(tmp_path, "pfaffian-table", 16, report=lines.append)
    real_write, state = os.write, {"records": 0, "half": False}

    def write(fd, data):
        if state["records"] < 2:  # two records fit
            state["records"] += 1
            return real_write(fd, data)
        if not state["half"]:  # the disk fills in the middle of the third
            state["half"] = True
            return real_write(fd, bytes(data[: len(data) // 2]))
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(checkpoints, "_write", write)
    assert route.mean_W(16, checkpoint=store) == route.mean_W(16)
    assert store.saved == 2 and store.failed is not None
    assert len(lines) == 1 and "disk is full" in lines[0] and "continuing without checkpoints" in lines[0]
    assert not [f for f in os.listdir(store.path) if f.startswith(".tmp-")]
    for name in os.listdir(store.path):  # the records written before the disk filled are whole
        assert store.load(int(name[1:-4])) is not None


def _writer(directory, seed, rounds):
    store = CheckpointStore(directory, "pfaffian-table", 12)
    rng = np.random.default_rng(seed)
    for _ in range(rounds):
        store.save(int(rng.integers(3)), np.full((50, 50), 7, dtype=np.int64))


def test_concurrent_writers_never_expose_a_partial_record(tmp_path):
    context = multiprocessing.get_context("fork" if "fork" in multiprocessing.get_all_start_methods() else "spawn")
    writers = [context.Process(target=_writer, args=(str(tmp_path), seed, 150)) for seed in (1, 2)]
    for w in writers:
        w.start()
    reader = _store(tmp_path, lines=[])
    seen = 0
    while any(w.is_alive() for w in writers):
        for key in range(3):
            value = reader.load(key)
            if value is not None:
                seen += 1
                assert value.shape == (50, 50) and int(value.sum()) == 7 * 2500
    for w in writers:
        w.join()
        assert w.exitcode == 0
    assert reader.damaged == 0 and seen > 0
    assert sorted(os.listdir(reader.path)) == ["p0.rec", "p1.rec", "p2.rec"]


def test_default_directory_follows_xdg(monkeypatch, tmp_path):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    assert default_directory() == os.path.join(str(tmp_path), "forcenet")
    monkeypatch.delenv("XDG_CACHE_HOME")
    monkeypatch.setenv("HOME", str(tmp_path))
    assert default_directory() == os.path.join(str(tmp_path), ".cache", "forcenet")


def _cli(*args):
    return [sys.executable, "-m", "forcenet", "table", "--method", "pfaffian", "--format", "json", *args]


def test_sigkill_at_random_points_resumes_to_the_same_bytes(tmp_path, capsys):
    N = 28
    assert main(["table", "--N", str(N), "--method", "pfaffian", "--format", "json"]) == 0
    expected = capsys.readouterr().out
    directory = tmp_path / "ck"
    table = CheckpointStore(directory, "pfaffian-table", N)
    total = route.mean_plan(N).ticks
    rng = random.Random(2606)
    kills = [rng.randrange(3, total - 3)]
    for target in kills:  # kill -9 when `target` primes are recorded (a random point), then finish
        process = subprocess.Popen(_cli("--N", str(N), "--checkpoint", str(directory), "--quiet"),
                                   stdout=subprocess.PIPE, stderr=subprocess.PIPE)
        deadline = time.monotonic() + 300  # generous: on a loaded machine (the suite's other workers) the child
        # may compile its kernels first
        while time.monotonic() < deadline and process.poll() is None:
            if os.path.isdir(table.path) and len([f for f in os.listdir(table.path) if f.endswith(".rec")]) >= target:
                break
            time.sleep(0.005)
        process.send_signal(signal.SIGKILL)
        process.communicate()
        assert process.returncode == -signal.SIGKILL
    recorded = len([f for f in os.listdir(table.path) if f.endswith(".rec")])
    assert kills[-1] <= recorded < total
    result = subprocess.run(_cli("--N", str(N), "--checkpoint", str(directory)), capture_output=True, text=True, check=False)
    assert result.returncode == 0 and result.stdout == expected
    assert f"reused {recorded} of {total} primes, computed {total - recorded}" in result.stderr


def test_runs_over_a_minute_checkpoint_by_default_in_the_cache(monkeypatch, tmp_path):
    import argparse

    import forcenet
    from forcenet.cli.cluster import engine_options

    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    args = argparse.Namespace(method="pfaffian", N=64, moments=1, scheduler=None, checkpoint=None, no_checkpoint=False)

    def options(seconds):
        return engine_options(args, True, "--method pfaffian", seconds, lambda directory: directory)

    client, directory = options(61)
    request = forcenet.plan(64, method="pfaffian", checkpoint=directory)  # what the command line plans with it
    store = request.checkpoint
    assert client is None and store.path.startswith(os.path.join(str(tmp_path), "forcenet", "pfaffian-table-N64"))
    assert options(59) == (None, None)
    args.no_checkpoint = True
    assert options(3600) == (None, None)
    assert f"checkpoints in {store.path}: 0 of {request.cost.ticks} primes recorded" in request.cost.what


@pytest.mark.parametrize("argv, message", [
    (["--method", "pfaffian", "--checkpoint", "ck", "--no-checkpoint"], "--checkpoint and --no-checkpoint contradict"),
    (["--method", "fast", "--checkpoint", "ck"], "--checkpoint applies to --method pfaffian only"),
    (["--method", "pfaffian", "--checkpoint", "no/such/dir"], "--checkpoint=no/such/dir: its parent"),
])
def test_checkpoint_options_refused_in_one_line(argv, message, capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert main(["table", "--N", "12", "--format", "json", *argv]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and message in err and os.listdir(tmp_path) == []


# ---------------------------------------------------------------- issue 46: hostile files, bad places, wrong content


def _timed(call, seconds=5.0):
    start = time.monotonic()
    result = call()
    assert time.monotonic() - start < seconds
    return result


def test_a_fifo_named_like_a_record_is_not_opened(tmp_path):
    lines = []
    store = _store(tmp_path, lines=lines)
    store.save(5, np.arange(3))
    os.mkfifo(store._file(7))
    assert _timed(lambda: store.load(7)) is None  # no writer would ever come: opening it would hang
    assert not store.holds(7) and store.holds(5)
    assert len(lines) == 1 and "a FIFO" in lines[0] and store._file(7) in lines[0]
    store.save(7, np.arange(4))  # the recomputed record replaces the FIFO
    assert store.load(7).tolist() == [0, 1, 2, 3]


def test_a_device_node_named_like_a_record_is_not_read(tmp_path):
    lines = []
    store = _store(tmp_path, lines=lines)
    os.makedirs(store.path)
    try:
        os.mknod(store._file(7), 0o600 | __import__("stat").S_IFCHR, os.makedev(1, 5))  # /dev/zero's numbers
    except PermissionError:
        pytest.skip("creating a device node needs CAP_MKNOD")
    assert _timed(lambda: store.load(7)) is None  # /dev/zero would be read until memory runs out
    assert len(lines) == 1 and "a character device" in lines[0]


def test_a_symbolic_link_named_like_a_record_is_not_followed(tmp_path):
    lines = []
    store = _store(tmp_path, lines=lines)
    store.save(5, np.arange(3))
    os.symlink(store._file(5), store._file(7))  # a valid record of another prime, through a link
    assert store.load(7) is None and "a symbolic link" in lines[0] and not store.holds(7)


@pytest.mark.parametrize("make", ["missing home", "cache is a file", "unreadable folder"])
def test_an_unusable_checkpoint_place_is_one_line_and_creates_nothing(make, tmp_path, monkeypatch):
    monkeypatch.delenv("XDG_CACHE_HOME", raising=False)
    if make == "missing home":
        monkeypatch.setenv("HOME", str(tmp_path / "nobody"))
    elif make == "cache is a file":
        (tmp_path / "cache").write_text("not a directory")
        monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    lines = []
    directory = default_directory() if make != "unreadable folder" else tmp_path / "ck"
    store = CheckpointStore(directory, "pfaffian-table", 12, report=lines.append)
    if make == "unreadable folder":
        if os.geteuid() == 0:
            pytest.skip("root reads any folder")
        os.makedirs(store.path)
        os.chmod(store.path, 0)
    for p in range(481):  # one line, not one per prime
        assert store.load(p) is None
        store.save(p, np.arange(3))
    assert len(lines) == 1 and "continuing without checkpoints" in lines[0], lines
    assert store.saved == 0 and store.failed
    assert not (tmp_path / "nobody").exists()


def test_a_record_with_a_valid_checksum_but_wrong_content_is_named_dropped_and_recomputed(tmp_path):
    from forcenet.core.checkpoints import distrust_reused

    expected = route.mean_W(8)
    assert route.mean_W(8, checkpoint=tmp_path) == expected
    store = CheckpointStore(tmp_path, "pfaffian-table", 8)
    name = sorted(os.listdir(store.path))[0]
    key = int(name[1:-4])
    value = store.load(key).copy()
    value.flat[value.size // 2 + 1] = (value.flat[value.size // 2 + 1] + 1) % key  # still a residue mod p
    open(store._file(key), "wb").write(store.encode(key, value))  # a checksum that matches the wrong content
    for entry in os.scandir(store.path):
        os.utime(entry.path, (1e9, 1e9))  # written by an earlier run
    with pytest.raises(ArithmeticError):  # the route's own exact checks catch it; alone, it is a failure
        route.mean_W(8, checkpoint=tmp_path)
    lines = []
    started = time.time()
    for entry in os.scandir(store.path):
        os.utime(entry.path, (1e9, 1e9))
    table = distrust_reused(lambda: route.mean_W(8, checkpoint=tmp_path), tmp_path, 8, started, lines.append)
    assert table == expected
    named = [line for line in lines if "valid checksum but wrong content" in line]
    assert len(named) == 1 and store._file(key) in named[0]
    assert all("\n" not in line for line in lines)
    again = CheckpointStore(tmp_path, "pfaffian-table", 8)
    assert route.mean_W(8, checkpoint=again) == expected and again.damaged == 0 and again.reused > 0
    assert not [f for f in os.listdir(tmp_path) if f.startswith(".suspect-")]  # the set-aside folder is gone


def test_without_reused_records_an_arithmetic_error_stays_a_bug(tmp_path):
    from forcenet.core.checkpoints import distrust_reused

    def broken():
        raise ArithmeticError("a bug")

    with pytest.raises(ArithmeticError, match="a bug"):
        distrust_reused(broken, tmp_path, 8, time.time())


@pytest.mark.parametrize("shape", [(7, 7), (9,), (2, 8, 8), ()])
def test_a_record_of_the_wrong_shape_with_a_valid_checksum_is_named_and_recomputed(tmp_path, shape):
    """Issue 56: a 23 x 23 record where 24 x 24 belongs (checksum recomputed) was a ValueError on every rerun."""
    expected = route.mean_W(9)
    assert route.mean_W(9, checkpoint=tmp_path) == expected
    plain = CheckpointStore(tmp_path, "pfaffian-table", 9)
    key = int(sorted(os.listdir(plain.path))[0][1:-4])
    open(plain._file(key), "wb").write(plain.encode(key, np.ones(shape, dtype=np.int64)))
    lines = []
    store = CheckpointStore(tmp_path, "pfaffian-table", 9, report=lines.append)
    assert route.mean_W(9, checkpoint=store) == expected
    assert store.damaged == 1 and len(lines) == 1
    assert plain._file(key) in lines[0] and f"a record of shape {shape} where (9, 9) belongs" in lines[0]
    again = CheckpointStore(tmp_path, "pfaffian-table", 9)  # recomputed and written again: the next run reuses it
    assert route.mean_W(9, checkpoint=again) == expected and again.damaged == 0 and again.reused == 2
