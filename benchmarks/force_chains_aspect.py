"""The independent (or microcanonical) q-model at a chosen aspect ratio W = aspect * L: peak heights and collapse.

Sec. 7.3.1 scales the q-models in their vertical size only, "as increasing L_hor simply replicates the system";
this script measures what the width does (notes/force_chains.md, Sec. 4.2):

    python benchmarks/force_chains_aspect.py --aspect 1 --sizes 20,28,40,56,80,112,160
    python benchmarks/force_chains_aspect.py --aspect 4 --sizes 20,28,40,56,80
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from forcenet.numeric.force_chains.finite_size_scaling import NAMES, SizeBlocks, analyse, peak
from forcenet.numeric.force_chains.newman_ziff import sweep_lattice
from forcenet.numeric.force_chains.q_models import independent_samples, microcanonical_samples, q_lattice


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--model", choices=["independent", "microcanonical"], default="independent")
    parser.add_argument("--aspect", type=float, default=1.0)
    parser.add_argument("--sizes", default="20,28,40,56,80")
    parser.add_argument("--bonds", type=float, default=2e7, help="bonds per size (samples = bonds / M)")
    parser.add_argument("--seed", type=int, default=7)
    args = parser.parse_args()
    sizes = [int(x) for x in args.sizes.split(",")]
    generate = independent_samples if args.model == "independent" else microcanonical_samples
    rng = np.random.default_rng(args.seed)
    L_max = max(sizes)
    pilot = generate(L_max, int(args.aspect * L_max), 2, rng).ravel()
    thresholds = np.unique(np.quantile(pilot, np.linspace(0.01, 0.99, 600)))
    data, started = [], time.perf_counter()
    for L in sizes:
        W = int(args.aspect * L)
        lattice = q_lattice(L, W)
        per = max(2, int(args.bonds / lattice.bonds) // 32)
        sums = []
        for _ in range(32):
            s = sweep_lattice(lattice, generate(L, W, per, rng), thresholds)
            sums.append([s.total.sum(0), s.largest.sum(0), s.wraps.sum(0)])
        blocks = np.array(sums, dtype=np.float64)
        data.append(SizeBlocks(float(L * L), lattice.bonds, thresholds, blocks[:, 0], blocks[:, 1], blocks[:, 2],
                               np.full(32, float(per)), label=float(L)))
        f, h = peak(thresholds, data[-1].s2())
        print(f"L = {L:4d}  W = {W:4d}  samples = {32 * per:6d}  peak <s^2> = {h:9.3f} at f = {f:.4f}  "
              f"({time.perf_counter() - started:.0f} s)", flush=True)
    fit = analyse(data, replicas=50)
    for name in NAMES:
        print(f"{name:8s} collapse {fit.value[name]:.4f} +- {fit.error[name]:.4f}")
    print("nu pinned:", fit.pinned, " estimators:", {k: round(v, 4) for k, v in fit.estimators.items()},
          " errors:", {k: round(v, 4) for k, v in fit.estimator_errors.items()})


if __name__ == "__main__":
    main()
