"""The exception family (forcenet.core.errors): the library raises it, the command line catches only it.

notes/architecture.md, "Errors".  A bug shows as a bug: exit code 1, ``internal error``, the traceback
under ``--debug`` or in a file named on stderr.
"""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import pytest

import forcenet
from forcenet.cli import main
from forcenet.cli import table as table_cli
from forcenet.core.errors import ArgumentError, ArgumentTypeError, ConvergenceError, ForcenetError
from forcenet.core.validation import check_int, check_real


def test_the_family_is_exported_and_keeps_the_builtin_bases():
    assert (forcenet.ForcenetError, forcenet.ArgumentError, forcenet.ArgumentTypeError) == (
        ForcenetError, ArgumentError, ArgumentTypeError)
    assert issubclass(ArgumentError, ForcenetError) and issubclass(ArgumentError, ValueError)
    assert issubclass(ArgumentTypeError, ForcenetError) and issubclass(ArgumentTypeError, TypeError)
    assert not issubclass(ArgumentError, TypeError) and not issubclass(ArgumentTypeError, ValueError)
    assert forcenet.ConvergenceError is ConvergenceError and issubclass(ConvergenceError, RuntimeError)
    assert issubclass(ConvergenceError, ForcenetError)
    with pytest.raises(AttributeError):
        forcenet.NoSuchError  # noqa: B018 -- the module's __getattr__ still refuses unknown names


@pytest.mark.parametrize("call, kind", [
    (lambda: check_int(1, "N", minimum=2), ArgumentError),
    (lambda: check_int(2.0, "N", minimum=2), ArgumentTypeError),
    (lambda: check_int(True, "N", minimum=2), ArgumentTypeError),
    (lambda: check_real(float("nan"), "F", low=0), ArgumentError),
    (lambda: check_real("abc", "phi"), ArgumentTypeError),
    (lambda: forcenet.exact.count(1), ArgumentError),
])
def test_checks_raise_the_family(call, kind):
    with pytest.raises(kind) as info:
        call()
    assert type(info.value) is kind  # the exact class, not a builtin ValueError/TypeError


def test_expected_failures_of_other_modules_join_the_family():
    from forcenet.cli.common import UsageError
    from forcenet.exact.chicken_wire.square_triangle import TilingError
    from forcenet.exact.chicken_wire.tiling import MapError
    from forcenet.numeric.autocorr import AutocorrError
    from forcenet.testing import CannotJudgeError, DisagreementError

    for cls in (UsageError, TilingError, MapError, AutocorrError, CannotJudgeError, DisagreementError):
        assert issubclass(cls, ForcenetError), cls
    assert issubclass(MapError, ValueError)
    assert issubclass(DisagreementError, AssertionError) and issubclass(CannotJudgeError, AssertionError)


def _boom(kind):
    def command(args):
        raise kind("a bug: 3 is not 4")
    return command


def test_a_plain_value_error_is_a_bug_exit_1_traceback_in_a_named_file(monkeypatch, capsys, tmp_path):
    monkeypatch.setattr(table_cli, "cmd_count", _boom(ValueError))
    monkeypatch.setenv("TMPDIR", str(tmp_path))
    monkeypatch.setattr("tempfile.tempdir", None)  # gettempdir() reads TMPDIR again
    code = main(["count", "--N", "5"])
    out, err = capsys.readouterr()
    assert code == 1 and out == ""
    assert err.splitlines()[0] == "forcenet: internal error: ValueError: a bug: 3 is not 4"
    assert "Traceback" not in err
    path = Path(re.search(r"the traceback is in (\S+);", err).group(1))
    assert path.parent == tmp_path
    text = path.read_text()
    assert text.startswith("Traceback (most recent call last):") and "in command" in text
    assert text.rstrip().endswith("ValueError: a bug: 3 is not 4")


@pytest.mark.parametrize("kind", [ValueError, TypeError, KeyError, ZeroDivisionError])
def test_debug_prints_the_traceback_on_stderr(kind, monkeypatch, capsys):
    monkeypatch.setattr(table_cli, "cmd_count", _boom(kind))
    code = main(["--debug", "count", "--N", "5"])
    _, err = capsys.readouterr()
    assert code == 1
    assert err.startswith(f"forcenet: internal error: {kind.__name__}: ")
    assert "Traceback (most recent call last):" in err and "in command" in err
    assert "the traceback is in" not in err


@pytest.mark.parametrize("kind", [ArgumentError, ArgumentTypeError, ForcenetError])
def test_the_family_is_one_line_exit_2(kind, monkeypatch, capsys):
    monkeypatch.setattr(table_cli, "cmd_count", _boom(kind))
    code = main(["--debug", "count", "--N", "5"])
    out, err = capsys.readouterr()
    assert code == 2 and out == ""
    assert err == "forcenet: error: a bug: 3 is not 4\n"


def test_a_destination_that_is_a_directory_is_a_user_error_exit_2(tmp_path, capsys):
    """A file operation's failure names the argument: one line, exit code 2 (the writers raise the family)."""
    code = main(["count", "--N", "5", "--out", str(tmp_path)])
    out, err = capsys.readouterr()
    assert code == 2 and out == ""
    assert err == f"forcenet: error: --out={tmp_path}: is a directory; give a file name\n"
    assert list(tmp_path.iterdir()) == []


def test_an_os_error_inside_an_engine_is_a_bug_exit_1(monkeypatch, capsys, tmp_path):
    """An OSError that no file or stream operation of the command line raised is an internal error, not exit 2."""
    import errno

    import forcenet.tableaux_count as staircase  # the front door's engine, imported at its top

    def engine(N):
        raise OSError(errno.EBADF, "Bad file descriptor")

    monkeypatch.setattr(staircase, "tableau_count", engine)  # what forcenet.count_plan runs (N checked once)
    monkeypatch.setenv("TMPDIR", str(tmp_path))
    monkeypatch.setattr("tempfile.tempdir", None)
    code = main(["count", "--N", "5"])
    out, err = capsys.readouterr()
    assert code == 1 and out == ""
    assert err.splitlines()[0] == "forcenet: internal error: OSError: [Errno 9] Bad file descriptor"
    assert "the traceback is in" in err and "please report it" in err
    code = main(["--debug", "count", "--N", "5"])
    _, err = capsys.readouterr()
    assert code == 1 and "Traceback (most recent call last):" in err and "in engine" in err


_CHECK_UNDER_O = """
import copy
from forcenet.exact.chicken_wire.tiling import (Lattice2in2, TilingError, check_tiling, chicken_wire_configs,
                                                config_to_tiling, config_vertex_counts)
torus = Lattice2in2.rect(3, 3)
foam = next(c for c in chicken_wire_configs(3, 3) if config_vertex_counts(c)["Y"])
bad = copy.deepcopy(config_to_tiling(foam, torus))
bad["faces"].pop()
try:
    check_tiling(bad)
except TilingError as exc:
    print(__debug__, type(exc).__name__, exc)
else:
    print(__debug__, "no error")
"""


def test_checks_behave_the_same_under_python_O():
    """No bare assert in library code: ``python -O`` (asserts stripped) sees the same error."""
    runs = [subprocess.run([sys.executable, *flags, "-c", _CHECK_UNDER_O], capture_output=True, text=True, check=True)
            for flags in ([], ["-O"])]
    plain, optimized = (r.stdout.split(" ", 1) for r in runs)
    assert plain[0] == "True" and optimized[0] == "False"  # the second run really had its asserts stripped
    assert plain[1] == optimized[1] and optimized[1].startswith("TilingError ")
