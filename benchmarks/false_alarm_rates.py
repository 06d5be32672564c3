"""Measured false-alarm rates of forcenet.testing: correct samplers, many seeds, against the stated level.

Each row: a correct sampler (or a synthetic process with known mean), the
level ``alpha``, the number of accepted runs (chains too short are refused,
not counted), the rejection rate and its binomial standard deviation at
``alpha``. The promise (forcenet.numeric.agreement): at most ``alpha``, equal
to it for a single value. The ``naive`` rows show what the two design choices
remove: ``tau`` measured on the whole chain (the batches then depend on it)
and no gaps between batches.

Usage::

    python benchmarks/false_alarm_rates.py            # ~10 min on the 2-core machine
    python benchmarks/false_alarm_rates.py --quick    # ~1 min, fewer runs

Prints a Markdown table (notes/testing_against_exact.md).
"""

from __future__ import annotations

import argparse
import math
import time
import warnings

import numpy as np
from scipy.signal import lfilter
from scipy.stats import t as t_dist

from forcenet.exact import mean_W
from forcenet.numeric.autocorr import AutocorrError, integrated_time
from forcenet.numeric.triangle.exact_sampler import ExactSampler
from forcenet.numeric.triangle.metropolis import TriangleMetropolis
from forcenet.testing import compare


def ar1(rng, n, phi):
    e = rng.normal(size=n) * math.sqrt(1 - phi**2)
    e[0] /= math.sqrt(1 - phi**2)
    return lfilter([1.0], [1.0, -phi], e)


def rate(runs, make, exact, alpha, chain=False, **batching):
    rejected = accepted = 0
    for r in range(runs):
        try:
            rejected += not compare(make(r), exact, chain=chain, alpha=alpha, **batching).passed
            accepted += 1
        except AutocorrError:
            pass
    return rejected, accepted


def naive_chain_rate(runs, phi, n, alpha):
    """The rejected design: tau on the whole chain, 10 contiguous batches of n/10 >= 10 tau (refused otherwise)."""
    rejected = accepted = 0
    for r in range(runs):
        x = ar1(np.random.default_rng(r), n, phi)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            tau = integrated_time(x, quiet=True)[0]
        if n < 100 * tau:
            continue
        m = x.reshape(10, -1).mean(axis=1)
        t = m.mean() / (m.std(ddof=1) / math.sqrt(10))
        rejected += abs(t) > t_dist.ppf(1 - alpha / 2, 9)
        accepted += 1
    return rejected, accepted


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--quick", action="store_true")
    args = parser.parse_args()
    k = 5 if args.quick else 1
    rows = []

    def row(name, alpha, result, seconds):
        rejected, accepted = result
        r = rejected / max(accepted, 1)
        sd = math.sqrt(alpha * (1 - alpha) / max(accepted, 1))
        rows.append(f"| {name} | {alpha:g} | {accepted} | {r:.4f} | {(r - alpha) / sd:+.1f} | {seconds:.0f} |")
        print(rows[-1], flush=True)

    cases = [
        ("one normal value, K = 30", 0.05, 20000 // k, lambda s: np.random.default_rng(s).normal(size=30), 0.0, False),
        ("20 independent normal values, K = 300", 0.05, 10000 // k,
         lambda s: np.random.default_rng(s).normal(size=(300, 20)), np.zeros(20), False),
        ("20 normal values, correlation 0.9, K = 300", 0.05, 10000 // k,
         lambda s: (lambda g: math.sqrt(0.1) * g.normal(size=(300, 20)) + math.sqrt(0.9) * g.normal(size=(300, 1)))(
             np.random.default_rng(s)), np.zeros(20), False),
        ("30 independent normal values, K = 400", 1e-3, 20000 // k,
         lambda s: np.random.default_rng(s).normal(size=(400, 30)), np.zeros(30), False),
        ("exact sampler N = 6 (20 values), K = 1000", 0.01, 5000 // k,
         lambda s: ExactSampler(6, seed=s).sample_W(1000), mean_W(6), False),
        ("AR(1) tau = 19, 210 tau (just above refusal)", 0.05, 6000 // k,
         lambda s: ar1(np.random.default_rng(s), 3990, 0.9), 0.0, True),
        ("AR(1) tau = 19, 1000 tau", 0.01, 6000 // k, lambda s: ar1(np.random.default_rng(s), 19000, 0.9), 0.0, True),
        ("Metropolis N = 4 (9 values), 2500 sweeps", 0.05, 300 // k,
         lambda s: TriangleMetropolis(4, seed=s).run(sweeps=2500), mean_W(4), True),
    ]
    print("| sampler | alpha | runs | rate | (rate - alpha)/sd | s |\n| --- | --- | --- | --- | --- | --- |")
    for name, alpha, runs, make, exact, chain in cases:
        t0 = time.time()
        row(name, alpha, rate(runs, make, exact, alpha, chain), time.time() - t0)
    t0 = time.time()
    row("no gaps (gap_factor=0): AR(1) tau = 19, 300 tau", 0.05,
        rate(6000 // k, lambda s: ar1(np.random.default_rng(s), 5700, 0.9), 0.0, 0.05, True, gap_factor=0), time.time() - t0)
    t0 = time.time()
    row("naive: AR(1) tau = 19, 100 tau, tau on the whole chain, no gaps", 0.05,
        naive_chain_rate(6000 // k, 0.9, 1900, 0.05), time.time() - t0)


if __name__ == "__main__":
    main()
