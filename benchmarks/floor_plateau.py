"""The floor's exact pooled P(f) beyond the order-ideal DP (issue 27; notes/force_distribution.md Sec. 6.5).

For each N: the floor's pooled gap law by de Bruijn Pfaffians
(``floor_pooled_gap_law``, checkpointed), the exact density of ``f = N W`` at a
few points (exact rationals, printed correctly rounded), ``<f^2>``, the wall
time, and the SHA-256 of the exact gap counts.  Results accumulate in a JSON
file (atomic rewrite); N already there is skipped.

Usage::

    python benchmarks/floor_plateau.py --N 20 24 28 32 36 40 --out floor_plateau.json --checkpoint ckpt
"""

from __future__ import annotations

import argparse
import hashlib
import json
import os
import time
from fractions import Fraction

from forcenet.exact.triangle.distribution import density_from_gaps, moment_from_gaps
from forcenet.exact.triangle.pfaffian.floor import floor_pooled_gap_law

POINTS = ("0", "1/20", "1/10", "1/4", "1/2", "1", "2")


def summary(N: int, law) -> dict:
    """Exact density of f = N W at POINTS (as fractions' floats), <f^2>, and the counts' digest."""
    poly = density_from_gaps(law)  # density of W, pooled over the N loads
    values = {}
    for text in POINTS:
        f = Fraction(text)
        exact = poly.eval(f / N) / N  # P_N(f) = p_W(f / N) / N
        values[text] = float(Fraction(int(exact.p), int(exact.q)))
    f2 = moment_from_gaps(law, 2) * N * N
    digest = hashlib.sha256(",".join(map(str, law.counts)).encode()).hexdigest()
    return {"density": values, "f2": str(f2), "f2_float": float(f2), "sha256": digest}


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--N", type=int, nargs="+", required=True)
    parser.add_argument("--out", default="floor_plateau.json")
    parser.add_argument("--checkpoint", default=None, help="a checkpoint directory (every finished prime is kept)")
    parser.add_argument("--workers", type=int, default=None)
    args = parser.parse_args(argv)
    data = {}
    if os.path.exists(args.out):
        with open(args.out) as handle:
            data = json.load(handle)
    for N in args.N:
        if str(N) in data:
            continue
        start = time.time()
        law = floor_pooled_gap_law(N, workers=args.workers, checkpoint=args.checkpoint)
        seconds = time.time() - start
        data[str(N)] = {"seconds": seconds, **summary(N, law)}
        tmp = args.out + ".tmp"
        with open(tmp, "w") as handle:
            json.dump(data, handle, indent=1)
        os.replace(tmp, args.out)
        dens = data[str(N)]["density"]
        print(f"N={N} ({seconds:.0f} s wall): P(f) at " + ", ".join(f"{k}: {v:.5f}" for k, v in dens.items())
              + f"; <f^2> = {data[str(N)]['f2_float']:.5f}", flush=True)


if __name__ == "__main__":
    main()
