"""What every command shares: argument types and groups, the cost policy, output, errors.

The policy, in one place:

* bad input is a one-line error naming the argument and the allowed range,
  exit code 2, and no file or directory is created;
* a run whose plan (:class:`forcenet.core.plan.Plan`) is refused never
  starts; a run announced at over a minute needs ``--force``; every run
  announced at over two seconds prints its estimate and a progress bar on
  stderr (``--quiet``: neither);
* results go to stdout or to files written atomically, all at the end, all
  or none (:mod:`.output`); timings go to stderr, never into a result.
"""

from __future__ import annotations

import argparse
import functools
import shutil
import sys
import textwrap
import time
from collections.abc import Callable, Sequence
from typing import Any, NoReturn, TypeVar

from forcenet.core.errors import ArgumentError, ForcenetError
from forcenet.core.plan import Plan, duration_text
from forcenet.core.progress import Bar, left_text, owned, watched
from forcenet.core.validation import available_memory as memory_now
from forcenet.core.validation import check_int, check_real

__all__ = [
    "UsageError",
    "Parser",
    "given",
    "refuse_together",
    "integer",
    "defer",
    "deferred_option",
    "usage_error_line",
    "real",
    "add_layers",
    "add_format",
    "add_quiet",
    "add_force",
    "add_seed",
    "available_memory",
    "run_planned",
    "progress_label",
]

FORCE_SECONDS = 60  # a run announced at over a minute needs --force
ANNOUNCE_SECONDS = 2  # shorter runs are not announced

T = TypeVar("T")  # what an argument type or a planned run returns


class UsageError(ForcenetError):
    """Bad input or a refused run, detected after parsing; one line on stderr, exit code 2."""


class Parser(argparse.ArgumentParser):
    """argparse with one-line errors, exit code 2, and every option given at most once.

    The options given on the command line are recorded in ``args._given``
    (their ``dest``): :func:`given` tells an explicit value from a default.
    """

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        kwargs["formatter_class"] = _narrow(kwargs.get("formatter_class", argparse.HelpFormatter))
        super().__init__(*args, **kwargs)

    def error(self, message: str) -> NoReturn:
        self.exit(2, usage_error_line(self.prog, message))

    def _add_action(self, action: Any) -> Any:  # every option of this parser and of its mutually exclusive groups
        action = super()._add_action(action)
        if action.option_strings and not isinstance(action, (argparse._HelpAction, argparse._VersionAction)):
            action.__class__ = _once(type(action))  # type: ignore[arg-type]  # a class is hashable
        return action


HELP_COLUMNS = 80  # help is wrapped to at most this many columns, however wide the terminal (issue 53)


@functools.cache
def _narrow(cls: Any) -> Any:
    """The help formatter ``cls`` wrapping at ``min(terminal, HELP_COLUMNS) - 2`` columns (argparse's margin)."""

    class Narrow(cls):
        def __init__(self, prog: str, indent_increment: int = 2, max_help_position: int = 24,
                     width: int | None = None) -> None:
            columns = min(width + 2 if width else shutil.get_terminal_size().columns, HELP_COLUMNS)
            super().__init__(prog, indent_increment, max_help_position, columns - 2)

    return Narrow


@functools.cache
def _once(cls: Any) -> Any:
    """The action class ``cls`` refusing a second occurrence of its option ("--N given twice")."""

    class Once(cls):
        def __call__(self, parser: argparse.ArgumentParser, namespace: argparse.Namespace, values: Any,
                     option_string: str | None = None) -> None:
            seen = vars(namespace).setdefault("_given", set())
            if self.dest in seen:
                parser.error(f"{'/'.join(self.option_strings)} given twice; give it once")
            seen.add(self.dest)
            super().__call__(parser, namespace, values, option_string)

    Once.__name__ = Once.__qualname__ = cls.__name__
    return Once


def usage_error_line(prog: str, message: str) -> str:
    """The parser's one-line error, ``forcenet table: error: argument --N: ...`` (also for a deferred range)."""
    return f"{prog}: error: {message}\n"


def deferred_option(args: argparse.Namespace, exc: BaseException) -> tuple[str, str] | None:
    """``(prog, option)`` when ``exc`` is the front door's refusal of a range the parser left to it (:func:`integer`
    with ``deferred=True``), else ``None``: the command line then reports it as the parser would have."""
    argument = getattr(exc, "argument", None)
    deferred: dict[str, tuple[str, str]] = vars(args).get("_deferred") or {}
    return deferred.get(argument) if isinstance(argument, str) else None


def given(args: argparse.Namespace, dest: str) -> bool:
    """Whether the option ``dest`` was given on the command line (not its default)."""
    return dest in vars(args).get("_given", ())


def refuse_together(args: argparse.Namespace, first: str, second: str, why: str) -> None:
    """A contradiction: ``first`` and ``second`` (dests, both given) refused in one line naming both."""
    if given(args, first) and given(args, second):
        raise UsageError(f"--{first.replace('_', '-')} and --{second.replace('_', '-')} contradict each other: {why}")


# ----------------------------------------------------------------- argument types


