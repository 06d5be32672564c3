"""First-call cost of each kernel group: compiling (empty numba cache) against loading (cached), in fresh processes.

Issue 24 item 12: the plans add the compile time of the kernels a run will
use when numba's cache does not hold them (``forcenet.core.plan.with_compilation``).
Every figure is the CPU time (what an idle machine takes; the reference
machine is shared) of the group's first call in a fresh process, with
``NUMBA_CACHE_DIR`` a new empty directory (compiling) and then the same
directory (loading the cache).

    python benchmarks/compile_times.py
"""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile

GROUPS = {
    "triangle Metropolis": "from forcenet.numeric.triangle.metropolis import TriangleMetropolis as T; T(4, seed=0).sweep(1)",
    "triangle slice": "from forcenet.numeric.triangle.metropolis import TriangleMetropolis as T; T(4, seed=0, move='slice').sweep(1)",
    "exact sampler": "from forcenet.numeric.triangle.exact_sampler import ExactSampler as E; E(4, seed=0).mean_W(2)",
    "packing Metropolis": ("from forcenet.numeric.packing import PackingMetropolis as P, Scene; "
                           "P(Scene(N=3, P=4, F=1.0, pv=1.0, ph=1.0), seed=0).sweep(1)"),
    "packing slice": ("from forcenet.numeric.packing import PackingMetropolis as P, Scene; "
                      "P(Scene(N=3, P=4, F=1.0, pv=1.0, ph=1.0), seed=0, move='slice').sweep(1)"),
    "Pfaffian table": "from forcenet.exact.triangle.free_fermion.route import mean_W; mean_W(6, workers=1)",
    "Pfaffian lattice direction": ("from forcenet.exact.triangle.free_fermion.route import lattice_direction; "
                                   "lattice_direction(6, workers=1)"),
}

SNIPPET = "import time\n{imports}\nt0 = time.process_time()\n{call}\nprint(f'{{time.process_time() - t0:.2f}}')\n"


def first_call(code: str, cache: str) -> float:
    imports, call = code.split("; ", 1)
    env = dict(os.environ, NUMBA_CACHE_DIR=cache)
    out = subprocess.run([sys.executable, "-c", SNIPPET.format(imports=imports, call=call)], env=env,
                         capture_output=True, text=True, check=True)
    return float(out.stdout.split()[-1])


def main():
    print("| kernel group | first call, empty cache (s) | first call, cached (s) | compiling (s) |")
    print("| --- | --- | --- | --- |")
    for name, code in GROUPS.items():
        with tempfile.TemporaryDirectory() as cache:
            cold = first_call(code, cache)
            warm = first_call(code, cache)
        print(f"| {name} | {cold:.1f} | {warm:.1f} | {cold - warm:.1f} |", flush=True)


if __name__ == "__main__":
    main()
