"""Speed against error for the two samplers (issue 4).

For each N and budget: CPU seconds, RMS error of the sampled <W> table against
the exact table (exact core), and effective independent samples per CPU
second (exact sampler: every sample; Metropolis: sweeps / tau, with tau the
largest integrated autocorrelation time over the grains, in sweeps).

Usage::

    python benchmarks/speed_vs_error.py --N 11 24 --exact-samples 250 1000 4000 16000 \\
        --metropolis-sweeps 1000 4000 16000
    python benchmarks/speed_vs_error.py --ess-only --N 50 --metropolis-sweeps 3000
    python benchmarks/speed_vs_error.py --N 11 24 --kernels compiled python ...   # both kernels, same command
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from forcenet.numeric.autocorr import integrated_time
from forcenet.numeric.triangle.exact_sampler import ExactSampler
from forcenet.numeric.triangle.metropolis import TriangleMetropolis


def exact_table(N):
    from forcenet.exact import mean_W

    return np.array([[float(x) for x in row] + [0.0] * (N - len(row)) for row in mean_W(N)])


def rms(mean, exact):
    mask = np.tril(np.ones_like(exact, dtype=bool))
    return float(np.sqrt(np.mean((mean - exact)[mask] ** 2)))


def run_exact(N, K, seed, kernel=None):
    t0 = time.process_time()
    mean, _ = ExactSampler(N, seed=seed, kernel=kernel).mean_W(K)
    return mean, time.process_time() - t0, K


def run_metropolis(N, sweeps, seed, kernel=None, move="metropolis"):
    t0 = time.process_time()
    sampler = TriangleMetropolis(N, seed=seed, kernel=kernel, move=move)
    chain = sampler.run(sweeps, burn_in=max(100, sweeps // 10))
    seconds = time.process_time() - t0
    flat = chain.reshape(sweeps, -1)[:, np.tril(np.ones((N, N), dtype=bool)).ravel()]
    flat = flat[:, flat.std(axis=0) > 0]
    tau = integrated_time(flat, quiet=True)
    return chain.mean(axis=0), seconds, sweeps / tau.max()


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--N", type=int, nargs="+", default=[11, 24])
    parser.add_argument("--exact-samples", type=int, nargs="+", default=[250, 1000, 4000, 16000])
    parser.add_argument("--metropolis-sweeps", type=int, nargs="+", default=[1000, 4000, 16000])
    parser.add_argument("--ess-only", action="store_true", help="skip the exact table; report effective samples per second")
    parser.add_argument("--seed", type=int, default=7)
    parser.add_argument("--plot", help="write a log-log plot of RMS error against CPU seconds to this PNG")
    parser.add_argument("--kernels", nargs="+", default=["compiled"], choices=["compiled", "python"],
                        help="sampler kernels to run (the compiled ones' first call is warmed up outside the timing)")
    parser.add_argument("--moves", nargs="+", default=["metropolis"], choices=["metropolis", "slice"],
                        help="Markov-chain moves to run (slice: compiled kernel only)")
    parser.add_argument("--no-exact", action="store_true", help="skip the exact sampler's rows")
    parser.add_argument("--python-max-seconds", type=float, default=200.0,
                        help="skip a reference-kernel budget estimated above this many CPU seconds")
    args = parser.parse_args(argv)
    rows = []
    if "compiled" in args.kernels:  # compile (or load the cache) before any timing
        ExactSampler(5, seed=0, kernel="compiled").mean_W(2)
        for move in args.moves:
            TriangleMetropolis(5, seed=0, kernel="compiled", move=move).sweep(1)
    print("| N | sampler | kernel | budget | CPU s | RMS error | effective samples | effective samples / CPU s |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- |")
    for N in args.N:
        exact = None if args.ess_only else exact_table(N)
        for kernel in args.kernels:
            per_sample = 6.5e-8 * N**3 if kernel == "python" else 1.25e-8 * N * N * np.log(N)
            per_sweep = 4e-5 * N * (N - 1) / 2 if kernel == "python" else 0.0
            for K in [] if args.no_exact else args.exact_samples:
                if per_sample * K > args.python_max_seconds:
                    continue
                mean, seconds, ess = run_exact(N, K, args.seed, kernel)
                err = "-" if exact is None else f"{rms(mean, exact):.2e}"
                print(f"| {N} | exact | {kernel} | {K} samples | {seconds:.2f} | {err} | {ess:.0f} | {ess / seconds:.1f} |", flush=True)
                rows.append((N, f"exact sampler ({kernel})", seconds, None if exact is None else rms(mean, exact)))
            for move in args.moves:
                if move == "slice" and kernel == "python":
                    continue
                for S in args.metropolis_sweeps:
                    if per_sweep * S * 1.1 > args.python_max_seconds:
                        continue
                    mean, seconds, ess = run_metropolis(N, S, args.seed, kernel, move)
                    err = "-" if exact is None else f"{rms(mean, exact):.2e}"
                    name = "metropolis" if move == "metropolis" else "slice move"
                    print(f"| {N} | {name} | {kernel} | {S} sweeps | {seconds:.2f} | {err} | {ess:.0f} | {ess / seconds:.2f} |",
                          flush=True)
                    rows.append((N, f"{name} ({kernel})", seconds, None if exact is None else rms(mean, exact)))
    if args.plot:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, ax = plt.subplots(figsize=(6, 4.5))
        for N in args.N:
            for name in sorted({nm for n, nm, _, _ in rows if n == N}):
                marker = ("o" if name.startswith("exact") else "s") + ("-" if "compiled" in name else ":")
                pts = [(s, e) for n, nm, s, e in rows if n == N and nm == name and e is not None]
                if pts:
                    ax.loglog(*zip(*pts), marker, label=f"{name}, N={N}")
        ax.set_xlabel("CPU seconds")
        ax.set_ylabel("RMS error of the <W> table")
        ax.set_title("speed against error (exact values from the exact core)")
        ax.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(args.plot, dpi=110)


if __name__ == "__main__":
    main()