def integer(name: str, minimum: int | None = None, maximum: int | None = None, *,
            deferred: bool = False) -> Callable[[str], int]:
    """argparse type: an integer in range, with the validation module's message.

    ``deferred=True``: the text is read as an integer here and its range is left to the front door, which checks
    the whole request once (:func:`defer` records the option, so a refusal still reads ``argument --N: ...``).

    Examples
    --------
    >>> integer("N", 2)("12")
    12
    >>> integer("N", 2, deferred=True)("1")  # read; the range is the front door's check
    1
    """

    def parse(text: str) -> int:
        if not text.isascii():
            raise ArgumentError(f"{name}={text!r} is not an integer: use the ASCII digits 0-9")
        try:
            value = int(text)
        except ValueError:
            return check_int(text, name, minimum, maximum)  # raises the uniform ArgumentTypeError message
        return value if deferred else check_int(value, name, minimum, maximum)

    return _argparse_type(parse)


def defer(p: argparse.ArgumentParser, name: str, option: str) -> None:
    """Record that the range of ``option`` (the front door's argument ``name``) is checked by the front door."""
    deferred = dict(p.get_default("_deferred") or {})
    deferred[name] = (p.prog, option)
    p.set_defaults(_deferred=deferred)


def real(name: str, low: float | None = None, high: float | None = None, *, low_open: bool = False,
         high_open: bool = False) -> Callable[[str], float]:
    """argparse type: a finite real number in range (``nan``, ``inf`` and non-numbers are refused).

    Examples
    --------
    >>> real("F", 0, low_open=True)("2.5")
    2.5
    """

    def parse(text: str) -> float:
        if not text.isascii():
            raise ArgumentError(f"{name}={text!r} is not a number: use the ASCII digits 0-9")
        return check_real(text, name, low, high, low_open=low_open, high_open=high_open)

    return _argparse_type(parse)


def _argparse_type(parse: Callable[[str], T]) -> Callable[[str], T]:
    def wrapped(text: str) -> T:
        try:
            return parse(text)
        except ForcenetError as exc:  # the checks' one-line message; anything else is a bug and propagates
            raise argparse.ArgumentTypeError(str(exc)) from None

    wrapped.__name__ = "value"
    return wrapped


# ---------------------------------------------------------------- argument groups


def add_layers(p: argparse.ArgumentParser, maximum: int | None = None, minimum: int = 2,
               help_text: str | None = None, *, deferred: bool = False) -> None:
    """``--N``; ``deferred=True`` when the command's front door checks ``N`` (then once, there)."""
    allowed = f"{minimum}..{maximum}" if maximum else f">= {minimum}"
    p.add_argument("--N", type=integer("N", minimum, maximum, deferred=deferred), required=True,
                   help=help_text or f"number of layers ({allowed})")
    if deferred:
        defer(p, "N", "--N")


def add_format(p: argparse.ArgumentParser, choices: Sequence[str] = ("text", "json"), default: str | None = "text",
               out: bool = True) -> None:
    p.add_argument("--format", choices=list(choices), default=default, help=f"output format (default {default})")
    if out:
        p.add_argument("--out", help="write the output to this file instead of stdout (atomically; its directory must exist)")


def add_quiet(p: argparse.ArgumentParser) -> None:
    p.add_argument("--quiet", action="store_true", help="no cost announcement, no progress bar (stderr)")


def add_force(p: argparse.ArgumentParser) -> None:
    p.add_argument("--force", action="store_true", help=f"run even if announced at over {FORCE_SECONDS} s")


def add_seed(p: argparse.ArgumentParser, default: int = 0) -> None:
    p.add_argument("--seed", type=integer("seed", 0, 2**63 - 1), default=default, help=f"random seed, an integer >= 0 (default {default})")


# ------------------------------------------------------------------- the cost policy


def available_memory() -> int:
    """Bytes of memory available now (:func:`forcenet.core.validation.available_memory`), 16 GiB if unknown."""

    return memory_now() or 16 * 2**30


PLAIN_PROGRESS_SECONDS = 60  # off a terminal, a run announced at over a minute reports every ~10 %


class _PlainProgress:
    """Progress off a terminal (a log file, a pipe): a plain line per ~10 %, no carriage return, no animation."""

    def __init__(self, total: float, desc: str, unit: str) -> None:
        self.total, self.desc, self.unit = total, desc, unit
        self.n, self.next_tenth, self.t0 = 0.0, 1, time.perf_counter()

    def update(self, k: float = 1) -> None:
        self.n += k
        while self.next_tenth < 10 and self.n >= self.total * self.next_tenth / 10:
            elapsed = time.perf_counter() - self.t0
            count = "" if self.unit == "s" else f" ({self.n:.0f}/{self.total:.0f} {self.unit})"
            print(f"forcenet: {self.desc}: {10 * self.next_tenth} %{count} after {elapsed:.0f} s, "
                  f"{left_text(elapsed * (self.total - self.n) / self.n)}", file=sys.stderr, flush=True)
            self.next_tenth += 1

    def close(self) -> None:
        pass


