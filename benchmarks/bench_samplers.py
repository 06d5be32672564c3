"""Samplers at compiled speed (issue 17): the compiled kernels against the reference kernels, in one command.

Every figure is CPU seconds (``time.process_time``) of this process, the
median (and min) of several repetitions; every ratio is reference / compiled
measured in the same command.  The reference kernels are the pure-Python
implementations the samplers had before (``kernel="python"``: the same code,
still the tests' oracle).

    python benchmarks/bench_samplers.py metropolis   # triangle N = 11, 24, 50; packing scenes; the floor
    python benchmarks/bench_samplers.py exact        # exact sampler N = 50..2000 (reference up to N = 1000)
    python benchmarks/bench_samplers.py compile      # first-call compile time vs cached load (fresh processes)

The floor: a kernel that only applies each move's changes to the affected
forces (the light cone of ``W``; with a finite ``p_h`` also the running sums
``F4`` right of the grain), always accepting, no weight, no constraint test.
"""

from __future__ import annotations

import math
import os
import statistics
import subprocess
import sys
import tempfile
import time
from functools import partial

import numpy as np

from forcenet.numeric.jit import njit


def timed(fn, reps):
    times = []
    for _ in range(reps):
        t0 = time.process_time()
        fn()
        times.append(time.process_time() - t0)
    return statistics.median(times), min(times)


# ------------------------------------------------------------------------ the floor


@njit(cache=False)
def floor_triangle(q, W, gi, gj, picks, values):
    """Apply each move's new q to the light cone of W (always accepted); returns forces written."""
    N = W.shape[0]
    written = 0
    for m in range(picks.shape[0]):
        i = gi[picks[m]]
        j = gj[picks[m]]
        q[i, j] = values[m]
        for k in range(i + 1, N):
            for c in range(j, j + k - i + 1):
                a = 0.0
                if c < k:
                    a = q[k - 1, c] * W[k - 1, c]
                if c >= 1:
                    a = a + (1.0 - q[k - 1, c - 1]) * W[k - 1, c - 1]
                W[k, c] = a
                written += 1
    return written


@njit(cache=False)
def floor_packing(q, W, cs, gi, gj, picks, values, mg, has_ph):
    """Light cone of W, and with ph the running sums of (a stand-in for) the lateral increments right of j."""
    N, P = W.shape
    written = 0
    for m in range(picks.shape[0]):
        i = gi[picks[m]]
        j = gj[picks[m]]
        q[i, j] = values[m]
        hi = j + 1
        for k in range(i + 1, N):
            hi = min(P, hi + 1)
            for c in range(j, hi):
                a = q[k - 1, c] * W[k - 1, c] + mg
                if c >= 1:
                    a = a + (1.0 - q[k - 1, c - 1]) * W[k - 1, c - 1]
                W[k, c] = a
                written += 1
        if has_ph:
            for k in range(i, N):
                run = cs[k, j - 1] if j >= 1 else 0.0
                for c in range(j, P):
                    run = run + (2.0 * q[min(k, N - 2), c] * W[k, c] - mg) * 0.57735
                    cs[k, c] = run
                    written += 1
    return written


def floor_per_move(kind, sampler, moves=200_000):
    rng = np.random.default_rng(0)
    G = len(sampler.grains)
    gi = np.array([g[0] for g in sampler.grains], dtype=np.int64)
    gj = np.array([g[1] for g in sampler.grains], dtype=np.int64)
    picks = rng.integers(0, G, size=moves)
    values = rng.random(moves)
    q, W = sampler.q.copy(), sampler.W.copy()
    if kind == "triangle":
        floor_triangle(q, W, gi, gj, picks[:10], values[:10])
        med, _ = timed(lambda: floor_triangle(q, W, gi, gj, picks, values), 5)
        written = floor_triangle(q, W, gi, gj, picks, values)
    else:
        scene = sampler.scene
        cs = np.zeros(W.shape)
        args = (float(scene.mg), scene.ph is not None)
        floor_packing(q, W, cs, gi, gj, picks[:10], values[:10], *args)
        med, _ = timed(lambda: floor_packing(q, W, cs, gi, gj, picks, values, *args), 5)
        written = floor_packing(q, W, cs, gi, gj, picks, values, *args)
    return med / moves, written / moves


