"""Single-q Metropolis against the slice move on the N x P packing: effective samples per CPU second at equal error.

For each scene and move: CPU seconds of the chain (compiled kernels, warmed
up), acceptance, the largest integrated autocorrelation time over the grains
(in sweeps; flagged ``*`` when the chain is shorter than 50 tau, where tau is
only a lower bound), effective samples per CPU second, and the error against a
reference: the exact table (gravity, every q allowed: ``mean_W_mobilized``),
independent rejection samples (``uniform_networks``, small isotropic scene),
or, where neither exists, the other move's long chain (z-scores of the
difference of the two means).

    python benchmarks/packing_moves.py small     # gravity 4 x 4 (exact) and isotropic 3 x 3 (rejection)
    python benchmarks/packing_moves.py panel     # isotropic 8 x 17, F/p = 3 and 10 (~10 min)
"""

from __future__ import annotations

import math
import sys
import time
import warnings

import numpy as np

from forcenet.numeric.autocorr import integrated_time
from forcenet.numeric.packing import PackingMetropolis, Scene


def chain(scene, move, records, thin, seed):
    sampler = PackingMetropolis(scene, seed=seed, move=move)
    sampler.sweep(10)
    t0 = time.process_time()
    W = sampler.run(records, burn_in=records * thin // 10, thin=thin)
    seconds = time.process_time() - t0
    flat = W.reshape(records, -1)
    varying = flat.std(axis=0) > 1e-12
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        tau = np.ones(flat.shape[1])
        tau[varying] = integrated_time(flat[:, varying], quiet=True)
    trusted = records > 50 * tau.max()
    mean = flat.mean(axis=0)
    err = np.sqrt(flat.var(axis=0, ddof=1) * tau / records)
    return {"seconds": seconds, "acceptance": sampler.acceptance_rate, "tau": tau.max() * thin, "trusted": trusted,
            "mean": mean, "err": err, "sweeps": records * thin * 1.1, "recorded": records * thin,
            "evals": sampler.evaluations / max(1, sampler.attempted)}


def report(name, results, reference=None, ref_err=None):
    for move, r in results.items():
        if reference is None:  # against the other move
            other = results["slice" if move == "metropolis" else "metropolis"]
            ref, rerr = other["mean"], other["err"]
        else:
            ref, rerr = reference, ref_err
        sigma = np.hypot(r["err"], rerr)
        free = sigma > 0
        z = np.abs(r["mean"] - ref)[free] / sigma[free]
        rms = float(np.sqrt(np.mean((r["mean"] - ref)[free] ** 2)))
        ess = r["recorded"] / r["tau"]
        flag = "" if r["trusted"] else "*"
        print(f"| {name} | {move} | {r['recorded']:.0f} | {r['seconds']:.1f} | {1e3 * r['seconds'] / r['sweeps']:.4f} | "
              f"{r['acceptance']:.3f} | {r['tau']:.0f}{flag} | {ess:.0f} | {ess / r['seconds']:.3g} | {rms:.2e} | "
              f"{z.max():.2f} |", flush=True)


HEADER = ("| scene | move | sweeps | CPU s | ms/sweep | acceptance | tau_max (sweeps) | effective samples | "
          "effective / CPU s | RMS error | max abs z |\n| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")


def small():
    from forcenet.exact.packing.mobilized import mean_W_mobilized
    from forcenet.numeric.packing.networks import uniform_networks

    print(HEADER)
    scene = Scene(N=4, P=4, F=10.0, mg=1.0, j0=2)
    exact = np.array(mean_W_mobilized(4, 4, F=10, j0=2, mg=1), dtype=float).ravel()
    results = {move: chain(scene, move, 100_000, 1, 3) for move in ("metropolis", "slice")}
    report("gravity 4 x 4, F/mg = 10 (exact)", results, exact, np.zeros_like(exact))
    scene = Scene(N=3, P=3, F=1.0, pv=1.0, ph=1.0)
    W, _ = uniform_networks(scene, 200_000, np.random.default_rng(7))
    flat = W.reshape(len(W), -1)
    results = {move: chain(scene, move, 100_000, 1, 4) for move in ("metropolis", "slice")}
    report("isotropic 3 x 3, F/p = 1 (rejection)", results, flat.mean(axis=0), flat.std(axis=0, ddof=1) / math.sqrt(len(W)))


def panel():
    print(HEADER)
    for F, budget in ((3.0, {"metropolis": (100_000, 4), "slice": (100_000, 2)}),
                      (10.0, {"metropolis": (100_000, 20), "slice": (100_000, 8)})):
        scene = Scene(N=8, P=17, F=F, pv=1.0, ph=1.0)
        results = {move: chain(scene, move, *budget[move], 5) for move in ("metropolis", "slice")}
        report(f"isotropic 8 x 17, F/p = {F:g}", results)


if __name__ == "__main__":
    {"small": small, "panel": panel}[sys.argv[1] if len(sys.argv) > 1 else "small"]()
