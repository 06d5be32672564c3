"""Checkpoints: every finished task of a long run recorded durably, so a rerun recomputes only what is missing.

One record per task (per prime of a multi-modular route), one file per
record, written by the client as results arrive (workers need no shared file
system).  A record is ::

    b"forcenet-checkpoint\\n" | header length (8 bytes) | header (JSON) | payload | SHA-256 of all before

The header names the request (``route``, ``N``, ``moments``, ``prime``) and
the format version, and describes the payload (an integer numpy array:
``dtype``, ``shape``).  The guarantees, each tested in
``tests/test_checkpoints.py``:

* **atomic**: a record is written by the package's one writer
  (:func:`forcenet.core.atomic_files.write_atomic`): a temporary file beside
  it, flushed to disk (``fsync``), then renamed over its name
  (``os.replace``), and the directory is synced; a reader sees a whole record or none, whatever kills
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
  checkpoints; records already written stay valid;
* **regular files only**: a FIFO, a device, a socket or a symbolic link
  named like a record is never opened as one (``lstat`` first, then
  ``O_NONBLOCK | O_NOFOLLOW`` and ``fstat`` on the handle, and at most
  :data:`MAX_RECORD_BYTES` read): reported in one line and recomputed;
* **one line per cause**: a directory that cannot be used (a file in its
  place, no permission, a home directory that does not exist) is reported
  once, and the run continues without checkpoints; no folder above the
  checkpoint directory (above the home directory for the default) is ever
  created;
* **valid checksum, wrong content**: a record written by a faulty program
  (or by hand) passes its checksum; when the run's own exact checks then
  fail, :func:`distrust_reused` sets the reused records aside, the run is
  repeated, and every record whose recomputation differs is named on
  stderr and dropped (the others are kept).

Atomic files rather than sqlite3: damage stays confined to one record (a
flipped bit inside an SQLite page is not detected by SQLite, and a damaged
page can make the whole database unreadable), and every guarantee above is a
property of ``rename`` and a checksum that the tests can fault directly.

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
import shutil
import stat
import struct
import sys
import tempfile
import time
from collections.abc import Callable, Collection
from dataclasses import replace
from typing import TYPE_CHECKING, Any, TypeVar

import numpy as np

from forcenet.core.atomic_files import TEMP_PREFIX, write_atomic
from forcenet.core.compiled import cache_home

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

    from forcenet.core.plan import Plan

T = TypeVar("T")

__all__ = ["FORMAT_VERSION", "MAX_RECORD_BYTES", "default_directory", "CheckpointStore", "distrust_reused", "run_distrusting",
           "records_held", "resumed_plan"]

FORMAT_VERSION = 1
_MAGIC = b"forcenet-checkpoint\n"
_LENGTH = struct.Struct("<Q")
_DIGEST = 32
_TEMP_PREFIX = TEMP_PREFIX
_STALE_SECONDS = 600  # a temporary file this old belongs to a killed writer
_write = os.write  # one name for every byte written (the full-disk tests fault it)
MAX_RECORD_BYTES = 2**31  # no record of any route is larger (N = 200's table: ~0.3 MiB per prime)


def default_directory() -> str:
    """Where runs announced at over a minute keep their checkpoints: ``$XDG_CACHE_HOME/forcenet``, else ``~/.cache/forcenet``.

    Examples
    --------
    >>> default_directory().endswith("forcenet")
    True
    """
    return os.path.join(cache_home(), "forcenet")


def _default_anchor() -> str:
    """The folder the default checkpoint directory may be created under, which must exist already: the parent of
    ``$XDG_CACHE_HOME``, else the home directory."""
    xdg = os.environ.get("XDG_CACHE_HOME", "")
    return os.path.dirname(xdg) if os.path.isabs(xdg) else os.path.expanduser("~")


_REPORTED: set[tuple[str, str]] = set()  # (directory, cause) already reported in this run: one line per cause


def _once(report: Callable[[str], object], directory: str, cause: str, message: str) -> None:
    """``report(message)`` unless this cause in this directory was reported already in this run (every layer's
    store of a run shares the directory: a full disk is one line, not one per layer)."""
    key = (os.path.abspath(directory), cause)
    if key not in _REPORTED:
        _REPORTED.add(key)
        report(message)


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
    shape : tuple of int, optional
        The shape every record of the request has, when the route knows it: a record of another shape
        (a valid checksum on the wrong content) is named and recomputed like a damaged one.

    Attributes
    ----------
    path : str
        The request's folder.
    reused, saved, damaged, ignored : int
        Records loaded, written, found damaged and found of another request, so far.
    failed : str or None
        Why saving stopped (e.g. a full disk), or None.
    """

    def __init__(self, directory: str | os.PathLike[str], route: str, N: int, moments: int = 1,
                 report: Callable[[str], object] | None = None, shape: tuple[int, ...] | None = None) -> None:
        self.directory = os.fspath(directory)
        self.shape = None if shape is None else tuple(int(s) for s in shape)  # every record's, when known
        self.request = {"format": FORMAT_VERSION, "route": str(route), "N": int(N), "moments": int(moments)}
        self.path = os.path.join(self.directory, f"{route}-N{int(N)}-m{int(moments)}-v{FORMAT_VERSION}")
        self.report = report if report is not None else _stderr_line
        self.reused = self.saved = self.damaged = self.ignored = 0
        self.failed: str | None = None
        self._usable: bool | None = None  # decided on first use
        default = os.path.abspath(self.directory) == os.path.abspath(default_directory())
        self._anchor = _default_anchor() if default else os.path.dirname(os.path.abspath(self.directory))

    def __repr__(self) -> str:
        return f"CheckpointStore({self.path!r})"

    def _file(self, key: int) -> str:
        return os.path.join(self.path, f"p{int(key)}.rec")

    def encode(self, key: int, value: ArrayLike) -> bytes:
        """The record of ``value`` (an integer array or integer) under ``key``."""
        array = np.asarray(value, dtype=np.int64)
        header = dict(self.request, prime=int(key), dtype="<i8", shape=list(array.shape))
        head = json.dumps(header, sort_keys=True).encode()
        body = _MAGIC + _LENGTH.pack(len(head)) + head + array.astype("<i8").tobytes(order="C")
        return body + hashlib.sha256(body).digest()

    def decode(self, key: int, data: bytes) -> tuple[np.ndarray | None, Any]:
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
        if self.shape is not None and array.shape != self.shape:  # a valid checksum on a record that cannot fit
            return None, f"a record of shape {array.shape} where {self.shape} belongs"
        return array.astype(np.int64), None

    def _folder_problem(self) -> str | None:
        """Why the request's folder cannot hold records (one reason for every record), or None."""
        if not os.path.isdir(self._anchor):
            return f"{self._anchor} does not exist (it is not created for checkpoints)"
        path = self.path
        while True:
            try:
                mode = os.stat(path).st_mode
            except FileNotFoundError:
                parent = os.path.dirname(path)
                if parent == path:
                    return None
                path = parent
                continue
            except OSError as exc:
                return f"{path}: {exc.strerror}"
            if not stat.S_ISDIR(mode):
                return f"{path} is not a directory"
            if path == self.path and not os.access(path, os.R_OK | os.X_OK):
                return f"{path}: permission denied"
            return None

    def usable(self) -> bool:
        """Whether the folder can hold records; if not, reported once (one line) and the run goes on without."""
        if self._usable is None:
            problem = self._folder_problem()
            self._usable = problem is None
            if problem is not None:
                self.failed = problem
                _once(self.report, self.directory, problem, f"checkpoints disabled: {problem}; continuing without "
                      "checkpoints (give another directory: checkpoint= in Python, --checkpoint DIR at the command "
                      "line; or none)")
        return self._usable

    def load(self, key: int) -> np.ndarray | None:
        """The recorded value of ``key`` (a numpy int64 array), or None (missing, damaged, another request)."""
        if not self.usable():
            return None
        name = self._file(key)
        try:
            info = os.lstat(name)
        except FileNotFoundError:
            return None
        except OSError as exc:
            self.report(f"checkpoint {name}: unreadable ({exc.strerror}); recomputing it")
            return None
        problem = _not_a_record(info)
        if problem is None:
            try:
                fd = os.open(name, os.O_RDONLY | os.O_NONBLOCK | getattr(os, "O_NOFOLLOW", 0))
                try:
                    info = os.fstat(fd)  # the file opened, not whatever the name pointed at before
                    problem = _not_a_record(info)
                    data = b"" if problem else _read_at_most(fd, info.st_size)
                finally:
                    os.close(fd)
            except OSError as exc:
                self.report(f"checkpoint {name}: unreadable ({exc.strerror}); recomputing it")
                return None
        if problem is not None:
            self.damaged += 1
            self.report(f"checkpoint {name}: {problem}, not a record; ignored and recomputed")
            return None
        value, reason = self.decode(key, data)
        if value is None:
            if reason.startswith("another request"):
                self.ignored += 1
            else:
                self.damaged += 1
                self.report(f"checkpoint {name}: {reason}; recomputing it")
            return None
        self.reused += 1
        return value

    def holds(self, key: int) -> bool:
        """Whether a record of ``key`` exists (a regular file; not yet verified: :meth:`load` checks it)."""
        try:
            return stat.S_ISREG(os.lstat(self._file(key)).st_mode)
        except OSError:
            return False

    def save(self, key: int, value: ArrayLike) -> None:
        """Record ``value`` under ``key`` atomically; on a write error report once and stop saving."""
        if self.failed is not None or not self.usable():
            return
        data = self.encode(key, value)
        try:
            os.makedirs(self.path, exist_ok=True)
            if self.saved == 0:
                _sweep(self.path)
            # the one writer (temporary file, fsync, rename, folder synced); a record's name is the store's own:
            # a FIFO, device or link planted there is replaced, never opened
            write_atomic(self._file(key), data, owned=True, write=_write)
            self.saved += 1
        except OSError as exc:
            self.failed = exc.strerror or str(exc)
            kind = "the disk is full" if exc.errno in (errno.ENOSPC, errno.EDQUOT) else self.failed
            _once(self.report, self.directory, kind,
                  f"checkpoint {self.path}: cannot write ({kind}); continuing without checkpoints")


