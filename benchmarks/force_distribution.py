"""Numbers and figures of notes/force_distribution.md (issue 16): exact P(f) for N <= 20, samples to N = 1000.

Exact side: the gap laws of every layer (one pass over the ideals each,
forcenet.exact.triangle.gaps) and of the contacts, cached in --cache;
densities evaluated in the stable Bernstein form. Sampled side: the .npz
files of benchmarks/force_distribution_samples.py.

Usage::

    OMP_NUM_THREADS=1 python benchmarks/force_distribution.py --N 8 12 16 20 \
        --samples /tmp/fd/s200.npz /tmp/fd/s500.npz /tmp/fd/s1000.npz --figures notes/figures
"""

from __future__ import annotations

import argparse
import math
import os
import pickle
from fractions import Fraction

import numpy as np


def exact_laws(N, cache):
    path = os.path.join(cache, f"laws_N{N}.pkl")
    if os.path.exists(path):
        with open(path, "rb") as handle:
            return pickle.load(handle)
    from forcenet.exact.triangle.gaps import contact_gap_counts, layer_gap_counts

    laws = {"layers": {i: layer_gap_counts(N, i) for i in range(2, N + 1)}, "contacts": contact_gap_counts(N)}
    with open(path, "wb") as handle:
        pickle.dump(laws, handle)
    return laws


def pooled(laws):
    from forcenet.exact.triangle.distribution import pool_gaps

    return pool_gaps(laws)


def layer_P(gaps, i, f):
    """P_i(f) of f = i W from the pooled gap law of layer i."""
    from forcenet.numeric.triangle.force_distribution import density_values

    f = np.asarray(f, dtype=float)
    return np.where(f <= i, density_values(gaps, np.clip(f / i, 0, 1)) / i, 0.0)


def ensemble_P(laws, N, f):
    M = sum(range(2, N + 1))
    return sum(i * layer_P(pooled(laws["layers"][i]), i, f) for i in range(2, N + 1)) / M


def contact_P(laws, N, i, f):
    from forcenet.numeric.triangle.force_distribution import density_values

    pool = pooled([laws["contacts"][(i, j, k)] for j in range(1, i + 1) for k in ("F5", "F6")])
    f = np.asarray(f, dtype=float)
    return np.where(f <= 2 * i, density_values(pool, np.clip(f / (2 * i), 0, 1)) / (2 * i), 0.0), pool


def second_moment_scaled(gaps, scale):
    """E[(scale X)^2] exactly, X the spacing of ``gaps``."""
    from forcenet.exact.triangle.distribution import moment_from_gaps

    return moment_from_gaps(gaps, 2) * scale * scale


def grain_numbers(gaps):
    """Local law f = W/<W> of one grain: Var f, Beta-noise share, tail numbers."""
    from forcenet.numeric.triangle.force_distribution import cdf_values, density_values

    d = gaps.d
    P = np.array(gaps.counts, dtype=float) / gaps.total
    g = np.arange(d + 2)
    Eg, Eg2 = (P * g).sum(), (P * g * g).sum()
    mean = Eg / (d + 1)
    noise = (P * g * (d + 1 - g)).sum() / ((d + 1) ** 2 * (d + 2))  # E Var(W | g)
    var = noise + (Eg2 - Eg**2) / (d + 1) ** 2
    out = {"var_f": round(float(var / mean**2), 4), "noise_share": round(float(noise / var), 4),
           "gap_rel_sd": round(math.sqrt(Eg2 - Eg**2) / Eg, 4)}
    for t in (2, 3):
        out[f"P(f>{t})"] = float(f"{1 - cdf_values(gaps, min(1.0, t * mean)):.4g}")
    ff = np.array([3.0, 4.0, 5.0])
    dens = density_values(gaps, np.clip(ff * mean, 0, 1)) * mean
    out["ln p(3,4,5)"] = np.log(dens).round(2).tolist()
    return out


