"""The derived edge law of the lattice directions against exact and sampled data (issue 43, item 3).

Derived (``notes/scaling_limit.md`` Sec. 5): ``<W_(i,1)> = e(z) + a(z) N^(-2/3) + O(1/N)`` and
``sd(W_(i,1)) = s(z) N^(-2/3) (1 + o(1))`` with ``a = |E chi| c(z)``, ``s = sd(chi) c(z)``,
``c = (1 - z)^(4/3) / (2^(4/3) (z (2 - z))^(1/6))``, ``chi`` Tracy-Widom GUE
(``forcenet.numeric.limit_shape.edge``).  This script

* takes the exact lattice columns N = 32..160 from the digest
  (``notes/data/lattice_columns.json``), fixes ``a(z)`` and fits the next orders
  ``N^-1, N^-4/3, N^-5/3, N^-2`` (relative least squares), prints the residuals, the
  prediction of N = 136..160 from the fit on N <= 128, and the free fits of the
  amplitude that bracket ``a(z)``;
* compares the exact-sampler means and standard deviations at N = 200..2000
  (``benchmarks/edge_sampled.py``; summary kept in ``notes/data/edge_sampled.json``)
  with the law continued from the exact fit (in standard errors);
* does the same for the standard deviation with the exact second moments of the
  lattice directions (``benchmarks/lattice_fluctuations.py``, N = 16..64; summary in
  ``notes/data/edge_exact_sd.json``);
* draws ``notes/figures/edge_law.png``: ``N^(2/3) (<W> - e)`` and ``N^(2/3) sd`` against
  ``N^(-1/3)``, whose intercepts are the derived amplitudes.

Usage::

    python benchmarks/edge_check.py --sampled /tmp/edge_sampled.json --exact-sd /tmp/lattice_fluctuations.json \
        --figures notes/figures      # refresh the two summaries from raw runs (several --sampled files pool), then check
    python benchmarks/edge_check.py --figures /tmp/fig   # from the summaries in notes/data alone
"""

from __future__ import annotations

import argparse
import json
import os
from fractions import Fraction

import mpmath
import numpy as np

from forcenet.exact.triangle.tables import fraction_from_text
from forcenet.numeric.limit_shape.edge import edge_amplitude, edge_sd_amplitude
from forcenet.numeric.limit_shape.surface import lattice_response

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(HERE, "..", "notes", "data")
DIGEST = os.path.join(DATA, "lattice_columns.json")
SAMPLED = os.path.join(DATA, "edge_sampled.json")
EXACT_SD = os.path.join(DATA, "edge_exact_sd.json")
DEPTHS = (Fraction(1, 4), Fraction(1, 2), Fraction(3, 4))
NEXT = (-1.0, -4 / 3, -5 / 3, -2.0)  # the orders fitted beyond the derived N^(-2/3)


def limit(i: int, N: int) -> float:
    return float(lattice_response(Fraction(i, N), dps=30))


def exact_deviations(z: Fraction) -> tuple[np.ndarray, np.ndarray]:
    """``N`` and ``<W_(zN,1)> - e(z)`` from the digest (25 digits; the difference in mpmath)."""
    with open(DIGEST) as handle:
        columns = json.load(handle)["columns"]
    Ns = sorted(int(n) for n in columns)
    devs = []
    for N in Ns:
        i = int(z * N)
        with mpmath.workdps(40):
            devs.append(float(mpmath.mpf(columns[str(N)]["W_i1"][i - 1]) - lattice_response(Fraction(i, N), dps=35)))
    return np.array(Ns, dtype=float), np.array(devs)


def fixed_fit(Ns, devs, amplitude, k, rows=None):
    """Relative least squares of ``devs - amplitude N^(-2/3)`` on the first ``k`` orders of NEXT."""
    rows = np.ones(len(Ns), bool) if rows is None else rows
    rest = devs - amplitude * Ns ** (-2 / 3)
    A = np.array([Ns**p for p in NEXT[:k]]).T
    coef = np.linalg.lstsq(A[rows] / devs[rows, None], rest[rows] / devs[rows], rcond=None)[0]
    return coef, amplitude * Ns ** (-2 / 3) + A @ coef


