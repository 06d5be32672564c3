"""Checkpoints: every finished task of a long run recorded durably, so a rerun recomputes only what is missing.

One record per task (per prime of a multi-modular route), one file per
record, written by the client as results arrive (workers need no shared file
system).  A record is ::

    b"forcenet-checkpoint\\n" | header length (8 bytes) | header (JSON) | payload | SHA-256 of all before

The header names the request (``route``, ``N``, ``moments``, ``prime``) and
the format version, and describes the payload (an integer numpy array:
``dtype``, ``shape``).  The guarantees, each tested in
``tests/test_checkpoints.py``:

* **atomic**: a record is written to a temporary file beside it, flushed to
  disk (``fsync``), then renamed over its name (``os.replace``), and the
  directory is synced; a reader sees a whole record or none, whatever kills
  the writer (SIGKILL, Ctrl-C, a power cut);
* **checked**: a truncated or bit-flipped record fails its checksum (or its
  framing), is reported in one line and recomputed, never trusted;
* **per request**: a record whose header names another request or format
  version is ignored (and overwritten by the recomputed one);
* **concurrent writers**: two processes on the same request write distinct
  temporary files and rename them; the last rename wins and both are whole;
* **killed writers**: a temporary file left by a writer killed before its
  rename never counts as a record, and is removed by the next run after
  ten minutes;
* **full disk** (or any write error): the temporary file is removed, the
  problem reported once in one line, and the run continues without further
  checkpoints; records already written stay valid.

Atomic files rather than sqlite3: damage stays confined to one record (a
flipped bit inside an SQLite page is not detected by SQLite, and a damaged
page can make the whole database unreadable), and every guarantee above is a
property of ``rename`` and a checksum that the tests can fault directly.

May import: nothing of the package.

Examples
--------
>>> import tempfile, numpy as np
>>> store = CheckpointStore(tempfile.mkdtemp(), "pfaffian-table", N=5)
>>> store.save(101, np.arange(4).reshape(2, 2))
>>> store.load(101).tolist(), store.load(103)
([[0, 1], [2, 3]], None)
"""

from __future__ import annotations

import errno
import hashlib
import json
import os
import struct
import sys
import tempfile
import time

import numpy as np

__all__ = ["FORMAT_VERSION", "default_directory", "CheckpointStore"]

FORMAT_VERSION = 1
_MAGIC = b"forcenet-checkpoint\n"
_LENGTH = struct.Struct("<Q")
_DIGEST = 32
_TEMP_PREFIX = ".tmp-"
_STALE_SECONDS = 600  # a temporary file this old belongs to a killed writer
_write = os.write  # one name for every byte written (the full-disk tests fault it)


def default_directory() -> str:
    """Where runs announced at over a minute keep their checkpoints: ``$XDG_CACHE_HOME/forcenet``, else ``~/.cache/forcenet``.

    Examples
    --------
    >>> default_directory().endswith("forcenet")
    True
    """
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return os.path.join(base, "forcenet")


def _stderr_line(message: str) -> None:
    print(f"forcenet: {message}", file=sys.stderr)


