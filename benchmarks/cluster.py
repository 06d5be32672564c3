"""The Pfaffian route's per-prime tasks beyond one process: cost model, scheduler overhead, 1 vs 2 workers.

Usage (needs ``pip install '.[distributed]'``)::

    python benchmarks/cluster.py model 20 28 36 44 52 64   # CPU seconds per prime vs the plan's model
    python benchmarks/cluster.py overhead 400              # a Dask scheduler's cost per task (loopback)
    python benchmarks/cluster.py scaling 64                # a local cluster of 1, then 2 worker processes
    python benchmarks/cluster.py crt 64 100 128            # the client's Chinese remaindering of the table
    python benchmarks/cluster.py predict 128 150 200       # predicted wall time on 16 and 64 workers
    python benchmarks/cluster.py acceptance                # the issue's scenario on `dask scheduler`/`dask worker`

Each line printed is one measurement; notes/benchmarks.md quotes them.
"""

from __future__ import annotations

import os
import sys
import time


def _primes(N: int) -> tuple[int, ...]:
    """The Pfaffian table's primes for ``N`` (their product exceeds ``(d + 1) count``)."""
    from forcenet.exact.triangle.free_fermion import cost
    from forcenet.exact.triangle.staircase import count, dimension

    return cost.route_primes(N, (dimension(N) + 1) * count(N))


def _load() -> str:
    return " ".join(f"{x:.1f}" for x in os.getloadavg())


def model(sizes):
    """CPU seconds of one prime (process time, insensitive to other processes' load) against ``cost.prime_seconds``."""
    from forcenet.exact.triangle.free_fermion import cost
    from forcenet.exact.triangle.free_fermion.engine import edge_residues, prime_residues

    for N in sizes:
        primes = _primes(N)[:4]
        prime_residues(N, primes[0])  # kernels loaded
        t0 = time.process_time()
        for p in primes[1:]:
            prime_residues(N, p)
        table = (time.process_time() - t0) / 3
        t0 = time.process_time()
        for p in primes[1:]:
            edge_residues(N, p)
        edge = (time.process_time() - t0) / 3
        print(f"N={N} table: {table:.4f} s/prime (model {cost.prime_seconds(N):.4f}, ratio {table / cost.prime_seconds(N):.2f}); "
              f"lattice: {edge:.4f} s/prime (model {cost.edge_seconds(N):.4f}, ratio {edge / cost.edge_seconds(N):.2f}); "
              f"load {_load()}", flush=True)


def _cpu():
    return time.process_time()


def _echo(array):
    return array


def overhead(tasks: int):
    """A loopback Dask cluster's cost per task (1, then 2 workers) returning a 64 x 64 int64 residue table: wall,
    and the CPU it costs the client's process (client, scheduler and nannies of a LocalCluster) and the workers."""
    import numpy as np
    from distributed import Client, LocalCluster

    from forcenet.core.execution import run_tasks

    payload = np.zeros((64, 64), dtype=np.int64)
    for workers in (1, 2):
        with LocalCluster(n_workers=workers, threads_per_worker=1, host="127.0.0.1", dashboard_address=None) as cluster, \
                Client(cluster) as client:
            run_tasks(_echo, [(payload,)] * 20, executor=client)
            before, c0 = client.run(_cpu), time.process_time()
            t0 = time.perf_counter()
            run_tasks(_echo, [(payload + k,) for k in range(tasks)], executor=client)
            wall = time.perf_counter() - t0
            client_cpu = time.process_time() - c0
            worker_cpu = sum(t - before[w] for w, t in client.run(_cpu).items())
        print(f"{tasks} tasks on {workers} worker(s): {wall:.2f} s wall, {wall / tasks * 1e3:.1f} ms per task; CPU per task: "
              f"client process {client_cpu / tasks * 1e3:.1f} ms, workers {worker_cpu / tasks * 1e3:.1f} ms; "
              f"load {_load()}", flush=True)


def _warm():
    from forcenet.exact.triangle.free_fermion.engine import count_residue

    return count_residue(12, 33554393)


def _prime_cpu(N: int, primes):
    """CPU seconds per prime of ``prime_residues`` in this process (kernels loaded first)."""
    from forcenet.exact.triangle.free_fermion.engine import prime_residues

    _warm()
    t0 = time.process_time()
    for p in primes:
        prime_residues(N, p)
    return (time.process_time() - t0) / len(primes)