def _not_a_record(info: os.stat_result) -> str | None:
    """Why a file of this kind and size cannot be a record, or None for a regular file of a possible size."""
    mode = info.st_mode
    if not stat.S_ISREG(mode):
        kinds = ((stat.S_ISFIFO, "a FIFO"), (stat.S_ISCHR, "a character device"), (stat.S_ISBLK, "a block device"),
                 (stat.S_ISSOCK, "a socket"), (stat.S_ISLNK, "a symbolic link"), (stat.S_ISDIR, "a directory"))
        return next((text for test, text in kinds if test(mode)), "not a regular file")
    if info.st_size > MAX_RECORD_BYTES:
        return f"{info.st_size} bytes, more than any record"
    return None


def _read_at_most(fd: int, size: int) -> bytes:
    """The ``size`` bytes of a regular file (fewer if it shrank; never more than ``size + 1``)."""
    chunks, left = [], size + 1
    while left > 0:
        chunk = os.read(fd, min(left, 2**24))
        if not chunk:
            break
        chunks.append(chunk)
        left -= len(chunk)
    return b"".join(chunks)


def distrust_reused(run: Callable[[], T], directory: str | os.PathLike[str] | None, N: int, started: float,
                    report: Callable[[str], object] | None = None) -> T:
    """``run()``; if it fails its exact checks (``ArithmeticError``) after reusing records, repeat it without them.

    A record with a valid checksum but wrong content (a faulty program, a hand edit) is only caught by the
    route's own exact checks, after the Chinese remaindering.  The records of ``N`` in ``directory`` older
    than ``started`` (the ones this run reused, not the ones it wrote) are moved aside, ``run()`` is repeated
    (recomputing them), and each record whose recomputation differs is named on stderr and dropped; records
    set aside that the repeated run did not write again (another request's) are put back.  Without reused
    records, or if the repeated run fails too, the error is a bug and propagates.

    Parameters
    ----------
    run : callable
        The whole run, no arguments.
    directory : str or os.PathLike or None
        The checkpoint directory (None: just ``run()``).
    N : int
        The request's size: the folders of ``N`` are examined.
    started : float
        ``time.time()`` when the run began.
    report : callable, optional
        Receives each one-line report (default: stderr).

    Examples
    --------
    >>> distrust_reused(lambda: 42, None, 12, 0.0)
    42
    """
    _REPORTED.clear()  # a new run: each cause is reported again, once
    if directory is None:
        return run()
    report = report if report is not None else _stderr_line
    try:
        return run()
    except ArithmeticError as failure:
        directory = os.fspath(directory)
        reused = _records_before(directory, N, started)
        if not reused:
            raise
        aside = tempfile.mkdtemp(prefix=".suspect-", dir=directory)
        report(f"the run's exact checks failed ({failure}) after reusing {len(reused)} checkpoint records of "
               f"N={N} in {directory}: setting them aside and recomputing them once")
        moved = {}
        for k, path in enumerate(reused):
            target = os.path.join(aside, f"{k}.rec")
            os.replace(path, target)
            moved[path] = target
        try:
            result = run()
        finally:
            for path, target in moved.items():
                if not os.path.exists(path):  # not written again: another request's, or the run failed: put back
                    os.replace(target, path)
                    continue
                with open(path, "rb") as new, open(target, "rb") as old:
                    if new.read() != old.read():
                        report(f"checkpoint {path}: valid checksum but wrong content (its recomputation differs); "
                               "dropped and replaced by the recomputed record")
            shutil.rmtree(aside, ignore_errors=True)
        return result


