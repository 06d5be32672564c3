"""Exact-sampler data at large N for notes/force_distribution.md (issue 16, large-N limit).

For each sample: the pooled f = i W_{i,j} of three pools (the floor, the layer
i = N/2, every grain of layers 2..N), the contacts between layers N - 1 and N, the loads of the central grains of the
floor and of layer N/2, and their rank gaps (W without the Beta noise).
Saved to an .npz; the figures and numbers are made by
benchmarks/force_distribution.py.

Usage::

    OMP_NUM_THREADS=1 python benchmarks/force_distribution_samples.py --N 200 --samples 400 --seed 7 --out data.npz
"""

from __future__ import annotations

import argparse
import time

import numpy as np


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--N", type=int, required=True)
    parser.add_argument("--samples", type=int, required=True)
    parser.add_argument("--seed", type=int, default=7)
    parser.add_argument("--batch", type=int, default=16)
    parser.add_argument("--centre", type=int, default=10, help="central grains j = c-K..c+K of the two layers")
    parser.add_argument("--out", required=True)
    args = parser.parse_args(argv)

    from forcenet.numeric.triangle.exact_sampler import sample_tableaux, tableaux_to_W

    N, d = args.N, args.N * (args.N - 1) // 2
    rng = np.random.default_rng(args.seed)
    layers = {"floor": N, "mid": N // 2}
    edges = np.concatenate([[0.0], np.logspace(-3, np.log10(N), 400)])
    hist = {name: np.zeros(len(edges) - 1) for name in ("floor", "mid", "ensemble", "contacts")}
    centre_W = {name: [] for name in layers}
    centre_g = {name: [] for name in layers}
    t0 = time.perf_counter()
    done = 0
    while done < args.samples:
        k = min(args.batch, args.samples - done)
        T = sample_tableaux(N, k, rng).astype(np.int64)
        W = tableaux_to_W(T, rng)
        for name, i in layers.items():
            hist[name] += np.histogram(i * W[:, i - 1, :i].ravel(), edges)[0]
            c = (i + 1) // 2
            js = np.arange(max(1, c - args.centre), min(i, c + args.centre) + 1)
            centre_W[name].append(W[:, i - 1, js - 1])
            cols = N - i + js
            hi = np.where(js == i, d + 1, T[:, np.minimum(js, N - 1), np.minimum(cols, N - 1)])
            lo = np.where(js == 1, 0, T[:, js - 1, cols - 1])
            centre_g[name].append(hi - lo)
        pool = np.concatenate([i * W[:, i - 1, :i] for i in range(2, N + 1)], axis=1)
        hist["ensemble"] += np.histogram(pool.ravel(), edges)[0]
        # contacts between layers N-1 and N: F5, F6 in units of 2/sqrt3 are S_{N,j} - S_{N-1,j-1} and
        # S_{N-1,j} - S_{N,j} (Eqs. 3.8, 4.6); f = 2 (N - 1) x spacing
        S = np.cumsum(W[:, N - 2 :, :], axis=2)  # S[:, 0] = layer N-1, S[:, 1] = layer N
        above = np.concatenate([np.zeros((k, 1)), S[:, 0, : N - 1]], axis=1)  # S_{N-1,0..N-1}
        F5 = S[:, 1, : N - 1] - above[:, : N - 1]
        F6 = above[:, 1:] - S[:, 1, : N - 1]
        hist["contacts"] += np.histogram(2 * (N - 1) * np.concatenate([F5, F6], axis=1).ravel(), edges)[0]
        done += k
        print(f"N={N}: {done}/{args.samples} samples, {time.perf_counter() - t0:.0f} s", flush=True)
    np.savez_compressed(
        args.out, N=N, samples=args.samples, seed=args.seed, edges=edges,
        **{f"hist_{k}": v for k, v in hist.items()},
        **{f"W_{k}": np.concatenate(v) for k, v in centre_W.items()},
        **{f"g_{k}": np.concatenate(v) for k, v in centre_g.items()},
    )
    print(f"saved {args.out}: {time.perf_counter() - t0:.0f} s")


if __name__ == "__main__":
    main()
