"""The whole <W> table on the thesis's integer route at N = 12 (issue 3), against the exact core.

Run:  python benchmarks/gamma_table.py [N] [--workers 2]        (default N = 12)

Bulk grains ``r >= 2`` by the Gamma recursion (4.73)-(4.77) with the last row
summed as a chain (``forcenet.exact.thesis.gamma_bulk_integer``, ~3 min and 6-20 GB per
grain at N = 12), the left boundary by (4.67) (``forcenet.exact.thesis.boundary_mean_W``),
the bottom layer from the layer above.  Every grain is computed directly (the
left-right mirror symmetry is *checked*, not used).  Results are appended to
``out/gamma_table_N{N}.json`` after each grain (atomic rewrite), so an
interrupted run resumes where it stopped.  Prints one line per grain and a
summary with the ratio of times against the exact core.
"""

import argparse
import json
import os
import resource
import tempfile
import time
from multiprocessing import Pool
from pathlib import Path

from forcenet.exact import mean_W
from forcenet.exact.thesis.recursions import gamma_bulk_integer, table_from_bulk

ROOT = Path(__file__).resolve().parents[1]


def one_grain(args):
    N, q, r = args
    t = time.perf_counter()
    X = gamma_bulk_integer(N, q, r)
    rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1e6
    return q, r, str(X), time.perf_counter() - t, rss


def save(path: Path, data: dict) -> None:
    fd, tmp = tempfile.mkstemp(dir=path.parent, suffix=".tmp")
    with os.fdopen(fd, "w") as f:
        json.dump(data, f, indent=1)
    os.replace(tmp, path)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("N", type=int, nargs="?", default=12)
    ap.add_argument("--workers", type=int, default=2)
    args = ap.parse_args()
    N = args.N
    out = ROOT / "out" / f"gamma_table_N{N}.json"
    out.parent.mkdir(exist_ok=True)
    data = json.loads(out.read_text()) if out.exists() else {"N": N, "bulk": {}, "seconds": {}, "rss_GB": {}}
    # representatives of the mirror orbits (larger r: smaller boxes) first, then their mirrors
    grains = []
    for q in range(1, N - 1):
        i = N - q
        for r in sorted(range(2, i + 1), key=lambda r: (r < i + 1 - r, -r)):
            grains.append((q, r))
    grains.sort(key=lambda g: (g[1] < N - g[0] + 1 - g[1]) or g[1] == N - g[0])
    todo = [(N, q, r) for q, r in grains if f"{q},{r}" not in data["bulk"]]
    print(f"N = {N}: {len(todo)} bulk grains to compute (~3 min and 6-20 GB each at N = 12), {args.workers} workers",
          flush=True)
    t0 = time.perf_counter()
    with Pool(args.workers) as pool:
        for q, r, X, sec, rss in pool.imap_unordered(one_grain, todo):
            data["bulk"][f"{q},{r}"] = X
            data["seconds"][f"{q},{r}"] = round(sec, 1)
            data["rss_GB"][f"{q},{r}"] = round(rss, 2)
            save(out, data)
            print(f"  grain (q, r) = ({q}, {r}): {sec:.0f} s, peak RSS {rss:.1f} GB", flush=True)
    print(f"bulk done in {time.perf_counter() - t0:.0f} s", flush=True)

    t = time.perf_counter()
    exact = mean_W(N)
    t_core = time.perf_counter() - t
    t = time.perf_counter()
    rows = table_from_bulk(N, lambda q, r: int(data["bulk"][f"{q},{r}"]))  # (4.67) + bottom layer
    t_boundary = time.perf_counter() - t
    table = {(i, r): rows[i - 1][r - 1] for i in range(1, N + 1) for r in range(1, i + 1)}
    wrong = [g for g, v in table.items() if v != exact[g[0] - 1][g[1] - 1]]
    mirror = all(table[(i, r)] == table[(i, i + 1 - r)] for i, r in table)
    bulk_seconds = sum(data["seconds"].values())
    print(f"N = {N}: {len(table)} grains, equal to the exact core: {not wrong} {wrong[:5]}; mirror symmetric: {mirror}")
    print(f"time: bulk {bulk_seconds:.0f} s (sum over grains), boundary + normalization {t_boundary:.0f} s, "
          f"exact core {t_core:.3f} s; ratio {(bulk_seconds + t_boundary) / t_core:.3g}x; "
          f"peak RSS per grain {max(data['rss_GB'].values()):.1f} GB")
    data["check"] = {"equal_to_exact_core": not wrong, "mirror_symmetric": mirror, "boundary_seconds": round(t_boundary),
                     "core_seconds": t_core}
    save(out, data)


if __name__ == "__main__":
    main()
