"""The floor's Pfaffians by displacement against the lazy elimination they replaced (issue 27; notes/benchmarks.md).

For each N, one prime of the floor route (``floor_prime_residues``) by both
kernels, in alternation in the same process (``--rounds`` each, the best CPU
time kept): the ratio, the residues' equality, and the cost model's
prediction (``floor_prime_seconds``, reference machine).  Both kernels are
compiled before the clock starts.

Usage::

    python benchmarks/floor_displacement.py --N 20 28 36 --grains
    python benchmarks/floor_displacement.py --N 28 36 44 52
"""

from __future__ import annotations

import argparse
import time

from forcenet.exact.triangle.de_bruijn.floor import floor_prime_residues, floor_prime_seconds, floor_primes


def cpu(N: int, p: int, grains: bool, kernel: str):
    """(CPU seconds, residues) of one prime."""
    start = time.process_time()
    out = floor_prime_residues(N, p, grains, kernel)
    return time.process_time() - start, out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--N", type=int, nargs="+", required=True)
    parser.add_argument("--grains", action="store_true", help="every floor load (n + 1 fugacities), not the pool")
    parser.add_argument("--rounds", type=int, default=2)
    args = parser.parse_args()
    for kernel in ("displacement", "elimination"):  # compile outside the clock
        floor_prime_residues(6, floor_primes(6)[0], args.grains, kernel)
    what = "every load" if args.grains else "pooled"
    print(f"floor route, {what}: CPU seconds per prime, best of {args.rounds}, kernels alternating")
    print("N | displacement | elimination | ratio | model (reference machine) | residues equal")
    for N in args.N:
        p = floor_primes(N)[0]
        best = {"displacement": float("inf"), "elimination": float("inf")}
        outs = {}
        for _ in range(args.rounds):
            for kernel in best:
                seconds, outs[kernel] = cpu(N, p, args.grains, kernel)
                best[kernel] = min(best[kernel], seconds)
        same = bool((outs["displacement"] == outs["elimination"]).all())
        print(f"{N} | {best['displacement']:.2f} | {best['elimination']:.2f} | "
              f"{best['elimination'] / best['displacement']:.2f} | {floor_prime_seconds(N, args.grains):.2f} | {same}",
              flush=True)


if __name__ == "__main__":
    main()
