"""Refit of the finite-size corrections of the response on exact tables to N = 64 (issue 18).

``notes/scaling_limit.md`` asks whether the correction on the lattice
directions is ``N^-1``, ``N^-2/3`` or a mix.  With the Pfaffian route the exact
tables reach far beyond the order-ideal DP's N = 28; this script reads them
(``out/mean_W_N{N}.json``, written by ``forcenet table --method pfaffian --N N
--format json --out ...`` or ``benchmarks/pfaffian_table.py table --save out``;
missing small ones are computed), and

* fits the deviation from the limit ``delta(N) = exact - limit`` on the lattice
  direction (``z = 1/4, 1/2, 3/4``, N a multiple of 4 so that ``z N`` is a row)
  and in the bulk with three models, least squares in ``log |delta|`` for the
  power law and relative least squares for the two-term laws:

  - ``A N^-alpha`` (free exponent),
  - ``a N^-1 + b N^-2`` (analytic corrections),
  - ``a N^-2/3 + b N^-1`` (an edge term plus an analytic one), and with ``+ c N^-4/3``,
  - ``a N^-1/2 + b N^-1``;

* prints the local exponents ``-d log|delta| / d log N`` between neighbours;
* extrapolates each fit to the exact-sampler values of ``notes/scaling_limit.md``
  Sec. 3 (N = 100 ... 1000), which none of the fits saw;
* draws ``notes/figures/scaling_refit.png``.

Usage::

    python benchmarks/scaling_refit.py --N 8 12 16 20 24 28 32 40 48 56 64 --dir out
"""

from __future__ import annotations

import argparse
import json
import os
from fractions import Fraction

import numpy as np

from forcenet.numeric.limit_shape.surface import bulk_response, lattice_response

# exact-sampler deviations from the limit, notes/scaling_limit.md Sec. 3 (seed 2026): N -> (delta, stderr)
SAMPLED = {
    0.5: {50: (0.0302, 0.0003), 100: (0.0174, 0.0003), 200: (0.0106, 0.0003), 500: (0.0057, 0.0003), 1000: (0.0028, 0.0003)},
    0.75: {50: (0.0123, 0.0001), 100: (0.0071, 0.0001), 200: (0.0042, 0.0001), 500: (0.0021, 0.0001), 1000: (0.0012, 0.0001)},
}


def load_table(N: int, directory: str):
    path = os.path.join(directory, f"mean_W_N{N}.json")
    if not os.path.exists(path):
        if N > 40:
            raise SystemExit(f"{path} is missing: run forcenet table --method pfaffian --N {N} --format json --out {path} --force")
        from forcenet.exact.triangle.pfaffian.route import mean_W
        from forcenet.exact.triangle.tables import exact_table, to_json, write_atomic

        write_atomic(path, to_json(exact_table(N, mean_table=mean_W(N))) + "\n")
    with open(path) as handle:
        data = json.load(handle)
    return [[float(Fraction(x)) for x in row] for row in data["mean_W"]]


MODELS = {
    "A N^-alpha": None,
    "a/N + b/N^2": (1.0, 2.0),
    "a/N^(2/3) + b/N": (2.0 / 3.0, 1.0),
    "a/N^(2/3) + b/N + c/N^(4/3)": (2.0 / 3.0, 1.0, 4.0 / 3.0),
    "a/N^(1/2) + b/N": (0.5, 1.0),
}


def fit(model, Ns, devs):
    """Parameters and relative RMS residual of one model."""
    Ns, devs = np.asarray(Ns, float), np.asarray(devs, float)
    if MODELS[model] is None:
        slope, intercept = np.polyfit(np.log(Ns), np.log(np.abs(devs)), 1)
        params = (float(np.sign(devs[-1]) * np.exp(intercept)), float(-slope))
        pred = params[0] * Ns ** -params[1]
    else:
        X = np.stack([Ns**-e for e in MODELS[model]], axis=1) / np.abs(devs)[:, None]
        coef, *_ = np.linalg.lstsq(X, devs / np.abs(devs), rcond=None)
        params = tuple(float(c) for c in coef)
        pred = sum(c * Ns**-e for c, e in zip(coef, MODELS[model]))
    return params, float(np.sqrt(np.mean(((pred - devs) / devs) ** 2)))


