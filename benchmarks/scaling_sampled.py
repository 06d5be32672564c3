"""Exact-sampler estimates at large N against the scaling limit (issue 6, part 2).

For each N, draws independent uniform configurations with
``forcenet.numeric.triangle.exact_sampler`` (seeded), stores the mean <W> table and its standard
error in ``out/sampled_N{N}_S{samples}.npz``, and compares with
``forcenet.numeric.limit_shape.surface`` at fixed (x, z): deviation and its error bar.

Usage::

    python benchmarks/scaling_sampled.py --N 50 100 200 500 --samples 2048 1024 256 64
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np

from forcenet.numeric.limit_shape.surface import bulk_response, lattice_response
from forcenet.numeric.triangle.exact_sampler import ExactSampler


def sampled(N, samples, seed, batch):
    path = os.path.join("out", f"sampled_N{N}_S{samples}_seed{seed}.npz")
    if os.path.exists(path):
        data = np.load(path)
        return data["mean"], data["stderr"], float(data["seconds"])
    t0 = time.perf_counter()
    mean, stderr = ExactSampler(N, seed=seed, batch=batch).mean_W(samples)
    seconds = time.perf_counter() - t0
    os.makedirs("out", exist_ok=True)
    np.savez(path, mean=mean, stderr=stderr, seconds=seconds)
    return mean, stderr, seconds


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--N", type=int, nargs="+", default=[50, 100, 200])
    parser.add_argument("--samples", type=int, nargs="+", default=[2048, 1024, 256])
    parser.add_argument("--seed", type=int, default=2026)
    parser.add_argument("--figures", default="notes/figures")
    args = parser.parse_args(argv)
    if len(args.samples) != len(args.N):
        parser.error("--samples needs one count per --N")
    results = {}
    for N, K in zip(args.N, args.samples):
        batch = max(8, min(K, 4096 // max(1, N // 25)))
        results[N] = sampled(N, K, args.seed, batch)
        print(f"N={N}: {K} samples in {results[N][2]:.1f} s", flush=True)

    print("\n| probe | limit | " + " | ".join(f"N={N}" for N in args.N) + " |")
    print("|" + " --- |" * (len(args.N) + 2))
    probes = [("edge z=1/2: <W_{i,1}>", 0.5, None), ("edge z=3/4: <W_{i,1}>", 0.75, None),
              ("bulk z=3/4, x~0: N<W>", 0.75, 0.0), ("bulk z=3/4, x~-z/2: N<W>", 0.75, -0.5),
              ("bottom z=1, x~0: N<W>", 1.0, 0.0)]
    for name, z, xfrac in probes:
        cells = []
        for N in args.N:
            mean, err, _ = results[N]
            i = round(z * N)
            if xfrac is None:
                value, sigma, limit = mean[i - 1, 0], err[i - 1, 0], float(lattice_response(i / N))
            else:
                j = round((xfrac * i + i + 1) / 2)
                x = (2 * j - i - 1) / N
                value, sigma, limit = N * mean[i - 1, j - 1], N * err[i - 1, j - 1], float(bulk_response(x, i / N))
            digits = 5 if xfrac is None else 4  # the edge values carry errors of ~1e-5
            cells.append(f"{value:.{digits}f} ± {sigma:.{digits}f} ({value - limit:+.{digits}f})")
        print(f"| {name} | {limit:.5f} | " + " | ".join(cells) + " |")

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(11, 4.5))
    z = 0.75
    xs = np.linspace(-z + 1e-6, z - 1e-6, 121)
    axes[0].plot(xs, [float(bulk_response(x, z, dps=15)) for x in xs], "k-", lw=2, label="limit", zorder=10)
    for N in args.N:
        mean, err, _ = results[N]
        i = round(z * N)
        js = np.arange(2, i)
        axes[0].errorbar((2 * js - i - 1) / N, N * mean[i - 1, js - 1], yerr=N * err[i - 1, js - 1], fmt="o", ms=2, label=f"N={N} (exact sampler)")
    axes[0].set_ylim(0, 4)
    axes[0].set_xlabel("x = (2j - i - 1)/N")
    axes[0].set_title("N<W> at z = 3/4: sampled vs limit")
    axes[0].legend(fontsize=7)
    zs = np.linspace(0.02, 1, 100)
    axes[1].plot(zs, [float(lattice_response(t, dps=15)) for t in zs], "k-", lw=2, label="limit", zorder=10)
    for N in args.N:
        mean, err, _ = results[N]
        i = np.arange(1, N + 1)
        axes[1].errorbar(i / N, mean[i - 1, 0], yerr=err[i - 1, 0], fmt="o", ms=2, label=f"N={N}")
    axes[1].set_xlabel("z = i/N")
    axes[1].set_title("<W_{i,1}> on the lattice direction")
    axes[1].legend(fontsize=7)
    fig.tight_layout()
    os.makedirs(args.figures, exist_ok=True)
    path = os.path.join(args.figures, "scaling_limit_sampled.png")
    fig.savefig(path, dpi=110)
    print(f"\nfigure: {path}")


if __name__ == "__main__":
    main()
