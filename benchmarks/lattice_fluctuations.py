"""Exact fluctuations of the lattice-direction loads W_(i,1) by Pfaffians (issue 27, notes/fluctuations.md Sec. 2).

For each N: the exact gap law of every W_(i,1) (``lattice_gap_laws``), its first
four moments E[W^s] = E[g (g+1) ... (g+s-1)] / ((d+1) ... (d+s)) as exact
fractions (written as strings), the wall time, and a printed summary at fixed
depths z = i/N: the mean, the standard deviation, and its tableau part
sd(g)/(d+1) (the rest is the Dirichlet noise of the spacings).

Usage::

    python benchmarks/lattice_fluctuations.py --N 16 24 32 40 48 --out lattice_fluctuations.json
"""

from __future__ import annotations

import argparse
import json
import os
import time

from forcenet.exact.triangle.distribution import moment_from_gaps
from forcenet.exact.triangle.free_fermion.fluctuations import lattice_gap_laws
from forcenet.exact.triangle.tables import fraction_from_text, fraction_str


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--N", type=int, nargs="+", required=True)
    parser.add_argument("--out", default="lattice_fluctuations.json")
    parser.add_argument("--workers", type=int, default=None)
    args = parser.parse_args(argv)
    data = {}
    if os.path.exists(args.out):
        with open(args.out) as handle:
            data = json.load(handle)
    for N in args.N:
        start = time.time()
        laws = lattice_gap_laws(N, workers=args.workers)
        seconds = time.time() - start
        moments = {i: [fraction_str(moment_from_gaps(law, s)) for s in range(1, 5)] for i, law in laws.items()}
        data[str(N)] = {"seconds": seconds, "moments": moments}
        tmp = args.out + ".tmp"
        with open(tmp, "w") as handle:
            json.dump(data, handle)
        os.replace(tmp, args.out)
        row = []
        for z in (0.25, 0.5, 0.75, 1.0):
            i = max(2, round(z * N))
            m1, m2 = (fraction_from_text(x) for x in moments[i][:2])
            d = N * (N - 1) // 2
            g1, g2 = m1 * (d + 1), m2 * (d + 1) * (d + 2) - m1 * (d + 1)  # E[g], E[g^2]
            rank = float(g2 - g1 * g1) ** 0.5 / (d + 1)  # the tableau part of the fluctuation, sd(g)/(d+1)
            row.append(f"z={i / N:.2f}: <W>={float(m1):.5f} sd={float(m2 - m1 * m1) ** 0.5:.5f} rank sd={rank:.5f}")
        print(f"N={N} ({seconds:.0f} s): " + "; ".join(row), flush=True)


if __name__ == "__main__":
    main()