def law(N, amplitude, coef):
    return amplitude * N ** (-2 / 3) + sum(c * N**p for c, p in zip(coef, NEXT))


def free_amplitude(Ns, devs, k, lo):
    rows = Ns >= lo
    A = np.array([Ns**p for p in (-2 / 3,) + NEXT[: k - 1]]).T
    return np.linalg.lstsq(A[rows] / devs[rows, None], np.ones(rows.sum()), rcond=None)[0][0]


def summarize_sampled(raw_paths: list[str]) -> dict:
    """Mean and sd (both lattice directions pooled) with batch-scatter errors, for z = 1/4, 1/2, 3/4.

    Several raw files (independent seeds) pool their batches for the same N (same batch size).
    """
    from edge_sampled import summary

    raw: dict = {}
    for path in raw_paths:
        with open(path) as handle:
            for n_text, record in json.load(handle).items():
                if n_text not in raw:
                    raw[n_text] = record
                    continue
                if record["size"] != raw[n_text]["size"]:
                    raise SystemExit(f"N={n_text}: batches of {record['size']} and {raw[n_text]['size']} do not pool")
                for key in ("sum_left", "sum_right", "sq_left", "sq_right"):
                    raw[n_text][key] = raw[n_text][key] + record[key]
                raw[n_text]["seconds"] += record["seconds"]
    out = {}
    for n_text, record in raw.items():
        N = int(n_text)
        out[n_text] = {"seconds": record["seconds"]}
        for z in DEPTHS:
            out[n_text][str(z)] = summary(record, int(z * N))
    return out


def summarize_exact_sd(raw_path: str) -> dict:
    """``<W>`` and ``sd(W)`` of ``W_(zN,1)`` to 20 digits from the exact moments (fractions)."""
    with open(raw_path) as handle:
        raw = json.load(handle)
    out = {}
    for n_text, record in raw.items():
        N = int(n_text)
        out[n_text] = {}
        for z in DEPTHS:
            if (z * N).denominator != 1:
                continue
            m1, m2 = (fraction_from_text(x) for x in record["moments"][str(int(z * N))][:2])
            with mpmath.workdps(30):
                var = mpmath.mpf((m2 - m1 * m1).numerator) / (m2 - m1 * m1).denominator
                out[n_text][str(z)] = {"mean": mpmath.nstr(mpmath.mpf(m1.numerator) / m1.denominator, 20),
                                       "sd": mpmath.nstr(mpmath.sqrt(var), 20)}
    return out


