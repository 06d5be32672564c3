"""Where results go: files, devices, pipes and standard output, each checked before the work.

The policy, in one place:

* every destination (``--out``, ``--plot``, the files of ``--out-dir``, and
  standard output when it receives the result) is checked before any
  computation: :func:`destination`, :func:`check_output_dir`,
  :func:`check_stdout`;
* a regular file is written atomically: a temporary file beside it, renamed
  over it at the end (a symbolic link is followed: its *target* is replaced,
  the link stays; an existing file keeps its permissions);
* a character device, a FIFO, a socket or ``/dev/stdout`` (anything reached
  through ``/proc``) is written in place, never replaced;
* an existing file without write permission is refused, whoever runs the
  command (its mode bits are read: root bypasses the permission checks);
* several files are written all or none (:func:`write_files`): on any failure,
  Ctrl-C included, the temporaries are removed and every file already
  renamed is given back its old content, or removed if it is new;
* messages name the user's path and the argument, never a temporary file,
  and say "standard output" when that is what failed.
"""

from __future__ import annotations

import os
import sys
from collections.abc import Callable, Iterable
from dataclasses import dataclass

from forcenet.core import atomic_files
from forcenet.core.errors import ArgumentError

from .common import UsageError

__all__ = ["Destination", "destination", "check_output_path", "check_output_dir", "check_stdout", "emit",
           "write_stdout", "write_files", "EXIT_DISAGREES", "EXIT_CANNOT_JUDGE", "EXIT_CODES"]

# exit codes of every command (README "Command line", forcenet --help): one meaning each
EXIT_DISAGREES = 3  # the main job's Monte Carlo cross-check found the table and the samples in disagreement
EXIT_CANNOT_JUDGE = 4  # the cross-check's samples cannot support a verdict (too few to reveal a wrong mean)
EXIT_CODES = """\
exit codes: 0 done (the cross-check agrees); 1 internal error (a bug: please
report it); 2 bad input, a refused run or a file-system error (one line on
stderr); 3 the main job's cross-check DISAGREES; 4 the cross-check cannot
judge (too few samples); 130 interrupted."""

STDOUT = "standard output"


@dataclass(frozen=True)
class Destination:
    """A checked output path: ``given`` by the user as argument ``name``; ``target`` is the file written."""

    given: str
    name: str
    target: str
    in_place: bool  # a device, FIFO, socket or a file reached through /proc (/dev/stdout): written in place
    mode: int | None  # permissions of the existing regular file (kept), None for a new file


def destination(path: str, name: str = "--out") -> Destination:
    """Check ``path`` as an output file before any work; how it will be written (:mod:`forcenet.core.atomic_files`).

    Raises
    ------
    UsageError
        One line naming ``name`` and ``path``: an empty name, a directory, a
        missing or read-only directory, or an existing file without write
        permission (from its mode bits, whoever runs the command).

    Examples
    --------
    >>> destination("/dev/null").in_place
    True
    >>> destination("")
    Traceback (most recent call last):
    ...
    forcenet.cli.common.UsageError: --out='': an empty file name; give a file name
    """
    try:
        target = atomic_files.resolve(path)
    except atomic_files.DestinationError as exc:
        raise UsageError(f"{name}={path or repr(path)}: {exc}") from None
    return Destination(path, name, target.path, target.in_place, target.mode)


def check_output_path(path: str | None, name: str = "--out") -> None:
    """Fail early (before any computation) on an output file that cannot be written."""
    if path is not None:
        destination(path, name)


def check_output_dir(directory: str, name: str = "--out-dir", files: Iterable[str] = ()) -> None:
    """Fail early on an output directory that is a file or whose parent is missing or read-only.

    ``files``: the names that will be written inside it, checked as destinations if the directory exists.
    """
    try:  # the one check, shared with Python's checkpoint= (forcenet.core.atomic_files.check_directory)
        atomic_files.check_directory(directory, name)
    except ArgumentError as exc:
        raise UsageError(str(exc)) from None
    if os.path.isdir(directory):
        for file in files:
            destination(os.path.join(directory, file), name)


def check_stdout() -> None:
    """Fail early when standard output, which is to receive the result, is closed."""
    if sys.stdout is None:
        raise UsageError(f"{STDOUT} is closed: nothing can be printed; give --out FILE or open it")


def write_stdout(text: str) -> None:
    """Print ``text`` and flush; a failure (a full disk, a closed stream) names standard output."""
    check_stdout()
    try:
        sys.stdout.write(text)
        sys.stdout.flush()
    except BrokenPipeError:  # the reader left (`| head`): main() ends quietly
        raise
    except (OSError, ValueError) as exc:  # ValueError: a closed stream
        _discard_stdout()
        reason = exc.strerror if isinstance(exc, OSError) and exc.strerror else str(exc)
        raise UsageError(f"{STDOUT}: {reason}") from None


def _discard_stdout() -> None:
    """Point file descriptor 1 at /dev/null: what is still buffered is dropped at exit, silently."""
    try:
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
    except (OSError, ValueError, AttributeError):
        pass


def emit(text: str, out: str | None = None, name: str = "--out") -> None:
    """Print ``text`` on stdout, or write it to ``out`` (atomically for a regular file)."""
    if not text.endswith("\n"):
        text += "\n"
    if out is None:
        write_stdout(text)
        return
    write_files({out: text}, name=name)


def _failure(dest: Destination, exc: OSError) -> UsageError:
    return UsageError(f"{dest.name}={dest.given}: {exc.strerror or exc}")


def write_files(files: dict, name: str = "--out", make_dir: str | None = None, names: dict | None = None,
                then: Callable[[], object] | None = None) -> None:
    """Write every ``{path: text}`` (``text`` may be ``bytes``), all or none; then call ``then()``.

    The one writer, :func:`forcenet.core.atomic_files.write_all`: regular
    files are first written to temporaries beside their targets, devices and
    FIFOs are written in place, then the temporaries are renamed and
    ``then()`` runs (e.g. the summary on standard output).  On any failure
    (or Ctrl-C) up to the end of ``then()``, the temporaries are removed,
    every file renamed so far gets its old content back (or is removed if it
    was new), and the directory ``make_dir`` is removed if this call created
    it.  ``names`` gives the argument of each path (default ``name``) for
    messages.
    """
    names = names or {}
    created = None
    try:
        if make_dir is not None and not os.path.isdir(make_dir):
            check_output_dir(make_dir)
            try:
                os.mkdir(make_dir)
            except OSError as exc:
                raise UsageError(f"{name}={make_dir}: cannot create the folder ({exc.strerror or exc})") from None
            created = make_dir
        dests = [(destination(path, names.get(path, name)), text) for path, text in files.items()]
        items = [(atomic_files.Target(dest.target, dest.in_place, dest.mode), text if isinstance(text, bytes)
                  else text.encode()) for dest, text in dests]
        atomic_files.write_all(items, then=then, failure=lambda i, exc: _failure(dests[i][0], exc),
                               before_in_place=_flush_stdout)
    except BaseException:
        if created is not None and os.path.isdir(created) and not os.listdir(created):
            os.rmdir(created)
        raise


def _flush_stdout() -> None:
    if sys.stdout is not None:
        sys.stdout.flush()
