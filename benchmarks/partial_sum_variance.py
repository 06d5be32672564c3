"""The variance of the force carried by the first j grains of a layer, exactly, to N = 80-100 (issue 27).

``S_ij = W_i1 + ... + W_ij`` is an order statistic of rank ``T`` among ``d``
uniforms, so ``Var S = Var T/(d+1)^2 + E[T (d+1-T)]/((d+1)^2 (d+2))``: the
tableau part and the Dirichlet noise (notes/fluctuations.md Sec. 1; the
lattice directions' analogue is Sec. 2).  ``partial_sum_moments`` gives both
exactly for about the price of the mean table.  ``Var S/<W>^2``, with ``<W>``
the mean load around ``S_ij``, is the variance of the number of partial sums
below a point; a beta-ensemble's bulk makes it grow like ``ln N/(beta pi^2)``.
For each N this prints, at
depths ``z = i/N`` and across the layer at ``x = j/i``, ``sd(T)/(d+1)`` (the
tableau part) and the whole ``Var S``, and the local exponents of the tableau
part between neighbouring N.  Results accumulate in a JSON file (atomic
rewrite; floats correctly rounded from the exact values).

Usage::

    python benchmarks/partial_sum_variance.py --N 16 32 48 64 80 96 --out partial_sum_variance.json --checkpoint ckpt
    python benchmarks/partial_sum_variance.py --out partial_sum_variance.json --figure partial_sum_variance.png
"""

from __future__ import annotations

import argparse
import json
import math
import os
import tempfile
import time
from fractions import Fraction

from forcenet.exact.triangle.free_fermion.partial_sums import partial_sum_moments

DEPTHS = (Fraction(1, 4), Fraction(1, 2), Fraction(3, 4), Fraction(1))
ACROSS = (Fraction(1, 4), Fraction(1, 2))


def probes(N: int) -> list[tuple[Fraction, Fraction, int, int]]:
    """``(z, x, i, j)``: the grain at depth ``i = z N`` and position ``j = x i`` (``N`` a multiple of 16: exact)."""
    if N % 16:
        raise SystemExit(f"--N {N}: the probes need N a multiple of 16 (i = N/4, j = i/4 exactly)")
    return [(z, x, int(z * N), int(x * z * N)) for z in DEPTHS for x in ACROSS]


def record(N: int, checkpoint: str | None) -> dict:
    """Exact moments of the probed partial sums at ``N``, as correctly rounded floats."""
    t0 = time.perf_counter()
    moments = partial_sum_moments(N, checkpoint=checkpoint)
    d = N * (N - 1) // 2
    rows = []
    for z, x, i, j in probes(N):
        first, second = moments[1][i - 1][j - 1], moments[2][i - 1][j - 1]
        ET = (d + 1) * first
        ET2 = (d + 1) * (d + 2) * second - ET
        tableau = (ET2 - ET * ET) / (d + 1) ** 2  # Var T / (d+1)^2
        noise = (ET * (d + 1) - ET2) / ((d + 1) ** 2 * (d + 2))
        assert tableau + noise == second - first * first
        spacing = (moments[1][i - 1][j] - (moments[1][i - 1][j - 2] if j > 1 else 0)) / 2  # <W> around S_ij
        rows.append({"z": str(z), "x": str(x), "i": i, "j": j, "mean": float(first), "spacing": float(spacing),
                     "count_var": float((second - first * first) / spacing**2),
                     "var": float(second - first * first), "tableau_sd": math.sqrt(tableau),
                     "noise_var": float(noise)})
    return {"N": N, "seconds": round(time.perf_counter() - t0, 1), "probes": rows}


def write_atomically(path: str, data: dict) -> None:
    folder = os.path.dirname(os.path.abspath(path))
    handle, temporary = tempfile.mkstemp(dir=folder, prefix=".partial_sum_variance.")
    with os.fdopen(handle, "w") as stream:
        json.dump(data, stream, indent=1, sort_keys=True)
    os.replace(temporary, path)


