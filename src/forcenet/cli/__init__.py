"""Command line interface: ``forcenet count|table|maps|limit|sample|transfer|bethe|entropy|dist|network``.

A small parser; one module per command family (:mod:`.table`, :mod:`.sample`,
:mod:`.limit`, :mod:`.chicken_wire`), the shared arguments and the policy in
:mod:`.common`.  :func:`main` is the one error boundary: every expected
failure -- the exception family :class:`forcenet.ForcenetError` (bad argument,
refused plan, a file or stream that cannot be written: the writers of
:mod:`.output` turn the ``OSError`` of their own operations into the family,
naming the argument), memory, interruption -- ends in one line on
stderr naming the argument or path, exit code 2 (130 on Ctrl-C), and no file
written or directory created.  Anything else is a bug, a plain ``ValueError``
or ``TypeError`` and an ``OSError`` that no file or stream operation of the
command line raised included: exit code 1, ``forcenet: internal error: <type>:
<message>``, and the traceback on stderr under ``--debug``, else in a file
whose path is printed.  The main job's cross-check has codes of its own: 3
when it DISAGREES, 4 when it cannot judge (:data:`.output.EXIT_CODES`, also in
``forcenet --help``).

Examples (shell)::

    forcenet count --N 40
    forcenet table --N 12                   # JSON + CSV + LaTeX files, summary, Monte Carlo check
    forcenet table --N 12 --format json     # the exact table on stdout
    forcenet table --N 9 --moments 2 --out table.csv
    forcenet entropy --phi 0.3 --dps 50     # the chicken-wire entropy, closed form (7.1)
"""

from __future__ import annotations

import argparse
import gc
import os
import sys
import tempfile
import traceback
from collections.abc import Sequence
from importlib.metadata import version

from forcenet.core.errors import ForcenetError
from forcenet.core.plan import interruptible_compilation

from . import chicken_wire, dist, force_chains, limit, sample, table
from . import network as network_command
from . import shear as shear_command
from .common import Parser, UsageError, deferred_option, given, usage_error_line
from .output import EXIT_CODES, check_stdout, destination

__all__ = ["main", "build_parser"]


_DESCRIPTION = """\
Exact results for the force network ensemble of static granular matter
(Ostojic's 2006 thesis): the fully mobilized triangle of N layers of grains
under a unit overload, exactly (fractions) and by Monte Carlo.

Each command has its own help: forcenet COMMAND --help."""

_EXAMPLES = """\
examples, one per command (each takes a few seconds at most):
  forcenet count --N 12              # how many force networks (tableaux)
  forcenet table --N 12              # the main job: 3 files in
                                     # ./forcenet-tables/, a summary, a check
  forcenet table --N 12 --format json        # just the exact <W_ij>
  forcenet maps --N 7                # the thesis's map counting (Sec. 4.6)
  forcenet limit --x 0.2 --z 0.6     # N <W> in the scaling limit
  forcenet sample --N 10 --samples 2000      # Monte Carlo <W>, error bars
  forcenet transfer --L 6            # chicken wire: a cylinder's transfer
  forcenet bethe --L 6 --n 2 --m 1   # chicken wire: one Bethe-ansatz sector
  forcenet entropy --phi 0.3         # chicken-wire entropy, Eq. (7.1)
  forcenet dist --N 12 --grain 12,6  # exact density of one force
  forcenet scaling --model percolation --sizes 16,24,32,48 --samples 200
                                     # clusters of large forces (Table 7.1)
  forcenet network packing.json --exact  # your own contact network: every
                                     # force's exact mean
  forcenet yield-stress --size 4     # the largest shear stress, exactly

Results go to stdout (or to --out FILE, written atomically); costs, progress
and errors go to stderr. Runs announced at over a minute need --force.
More: the README (README.md of the source, or the package page).

""" + EXIT_CODES


def build_parser() -> Parser:
    parser = Parser(prog="forcenet", description=_DESCRIPTION, epilog=_EXAMPLES,
                    formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--version", action="version", version=f"%(prog)s {version('forcenet')}")
    parser.add_argument("--debug", action="store_true",
                        help="on an internal error (a bug), print the traceback on stderr instead of to a file")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=Parser, metavar="COMMAND")
    for family in (table, limit, sample, chicken_wire, dist, force_chains, network_command, shear_command):
        family.register(sub)
    return parser


_EXTENSION_FORMATS = {".json": "json", ".csv": "csv", ".tex": "latex"}


def _check_destinations(args: argparse.Namespace) -> None:
    """Every destination of the result, before any work: the files named, else standard output."""
    for name in ("out", "plot"):
        if getattr(args, name, None) is not None:
            destination(getattr(args, name), f"--{name}")
    if getattr(args, "out", None) is None:
        check_stdout()
    elif given(args, "format"):  # the name's extension says a format: it must be the one asked for
        extension = os.path.splitext(args.out)[1].lower()
        implied = _EXTENSION_FORMATS.get(extension)
        if implied is not None and implied != args.format:
            raise UsageError(f"--format {args.format} and --out={args.out} contradict each other: a {extension} file "
                             f"holds {implied}; drop --format or rename the file")


