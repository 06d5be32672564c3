"""Issue 45 item 1: worker processes never outlive their parent, however it dies.

A pooled run (the Pfaffian route's per-prime pool, the samplers' pool) is
started as a subprocess, SIGKILLed once its workers exist, and every worker
must be gone a few seconds later: each worker of a local pool arms the
parent-death signal (:func:`forcenet.core.lifetime.die_with_parent`).
Before: all three processes of ``table --N 56 --method pfaffian`` were alive
10 s after the parent's SIGKILL.
"""

import os
import signal
import subprocess
import sys
import time

import pytest

from forcenet.core.execution import _PIDS, _submit_local, _terminate, local_pool

pytestmark = pytest.mark.skipif(not os.path.isdir("/proc/self/task"), reason="reads child processes from /proc")

ENTRY = "import sys; from forcenet.__main__ import run; sys.exit(run())"
GONE_SECONDS = 5.0  # the bound of the acceptance is 10 s


def _children(pid: int) -> list[int]:
    found = []
    try:
        for task in os.listdir(f"/proc/{pid}/task"):
            with open(f"/proc/{pid}/task/{task}/children") as handle:
                found += [int(x) for x in handle.read().split()]
    except (FileNotFoundError, ProcessLookupError):
        pass
    return found


def _alive(pid: int) -> bool:
    """Running or sleeping (a zombie or a reaped pid is gone)."""
    try:
        with open(f"/proc/{pid}/stat") as handle:
            return handle.read().rsplit(")", 1)[-1].split()[0] not in ("Z", "X")
    except (FileNotFoundError, ProcessLookupError):
        return False


def _workers(pid: int) -> list[int]:
    """The pool's worker processes (not multiprocessing's resource tracker)."""
    out = []
    for child in _children(pid):
        try:
            with open(f"/proc/{child}/cmdline", "rb") as handle:
                if b"resource_tracker" not in handle.read():
                    out.append(child)
        except FileNotFoundError:
            pass
    return out


def _kill_parent_and_wait(args, tmp_path, count: int) -> tuple[list[int], float]:
    """Start ``forcenet *args``, SIGKILL it once ``count`` workers run, return (workers, seconds until all are gone)."""
    process = subprocess.Popen([sys.executable, "-c", ENTRY, *args], cwd=tmp_path, stdout=subprocess.DEVNULL,
                               stderr=subprocess.DEVNULL)
    try:
        deadline, workers = time.monotonic() + 120, []
        while time.monotonic() < deadline and process.poll() is None and len(workers) < count:
            time.sleep(0.05)
            workers = _workers(process.pid)
        assert len(workers) >= count, "the run did not start its worker processes"
        time.sleep(0.5)  # the workers have taken their first tasks
        workers = _workers(process.pid)
        process.kill()
        process.wait(10)
        t0 = time.monotonic()
        while any(_alive(w) for w in workers) and time.monotonic() - t0 < GONE_SECONDS:
            time.sleep(0.05)
        return workers, time.monotonic() - t0
    finally:
        if process.poll() is None:
            process.kill()
            process.wait()
        for pid in _workers(process.pid):  # never leave one behind, even when the test fails
            os.kill(pid, signal.SIGKILL)


def test_pfaffian_pool_workers_die_with_a_sigkilled_parent(tmp_path):
    args = ["table", "--N", "56", "--method", "pfaffian", "--force", "--no-checkpoint", "--out", "t.json"]
    workers, seconds = _kill_parent_and_wait(args, tmp_path, 2)
    survivors = [w for w in workers if _alive(w)]
    for pid in survivors:
        os.kill(pid, signal.SIGKILL)
    assert not survivors, f"{len(survivors)} of {len(workers)} workers alive {seconds:.1f} s after the parent's SIGKILL"
    assert os.listdir(tmp_path) == []