def write_json(path: str, data: dict) -> None:
    tmp = path + ".tmp"
    with open(tmp, "w") as handle:
        json.dump(data, handle, indent=1, sort_keys=True)
        handle.write("\n")
    os.replace(tmp, path)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sampled", nargs="*", default=None,
                        help="raw outputs of edge_sampled.py, independent seeds pooled (refreshes the summary)")
    parser.add_argument("--exact-sd", default=None, help="raw output of lattice_fluctuations.py (refreshes the summary)")
    parser.add_argument("--figures", default="notes/figures")
    parser.add_argument("--fit-until", type=int, default=128, help="largest N of the out-of-sample fit")
    args = parser.parse_args(argv)
    if args.sampled:
        write_json(SAMPLED, summarize_sampled(args.sampled))
    if args.exact_sd:
        write_json(EXACT_SD, summarize_exact_sd(args.exact_sd))
    sampled = json.load(open(SAMPLED)) if os.path.exists(SAMPLED) else {}
    exact_sd = json.load(open(EXACT_SD)) if os.path.exists(EXACT_SD) else {}

    curves = {}
    print("## the mean: derived amplitude fixed, next orders fitted on the exact columns\n")
    print("| z | a(z) derived | orders fitted | rel. RMS | max rel. | N = 136..160 predicted from N <= "
          f"{args.fit_until} (max rel.) |")
    print("| --- | --- | --- | --- | --- | --- |")
    for z in DEPTHS:
        Ns, devs = exact_deviations(z)
        a = float(edge_amplitude(z, dps=15))
        for k in (1, 2, 3, 4):
            coef, fitted = fixed_fit(Ns, devs, a, k)
            rel = (fitted - devs) / devs
            _, ahead = fixed_fit(Ns, devs, a, k, Ns <= args.fit_until)
            miss = np.abs((ahead - devs) / devs)[Ns > args.fit_until]
            print(f"| {z} | {a:.6f} | {k} | {np.sqrt(np.mean(rel**2)):.1e} | {np.abs(rel).max():.1e} | {miss.max():.1e} |")
        curves[z] = (Ns, devs, a, fixed_fit(Ns, devs, a, 4)[0])
        print("|  | amplitudes of N^-1, N^-4/3, N^-5/3, N^-2: " + ", ".join(f"{c:.4f}" for c in curves[z][3]) + " | | | | |")

    print("\n## free fits of the amplitude (a N^-2/3 + k-1 further orders), ratio to the derived a(z)\n")
    print("| z | fit from | 4 terms | 5 terms |")
    print("| --- | --- | --- | --- |")
    for z in DEPTHS:
        Ns, devs, a, _ = curves[z]
        for lo in (32, 48, 64):
            print(f"| {z} | {lo} | {free_amplitude(Ns, devs, 4, lo) / a:.4f} | {free_amplitude(Ns, devs, 5, lo) / a:.4f} |")

    if sampled:
        Nsamp = sorted(int(n) for n in sampled)
        print("\n## sampled means against the law fitted on the exact columns (not fitted: standard errors)\n")
        print("| z | " + " | ".join(f"N = {N}" for N in Nsamp) + " |")
        print("| --- |" + " --- |" * len(Nsamp))
        for z in DEPTHS:
            Ns, devs, a, coef = curves[z]
            cells = []
            for N in Nsamp:
                r = sampled[str(N)][str(z)]
                dev = r["mean"] - limit(int(z * N), N)
                cells.append(f"{dev:.6f} ± {r['mean_err']:.6f} ({(dev - law(N, a, coef)) / r['mean_err']:+.1f})")
            print(f"| {z} | " + " | ".join(cells) + " |")

    print("\n## the standard deviation: N^(2/3) sd against the derived sd(chi) c(z)\n")
    sd_rows = {}
    for z in DEPTHS:
        s = float(edge_sd_amplitude(z, dps=15))
        pts = []
        for n_text, rec in sorted(exact_sd.items(), key=lambda t: int(t[0])):
            if str(z) in rec:
                pts.append((int(n_text), float(rec[str(z)]["sd"]), 0.0, "exact"))
        for n_text, rec in sorted(sampled.items(), key=lambda t: int(t[0])):
            pts.append((int(n_text), rec[str(z)]["sd"], rec[str(z)]["sd_err"], "sampled"))
        sd_rows[z] = (s, pts, None)
        # N^(2/3) sd = s + b t + c t^2 (+ d t^3), t = N^(-1/3), on N >= 32: the sampled points with their
        # errors, the exact ones with a floor of 1e-3 relative (the size of the orders left out); s free or fixed
        print(f"z = {z}: s(z) = {s:.6f}; N^(2/3) sd / s(z): "
              + ", ".join(f"{N}: {v * N ** (2 / 3) / s:.4f}" + (f" ± {err * N ** (2 / 3) / s:.4f}" if err else "")
                          for N, v, err, _ in pts))
        use = [(N, v, err) for N, v, err, _ in pts if N >= 32]
        if len(use) >= 5:
            Na = np.array([p[0] for p in use], float)
            t, y = Na ** (-1 / 3), np.array([p[1] for p in use]) * Na ** (2 / 3)
            e = np.array([max(err * N ** (2 / 3), 1e-3 * yy) for (N, _, err), yy in zip(use, y)])
            for k in (2, 3):
                A = np.array([t**j for j in range(k + 1)]).T / e[:, None]
                free = np.linalg.lstsq(A, y / e, rcond=None)[0]
                err0 = float(np.sqrt(np.linalg.inv(A.T @ A)[0, 0]))
                chi2 = float(np.sum((A @ free - y / e) ** 2))
                fixed = np.linalg.lstsq(A[:, 1:], (y - s) / e, rcond=None)[0]
                chi2_fixed = float(np.sum((A[:, 1:] @ fixed - (y - s) / e) ** 2))
                if k == 3:
                    sd_rows[z] = (s, pts, fixed)
                print(f"  {k} correction orders: free intercept {free[0]:.4f} ± {err0:.4f} ({free[0] / s:.3f} s), "
                      f"chi2 {chi2:.1f} on {len(y) - k - 1}; s fixed: chi2 {chi2_fixed:.1f} on {len(y) - k}")

    draw(curves, sampled, sd_rows, args.figures)


