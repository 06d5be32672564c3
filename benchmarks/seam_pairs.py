"""Paired timings of plans and runs, for a refactoring that must not change their speed (issue 51).

    python benchmarks/seam_pairs.py            # this install: one line per case, median of the repeats (seconds)

Run it with the installs before and after the change, alternately (the machine's load moves), and compare the
medians. Every run is timed warm (one call first: imports, compiled kernels, caches of the engines' costs).
"""

from __future__ import annotations

import statistics
import sys
import time

import forcenet

PLANS = [
    ("plan(40)", lambda: forcenet.plan(40)),
    ("plan(40, moments=2)", lambda: forcenet.plan(40, moments=2)),
    ("plan(40, moments=2, row=20)", lambda: forcenet.plan(40, moments=2, row=20)),
    ("plan(24, method='pfaffian')", lambda: forcenet.plan(24, method="pfaffian")),
    ("law_plan(36, (36, 18))", lambda: forcenet.law_plan(36, (36, 18))),
    ("law_plan(12)", lambda: forcenet.law_plan(12)),
]
RUNS = [
    ("table(12, 2, 'fast')", lambda: forcenet.table(12, 2, "fast")),
    ("table(7, 2, 'thesis')", lambda: forcenet.table(7, 2, "thesis")),
    ("table(9, 1, 'lambda')", lambda: forcenet.table(9, 1, "lambda")),
    ("table(6, 2, 'maps')", lambda: forcenet.table(6, 2, "maps")),
    ("table(24, 1, 'pfaffian')", lambda: forcenet.table(24, 1, "pfaffian")),
    ("table(9, 2, 'pfaffian')", lambda: forcenet.table(9, 2, "pfaffian")),
    ("table(30, 2, row=29)", lambda: forcenet.table(30, 2, row=29)),
    ("table(14, 2, 'pfaffian', row=7)", lambda: forcenet.table(14, 2, "pfaffian", row=7)),
    ("law(12, (12, 6))", lambda: forcenet.law(12, (12, 6))),
    ("law(24, layer=24)", lambda: forcenet.law(24, layer=24)),
]


def timed(function, repeats: int) -> float:
    function()  # warm
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        function()
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def main() -> int:
    for name, function in PLANS:
        print(f"{name:32s} {timed(function, 20):.6f}")
    for name, function in RUNS:
        print(f"{name:32s} {timed(function, 2):.4f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