def _error(message: str) -> int:
    print(f"forcenet: error: {message}", file=sys.stderr)
    return 2


def _internal_error(exc: BaseException, debug: bool) -> int:
    """A bug: one line naming the exception, the traceback on stderr (``--debug``) or in a file named there."""
    print(f"forcenet: internal error: {type(exc).__name__}: {exc}", file=sys.stderr)
    text = "".join(traceback.format_exception(exc))
    if debug:
        print(text, end="", file=sys.stderr)
        return 1
    try:
        fd, path = tempfile.mkstemp(prefix="forcenet-traceback-", suffix=".txt")
        with os.fdopen(fd, "w", encoding="utf-8") as handle:
            handle.write(text)
    except OSError:  # no writable temporary directory: the traceback goes to stderr after all
        print(text, end="", file=sys.stderr)
        return 1
    print(f"forcenet: the traceback is in {path}; please report it (forcenet --debug ... prints it)", file=sys.stderr)
    return 1


def _release_quietly(exc: BaseException) -> None:
    """Free the interrupted frames now, silencing the finalizers of objects that Ctrl-C left half-built.

    Ctrl-C can land inside a third-party constructor (llvmlite's, while numba
    compiles); that object's ``__del__`` then fails on a missing attribute and
    Python prints "Exception ignored in ..." after the one-line message.
    """
    hook = sys.unraisablehook
    sys.unraisablehook = lambda unraisable: None
    try:
        traceback.clear_frames(exc.__traceback__)  # the executing frames (this one) are skipped
    finally:
        sys.unraisablehook = hook


def _valued_options(parser: argparse.ArgumentParser) -> tuple[set[str], set[str]]:
    """(the option strings that take one value, every option string) of the parser and its subcommands."""
    valued, every = set(), set()  # type: set[str], set[str]
    parsers, seen = [parser], set()
    while parsers:
        current = parsers.pop()
        if id(current) in seen:
            continue
        seen.add(id(current))
        for action in current._actions:
            if isinstance(action, argparse._SubParsersAction):
                parsers.extend(action.choices.values())
            every.update(action.option_strings)
            if action.option_strings and action.nargs is None:
                valued.update(action.option_strings)
    return valued, every


def _join_negative_values(parser: argparse.ArgumentParser, argv: list[str]) -> list[str]:
    """``--grain -1,1`` read as ``--grain=-1,1``: a value that starts with ``-`` (argparse would take it for an
    option and answer "expected one argument") is joined to the option that takes it, unless it is an option
    itself; the value then meets its own check, which names the range."""
    valued, every = _valued_options(parser)
    out: list[str] = []
    k = 0
    while k < len(argv):
        token = argv[k]
        if token == "--":
            out += argv[k:]
            break
        following = argv[k + 1] if k + 1 < len(argv) else None
        if (token in valued and following is not None and following.startswith("-") and following != "-"
                and following.split("=", 1)[0] not in every):
            out.append(f"{token}={following}")
            k += 2
            continue
        out.append(token)
        k += 1
    return out


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; returns the exit code."""
    sys.set_int_max_str_digits(0)  # huge exact integers are printed whole (count --N 84 has 4300+ digits)
    parser = build_parser()
    argv = _join_negative_values(parser, list(sys.argv[1:] if argv is None else argv))
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # argparse: --help (0) or a one-line usage error (2)
        return 0 if exc.code in (0, None) else 2
    try:
        _check_destinations(args)
        with interruptible_compilation():  # Ctrl-C while numba compiles is not lost in LLVM's callbacks
            return args.func(args)
    except ForcenetError as exc:  # expected failures (UsageError, the library's argument checks): they name the argument
        deferred = deferred_option(args, exc)
        if deferred is not None:  # a range the parser left to the front door: reported as the parser reports one
            prog, option = deferred
            print(usage_error_line(prog, f"argument {option}: {exc}"), end="", file=sys.stderr)
            return 2
        return _error(str(exc))
    except MemoryError:
        return _error("out of memory: choose a smaller size (the cost announcement is an estimate)")
    except KeyboardInterrupt as exc:
        _release_quietly(exc)
        print("forcenet: interrupted; no partial output was written", file=sys.stderr)
        gc.freeze()  # no collection of the compiled kernels' objects at exit: 1.8 s -> 0.2 s (tests/test_interrupt.py)
        return 130
    except BrokenPipeError:  # e.g. `forcenet maps --N 9 | head`
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0
    except Exception as exc:  # anything else is a bug: a plain ValueError or TypeError, an OSError no writer named
        return _internal_error(exc, getattr(args, "debug", False))


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
