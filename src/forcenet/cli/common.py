"""What every command shares: argument types and groups, the cost policy, output, errors.

The policy, in one place:

* bad input is a one-line error naming the argument and the allowed range,
  exit code 2, and no file or directory is created;
* a run whose plan (:class:`forcenet.exact.plan.Plan`) is refused never
  starts; a run announced at over a minute needs ``--force``; every run
  announced at over two seconds prints its estimate and a progress bar on
  stderr (``--quiet``: neither);
* results go to stdout or to files written atomically, all at the end, all
  or none; timings go to stderr, never into a result.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
import tempfile
import time

from forcenet.exact.plan import Plan
from forcenet.exact.validation import check_int, check_real

__all__ = [
    "UsageError",
    "Parser",
    "integer",
    "real",
    "add_layers",
    "add_format",
    "add_quiet",
    "add_force",
    "add_seed",
    "available_memory",
    "run_planned",
    "emit",
    "write_files",
    "json_dumps",
]

FORCE_SECONDS = 60  # a run announced at over a minute needs --force
ANNOUNCE_SECONDS = 2  # shorter runs are not announced


class UsageError(Exception):
    """Bad input or a refused run, detected after parsing; one line on stderr, exit code 2."""


class Parser(argparse.ArgumentParser):
    """argparse with one-line errors and exit code 2."""

    def error(self, message):
        self.exit(2, f"{self.prog}: error: {message}\n")


# ----------------------------------------------------------------- argument types


def integer(name: str, minimum: int | None = None, maximum: int | None = None):
    """argparse type: an integer in range, with the validation module's message.

    Examples
    --------
    >>> integer("N", 2)("12")
    12
    """

    def parse(text):
        try:
            value = int(text)
        except ValueError:
            return check_int(text, name, minimum, maximum)  # raises the uniform TypeError message
        return check_int(value, name, minimum, maximum)

    return _argparse_type(parse)


def real(name: str, low=None, high=None, *, low_open: bool = False, high_open: bool = False):
    """argparse type: a finite real number in range (``nan``, ``inf`` and non-numbers are refused).

    Examples
    --------
    >>> real("F", 0, low_open=True)("2.5")
    2.5
    """

    def parse(text):
        return check_real(text, name, low, high, low_open=low_open, high_open=high_open)

    return _argparse_type(parse)


def _argparse_type(parse):
    def wrapped(text):
        try:
            return parse(text)
        except (TypeError, ValueError) as exc:
            raise argparse.ArgumentTypeError(str(exc)) from None

    wrapped.__name__ = "value"
    return wrapped


# ---------------------------------------------------------------- argument groups


def add_layers(p, maximum: int | None = None, minimum: int = 2, help_text: str | None = None):
    allowed = f"{minimum}..{maximum}" if maximum else f">= {minimum}"
    p.add_argument("--N", type=integer("N", minimum, maximum), required=True, help=help_text or f"number of layers ({allowed})")


def add_format(p, choices=("text", "json"), default="text", out: bool = True):
    p.add_argument("--format", choices=list(choices), default=default, help=f"output format (default {default})")
    if out:
        p.add_argument("--out", help="write the output to this file instead of stdout (atomically; its directory must exist)")


def add_quiet(p):
    p.add_argument("--quiet", action="store_true", help="no cost announcement, no progress bar (stderr)")


def add_force(p):
    p.add_argument("--force", action="store_true", help=f"run even if announced at over {FORCE_SECONDS} s")


def add_seed(p, default: int = 0):
    p.add_argument("--seed", type=integer("seed", 0, 2**63 - 1), default=default, help=f"random seed, an integer >= 0 (default {default})")


# ------------------------------------------------------------------- the cost policy


def available_memory() -> int:
    """Bytes of memory available now (``MemAvailable``), 16 GiB if unknown."""
    try:
        with open("/proc/meminfo") as handle:
            for line in handle:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except OSError:
        pass
    return 16 * 2**30


def _progress_bar(total: int, desc: str, unit: str):
    from tqdm import tqdm

    # a bar counted in estimated seconds (phases of different units, exact.plan.combine_by_time) moves by fractions
    fmt = "{l_bar}{bar}| {n:.0f}/{total_fmt} estimated s [{elapsed}<{remaining}]" if unit == "s" else None
    return tqdm(total=total, desc=desc, unit=unit, unit_scale=total >= 10_000, file=sys.stderr, leave=False,
                bar_format=fmt)


def run_planned(plan: Plan, run, *, force: bool = False, quiet: bool = False):
    """Refuse, announce, or run ``run(progress)`` under a progress bar, as the plan says.

    ``run`` receives ``progress(k=1)`` (or None when nothing is shown).
    """
    if not plan.runnable:
        raise UsageError(plan.refusal)
    if plan.seconds > FORCE_SECONDS and not force:
        raise UsageError(f"{plan.what} takes {plan.describe()}; add --force to run it")
    if quiet or plan.seconds <= ANNOUNCE_SECONDS:
        return run(None)
    print(f"forcenet: {plan.what}: estimated {plan.describe()}", file=sys.stderr)
    t0 = time.perf_counter()
    bar = _progress_bar(plan.ticks, plan.what, plan.unit) if plan.ticks else None
    try:
        result = run(bar.update if bar else None)
    finally:
        if bar:
            bar.close()
    print(f"forcenet: {plan.what}: done in {time.perf_counter() - t0:.1f} s", file=sys.stderr)
    return result


# --------------------------------------------------------------------------- output


def json_dumps(obj) -> str:
    """JSON without NaN/Infinity (refused: they are not JSON)."""
    return json.dumps(obj, allow_nan=False)


def _check_directory(path: str, name: str):
    directory = os.path.dirname(os.path.abspath(path)) or "."
    if not os.path.isdir(directory):
        raise UsageError(f"{name}={path}: the directory {directory} does not exist (create it first)")
    if not os.access(directory, os.W_OK | os.X_OK):
        raise UsageError(f"{name}={path}: the directory {directory} is not writable")
    if os.path.isdir(path):
        raise UsageError(f"{name}={path}: is a directory; give a file name")


def emit(text: str, out: str | None = None, name: str = "--out") -> None:
    """Print ``text`` on stdout, or write it to ``out`` atomically."""
    if not text.endswith("\n"):
        text += "\n"
    if out is None:
        sys.stdout.write(text)
        sys.stdout.flush()
        return
    write_files({out: text}, name=name)


def check_output_path(path: str | None, name: str = "--out") -> None:
    """Fail early (before any computation) on an output file that cannot be written."""
    if path is not None:
        _check_directory(path, name)


def check_output_dir(directory: str, name: str = "--out-dir") -> None:
    """Fail early on an output directory that is a file or whose parent is missing or read-only."""
    absolute = os.path.abspath(directory)
    if os.path.exists(absolute):
        if not os.path.isdir(absolute):
            raise UsageError(f"{name}={directory}: exists and is not a directory")
        if not os.access(absolute, os.W_OK | os.X_OK):
            raise UsageError(f"{name}={directory}: the directory is not writable")
        return
    parent = os.path.dirname(absolute)
    if not os.path.isdir(parent):
        raise UsageError(f"{name}={directory}: its parent {parent} does not exist or is not a directory")
    if not os.access(parent, os.W_OK | os.X_OK):
        raise UsageError(f"{name}={directory}: cannot be created, {parent} is not writable")


def write_files(files: dict, name: str = "--out", make_dir: str | None = None) -> None:
    """Write every ``{path: text}`` atomically, all or none (``text`` may be ``bytes``).

    Every file is first written to a temporary file beside its target, then
    all are renamed; on any failure (or Ctrl-C) the temporaries, the files
    renamed so far and the directory ``make_dir`` (if this call created it)
    are removed, so nothing is left behind.
    """
    created = None
    if make_dir is not None and not os.path.isdir(make_dir):
        check_output_dir(make_dir)
        os.mkdir(make_dir)
        created = make_dir
    temps, renamed = {}, []
    try:
        for path, text in files.items():
            _check_directory(path, name)
            directory = os.path.dirname(os.path.abspath(path))
            fd, tmp = tempfile.mkstemp(dir=directory, prefix=".tmp-", suffix=os.path.basename(path))
            temps[path] = tmp
            umask = os.umask(0)
            os.umask(umask)
            os.chmod(tmp, 0o666 & ~umask)  # mkstemp creates 0600; give the usual permissions
            with os.fdopen(fd, "wb" if isinstance(text, bytes) else "w") as handle:  # bytes: e.g. a PNG
                handle.write(text)
                handle.flush()
                os.fsync(handle.fileno())
        for path, tmp in temps.items():
            os.replace(tmp, path)
            renamed.append(path)
    except BaseException:
        for tmp in temps.values():
            if os.path.exists(tmp):
                os.unlink(tmp)
        for path in renamed:
            if os.path.exists(path):
                os.unlink(path)
        if created is not None and os.path.isdir(created) and not os.listdir(created):
            os.rmdir(created)
        raise


def finite_or_none(x: float):
    """A float for JSON, None for inf/nan (JSON has neither)."""
    return x if math.isfinite(x) else None
