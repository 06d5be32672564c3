"""The variance of the force carried by the first j grains of a layer, exactly, to N = 80-100 (issue 27).

``S_ij = W_i1 + ... + W_ij`` is an order statistic of rank ``T`` among ``d``
uniforms, so ``Var S = Var T/(d+1)^2 + E[T (d+1-T)]/((d+1)^2 (d+2))``: the
tableau part and the Dirichlet noise (notes/fluctuations.md Sec. 1; the
lattice directions' analogue is Sec. 2).  ``partial_sum_moments`` gives both
exactly for about the price of the mean table.  For each N this prints, at
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

from forcenet.exact.triangle.pfaffian.partial_sums import partial_sum_moments

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
        rows.append({"z": str(z), "x": str(x), "i": i, "j": j, "mean": float(first),
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


def figure(data: dict, path: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    runs = sorted(data.values(), key=lambda r: r["N"])
    Ns = [r["N"] for r in runs]
    fig, ax = plt.subplots(figsize=(6, 4.2))
    for k, (z, x) in enumerate((z, x) for z in DEPTHS for x in ACROSS):
        sd = [r["probes"][k]["tableau_sd"] for r in runs]
        ax.loglog(Ns, sd, "o-", ms=3, label=f"z = {z}, x = {x}")
    ax.loglog(Ns, [0.5 * N ** -0.75 for N in Ns], "k:", label="N^(-3/4)")
    ax.loglog(Ns, [0.5 * N ** -1.0 for N in Ns], "k--", label="N^(-1)")
    ax.set_xlabel("N")
    ax.set_ylabel("sd(T)/(d+1): the tableau part of sd(S_ij)")
    ax.legend(fontsize=7)
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
    if args.figure:
        figure(data, args.figure)


if __name__ == "__main__":
    main()