def predict(model, params, N):
    if MODELS[model] is None:
        return params[0] * N ** -params[1]
    return sum(c * N**-e for c, e in zip(params, MODELS[model]))


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--N", type=int, nargs="+", default=[8, 12, 16, 20, 24, 28, 32, 40, 48, 56, 64])
    parser.add_argument("--dir", default="out")
    parser.add_argument("--fit-from", type=int, default=16, help="smallest N used in the fits")
    parser.add_argument("--figures", default="notes/figures")
    args = parser.parse_args(argv)
    Ns = sorted(N for N in args.N if N % 4 == 0)
    tables = {N: load_table(N, args.dir) for N in Ns}

    def edge(z):
        return lambda N: (tables[N][round(z * N) - 1][0], float(lattice_response(round(z * N) / N)))

    def bulk(z):
        def probe(N):
            i = round(z * N)
            j = i // 2 + 1 if i % 2 else i // 2  # x = (2j - i - 1)/N = 0 or -1/N
            x = (2 * j - i - 1) / N
            return N * tables[N][i - 1][j - 1], float(bulk_response(x, i / N))

        return probe

    probes = [("edge z=1/4", edge(0.25), None), ("edge z=1/2", edge(0.5), 0.5), ("edge z=3/4", edge(0.75), 0.75),
              ("bulk z=1/2, x~0 (N<W>)", bulk(0.5), None), ("bulk z=3/4, x~0 (N<W>)", bulk(0.75), None)]
    fitted = {}
    print("| probe | limit | " + " | ".join(f"N={N}" for N in Ns) + " |")
    print("|" + " --- |" * (len(Ns) + 2))
    for name, probe, _ in probes:
        values = [probe(N) for N in Ns]
        devs = [ex - lim for ex, lim in values]
        fitted[name] = devs
        print(f"| {name} | {values[-1][1]:.5f} | " + " | ".join(f"{d:+.5f}" for d in devs) + " |")
    print("\nlocal exponents -dlog|delta|/dlogN between neighbouring N:")
    for name, devs in fitted.items():
        loc = [-np.log(abs(devs[k + 1] / devs[k])) / np.log(Ns[k + 1] / Ns[k]) for k in range(len(Ns) - 1)]
        print(f"  {name}: " + ", ".join(f"{Ns[k]}-{Ns[k + 1]}: {v:.2f}" for k, v in enumerate(loc)))
    use = [N for N in Ns if N >= args.fit_from]
    print(f"\nfits over N = {use[0]}..{use[-1]} (relative RMS residual), and the fit's prediction of the sampled deviations:")
    print("| probe | model | parameters | rel. RMS | " + " | ".join(f"N={N} sampled" for N in SAMPLED[0.5]) + " |")
    print("|" + " --- |" * (4 + len(SAMPLED[0.5])))
    results = {}
    for name, _, z in probes:
        devs = [fitted[name][Ns.index(N)] for N in use]
        for model in MODELS:
            params, rms = fit(model, use, devs)
            results[(name, model)] = params
            cells = ""
            if z is not None:
                cells = " | ".join(f"{predict(model, params, N):.4f} vs {d:.4f}±{e:.4f}" for N, (d, e) in SAMPLED[z].items())
            else:
                cells = " | ".join("-" for _ in SAMPLED[0.5])
            print(f"| {name} | {model} | " + ", ".join(f"{p:.4g}" for p in params) + f" | {rms:.2e} | {cells} |")

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    os.makedirs(args.figures, exist_ok=True)
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.5))
    grid = np.geomspace(use[0], 1200, 200)
    for ax, (name, z) in zip(axes, (("edge z=1/2", 0.5), ("edge z=3/4", 0.75))):
        ax.loglog(Ns, np.abs(fitted[name]), "ko", ms=4, label="exact tables (Pfaffian route)")
        sN = list(SAMPLED[z])
        ax.errorbar(sN, [SAMPLED[z][N][0] for N in sN], yerr=[SAMPLED[z][N][1] for N in sN], fmt="s", color="C3",
                    ms=4, label="exact sampler (not fitted)")
        for k, model in enumerate(MODELS):
            ax.loglog(grid, [abs(predict(model, results[(name, model)], N)) for N in grid], f"C{k}-", lw=1, label=f"fit {model}")
        ax.set_title(f"lattice direction, z = {z}: <W_(i,1)> - limit")
        ax.set_xlabel("N")
        ax.legend(fontsize=7)
    fig.tight_layout()
    path = os.path.join(args.figures, "scaling_refit.png")
    fig.savefig(path, dpi=110)
    print(f"\nfigure: {path}")


if __name__ == "__main__":
    main()
