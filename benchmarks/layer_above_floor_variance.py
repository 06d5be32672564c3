"""The variance of every load of layer N - 1, exactly, against N: the cover identity for the price of the mean (issue 43).

Each floor partial sum is uniform between its two covers in layer ``N - 1``,
so ``<W_(N-1,j)^2>`` comes from three single-cell second moments
(notes/fluctuations.md Sec. 3.1; ``covers.cover_row_moments``), which the
mean's Pfaffian evaluations give (``partial_sums.partial_sum_moments``).
For each N this records ``<W>`` and ``<W^2>`` of every load of layer
``N - 1`` (floats correctly rounded from the exact values; the exact sum
``sum_j <W^2> = 3/(2N - 1)`` checked), with the run's wall and CPU seconds,
and prints ``Var W/<W>^2`` at ``x = j/(N - 1) = 1/2`` and ``1/4`` and
``N^2 Var W`` at the centre.  The figure: ``Var W/<W>^2`` at the centre and
at ``x = 1/4`` against ``1/N`` (with the GOE and GUE spacing variances, the
floor's and the bulk's limits), and the profile ``N^2 Var W_(N-1,j)``
against ``x`` for every N.

Usage::

    python benchmarks/layer_above_floor_variance.py --N 8 12 16 20 24 28 32 40 48 56 --out layer_above_floor_variance.json --checkpoint ckpt
    python benchmarks/layer_above_floor_variance.py --out layer_above_floor_variance.json --figure layer_above_floor_variance.png
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import tempfile
import time
from fractions import Fraction

from forcenet.exact.triangle.free_fermion.covers import cover_row_moments

GOE, GUE = 0.2855, 0.1800  # Var s of the unfolded spacing (notes/force_distribution.md Sec. 6.8)


def cpu_seconds() -> float:
    """CPU seconds of this process and its finished children (the worker processes)."""
    own, children = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + children.ru_utime + children.ru_stime


def record(N: int, checkpoint: str | None) -> dict:
    """Layer ``N - 1``'s exact ``<W>``, ``<W^2>`` (as correctly rounded floats) and the run's seconds."""
    wall, cpu = time.perf_counter(), cpu_seconds()
    rows = cover_row_moments(N, N - 1, checkpoint=checkpoint)
    wall, cpu = time.perf_counter() - wall, cpu_seconds() - cpu
    if sum(rows[2]) != Fraction(3, 2 * N - 1) or sum(rows[1]) != 1:  # notes/force_distribution.md Sec. 6.2
        raise ArithmeticError(f"N={N}: layer N - 1 breaks sum <W> = 1 or sum <W^2> = 3/(2N - 1)")
    relative = [m2 / m1**2 - 1 for m1, m2 in zip(rows[1], rows[2])]
    return {"mean_W": [float(x) for x in rows[1]], "mean_W2": [float(x) for x in rows[2]],
            "relative_variance": [float(x) for x in relative], "wall_seconds": round(wall, 1),
            "cpu_seconds": round(cpu, 1)}


def at(values: list[float], x: float) -> float:
    """The value at ``j/(N - 1) = x`` (the mean of the two neighbours when it falls between loads)."""
    position = x * (len(values) + 1) - 1  # load j sits at x = j/(N - 1), 0-based index j - 1
    low = int(position)
    return values[low] if position == low else (values[low] + values[low + 1]) / 2


def write_json(path: str, data: dict) -> None:
    directory = os.path.dirname(os.path.abspath(path))
    fd, tmp = tempfile.mkstemp(dir=directory, prefix=".tmp-")
    with os.fdopen(fd, "w") as handle:
        json.dump(data, handle, indent=1, sort_keys=True)
    os.replace(tmp, path)


def figure(data: dict, path: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    Ns = sorted(int(N) for N in data)
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.2))
    for x, marker in ((0.5, "o"), (0.25, "s")):
        left.plot([1 / N for N in Ns], [at(data[str(N)]["relative_variance"], x) for N in Ns], marker + "-",
                  label=f"layer N-1, j = {x} N")
    left.axhline(GOE, color="k", ls="--", lw=0.8, label="GOE spacing (the floor's limit)")
    left.axhline(GUE, color="k", ls=":", lw=0.8, label="GUE spacing (the bulk's limit)")
    left.set_xlabel("1/N")
    left.set_ylabel("Var W / <W>^2")
    left.set_xlim(left=0)
    left.legend(fontsize=8, loc="center right")
    left.set_title("layer N-1: the relative variance, exact")
    for N in Ns:
        values = data[str(N)]
        variance = [N * N * (m2 - m1 * m1) for m1, m2 in zip(values["mean_W"], values["mean_W2"])]
        right.plot([(j - 0.5) / (N - 1) for j in range(1, N)], variance, lw=1, label=f"N = {N}")
    right.set_xlabel("x = (j - 1/2)/(N - 1)")
    right.set_ylabel("N^2 Var W_(N-1,j)")
    right.legend(fontsize=7, ncol=2)
    right.set_title("the profile across the layer")
    fig.tight_layout()
    fig.savefig(path, dpi=120)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--N", type=int, nargs="*", default=[])
    parser.add_argument("--out", required=True, help="JSON file the results accumulate in")
    parser.add_argument("--checkpoint", help="checkpoint directory of the partial sums' primes")
    parser.add_argument("--figure", help="write the figure (PNG) from the JSON file")
    args = parser.parse_args()
    data = json.load(open(args.out)) if os.path.exists(args.out) else {}
    for N in args.N:
        data[str(N)] = record(N, args.checkpoint)
        write_json(args.out, data)
        print(f"N = {N}: {data[str(N)]['wall_seconds']} s wall, {data[str(N)]['cpu_seconds']} s CPU", flush=True)
    print("| N | Var W/<W>^2, j = N/2 | j = N/4 | N^2 Var W, j = N/2 | wall s | CPU s |")
    print("| --- | --- | --- | --- | --- | --- |")
    for N in sorted(int(k) for k in data):
        v = data[str(N)]
        centre = N * N * (at(v["mean_W2"], 0.5) - at(v["mean_W"], 0.5) ** 2)
        print(f"| {N} | {at(v['relative_variance'], 0.5):.4f} | {at(v['relative_variance'], 0.25):.4f} | "
              f"{centre:.4f} | {v['wall_seconds']} | {v['cpu_seconds']} |")
    if args.figure:
        figure(data, args.figure)


if __name__ == "__main__":
    main()
