"""The per-prime tasks on a real Dask cluster (two worker processes on 127.0.0.1), and Ctrl-C on a local pool.

The same request gives the same bytes locally and on the cluster; a worker
killed mid-run changes nothing in the result; a task failing for another
reason fails the run with its message; ``--scheduler`` without the extra is
one line naming it; Ctrl-C ends a multi-worker run within seconds, workers
included, leaving no file.
"""

import json
import os
import signal
import subprocess
import sys
import time

import pytest

from forcenet.cli import main
from forcenet.exact.execution import executor_workers, run_tasks
from forcenet.exact.triangle.pfaffian import route
from forcenet.exact.triangle.pfaffian.engine import count_residue

distributed = pytest.importorskip("distributed")  # the `test` extra includes `distributed`


def _warm():
    """Load the compiled kernels in a worker (once; later tasks measure the work, not numba's start-up)."""
    return count_residue(12, 33554393)


@pytest.fixture(scope="module")
def client():
    cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                                       dashboard_address=None)
    client = distributed.Client(cluster, set_as_default=False)
    client.run(_warm)
    yield client
    client.close()
    cluster.close()


def _local_json(N: int, capsys) -> str:
    assert main(["table", "--N", str(N), "--method", "pfaffian", "--format", "json"]) == 0
    return capsys.readouterr().out


def _cli(*args, **kwargs):
    return subprocess.run([sys.executable, "-m", "forcenet", "table", "--method", "pfaffian", "--format", "json",
                           *args], capture_output=True, text=True, check=False, **kwargs)


def test_cluster_gives_the_local_bytes_through_the_command_line(client, capsys, tmp_path):
    address = client.scheduler.address
    expected = _local_json(26, capsys)
    result = _cli("--N", "26", "--scheduler", address)
    assert result.returncode == 0, result.stderr
    assert result.stdout == expected
    scheduler_file = tmp_path / "scheduler.json"  # the other form of ADDRESS: a scheduler file
    scheduler_file.write_text(json.dumps({"address": address}))
    expected = _local_json(12, capsys)
    assert main(["table", "--N", "12", "--method", "pfaffian", "--format", "json", "--scheduler", str(scheduler_file)]) == 0
    assert capsys.readouterr().out == expected


def test_plan_announces_the_cluster_and_its_time(client):
    plan = route.table_plan(64, executor=client)
    assert f"on 2 workers of Dask scheduler {client.scheduler.address}" in plan.what
    local = route.table_plan(64, workers=1)
    assert plan.seconds < local.seconds  # two workers, the scheduler's overhead included
    assert executor_workers(client) == 2


def test_a_worker_killed_mid_run_changes_nothing(client):
    N = 26
    expected = route.mean_W(N)
    pids = client.run(os.getpid)
    done = []

    def progress(k):
        done.append(k)
        if len(done) == 8:  # about 25 % of the primes finished: kill a worker in the middle of its task
            os.kill(next(iter(pids.values())), signal.SIGKILL)

    assert route.mean_W(N, executor=client, progress=progress) == expected
    assert len(done) == route.table_plan(N).ticks


def test_a_failing_task_fails_the_run_with_its_message(client):
    with pytest.raises(ValueError, match="backend"):
        run_tasks(count_residue, [(12, 33554393, "no-such-backend")] * 2, executor=client.get_executor())


def test_scheduler_without_the_extra_is_one_line():
    block = ("import sys; sys.modules['distributed'] = None; from forcenet.cli import main; "
             "sys.exit(main(['table', '--N', '20', '--method', 'pfaffian', '--format', 'json', "
             "'--scheduler', 'tcp://127.0.0.1:1']))")
    result = subprocess.run([sys.executable, "-c", block], capture_output=True, text=True, check=False)
    assert result.returncode == 2 and result.stdout == ""
    assert result.stderr.count("\n") == 1 and "pip install 'forcenet[distributed]'" in result.stderr


def test_unreachable_scheduler_is_one_line(monkeypatch, capsys):
    from forcenet.cli import table

    monkeypatch.setattr(table, "_CONNECT_SECONDS", 1)
    assert main(["table", "--N", "20", "--method", "pfaffian", "--format", "json", "--scheduler", "tcp://127.0.0.1:9"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--scheduler=tcp://127.0.0.1:9: cannot connect" in err


def _children(pid: int) -> list[int]:
    out = []
    for task in os.listdir(f"/proc/{pid}/task"):
        with open(f"/proc/{pid}/task/{task}/children") as handle:
            out += [int(x) for x in handle.read().split()]
    return out


def _gone(pid: int) -> bool:
    try:
        with open(f"/proc/{pid}/stat") as handle:
            return handle.read().split(")")[-1].split()[0] in ("Z", "X")
    except FileNotFoundError:
        return True


@pytest.mark.skipif(not os.path.isdir("/proc/self/task"), reason="reads child processes from /proc")
def test_ctrl_c_ends_a_multi_worker_run_within_seconds(tmp_path):
    out = tmp_path / "table.json"
    process = subprocess.Popen([sys.executable, "-m", "forcenet", "table", "--N", "56", "--method", "pfaffian",
                                "--out", str(out), "--force", "--no-checkpoint"],
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, start_new_session=True)
    deadline, workers = time.monotonic() + 90, []
    while time.monotonic() < deadline and process.poll() is None and len(workers) < 2:
        workers = [c for c in _children(process.pid) if "spawn_main" in open(f"/proc/{c}/cmdline").read()]
        time.sleep(0.05)
    assert len(workers) >= 2, "the run did not start its worker processes"
    time.sleep(2.0)  # the workers are inside their compiled kernels
    t0 = time.monotonic()
    os.killpg(process.pid, signal.SIGINT)  # what a terminal's Ctrl-C does
    _, err = process.communicate(timeout=30)
    elapsed = time.monotonic() - t0
    assert process.returncode == 130, err
    assert elapsed < 3.0, elapsed
    assert "interrupted" in err.decode()
    assert os.listdir(tmp_path) == []
    deadline = time.monotonic() + 2
    while time.monotonic() < deadline and not all(_gone(pid) for pid in workers):
        time.sleep(0.05)
    assert all(_gone(pid) for pid in workers)
