"""The numbers the README and the docs state about runs, printed from the plans themselves (issue 53 item 6).

    python benchmarks/plan_numbers.py              # Markdown: each route's reach and the cost of typical tables
    python benchmarks/plan_numbers.py --memory 16  # as planned for a machine of 16 GiB available

The plans (``forcenet.plan``) are the one source: their constants are the
measured ones of ``notes/benchmarks.md`` (the benchmark record), their
refusals state the limits. Docs that quote a limit or a cost paste this
output (or run this script when they are built), so the refusal, ``--help``
and the docs cannot disagree.
"""

from __future__ import annotations

import argparse

import forcenet

ROUTES = ("fast", "thesis", "lambda", "maps", "pfaffian")


def reach(method: str, memory: int, top: int = 400) -> int:
    """The largest N the route's plan runs within ``memory`` (its range and its memory), scanning up from 2."""
    best = 1
    for N in range(2, top + 1):
        if not forcenet.plan(N, method=method, memory_bytes=memory).runnable:
            break
        best = N
    return best


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--memory", type=float, default=16.0, help="GiB available (default 16)")
    args = parser.parse_args()
    memory = int(args.memory * 2**30)
    print(f"Each route's reach with {args.memory:g} GiB available (the largest N its plan runs):\n")
    print("| method | largest N | its plan there |\n| --- | --- | --- |")
    for method in ROUTES:
        N = reach(method, memory)
        print(f"| {method} | {N} | {forcenet.plan(N, method=method, memory_bytes=memory).describe()} |")
    print("\nThe exact table, `method='auto'`, as planned (`forcenet.plan(N)`; the command line's main job adds "
          "its Monte Carlo cross-check, `forcenet table --N N` announces both):\n")
    print("| N | route | plan |\n| --- | --- | --- |")
    for N in (12, 24, 40, 60, 100, 150, 200):
        plan = forcenet.plan(N, memory_bytes=memory)
        print(f"| {N} | {plan.method} | {plan.describe()} |")


if __name__ == "__main__":
    main()
