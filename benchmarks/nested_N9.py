"""The nested-matrix integration at N = 9 for a few grains, against the exact core.

Run:  python benchmarks/nested_N9.py [grain ...]      (grain as i,j; default 5,3 8,1 9,5)
One integration at N = 9 takes ~6 min and ~19 GB; the normalization is
integrated once and reused.  Prints one line per grain (used in notes/chapter4.md).
"""

import resource
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from exact import mean_W  # noqa: E402
from exact.nested import integrate_layers  # noqa: E402

N = 9
grains = [tuple(int(x) for x in g.split(",")) for g in sys.argv[1:]] or [(5, 3), (8, 1), (9, 5)]
exact = mean_W(N)
t0 = time.perf_counter()
Z = integrate_layers(N)
print(f"N = {N}: normalization {Z} ({time.perf_counter() - t0:.0f} s)", flush=True)
for i, j in grains:
    t = time.perf_counter()
    value = integrate_layers(N, {(i, j): 1}) / Z
    rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1e6
    print(f"<W_{i},{j}> nested = {value}, exact core = {exact[i - 1][j - 1]}, equal: {value == exact[i - 1][j - 1]} "
          f"({time.perf_counter() - t:.0f} s, peak RSS {rss:.1f} GB)", flush=True)
