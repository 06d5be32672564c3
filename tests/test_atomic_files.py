"""The one atomic writer (forcenet.core.atomic_files): its policy, and that the three writers of the package use it."""

from __future__ import annotations

import os
import stat
import threading

import numpy as np
import pytest

from forcenet.core import atomic_files
from forcenet.core.atomic_files import DestinationError, resolve, write_all, write_atomic


def test_a_new_file_gets_the_usual_mode_and_an_old_one_keeps_its_own(tmp_path):
    path = tmp_path / "a.txt"
    write_atomic(path, "one")
    umask = os.umask(0)
    os.umask(umask)
    assert stat.S_IMODE(os.stat(path).st_mode) == 0o666 & ~umask
    os.chmod(path, 0o640)
    write_atomic(path, "two")
    assert path.read_text() == "two" and stat.S_IMODE(os.stat(path).st_mode) == 0o640
    assert os.listdir(tmp_path) == ["a.txt"]


def test_a_link_is_followed_and_stays(tmp_path):
    (tmp_path / "real.txt").write_text("old")
    os.symlink("real.txt", tmp_path / "link.txt")
    write_atomic(tmp_path / "link.txt", "new")
    assert os.path.islink(tmp_path / "link.txt") and (tmp_path / "real.txt").read_text() == "new"


def test_a_read_only_file_is_refused_by_its_mode_bits(tmp_path):
    path = tmp_path / "ro.txt"
    path.write_text("keep")
    os.chmod(path, 0o444)
    with pytest.raises(DestinationError, match=r"is read-only \(mode 444\)"):
        write_atomic(path, "lost")
    assert path.read_text() == "keep"


def test_a_fifo_is_written_in_place(tmp_path):
    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    got = []
    reader = threading.Thread(target=lambda: got.append(open(fifo, "rb").read()))
    reader.start()
    write_atomic(fifo, b"through the pipe")
    reader.join(10)
    assert got == [b"through the pipe"] and stat.S_ISFIFO(os.lstat(fifo).st_mode)


def test_a_device_node_is_written_in_place_never_replaced(tmp_path):
    node = tmp_path / "null"
    try:
        os.mknod(node, 0o666 | stat.S_IFCHR, os.makedev(1, 3))  # /dev/null's numbers, in a temporary folder
    except PermissionError:
        pytest.skip("creating a device node needs CAP_MKNOD")
    assert resolve(node).in_place
    write_atomic(node, "discarded")
    assert stat.S_ISCHR(os.lstat(node).st_mode) and os.listdir(tmp_path) == ["null"]


def test_an_owned_name_is_replaced_whatever_sits_there(tmp_path):
    fifo = tmp_path / "p7.rec"
    os.mkfifo(fifo)
    write_atomic(fifo, b"record", owned=True)  # never opened: no reader would come
    assert stat.S_ISREG(os.lstat(fifo).st_mode) and fifo.read_bytes() == b"record"


def test_all_or_none_gives_old_contents_back(tmp_path, monkeypatch):
    a, b = tmp_path / "a", tmp_path / "b"
    a.write_text("old a")

    def fail():
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        write_all([(resolve(a), b"new a"), (resolve(b), b"new b")], then=fail)
    assert a.read_text() == "old a" and sorted(os.listdir(tmp_path)) == ["a"]


def test_a_failed_write_leaves_nothing(tmp_path):
    def full(fd, data):
        raise OSError(28, "No space left on device")

    with pytest.raises(OSError, match="No space"):
        write_atomic(tmp_path / "x", b"data", write=full)
    assert os.listdir(tmp_path) == []


def test_the_three_writers_are_this_one(tmp_path, monkeypatch):
    from forcenet.cli.output import write_files
    from forcenet.core.checkpoints import CheckpointStore
    from forcenet.exact.triangle.tables import write_atomic as table_writer

    calls = []
    real = atomic_files.write_all
    monkeypatch.setattr(atomic_files, "write_all", lambda items, **kw: (calls.append(len(items)), real(items, **kw)))
    write_files({str(tmp_path / "out.txt"): "x"})
    table_writer(tmp_path / "t.json", "{}")
    CheckpointStore(tmp_path / "ck", "pfaffian-table", N=5).save(101, np.arange(3))
    assert calls == [1, 1, 1]