@pytest.mark.slow
def test_sampler_pool_workers_die_with_a_sigkilled_parent(tmp_path):
    args = ["sample", "--N", "30", "--sampler", "metropolis", "--samples", "1000", "--burn-in", "10000000",
            "--workers", "2", "--force", "--out", "s.txt"]
    workers, seconds = _kill_parent_and_wait(args, tmp_path, 2)
    survivors = [w for w in workers if _alive(w)]
    for pid in survivors:
        os.kill(pid, signal.SIGKILL)
    assert not survivors, f"{len(survivors)} of {len(workers)} workers alive {seconds:.1f} s after the parent's SIGKILL"


def _parent_and_pdeathsig():
    """(the parent's pid, the parent-death signal armed in this worker) read from /proc and prctl."""
    import ctypes

    libc = ctypes.CDLL(None)
    value = ctypes.c_int(0)
    libc.prctl(2, ctypes.byref(value), 0, 0, 0)  # PR_GET_PDEATHSIG
    return os.getppid(), value.value


@pytest.mark.parametrize("method", ["spawn", "fork"])
def test_every_local_pool_arms_the_parent_death_signal(method):
    with local_pool(1, method) as pool:
        parent, armed = pool.submit(_parent_and_pdeathsig).result(timeout=60)
    assert parent == os.getpid()
    assert armed == signal.SIGKILL


def test_a_worker_whose_parent_is_already_gone_exits_at_once():
    # the race the check closes: the parent died before the worker armed its signal (then re-parented)
    block = f"from forcenet.core.lifetime import die_with_parent; die_with_parent({os.getpid()} + 10**7); print('ran')"
    result = subprocess.run([sys.executable, "-c", block], capture_output=True, text=True, timeout=60, check=False)
    assert result.returncode == 1 and result.stdout == ""
    block = "import os; from forcenet.core.lifetime import die_with_parent; die_with_parent(os.getppid()); print('ran')"
    result = subprocess.run([sys.executable, "-c", block], capture_output=True, text=True, timeout=60, check=False)
    assert result.returncode == 0 and result.stdout == "ran\n"  # the real parent: armed, and the work goes on


def _sigint_disposition():
    return signal.getsignal(signal.SIGINT)


@pytest.mark.parametrize("method", ["spawn", "fork"])
def test_a_local_pools_workers_leave_ctrl_c_to_their_parent(method):
    """A terminal's Ctrl-C reaches the whole process group; the workers ignore it and the parent stops them."""
    with local_pool(1, method) as pool:
        assert pool.submit(_sigint_disposition).result(timeout=60) == signal.SIG_IGN


def _nap(seconds):
    time.sleep(seconds)
    return seconds


@pytest.mark.skipif(not hasattr(signal, "pthread_kill"), reason="delivers the signal to one thread")
def test_a_signal_handed_to_another_thread_ends_the_wait_within_a_poll():
    """The kernel may hand a process's signal to any thread; Python runs the handler in the main thread only when
    it next runs bytecode. The pool's wait is bounded, so the run ends within a poll, not when the tasks end."""
    import threading

    from forcenet.core.execution import run_tasks

    class Stop(Exception):
        pass

    def stop(signum, frame):
        raise Stop

    previous = signal.signal(signal.SIGUSR1, stop)
    timer = threading.Timer(1.0, lambda: signal.pthread_kill(threading.get_ident(), signal.SIGUSR1))
    try:
        t0 = time.monotonic()
        timer.start()
        with pytest.raises(Stop):
            run_tasks(_nap, [(30,), (30,)], workers=2, start_method="fork")
        elapsed = time.monotonic() - t0
    finally:
        timer.cancel()
        signal.signal(signal.SIGUSR1, previous)
    assert elapsed < 15, f"{elapsed:.1f} s: the wait ended only with the tasks"


