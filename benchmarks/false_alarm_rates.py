"""Measured false-alarm rates and power of forcenet.testing on the project's own observables.

Level rows: many independent tables from a correct sampler (or chains of a
correct Markov chain), each compared with its exact means at ``alpha``; the
rate must be at most ``alpha``. ``(rate - alpha)/sd`` is in binomial standard
deviations at ``alpha``; ``runs`` counts the accepted runs (chains too short
are refused and not counted). The exact means come from the exact routes:
``mean_W`` (triangle), ``contact_gap_law(...).mean()`` (contact forces),
``exact_mean_W(scene)`` (packing), the enumerated component (chicken wire).

Routes: ``bounded`` is the default when bounds are given (betting,
:mod:`forcenet.numeric.betting`); ``t`` is the route without bounds, which
refuses fewer than ``T_MIN_ROWS`` independent rows; ``t, old`` is that route
with the refusal switched off (the behaviour before it, issue 28).

Power rows: a wrong sampler (a shift of +-0.05 on two grains of N = 6, the
q-model) and the fraction of tables it fails.

Bound rows (``--only bound``, issue 53): the distribution-free bound
(:mod:`forcenet.numeric.chebyshev`) decides alone where the size rule
refuses: its false alarms on correct tables the t route cannot judge
(``bound fired``: DISAGREES among them), and the power on heat-bath chains
whose uniform draw is biased to ``u**bias`` (:mod:`forcenet.testing.chains`).

Usage::

    OMP_NUM_THREADS=1 python benchmarks/false_alarm_rates.py            # ~40 min on the 2-core machine
    OMP_NUM_THREADS=1 python benchmarks/false_alarm_rates.py --quick    # ~5 min, 1/8 of the runs

Prints a Markdown table (notes/testing_against_exact.md).
"""

from __future__ import annotations

import argparse
import math
import time
from fractions import Fraction

import numpy as np
from scipy.special import ndtr
from scipy.stats import beta as beta_dist

import forcenet.numeric.size_rule as size_rule
from forcenet.exact import mean_W
from forcenet.numeric.autocorr import AutocorrError
from forcenet.numeric.triangle.exact_sampler import ExactSampler
from forcenet.numeric.triangle.metropolis import TriangleMetropolis, q_model_samples
from forcenet.testing import compare, exact_mean_W


