"""Figures analogous to the thesis's Figs. 3.4, 3.8 and 4.3 (issue 4).

* ``response_map_N35.png``: mean response and its standard deviation, N = 35,
  exact sampler (Fig. 3.4).
* ``q_distributions.png``: p(q_{i,j}) at j = i/2 for N = 25 and 50 and on the
  left boundary at several depths (Fig. 3.8).
* ``exact_vs_sampled_N11.png``: exact values against Metropolis and the exact
  sampler, boundary r = 1 and row 8 (Fig. 4.3).

Usage::

    python benchmarks/figures_response.py --samples 4000 --sweeps 20000
"""

from __future__ import annotations

import argparse
import os

import numpy as np


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--samples", type=int, default=4000)
    parser.add_argument("--sweeps", type=int, default=20000)
    parser.add_argument("--seed", type=int, default=35)
    parser.add_argument("--figures", default="notes/figures")
    args = parser.parse_args(argv)

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from forcenet.exact import mean_W
    from forcenet.numeric.autocorr import mean_and_stderr
    from forcenet.numeric.triangle.exact_sampler import ExactSampler, q_from_W
    from forcenet.numeric.triangle.metropolis import TriangleMetropolis

    os.makedirs(args.figures, exist_ok=True)

    # Fig. 3.4: response map and standard deviation, N = 35
    N = 35
    W = ExactSampler(N, seed=args.seed).sample_W(args.samples)
    mean, std = W.mean(axis=0), W.std(axis=0)
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.8))
    for ax, data, title in zip(axes, (mean, std), ("mean response <W_ij>", "standard deviation of W_ij")):
        grid = np.full((N, 2 * N - 1), np.nan)
        for i in range(N):
            for j in range(i + 1):
                grid[i, N - 1 - i + 2 * j] = data[i, j]
        im = ax.imshow(grid, cmap="turbo", aspect="auto", interpolation="nearest", norm=matplotlib.colors.LogNorm())
        ax.set_title(f"{title}, N = {N} ({args.samples} exact samples)")
        ax.set_xlabel("2j - i - 1 (doubled horizontal offset)")
        ax.set_ylabel("layer i")
        ax.set_xticks([0, N - 1, 2 * N - 2], [-(N - 1), 0, N - 1])
        fig.colorbar(im, ax=ax)
    fig.tight_layout()
    fig.savefig(os.path.join(args.figures, "response_map_N35.png"), dpi=100)

    # Fig. 3.8: q distributions
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    for N in (25, 50):
        Wn = ExactSampler(N, seed=args.seed + N).sample_W(args.samples)
        q = q_from_W(Wn)
        for i in (N // 2, (3 * N) // 4):
            j = i // 2
            axes[0].hist(q[:, i - 1, j - 1], bins=40, range=(0, 1), density=True, histtype="step", label=f"N={N}, i={i}, j={j}")
        if N == 25:
            for i in (5, 10, 15, 20):
                axes[1].hist(q[:, i - 1, 0], bins=40, range=(0, 1), density=True, histtype="step", label=f"i={i}")
    axes[0].set_title("p(q_ij) at j = i/2 (exact sampler)")
    axes[1].set_title("p(q_i1) on the left boundary, N = 25")
    for ax in axes:
        ax.set_xlabel("q")
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(args.figures, "q_distributions.png"), dpi=100)

    # Fig. 4.3: exact vs sampled, N = 11
    N = 11
    exact = mean_W(N)
    chain = TriangleMetropolis(N, seed=args.seed).run(args.sweeps, burn_in=args.sweeps // 10)
    m_mc, e_mc, _ = mean_and_stderr(chain)
    m_ex, e_ex = ExactSampler(N, seed=args.seed).mean_W(args.samples)
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    i = np.arange(1, N + 1)
    axes[0].plot(i, [float(exact[k - 1][0]) for k in i], "ks-", label="exact")
    axes[0].errorbar(i, m_mc[i - 1, 0], yerr=e_mc[i - 1, 0], fmt="o", label="Metropolis")
    axes[0].errorbar(i + 0.15, m_ex[i - 1, 0], yerr=e_ex[i - 1, 0], fmt="^", label="exact sampler")
    axes[0].set_xlabel("layer i")
    axes[0].set_title("<W_i,1> on the boundary, N = 11")
    row = 8
    j = np.arange(1, row + 1)
    axes[1].plot(j, [float(exact[row - 1][k - 1]) for k in j], "ks-", label="exact")
    axes[1].errorbar(j, m_mc[row - 1, j - 1], yerr=e_mc[row - 1, j - 1], fmt="o", label="Metropolis")
    axes[1].errorbar(j + 0.1, m_ex[row - 1, j - 1], yerr=e_ex[row - 1, j - 1], fmt="^", label="exact sampler")
    axes[1].set_xlabel("grain j")
    axes[1].set_title(f"<W_{row},j> (the thesis's bulk row for q = 3), N = 11")
    for ax in axes:
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(args.figures, "exact_vs_sampled_N11.png"), dpi=100)
    print("figures written to", args.figures)


if __name__ == "__main__":
    main()
