"""Entropy per site of the chicken-wire model on the isotropic line, from the Bethe ansatz.

Run:  python benchmarks/isotropic_scan.py [L_max[:L_start]] [ratio ...]     (ratio as a,n,m, e.g. 6,2,1)

For each ratio (L, n, m) = k (a, 2c, c) the densities of left, right and
horizontal particles are all Q = c/a: n = 2m fixes the first two, a photon
fugacity e^mu (a twist of the Bethe equations) the third.  The entropy per
site v = log(Lambda)/L - mu Q is extrapolated to L -> oo by a fit in 1/L^2
(with and without a 1/L^4 term; their difference is the quoted error).
Writes out/isotropic_scan_<a>_<n>_<m>.json and prints a table row per ratio
(used in notes/chicken_wire.md).
"""

import json
import os
import sys
import time
from pathlib import Path

from forcenet.numeric.chicken_wire.bethe import isotropic_sequence
from forcenet.numeric.chicken_wire.isotropic import extrapolate


def main(argv):
    L_max, _, L_start = (argv[0] if argv else "600").partition(":")
    L_max, L_start = int(L_max), int(L_start or 12)
    ratios = [tuple(int(x) for x in r.split(",")) for r in argv[1:]] or [(6, 2, 1)]
    for a, b, c in ratios:
        t0 = time.perf_counter()
        k_max = L_max // a
        points, error = [], None
        try:
            for p in isotropic_sequence(range(max(2, -(-L_start // a)), k_max + 1), ratio=(a, b, c)):
                points.append(p)
        except RuntimeError as exc:
            error = str(exc)
        dt = time.perf_counter() - t0
        Ls = [p.L for p in points]
        record = {
            "ratio": [a, b, c],
            "Q": c / a,
            "L": Ls,
            "v": [p.entropy_per_site for p in points],
            "mu": [p.log_fugacity for p in points],
            "seconds": dt,
            "failure": error,
        }
        if len(points) >= 8:
            record["v_oo"], record["v_err"] = extrapolate(Ls, record["v"])
            record["mu_oo"], record["mu_err"] = extrapolate(Ls, record["mu"])
        path = Path("out") / f"isotropic_scan_{a}_{b}_{c}.json"
        path.parent.mkdir(exist_ok=True)
        tmp = path.with_suffix(".tmp")
        tmp.write_text(json.dumps(record, indent=1))
        os.replace(tmp, path)
        print(
            f"Q = {c}/{a}: L <= {Ls[-1] if Ls else '-'}: v_oo = {record.get('v_oo', float('nan')):.12f} "
            f"+- {record.get('v_err', float('nan')):.1e}, mu_oo = {record.get('mu_oo', float('nan')):.9f} "
            f"+- {record.get('mu_err', float('nan')):.1e}, {dt:.0f} s" + (f"; stopped: {error}" if error else ""),
            flush=True,
        )


if __name__ == "__main__":
    main(sys.argv[1:])
