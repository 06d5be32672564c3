"""Figure: entropy per site on the chicken-wire isotropic line, Bethe ansatz against (7.3)/(7.4).

Run:  python benchmarks/isotropic_scan.py 600 6,2,1 8,2,1 7,2,1 11,4,2
      python benchmarks/isotropic_scan.py 600:120 10,2,1
      python benchmarks/figure_isotropic.py
Reads out/isotropic_scan_*.json; writes notes/figures/isotropic_entropy.png.
"""

import json
import math
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import mpmath  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from forcenet.numeric.chicken_wire.isotropic import density_Q, entropy_small_parameter  # noqa: E402

rows = []
for path in sorted(Path("out").glob("isotropic_scan_*.json")):
    d = json.loads(path.read_text())
    if "v_oo" in d:
        rows.append((d["Q"], d["v_oo"], d["v_err"], d["mu_oo"]))
if not rows:
    sys.exit("no finished scans in out/: run benchmarks/isotropic_scan.py first")
rows.sort()
Q = [r[0] for r in rows]
v = [r[1] for r in rows]

phis = [math.pi / 2 - 1.4 * k / 200 for k in range(1, 201)]
Qs = [float(density_Q(p, 15)) for p in phis]
series = [float(entropy_small_parameter(math.pi / 2 - p, 15)) for p in phis]

fig, (a, b) = plt.subplots(1, 2, figsize=(10, 4))
a.plot(Q, v, "o", label="Bethe ansatz, L -> oo (this work)")
a.plot(Qs, series, "-", label="(7.3) as reconstructed, with (7.2)")
a.axhline(0.0627861, ls=":", c="k", lw=0.8)
a.annotate("maximum 0.0627861 at Q* = 0.1845", (0.02, 0.064), fontsize=8)
a.set_xlim(0, 0.2)
a.set_ylim(0, 0.12)
a.set_xlabel("Q (particles per site and direction)")
a.set_ylabel("entropy per site v")
a.legend(fontsize=8)
a.set_title("chicken-wire model, isotropic line")

ls = [1 / (3 * q) for q in Q]
g_minus = [vv / (3 * q * q) - math.log(1 / q) for q, vv in zip(Q, v)]
b.plot(ls, g_minus, "o", label="Bethe ansatz: g - log(3 l)")
b.axhline(1.5 + math.log(2), ls="--", c="C1", label="(7.4) as reconstructed: 3/2 + log 2")
b.set_xlabel("hexagon side l = 1/(3Q)")
b.set_ylabel("entropy per hexagon minus log(3 l)")
b.legend(fontsize=8)
b.set_title("entropy per grain: (7.4) against the Bethe ansatz")
fig.tight_layout()
out = Path("notes/figures/isotropic_entropy.png")
fig.savefig(out, dpi=120)
print(f"wrote {out}")
_ = mpmath