def scaling(N: int):
    """Wall time of the table at ``N`` on a local cluster of 1 and of 2 worker processes (kernels loaded first),
    with what the load cannot blur: each worker's CPU seconds and the sum of its tasks' compute time (Dask's task
    stream), whose largest share is the run's critical path."""
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor

    from distributed import Client, LocalCluster, get_task_stream

    from forcenet.exact.triangle.free_fermion import cost, route

    primes = _primes(N)[:8]
    with ProcessPoolExecutor(1, mp_context=multiprocessing.get_context("spawn")) as pool:
        local = pool.submit(_prime_cpu, N, primes).result()
    print(f"N={N}: one local process, {local:.3f} CPU s per prime (8 primes); load {_load()}", flush=True)
    walls, paths, cpus = {}, {}, {}
    for workers in (1, 2):
        with LocalCluster(n_workers=workers, threads_per_worker=1, host="127.0.0.1", dashboard_address=None) as cluster, \
                Client(cluster) as client:
            client.run(_warm)
            before = client.run(_cpu)
            t0 = time.perf_counter()
            with get_task_stream(client) as stream:
                route.mean_W(N, executor=client)
            walls[workers] = time.perf_counter() - t0
            cpu = {w: t - before[w] for w, t in client.run(_cpu).items()}
            busy = dict.fromkeys(cpu, 0.0)
            for task in stream.data:
                busy[task["worker"]] += sum(s["stop"] - s["start"] for s in task["startstops"] if s["action"] == "compute")
            paths[workers], cpus[workers] = max(busy.values()), max(cpu.values())
            cost = client.submit(_prime_cpu, N, primes, pure=False).result()
            print(f"N={N} on {workers} worker process(es): {walls[workers]:.1f} s wall, {len(stream.data)} tasks "
                  f"(then 8 primes in a worker: {cost:.3f} CPU s per prime); "
                  f"per worker: compute {', '.join(f'{b:.1f}' for b in busy.values())} s, "
                  f"CPU {', '.join(f'{c:.1f}' for c in cpu.values())} s; load {_load()}", flush=True)
    print(f"ratio 1 worker / 2 workers: wall {walls[1] / walls[2]:.2f}, critical path (the busiest worker's compute) "
          f"{paths[1] / paths[2]:.2f}, busiest worker's CPU {cpus[1] / cpus[2]:.2f}", flush=True)


def crt(sizes):
    """Client seconds of the Chinese remaindering of the whole table (n^2 entries over all primes)."""
    import random

    from forcenet.exact.modular import crt_many

    for N in sizes:
        n = N - 1
        primes = _primes(N)
        rng = random.Random(N)
        rows = [[rng.randrange(p) for p in primes] for _ in range(50)]
        t0 = time.process_time()
        crt_many(rows, primes)  # the route's Chinese remaindering (basis once, then each row)
        per_entry = (time.process_time() - t0) / 50
        print(f"N={N}: {len(primes)} primes, CRT {per_entry * 1e3:.2f} ms per entry, {n * n * per_entry:.1f} s "
              f"for the n^2 = {n * n} entries; load {_load()}", flush=True)


def _cli(*args, **kwargs):
    import subprocess

    return subprocess.run([sys.executable, "-m", "forcenet", "table", "--method", "pfaffian", "--format", "json",
                           "--force", *args], capture_output=True, text=True, **kwargs, check=False)


def _records(directory: str, N: int) -> int:
    path = os.path.join(directory, f"pfaffian-table-N{N}-m1-v1")
    return len([f for f in os.listdir(path) if f.endswith(".rec")]) if os.path.isdir(path) else 0


