"""Every floor load's exact variance against N, beside the GOE spacing's (issue 27; notes/force_distribution.md Sec. 6.7).

For each N: every floor load's exact gap law (``floor_gap_laws``, de Bruijn
Pfaffians, checkpointed), then for each load ``W_{N,j}`` its exact mean and
variance (``E[W] = E[g]/(d+1)``, ``E[W^2] = E[g(g+1)]/((d+1)(d+2))``) and the
normalized variance ``Var(W)/E[W]^2`` (exact rationals, printed correctly
rounded), the wall time and the SHA-256 of the gap counts.  Results
accumulate in a JSON file (atomic rewrite); N already there is skipped.

The limit: a floor load at position ``x`` is a GOE nearest-neighbour spacing
on the scale of its mean (Sec. 6.6), so its normalized variance tends to the
GOE's ``E[s^2] - 1`` = 0.2855306557 (``benchmarks/goe_spacing.py``) for
every ``x`` inside ``(0, 1)``.  With ``--figure PNG``: the centre's
normalized variance against ``1/N`` and the profile against ``x``.

Usage::

    python benchmarks/floor_variance.py --N 12 16 20 24 28 32 36 40 --out floor_variance.json --checkpoint ckpt
    python benchmarks/floor_variance.py --N 20 --out floor_variance.json --figure floor_variance.png
"""

from __future__ import annotations

import argparse
import hashlib
import json
import os
import time
from fractions import Fraction

from forcenet.exact.triangle.de_bruijn.floor import floor_gap_laws
from forcenet.exact.triangle.staircase import dimension

GOE_NORMALIZED_VARIANCE = 0.2855306557  # E_GOE[s^2] - 1, benchmarks/goe_spacing.py (Bornemann's determinant)


def moments(law, d: int) -> tuple[Fraction, Fraction]:
    """Exact ``(E[W], Var W)`` of a load from its gap law (Dirichlet spacings given the ranks)."""
    total = law.total
    mean = Fraction(sum(g * c for g, c in enumerate(law.counts)), total * (d + 1))
    second = Fraction(sum(g * (g + 1) * c for g, c in enumerate(law.counts)), total * (d + 1) * (d + 2))
    return mean, second - mean * mean


def summary(N: int, laws: dict) -> dict:
    d = dimension(N)
    rows = []
    digest = hashlib.sha256()
    for j in range(1, N + 1):
        mean, var = moments(laws[j], d)
        rows.append({"j": j, "mean": float(mean), "var": float(var), "normalized_var": float(var / (mean * mean))})
        digest.update(repr(laws[j].counts).encode())
    return {"loads": rows, "sha256": digest.hexdigest()}


def write_atomic(path: str, data: dict) -> None:
    tmp = f"{path}.tmp{os.getpid()}"
    with open(tmp, "w") as fh:
        json.dump(data, fh, indent=1, sort_keys=True)
        fh.flush()
        os.fsync(fh.fileno())
    os.replace(tmp, path)


def figure(data: dict, path: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    Ns = sorted(int(N) for N in data)
    fig, (left, right) = plt.subplots(1, 2, figsize=(10, 4))
    for N in Ns:
        loads = data[str(N)]["loads"]
        right.plot([(r["j"] - 0.5) / N for r in loads], [r["normalized_var"] for r in loads], ".-", ms=3, lw=0.7,
                   label=f"N = {N}")
    right.axhline(GOE_NORMALIZED_VARIANCE, color="k", ls="--", lw=0.8, label="GOE spacing")
    right.set_xlabel("x = (j - 1/2)/N")
    right.set_ylabel("Var(W_{N,j}) / <W_{N,j}>^2")
    right.set_ylim(0.2, 1.05)
    right.legend(fontsize=7)
    centre = [data[str(N)]["loads"][N // 2 - 1]["normalized_var"] if N % 2 == 0 else
              data[str(N)]["loads"][N // 2]["normalized_var"] for N in Ns]
    inv2 = [1 / N**2 for N in Ns]
    left.plot(inv2, centre, "o", label="exact, central load")
    slope = sum((GOE_NORMALIZED_VARIANCE - c) * N**2 for c, N in zip(centre, Ns) if N >= 24) / sum(N >= 24 for N in Ns)
    left.plot([0, max(inv2)], [GOE_NORMALIZED_VARIANCE, GOE_NORMALIZED_VARIANCE - slope * max(inv2)], "-", lw=0.7,
              label=f"GOE - {slope:.2f}/N^2 (mean over N >= 24)")
    left.axhline(GOE_NORMALIZED_VARIANCE, color="k", ls="--", lw=0.8, label="GOE spacing (N = oo)")
    left.set_xlabel("1/N^2")
    left.set_ylabel("normalized variance")
    left.set_xlim(left=0)
    left.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=130)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--N", type=int, nargs="+", required=True)
    parser.add_argument("--out", required=True)
    parser.add_argument("--checkpoint", default=None, help="checkpoint directory (default: the user's cache)")
    parser.add_argument("--workers", type=int, default=None)
    parser.add_argument("--figure", default=None)
    args = parser.parse_args()
    data = json.load(open(args.out)) if os.path.exists(args.out) else {}
    for N in args.N:
        if str(N) in data:
            continue
        start = time.time()
        laws = floor_gap_laws(N, workers=args.workers, checkpoint=args.checkpoint)
        entry = summary(N, laws)
        entry["wall_seconds"] = round(time.time() - start, 1)
        data[str(N)] = entry
        write_atomic(args.out, data)
        mid = entry["loads"][N // 2 - 1] if N % 2 == 0 else entry["loads"][N // 2]
        print(f"N={N}: central load normalized variance {mid['normalized_var']:.6f} "
              f"(GOE {GOE_NORMALIZED_VARIANCE}), {entry['wall_seconds']} s", flush=True)
    if args.figure:
        figure(data, args.figure)


if __name__ == "__main__":
    main()
