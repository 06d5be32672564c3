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
from forcenet.core.execution import executor_workers, run_tasks
from forcenet.exact.triangle.free_fermion import route
from forcenet.exact.triangle.free_fermion.engine import count_residue, prime_residues

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
                           *args], capture_output=True, text=True, **kwargs, check=False)


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
    plan = route.mean_plan(64, executor=client)
    assert f"on 2 workers of Dask scheduler {client.scheduler.address}" in plan.what
    local = route.mean_plan(64, workers=1)
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
    assert len(done) == route.mean_plan(N).ticks


def test_a_failing_task_fails_the_run_with_its_message(client):
    with pytest.raises(ValueError, match="p=33554392 is out of range"):
        run_tasks(prime_residues, [(12, 33554392)] * 2, executor=client.get_executor())


def _worker_state(megabytes: int = 1, rounds: int = 20):
    """The page faults of allocating, touching and freeing a ``megabytes`` array ``rounds`` times in this thread,
    the most threads of any BLAS/OpenMP pool here, and the environment's malloc setting."""
    import resource

    import numpy as np
    from threadpoolctl import threadpool_info

    before = resource.getrusage(resource.RUSAGE_THREAD).ru_minflt
    for _ in range(rounds):
        np.ones(megabytes * 2**17).sum()  # a kernel's work array: over glibc's fixed 128 KiB mmap threshold
    faults = resource.getrusage(resource.RUSAGE_THREAD).ru_minflt - before
    threads = max([pool["num_threads"] for pool in threadpool_info()] or [1])
    return faults, threads, os.environ.get("MALLOC_TRIM_THRESHOLD_")


@pytest.mark.skipif(not hasattr(__import__("resource"), "RUSAGE_THREAD"), reason="per-thread page faults (Linux)")
def test_a_worker_task_runs_as_in_a_local_process(client, monkeypatch):
    # Dask's nanny starts workers with MALLOC_TRIM_THRESHOLD_, which froze glibc's mmap threshold: a work array of
    # 1 MiB was mapped and page-faulted afresh by every call (256 faults each); run_tasks readies the worker first
    pages = 2**20 // os.sysconf("SC_PAGE_SIZE")
    for faults, threads, trim in run_tasks(_worker_state, [()] * 4, executor=client):
        assert trim is not None  # the nanny's setting is there: the fix, not the environment, makes the difference
        assert faults < 20 * pages / 4, faults
        assert threads == 1
    # the same in a bare process with the nanny's environment: the faults the fix removes
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor

    monkeypatch.setenv("MALLOC_TRIM_THRESHOLD_", "65536")
    monkeypatch.delenv("MALLOC_MMAP_THRESHOLD_", raising=False)
    with ProcessPoolExecutor(1, mp_context=multiprocessing.get_context("spawn")) as pool:
        bare = pool.submit(_worker_state).result()[0]
        readied = run_tasks(_worker_state, [()] * 2, executor=pool)
    assert bare >= 20 * pages * 3 / 4, bare
    assert all(faults < 20 * pages / 4 for faults, _, _ in readied), readied


def test_scheduler_without_the_extra_is_one_line():
    block = ("import sys; sys.modules['distributed'] = None; from forcenet.cli import main; "
             "sys.exit(main(['table', '--N', '20', '--method', 'pfaffian', '--format', 'json', "
             "'--scheduler', 'tcp://127.0.0.1:1']))")
    result = subprocess.run([sys.executable, "-c", block], capture_output=True, text=True, check=False)
    assert result.returncode == 2 and result.stdout == ""
    assert result.stderr.count("\n") == 1 and "pip install 'forcenet[distributed]'" in result.stderr


