"""Time and peak memory of the exact force distributions (issue 16), one case per process.

Cases:

* ``grains``: the exact density and CDF (sympy polynomials) of every grain of
  layers 2..N (N - 1 passes over the ideals, then the polynomials);
* ``ensemble``: the exact ensemble P(f) (every grain of layers 2..N), pieces with exact coefficients;
* ``floor``: the exact P(f) of the floor layer alone (one pass);
* ``contacts``: the gap laws of every contact force F5, F6 (N - 1 row passes);
* ``ratio``: every grain's moments s = 1..4 from the gap laws against ``moment()``
  (the marked-chain DP), in the same process: the speed claim as a ratio.

Each line reports the plan's estimate next to the measurement.

Usage::

    OMP_NUM_THREADS=1 python benchmarks/distribution_timing.py grains 12
    OMP_NUM_THREADS=1 python benchmarks/distribution_timing.py ensemble 20
"""

from __future__ import annotations

import resource
import sys
import time


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    what, N = argv[0], int(argv[1])
    from forcenet.exact.triangle import distribution as D
    from forcenet.exact.triangle.gaps import contact_gap_counts, layer_gap_counts

    if what == "ratio":
        from forcenet.exact.triangle.moments import moment

        grains = [(i, j) for i in range(2, N + 1) for j in range(1, i + 1)]
        t0 = time.perf_counter()
        via_gaps = {(g, s): D.moment_from_gaps(D.grain_gap_counts(N, g), s) for g in grains for s in range(1, 5)}
        t1 = time.perf_counter()
        via_dp = {(g, s): moment(N, g, s) for g in grains for s in range(1, 5)}
        t2 = time.perf_counter()
        assert via_gaps == via_dp
        print(f"ratio N={N}: {len(via_gaps)} moments from the gap laws {t1 - t0:.2f} s, by moment() {t2 - t1:.2f} s "
              f"(x{(t2 - t1) / (t1 - t0):.1f}); equal")
        return
    kind = {"grains": "all", "ensemble": "ensemble", "floor": "layer", "contacts": "contacts"}[what]
    plan = D.distribution_plan(N, kind)
    t0 = time.perf_counter()
    if what == "grains":
        for i in range(2, N + 1):
            layer_gap_counts(N, i)
        t1 = time.perf_counter()
        for i in range(2, N + 1):
            for j in range(1, i + 1):
                D.density(N, (i, j))
                D.cdf(N, (i, j))
        detail = f"gap laws {t1 - t0:.2f} s, {N * (N + 1) // 2 - 1} densities + CDFs {time.perf_counter() - t1:.2f} s"
    elif what == "ensemble":
        pieces = D.triangle_force_density(N)
        detail = f"{len(pieces)} pieces of degree {max(p.poly.degree() for p in pieces)}"
    elif what == "floor":
        P = D.layer_force_density(N, N)
        detail = f"degree {P.degree()}"
    else:
        laws = contact_gap_counts(N)
        detail = f"{len(laws)} contact laws"
    seconds = time.perf_counter() - t0
    rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(f"{what} N={N}: {seconds:.2f} s, peak RSS {rss:.0f} MiB ({detail}); plan: {plan.describe()}")


if __name__ == "__main__":
    main()
