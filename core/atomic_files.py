"""One atomic writer: the command line's files, the exact tables and the checkpoint records.

The policy, in one place:

* a regular file is written to a temporary file in its own folder, flushed to
  disk (``fsync``), renamed over its name (``os.replace``), and the folder is
  synced: a reader sees the old content or the new, never a part, whatever
  kills the writer;
* an existing file keeps its permissions; a new one gets ``0666 & ~umask``
  (``mkstemp`` alone would make it ``0600``);
* a symbolic link is followed: its *target* is replaced, the link stays;
* a character device, a FIFO, a socket or a file reached through ``/proc``
  (``/dev/stdout``) is written in place, never replaced;
* an existing file without write permission is refused, from its mode bits
  (whoever runs the command: root bypasses the permission checks);
* several files are written all or none (:func:`write_all`): on any failure,
  Ctrl-C included, the temporaries are removed and every file already renamed
  is given back its old content (or removed if it was new).

A name the program owns (a checkpoint record, ``owned=True``) is the one
exception: whatever sits there (a FIFO, a device, a link planted in its place)
is replaced by the record, never opened, followed or written into.

Examples
--------
>>> import os, tempfile
>>> path = os.path.join(tempfile.mkdtemp(), "table.json")
>>> write_atomic(path, "{}\\n")
>>> open(path).read()
'{}\\n'
>>> resolve(os.devnull).in_place
True
"""

from __future__ import annotations

import os
import stat
import tempfile
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import cast

from .errors import ArgumentError, ArgumentTypeError, ForcenetError

__all__ = ["TEMP_PREFIX", "DestinationError", "Target", "check_directory", "resolve", "write_all", "write_atomic", "sync_directory"]

_MAX_LINKS = 40  # symbolic links followed, as the kernel does
TEMP_PREFIX = ".tmp-"


class DestinationError(ArgumentError):
    """A destination that cannot be written; the message is the reason alone (the caller names the argument)."""


@dataclass(frozen=True)
class Target:
    """A checked destination: ``path`` is the file written (a link's target), ``in_place`` for a device,
    FIFO, socket or ``/proc`` file (written in place), ``mode`` the permissions of an existing regular file
    (kept; None for a new file), ``owned`` for a name the program owns (replaced whatever it is)."""

    path: str
    in_place: bool = False
    mode: int | None = None
    owned: bool = False


def _through_proc(path: str) -> bool:
    """Whether ``path`` reaches its file through ``/proc`` (``/dev/stdout``, ``/dev/fd/1``, a link to them)."""
    p = os.path.abspath(path)
    for _ in range(_MAX_LINKS):
        if p.startswith("/proc/") or os.path.realpath(os.path.dirname(p)).startswith("/proc/"):
            return True
        if not os.path.islink(p):
            return False
        try:
            p = os.path.join(os.path.dirname(p), os.readlink(p))
        except OSError:  # a link that vanished or cannot be read: not through /proc; opening it reports why
            return False
    return False


def _check_folder(target: str) -> None:
    folder = os.path.dirname(target) or "."
    if not os.path.isdir(folder):
        raise DestinationError(f"the directory {folder} does not exist (create it first)")
    if not os.access(folder, os.W_OK | os.X_OK):
        raise DestinationError(f"the directory {folder} is not writable")