def acceptance(port: int = 8799):
    """The issue's scenario: `dask scheduler` and two `dask worker` on loopback; N = 36 bytes, N = 44 with a
    worker killed at 30 %, N = 48 with --checkpoint killed (SIGKILL) at 40 % and resumed, a truncated record."""
    import signal
    import subprocess
    import tempfile

    from forcenet.exact.triangle.free_fermion import route

    address = f"tcp://127.0.0.1:{port}"
    procs = [subprocess.Popen(["dask", "scheduler", "--host", "127.0.0.1", "--port", str(port),
                               "--dashboard-address", ":0"], stderr=subprocess.DEVNULL)]
    time.sleep(3)
    procs += [subprocess.Popen(["dask", "worker", address, "--nthreads", "1"], stderr=subprocess.DEVNULL)
              for _ in range(2)]
    try:
        time.sleep(5)
        t0 = time.perf_counter()
        local = _cli("--N", "36", "--no-checkpoint").stdout
        t_local = time.perf_counter() - t0
        t0 = time.perf_counter()
        remote = _cli("--N", "36", "--scheduler", address, "--no-checkpoint")
        print(f"N=36: cluster bytes == local bytes: {remote.stdout == local} (local {t_local:.1f} s, "
              f"cluster {time.perf_counter() - t0:.1f} s); load {_load()}", flush=True)

        reference = _cli("--N", "44", "--no-checkpoint").stdout
        directory = tempfile.mkdtemp()
        run = subprocess.Popen([sys.executable, "-m", "forcenet", "table", "--method", "pfaffian", "--format", "json",
                                "--force", "--N", "44", "--scheduler", address, "--checkpoint", directory],
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        total = route.mean_plan(44).ticks
        while run.poll() is None and _records(directory, 44) < 0.3 * total:
            time.sleep(0.02)
        import psutil  # installed with distributed

        victim = [child.pid for child in psutil.Process(procs[1].pid).children()]
        for pid in victim:
            os.kill(pid, signal.SIGKILL)
        at = _records(directory, 44)
        out, _ = run.communicate()
        print(f"N=44: worker process {victim} killed at {at}/{total} primes; "
              f"bytes unchanged: {out == reference}; load {_load()}", flush=True)

        reference = _cli("--N", "48", "--no-checkpoint", "--scheduler", address)
        t0 = time.perf_counter()
        full = _cli("--N", "48", "--no-checkpoint", "--scheduler", address)
        t_full = time.perf_counter() - t0
        directory = tempfile.mkdtemp()
        total = route.mean_plan(48).ticks
        run = subprocess.Popen([sys.executable, "-m", "forcenet", "table", "--method", "pfaffian", "--format", "json",
                                "--force", "--N", "48", "--scheduler", address, "--checkpoint", directory],
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE)
        while run.poll() is None and _records(directory, 48) < 0.4 * total:
            time.sleep(0.02)
        run.send_signal(signal.SIGKILL)
        run.communicate()
        kept = _records(directory, 48)
        t0 = time.perf_counter()
        resumed = _cli("--N", "48", "--scheduler", address, "--checkpoint", directory)
        t_resumed = time.perf_counter() - t0
        print(f"N=48: killed (SIGKILL) at {kept}/{total} primes; full run {t_full:.1f} s, resumed {t_resumed:.1f} s "
              f"({t_resumed / t_full:.0%} of a full run); same bytes: {resumed.stdout == full.stdout == reference.stdout}; "
              f"{resumed.stderr.strip().splitlines()[-1]}; load {_load()}", flush=True)
        path = os.path.join(directory, "pfaffian-table-N48-m1-v1")
        victim = os.path.join(path, sorted(os.listdir(path))[0])
        with open(victim, "r+b") as handle:
            handle.truncate(100)
        again = _cli("--N", "48", "--scheduler", address, "--checkpoint", directory)
        print(f"N=48 after truncating {os.path.basename(victim)}: same bytes: {again.stdout == full.stdout}; "
              f"stderr: {' | '.join(again.stderr.strip().splitlines())}", flush=True)
    finally:
        for proc in reversed(procs):
            proc.terminate()
            proc.wait(10)


# measured in this file's runs (notes/benchmarks.md, "A Dask task costs what a local one does"): a table prime's
# CPU in a readied Dask worker over a local process's (0.99, interleaved, N = 64) times 1.05 for the worker's event
# loop (its profiler and monitors, ~5 % of a core), the client process's CPU per task (scheduler, client, nannies of
# a LocalCluster: serial) and a worker's own per task (result, bookkeeping), both from `overhead`
_WORKER_RATIO = 0.99 * 1.05
_SERIAL_PER_TASK = 0.0075
_WORKER_PER_TASK = 0.0102


def predict(sizes):
    """Wall time on 16 and 64 workers: count(N)'s primes, then the table's (or the lattice column's), each
    ``ceil(P / K)`` rounds of (the idle model's per-prime seconds x the worker's measured ratio + the worker's
    per-task cost), plus the scheduler's serial cost per task (no overlap assumed), plus the client's CRT."""
    from math import factorial

    from forcenet.core.execution import wall_seconds
    from forcenet.exact.triangle.free_fermion import cost, route
    from forcenet.exact.triangle.free_fermion.engine import count_residue

    for N in sizes:
        nprimes = route.mean_plan(N).ticks
        edge = route.lattice_direction_plan(N).ticks
        counts = cost.route_primes(N, factorial(N * (N - 1) // 2))
        count_residue(N, counts[0])
        t0 = time.process_time()
        for p in counts[1:6]:
            count_residue(N, p)
        per_count = (time.process_time() - t0) / 5
        per_prime = cost.prime_seconds(N) * _WORKER_RATIO
        per_edge = cost.edge_seconds(N) * _WORKER_RATIO
        crt = cost.CRT_SECONDS * nprimes**2 * (N - 1) ** 2
        for K in (16, 64):
            count = wall_seconds(per_count, len(counts), K, _WORKER_PER_TASK) + len(counts) * _SERIAL_PER_TASK
            table = wall_seconds(per_prime, nprimes, K, _WORKER_PER_TASK) + nprimes * _SERIAL_PER_TASK
            column = wall_seconds(per_edge, edge, K, _WORKER_PER_TASK) + edge * _SERIAL_PER_TASK
            print(f"N={N}, K={K}: count {len(counts)} primes of {per_count * 1e3:.1f} ms: {count / 60:.1f} min; table "
                  f"{nprimes} primes of {per_prime:.1f} s: {table / 3600:.2f} h + CRT {crt / 3600:.2f} h = "
                  f"{(count + table + crt) / 3600:.2f} h; lattice column {edge} primes of {per_edge:.1f} s: "
                  f"{(count + column) / 3600:.2f} h", flush=True)


if __name__ == "__main__":
    what, *rest = sys.argv[1:]
    if what == "model":
        model([int(x) for x in rest])
    elif what == "overhead":
        overhead(int(rest[0]) if rest else 400)
    elif what == "scaling":
        scaling(int(rest[0]) if rest else 64)
    elif what == "acceptance":
        acceptance()
    elif what == "crt":
        crt([int(x) for x in rest])
    elif what == "predict":
        predict([int(x) for x in rest])
    else:
        raise SystemExit(f"unknown measurement {what!r}: model, overhead, scaling or predict")