def test_a_worker_that_dies_is_a_family_error():
    """A local pool's worker gone (here it exits at once): the run stops with ClusterError, not
    concurrent.futures' BrokenProcessPool, and its message says what to do."""
    from concurrent.futures import BrokenExecutor

    from forcenet.core.errors import ClusterError
    from forcenet.core.execution import run_tasks

    with pytest.raises(ClusterError, match="ended abruptly") as caught:
        run_tasks(os._exit, [(3,), (3,)], workers=2)
    assert isinstance(caught.value.__cause__, BrokenExecutor)


UNGUARDED = ("from operator import add\n\nfrom forcenet.core.execution import run_tasks\n\n"
             "print('top level')\nprint(run_tasks(add, [(1, 2), (3, 4), (5, 6)], workers=2))\n")


@pytest.mark.parametrize("how", ["script", "stdin", "-c"])
def test_a_script_without_the_main_guard_runs_once(tmp_path, how):
    """Spawned workers never run the caller's script (issue 53): a script without ``if __name__ ==
    "__main__":``, the same code read from stdin or given to ``python -c``, runs its top level once, its
    workers compute, and nothing is written to stderr."""
    script = tmp_path / "unguarded.py"
    script.write_text(UNGUARDED)
    args = {"script": [str(script)], "stdin": ["-"], "-c": ["-c", UNGUARDED]}[how]
    done = subprocess.run([sys.executable, *args], input=UNGUARDED if how == "stdin" else None, capture_output=True,
                          text=True, timeout=120, cwd=tmp_path, check=False)
    assert (done.returncode, done.stdout, done.stderr) == (0, "top level\n[3, 7, 11]\n", "")


def test_the_callers_main_module_is_back_after_the_workers_start():
    """The bare ``__main__`` lasts only while the pool starts its workers."""
    from operator import add

    from forcenet.core.execution import run_tasks

    main = sys.modules["__main__"]
    assert run_tasks(add, [(1, 2), (3, 4)], workers=2) == [3, 7]
    assert sys.modules["__main__"] is main

@pytest.mark.slow
@pytest.mark.parametrize("how", ["script", "stdin"])
def test_an_unguarded_script_runs_the_pool_route_table(tmp_path, how):
    """The issue's acceptance: ``forcenet.table(40)`` (the multi-prime route, a pool of workers) from a script
    without the guard, and from stdin, prints its one line and nothing else."""
    code = "import forcenet\n\nprint(forcenet.table(40, progress=False).N)\n"
    script = tmp_path / "t.py"
    script.write_text(code)
    args = [str(script)] if how == "script" else ["-"]
    done = subprocess.run([sys.executable, *args], input=code if how == "stdin" else None, capture_output=True,
                          text=True, timeout=600, cwd=tmp_path, check=False)
    assert (done.returncode, done.stdout, done.stderr) == (0, "40\n", "")


@pytest.mark.slow
def test_an_interrupted_pool_stops_the_workers_it_has_no_pid_of():
    """The pool's stop terminates every worker its submits started, also one whose pid it never read (a worker
    interrupted while starting printed a traceback after "interrupted"): here both workers run a 30 s task and
    their reported pids are dropped, so only the submits' record names them; they must be gone within 5 s.
    (Slow: in a loaded CI run of an earlier form, checked at once after the stop, a worker still read as alive;
    not understood yet, see notes/benchmarks.md.)"""
    import multiprocessing

    pool = local_pool(2)
    futures = _submit_local(pool, [(time.sleep, 30), (time.sleep, 30)])
    started, reported = _PIDS[pool], []
    deadline = time.monotonic() + 60
    while len(reported) < 2 and time.monotonic() < deadline:  # both workers up and on their tasks
        reported += [started.get()] if not started.empty() else []
        time.sleep(0.05)
    time.sleep(0.5)
    processes = [p for p in multiprocessing.active_children() if p.pid in reported]
    del _PIDS[pool]  # only the submits' record names them now
    _terminate(pool)
    deadline = time.monotonic() + 5
    while any(p.is_alive() for p in processes) and time.monotonic() < deadline:
        time.sleep(0.1)
    assert len(futures) == 2 and len(processes) == 2 and not any(p.is_alive() for p in processes)