def resolve(path: str | os.PathLike[str]) -> Target:
    """Check ``path`` as a destination before any work, and say how it will be written.

    Parameters
    ----------
    path : str or os.PathLike
        The file to write (a link is followed to its target).

    Returns
    -------
    Target
        The file written and how (in place, or atomically keeping ``mode``).

    Raises
    ------
    DestinationError
        The reason alone (the caller names the argument): an empty name, a
        directory, a missing or read-only folder, an existing file without
        write permission (from its mode bits).

    Examples
    --------
    >>> resolve("")
    Traceback (most recent call last):
    ...
    forcenet.core.atomic_files.DestinationError: an empty file name; give a file name
    """
    path = os.fspath(path)
    if path == "":
        raise DestinationError("an empty file name; give a file name")
    if path.endswith(("/", os.sep)):
        raise DestinationError("ends in '/', a directory; give a file name")
    magic = _through_proc(path)
    try:
        st: os.stat_result | None = os.stat(path)  # follows links
    except (FileNotFoundError, NotADirectoryError):
        st = None  # a new file (or a link to one); a file used as a folder is said below
    except OSError as exc:
        raise DestinationError(exc.strerror or str(exc)) from None
    target = path if magic else os.path.realpath(path)
    if st is None:
        _check_folder(target)
        return Target(target)
    if stat.S_ISDIR(st.st_mode):
        raise DestinationError("is a directory; give a file name")
    if not st.st_mode & 0o222 or not os.access(path, os.W_OK):
        raise DestinationError(f"is read-only (mode {stat.S_IMODE(st.st_mode):o}); make it writable or "
                               "choose another name")
    if magic or not stat.S_ISREG(st.st_mode):
        return Target(target, in_place=True)
    _check_folder(target)
    return Target(target, mode=stat.S_IMODE(st.st_mode))


def _umask() -> int:
    umask = os.umask(0)
    os.umask(umask)
    return umask


def _write_fd(fd: int, data: bytes, write: Callable[[int, memoryview], int]) -> None:
    view = memoryview(data)
    while view:
        view = view[write(fd, view):]


def _write_in_place(target: Target, data: bytes) -> None:
    """A device, FIFO or /dev/stdout: opened without creating or truncating, written whole."""
    flags = os.O_WRONLY | (os.O_APPEND if stat.S_ISREG(os.stat(target.path).st_mode) else 0)
    fd = os.open(target.path, flags)
    try:
        _write_fd(fd, data, os.write)
    finally:
        os.close(fd)


def _temporary(target: Target, data: bytes, umask: int, write: Callable[[int, memoryview], int]) -> str:
    """A temporary file beside ``target`` holding ``data``, flushed to disk, with the target's mode."""
    fd, tmp = tempfile.mkstemp(dir=os.path.dirname(target.path) or ".", prefix=TEMP_PREFIX,
                               suffix="" if target.owned else os.path.basename(target.path))
    try:
        try:
            os.fchmod(fd, target.mode if target.mode is not None else 0o666 & ~umask)  # mkstemp makes 0600
            _write_fd(fd, data, write)
            os.fsync(fd)
        finally:
            os.close(fd)
    except BaseException:
        _unlink(tmp)
        raise
    return tmp


def sync_directory(path: str) -> None:
    """Make a rename in folder ``path`` durable (POSIX: fsync the folder); silently skipped where impossible.

    Examples
    --------
    >>> sync_directory(".")
    """
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