class CheckpointStore:
    """The records of one request (route, ``N``, ``moments``) in a directory.

    Parameters
    ----------
    directory : str or os.PathLike
        The checkpoint directory; each request has its own folder inside
        (created on the first save).
    route : str
        The route's name, e.g. ``"pfaffian-table"``.
    N, moments : int
        The request.
    report : callable, optional
        Receives each one-line report (a damaged record, a write failure);
        default: printed on stderr.

    Attributes
    ----------
    path : str
        The request's folder.
    reused, saved, damaged, ignored : int
        Records loaded, written, found damaged and found of another request, so far.
    failed : str or None
        Why saving stopped (e.g. a full disk), or None.
    """

    def __init__(self, directory, route: str, N: int, moments: int = 1, report=None):
        self.directory = os.fspath(directory)
        self.request = {"format": FORMAT_VERSION, "route": str(route), "N": int(N), "moments": int(moments)}
        self.path = os.path.join(self.directory, f"{route}-N{int(N)}-m{int(moments)}-v{FORMAT_VERSION}")
        self.report = report if report is not None else _stderr_line
        self.reused = self.saved = self.damaged = self.ignored = 0
        self.failed: str | None = None

    def __repr__(self) -> str:
        return f"CheckpointStore({self.path!r})"

    def _file(self, key: int) -> str:
        return os.path.join(self.path, f"p{int(key)}.rec")

    def encode(self, key: int, value) -> bytes:
        """The record of ``value`` (an integer array or integer) under ``key``."""
        array = np.asarray(value, dtype=np.int64)
        header = dict(self.request, prime=int(key), dtype="<i8", shape=list(array.shape))
        head = json.dumps(header, sort_keys=True).encode()
        body = _MAGIC + _LENGTH.pack(len(head)) + head + array.astype("<i8").tobytes(order="C")
        return body + hashlib.sha256(body).digest()

    def decode(self, key: int, data: bytes):
        """``(array, None)`` for a valid record of this request, else ``(None, reason)``; ``reason`` starts
        with ``"another request"`` for a whole record that is not this request's."""
        start = len(_MAGIC) + _LENGTH.size
        if len(data) < start + _DIGEST or not data.startswith(_MAGIC):
            return None, f"truncated or not a record ({len(data)} bytes)"
        if hashlib.sha256(data[:-_DIGEST]).digest() != data[-_DIGEST:]:
            return None, "checksum mismatch (truncated or corrupted)"
        (length,) = _LENGTH.unpack_from(data, len(_MAGIC))
        try:
            header = json.loads(data[start:start + length])
            shape = tuple(int(s) for s in header["shape"])
            array = np.frombuffer(data[start + length:-_DIGEST], dtype="<i8").reshape(shape)
        except (ValueError, KeyError, TypeError):
            return None, "malformed header"
        if {k: header.get(k) for k in self.request} != self.request or header.get("prime") != int(key):
            return None, "another request"
        return array.astype(np.int64), None

    def load(self, key: int):
        """The recorded value of ``key`` (a numpy int64 array), or None (missing, damaged, another request)."""
        try:
            with open(self._file(key), "rb") as handle:
                data = handle.read()
        except FileNotFoundError:
            return None
        except OSError as exc:
            self.report(f"checkpoint {self._file(key)}: unreadable ({exc.strerror}); recomputing it")
            return None
        value, reason = self.decode(key, data)
        if value is None:
            if reason.startswith("another request"):
                self.ignored += 1
            else:
                self.damaged += 1
                self.report(f"checkpoint {self._file(key)}: {reason}; recomputing it")
            return None
        self.reused += 1
        return value

    def holds(self, key: int) -> bool:
        """Whether a record of ``key`` exists (not yet verified: :meth:`load` checks it)."""
        return os.path.isfile(self._file(key))

    def save(self, key: int, value) -> None:
        """Record ``value`` under ``key`` atomically; on a write error report once and stop saving."""
        if self.failed is not None:
            return
        data = self.encode(key, value)
        tmp = None
        try:
            os.makedirs(self.path, exist_ok=True)
            if self.saved == 0:
                _sweep(self.path)
            fd, tmp = tempfile.mkstemp(dir=self.path, prefix=_TEMP_PREFIX)
            try:
                view = memoryview(data)
                while view:
                    view = view[_write(fd, view):]
                os.fsync(fd)
            finally:
                os.close(fd)
            os.replace(tmp, self._file(key))
            tmp = None
            _sync_directory(self.path)
            self.saved += 1
        except OSError as exc:
            self.failed = exc.strerror or str(exc)
            kind = "the disk is full" if exc.errno in (errno.ENOSPC, errno.EDQUOT) else self.failed
            self.report(f"checkpoint {self.path}: cannot write ({kind}); continuing without checkpoints")
        finally:
            if tmp is not None:
                try:
                    os.unlink(tmp)
                except OSError:
                    pass


def _sweep(path: str) -> None:
    """Remove temporary files left by writers killed before their rename (older than a live write can be)."""
    now = time.time()
    for name in os.listdir(path):
        if name.startswith(_TEMP_PREFIX):
            try:
                if now - os.path.getmtime(os.path.join(path, name)) > _STALE_SECONDS:
                    os.unlink(os.path.join(path, name))
            except OSError:  # another process removed it first
                pass


def _sync_directory(path: str) -> None:
    """Make a rename durable (POSIX: fsync the directory)."""
    try:
        fd = os.open(path, os.O_RDONLY)
    except OSError:  # pragma: no cover - platforms without directory handles
        return
    try:
        os.fsync(fd)
    except OSError:  # pragma: no cover - file systems refusing directory fsync
        pass
    finally:
        os.close(fd)