def numbers(Ns, cache):
    rows = {}
    for N in Ns:
        laws = exact_laws(N, cache)
        floor = pooled(laws["layers"][N])
        r = {"P_floor(0)": str(Fraction(N - 1, N))}
        for f in (0.1, 0.25, 0.5, 1, 2, 3, 4):
            r[f"P_floor({f})"] = float(layer_P(floor, N, f))
        r["<f^2>_floor"] = float(second_moment_scaled(floor, N))
        M = sum(range(2, N + 1))
        r["P_ens(0)"] = str(Fraction(N - 1, M))
        fs = [0.1, 0.25, 0.5, 1, 2, 3, 4, 6, 8]
        vals = ensemble_P(laws, N, fs)
        r.update({f"P_ens({f})": float(v) for f, v in zip(fs, vals)})
        r["<f^2>_ens"] = float(sum(i * second_moment_scaled(pooled(laws["layers"][i]), i) for i in range(2, N + 1)) / M)
        for f in (2.0, 3.0, 5.0, 8.0):
            a, b = ensemble_P(laws, N, [f * (1 - 1e-3), f * (1 + 1e-3)])
            if a > 0 and b > 0 and f < N - 1:
                r[f"dlnP/dlnf_ens({f:g})"] = float((math.log(b) - math.log(a)) / (math.log(1 + 1e-3) - math.log(1 - 1e-3)))
        for i, name in ((N - 1, "contacts_below_N-1"), (N // 2, "contacts_mid")):
            vals, pool = contact_P(laws, N, i, [0.0, 1.0, 2.0, 4.0, 6.0])
            r[f"P_{name}(0,1,2,4,6)"] = [float(f"{v:.4g}") for v in vals]
            r[f"P_{name}(0)"] = str(Fraction(pool.counts[1] * pool.d, pool.total) / (2 * i))
            r[f"<f^2>_{name}"] = float(second_moment_scaled(pool, 2 * i))
        r["floor_centre"] = grain_numbers(laws["layers"][N][(N + 1) // 2 - 1])
        i = N // 2
        r["mid_centre"] = grain_numbers(laws["layers"][i][(i + 1) // 2 - 1])
        rows[N] = r
    return rows


def sampled(paths):
    out = {}
    for path in paths:
        if not os.path.exists(path):
            continue
        z = np.load(path)
        N = int(z["N"])
        e = z["edges"]
        width = np.diff(e)
        entry = {"N": N, "samples": int(z["samples"]), "centres": np.sqrt(e[1:] * np.maximum(e[:-1], 1e-4))}
        for pool in ("floor", "mid", "ensemble", "contacts"):
            if f"hist_{pool}" not in z:
                continue
            h = z[f"hist_{pool}"]
            entry[pool] = (h / (h.sum() * width), np.sqrt(h) / (h.sum() * width))
        for name in ("floor", "mid"):
            # the central grains share one mean (the profile is flat there to second order in x):
            # normalize by the mean over all of them and all samples; error bars from the spread
            # between samples (the grains of one sample are correlated)
            W, g = z[f"W_{name}"], z[f"g_{name}"].astype(float)
            f, h = W / W.mean(), g / g.mean()
            entry[f"W_{name}"], entry[f"g_{name}"] = f.ravel(), h.ravel()
            d = N * (N - 1) // 2
            noise = (g * (d + 1 - g)).mean() / ((d + 1) ** 2 * (d + 2))
            entry[f"noise_share_{name}"] = float(noise / W.var())
            K = W.shape[0]
            for key, x in (("var_f", f), ("var_g", h)):
                per = ((x - 1) ** 2).mean(axis=1)
                entry[f"{key}_{name}"] = (float(per.mean()), float(per.std(ddof=1) / np.sqrt(K)))
            for t in (2, 3):
                per = (f > t).mean(axis=1)
                entry[f"P(f>{t})_{name}"] = (float(per.mean()), float(per.std(ddof=1) / np.sqrt(K)))
            entry[f"grains_{name}"] = W.shape[1]
        out[N] = entry
    return out


def figures(Ns, cache, samples, outdir):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from forcenet.numeric.triangle.force_distribution import density_values

    colours = {N: f"C{k}" for k, N in enumerate(Ns)}
    # 1. the ensemble and floor pools, linear and log-log
    fig, ax = plt.subplots(1, 3, figsize=(15, 4.6))
    f = np.linspace(0, 8, 801)[1:]
    fl = np.logspace(-2, np.log10(60), 400)
    for N in Ns:
        laws = exact_laws(N, cache)
        ax[0].semilogy(f, ensemble_P(laws, N, f), color=colours[N], label=f"exact N={N}")
        ax[1].loglog(fl, ensemble_P(laws, N, fl), color=colours[N], label=f"exact N={N}")
        ax[2].semilogy(f, layer_P(pooled(laws["layers"][N]), N, f), color=colours[N], label=f"exact N={N}")
    for k, (N, s) in enumerate(sorted(samples.items())):
        m = ["o", "s", "^"][k % 3]
        dens, err = s["ensemble"]
        keep = dens > 0
        ax[0].errorbar(s["centres"][keep], dens[keep], err[keep], fmt=m, ms=2.5, lw=0.5, color="k", alpha=0.6,
                       label=f"sampler N={N} ({s['samples']})")
        ax[1].errorbar(s["centres"][keep], dens[keep], err[keep], fmt=m, ms=2.5, lw=0.5, color="k", alpha=0.6,
                       label=f"sampler N={N}")
        dens, err = s["floor"]
        keep = dens > 0
        ax[2].errorbar(s["centres"][keep], dens[keep], err[keep], fmt=m, ms=2.5, lw=0.5, color="k", alpha=0.6,
                       label=f"sampler N={N}")
    ax[0].semilogy(f, np.exp(-f), "k:", lw=0.8, label="exp(-f)")
    ax[1].axvline(max(samples) * (3 - 2 * np.sqrt(2)) / 4 if samples else 1, color="k", ls="--", lw=0.6,
                  label="N (3 - 2 sqrt2)/4, largest N sampled")
    ax[0].set(xlabel="f = i W_ij (load / mean load of its layer)", ylabel="P(f)", ylim=(1e-5, 2), xlim=(0, 8),
              title="(a) every grain of layers 2..N")
    ax[1].set(xlabel="f", ylabel="P(f)", ylim=(1e-7, 2), title="(b) the same, log-log: the lattice-direction plateau")
    ax[2].set(xlabel="f = N W_Nj (floor)", ylabel="P(f)", ylim=(1e-5, 2), xlim=(0, 8), title="(c) the floor layer")
    for a in ax:
        a.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(outdir, "force_distribution_pools.png"), dpi=110)
    plt.close(fig)
    # 2. the local law: one grain scaled by its own mean, exact and sampled (with and without the Beta noise)
    fig, ax = plt.subplots(1, 2, figsize=(11, 4.6))
    f = np.linspace(0, 5, 501)
    for a, (name, title) in zip(ax, (("floor", "floor centre grain"), ("mid", "centre grain of layer N/2"))):
        for N in Ns:
            laws = exact_laws(N, cache)
            i = N if name == "floor" else N // 2
            gaps = laws["layers"][i][(i + 1) // 2 - 1]
            mu = gaps.mean() / (gaps.d + 1)
            a.semilogy(f, density_values(gaps, np.clip(f * float(mu), 0, 1)) * float(mu), color=colours[N], label=f"exact N={N}")
        for k, (N, s) in enumerate(sorted(samples.items())):
            bins = np.linspace(0, 5, 51)
            c = 0.5 * (bins[1:] + bins[:-1])
            for key, m, lab in ((f"W_{name}", "o", "W/<W>"), (f"g_{name}", "x", "g/<g>")):
                h, _ = np.histogram(s[key], bins)
                dens = h / (s[key].size * np.diff(bins))
                keep = h > 0
                a.plot(c[keep], dens[keep], m, ms=3, color=f"C{len(Ns) + k}", label=f"sampler N={N}, {lab}")
        a.set(xlabel="f = W / <W>", ylabel="p(f)", ylim=(1e-5, 2), title=f"(d) local law: {title}")
        a.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(outdir, "force_distribution_local.png"), dpi=110)
    plt.close(fig)
    # 3. contacts pooled per layer
    fig, ax = plt.subplots(figsize=(6, 4.6))
    f = np.linspace(0, 8, 801)
    for N in Ns:
        laws = exact_laws(N, cache)
        for i, ls in ((N - 1, "-"), (N // 2, "--")):
            vals, _ = contact_P(laws, N, i, f)
            ax.semilogy(f, vals, ls, color=colours[N], label=f"N={N}, below layer {i}")
    for k, (N, s) in enumerate(sorted(samples.items())):
        if "contacts" in s:
            dens, err = s["contacts"]
            keep = (dens > 0) & (s["centres"] < 8)
            ax.errorbar(s["centres"][keep], dens[keep], err[keep], fmt=["o", "s", "^"][k % 3], ms=2.5, lw=0.5,
                        color="k", alpha=0.6, label=f"sampler N={N}, below layer {N - 1}")
    ax.semilogy(f, np.exp(-f), "k:", label="exp(-f)")
    ax.set(xlabel="f = F / <F> (the 2i contacts between layers i and i+1)", ylabel="P(f)", ylim=(1e-6, 2),
           title="(e) contact forces F5, F6, exact")
    ax.legend(fontsize=6)
    fig.tight_layout()
    fig.savefig(os.path.join(outdir, "force_distribution_contacts.png"), dpi=110)
    plt.close(fig)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--N", type=int, nargs="+", default=[8, 12, 16, 20])
    parser.add_argument("--samples", nargs="*", default=[])
    parser.add_argument("--cache", default="/tmp/fd")
    parser.add_argument("--figures", default=None)
    args = parser.parse_args(argv)
    os.makedirs(args.cache, exist_ok=True)
    rows = numbers(args.N, args.cache)
    for N, r in rows.items():
        print(f"--- N = {N}")
        for k, v in r.items():
            print(f"  {k}: {v if not isinstance(v, float) else f'{v:.5g}'}")
    samples = sampled(args.samples)

    def pm(v):
        return f"{v[0]:.4f} +- {v[1]:.4f}"

    for N, s in samples.items():
        print(f"--- sampler N = {N} ({s['samples']} samples)")
        for name in ("floor", "mid"):
            print(f"  {name} ({s[f'grains_{name}']} central grains): Var(W/<W>) = {pm(s[f'var_f_{name}'])}, "
                  f"Var(g/<g>) = {pm(s[f'var_g_{name}'])}, Beta-noise share = {s[f'noise_share_{name}']:.4f}; "
                  f"P(f>2) = {pm(s[f'P(f>2)_{name}'])}, P(f>3) = {pm(s[f'P(f>3)_{name}'])}")
        dens, _ = s["ensemble"]
        c = s["centres"]
        far = c > 4
        top = c[far][np.argmax(dens[far])] if far.any() else float("nan")
        print(f"  ensemble: P(f) for f > 4 peaks at f = {top:.1f}; the lattice directions' maximum N (3 - 2 sqrt2)/4 = "
              f"{N * (3 - 2 * np.sqrt(2)) / 4:.1f}; mean P(f) on (4, {0.03 * N:.0f}) = {dens[(c > 4) & (c < 0.03 * N)].mean():.2e}, "
              f"times N^2: {dens[(c > 4) & (c < 0.03 * N)].mean() * N * N:.0f}")
        for pool in ("floor", "ensemble", "contacts"):
            if pool not in s:
                continue
            dens, err = s[pool]
            for lo, hi in ((0.1, 0.3), (0.01, 0.03), (0.003, 0.01)):
                keep = (c > lo) & (c < hi)
                print(f"  {pool}: mean P(f) on ({lo}, {hi}) = {dens[keep].mean():.3f} "
                      f"+- {np.sqrt((err[keep] ** 2).sum()) / keep.sum():.3f}")
    if args.figures:
        figures(args.N, args.cache, samples, args.figures)


if __name__ == "__main__":
    main()
