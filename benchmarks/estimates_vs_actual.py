"""The plans' estimates against the measured time (issue 53: estimates within 1.5x on an idle machine).

    python benchmarks/estimates_vs_actual.py                 # every case below, each in a fresh process
    python benchmarks/estimates_vs_actual.py table-40 law    # only these cases

For each case: the plan's ``seconds`` (what ``plan.describe()`` announces), the wall time of ``plan.run()``
in a fresh Python process (imports done, nothing warmed: what a user's script meets, compiled kernels
loaded from the on-disk cache), and their ratio (measured / estimated). The load average before and after
is printed: on a shared machine the wall-time ratio grows with the load, so compare only runs made idle
(load < 1 on the 2 cores).  Beside it, the CPU seconds of the run (this process and its worker processes)
and the CPU time per worker (CPU / workers the plan uses): under load the CPU time moves much less than the
wall time, so ``cpu / workers / estimate`` is the loaded machine's best guess of the idle ratio (an
underestimate when the run waits on something else than a core: memory, disk, the workers' start).
``--repeat K`` runs each case K times and prints each measurement.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import time
from collections.abc import Callable
from typing import Any

import forcenet
from forcenet.exact.contact_network.geometries import triangle
from forcenet.exact.triangle.prime_tasks import workers_for


def _network_exact() -> Any:
    return forcenet.network_plan(triangle(5).network)  # exact means (the default without samples), dimension 10


def _network_sampled() -> Any:
    return forcenet.network_plan(triangle(5).network, samples=20000, seed=0)  # default burn-in, one chain


CASES: dict[str, Callable[[], Any]] = {
    "table-40": lambda: forcenet.plan(40),
    "table-48": lambda: forcenet.plan(48),
    "law": lambda: forcenet.law_plan(24, (24, 12)),  # the auto route: de Bruijn Pfaffians of the floor
    "law-12": lambda: forcenet.law_plan(12, (12, 6)),  # the README's `dist --N 12 --grain 12,6`: order ideals
    "network": _network_exact,
    "network-sampled": _network_sampled,
    "scaling-percolation": lambda: forcenet.scaling_plan("percolation"),
    "scaling-q-independent": lambda: forcenet.scaling_plan("q-independent"),
    "scaling-q-microcanonical": lambda: forcenet.scaling_plan("q-microcanonical"),
}


def _cpu() -> float:
    """CPU seconds (user + system) of this process and of its finished children."""
    own, children = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + children.ru_utime + children.ru_stime


def _workers(plan: Any) -> int:
    """The processes a plan's run keeps busy: a run over primes the available cores when it pays for starting
    them (:func:`forcenet.exact.triangle.prime_tasks.workers_for`), a request's ``workers``, else 1."""
    cost = getattr(plan, "cost", None)
    if getattr(cost, "unit", None) == "prime":
        return workers_for(None, int(cost.ticks), float(plan.seconds))
    value = getattr(getattr(plan, "request", None), "workers", None)
    return value if isinstance(value, int) and value > 0 else 1


def measure(name: str) -> dict[str, Any]:
    """Plan the case, run it once, time the run (wall and CPU, this process and its workers)."""
    plan = CASES[name]()
    cpu, start = _cpu(), time.perf_counter()
    plan.run()
    wall, cpu = time.perf_counter() - start, _cpu() - cpu
    return {"case": name, "estimate": float(plan.seconds), "actual": wall, "cpu": cpu,
            "workers": _workers(plan), "plan": plan.describe()}


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("cases", nargs="*", help=f"cases to run (default all: {', '.join(CASES)})")
    parser.add_argument("--repeat", type=int, default=1, help="runs per case (default 1)")
    parser.add_argument("--one", help=argparse.SUPPRESS)  # internal: measure one case in this process
    args = parser.parse_args(argv)
    if args.one:
        print(json.dumps(measure(args.one)))
        return
    unknown = [c for c in args.cases if c not in CASES]
    if unknown:
        parser.error(f"unknown case(s) {', '.join(unknown)}; the cases are {', '.join(CASES)}")
    print("| case | estimate (s) | wall (s) | wall / estimate | CPU (s) | workers | CPU / workers / estimate "
          "| load before, after | plan |")
    print("| --- | ---: | ---: | ---: | ---: | ---: | ---: | --- | --- |")
    for name in args.cases or list(CASES):
        for _ in range(args.repeat):
            before = os.getloadavg()[0]
            done = subprocess.run([sys.executable, __file__, "--one", name], capture_output=True, text=True,
                                  check=True)
            r = json.loads(done.stdout.strip().splitlines()[-1])
            est = r["estimate"] if r["estimate"] > 0 else float("nan")
            print(f"| {name} | {r['estimate']:.2f} | {r['actual']:.2f} | {r['actual'] / est:.2f} | {r['cpu']:.2f} | "
                  f"{r['workers']} | {r['cpu'] / r['workers'] / est:.2f} | {before:.1f}, {os.getloadavg()[0]:.1f} | "
                  f"{r['plan']} |", flush=True)


if __name__ == "__main__":
    main()
