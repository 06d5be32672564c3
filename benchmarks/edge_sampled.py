"""Exact samples of the lattice-direction loads at large N: mean and standard deviation of W_(i,1) (issue 43, item 3).

For each N, draws ``--samples`` independent uniform configurations with the exact
sampler (Sagan's shifted hook walk, ``forcenet.numeric.triangle.exact_sampler``),
in ``--batches`` independent batches of equal size, and keeps for every layer i the
batch sums of ``W_(i,1)``, ``W_(i,i)`` and their squares (the two lattice directions
have the same law).  Error bars come from the scatter of the batch estimates
(independent samples: no autocorrelation to correct for).  Writes one JSON file
(``--out``), each N recorded as it finishes (atomic), so a killed run keeps the
finished sizes; ``benchmarks/edge_check.py`` compares them with the derived edge law.

Usage::

    nice -n 10 python benchmarks/edge_sampled.py --N 200 500 1000 2000 --samples 8000 1600 800 320 \
        --out /tmp/edge_sampled.json       # raw batch sums (megabytes); edge_check.py keeps a summary
"""

from __future__ import annotations

import argparse
import json
import os
import time

import numpy as np

from forcenet.numeric.triangle.exact_sampler import ExactSampler


def lattice_batches(N: int, samples: int, batches: int, seed: int) -> dict:
    """Per batch: sums of ``W_(i,1)``, ``W_(i,i)`` and of their squares over its samples, ``i = 1..N``."""
    sampler = ExactSampler(N, seed=seed)
    size = samples // batches
    rows = np.arange(N)
    out = {"size": size, "sum_left": [], "sum_right": [], "sq_left": [], "sq_right": []}
    for _ in range(batches):
        sums = sampler.moment_sums(size, orders=(1,))[1]
        first, second = sums
        out["sum_left"].append(first[rows, 0].tolist())
        out["sum_right"].append(first[rows, rows].tolist())
        out["sq_left"].append(second[rows, 0].tolist())
        out["sq_right"].append(second[rows, rows].tolist())
    return out


def summary(record: dict, i: int) -> dict:
    """Mean and sd of ``W_(i,1)`` (both lattice directions pooled) with batch-scatter error bars.

    The variance is the mean of the batches' unbiased variances (so no small-batch bias
    of a sample sd), the sd its square root, its error from the batches' scatter.
    """
    n = record["size"]
    means, variances = [], []
    for side in ("left", "right"):
        s = np.array(record[f"sum_{side}"])[:, i - 1]
        q = np.array(record[f"sq_{side}"])[:, i - 1]
        m = s / n
        means.append(m)
        variances.append((q - n * m * m) / (n - 1))
    mean_b = (means[0] + means[1]) / 2  # per batch
    var_b = (variances[0] + variances[1]) / 2
    B = len(mean_b)
    var, var_err = float(var_b.mean()), float(var_b.std(ddof=1) / np.sqrt(B))
    sd = float(np.sqrt(var))
    return {"mean": float(mean_b.mean()), "mean_err": float(mean_b.std(ddof=1) / np.sqrt(B)),
            "sd": sd, "sd_err": var_err / (2 * sd),
            "configurations": n * B, "loads": 2 * n * B}


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--N", type=int, nargs="+", required=True)
    parser.add_argument("--samples", type=int, nargs="+", required=True)
    parser.add_argument("--batches", type=int, default=16)
    parser.add_argument("--seed", type=int, default=4343)
    parser.add_argument("--out", required=True)
    args = parser.parse_args(argv)
    if len(args.samples) != len(args.N):
        parser.error("--samples needs one count per --N")
    data = {}
    if os.path.exists(args.out):
        with open(args.out) as handle:
            data = json.load(handle)
    for N, K in zip(args.N, args.samples):
        if str(N) in data:
            print(f"N={N}: recorded already", flush=True)
            continue
        start = time.time()
        record = lattice_batches(N, K, args.batches, args.seed + N)
        record["seconds"] = time.time() - start
        data[str(N)] = record
        tmp = args.out + ".tmp"
        with open(tmp, "w") as handle:
            json.dump(data, handle)
        os.replace(tmp, args.out)
        cells = []
        for z in (0.25, 0.5, 0.75):
            r = summary(record, round(z * N))
            cells.append(f"z={z}: {r['mean']:.6f}±{r['mean_err']:.6f} sd {r['sd']:.6f}±{r['sd_err']:.6f}")
        print(f"N={N} ({record['seconds']:.0f} s): " + "; ".join(cells), flush=True)


if __name__ == "__main__":
    main()
