"""Exact tables against the scaling limit of the response (issue 6).

Reads exact tables written by ``forcenet table --N N --format json --out
out/mean_W_N{N}.json`` (computing missing ones), compares them with
``forcenet.numeric.limit_shape.surface`` and fits the finite-size corrections
``|exact - limit| ~ A N^(-alpha)`` over the largest N.  Writes figures to
``notes/figures/`` and prints Markdown for ``notes/scaling_limit.md``.

Usage::

    python benchmarks/scaling_check.py --N 8 12 16 20 24 26 28
"""

from __future__ import annotations

import argparse
import json
import os

import numpy as np

from forcenet.exact.triangle.tables import fraction_from_text
from forcenet.numeric.limit_shape.surface import bulk_response, lattice_response


def load_table(N: int, directory: str = "out"):
    path = os.path.join(directory, f"mean_W_N{N}.json")
    if not os.path.exists(path):
        from forcenet.exact.triangle.tables import exact_table, to_json, write_atomic

        write_atomic(path, to_json(exact_table(N)) + "\n")
    with open(path) as handle:
        data = json.load(handle)
    return [[float(fraction_from_text(x)) for x in row] for row in data["mean_W"]]


def fit_power(Ns, deviations):
    Ns, dev = np.asarray(Ns, float), np.abs(np.asarray(deviations, float))
    slope, intercept = np.polyfit(np.log(Ns), np.log(dev), 1)
    return -slope, float(np.exp(intercept))


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--N", type=int, nargs="+", default=[8, 12, 16, 20, 24])
    parser.add_argument("--figures", default="notes/figures")
    args = parser.parse_args(argv)
    Ns = sorted(args.N)
    tables = {N: load_table(N) for N in Ns}

    # probes: (name, function N -> (exact value, limit value))
    def edge(z):
        def probe(N):
            i = round(z * N)
            return tables[N][i - 1][0], float(lattice_response(i / N))

        return probe

    def bulk(z, xfrac):
        def probe(N):
            i = round(z * N)
            j = round((xfrac * i + i + 1) / 2)  # x = (2j - i - 1)/N closest to xfrac * z
            x = (2 * j - i - 1) / N
            return N * tables[N][i - 1][j - 1], float(bulk_response(x, i / N))

        return probe

    probes = [
        ("edge z=1/4: <W_{i,1}>", edge(0.25)),
        ("edge z=1/2: <W_{i,1}>", edge(0.5)),
        ("edge z=3/4: <W_{i,1}>", edge(0.75)),
        ("bulk z=1/2, x~0: N<W>", bulk(0.5, 0.0)),
        ("bulk z=3/4, x~0: N<W>", bulk(0.75, 0.0)),
        ("bulk z=3/4, x~-z/2: N<W>", bulk(0.75, -0.5)),
        ("bottom z=1, x~0: N<W>", bulk(1.0, 0.0)),
        ("bottom z=1, x~-1/2: N<W>", bulk(1.0, -0.5)),
    ]
    header = "| probe | limit | " + " | ".join(f"N={N}" for N in Ns) + " | fitted exponent | amplitude |"
    print(header)
    print("|" + " --- |" * (len(Ns) + 4))
    for name, probe in probes:
        values = [probe(N) for N in Ns]
        devs = [ex - lim for ex, lim in values]
        big = [N for N in Ns if N >= 12]
        alpha, amp = fit_power(big, [devs[Ns.index(N)] for N in big])
        cells = " | ".join(f"{ex:.5f} ({d:+.4f})" for (ex, _), d in zip(values, devs))
        print(f"| {name} | {values[-1][1]:.5f} | {cells} | {alpha:.2f} | {amp:.3g} |")

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    os.makedirs(args.figures, exist_ok=True)
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.5))
    for ax, z in zip(axes[:2], (0.5, 0.75)):
        xs = np.linspace(-z + 1e-6, z - 1e-6, 121)
        ax.plot(xs, [float(bulk_response(x, z, dps=15)) for x in xs], "k-", lw=2, label="limit", zorder=10)
        for N in Ns:
            i = round(z * N)
            js = np.arange(2, i)
            ax.plot((2 * js - i - 1) / N, [N * tables[N][i - 1][j - 1] for j in js], "o-", ms=3, label=f"N={N} (exact)")
        ax.set_ylim(0, 4)
        ax.set_title(f"bulk response N<W> at z = {z} (limit diverges at |x| = z)")
        ax.set_xlabel("x = (2j - i - 1)/N")
        ax.legend(fontsize=7)
    ax = axes[2]
    zs = np.linspace(0.02, 1, 100)
    ax.plot(zs, [float(lattice_response(z, dps=15)) for z in zs], "k-", lw=2, label="(1 - sqrt(z(2-z)))/2", zorder=10)
    for N in Ns:
        i = np.arange(1, N + 1)
        ax.plot(i / N, [tables[N][k - 1][0] for k in i], "o", ms=3, label=f"N={N} (exact)")
    ax.set_title("response on the lattice direction, <W_{i,1}>")
    ax.set_xlabel("z = i/N")
    ax.legend(fontsize=7)
    fig.tight_layout()
    path = os.path.join(args.figures, "scaling_limit_exact.png")
    fig.savefig(path, dpi=110)
    print(f"\nfigure: {path}")


if __name__ == "__main__":
    main()
