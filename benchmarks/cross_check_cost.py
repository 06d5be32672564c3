"""CPU seconds per stored value of forcenet.testing.compare as the main job's cross-check calls it (bounds (0, 1)).

    python benchmarks/cross_check_cost.py

The constant CROSS_CHECK_SECONDS_PER_VALUE of forcenet.testing.cross_check is checked against this.
"""
import time
from fractions import Fraction

import numpy as np

from forcenet.exact.triangle.moments import mean_W
from forcenet.numeric.triangle.exact_sampler import ExactSampler
from forcenet.testing import compare

for N, rows in ((20, 20000), (40, 20000)):
    grains = [(i, j) for i in range(2, N + 1) for j in range(1, i)]
    sampler = ExactSampler(N, seed=1)
    W = np.concatenate([sampler.sample_W(min(sampler.batch, rows - k)) for k in range(0, rows, sampler.batch)])
    X = np.stack([W[:, i - 1, j - 1] for i, j in grains], axis=1)
    exact = [Fraction(float(x)) for x in X.mean(axis=0)] if N > 24 else [mean_W(N)[i - 1][j - 1] for i, j in grains]
    c0 = time.process_time()
    compare(X, exact, keys=grains, bounds=(0, 1))
    cpu = time.process_time() - c0
    print(f"N={N}: {rows} rows x {len(grains)} grains: {cpu:.2f} s CPU, {cpu / X.size * 1e9:.0f} ns per value")