def records_held(directory: str | os.PathLike[str], N: int, routes: Collection[str]) -> int:
    """How many record files (regular files, not yet verified) the requests of ``N`` of ``routes`` hold in
    ``directory`` (a route's name, or the name and a layer ``i``: a run with one request per layer).

    Examples
    --------
    >>> import tempfile
    >>> d = tempfile.mkdtemp()
    >>> CheckpointStore(d, "pfaffian-layer-grains3", N=5).save(101, 7)
    >>> records_held(d, 5, ("pfaffian-layer-grains", "pfaffian-floor-grains")), records_held(d, 5, ("pfaffian-layer",))
    (1, 0)
    """
    held = 0
    try:
        folders = os.listdir(directory)
    except OSError:
        return 0
    mark = f"-N{int(N)}-m"
    for folder in folders:
        if mark not in folder or not folder.endswith(f"-v{FORMAT_VERSION}"):
            continue
        route = folder[:folder.index(mark)]
        if route not in routes and route.rstrip("0123456789") not in routes:  # a layer's route: the name + i
            continue
        try:
            entries = list(os.scandir(os.path.join(directory, folder)))
        except OSError:
            continue
        held += sum(1 for e in entries if e.name.endswith(".rec") and not e.name.startswith(_TEMP_PREFIX)
                    and e.is_file(follow_symlinks=False))
    return held


