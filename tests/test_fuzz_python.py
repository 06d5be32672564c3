"""Issue 56 (items 1, 3-6, 10's ``--out``/``--checkpoint``): a second hostile fuzz of the Python arguments.

Each case is one line of a table: the input and what must come of it -- in Python the
``forcenet.ForcenetError`` subclass whose message names the argument as the caller spelled it
(``checkpoint=``, ``x=``, ``grid=``...), at the command line exit 2 with one line on stderr.  Python's
``checkpoint=`` and the command line's ``--checkpoint`` go through one check
(:func:`forcenet.core.atomic_files.check_directory`), so every bad directory is refused by both, alike, before
any work.  Every case runs within a bound of seconds.
"""

from __future__ import annotations

import os
import time
from decimal import Decimal
from fractions import Fraction

import numpy as np
import pytest
import sympy

import forcenet
from forcenet.cli import main
from forcenet.core.errors import ArgumentError, ArgumentTypeError, ForcenetError
from forcenet.law_results import GRID_MAX, MOMENT_MAX
from forcenet.testing import compare

ROOT = os.geteuid() == 0 if hasattr(os, "geteuid") else False


@pytest.fixture
def sandbox(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    return tmp_path


def _bounded(call, bound=10.0):
    start = time.monotonic()
    try:
        return call()
    finally:
        assert time.monotonic() - start < bound


def _refused(call, kind, piece, bound=10.0):
    """``call()`` raises ``kind`` (a subclass of the family), its one-line message holding ``piece``."""
    with pytest.raises(kind) as info:
        _bounded(call, bound)
    assert isinstance(info.value, ForcenetError)
    message = str(info.value)
    assert "\n" not in message and piece in message, message
    return message


# --- 1. checkpoint= as --checkpoint: one check ------------------------------------------------------------------

def _bad_directory(kind, root):
    """A directory argument of the given ``kind`` under ``root`` (made there), and the reason's words."""
    if kind == "file":
        (root / "records.txt").write_text("x")
        return "records.txt", "not a directory"
    if kind == "empty":
        return "", "an empty directory name"
    if kind == "devnull":
        return os.devnull, "not a directory"
    if kind == "loop":
        os.symlink("loop", root / "loop")
        return "loop", "symbolic link"
    if kind == "dangling":
        os.symlink(root / "nowhere" / "deeper", root / "dangling")
        return "dangling", "symbolic link"
    if kind == "long":
        return "d" * 300, "longer than"
    if kind == "no-parent":
        return os.path.join("missing", "records"), "does not exist"
    if kind == "parent-is-file":
        (root / "plain").write_text("x")
        return os.path.join("plain", "records"), "does not exist"
    if kind == "nul":
        return "rec\0ords", "NUL"
    if kind == "pathlike-file":
        (root / "f.json").write_text("{}")
        return root / "f.json", "not a directory"
    if kind == "read-only":
        (root / "ro").mkdir()
        os.chmod(root / "ro", 0o500)
        return os.path.join("ro", "records"), "not writable"
    raise AssertionError(kind)


DIRECTORY_KINDS = ["file", "empty", "devnull", "loop", "dangling", "long", "no-parent", "parent-is-file", "nul",
                   "pathlike-file", pytest.param("read-only", marks=pytest.mark.skipif(ROOT, reason="root writes"))]

PYTHON_CHECKPOINT_CALLS = {
    "plan": lambda d: forcenet.plan(12, method="pfaffian", checkpoint=d),
    "table": lambda d: forcenet.table(12, method="pfaffian", checkpoint=d),
    "law_plan": lambda d: forcenet.law_plan(40, layer=40, checkpoint=d),
    "law": lambda d: forcenet.law(40, layer=40, checkpoint=d),
    "scaling_plan": lambda d: forcenet.scaling_plan("percolation", checkpoint=d),
}


@pytest.mark.parametrize("kind", DIRECTORY_KINDS)
@pytest.mark.parametrize("call", sorted(PYTHON_CHECKPOINT_CALLS))
def test_python_checkpoint_refused_before_any_work(call, kind, sandbox, capsys):
    directory, reason = _bad_directory(kind, sandbox)
    before = sorted(os.listdir(sandbox))
    message = _refused(lambda: PYTHON_CHECKPOINT_CALLS[call](directory), ArgumentError, reason)
    assert message.startswith("checkpoint=") and "--checkpoint" not in message
    assert sorted(os.listdir(sandbox)) == before  # nothing written, in the current folder least of all
    assert "--checkpoint" not in capsys.readouterr().err  # no command-line advice printed to a Python caller


@pytest.mark.parametrize("kind", DIRECTORY_KINDS)
def test_cli_checkpoint_refused_alike(kind, sandbox, capsys):
    directory, reason = _bad_directory(kind, sandbox)
    if kind == "nul":
        pytest.skip("a command line cannot hold a NUL byte")
    code = _bounded(lambda: main(["table", "--N", "12", "--method", "pfaffian", "--checkpoint", str(directory)]))
    err = capsys.readouterr().err
    assert code == 2 and len(err.splitlines()) == 1 and reason in err and "--checkpoint=" in err, err


@pytest.mark.parametrize("kind", DIRECTORY_KINDS)
@pytest.mark.parametrize("command", [["scaling", "--model", "percolation"], ["dist", "--N", "40", "--layer", "40"]])
def test_cli_checkpoint_refused_by_every_command(command, kind, sandbox, capsys):
    directory, reason = _bad_directory(kind, sandbox)
    if kind == "nul":
        pytest.skip("a command line cannot hold a NUL byte")
    code = _bounded(lambda: main([*command, "--checkpoint", str(directory)]))
    err = capsys.readouterr().err
    assert code == 2 and len(err.splitlines()) == 1 and reason in err and "--checkpoint=" in err, err


@pytest.mark.parametrize("kind", DIRECTORY_KINDS)
def test_one_check_same_reason(kind, sandbox, capsys):
    """The Python message and the command line's give the same reason after the argument."""
    directory, _ = _bad_directory(kind, sandbox)
    if kind == "nul":
        pytest.skip("a command line cannot hold a NUL byte")
    with pytest.raises(ArgumentError) as info:
        forcenet.plan(12, method="pfaffian", checkpoint=directory)
    main(["table", "--N", "12", "--method", "pfaffian", "--checkpoint", str(directory)])
    err = capsys.readouterr().err
    assert str(info.value).split(": ", 1)[1].split(";")[0] in err, (str(info.value), err)


@pytest.mark.parametrize("value", [5, 1.5, b"records", ["a"], object(), True])
@pytest.mark.parametrize("call", ["plan", "law_plan", "scaling_plan"])
def test_checkpoint_of_the_wrong_type(call, value, sandbox):
    _refused(lambda: PYTHON_CHECKPOINT_CALLS[call](value), ArgumentTypeError, "is not a directory path")


@pytest.mark.parametrize("call", ["plan", "law_plan"])
def test_a_new_checkpoint_folder_is_accepted(call, sandbox):
    plan = PYTHON_CHECKPOINT_CALLS[call](sandbox / "new")
    assert plan.runnable and plan.checkpoint is not None
    assert not (sandbox / "new").exists()  # planning creates nothing


# --- 4. memory_bytes ---------------------------------------------------------------------------------------------

MEMORY_CALLS = {
    "plan": lambda m: forcenet.plan(6, memory_bytes=m),
    "table": lambda m: forcenet.table(6, memory_bytes=m),
    "plan-moments": lambda m: forcenet.plan(6, moments=3, memory_bytes=m),
    "plan-row": lambda m: forcenet.row_plan(6, 3, memory_bytes=m),
    "law_plan": lambda m: forcenet.law_plan(6, layer=6, memory_bytes=m),
}


@pytest.mark.parametrize("value, kind", [(0, ArgumentError), (-1, ArgumentError), (True, ArgumentTypeError),
                                         (1.5, ArgumentTypeError), ("100", ArgumentTypeError)])
@pytest.mark.parametrize("call", sorted(MEMORY_CALLS))
def test_memory_bytes_out_of_the_family(call, value, kind):
    _refused(lambda: MEMORY_CALLS[call](value), kind, "memory_bytes=")


@pytest.mark.parametrize("memory", [1, 100, 2000])
def test_tiny_memory_plans_a_refusal_or_a_route_that_fits(memory):
    plan = forcenet.plan(6, memory_bytes=memory)
    assert plan.runnable or "available" in plan.refusal
    fast = forcenet.plan(8, method="fast", memory_bytes=memory)  # the order-ideal DP's refusal names a way out
    assert not fast.runnable and "is available" in fast.refusal and "method='auto' runs it" in fast.refusal


def test_one_byte_still_computes_the_table_by_a_route_that_fits():
    assert forcenet.table(6, memory_bytes=1).mean_W == forcenet.table(6).mean_W


# --- 3, 5. a Law's arguments -------------------------------------------------------------------------------------

@pytest.fixture(scope="module")
def law():
    return forcenet.law(4, layer=4)


BAD_POINTS = [
    (float("nan"), ArgumentError, "finite"), (float("inf"), ArgumentError, "finite"),
    (float("-inf"), ArgumentError, "finite"), (np.float64("nan"), ArgumentError, "finite"),
    (np.float32("inf"), ArgumentError, "finite"), ("abc", ArgumentTypeError, "not a number"),
    ("1/0", ArgumentError, "zero denominator"), ("", ArgumentTypeError, "not a number"),
    (None, ArgumentTypeError, "not a number"), (1j, ArgumentTypeError, "not a number"),
    ([1], ArgumentTypeError, "not a number"), ((1, 2), ArgumentTypeError, "not a number"),
    ({}, ArgumentTypeError, "not a number"), (True, ArgumentTypeError, "not a number"),
    (False, ArgumentTypeError, "not a number"), ("1e99999999", ArgumentError, "exponent"),
    ("-1e-99999999", ArgumentError, "exponent"), (object(), ArgumentTypeError, "not a number"),
    (b"1", ArgumentTypeError, "not a number"), (Decimal("NaN"), ArgumentTypeError, "not a number"),
]


@pytest.mark.parametrize("x, kind, piece", BAD_POINTS, ids=[repr(p[0])[:20] for p in BAD_POINTS])
@pytest.mark.parametrize("method", ["density_at", "cdf_at"])
def test_law_points_refused(law, method, x, kind, piece):
    message = _refused(lambda: getattr(law, method)(x), kind, piece)
    assert message.startswith("x=")


@pytest.mark.parametrize("method", ["density_at", "cdf_at"])
@pytest.mark.parametrize("x", ["1/3", "5/2", "-1", "7", "0.75", "3e-1"])
def test_law_points_exact_by_every_spelling(law, method, x):
    """A point as a string, a Fraction, a sympy Rational and a Decimal: one exact value; a binary float close
    to it rounds the exact value at that float."""
    at = getattr(law, method)
    value = at(x)
    assert isinstance(value, Fraction)
    assert at(Fraction(x)) == at(sympy.Rational(x)) == value
    if "/" not in x:
        assert at(Decimal(x)) == value
    assert abs(at(float(Fraction(x))) - float(value)) <= 1e-12


@pytest.mark.parametrize("s, kind", [(10**8, ArgumentError), (MOMENT_MAX + 1, ArgumentError), (-1, ArgumentError),
                                     (True, ArgumentTypeError), (1.5, ArgumentTypeError), ("2", ArgumentTypeError),
                                     (None, ArgumentTypeError)])
def test_law_moment_capped(law, s, kind):
    _refused(lambda: law.moment(s), kind, "s=", bound=2.0)


def test_law_moment_at_the_cap_is_bounded(law):
    """The highest moment answers within a second and lies between the support's powers."""
    lo, hi = law.support
    value = _bounded(lambda: law.moment(MOMENT_MAX), 2.0)
    assert lo**MOMENT_MAX <= value <= hi**MOMENT_MAX


GRID_CALLS = {
    "grid": ("K", lambda law, k: law.grid(k)),
    "to_json": ("grid", lambda law, k: law.to_json(grid=k)),
    "to_dict": ("grid", lambda law, k: law.to_dict(grid=k)),
    "to_csv": ("grid", lambda law, k: law.to_csv(grid=k)),
    "to_latex": ("grid", lambda law, k: law.to_latex(grid=k)),
    "to_text": ("grid", lambda law, k: law.to_text(grid=k)),
    "plot": ("points", lambda law, k: law.plot(points=k)),
}


@pytest.mark.parametrize("k, kind", [(0, ArgumentError), (-3, ArgumentError), (GRID_MAX + 1, ArgumentError),
                                     (10**9, ArgumentError), (True, ArgumentTypeError), (2.0, ArgumentTypeError),
                                     ("10", ArgumentTypeError)])
@pytest.mark.parametrize("method", sorted(GRID_CALLS))
def test_law_grid_capped_naming_the_argument(law, method, k, kind):
    name, call = GRID_CALLS[method]
    message = _refused(lambda: call(law, k), kind, f"in 1..{GRID_MAX}", bound=2.0)
    assert message.startswith(f"{name}="), message


def test_the_command_line_caps_grid_alike(capsys):
    code = main(["dist", "--N", "4", "--layer", "4", "--grid", str(GRID_MAX + 1)])
    err = capsys.readouterr().err
    assert code == 2 and f"1..{GRID_MAX}" in err, err


@pytest.mark.parametrize("ax", [5, "axes", object(), [None]])
def test_law_plot_refuses_what_is_not_axes(law, ax):
    pytest.importorskip("matplotlib")
    _refused(lambda: law.plot(ax=ax), ArgumentTypeError, "ax=")


# --- 6. compare: a table of another size, a Table --------------------------------------------------------------

def _uniform(N, K=200):
    """``K`` samples shaped like an ``N``-layer triangle (row ``i`` has ``i`` values in [0, 1])."""
    rng = np.random.default_rng(N)
    x = rng.uniform(size=(K, N, N))
    return np.tril(x)  # zeros beyond the triangle, as the samplers give


@pytest.fixture(scope="module")
def table6():
    return forcenet.table(6)


@pytest.mark.parametrize("N", [7, 8, 12])
@pytest.mark.parametrize("as_table", [True, False])
def test_compare_refuses_samples_bigger_than_the_table(table6, N, as_table):
    exact = table6 if as_table else table6.mean_W
    _refused(lambda: compare(_uniform(N), exact), ArgumentError, f"fewer than the samples' first axis of length {N}")


@pytest.mark.parametrize("N", [3, 5])
def test_compare_refuses_samples_smaller_than_the_table(table6, N):
    _refused(lambda: compare(_uniform(N), table6), ArgumentError, "more than the samples' axis")


def test_compare_takes_a_table_as_its_mean(table6):
    from forcenet.numeric.triangle.exact_sampler import ExactSampler

    W = ExactSampler(6, seed=3).sample_W(2000)
    by_table, by_list = compare(W, table6), compare(W, table6.mean_W)
    assert by_table.verdict == by_list.verdict == "agrees"
    assert by_table.values == by_list.values


# --- 10. --out naming the --checkpoint folder ------------------------------------------------------------------

@pytest.mark.parametrize("out, checkpoint", [("r.json", "r.json"), ("r.json", "r.json/"), ("./r.json", "r.json"),
                                             ("r.json", os.path.join("r.json", "inner"))])
def test_out_naming_the_checkpoint_folder_refused_before_the_run(out, checkpoint, sandbox, capsys):
    if checkpoint.endswith("inner"):
        (sandbox / "r.json").mkdir()  # --checkpoint inside an existing folder that --out names
    code = _bounded(lambda: main(["table", "--N", "40", "--method", "pfaffian", "--checkpoint", checkpoint,
                                  "--out", out]), 10.0)
    err = capsys.readouterr().err
    assert code == 2 and len(err.splitlines()) == 1 and "--out" in err, err
    assert not (sandbox / "r.json").exists() or not os.listdir(sandbox / "r.json")  # no record written


# --- 5. the other arguments: limit_shape's coordinates, progress=, a shut-down executor --------------------------

@pytest.mark.parametrize("x, z, kind, piece", [
    ("0", float("inf"), ArgumentError, "z=inf"), ("0", float("-inf"), ArgumentError, "z=-inf"),
    (float("nan"), "1/2", ArgumentError, "x=nan"), (float("inf"), "1/2", ArgumentError, "x=inf"),
    ("0", np.float64("nan"), ArgumentError, "z=nan"), ("1e99999999", "1/2", ArgumentError, "exponent"),
    ("0", "-1e-99999999", ArgumentError, "exponent"), ("0", "1/0", ArgumentTypeError, "z='1/0'"),
    ("abc", "1/2", ArgumentTypeError, "x='abc'"), (None, "1/2", ArgumentTypeError, "x=None"),
    ("0", 1j, ArgumentTypeError, "z=1j"), (True, "1/2", ArgumentTypeError, "x"),
])
def test_limit_shape_coordinates_in_the_family(x, z, kind, piece):
    _refused(lambda: forcenet.limit_shape(x, z), kind, piece)


PROGRESS_CALLS = {
    "table": lambda p: forcenet.table(5, progress=p),
    "law": lambda p: forcenet.law(4, layer=4, progress=p),
    "plan.run": lambda p: forcenet.plan(5).run(p),
}


@pytest.mark.parametrize("progress", ["yes", 5, 1.0, [], object()])
@pytest.mark.parametrize("call", sorted(PROGRESS_CALLS))
def test_progress_neither_callable_nor_bool_refused(call, progress):
    _refused(lambda: PROGRESS_CALLS[call](progress), ArgumentTypeError, "progress=")


@pytest.mark.parametrize("progress", [None, False])
@pytest.mark.parametrize("call", sorted(PROGRESS_CALLS))
def test_progress_off_runs(call, progress):
    assert PROGRESS_CALLS[call](progress) is not None


def test_a_callable_progress_counts_ticks():
    ticks = []
    forcenet.table(6, method="fast", progress=lambda k=1: ticks.append(k))
    assert ticks


EXECUTOR_CALLS = {
    "plan": lambda e: forcenet.plan(12, method="pfaffian", executor=e),
    "table": lambda e: forcenet.table(12, method="pfaffian", executor=e),
    "law_plan": lambda e: forcenet.law_plan(40, layer=40, executor=e),
}


@pytest.mark.parametrize("pool", ["threads", "processes"])
@pytest.mark.parametrize("call", sorted(EXECUTOR_CALLS))
def test_a_shut_down_executor_is_refused_before_the_run(call, pool):
    from concurrent.futures import ProcessPoolExecutor, ThreadPoolExecutor

    executor = (ThreadPoolExecutor if pool == "threads" else ProcessPoolExecutor)(1)
    executor.shutdown()
    _refused(lambda: EXECUTOR_CALLS[call](executor), ArgumentError, "is shut down")


@pytest.mark.parametrize("value", [3, "localhost:8786", object()])
@pytest.mark.parametrize("call", sorted(EXECUTOR_CALLS))
def test_what_is_not_an_executor_is_refused(call, value):
    _refused(lambda: EXECUTOR_CALLS[call](value), ArgumentTypeError, "is not a concurrent.futures.Executor")


# --- 9. a closed terminal's SIGHUP; Dask's internal class names ------------------------------------------------

_TRACKER_PROBE = """
import signal, sys, multiprocessing.resource_tracker as rt
from forcenet.core.execution import local_pool
mine = lambda *a: None
signal.signal(signal.SIGHUP, mine)
with local_pool(1) as pool:
    pool.submit(abs, -1).result()
    status = open(f"/proc/{rt._resource_tracker._pid}/status").read()
    ignored = int(next(l for l in status.splitlines() if l.startswith("SigIgn:")).split()[1], 16)
    quiet = "-Wignore:resource_tracker:UserWarning" in open(f"/proc/{rt._resource_tracker._pid}/cmdline").read()
    print(ignored & 1, signal.getsignal(signal.SIGHUP) is mine, quiet, "ignore:resource_tracker" in str(sys.warnoptions))
"""


@pytest.mark.skipif(not os.path.exists("/proc/self/status"), reason="reads /proc")
def test_the_resource_tracker_outlives_a_hangup_and_the_handler_is_restored():
    """The tracker ignores SIGHUP (a group's hang-up would kill it and the shutdown print KeyError tracebacks
    from a relaunched one) and its "leaked semaphore" warnings (after a SIGKILL); this process's own SIGHUP
    handler and warning options are left as they were."""
    import subprocess
    import sys

    done = subprocess.run([sys.executable, "-c", _TRACKER_PROBE], capture_output=True, text=True, timeout=60, check=False)
    assert done.returncode == 0 and "Traceback" not in done.stderr, done.stderr
    assert done.stdout.split() == ["1", "True", "True", "False"], done.stdout  # deaf, restored, quiet, restored


def test_a_dask_executor_is_named_as_a_cluster_not_by_its_class():
    from concurrent.futures import Executor

    from forcenet.core.execution import executor_label

    fake = type("ClientExecutor", (Executor,), {"__module__": "distributed.client"})()
    label = executor_label(fake)
    assert "ClientExecutor" not in label and "Dask" in label


# --- 10. estimates count only the work measured in this run ----------------------------------------------------

def _triple(a):
    return np.array([3 * a], dtype=np.int64)


@pytest.mark.parametrize("held", [0, 1, 3, 5])
def test_reused_records_tick_once_before_the_measured_work(held, tmp_path):
    """The records taken from a checkpoint come in one progress call before any computed task: a rate measured
    from the first call on (the command line's restated estimate) counts only the work of this run."""
    from forcenet.core.checkpoints import CheckpointStore
    from forcenet.core.execution import run_tasks

    store = CheckpointStore(tmp_path, "fuzz-test", N=5)
    for key in range(held):
        store.save(key, _triple(key))
    calls = []
    results = run_tasks(_triple, [(k,) for k in range(5)], progress=calls.append, store=store, keys=list(range(5)))
    assert [int(r[0]) for r in results] == [0, 3, 6, 9, 12]
    assert calls == ([held] if held else []) + [1] * (5 - held)


@pytest.fixture(scope="module")
def law20():
    return forcenet.law(20, layer=20)


def test_a_grid_too_long_for_its_degree_is_refused_naming_what_fits(law20):
    """``grid(100000)`` of a degree-189 law would take minutes: refused at once, naming the ``K`` that fits, which
    then runs within the planned time (``GRID_SECONDS``)."""
    from forcenet.law_results import GRID_SECONDS

    message = _refused(lambda: law20.to_json(grid=GRID_MAX), ArgumentError, "for this law", bound=2.0)
    fits = int(message.rsplit("1..", 1)[1].split()[0])
    assert 1 <= fits < GRID_MAX
    small = max(1, fits // 100)  # a hundredth of it: well inside the plan, quick here
    x, p, F = _bounded(lambda: law20.grid(small), GRID_SECONDS / 100 * 3)
    assert len(x) == small + 1 and F[-1] == 1.0
