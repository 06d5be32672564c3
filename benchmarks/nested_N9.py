"""The nested-matrix integration (thesis Secs. 4.3-4.5) for every grain, against the exact core.

Run:  python benchmarks/nested_N9.py [N] [--workers W] [--baseline]

Integrates the normalization and ``<W_{i,j}>`` for every grain with the
modular engine (``forcenet.exact.thesis.nested.integrate_layers``), compares each with the
exact core (order-ideal DP), and prints times and peak memory.  With
``--baseline`` the normalization is also integrated with the literal
Fraction/dictionary version first, in the same run, for the ratio
(N = 9: ~6 min and 19 GB, so it runs alone before the workers start).
Default N = 9, one worker (~6 GB per worker at N = 9).  Used in
notes/chapter4.md and notes/benchmarks.md.
"""

import argparse
import multiprocessing
import resource
import sys
import time

from forcenet.exact import mean_W, normalization
from forcenet.exact.thesis.nested import integrate_layers


def _peak_gb():
    """Peak resident memory of this process in GB.

    ``VmHWM`` of the process's own address space where Linux has it:
    ``ru_maxrss`` survives fork and exec, so a worker started after the
    19 GB baseline would report the parent's peak.
    """
    try:
        with open("/proc/self/status") as status:
            for line in status:
                if line.startswith("VmHWM:"):
                    return int(line.split()[1]) / 1e6
    except OSError:
        pass
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1e6


def _grain(args):
    N, g = args
    t = time.perf_counter()
    value = integrate_layers(N, {g: 1})
    return g, value, time.perf_counter() - t, _peak_gb()


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("N", nargs="?", type=int, default=9)
    parser.add_argument("--workers", type=int, default=1)
    parser.add_argument("--baseline", action="store_true", help="also time the literal Fraction version (normalization)")
    args = parser.parse_args()
    N = args.N
    t = time.perf_counter()
    exact_table, exact_norm = mean_W(N), normalization(N)
    t_core = time.perf_counter() - t
    print(f"N = {N}: exact core (table + normalization) {t_core:.3f} s", flush=True)
    if args.baseline:
        t = time.perf_counter()
        literal = integrate_layers(N, arithmetic="fraction")
        t_literal = time.perf_counter() - t
        print(f"  normalization, literal Fraction recursion: {t_literal:.0f} s, peak RSS {_peak_gb():.1f} GB, "
              f"equal to the exact core: {literal == exact_norm}", flush=True)
    t = time.perf_counter()
    volume = integrate_layers(N)
    t_norm = time.perf_counter() - t
    print(f"  normalization, modular recursion: {t_norm:.1f} s, equal to the exact core: {volume == exact_norm}"
          + (f", {t_literal / t_norm:.1f}x faster than the literal one" if args.baseline else ""), flush=True)
    grains = [(i, j) for i in range(1, N + 1) for j in range(1, i + 1)]
    t_all = time.perf_counter()
    equal, times, peaks = 0, [], []
    with multiprocessing.get_context("spawn").Pool(args.workers, maxtasksperchild=1) as pool:  # one fresh process per grain
        for g, value, seconds, peak in pool.imap_unordered(_grain, [(N, g) for g in grains]):
            mean = value / volume
            ok = mean == exact_table[g[0] - 1][g[1] - 1]
            equal += ok
            times.append(seconds)
            peaks.append(peak)
            print(f"  <W_{g[0]},{g[1]}> = {mean}  equal: {ok}  ({seconds:.1f} s, worker peak RSS {peak:.1f} GB)", flush=True)
    wall = time.perf_counter() - t_all
    print(f"N = {N}: {equal}/{len(grains)} grains equal to the exact core; {len(grains)} integrations "
          f"{sum(times):.0f} s ({min(times):.1f}-{max(times):.1f} s each), wall {wall:.0f} s with {args.workers} worker(s), "
          f"peak RSS per worker {max(peaks):.1f} GB; ratio to the exact core {(sum(times) + t_norm) / t_core:.2g}", flush=True)
    return 0 if equal == len(grains) else 1


if __name__ == "__main__":
    sys.exit(main())
