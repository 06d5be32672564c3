"""Bonds per second of the all-thresholds cluster pass against scipy's connected components, in the same run.

forcenet's pass (:func:`forcenet.numeric.force_chains.newman_ziff.sweep_lattice`) groups the bonds of a sample
by threshold and adds them to a compiled union-find once, recording the cluster statistics at every threshold.
The baseline is what one would write with scipy: at each threshold, the kept bonds' sparse graph and
``scipy.sparse.csgraph.connected_components``, then the cluster sizes in bonds by ``bincount``.  Rates are
bonds per CPU second of this process (``time.process_time``: one core, robust to other jobs on the machine),
for one threshold (scipy's pass) and for all ``T`` thresholds (forcenet's pass; scipy's cost is ``T`` passes).

    python benchmarks/bench_force_chains.py --L 64 256 --samples 20 --thresholds 600
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

from forcenet.numeric.force_chains.newman_ziff import periodic_lattice, sweep_lattice


def scipy_one_threshold(lattice, forces: np.ndarray, threshold: float) -> tuple[int, int]:
    total = largest = 0
    for row in forces:
        keep = row > threshold
        graph = coo_matrix((np.ones(int(keep.sum())), (lattice.head[keep], lattice.tail[keep])),
                           shape=(lattice.sites, lattice.sites)).tocsr()
        _, label = connected_components(graph, directed=False)
        sizes = np.bincount(label[lattice.head[keep]])
        total += int((sizes**2).sum() - sizes.max() ** 2)
        largest += int(sizes.max())
    return total, largest


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--L", type=int, nargs="+", default=[64, 256])
    parser.add_argument("--samples", type=int, default=20)
    parser.add_argument("--thresholds", type=int, default=600)
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    levels = np.linspace(0.01, 0.99, args.thresholds)
    print("| L | bonds/sample | forcenet, all T thresholds, wrapping (Mbonds/s) | without wrapping (Mbonds/s) | "
          "scipy, one threshold (Mbonds/s) | speed-up at T thresholds |")
    print("| --- | --- | --- | --- | --- | --- |")
    for L in args.L:
        lattice = periodic_lattice("square", L)
        forces = np.random.default_rng(L).random((args.samples, lattice.bonds))
        sweep_lattice(lattice, forces[:1], levels)  # compile (or load) first
        bonds = forces.size
        best = {"wrap": 0.0, "plain": 0.0, "scipy": 0.0}
        for _ in range(args.repeats):  # interleaved: the same load on the machine for both
            t = time.process_time()
            stats = sweep_lattice(lattice, forces, levels)
            best["wrap"] = max(best["wrap"], bonds / (time.process_time() - t))
            t = time.process_time()
            sweep_lattice(lattice, forces, levels, wrapping=False)
            best["plain"] = max(best["plain"], bonds / (time.process_time() - t))
            t = time.process_time()
            check = scipy_one_threshold(lattice, forces, 0.5)
            best["scipy"] = max(best["scipy"], bonds / (time.process_time() - t))
        k = int(np.argmin(np.abs(levels - 0.5)))
        ours = scipy_one_threshold(lattice, forces, float(levels[k]))
        if ours != (int(stats.total[:, k].sum()), int(stats.largest[:, k].sum())):
            raise SystemExit(f"L={L}: the two routes disagree at f={levels[k]}")
        del check
        speedup = best["wrap"] * args.thresholds / best["scipy"]
        print(f"| {L} | {lattice.bonds} | {best['wrap'] / 1e6:.1f} | {best['plain'] / 1e6:.1f} | "
              f"{best['scipy'] / 1e6:.1f} | {speedup:.0f}x |")


if __name__ == "__main__":
    main()