LABEL_CHARACTERS = 30  # a bar's label at most: the quantity and N, so the percentage shows at 80 columns
REVISE_FACTOR = 1.5  # a measured rate this far from the plan's restates the estimate (once)
REVISE_SECONDS = 2.0  # ... measured over at least this long, after the first finished tick
REVISE_SHARE = 0.15  # ... and over at least this share of the ticks


def progress_label(what: str) -> str:
    """The bar's label: the quantity and N, before the details (``"exact table N=40"``).

    Examples
    --------
    >>> progress_label("exact table N=40 (Pfaffians); auto chose pfaffian: the fastest by the plans (pfaffian ~7 s)")
    'exact table N=40'
    """
    cut = min([i for i in (what.find(" ("), what.find(";"), what.find(", ")) if i > 0] or [len(what)])
    label = what[:cut].strip()
    return label if len(label) <= LABEL_CHARACTERS else label[:LABEL_CHARACTERS - 3].rstrip() + "..."


def _progress_bar(total: int, desc: str, unit: str, seconds: float = 0.0) -> Any:
    """An animated bar on a terminal; elsewhere plain lines (over a minute) or nothing."""
    if not watched(sys.stderr):
        return _PlainProgress(total, desc, unit) if seconds > PLAIN_PROGRESS_SECONDS else None
    return Bar(total, desc, unit)  # never past 100 %, the time left in words (forcenet.core.progress)


class _Reviser:
    """``progress(k)`` that also restates the estimate once, from the measured rate, when it is off by
    :data:`REVISE_FACTOR` (a loaded machine, a cluster): one line, one time, never two times on one line."""

    def __init__(self, plan: Plan, label: str, bar: Any) -> None:
        self.plan, self.label, self.bar = plan, label, bar
        self.t0, self.done, self.revised = time.perf_counter(), 0.0, False
        self.first: tuple[float, float] | None = None  # (time, ticks) at the first finished tick

    def __call__(self, k: float = 1) -> None:
        if self.bar is not None:
            self.bar.update(k)
        self.done += k
        now = time.perf_counter()
        if self.first is None:  # the first tick pays the start-up (workers, kernels): the rate is measured after it
            self.first = (now, self.done)
            return
        t1, n1 = self.first
        if (self.revised or self.plan.compiling or now - t1 < REVISE_SECONDS or self.done <= n1
                or self.done >= self.plan.ticks  # compiling (a later phase's kernels too) is no rate of the run
                or self.done - n1 < REVISE_SHARE * self.plan.ticks):  # a rate of a few ticks is noise
            return
        total = (t1 - self.t0) + (now - t1) * (self.plan.ticks - n1) / (self.done - n1)
        if not 1 / REVISE_FACTOR <= total / max(self.plan.seconds, 1e-9) <= REVISE_FACTOR:
            self.revised = True
            line = (f"forcenet: {self.label}: at the measured rate ~{duration_text(total)} in all "
                    f"({self.done / self.plan.ticks:.0%} after {duration_text(now - self.t0)})")
            if hasattr(self.bar, "write"):
                self.bar.write(line)
            else:
                print(line, file=sys.stderr, flush=True)


def run_planned(plan: Plan, run: Callable[[Callable[..., None] | None], T], *, force: bool = False,
                quiet: bool = False) -> T:
    """Refuse, announce, or run ``run(progress)`` under a progress bar, as the plan says.

    ``run`` receives ``progress(k=1)`` (or None when nothing is shown).  The
    announcement is its own line (the plan's ``what`` and one estimate; a
    reason after ``;``, e.g. ``auto``'s choice, on a line of its own); the
    bar's label is short (:func:`progress_label`); the estimate is restated
    once from the measured rate when it is off (:class:`_Reviser`).
    """
    if not plan.runnable:
        raise UsageError(plan.refusal)
    if plan.seconds > FORCE_SECONDS and not force:
        raise UsageError(f"{plan.what} takes {plan.describe()}; add --force to run it")
    with owned():  # the front door's own progress policy stays silent: this function shows the progress
        return _announced(plan, run, quiet)


def _announced(plan: Plan, run: Callable[[Callable[..., None] | None], T], quiet: bool) -> T:
    """``run(progress)``: announced, under a bar, unless quiet or short."""
    if quiet or plan.seconds <= ANNOUNCE_SECONDS:
        return run(None)
    what, _, why = plan.what.partition("; ")
    for line in [f"forcenet: {what}: estimated {plan.describe()}", *([f"forcenet: {why}"] if why else [])]:
        print(textwrap.fill(line, 80, subsequent_indent="  ", break_on_hyphens=False), file=sys.stderr)
    label = progress_label(plan.what)
    t0 = time.perf_counter()
    bar = _progress_bar(plan.ticks, label, plan.unit, plan.seconds) if plan.ticks else None
    try:
        result = run(_Reviser(plan, label, bar) if plan.ticks else None)
    finally:
        if bar:
            bar.close()
    print(f"forcenet: {label}: done in {time.perf_counter() - t0:.1f} s", file=sys.stderr)
    return result