def tables(draw, K, runs, chunk=200_000):
    """``runs`` independent tables of ``K`` rows from ``draw(n)`` (n rows at a time)."""
    per = max(1, chunk // K)
    done = 0
    while done < runs:
        n = min(per, runs - done)
        rows = draw(n * K)
        for r in range(n):
            yield rows[r * K:(r + 1) * K]
        done += n


def triangle(N, seed):
    sampler = ExactSampler(N, seed=seed)
    return lambda n: sampler.sample_W(n)


def contact_forces(N, seed):
    """(sqrt3/2) F5 and F6 of every grain of layers 1..N-1 (Eq. (3.8)): spacings of the partial sums."""
    sampler = ExactSampler(N, seed=seed)

    def draw(n):
        W = sampler.sample_W(n)
        S = np.concatenate([np.zeros((n, N, 1)), np.cumsum(W, axis=2)], axis=2)
        cols = []
        for i in range(1, N):
            for j in range(1, i + 1):
                cols.append(S[:, i, j] - S[:, i - 1, j - 1])  # F5 = S_{i+1,j} - S_{i,j-1}
                cols.append(S[:, i - 1, j] - S[:, i, j])  # F6 = S_{i,j} - S_{i+1,j}
        return np.stack(cols, axis=1)
    return draw


def contact_means(N):
    """Exact means: a spacing of d uniforms of rank gap g has mean E[g] / (d + 1) (order statistics)."""
    from forcenet.exact.triangle.gaps import contact_gap_law

    d = N * (N - 1) // 2
    return [contact_gap_law(N, (i, j), kind).mean() / (d + 1) for i in range(1, N) for j in range(1, i + 1)
            for kind in ("F5", "F6")]


def packing(scene, seed):
    from forcenet.numeric.packing import uniform_networks

    rng = np.random.default_rng(seed)
    return lambda n: uniform_networks(scene, n, rng)[0]


def packing_bounds(scene):
    """Each W of row i lies in [0, the row's load F + P pv + i P mg] (repulsive forces, load conservation)."""
    hi = [[float(scene.F + scene.P * scene.pv + (i + 1) * scene.P * scene.mg)] * scene.P for i in range(scene.N)]
    return 0.0, hi


def chicken_wire(seed):
    """Independent uniform draws from the enumerated component of the 12 x 12 honeycomb of side 2 (1230 foams)."""
    from forcenet.numeric.chicken_wire.monte_carlo import ChickenWire, component

    obs = np.array([c.observables() for c in component(ChickenWire.honeycomb(12, 12, side=2))])
    exact = [Fraction(int(v), len(obs)) for v in obs.sum(axis=0)]
    rng = np.random.default_rng(seed)
    return (lambda n: obs[rng.integers(len(obs), size=n)]), exact, (obs.min(axis=0), obs.max(axis=0))


def skewed_chain(seed, n, phi=0.9, a=1.0, b=8.0):
    """A bounded, skewed stationary chain: Beta(a, b) marginal through a Gaussian AR(1) (tau ~ 19 at phi 0.9)."""
    from scipy.signal import lfilter

    rng = np.random.default_rng(seed)
    e = rng.normal(size=n) * math.sqrt(1 - phi**2)
    e[0] /= math.sqrt(1 - phi**2)
    return beta_dist.ppf(ndtr(lfilter([1.0], [1.0, -phi], e)), a, b)


def rate(samples, exact, alpha, **options):
    """(DISAGREES verdicts, judged runs, runs refused: 'cannot judge' or a chain too short)."""
    rejected = accepted = refused = 0
    for x in samples:
        try:
            verdict = compare(x, exact, alpha=alpha, **options).verdict
        except AutocorrError:
            verdict = "cannot judge"
        refused += verdict == "cannot judge"
        accepted += verdict != "cannot judge"
        rejected += verdict == "DISAGREES"
    return rejected, accepted, refused


class Old:
    """The t route as before issue 45: no size rule (no refusal, no skewness charge)."""

    def __enter__(self):
        self.saved, size_rule._SKEW_RULE = size_rule._SKEW_RULE, False

    def __exit__(self, *exc):
        size_rule._SKEW_RULE = self.saved


def shifted(draw, N, grains, shift=0.05):
    """A wrong sampler: +shift on the first grain, -shift on the second (clipped to [0, 1])."""
    def wrong(n):
        W = draw(n).copy()
        (i, j), (k, m) = grains
        W[:, i - 1, j - 1] = np.clip(W[:, i - 1, j - 1] + shift, 0, 1)
        W[:, k - 1, m - 1] = np.clip(W[:, k - 1, m - 1] - shift, 0, 1)
        return W
    return wrong


CONTROLS = {  # unbounded skewed single values: (draw(rng, n), exact mean, skewness)
    "exponential": (lambda rng, n: rng.exponential(size=n), 1.0, 2.0),
    "lognormal, sigma = 0.5": (lambda rng, n: rng.lognormal(0.0, 0.5, size=n), math.exp(0.125), 1.75),
    "lognormal, sigma = 1": (lambda rng, n: rng.lognormal(0.0, 1.0, size=n), math.exp(0.5), 6.18),
    "normal": (lambda rng, n: rng.normal(size=n), 0.0, 0.0),
}


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--only", choices=["level", "t", "controls", "power", "chains", "bound"],
                        help="one part of the table")
    parser.add_argument("--seed", type=int, default=4500, help="base of the seeds (fresh seeds: another base)")
    args = parser.parse_args()
    k = 8 if args.quick else 1
    seed = args.seed
    print("| case | route | K | alpha | judged (cannot judge) | false alarms | rate / alpha +- sd | 95% upper | s |\n"
          "| --- | --- | --- | --- | --- | --- | --- | --- | --- |")

    def row(case, route, K, alpha, result, t0):
        rejected, accepted, refused = result
        n = max(accepted, 1)
        sd = math.sqrt(alpha * (1 - alpha) / n)  # the rate's binomial error at alpha
        upper = float(beta_dist.ppf(0.95, rejected + 1, n - rejected)) if accepted else 1.0  # Clopper-Pearson
        print(f"| {case} | {route} | {K} | {alpha:g} | {accepted} ({refused}) | {rejected} | "
              f"{rejected / n / alpha:.2f} +- {sd / alpha:.2f} | {upper / alpha:.2f} | {time.time() - t0:.0f} |",
              flush=True)

    def power(case, route, K, result, t0):
        rejected, accepted, refused = result
        total = accepted + refused
        p = rejected / max(total, 1)
        print(f"| {case} | {route} | {K} | 0.001 | {accepted} ({refused}) | caught {rejected} | "
              f"{p:.2f} +- {math.sqrt(p * (1 - p) / max(total, 1)):.2f} | | {time.time() - t0:.0f} |", flush=True)

    if args.only in (None, "level"):
        level = []
        for N, Ks in ((4, (20, 100)), (6, (10, 20, 100, 1000)), (10, (20, 200, 1000))):
            level += [(f"triangle W, N = {N}", triangle(N, seed + N), mean_W(N), {}, K) for K in Ks]
        level += [("contact forces F5, F6, N = 6", contact_forces(6, seed + 7), contact_means(6), {"bounds": (0, 1)}, K)
                  for K in (20, 100)]
        from forcenet.numeric.packing import Scene

        scene = Scene(N=3, P=4, F=10, j0=2, mg=1)
        level += [("packing N = 3, P = 4, F = 10, mg = 1", packing(scene, seed + 8), exact_mean_W(scene), {}, K)
                  for K in (20, 100)]
        draw, exact, bounds = chicken_wire(seed + 9)
        level += [("chicken wire, 12 x 12 component", draw, exact, {"bounds": bounds}, K) for K in (20, 100)]
        for case, draw, exact, options, K in level:
            for alpha, runs in ((1e-3, 8000), (0.01, 2000)):
                t0 = time.time()
                runs = runs if K > 10 else 500  # below the bounded test's smallest K: every table is refused
                runs = runs if K < 1000 else runs // 4
                row(case, "bounded", K, alpha, rate(tables(draw, K, runs // k), exact, alpha, **options), t0)
    if args.only in (None, "t"):  # the project's tables without their bounds (bounds=False): the t route
        for N, Ks in ((6, ((10, 500), (20, 500), (100, 500), (1000, 500), (2500, 4000), (5000, 2000))),
                      (10, ((200, 500), (1000, 500), (4000, 1500), (8000, 1000)))):
            for K, runs in Ks:
                for alpha in (1e-3, 0.01):
                    t0 = time.time()
                    row(f"triangle W, N = {N}", "t", K, alpha,
                        rate(tables(triangle(N, seed + 300 + N), K, runs // k), mean_W(N), alpha, bounds=False), t0)
        with Old():
            for N, K in ((6, 20), (6, 100), (10, 200)):
                for alpha in (1e-3, 0.01):
                    t0 = time.time()
                    row(f"triangle W, N = {N}", "t, old", K, alpha,
                        rate(tables(triangle(N, seed + 500 + N), K, 4000 // k), mean_W(N), alpha, bounds=False), t0)
    if args.only in (None, "controls"):  # unbounded skewed values: no bounds exist, only the t route
        for name, (draw, exact, skew) in CONTROLS.items():
            rng = np.random.default_rng(seed + 600 + len(name))
            for K in (10, 20, 100, 1000):
                for alpha, runs in ((1e-3, 8000), (0.01, 4000)):
                    t0 = time.time()
                    row(f"{name} (skewness {skew:g}), one value", "t", K, alpha,
                        rate(tables(lambda n, draw=draw, rng=rng: draw(rng, n), K, runs // k), exact, alpha), t0)
    if args.only in (None, "chains"):
        exact = beta_dist.mean(1.0, 8.0)
        for n_over_tau in (210, 1000):
            for alpha, runs in ((1e-3, 4000), (0.01, 2000)):
                t0 = time.time()
                chains = (skewed_chain(seed + s, 19 * n_over_tau) for s in range(runs // k))
                row(f"Beta(1, 8) chain, tau = 19, {n_over_tau} tau", "t, batch means", "10-50", alpha,
                    rate(chains, exact, alpha, chain=True, bounds=(0, 1)), t0)
        for alpha, runs in ((0.05, 400), (0.01, 800)):
            t0 = time.time()
            chains = (TriangleMetropolis(4, seed=seed + s).run(sweeps=2500) for s in range(runs // k))
            row("Metropolis N = 4 (9 values), 2500 sweeps", "t, batch means", "10-50", alpha,
                rate(chains, mean_W(4), alpha, chain=True), t0)
    if args.only in (None, "power"):
        N = 6
        for grains in (((5, 2), (5, 3)), ((4, 1), (4, 2))):
            for K in (100, 200, 400):
                wrong = shifted(triangle(N, seed + 700 + K), N, grains)
                case = f"shift +-0.05 on {grains[0]}, {grains[1]}, N = 6"
                t0 = time.time()
                power(case, "bounded", K, rate(tables(wrong, K, 500 // k), mean_W(N), 1e-3), t0)
                with Old():
                    t0 = time.time()
                    power(case, "t, old", K, rate(tables(wrong, K, 500 // k), mean_W(N), 1e-3, bounds=False), t0)
            wrong = shifted(triangle(N, seed + 800), N, grains, shift=0.015)
            t0 = time.time()
            power(f"shift +-0.015 on {grains[0]}, {grains[1]}, N = 6", "t", 2500,
                  rate(tables(wrong, 2500, 200 // k), mean_W(N), 1e-3, bounds=False), t0)
            t0 = time.time()
            power(f"shift +-0.015 on {grains[0]}, {grains[1]}, N = 6", "bounded", 2500,
                  rate(tables(wrong, 2500, 200 // k), mean_W(N), 1e-3), t0)
        rng = np.random.default_rng(seed + 11)
        for K in (20, 50, 100):
            t0 = time.time()
            power("q-model, N = 6", "bounded", K, rate(tables(lambda n: q_model_samples(N, n, rng), K, 500 // k),
                                                          mean_W(N), 1e-3), t0)
            with Old():
                t0 = time.time()
                power("q-model, N = 6", "t, old", K, rate(tables(lambda n: q_model_samples(N, n, rng), K, 500 // k),
                                                           mean_W(N), 1e-3, bounds=False), t0)
        t0 = time.time()

        def biased(s):
            chain = TriangleMetropolis(4, seed=seed + s).run(sweeps=3000, burn_in=100)
            chain[:, 3, 0] += 0.02  # W_41 + 0.02: about 5 standard errors
            return chain
        power("Metropolis N = 4, W_41 + 0.02", "t, batch means", "10-50",
              rate((biased(s) for s in range(200 // k)), mean_W(4), 1e-3, chain=True, bounds=False), t0)

    if args.only in (None, "bound"):
        bound(seed, k, row, power)


def bound(seed, k, row, power):
    """The bound's rows: level where only it speaks, power on heat-bath chains with large biases."""
    from forcenet.testing.chains import heat_bath_W

    def fired(samples, exact, alpha, **options):
        """(bound fired: DISAGREES while the size rule refuses, tables the size rule refused, judged tables)."""
        hits = refused = judged = 0
        for x in samples:
            try:
                report = compare(x, exact, alpha=alpha, **options)
            except AutocorrError:  # a chain too short for its guard: no verdict at all
                continue
            refused += not report.judged
            judged += report.judged
            hits += (not report.judged) and report.disagrees
        return hits, refused, judged

    for N, K in ((6, 20), (6, 100), (6, 1000)):
        for alpha in (1e-3, 0.01):
            t0 = time.time()
            row(f"triangle W, N = {N} (bound alone)", "t + bound", K, alpha,
                fired(tables(triangle(N, seed + 900 + K), K, 2000 // k), mean_W(N), alpha, bounds=False), t0)
    for name, (draw, exact, skew) in CONTROLS.items():
        rng = np.random.default_rng(seed + 950 + len(name))
        for K in (10, 100):
            t0 = time.time()
            row(f"{name} (skewness {skew:g}) (bound alone)", "t + bound", K, 1e-3,
                fired(tables(lambda n, draw=draw, rng=rng: draw(rng, n), K, 4000 // k), exact, 1e-3), t0)
    for sweeps in (5000, 20000):
        t0 = time.time()
        chains = (heat_bath_W(6, sweeps, seed + 1000 + s) for s in range(160 // k))
        row(f"heat bath N = 6, {sweeps} sweeps, correct", "t + bound", "10-50", 1e-3,
            fired(chains, mean_W(6), 1e-3, chain=True), t0)
    for bias in (1.03, 1.1, 1.2, 1.3, 1.6, 2.0):
        t0 = time.time()
        chains = (heat_bath_W(6, 20000, seed + 1100 + s, bias) for s in range(80 // k))
        power(f"heat bath N = 6, 20000 sweeps, u**{bias:g}", "t + bound", "10-50",
              rate(chains, mean_W(6), 1e-3, chain=True), t0)


if __name__ == "__main__":
    main()
