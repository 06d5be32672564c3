"""What a new user meets first (issue 53): help that fits 80 columns, however wide the terminal."""

from __future__ import annotations

import argparse

import pytest

from forcenet.cli import build_parser


def _parsers() -> dict[str, argparse.ArgumentParser]:
    parser = build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return {"": parser, **sub.choices}


@pytest.mark.parametrize("columns", ["80", "200"])
def test_every_help_fits_80_columns(monkeypatch, columns):
    monkeypatch.setenv("COLUMNS", columns)
    for name, parser in _parsers().items():
        wide = [line for line in parser.format_help().splitlines() if len(line) > 80]
        assert not wide, (name, wide)


def test_a_narrow_terminal_still_narrows_the_help(monkeypatch):
    monkeypatch.setenv("COLUMNS", "60")
    lines = _parsers()["sample"].format_help().splitlines()
    assert max(len(line) for line in lines if not line.startswith("usage")) <= 62


def test_plans_read_as_their_announcement_and_a_refused_plan_says_so():
    import forcenet

    refused = forcenet.plan(300)
    assert refused.describe().startswith("refused: no method can run it") and "~0 s" not in refused.describe()
    assert repr(refused).startswith("TablePlan(exact table N=300") and "refused:" in repr(refused)
    big = forcenet.plan(100)
    assert repr(big).startswith("TablePlan(exact table N=100 (Pfaffians): ~") and "seconds=" not in repr(big)
    assert big.describe() in repr(big) and len(repr(forcenet.sample_plan(8, 2000))) < 80


def test_exact_samples_do_not_depend_on_the_number_of_workers():
    """Issue 53 item 7: streams of the seed and their index, shared by the workers, pooled in stream order."""
    import forcenet

    one = forcenet.sample(6, 21000, seed=3, workers=1)
    for workers in (2, 3):
        other = forcenet.sample(6, 21000, seed=3, workers=workers)
        assert (one.mean == other.mean).all() and (one.stderr == other.stderr).all()
    assert not (forcenet.sample(6, 21000, seed=4).mean == one.mean).all()


@pytest.mark.parametrize("argv", [["sample", "--N", "9", "--samples", "500", "--seed", "1"],
                                  ["dist", "--N", "8", "--grain", "8,4"],
                                  ["table", "--N", "16", "--samples", "300"]])
def test_terminal_output_fits_80_columns(tmp_path, argv):
    import subprocess
    import sys

    done = subprocess.run([sys.executable, "-m", "forcenet", *argv, "--quiet"], capture_output=True, text=True,
                          cwd=tmp_path, timeout=300, check=False)
    assert done.returncode == 0, done.stderr
    assert max(map(len, done.stdout.splitlines())) <= 80, done.stdout
