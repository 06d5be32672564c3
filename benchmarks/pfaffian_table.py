"""Benchmark of the Pfaffian route (``--method pfaffian``) against the order-ideal DP, in the same run.

Each measurement runs in a fresh subprocess (wall time, CPU time of the
process and its workers, peak resident memory of the process and of its
largest worker).  Modes:

* ``table``: the full exact <W> table by Pfaffians, and by the order-ideal DP
  (``fast``) where ``N <= --dp-max``; ratios are DP / Pfaffian;
* ``prime``: one prime of the Pfaffian route (the work is the same for every
  prime), the number of primes needed, and the extrapolated full table; the
  same for the dense elimination of every ``(q, y)`` (the private ``_dense`` kernels in place of the compiled ones,
  the route before the displacement elimination, at its own largest prime),
  with the ratio of the extrapolated tables;
* ``compile``: the first call of the numba kernels with an empty cache
  (compilation) and with the cache (loading).

Usage::

    python benchmarks/pfaffian_table.py table --N 24 28 32 40 48 --dp-max 28 --save out
    python benchmarks/pfaffian_table.py prime --N 32 48 64 80 100
    python benchmarks/pfaffian_table.py compile

Prints Markdown tables and the fitted cost exponents; the load average of the
machine is printed with every row (the 2-core machine is shared).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import subprocess
import sys
import tempfile

RUNNER = """
import json, resource, time
t0 = time.perf_counter()
{body}
seconds = time.perf_counter() - t0
self_ru = resource.getrusage(resource.RUSAGE_SELF)
kids = resource.getrusage(resource.RUSAGE_CHILDREN)
print(json.dumps({{"seconds": seconds, "cpu": self_ru.ru_utime + self_ru.ru_stime + kids.ru_utime + kids.ru_stime,
                  "rss": self_ru.ru_maxrss * 1024, "child_rss": kids.ru_maxrss * 1024, **extra}}))
