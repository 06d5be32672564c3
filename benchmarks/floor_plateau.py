"""The floor's exact pooled P(f) beyond the order-ideal DP (issue 27; notes/force_distribution.md Sec. 6.5).

For each N: the floor's pooled gap law by de Bruijn Pfaffians
(``floor_pooled_gap_law``, checkpointed), the exact density of ``f = N W`` at a
few points (exact rationals, printed correctly rounded), ``<f^2>``, the wall
time, and the SHA-256 of the exact gap counts.  Results accumulate in a JSON
file (atomic rewrite); N already there is skipped.

With ``--figure PNG`` it also draws the exact P_N(f) of every N in the file
(the laws rebuilt from the checkpoints: Chinese remainders only) and the
plateau values against 1/N.

Usage::

    python benchmarks/floor_plateau.py --N 20 24 28 32 36 40 --out floor_plateau.json --checkpoint ckpt
    python benchmarks/floor_plateau.py --N 20 --out floor_plateau.json --checkpoint ckpt --figure floor_plateau.png
"""

from __future__ import annotations

import argparse
import hashlib
import json
import os
import time
from fractions import Fraction

from goe_spacing import floor_limit_density  # benchmarks/goe_spacing.py, beside this script

from forcenet.exact.triangle.de_bruijn.floor import floor_pooled_gap_law
from forcenet.exact.triangle.distribution import density_from_gaps, moment_from_gaps

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


def figure(data: dict, checkpoint, path: str) -> None:
    """P_N(f) on [0, 3] for every N in ``data`` (the Beta mixture in floats: positive terms, no cancellation), and
    P_N(1/10), P_N(1/4) against 1/N."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np
    from scipy.stats import beta

    Ns = sorted(int(k) for k in data)
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.2))
    f = np.linspace(0.0, 3.0, 301)
    for N in Ns:
        law = floor_pooled_gap_law(N, workers=1, checkpoint=checkpoint)
        w = f / N
        dens = sum(float(Fraction(c, law.total)) * beta.pdf(w, g, law.d + 1 - g) for g, c in enumerate(law.counts) if c)
        left.plot(f, dens / N, label=f"N = {N}")
    coarse = np.linspace(0.05, 3.0, 40)
    left.plot(coarse, [floor_limit_density(x) for x in coarse], "k--", label="N -> oo: arcsine mixture of GOE spacings")
    left.set_xlabel("f = N W (floor)")
    left.set_ylabel("exact P_N(f)")
    left.set_title("the floor's pooled P(f), exact (de Bruijn Pfaffians)")
    left.legend(fontsize=8)
    x = np.array([1.0 / N for N in Ns])
    for key, marker in (("1/10", "o"), ("1/4", "s")):
        right.plot(x, [data[str(N)]["density"][key] for N in Ns], marker, label=f"P_N({key})")
    right.axhspan(0.64, 0.66, color="0.85", label="sampled on (0.1, 0.3), N = 200-1000")
    for key, style in (("1/10", "C0:"), ("1/4", "C1:")):
        right.axhline(floor_limit_density(float(Fraction(key))), color=style[:2], linestyle=":",
                      label=f"N -> oo at f = {key} (GOE)")
    right.set_xlabel("1/N")
    right.set_xlim(left=0)
    right.set_title("the plateau against 1/N")
    right.legend(fontsize=8)
    fig.tight_layout()
    tmp = path + ".tmp.png"
    fig.savefig(tmp, dpi=120)
    os.replace(tmp, path)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--N", type=int, nargs="+", required=True)
    parser.add_argument("--out", default="floor_plateau.json")
    parser.add_argument("--checkpoint", default=None, help="a checkpoint directory (every finished prime is kept)")
    parser.add_argument("--workers", type=int, default=None)
    parser.add_argument("--figure", default=None, help="a PNG of P_N(f) for every N in --out, and the plateau")
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
    if args.figure:
        figure(data, args.checkpoint, args.figure)


if __name__ == "__main__":
    main()