def run_distrusting(checkpoint: CheckpointStore | str | os.PathLike[str] | None, N: int, attempt: Callable[[], T]) -> T:
    """``attempt()``, repeated once without the reused records if the route's exact checks fail
    (:func:`distrust_reused`: a record with a valid checksum but wrong content is named, dropped, recomputed).

    Parameters
    ----------
    checkpoint : CheckpointStore, str, os.PathLike or None
        The run's store, or its directory (one request per layer), or None.
    N : int
        The request's size.
    attempt : callable
        The whole run, no arguments.

    Examples
    --------
    >>> run_distrusting(None, 12, lambda: 42)
    42
    """
    started = time.time()

    def fresh() -> T:
        if isinstance(checkpoint, CheckpointStore):
            checkpoint.reused = checkpoint.saved = checkpoint.damaged = checkpoint.ignored = 0
        return attempt()

    directory = checkpoint.directory if isinstance(checkpoint, CheckpointStore) else checkpoint
    return distrust_reused(fresh, directory, N, started)


def resumed_plan(plan: Plan, directory: str | os.PathLike[str], N: int, routes: Collection[str],
                 fixed: float = 0.0) -> Plan:
    """``plan`` (one tick per prime) with the records already held in ``directory`` counted: its time without
    the compilation and without the ``fixed`` seconds every run pays whatever it reuses (the start-up of the
    process) scaled by the share still to compute, and the reuse stated in its description.

    For requests of about equal cost per prime (the pooled layers of the ensemble); a route whose requests
    differ plans each with its own held records instead (the table's moments, layer by layer).

    Examples
    --------
    >>> import tempfile
    >>> from forcenet.core.plan import Plan
    >>> d = tempfile.mkdtemp()
    >>> resumed_plan(Plan("x", 10.0, 0, 4, "prime"), d, 5, ("pfaffian-floor-grains",)).seconds
    10.0
    >>> CheckpointStore(d, "pfaffian-floor-grains", N=5).save(101, 7)
    >>> p = resumed_plan(Plan("x", 10.0, 0, 4, "prime"), d, 5, ("pfaffian-floor-grains",))
    >>> p.seconds, p.what.startswith("x; 1 of 4 primes recorded in ")
    (7.5, True)
    >>> resumed_plan(Plan("x", 10.0, 0, 4, "prime"), d, 5, ("pfaffian-floor-grains",), fixed=2.0).seconds
    8.0
    """
    ticks = max(int(plan.ticks), 1)
    held = min(records_held(directory, N, routes), ticks)
    if not held:
        return plan
    kept = sum(seconds for _, seconds in plan.compiling) + min(fixed, plan.seconds)  # paid by every run
    seconds = kept + (plan.seconds - kept) * (ticks - held) / ticks
    return replace(plan, what=f"{plan.what}; {held} of {ticks} primes recorded in {os.fspath(directory)}", seconds=seconds)


def _records_before(directory: str, N: int, started: float) -> list[str]:
    """The regular record files of ``N``'s folders in ``directory`` last written before ``started``."""
    found = []
    try:
        folders = [f for f in os.listdir(directory) if f"-N{int(N)}-m" in f and f.endswith(f"-v{FORMAT_VERSION}")]
    except OSError:
        return []
    for folder in folders:
        path = os.path.join(directory, folder)
        try:
            names = os.listdir(path)
        except OSError:
            continue
        for name in names:
            file = os.path.join(path, name)
            if name.endswith(".rec") and not name.startswith(_TEMP_PREFIX):
                try:
                    info = os.lstat(file)
                except OSError:
                    continue
                if stat.S_ISREG(info.st_mode) and info.st_mtime < started:
                    found.append(file)
    return sorted(found)


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