def test_unreachable_scheduler_is_one_line(monkeypatch, capsys):
    from forcenet.cli import cluster

    monkeypatch.setattr(cluster, "CONNECT_SECONDS", 1)
    assert main(["table", "--N", "20", "--method", "pfaffian", "--format", "json", "--scheduler", "tcp://127.0.0.1:9"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--scheduler=tcp://127.0.0.1:9: nothing listens at 127.0.0.1:9" in err


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


def test_the_floor_route_on_the_cluster_gives_the_local_law(client):
    """The floor's de Bruijn Pfaffians hand their primes to the cluster like the table does."""
    from forcenet.exact.triangle.de_bruijn.floor import floor_gap_laws, floor_pooled_gap_law

    assert floor_pooled_gap_law(16, executor=client) == floor_pooled_gap_law(16, workers=1)
    assert floor_gap_laws(9, executor=client) == floor_gap_laws(9, workers=1)



# ------------------------------------------------------------------ a TLS cluster on loopback (issue 45 item 3)

from tls_certificates import OPENSSL, make_certificates  # noqa: E402 - the TLS part's own helper


@pytest.fixture(scope="module")
def tls(tmp_path_factory):
    """A TLS scheduler on 127.0.0.1 with one worker, certificates made here: (address, certificates)."""
    if OPENSSL is None:
        pytest.skip("the openssl command makes the test's certificates")
    from distributed.security import Security

    certificates = make_certificates(tmp_path_factory.mktemp("tls"))
    (ca, _), (node, node_key), (me, my_key) = certificates["ca"], certificates["node"], certificates["client"]
    security = Security(tls_ca_file=ca, tls_scheduler_cert=node, tls_scheduler_key=node_key, tls_worker_cert=node,
                        tls_worker_key=node_key, tls_client_cert=me, tls_client_key=my_key, require_encryption=True)
    cluster = distributed.LocalCluster(n_workers=1, threads_per_worker=2, processes=False, protocol="tls",
                                       host="127.0.0.1", dashboard_address=None, security=security)
    assert cluster.scheduler_address.startswith("tls://127.0.0.1:")
    yield cluster.scheduler_address, certificates
    cluster.close()


def _tls_options(certificates, cert="client", ca="ca"):
    return ["--tls-ca-file", certificates[ca][0], "--tls-cert", certificates[cert][0],
            "--tls-key", certificates[cert][1]]


def test_a_tls_cluster_gives_the_local_bytes(tls, capsys):
    address, certificates = tls
    expected = _local_json(12, capsys)
    args = ["table", "--N", "12", "--method", "pfaffian", "--format", "json", "--scheduler", address]
    assert main([*args, *_tls_options(certificates)]) == 0
    out, err = capsys.readouterr()
    assert out == expected, err
    # the same client through Dask's own configuration (what DASK_DISTRIBUTED__COMM__TLS__* sets)
    import dask

    (ca, _), (me, my_key) = certificates["ca"], certificates["client"]
    with dask.config.set({"distributed.comm.tls.ca-file": ca, "distributed.comm.tls.client.cert": me,
                          "distributed.comm.tls.client.key": my_key}):
        assert main(args) == 0
    assert capsys.readouterr().out == expected


TLS_REFUSALS = {  # a client refused by the TLS cluster: one line naming why, exit 2, within seconds
    "no certificates": ([], "needs the cluster's CA and a client certificate"),
    "a stranger's certificate": (["stranger"], "TLS refused"),
    "a stranger's CA": (["client", "stranger_ca"], "TLS refused"),
    "tcp:// to a TLS scheduler": (["tcp"], "said nothing within"),
    "certificate without the CA": (["cert-only"], "--tls-ca-file missing"),
}


@pytest.mark.parametrize("case", list(TLS_REFUSALS))
def test_a_tls_cluster_refuses_a_client_in_one_line(tls, case, capsys, monkeypatch):
    from forcenet.cli import cluster

    monkeypatch.setattr(cluster, "CONNECT_SECONDS", 2.0)
    address, certificates = tls
    how, expected = TLS_REFUSALS[case]
    options = {"stranger": _tls_options(certificates, "stranger"), "client": _tls_options(certificates, "client", "stranger_ca"),
               "tcp": _tls_options(certificates), "cert-only": _tls_options(certificates)[2:]}.get(how[0] if how else "", [])
    if how == ["tcp"]:
        address, options = address.replace("tls://", "tcp://"), []
    t0 = time.monotonic()
    code = main(["table", "--N", "12", "--method", "pfaffian", "--format", "json", "--scheduler", address, *options])
    elapsed = time.monotonic() - t0
    out, err = capsys.readouterr()
    assert code == 2 and out == "", err
    assert err.count("\n") == 1 and expected in err, err
    assert elapsed < 10, elapsed


def test_the_readme_starts_nothing_on_every_interface():
    """Issue 45 item 3: every `dask scheduler` and `dask worker` of the README binds loopback or a private address
    (its dashboard too), the TLS cluster is shown, and what a scheduler lets its clients do is said."""
    import ipaddress
    import re
    from pathlib import Path

    # the cluster guide is the distributed tutorial of the site (the README links to it)
    readme = (Path(__file__).resolve().parents[1] / "docs" / "tutorials" / "distributed.md").read_text()
    starts = [line for line in readme.splitlines() if re.match(r"\s*dask (scheduler|worker)\b", line)]
    assert len(starts) >= 4
    for line in starts:
        host = re.search(r"--host (\S+)", line)
        assert host and ipaddress.ip_address(host.group(1)).is_private, line
        assert "--no-dashboard" in line or re.search(r"--dashboard-address 127\.0\.0\.1:\d+", line), line
    assert "--protocol tls" in readme and "--tls-ca-file ca.crt --tls-cert client.crt" in readme
    assert "runs whatever its clients send" in readme