"""

SNIPPETS = {
    "pfaffian": "from forcenet.exact.triangle.free_fermion.route import mean_W, mean_plan\n"
                "plan = mean_plan({N}, workers={workers})\n"
                "t = mean_W({N}, workers={workers}); extra = {{'plan': plan.seconds, 'primes': plan.ticks}}\n"
                "if {save!r}:\n"
                "    import os; from forcenet.exact.triangle.tables import exact_table, to_json, write_atomic\n"
                "    write_atomic(os.path.join({save!r}, 'mean_W_N{N}.json'), to_json(exact_table({N}, mean_table=t)) + '\\n')",
    "fast": "from forcenet.exact.triangle.moments import mean_W; t = mean_W({N}); extra = {{}}",
    "prime": "from forcenet.exact.triangle.free_fermion import cost, engine, route\n"
             "p = cost.route_primes({N}, 2)[0]; engine.prime_residues(3, p) if {N} > 3 else None\n"
             "c0 = time.process_time(); t0 = time.perf_counter(); engine.prime_residues({N}, p)\n"
             "extra = {{'prime_cpu': time.process_time() - c0, 'primes': route.mean_plan({N}).ticks}}",
    # the baseline: the same prime's work by the dense elimination, at the largest prime its bound allows
    "prime_dense": "import math\nfrom forcenet.exact.modular import is_prime\nfrom forcenet.exact.triangle.staircase import count\n"
                   "from forcenet.exact.triangle.free_fermion import _dense, cost, engine\n"
                   "p = cost.dense_prime_limit({N} - 1) - 1\nwhile not is_prime(p): p -= 1\n"
                   "oracle = engine._oracle_kernels(_dense); oracle.__enter__()\n"
                   "engine.prime_residues(3, p) if {N} > 3 else None\n"
                   "c0 = time.process_time(); engine.prime_residues({N}, p)\n"
                   "bits = ({N} * ({N} - 1) // 2 + 1) * count({N})\n"
                   "extra = {{'prime_cpu': time.process_time() - c0, 'primes': math.ceil(bits.bit_length() / math.log2(p))}}",
    "compile": "from forcenet.exact.triangle.free_fermion import engine\nimport numba\nt1 = time.perf_counter()\n"
               "engine.prime_residues(3, 8388593); engine.count_residue(5, 8388593)\n"
               "extra = {{'first_call': time.perf_counter() - t1}}",
}


def measure(kind: str, N: int = 0, workers: int = 2, timeout: float = 3600, env=None, save: str = ""):
    code = RUNNER.format(body=SNIPPETS[kind].format(N=N, workers=workers or None, save=save))
    load = os.getloadavg()[0]
    try:
        proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=timeout,
                              env={**os.environ, "OMP_NUM_THREADS": "1", **(env or {})}, check=False)
    except subprocess.TimeoutExpired:
        return None, f"> {timeout:.0f} s"
    if proc.returncode:
        lines = proc.stderr.strip().splitlines()
        return None, f"failed (exit code {proc.returncode}" + (f": {lines[-1]}" if lines else "") + ")"
    out = json.loads(proc.stdout.strip().splitlines()[-1])
    out["load"] = (load + os.getloadavg()[0]) / 2
    return out, None


def _fit(xs, ys):
    """Least-squares slope of log y against log x."""
    lx, ly = [math.log(x) for x in xs], [math.log(y) for y in ys]
    mx, my = sum(lx) / len(lx), sum(ly) / len(ly)
    return sum((a - mx) * (b - my) for a, b in zip(lx, ly)) / sum((a - mx) ** 2 for a in lx)


def table(args):
    print("| N | primes | plan s | Pfaffian wall s | CPU s | RSS MiB (parent / worker) | DP wall s | DP RSS MiB | DP / Pfaffian | load |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    points = []
    for N in args.N:
        res, err = measure("pfaffian", N, args.workers, args.timeout, save=args.save)
        if err:
            print(f"| {N} | | | {err} | | | | | | |", flush=True)
            continue
        points.append((N, res["seconds"], res["cpu"]))
        dp, dp_text, ratio = None, "-", "-"
        if N <= args.dp_max:
            dp, dp_err = measure("fast", N, timeout=args.timeout)
            dp_text = dp_err or f"{dp['seconds']:.1f}"
            ratio = "-" if dp is None else f"{dp['seconds'] / res['seconds']:.2g}x"
        print(f"| {N} | {res['primes']} | {res['plan']:.0f} | {res['seconds']:.1f} | {res['cpu']:.0f} | "
              f"{res['rss'] / 2**20:.0f} / {res['child_rss'] / 2**20:.0f} | {dp_text} | "
              f"{'-' if dp is None else round(dp['rss'] / 2**20)} | {ratio} | {res['load']:.1f} |",
              flush=True)
    if len(points) >= 2:
        print(f"\nfitted exponent of the CPU time in N over N = {points[0][0]}..{points[-1][0]}: "
              f"{_fit([p[0] for p in points], [p[2] for p in points]):.2f}")


def prime(args):
    print("| N | one prime CPU s | primes | extrapolated CPU s | on 2 cores | dense: one prime CPU s | dense: primes | "
          "dense: extrapolated CPU s | dense / displacement (table) | load |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    points = []
    for N in args.N:
        res, err = measure("prime", N, timeout=args.timeout)
        if err:
            print(f"| {N} | {err} | | | | | | | | |", flush=True)
            continue
        total = res["prime_cpu"] * res["primes"]
        points.append((N, res["prime_cpu"], total))
        base, base_err = measure("prime_dense", N, timeout=args.timeout) if N <= args.dense_max else (None, "-")
        if base is None:
            dense_cols = f"{base_err} | | | "
        else:
            dense_total = base["prime_cpu"] * base["primes"]
            dense_cols = f"{base['prime_cpu']:.2f} | {base['primes']} | {dense_total:.0f} | {dense_total / total:.2f}x"
        print(f"| {N} | {res['prime_cpu']:.2f} | {res['primes']} | {total:.0f} | {total / 2 / 60:.1f} min | {dense_cols} | "
              f"{res['load']:.1f} |", flush=True)
    if len(points) >= 2:
        xs = [p[0] - 1 for p in points]
        print(f"\nfitted exponents in n = N - 1: one prime {_fit(xs, [p[1] for p in points]):.2f}, "
              f"full table {_fit(xs, [p[2] for p in points]):.2f}")


def compile_time(args):
    with tempfile.TemporaryDirectory() as cache:
        cold, err = measure("compile", env={"NUMBA_CACHE_DIR": cache})
        warm, err2 = measure("compile", env={"NUMBA_CACHE_DIR": cache})
    if err or err2:
        print(err or err2)
        return
    print(f"first call with an empty cache (compilation): {cold['first_call']:.1f} s; "
          f"with the cache: {warm['first_call']:.2f} s (import of forcenet + numba: {warm['seconds'] - warm['first_call']:.1f} s)")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("mode", choices=["table", "prime", "compile"])
    parser.add_argument("--N", type=int, nargs="+", default=[24, 28, 32])
    parser.add_argument("--dp-max", type=int, default=26, help="run the order-ideal DP up to this N")
    parser.add_argument("--dense-max", type=int, default=100, help="prime mode: run the dense baseline up to this N")
    parser.add_argument("--workers", type=int, default=0, help="worker processes (0: the route's own choice)")
    parser.add_argument("--timeout", type=float, default=3600.0)
    parser.add_argument("--save", default="", help="also write each Pfaffian table as DIR/mean_W_N{N}.json (exact)")
    args = parser.parse_args(argv)
    {"table": table, "prime": prime, "compile": compile_time}[args.mode](args)


if __name__ == "__main__":
    main()
