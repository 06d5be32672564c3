"""One prime of each Pfaffian kernel timed in-process against its cost model (how fast is this machine?).

    python benchmarks/cost_check.py 32 64 96 120

For each N: one prime of the survival table (``engine.prime_residues``), of the
lattice directions (``engine.edge_residues``) and of one layer's gap law
(``fluctuations``' evaluations and Lagrange interpolation), CPU seconds after a
warm-up call, beside ``cost.prime_seconds``, ``cost.edge_seconds`` and
``fluctuations``' model, which are priced on the reference machine.  A
uniform ratio says the machine is slower or faster than the reference; a
ratio that moves with N says the model's shape is wrong.  Stop other jobs
first (the timings are CPU seconds of this process, but caches and turbo
are shared).
"""

from __future__ import annotations

import sys
import time


def main(argv: list[str]) -> None:
    from forcenet.exact.triangle.free_fermion import fluctuations
    from forcenet.exact.triangle.free_fermion.cost import edge_seconds, prime_seconds, route_primes
    from forcenet.exact.triangle.free_fermion.engine import edge_residues, prime_residues

    print("| N | table prime (model) | lattice prime (model) | one-layer law prime (model) |")
    print("| --- | --- | --- | --- |")
    for N in map(int, argv):
        p = route_primes(N, 10**30)[0]
        runs = [(prime_residues, (N, p), {}, prime_seconds(N)),
                (edge_residues, (N, p), {}, edge_seconds(N)),
                (fluctuations.edge_level_residues, (N, p), {"windows": [N - 1]}, fluctuations.law_prime_seconds(N, 1))]
        cells = []
        for run, args, kwargs, model in runs:
            run(*args, **kwargs)  # compiled and warm
            t = time.process_time()
            run(*args, **kwargs)
            cpu = time.process_time() - t
            cells.append(f"{cpu:.3f} s ({model:.3f} s, x{cpu / model:.2f})")
        print(f"| {N} | " + " | ".join(cells) + " |", flush=True)


if __name__ == "__main__":
    main(sys.argv[1:])
