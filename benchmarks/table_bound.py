"""The <W^2> table's floor: the fewest Pfaffian evaluations any evaluate-and-combine route needs (issue 27).

notes/fluctuations.md Sec. 6.1 proves that a rule for the ``m + 1`` two-time
functionals of a layer with ``m`` free points needs at least
``(k+1)(k+2)/2 (floor(m/2)+1)`` evaluations, ``k = floor(d/2)``; the mirror
symmetry halves that and the ``+-zeta`` pairing gives two values per
elimination.  This script prices the bound, and the simplex Newton-Cotes rule
(``(d+1)(d+2)/2`` nodes, ``m + 1`` values of ``zeta``), at the fastest
bordered Pfaffian measured here (the floor's displacement kernel,
``0.52 ns n^2 + 45 ns n`` on this machine, notes/benchmarks.md), over the
built route's primes, beside the built route's plan (``moments_plan``,
reference machine).  Two cores.

Usage::

    python benchmarks/table_bound.py --N 28 40 64
"""

from __future__ import annotations

import argparse

from forcenet.exact.triangle.pfaffian.floor import floor_primes
from forcenet.exact.triangle.pfaffian.moments import moments_plan

ROW_SECONDS, PIVOT_SECONDS = 0.52e-9, 45e-9  # one bordered Pfaffian of order n: ROW n^2 + PIVOT n (measured)


def eliminations(N: int) -> tuple[float, float]:
    """(at the proved bound, by the simplex Newton-Cotes rule): eliminations per prime, every layer 2..N."""
    n = N - 1
    d = n * (n + 1) // 2
    k = d // 2
    bound = sum((k + 1) * (k + 2) / 2 * (m // 2 + 1) for m in range(1, n + 1)) / 2 / 2  # mirror; +-zeta pairs
    simplex = sum((d + 1) * (d + 2) / 2 / 2 * (m + 2) / 2 for m in range(1, n + 1))
    return bound, simplex


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--N", type=int, nargs="+", default=[28, 40, 64])
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args()
    print("| N | primes | bound: eliminations/prime | bound, min | simplex rule, min | built route (plan), min |")
    print("| --- | --- | --- | --- | --- | --- |")
    for N in args.N:
        n, primes = N - 1, len(floor_primes(N))
        each = ROW_SECONDS * n * n + PIVOT_SECONDS * n
        bound, simplex = eliminations(N)
        minutes = [x * primes * each / args.workers / 60 for x in (bound, simplex)]
        built = moments_plan(N).seconds / 60
        print(f"| {N} | {primes} | {bound:.3g} | {minutes[0]:.1f} | {minutes[1]:.1f} | {built:.0f} |")


if __name__ == "__main__":
    main()