# ---------------------------------------------------------------------- Metropolis


def bench_metropolis():
    from forcenet.numeric.packing import PackingMetropolis, Scene
    from forcenet.numeric.triangle.metropolis import TriangleMetropolis

    configs = [
        ("triangle N = 11", "triangle", lambda k: TriangleMetropolis(11, seed=1, kernel=k), 400),
        ("triangle N = 24", "triangle", lambda k: TriangleMetropolis(24, seed=1, kernel=k), 60),
        ("triangle N = 50", "triangle", lambda k: TriangleMetropolis(50, seed=1, kernel=k), 6),
        ("triangle N = 24, p_h = 0.3", "triangle", lambda k: TriangleMetropolis(24, seed=1, ph=0.3, kernel=k), 30),
        ("isotropic 8 x 17, F/p = 10", "packing",
         lambda k: PackingMetropolis(Scene(N=8, P=17, F=10.0, pv=1.0, ph=1.0), seed=1, kernel=k), 100),
        ("isotropic 8 x 17, F/p = 3", "packing",
         lambda k: PackingMetropolis(Scene(N=8, P=17, F=3.0, pv=1.0, ph=1.0), seed=1, kernel=k), 100),
        ("gravity 20 x 41, F/mg = 100", "packing",
         lambda k: PackingMetropolis(Scene(N=20, P=41, F=100.0, mg=1.0), seed=1, kernel=k), 10),
    ]
    print("| system | moves/sweep | reference ms/sweep (min) | compiled ms/sweep (min) | ratio | compiled ns/move | "
          "affected forces/move | floor ns/move | move/floor | same chain |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    for name, kind, make, ref_sweeps in configs:
        ref, fast = make("python"), make("compiled")
        ref.sweep(ref_sweeps // 5 + 1)  # leave the start, warm up
        fast.sweep(ref_sweeps // 5 + 1)
        G = len(ref.grains)
        r_med, r_min = timed(partial(ref.sweep, ref_sweeps), 3)
        fast_sweeps = max(ref_sweeps, int(ref_sweeps * 1.0 / max(r_med, 1e-3) * 40))  # ~1 s of compiled work
        c_med, c_min = timed(partial(fast.sweep, fast_sweeps), 5)
        r_ms, c_ms = 1e3 * r_med / ref_sweeps, 1e3 * c_med / fast_sweeps
        a, b = make("python"), make("compiled")
        same = np.array_equal(a.run(5, burn_in=2), b.run(5, burn_in=2)) and a.accepted == b.accepted
        floor, forces = floor_per_move(kind, fast)
        per_move = c_med / fast_sweeps / G
        print(f"| {name} | {G} | {r_ms:.2f} ({1e3 * r_min / ref_sweeps:.2f}) | {c_ms:.4f} ({1e3 * c_min / fast_sweeps:.4f}) | "
              f"{r_ms / c_ms:.0f}x | {1e9 * per_move:.0f} | {forces:.0f} | {1e9 * floor:.0f} | {per_move / floor:.1f} | "
              f"{'yes' if same else 'NO'} |", flush=True)


# --------------------------------------------------------------------- exact sampler


def bench_exact(Ns=(50, 100, 200, 500, 1000, 2000), reference_max=1000):
    from forcenet.numeric.triangle.exact_sampler import ExactSampler
    from forcenet.numeric.triangle.hook_walk import hook_walk_W

    ExactSampler(5, seed=0).sample_W(2)
    print("| N | d | compiled ms/sample (min) | walk steps/removal | ns per (removal + step) | "
          "reference s/sample | ratio |")
    print("| --- | --- | --- | --- | --- | --- | --- |")
    rows = []
    for N in Ns:
        d = N * (N - 1) // 2
        reps = max(3, int(2e6 // (N * N)))
        rng = np.random.default_rng(N)
        empty = np.zeros((0, N, N))
        stats = np.zeros(1, np.int64)
        med, mn = timed(partial(hook_walk_W, rng, N, 1, empty, empty, empty, np.zeros(0, np.int64), stats), reps)
        steps = stats[0] / (reps * d)
        ref = "-"
        ratio = "-"
        if N <= reference_max:
            K = max(1, min(64, int(2e7 // N**3)))
            sampler = ExactSampler(N, seed=1, kernel="python", batch=K)
            r_med, _ = timed(partial(sampler.sample_W, K), 1 if N >= 500 else 3)
            ref = f"{r_med / K:.3g}"
            ratio = f"{r_med / K / med:.0f}x"
        rows.append((N, med))
        print(f"| {N} | {d} | {1e3 * med:.2f} ({1e3 * mn:.2f}) | {steps:.2f} | {1e9 * med / (d * (1 + steps)):.0f} | "
              f"{ref} | {ratio} |", flush=True)
    Ns_, ts = np.array([r[0] for r in rows], float), np.array([r[1] for r in rows])
    slope = np.polyfit(np.log(Ns_), np.log(ts), 1)[0]
    local = [math.log(ts[k + 1] / ts[k]) / math.log(Ns_[k + 1] / Ns_[k]) for k in range(len(ts) - 1)]
    print(f"\ncost exponent over N = {int(Ns_[0])}..{int(Ns_[-1])}: {slope:.2f} (fit of log t on log N); "
          f"local: {', '.join(f'{x:.2f}' for x in local)}")
    d2 = ts / (Ns_**2 * np.log(Ns_))
    print("t / (N^2 ln N) in ns: " + ", ".join(f"{1e9 * x:.1f}" for x in d2))


# ------------------------------------------------------------------------- compile


SNIPPET = r"""
import time, numpy as np
from forcenet.numeric.triangle.metropolis import TriangleMetropolis
from forcenet.numeric.packing import PackingMetropolis, Scene
from forcenet.numeric.triangle.exact_sampler import ExactSampler
import forcenet.numeric.triangle.metropolis_kernel, forcenet.numeric.triangle.slice_kernel
import forcenet.numeric.triangle.hook_walk, forcenet.numeric.packing.kernels
t0 = time.perf_counter()
TriangleMetropolis(4, seed=0, kernel="compiled").sweep(1)
t1 = time.perf_counter()
PackingMetropolis(Scene(N=3, P=4, F=1.0, pv=1.0, ph=1.0), seed=0, kernel="compiled").sweep(1)
t2 = time.perf_counter()
ExactSampler(4, seed=0, kernel="compiled").mean_W(2)
t3 = time.perf_counter()
print(f"{t1 - t0:.2f} {t2 - t1:.2f} {t3 - t2:.2f}")
"""


def bench_compile():
    with tempfile.TemporaryDirectory() as cache:
        env = dict(os.environ, NUMBA_CACHE_DIR=cache, OMP_NUM_THREADS="1")
        print("| process | triangle Metropolis s | packing Metropolis s | exact sampler s |")
        print("| --- | --- | --- | --- |")
        for label in ("first (empty cache: compile)", "second (cached)", "third (cached)"):
            out = subprocess.run([sys.executable, "-c", SNIPPET], env=env, capture_output=True, text=True, check=True)
            print(f"| {label} | " + " | ".join(out.stdout.split()) + " |", flush=True)


if __name__ == "__main__":
    what = sys.argv[1] if len(sys.argv) > 1 else "metropolis"
    {"metropolis": bench_metropolis, "exact": bench_exact, "compile": bench_compile}[what]()
