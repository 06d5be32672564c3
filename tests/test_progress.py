"""Issue 45 item 5: the progress bar readable at 80 columns, the announcement on its own line, one estimate per line,
the estimate restated once from the measured rate.

The bar is drawn on a pseudo-terminal of 80 columns (what a user's terminal is to tqdm): every frame fits and shows
its percentage. Before: the bar's label was the whole announcement of ``--method auto`` and no percentage was ever
visible at 80 or 120 columns.
"""

import fcntl
import os
import pty
import re
import select
import struct
import subprocess
import sys
import termios
import time

import pytest

from forcenet.cli import common
from forcenet.cli.common import progress_label, run_planned
from forcenet.core.plan import Plan

AUTO = ("exact table N=40 (Pfaffians); auto chose pfaffian: the fastest by the plans (pfaffian ~7 s; fast, thesis, "
        "lambda, maps out of range)")
DURATION = re.compile(r"~\d+(\.\d+)? (s|min|h|days)\b")


def _terminal(columns: int = 80):
    """(master, slave) of a pseudo-terminal ``columns`` wide."""
    master, slave = pty.openpty()
    fcntl.ioctl(slave, termios.TIOCSWINSZ, struct.pack("HHHH", 24, columns, 0, 0))
    return master, slave


def _read_all(master: int, timeout: float = 2.0) -> str:
    chunks, deadline = [], time.monotonic() + timeout
    while time.monotonic() < deadline:
        ready, _, _ = select.select([master], [], [], 0.1)
        if not ready:
            break
        try:
            chunks.append(os.read(master, 65536))
        except OSError:
            break
    return b"".join(chunks).decode("utf-8", "replace")


def _frames(text: str) -> list[str]:
    """What a terminal shows line by line: every carriage-return-separated frame, escape sequences removed."""
    text = re.sub(r"\x1b\[[0-9;]*[A-Za-z]", "", text)
    return [frame for line in text.split("\n") for frame in line.split("\r") if frame.strip()]


@pytest.mark.parametrize("unit", ["prime", "s"])
def test_the_bar_shows_its_percentage_at_80_columns(monkeypatch, unit):
    master, slave = _terminal(80)
    terminal = os.fdopen(slave, "w", buffering=1)
    monkeypatch.setattr(sys, "stderr", terminal)
    monkeypatch.setattr(common, "REVISE_SECONDS", 1e9)  # this test is about the bar

    def run(progress):
        for _ in range(10):
            time.sleep(0.12)  # tqdm redraws at most every 0.1 s
            progress(1)
        return "result"

    try:
        assert run_planned(Plan(AUTO, 5.0, ticks=10, unit=unit), run) == "result"
        terminal.flush()
        frames = _frames(_read_all(master))
    finally:
        terminal.close()
        os.close(master)
    assert frames[0] == "forcenet: exact table N=40 (Pfaffians): estimated ~5 s"
    assert frames[1].startswith("forcenet: auto chose pfaffian")  # the reason: a line of its own
    bars = [f for f in frames if f.startswith("exact table N=40:")]
    assert bars, frames
    assert all(len(f) <= 80 for f in bars), max(bars, key=len)
    assert all(re.search(r"\b\d{1,3}%", f) for f in bars), bars
    assert any("100%" in f or "90%" in f for f in bars), bars
    assert frames[-1].startswith("forcenet: exact table N=40: done in")
    assert all(len(DURATION.findall(f)) <= 1 for f in frames[:1])  # the announcement states one time


def test_the_estimate_is_restated_once_from_the_measured_rate(monkeypatch, capsys):
    monkeypatch.setattr(common, "REVISE_SECONDS", 0.2)

    def run(progress):
        for _ in range(20):
            time.sleep(0.05)  # 20 ticks in ~1 s where the plan said 10 s: ten times fast
            progress(1)

    run_planned(Plan("exact table N=30 (Pfaffians)", 10.0, ticks=20, unit="prime"), run)
    lines = capsys.readouterr().err.splitlines()
    revised = [line for line in lines if "at the measured rate" in line]
    assert len(revised) == 1, lines
    assert revised[0].startswith("forcenet: exact table N=30: at the measured rate ~1 s in all")
    assert all(len(DURATION.findall(line)) <= 1 for line in lines), lines  # no line states two different times


def test_an_estimate_that_holds_is_not_restated(monkeypatch, capsys):
    monkeypatch.setattr(common, "REVISE_SECONDS", 0.2)

    def run(progress):
        for _ in range(10):
            time.sleep(0.25)
            progress(1)

    run_planned(Plan("exact table N=30 (Pfaffians)", 3.0, ticks=10, unit="prime"), run)  # 2.5 s: within 1.5x
    assert "measured rate" not in capsys.readouterr().err


@pytest.mark.parametrize("what, label", [
    (AUTO, "exact table N=40"),
    ("exact tables N=9, <W^s> for s = 1..2 (order ideals)", "exact tables N=9"),
    ("<W^2> table N=20", "<W^2> table N=20"),
    ("x" * 50, "x" * 27 + "..."),
])
def test_the_label_is_the_quantity_and_N(what, label):
    assert progress_label(what) == label


