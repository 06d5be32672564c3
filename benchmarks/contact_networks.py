"""Contact networks (issue 55): the sampler's effective samples per second, the exact route's time, 1000 grains.

    python benchmarks/contact_networks.py sampler [--grains 50 150 500]   # paired: compiled vs plain numpy
    python benchmarks/contact_networks.py exact                          # time against the dimension
    python benchmarks/contact_networks.py families                       # the thesis's triangles, d to 21
    python benchmarks/contact_networks.py large [--grains 1000]          # relax, then sample with error bars
    python benchmarks/contact_networks.py basis --grains 450 --basis dense|projected|sparse  # Ker A's route

``sampler``: soft-disk packings (relaxed_packing) of growing size; in the same run, forcenet's compiled
coordinate hit-and-run and a plain numpy hit-and-run (a uniformly random direction in Ker A each move, the
chord by vectorized numpy; one recorded state per d moves); effective samples per second = min over the
forces of (recorded states / tau) divided by the sampling time (setup excluded, reported apart).
``exact``: random rational networks of dimension 5..20 (tests/test_contact_network.py's generator), the
triangulation route's time.  ``large``: the acceptance run, wall time from relaxation to error bars.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

import forcenet
from forcenet.numeric.autocorr import integrated_time
from forcenet.numeric.contact_network.hit_and_run import HitAndRun
from forcenet.numeric.contact_network.soft_disks import relaxed_packing


def plain_hit_and_run(walk: HitAndRun, states: int, seed: int) -> tuple[np.ndarray, float]:
    """Hit-and-run with uniformly random directions, plain numpy: ``states`` states, ``d`` moves apart."""
    rng = np.random.default_rng(seed)
    K, z = walk.K, walk.start.copy()
    d = K.shape[1]
    out = np.empty((states, K.shape[0]))
    t0 = time.perf_counter()
    for k in range(states):
        for _ in range(d):
            u = rng.normal(size=d)
            w = K @ (u / np.linalg.norm(u))
            positive, negative = w > 1e-300, w < -1e-300
            lo = np.max(-np.maximum(z[positive], 0) / w[positive], initial=-np.inf)
            hi = np.min(-np.maximum(z[negative], 0) / w[negative], initial=np.inf)
            z = z + (lo + (hi - lo) * rng.random()) * w
        out[k] = z
    return out, time.perf_counter() - t0


def ess(samples: np.ndarray, fixed: np.ndarray) -> float:
    tau = integrated_time(samples[:, ~fixed], tol=0, quiet=True)
    return float(samples.shape[0] / tau.max())


def sampler(grains: list[int], states: int) -> None:
    print("| grains | contacts | d | setup s | compiled: states, s, ESS/s | numpy: states, s, ESS/s | ratio |")
    print("| --- | --- | --- | --- | --- | --- | --- |")
    for n in grains:
        net = relaxed_packing(n, seed=1).network()
        t0 = time.perf_counter()
        walk = HitAndRun(net)
        setup = time.perf_counter() - t0
        chain = walk.run(states, seed=1)
        fast = ess(chain.samples, walk.fixed) / chain.seconds
        plain_states = max(200, states // 5)
        samples, seconds = plain_hit_and_run(walk, plain_states, seed=1)
        slow = ess(samples, walk.fixed) / seconds
        print(f"| {n} | {len(net.contacts)} | {walk.dimension} | {setup:.1f} | {states}, {chain.seconds:.1f}, "
              f"{fast:.3g} | {plain_states}, {seconds:.1f}, {slow:.3g} | {fast / slow:.0f} |", flush=True)


def exact(dimensions: list[int]) -> None:
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
    from test_contact_network import random_network

    from forcenet.exact.contact_network.polytope import check_polytope, exact_polytope
    from forcenet.exact.contact_network.triangulation_moments import moments_by_triangulation

    print("| d | grains | contacts | simplices | seconds (means and second moments) |")
    print("| --- | --- | --- | --- | --- |")
    for d in dimensions:
        grains = max(2, d // 2)
        contacts = 2 * grains + d
        for seed in range(3000):
            net = random_network(seed, grains, contacts)
            try:
                check_polytope(net)
            except forcenet.ArgumentError:
                continue
            poly = exact_polytope(net)
            if poly.dimension != d:
                continue
            t0 = time.perf_counter()
            m = moments_by_triangulation(poly, 2)
            print(f"| {d} | {grains} | {contacts} | {m.pieces} | {time.perf_counter() - t0:.2f} |", flush=True)
            break



def exact_families() -> None:
    """The exact route on the thesis's families of growing dimension: the chapter-4 triangle (few vertices, d =
    N(N-1)/2 up to 21) and the snooker triangle (many vertices), with Normaliz's vertex count beside the time."""
    from forcenet.exact.contact_network.geometries import snooker, triangle
    from forcenet.exact.contact_network.polytope import exact_polytope
    from forcenet.exact.contact_network.triangulation_moments import moments_by_triangulation, polytope_facts

    print("| family | N | d | contacts | vertices | simplices | seconds (means and second moments) |")
    print("| --- | --- | --- | --- | --- | --- | --- |")
    for name, build, sizes in (("triangle", triangle, (3, 4, 5, 6, 7)), ("snooker", snooker, (3, 4))):
        for N in sizes:
            net = build(N).network
            poly = exact_polytope(net)
            d, vertices, _ = polytope_facts(poly)
            t0 = time.perf_counter()
            m = moments_by_triangulation(poly, 2)
            print(f"| {name} | {N} | {d} | {len(net.contacts)} | {vertices} | {m.pieces} | "
                  f"{time.perf_counter() - t0:.2f} |", flush=True)