def report(data: dict) -> None:
    runs = sorted(data.values(), key=lambda r: r["N"])
    print("| N | " + " | ".join(f"z={z}, x={x}" for z in DEPTHS for x in ACROSS) + " |")
    print("| --- |" + " --- |" * (len(DEPTHS) * len(ACROSS)))
    for run in runs:
        cells = [f"{r['tableau_sd']:.5f} / {r['var']:.3e}" for r in run["probes"]]
        print(f"| {run['N']} | " + " | ".join(cells) + " |")
    print("\nlocal exponents of the tableau part, -dlog sd(T)/(d+1) / dlog N:")
    for k, (z, x) in enumerate((z, x) for z in DEPTHS for x in ACROSS):
        pairs = []
        for a, b in zip(runs, runs[1:]):
            sa, sb = a["probes"][k]["tableau_sd"], b["probes"][k]["tableau_sd"]
            pairs.append(f"{a['N']}-{b['N']}: {-math.log(sb / sa) / math.log(b['N'] / a['N']):.3f}")
        print(f"  z={z}, x={x}: " + ", ".join(pairs))


def report_log_correlated(data: dict) -> None:
    """``Var S / <W>^2`` (the variance of the number of partial sums below a point) against ``ln N``."""
    runs = sorted(data.values(), key=lambda r: r["N"])
    print("\nVar S_ij / <W>^2 (<W> the mean load around S_ij), and its slope per ln N "
          f"(a beta-ensemble's bulk: 1/(beta pi^2); beta = 2: {1 / (2 * math.pi**2):.4f}, beta = 1: "
          f"{1 / math.pi**2:.4f}):")
    for k, (z, x) in enumerate((z, x) for z in DEPTHS for x in ACROSS):
        values = [(r["N"], r["probes"][k]["count_var"]) for r in runs]
        slopes = [f"{a[0]}-{b[0]}: {(b[1] - a[1]) / math.log(b[0] / a[0]):.4f}" for a, b in zip(values, values[1:])]
        print(f"  z={z}, x={x}: " + ", ".join(f"{v:.4f}" for _, v in values) + "; slopes " + ", ".join(slopes))


def figure(data: dict, path: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    runs = sorted(data.values(), key=lambda r: r["N"])
    Ns = [r["N"] for r in runs]
    logs = [math.log(N) for N in Ns]
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.2))
    for k, (z, x) in enumerate((z, x) for z in DEPTHS for x in ACROSS):
        label = f"z = {z}, x = {x}"
        left.loglog(Ns, [r["probes"][k]["tableau_sd"] for r in runs], "o-", ms=3, label=label)
        right.plot(logs, [r["probes"][k]["count_var"] for r in runs], "o-", ms=3, label=label)
    left.loglog(Ns, [0.6 * N**-1.0 * math.sqrt(math.log(N)) for N in Ns], "k--", label="sqrt(ln N)/N")
    left.set_xlabel("N")
    left.set_ylabel("sd(T)/(d+1): the tableau part of sd(S_ij)")
    for beta, style in ((1, "k--"), (2, "k:")):
        top = runs[-1]["probes"][-1 if beta == 1 else 3]["count_var"]
        right.plot(logs, [top + (u - logs[-1]) / (beta * math.pi**2) for u in logs], style,
                   label=f"slope 1/({beta} pi^2)")
    right.set_xlabel("ln N")
    right.set_ylabel("Var S_ij / <W>^2")
    right.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=130)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--N", type=int, nargs="*", default=[])
    parser.add_argument("--out", required=True)
    parser.add_argument("--checkpoint")
    parser.add_argument("--figure")
    args = parser.parse_args()
    if args.figure:  # check the destination before any work
        open(args.figure, "ab").close()
    data = json.load(open(args.out)) if os.path.exists(args.out) else {}
    for N in args.N:
        data[str(N)] = record(N, args.checkpoint)
        write_atomically(args.out, data)
        print(f"N={N}: {data[str(N)]['seconds']} s", flush=True)
    report(data)
    report_log_correlated(data)
    if args.figure:
        figure(data, args.figure)


if __name__ == "__main__":
    main()
