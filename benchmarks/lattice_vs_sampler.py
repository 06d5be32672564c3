"""The exact lattice direction <W_(i,1)> by Pfaffians against the exact (hook-walk) sampler (issue 18).

Reads ``lattice_N{N}.json`` (written by ``benchmarks/scaling_refit.py --lattice N``)
or computes it, draws ``--samples`` independent tableaux with
:class:`forcenet.numeric.triangle.exact_sampler.ExactSampler` and compares the
``N - 1`` sampled means of ``W_(i,1)``, ``i = 2..N``, with the exact values:
Hotelling's chi-square and the Bonferroni max |z|, each at ``alpha / 2``
(``forcenet.testing``; at alpha = 1e-3 the max |z| bound is about 4.4 sigma
for 99 grains).

Usage::

    python benchmarks/lattice_vs_sampler.py --N 100 --samples 20000 --dir out
"""

from __future__ import annotations

import argparse
import json
import os
import time

import numpy as np

from forcenet.exact.triangle.tables import fraction_from_text
from forcenet.numeric.agreement import compare_samples
from forcenet.numeric.triangle.exact_sampler import ExactSampler


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--N", type=int, default=100)
    parser.add_argument("--samples", type=int, default=20000)
    parser.add_argument("--seed", type=int, default=100)
    parser.add_argument("--dir", default="out")
    parser.add_argument("--alpha", type=float, default=1e-3)
    args = parser.parse_args(argv)
    path = os.path.join(args.dir, f"lattice_N{args.N}.json")
    if os.path.exists(path):
        with open(path) as handle:
            column = [fraction_from_text(x) for x in json.load(handle)["W_i1"]]
    else:
        from forcenet.exact.triangle.free_fermion.route import lattice_direction

        column = lattice_direction(args.N)
    N = args.N
    t0 = time.perf_counter()
    sampler, rows, drawn = ExactSampler(N, seed=args.seed), [], 0
    while drawn < args.samples:
        W = sampler.sample_W(min(sampler.batch, args.samples - drawn))
        rows.append(W[:, 1:, 0])  # W_(i,1), i = 2..N
        drawn += W.shape[0]
    seconds = time.perf_counter() - t0
    result = compare_samples(np.concatenate(rows), column[1:], keys=[(i, 1) for i in range(2, N + 1)], alpha=args.alpha)
    print(f"N={N}, {drawn} exact samples in {seconds:.1f} s (seed {args.seed}), {N - 1} grains (i, 1):")
    print(result.summary())
    return 0 if result.passed else 1


if __name__ == "__main__":
    raise SystemExit(main())