def draw(curves, sampled, sd_rows, folder):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(11, 4.6))
    colours = {Fraction(1, 4): "C0", Fraction(1, 2): "C1", Fraction(3, 4): "C2"}
    t = np.linspace(0, 32 ** (-1 / 3), 200)
    ax = axes[0]
    for z, (Ns, devs, a, coef) in curves.items():
        c = colours[z]
        ax.plot(Ns ** (-1 / 3), devs * Ns ** (2 / 3), "o", color=c, ms=4, label=f"exact, z = {z}")
        with np.errstate(divide="ignore"):
            N = t[1:] ** -3.0
        ax.plot(t[1:], law(N, a, coef) * N ** (2 / 3), "-", color=c, lw=1)
        ax.plot([0], [a], "*", color=c, ms=12)
        for n_text, rec in sampled.items():
            N = int(n_text)
            r = rec[str(z)]
            ax.errorbar(N ** (-1 / 3), (r["mean"] - limit(int(z * N), N)) * N ** (2 / 3),
                        yerr=r["mean_err"] * N ** (2 / 3), fmt="s", color=c, mfc="none", ms=5)
    ax.set_xlabel("N^(-1/3)")
    ax.set_ylabel("N^(2/3) (<W_(i,1)> - e(z))")
    ax.set_title("mean: exact (o), sampled (squares), derived a(z) (*)", fontsize=10)
    ax.set_xlim(left=0)
    ax.legend(fontsize=8)
    ax = axes[1]
    for z, (s, pts, fixed) in sd_rows.items():
        c = colours[z]
        if fixed is not None:  # s(z) fixed, three orders fitted on N >= 32
            tt = np.linspace(0, 32 ** (-1 / 3), 100)
            ax.plot(tt, s + sum(f * tt ** (j + 1) for j, f in enumerate(fixed)), "--", color=c, lw=1)
        for N, v, err, kind in pts:
            if kind == "exact":
                ax.plot(N ** (-1 / 3), v * N ** (2 / 3), "o", color=c, ms=4)
            else:
                ax.errorbar(N ** (-1 / 3), v * N ** (2 / 3), yerr=err * N ** (2 / 3), fmt="s", color=c, mfc="none", ms=5)
        ax.plot([0], [s], "*", color=c, ms=12, label=f"z = {z}: sd(chi) c(z)")
    ax.set_xlabel("N^(-1/3)")
    ax.set_ylabel("N^(2/3) sd(W_(i,1))")
    ax.set_title("sd: exact (o), sampled (squares); dashed: s(z) fixed", fontsize=10)
    ax.set_xlim(left=0)
    ax.legend(fontsize=8)
    fig.tight_layout()
    os.makedirs(folder, exist_ok=True)
    fig.savefig(os.path.join(folder, "edge_law.png"), dpi=110)
    print(f"\nwrote {os.path.join(folder, 'edge_law.png')}")


if __name__ == "__main__":
    main()
