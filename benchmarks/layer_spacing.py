"""The local load law of the layers just above the floor, exactly: GOE on the floor, and one layer up? (issue 27).

For each N and each offset K: every load of layer ``N - K`` by its exact gap
law (``layer_gap_laws``, de Bruijn Pfaffians, checkpointed; the floor's
``floor_gap_laws`` for K = 0), and for each load ``W`` its exact mean ``mu``,
normalized variance ``Var W / mu^2`` and ``mu E[1/W]`` (``E[1/s]`` of the
normalized load ``s = W/mu``; ``E[1/W] = sum_g P(g) d/(g - 1)``), printed
for the central load.  Results accumulate in a JSON file (atomic rewrite).

The references, computed here from the Fredholm determinants of the bulk
spacing laws (Gaudin; Bornemann's Nystrom method): the GOE's ``E[s^2] - 1``
= 0.28553 and ``E[1/s]`` = 1.59161 (``benchmarks/goe_spacing.py``), the
GUE's from ``det(I - K_sine)`` on ``(0, s)``.  ``E[1/s]`` of layer
``N - 1`` fixes the slope of the contacts' ``P(0) ~ (2 E[1/s]/pi^2) ln N``
(``benchmarks/contact_plateau.py``, notes/force_distribution.md Sec. 6.2).

Usage::

    python benchmarks/layer_spacing.py --N 12 16 20 24 28 --above 0 1 2 --out layer_spacing.json --checkpoint ckpt
    python benchmarks/layer_spacing.py --reference
    python benchmarks/layer_spacing.py --out layer_spacing.json --figure layer_spacing.png
"""

from __future__ import annotations

import argparse
import json
import os
import time
from fractions import Fraction

import numpy as np

from forcenet.exact.triangle.de_bruijn.floor import floor_gap_laws
from forcenet.exact.triangle.de_bruijn.layers import layer_gap_laws
from forcenet.exact.triangle.staircase import dimension

GOE = {"normalized_var": 0.2855306557, "mean_inverse": 1.59161}  # benchmarks/goe_spacing.py


def gue_reference(m: int = 40, h: float = 1e-3) -> dict:
    """The GUE bulk spacing's ``E[s^2] - 1`` and ``E[1/s]``: ``p_2 = E''``, ``E(s) = det(I - K_sine)`` on ``(0, s)``
    (Gauss-Legendre Nystrom, ``m`` nodes; the second derivative by central differences of step ``h``)."""
    from scipy.integrate import quad

    x, w = np.polynomial.legendre.leggauss(m)

    def gap(s: float) -> float:
        u, v = s * (x + 1) / 2, s * w / 2
        z = u[:, None] - u[None, :]
        K = np.where(z == 0, 1.0, np.sin(np.pi * z) / (np.pi * np.where(z == 0, 1.0, z)))
        root = np.sqrt(np.outer(v, v))
        return float(np.linalg.det(np.eye(m) - root * K))

    def p(s: float) -> float:
        return (gap(s + h) - 2 * gap(s) + gap(s - h)) / (h * h) if s > h else (np.pi**2 / 3) * s * s

    second = quad(lambda s: s * s * p(s), 0, 6, limit=200)[0]
    inverse = quad(lambda s: p(s) / s, 0, 6, limit=200)[0]
    return {"normalized_var": second - 1, "mean_inverse": inverse}


def load_numbers(law, d: int) -> dict:
    """Exact mean, normalized variance and ``mu E[1/W]`` of a load from its gap law (Dirichlet spacings)."""
    total = law.total
    mean = Fraction(sum(g * c for g, c in enumerate(law.counts)), total * (d + 1))
    second = Fraction(sum(g * (g + 1) * c for g, c in enumerate(law.counts)), total * (d + 1) * (d + 2))
    inverse = Fraction(sum(c * d * Fraction(1, g - 1) for g, c in enumerate(law.counts) if c), total) \
        if law.counts[1] == 0 else None
    return {"mean": float(mean), "normalized_var": float((second - mean * mean) / (mean * mean)),
            "mean_inverse": float(mean * inverse) if inverse is not None else None}


def write_atomic(path: str, data: dict) -> None:
    """The JSON file, written all or nothing (the command line's writer)."""
    from forcenet.cli.output import write_files

    write_files({path: json.dumps(data, indent=1, sort_keys=True)}, name="--out")


def figure(data: dict, path: str) -> None:
    """Left: the central load's normalized variance against the layer's height above the floor, one line per N, with
    the GOE and GUE values; right: the same for ``mu E[1/W]``."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    gue = gue_reference()
    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    for N in sorted({v["N"] for v in data.values()}):
        rows = sorted((N - v["layer"], v["loads"][(v["layer"] - 1) // 2]) for v in data.values() if v["N"] == N)
        for ax, key in zip(axes, ("normalized_var", "mean_inverse")):
            ax.plot([K for K, _ in rows], [c[key] for _, c in rows], "o-", ms=4, lw=0.8, label=f"N = {N}")
    for ax, key, label in zip(axes, ("normalized_var", "mean_inverse"), ("Var(W)/<W>^2", "<W> E[1/W]")):
        ax.axhline(GOE[key], color="k", ls="--", lw=0.8, label="GOE spacing")
        ax.axhline(gue[key], color="k", ls=":", lw=0.8, label="GUE spacing")
        ax.set(xlabel="K: layer N - K (0 = the floor)", ylabel=f"{label}, central load")
        ax.legend(fontsize=7)
    fig.suptitle("exact local load law: GOE on the floor, GUE a few layers up")
    fig.tight_layout()
    fig.savefig(path, dpi=130)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--N", type=int, nargs="+", default=[])
    parser.add_argument("--above", type=int, nargs="+", default=[1], help="offsets K: layer N - K (0: the floor)")
    parser.add_argument("--out", default=None)
    parser.add_argument("--checkpoint", default=None)
    parser.add_argument("--reference", action="store_true", help="print the GOE and GUE reference numbers")
    parser.add_argument("--figure", default=None, help="PNG: the central load against the height above the floor")
    args = parser.parse_args()
    if args.reference:
        print("GOE", GOE)
        print("GUE", {k: round(v, 5) for k, v in gue_reference().items()})
    data = json.load(open(args.out)) if args.out and os.path.exists(args.out) else {}
    for N in args.N:
        for K in args.above:
            key = f"{N},{K}"
            if key in data or not 0 <= K <= N - 2:
                continue
            start = time.time()
            i, d = N - K, dimension(N)
            laws = floor_gap_laws(N, checkpoint=args.checkpoint) if K == 0 else \
                layer_gap_laws(N, i, checkpoint=args.checkpoint)
            loads = [dict(load_numbers(laws[j], d), j=j) for j in range(1, i + 1)]
            data[key] = {"N": N, "layer": i, "loads": loads, "wall_seconds": round(time.time() - start, 1)}
            if args.out:
                write_atomic(args.out, data)
            c = loads[(i - 1) // 2]
            print(f"N={N} layer {i}: central load Var/mu^2 = {c['normalized_var']:.5f}, "
                  f"mu E[1/W] = {c['mean_inverse']:.5f}; {data[key]['wall_seconds']} s", flush=True)
    if args.figure:
        figure(data, args.figure)


if __name__ == "__main__":
    main()