def write_all(items: Sequence[tuple[Target, bytes]], *, then: Callable[[], object] | None = None,
              failure: Callable[[int, OSError], ForcenetError] | None = None,
              write: Callable[[int, memoryview], int] | None = None,
              before_in_place: Callable[[], object] | None = None) -> None:
    """Write every ``(target, data)``, all or none; then call ``then()``.

    Regular files are first written to temporaries beside their targets,
    devices and FIFOs are written in place, then the temporaries are renamed
    (their folders synced) and ``then()`` runs.  On any failure (or Ctrl-C)
    up to the end of ``then()``, the temporaries are removed and every file
    renamed so far gets its old content back (or is removed if it was new).

    Parameters
    ----------
    items : sequence of (Target, bytes)
        The destinations (from :func:`resolve`) and their contents.
    then : callable, optional
        Run after the last rename, inside the all-or-none guarantee.
    failure : callable, optional
        ``failure(i, exc)``: the exception to raise when writing item ``i``
        failed with ``exc`` (default: ``exc`` itself).
    write : callable, optional
        ``os.write``'s stand-in for the temporaries' bytes (tests fault it).
    before_in_place : callable, optional
        Called before the first in-place write (e.g. flushing standard output).

    Examples
    --------
    >>> import os, tempfile
    >>> folder = tempfile.mkdtemp()
    >>> a, b = (os.path.join(folder, name) for name in ("a.txt", "b.txt"))
    >>> write_all([(resolve(a), b"1"), (resolve(b), b"2")])
    >>> sorted(os.listdir(folder)), open(b).read()
    (['a.txt', 'b.txt'], '2')
    """
    def failed(i: int, exc: OSError) -> ForcenetError:  # the caller's error for item i (only with a failure)
        return cast("Callable[[int, OSError], ForcenetError]", failure)(i, exc)

    write = os.write if write is None else write
    umask = _umask()
    temps: dict[int, str] = {}
    renamed: list[tuple[str, str | None]] = []  # (target, backup of its old content or None)
    pending: str | None = None  # the backup of the file being renamed
    keep_old = len(items) > 1 or then is not None  # one file alone: the rename itself is all or none
    try:
        for i, (target, data) in enumerate(items):
            if not target.in_place:
                try:
                    temps[i] = _temporary(target, data, umask, write)
                except OSError as exc:
                    if failure is None:
                        raise
                    raise failed(i, exc) from None
        for i, (target, data) in enumerate(items):
            if target.in_place:
                if before_in_place is not None:
                    before_in_place()
                try:
                    _write_in_place(target, data)
                except BrokenPipeError:
                    raise
                except OSError as exc:
                    if failure is None:
                        raise
                    raise failed(i, exc) from None
        for i, tmp in list(temps.items()):
            target = items[i][0]
            pending = _backup(target.path) if keep_old else None
            try:
                os.replace(tmp, target.path)
            except OSError as exc:
                if failure is None:
                    raise
                raise failed(i, exc) from None
            del temps[i]
            renamed.append((target.path, pending))
            pending = None
            sync_directory(os.path.dirname(target.path) or ".")
        if then is not None:
            then()
    except BaseException:
        for tmp in [*temps.values(), *([pending] if pending else [])]:
            _unlink(tmp)
        for path, backup in reversed(renamed):
            if backup is not None:
                try:
                    os.rename(backup, path)
                except OSError:  # the old content stays in the backup file; the first failure is the one reported
                    pass
            else:
                _unlink(path)
        raise
    for _, backup in renamed:
        if backup is not None:
            _unlink(backup)


def write_atomic(path: str | os.PathLike[str], data: str | bytes, *, owned: bool = False,
                 write: Callable[[int, memoryview], int] | None = None) -> None:
    """Write ``data`` to ``path`` by the one policy (this module's): atomic for a regular file.

    Parameters
    ----------
    path : str or os.PathLike
        The destination, checked by :func:`resolve` (``owned=False``).
    data : str or bytes
        The content (``str`` is encoded as UTF-8).
    owned : bool
        A name the program owns (a checkpoint record): whatever is there is
        replaced, never followed nor written into; its folder must exist.
    write : callable, optional
        ``os.write``'s stand-in (tests fault it).

    Raises
    ------
    DestinationError
        The destination cannot be written (see :func:`resolve`).
    OSError
        The write itself failed (a full disk); nothing is left behind.

    Examples
    --------
    >>> import os, tempfile
    >>> path = os.path.join(tempfile.mkdtemp(), "x.txt")
    >>> write_atomic(path, b"one"); write_atomic(path, "two")
    >>> open(path).read(), [f for f in os.listdir(os.path.dirname(path)) if f != "x.txt"]
    ('two', [])
    """
    target = Target(os.fspath(path), owned=True) if owned else resolve(path)
    write_all([(target, data.encode() if isinstance(data, str) else data)], write=write)


