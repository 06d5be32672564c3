"""The contact forces above the floor, exactly, to N = 48: the ln N question of notes/force_distribution.md Sec. 6.2.

For each N: layer ``N - 1``'s pooled exact gap law (``layer_pooled_gap_law``,
de Bruijn Pfaffians, checkpointed; the DP below N = 20), then the exact
pooled gap law of the ``2(N - 1)`` contacts between layers ``N - 1`` and
``N`` (``floor_contact_gap_law``: the floor point between two layer
``N - 1`` points is uniform between them), and from it

* ``P(0)`` of ``f = F/<F>`` over those contacts, an exact rational
  (``<c> d P(gap = 1)``, ``<c> = 1/(2(N - 1))``), printed correctly rounded;
* ``P(f)`` at a few ``f`` (float, from the exact law);
* the layer ``N - 1`` loads' pooled normalized variance, exactly.

Results accumulate in a JSON file (atomic rewrite; the gap counts of layer
``N - 1`` are kept as decimal strings with their SHA-256); N already there is
skipped.  With ``--figure PNG``: ``P(0)`` against ``ln N`` and ``P(f)``.

Usage::

    python benchmarks/contact_plateau.py --N 8 12 16 20 24 28 32 36 40 44 48 --out contacts.json --checkpoint ckpt
    python benchmarks/contact_plateau.py --N 8 --out contacts.json --figure contact_plateau.png
"""

from __future__ import annotations

import argparse
import hashlib
import json
import math
import os
import time
from fractions import Fraction

import numpy as np

from forcenet.exact.triangle.gaps import GapCounts
from forcenet.exact.triangle.law_routes import floor_contact_gap_law, layer_gap_law, layer_route
from forcenet.exact.triangle.staircase import dimension

F_VALUES = (0.0, 0.05, 0.1, 0.25, 0.5, 1.0, 2.0, 3.0)


def contact_density(law: GapCounts, N: int, f: float) -> float:
    """``P(f)`` of ``f = c/<c>`` over the contacts, from their exact gap law (a Beta mixture)."""
    from scipy.stats import beta

    d = law.d
    mean = 1.0 / (2 * (N - 1))
    weights = [Fraction(c, law.total) for c in law.counts]
    return mean * sum(float(wt) * beta.pdf(f * mean, g, d + 1 - g) for g, wt in enumerate(weights) if wt and g >= 1)


def summary(N: int, layer: GapCounts) -> dict:
    d = dimension(N)
    contacts = floor_contact_gap_law(N, layer)
    p0 = Fraction(d * contacts.counts[1], contacts.total) / (2 * (N - 1))
    mean = Fraction(sum(g * c for g, c in enumerate(layer.counts)), layer.total * (d + 1))
    second = Fraction(sum(g * (g + 1) * c for g, c in enumerate(layer.counts)), layer.total * (d + 1) * (d + 2))
    digest = hashlib.sha256(repr(layer.counts).encode()).hexdigest()
    return {"P0": f"{p0.numerator}/{p0.denominator}" if N <= 12 else None, "P0_float": float(p0),
            "P_f": {str(f): contact_density(contacts, N, f) for f in F_VALUES[1:]},
            "layer_normalized_var": float((second - mean * mean) / (mean * mean)),
            "layer_counts": [str(c) for c in layer.counts], "layer_total": str(layer.total), "sha256": digest}


def write_atomic(path: str, data: dict) -> None:
    """The JSON file, written all or nothing (the command line's writer)."""
    from forcenet.cli.output import write_files

    write_files({path: json.dumps(data, indent=1, sort_keys=True)}, name="--out")


def figure(data: dict, path: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    Ns = sorted(int(n) for n in data)
    p0 = [data[str(n)]["P0_float"] for n in Ns]
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(10, 4))
    ax.plot(np.log(Ns), p0, "o-", label="exact")
    slope, icpt = np.polyfit(np.log(Ns[-4:]), p0[-4:], 1)
    xs = np.linspace(np.log(Ns[0]), np.log(Ns[-1]), 50)
    ax.plot(xs, icpt + slope * xs, "--", label=f"{icpt:.3f} + {slope:.3f} ln N (last four)")
    ax.set(xlabel="ln N", ylabel="P(f = 0)", title="contacts between layers N-1 and N")
    ax.legend()
    for n in Ns[:: max(1, len(Ns) // 5)] + [Ns[-1]]:
        fs = [0.0] + [float(f) for f in data[str(n)]["P_f"]]
        bx.plot(fs, [data[str(n)]["P0_float"]] + list(data[str(n)]["P_f"].values()), "o-", label=f"N = {n}")
    bx.set(xlabel="f = F/<F>", ylabel="P(f)", title="the same contacts, exact")
    bx.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=130)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--N", type=int, nargs="+", required=True)
    parser.add_argument("--out", required=True)
    parser.add_argument("--checkpoint", default=None, help="checkpoint directory (default: none)")
    parser.add_argument("--figure", default=None)
    args = parser.parse_args()
    data = json.load(open(args.out)) if os.path.exists(args.out) else {}
    for N in args.N:
        if str(N) in data:
            continue
        start = time.time()
        route, _plan = layer_route(N, N - 1)
        options = {} if route == "ideals" else {"checkpoint": args.checkpoint}
        layer = layer_gap_law(N, N - 1, route, **options)
        entry = summary(N, layer)
        entry["route"] = route
        entry["wall_seconds"] = round(time.time() - start, 1)
        data[str(N)] = entry
        write_atomic(args.out, data)
        print(f"N={N}: P(0) = {entry['P0_float']:.6f} (ln N = {math.log(N):.4f}), route {route}, "
              f"{entry['wall_seconds']} s", flush=True)
    if args.figure:
        figure(data, args.figure)


if __name__ == "__main__":
    main()
