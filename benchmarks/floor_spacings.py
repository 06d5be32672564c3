"""The floor's loads as spacings of a beta = 1 ensemble (issue 27, notes/fluctuations.md Sec. 5): a sampled check.

Draws exact samples (the hook-walk sampler of tableaux, which knows nothing of
the ensemble), unfolds the floor's free partial sums with the arcsine law
``F(v) = (2/pi) arcsin(sqrt(v))`` (the equilibrium measure of Jacobi
ensembles on [0, 1]) and prints the normalized variance of the unfolded
spacings of the middle half of the floor, with the error from batches of
samples, and the small-spacing fractions.  GOE: 0.286; GUE: 0.180; Poisson: 1.

Usage::

    python benchmarks/floor_spacings.py --N 120 --samples 1500 --seed 27
"""

from __future__ import annotations

import argparse

import numpy as np

from forcenet.numeric.triangle.exact_sampler import ExactSampler


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--N", type=int, default=120)
    parser.add_argument("--samples", type=int, default=1500)
    parser.add_argument("--seed", type=int, default=27)
    parser.add_argument("--batches", type=int, default=10)
    args = parser.parse_args(argv)
    N, n = args.N, args.N - 1
    W = ExactSampler(N, seed=args.seed).sample_W(args.samples)
    v = np.cumsum(W[:, N - 1, :N], axis=1)[:, :-1]  # the floor's free partial sums
    u = n * (2 / np.pi) * np.arcsin(np.sqrt(np.clip(v, 0, 1)))
    spacings = np.diff(u, axis=1)[:, n // 4 : 3 * n // 4]
    size = args.samples // args.batches
    stats = [b.var() / b.mean() ** 2 for b in (spacings[k * size : (k + 1) * size].ravel() for k in range(args.batches))]
    error = np.std(stats, ddof=1) / np.sqrt(args.batches)
    print(f"N={N}, {args.samples} samples: var/mean^2 of the unfolded bulk spacings {np.mean(stats):.4f} +- {error:.4f}")
    s = spacings.ravel() / spacings.mean()
    for cut in (0.1, 0.25, 0.5):
        print(f"P(s < {cut}) = {(s < cut).mean():.5f}")


if __name__ == "__main__":
    main()