def _backup(target: str) -> str | None:
    """A hard link to the old content of ``target`` (to give it back on failure), or None if it is new."""
    if not os.path.exists(target):
        return None
    for _ in range(100):
        name = os.path.join(os.path.dirname(target), f".bak-{os.urandom(6).hex()}-{os.path.basename(target)}")
        try:
            os.link(target, name)
            return name
        except FileExistsError:
            continue
        except OSError:
            return None  # no hard links here: the old content cannot be kept
    return None


def _unlink(path: str) -> None:
    try:
        os.unlink(path)
    except FileNotFoundError:
        pass


_NAME_MAX = 255  # bytes in one file name (Linux, macOS); the real limit is asked of the folder when it exists


def _name_max(folder: str) -> int:
    try:
        return int(os.pathconf(folder, "PC_NAME_MAX"))
    except (OSError, ValueError, AttributeError):  # no such folder, or a platform without pathconf
        return _NAME_MAX


def check_directory(directory: object, name: str) -> str:
    """The one check of a directory to write into (``checkpoint=`` in Python, ``--checkpoint`` and ``--out-dir``
    at the command line): a path, not empty, that is or can become a writable directory.

    Parameters
    ----------
    directory : object
        What the caller gave.
    name : str
        The argument as the caller spelled it (``"checkpoint"``, ``"--checkpoint"``): an option (``--...``) is
        shown as ``--name=value``, a keyword as ``name='value'``.

    Returns
    -------
    str
        The path (``os.fspath``); nothing is created.

    Raises
    ------
    ArgumentTypeError
        If ``directory`` is not a ``str`` or ``os.PathLike`` of ``str``.
    ArgumentError
        If it is empty, a file or a device, a symbolic link that leads nowhere (a loop, a missing target), a
        name longer than the file system takes, or in (or under) a folder missing or not writable.

    Examples
    --------
    >>> import tempfile
    >>> d = tempfile.mkdtemp()
    >>> check_directory(d, "checkpoint") == d
    True
    >>> check_directory("", "checkpoint")
    Traceback (most recent call last):
    ...
    forcenet.core.errors.ArgumentError: checkpoint='': an empty directory name; give a directory (e.g. checkpoint='.')
    >>> check_directory(os.devnull, "--checkpoint")
    Traceback (most recent call last):
    ...
    forcenet.core.errors.ArgumentError: --checkpoint=/dev/null: exists and is not a directory
    """
    option = name.startswith("-")
    if isinstance(directory, os.PathLike):
        directory = os.fspath(directory)
    if not isinstance(directory, str):
        raise ArgumentTypeError(f"{name}={directory!r} is not a directory path: give a str or os.PathLike")
    shown = f"{name}={directory}" if option and directory else f"{name}={directory!r}"
    if directory == "":
        raise ArgumentError(f"{shown}: an empty directory name; give a directory (e.g. {name}="
                            f"{'.' if option else repr('.')})")
    if "\0" in directory:
        raise ArgumentError(f"{shown}: a directory name with a NUL character; give a directory path")
    absolute = os.path.abspath(directory)
    if os.path.lexists(absolute) and not os.path.exists(absolute):  # a link to nowhere, or a loop of links
        raise ArgumentError(f"{shown}: a symbolic link that leads to no directory (a loop or a missing target)")
    if os.path.exists(absolute):
        if not os.path.isdir(absolute):
            raise ArgumentError(f"{shown}: exists and is not a directory")
        if not os.access(absolute, os.W_OK | os.X_OK):
            raise ArgumentError(f"{shown}: the directory is not writable")
        return directory
    parent = os.path.dirname(absolute)
    if not os.path.isdir(parent):
        raise ArgumentError(f"{shown}: its parent {parent} does not exist or is not a directory")
    limit = _name_max(parent)
    if len(os.fsencode(os.path.basename(absolute))) > limit:
        raise ArgumentError(f"{shown}: the name is longer than the {limit} bytes a file name may have here")
    if not os.access(parent, os.W_OK | os.X_OK):
        raise ArgumentError(f"{shown}: cannot be created, {parent} is not writable")
    return directory
