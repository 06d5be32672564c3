"""The <W^2> table against the evaluation bound of notes/fluctuations.md Sec. 6.1, priced two ways (issues 27, 43).

What is proved, and in which model: a route that evaluates *one layer's
two-time amplitude* ``F(s, t, zeta)`` (total degree ``<= d`` in ``(s, t)``,
degree ``m`` in ``zeta``) at points -- chosen in advance or adaptively,
derivatives (jets) counted one value each -- and combines the values
linearly needs at least ``(k+1)(k+2)/2 (floor(m/2)+1)`` values for that
layer, ``k = floor(d/2)``.  It is not a bound on computing ``<W^2>``: the
cover identity (Sec. 3.1) gives layer ``N - 1`` with no two-time evaluation.

The price of the whole table depends on what one evaluation serves:

* *per layer*: every layer pays its own evaluations (the built route's
  grids do; the bound summed over the layers ``m = 1..n``);
* *shared*: one elimination at a node serves every layer, as one of the
  mean route's eliminations serves every window (then the table needs only
  the largest layer's count, ``m = n``).  No two-time kernel with that
  property is known; the bound does not exclude one.

Both at the fastest bordered Pfaffian measured here (the floor's displacement
kernel, ``0.52 ns n^2 + 45 ns n``; notes/benchmarks.md), the mirror symmetry
and the ``+-zeta`` pairing granted, over the built route's primes, on two
cores; beside the simplex Newton-Cotes rule (``(d+1)(d+2)/2`` nodes,
``m + 1`` values of ``zeta``) and the built route's plan (reference machine).

The full task outputs all ``m + 1`` numbers of a layer, not one combination
of them: its bound is ``(k+1)(k+2)/2 (m+1)``, larger by ``(m+1)/(floor(m/2)+1)``
(``--measure`` prints that ratio, shared and per layer, beside the measured
cost of one bordered Pfaffian against the price used above: one prime of the
floor route with every load, ``(d//2+1)(d+3)`` nodes times ``(n+2)//2``
Pfaffians, CPU time, best of ``--rounds``).

Usage::

    python benchmarks/table_bound.py --N 28 40 64
    python benchmarks/table_bound.py --measure --N 16 20 24 28
"""

from __future__ import annotations

import argparse
import time

from forcenet.exact.triangle.de_bruijn.floor import floor_prime_residues, floor_primes
from forcenet.exact.triangle.pfaffian_table import moments_plan

ROW_SECONDS, PIVOT_SECONDS = 0.52e-9, 45e-9  # one bordered Pfaffian of order n: ROW n^2 + PIVOT n (measured)


def per_layer_bound(d: int, m: int) -> float:
    """Eliminations for one layer with ``m`` free points at the proved bound (mirror halved, two values per pair)."""
    k = d // 2
    return (k + 1) * (k + 2) / 2 * (m // 2 + 1) / 2 / 2


def full_task_ratio(N: int) -> tuple[float, float]:
    """(shared, per layer): the full task's bound, ``m + 1`` values of ``zeta``, over the one-combination bound."""
    n = N - 1
    d = n * (n + 1) // 2
    full = [per_layer_bound(d, m) * (m + 1) / (m // 2 + 1) for m in range(1, n + 1)]
    bound = [per_layer_bound(d, m) for m in range(1, n + 1)]
    return max(full) / max(bound), sum(full) / sum(bound)


def measured_pfaffian_seconds(N: int, rounds: int) -> tuple[float, int]:
    """(CPU seconds per bordered Pfaffian, Pfaffians per prime): one prime of the floor route, every load."""
    n = N - 1
    d = n * (n + 1) // 2
    count = (d // 2 + 1) * (d + 3) * ((n + 2) // 2)  # the nodes (mirror halved) times the +-zeta lanes
    p = floor_primes(N)[0]
    best = float("inf")
    for _ in range(rounds):
        start = time.process_time()
        floor_prime_residues(N, p, True)
        best = min(best, time.process_time() - start)
    return best / count, count


def measure(Ns: list[int], rounds: int) -> None:
    """The full task's bound over the priced one, and one Pfaffian's measured time over its price."""
    floor_prime_residues(6, floor_primes(6)[0], True)  # compile outside the clock
    print("| N | Pfaffians per prime | measured ns each | priced ns | measured / priced | full / priced count, shared "
          "| per layer | full task / priced, shared |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- |")
    for N in Ns:
        n = N - 1
        seconds, count = measured_pfaffian_seconds(N, rounds)
        priced = ROW_SECONDS * n * n + PIVOT_SECONDS * n
        shared, per_layer = full_task_ratio(N)
        print(f"| {N} | {count} | {seconds * 1e9:.0f} | {priced * 1e9:.0f} | {seconds / priced:.2f} | {shared:.3f} "
              f"| {per_layer:.3f} | {shared * seconds / priced:.2f} |", flush=True)


def eliminations(N: int) -> dict[str, float]:
    """Eliminations per prime for the whole table: the bound charged per layer or shared; the simplex rule both ways."""
    n = N - 1
    d = n * (n + 1) // 2
    simplex = [(d + 1) * (d + 2) / 2 / 2 * (m + 2) / 2 for m in range(1, n + 1)]
    bound = [per_layer_bound(d, m) for m in range(1, n + 1)]
    return {"bound, per layer": sum(bound), "bound, shared": max(bound),
            "simplex, per layer": sum(simplex), "simplex, shared": max(simplex)}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--N", type=int, nargs="+", default=[28, 40, 64])
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--measure", action="store_true", help="time one Pfaffian and print the full task's ratio")
    parser.add_argument("--rounds", type=int, default=3)
    args = parser.parse_args()
    if args.measure:
        measure(args.N, args.rounds)
        return
    keys = list(eliminations(4))
    print("| N | primes | " + " | ".join(f"{key}, min" for key in keys) + " | built route (plan), min |")
    print("| --- | --- | " + " | ".join("---" for _ in keys) + " | --- |")
    for N in args.N:
        n, primes = N - 1, len(floor_primes(N))
        each = ROW_SECONDS * n * n + PIVOT_SECONDS * n
        counts = eliminations(N)
        minutes = [counts[key] * primes * each / args.workers / 60 for key in keys]
        built = moments_plan(N).seconds / 60
        print(f"| {N} | {primes} | " + " | ".join(f"{x:.3g}" for x in minutes) + f" | {built:.3g} |")


if __name__ == "__main__":
    main()