@pytest.mark.slow
def test_the_real_command_shows_a_percentage_at_80_columns(tmp_path):
    master, slave = _terminal(80)
    env = {**os.environ, "COLUMNS": "80"}
    process = subprocess.Popen([sys.executable, "-m", "forcenet", "table", "--N", "40", "--format", "json", "--out",
                                str(tmp_path / "t.json"), "--no-checkpoint", "--force"], stdin=subprocess.DEVNULL,
                               stdout=subprocess.DEVNULL, stderr=slave, env=env)
    os.close(slave)
    output = []
    while process.poll() is None:
        output.append(_read_all(master, 1.0))
    output.append(_read_all(master, 1.0))
    os.close(master)
    assert process.returncode == 0, "".join(output)
    bars = [f for f in _frames("".join(output)) if f.startswith("exact table N=40:")]
    assert bars and all(len(f) <= 80 and re.search(r"\b\d{1,3}%", f) for f in bars), bars


@pytest.mark.parametrize("compiling, restated", [((), True), ((("kernels", 5.0),), False)])
def test_the_estimate_is_not_restated_from_a_rate_that_includes_compiling(monkeypatch, capsys, compiling, restated):
    """A run that compiles its kernels (first use on a machine) is slow at first for that reason alone: the
    measured rate would overstate the rest (the main job's N = 12 once said ~58 s for a 12 s run)."""
    from forcenet.cli import common
    from forcenet.core.plan import Plan

    clock = iter(float(t) for t in range(0, 1000, 10))
    monkeypatch.setattr(common.time, "perf_counter", lambda: next(clock))
    reviser = common._Reviser(Plan("exact table N=12", 12.0, ticks=10, compiling=compiling), "exact table N=12", None)
    for _ in range(5):
        reviser(1)
    assert ("at the measured rate" in capsys.readouterr().err) is restated


def test_the_bar_never_passes_100_percent_and_says_the_time_left(monkeypatch):
    """Issue 53: twice the planned ticks (a slow machine, an estimate in seconds): the bar re-estimates its total
    instead of counting past it; its time left reads "~N s left", never "est. s"."""
    from forcenet.core.progress import Bar

    master, slave = _terminal(80)
    terminal = os.fdopen(slave, "w", buffering=1)
    try:
        bar = Bar(10, "exact table N=40", "s", file=terminal)
        for _ in range(20):
            time.sleep(0.11)
            bar.update(1)
        bar.close()
        terminal.flush()
        frames = _frames(_read_all(master))
    finally:
        terminal.close()
        os.close(master)
    percents = [int(p) for f in frames for p in re.findall(r"\b(\d{1,3})%", f)]
    assert percents and max(percents) <= 100 and max(percents) >= 90, frames
    assert any(re.search(r"~\d+ s left", f) for f in frames) and not any("est. s" in f for f in frames), frames
    assert all(len(f) <= 80 for f in frames)


def test_the_front_door_shows_progress_where_a_person_watches():
    """``progress=None``: on a terminal, the plan's line and a bar; in a pipe, nothing; ``False`` never."""
    import io

    from forcenet.core.progress import ticks

    plan = Plan("exact table N=40 (Pfaffians)", 30.0, ticks=4, unit="prime")
    master, slave = _terminal(80)
    terminal = os.fdopen(slave, "w", buffering=1)
    try:
        with ticks(plan, None, "table N=40", terminal) as tick:
            assert tick is not None
            tick(4)
        with ticks(plan, False, "table N=40", terminal) as tick:
            assert tick is None
        terminal.flush()
        frames = _frames(_read_all(master))
    finally:
        terminal.close()
        os.close(master)
    assert frames[0] == "forcenet: exact table N=40 (Pfaffians): estimated ~30 s" and len(frames) >= 2
    pipe = io.StringIO()
    with ticks(plan, None, "table N=40", pipe) as tick:
        assert tick is None
    assert pipe.getvalue() == ""
    with ticks(Plan("x", 1.0, ticks=4), None, "x", terminal) as tick:  # a short run: no bar unasked
        assert tick is None


def test_a_script_in_a_pipe_prints_no_progress(tmp_path):
    code = "import forcenet\nprint(forcenet.table(12).N)\n"
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300, check=False)
    assert (done.returncode, done.stdout, done.stderr) == (0, "12\n", "")


def test_the_command_line_owns_its_progress(monkeypatch):
    """``--quiet`` (or a short run) hands the front door no tick: its own policy must not draw a bar then."""
    from forcenet.core.progress import ticks

    master, slave = _terminal(80)
    terminal = os.fdopen(slave, "w", buffering=1)
    monkeypatch.setattr(sys, "stderr", terminal)
    seen = []

    def run(progress):
        with ticks(Plan("x", 30.0, ticks=3), progress, "x") as tick:
            seen.append(tick)
        return "done"

    try:
        assert run_planned(Plan("x", 30.0, ticks=3), run, quiet=True) == "done"
        terminal.flush()
        shown = _read_all(master, 0.5)
    finally:
        terminal.close()
        os.close(master)
    assert seen == [None] and shown == ""