def large(grains: int, samples: int, thin: int) -> None:
    t0 = time.perf_counter()
    packing = relaxed_packing(grains, seed=1)
    net = packing.network()
    t1 = time.perf_counter()
    try:
        result = forcenet.network(net, samples=samples, thin=thin, seed=1)
    except forcenet.ForcenetError as exc:  # the chain too short for its autocorrelation time: said, timed
        print(f"{grains} grains, {len(net.contacts)} contacts: relaxed in {t1 - t0:.0f} s, sampled in "
              f"{time.perf_counter() - t1:.0f} s ({time.process_time():.0f} s CPU): {exc}")
        return
    t2 = time.perf_counter()
    rel = result.sampled_error / np.maximum(result.sampled_mean, 1e-300)
    varying = result.sampled_error > 0
    print(f"{grains} grains, {len(net.contacts)} contacts, dimension {result.dimension}: relaxed in {t1 - t0:.0f} s "
          f"(residual {packing.residual:.1e}), sampled {samples} states x {thin} sweeps with error bars in "
          f"{t2 - t1:.0f} s; tau (states) max {result.tau.max():.0f}, median {np.median(result.tau[varying]):.0f}; "
          f"relative error median {np.median(rel[varying]):.3f}, max {rel[varying].max():.3f}; "
          f"total {t2 - t0:.0f} s ({time.process_time():.0f} s CPU)")


def basis(grains: int, states: int, thin: int, route: str) -> None:
    """One network, one route (``dense``: the SVD basis; ``projected``: a basis from projected normal vectors;
    ``sparse``: projected random directions, no basis): relax, build
    the walk, sample, and print the time per effective sample (for farm-bench's paired runs)."""
    t0 = time.perf_counter()
    net = relaxed_packing(grains, seed=1).network()
    t1 = time.perf_counter()
    walk = HitAndRun(net, basis=route)
    t2 = time.perf_counter()
    chain = walk.run(states, seed=1, thin=thin)
    effective = ess(chain.samples, walk.fixed)
    print(f"{walk.route}: {grains} grains, {len(net.contacts)} contacts, d = {walk.dimension}: relax {t1 - t0:.1f} s, "
          f"walk set up {t2 - t1:.1f} s, {states} states x {thin} sweeps in {chain.seconds:.1f} s, ESS "
          f"{effective:.1f}, {chain.seconds / effective:.3g} s per effective sample (sampling), "
          f"{(time.perf_counter() - t1) / effective:.3g} s with the set-up; tau max {chain.samples.shape[0] / effective:.1f} "
          f"states; {time.process_time():.0f} s CPU", flush=True)


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("what", choices=["sampler", "exact", "families", "large", "basis"])
    parser.add_argument("--basis", choices=["auto", "dense", "projected", "sparse"], default="auto")
    parser.add_argument("--grains", type=int, nargs="*", default=None)
    parser.add_argument("--states", type=int, default=2000)
    parser.add_argument("--thin", type=int, default=4)
    args = parser.parse_args()
    if args.what == "sampler":
        sampler(args.grains or [50, 150, 500], args.states)
    elif args.what == "exact":
        exact([5, 8, 11, 14, 17, 20])
    elif args.what == "families":
        exact_families()
    elif args.what == "basis":
        basis((args.grains or [450])[0], args.states, args.thin, args.basis)
    else:
        large((args.grains or [1000])[0], args.states, args.thin)


if __name__ == "__main__":
    main()
