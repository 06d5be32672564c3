"""Benchmark of the exact core against baselines measured in the same run.

Each measurement runs in a fresh subprocess (no caches) and reports wall time
and peak resident memory.  Methods:

* ``fast``       exact <W> table, multi-modular order-ideal DP (forcenet.exact.triangle.ideal_dp)
* ``dict``       exact <W> table, plain dictionary DP with Python ints (forcenet.exact.reference.dictionary_dp)
* ``normaliz``   the normalization only (exact volume of the polytope), PyNormaliz
* ``moments2``   exact E[W^2] table (forcenet.exact.triangle.moments.moment_table)
* ``thesis``     <W> table by the nested-matrix integration (forcenet.exact.thesis.nested), modular engine
* ``thesis-literal``  the same recursion with nested-tuple indices and Fractions
* ``lambda``     <W> table by the Lambda/Gamma integer recursions (forcenet.exact.thesis.mean_W_gamma)
* ``maps``       <W> table by counting maps, Eq. (4.91) (forcenet.exact.thesis.mean_W_thesis_maps)

Usage::

    python benchmarks/bench_exact.py --N 8 10 12 14 16 20 24 --timeout 600

Prints a Markdown table: time ratios are baseline / fast at the same N.
The exact results agree by construction (tests), so the error column is 0 for
every exact method; speed is the only axis.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys

SNIPPETS = {
    "fast": "from forcenet.exact.triangle.moments import mean_W; t = mean_W({N})",
    "dict": "from forcenet.exact.reference.dictionary_dp import mean_W_dictionary; t = mean_W_dictionary({N})",
    "moments2": "from forcenet.exact.triangle.moments import moment_table; t = moment_table({N}, 2)",
    "thesis": "from forcenet.exact.thesis.nested import mean_W_nested; t = mean_W_nested({N})",
    "thesis-literal": "from forcenet.exact.thesis.nested import mean_W_nested; t = mean_W_nested({N}, arithmetic='fraction')",
    "lambda": "from forcenet.exact.thesis import mean_W_gamma; t = mean_W_gamma({N})",
    "maps": "from forcenet.exact.thesis import mean_W_thesis_maps; t = mean_W_thesis_maps({N})",
    "normaliz": """
import PyNormaliz
from forcenet.exact.reference.linear_extensions import partial_sum_poset
G = partial_sum_poset({N}); nodes = sorted(G.nodes()); idx = {{v: k for k, v in enumerate(nodes)}}; d = len(nodes)
rows = []
for u, v in G.edges():
    r = [0] * (d + 1); r[idx[v]] = 1; r[idx[u]] = -1; rows.append(r)
for k in range(d):
    r = [0] * (d + 1); r[k] = 1; rows.append(r)
    r = [0] * (d + 1); r[k] = -1; r[d] = 1; rows.append(r)
vol = PyNormaliz.Cone(inhom_inequalities=rows).Volume()
from forcenet.exact.triangle.staircase import count
assert int(vol if not isinstance(vol, (list, tuple)) else vol[0]) == count({N})
""",
}

RUNNER = """
import json, resource, time
t0 = time.perf_counter()
{body}
seconds = time.perf_counter() - t0
print(json.dumps({{"seconds": seconds, "rss": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024}}))
"""


def measure(method: str, N: int, timeout: float):
    code = RUNNER.format(body=SNIPPETS[method].format(N=N))
    try:
        proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=timeout, check=False)
    except subprocess.TimeoutExpired:
        return None, f"> {timeout:.0f} s"
    if proc.returncode:
        lines = proc.stderr.strip().splitlines()
        return None, f"failed (exit code {proc.returncode}" + (f": {lines[-1]}" if lines else "") + ")"
    return json.loads(proc.stdout.strip().splitlines()[-1]), None


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--N", type=int, nargs="+", default=[8, 10, 12, 14, 16, 20, 24])
    parser.add_argument("--methods", nargs="+", default=["fast", "dict", "normaliz", "moments2"])
    parser.add_argument("--timeout", type=float, default=600.0)
    args = parser.parse_args(argv)
    gave_up = set()
    print("| N | method | seconds | peak RSS (MiB) | time ratio vs fast |")
    print("| --- | --- | --- | --- | --- |")
    for N in args.N:
        fast = None
        for method in args.methods:
            if method in gave_up:
                print(f"| {N} | {method} | skipped (timed out or failed at a smaller N) | | |")
                continue
            result, problem = measure(method, N, args.timeout)
            if problem:
                gave_up.add(method)
                print(f"| {N} | {method} | {problem} | | |", flush=True)
                continue
            if method == "fast":
                fast = result["seconds"]
            ratio = f"{result['seconds'] / fast:.1f}x" if fast and method != "fast" else ""
            print(f"| {N} | {method} | {result['seconds']:.3f} | {result['rss'] / 2**20:.0f} | {ratio} |", flush=True)


if __name__ == "__main__":
    main()
