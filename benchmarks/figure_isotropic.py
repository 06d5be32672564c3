"""Figure: the chicken-wire entropy on the isotropic line, closed form (7.1) against the Bethe ansatz.

Run:  python benchmarks/figure_isotropic.py      (about 2 min: Bethe sequences to L = 240 at seven densities)
Writes notes/figures/isotropic_entropy.png: left, v(Q) per site from (7.1), the corrected series (7.3) and the
Bethe-ansatz values; right, the entropy per hexagon g = v/(3Q^2) minus log(3l), l = 1/(3Q), against the
corrected (7.4) limit log 2 - 3/2.
"""

import math
from fractions import Fraction
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

from forcenet.numeric.chicken_wire import isotropic as iso
from forcenet.numeric.chicken_wire.isotropic_bethe import isotropic_limit

densities = [Fraction(1, 10), Fraction(1, 9), Fraction(1, 8), Fraction(1, 7), Fraction(1, 6), Fraction(2, 11), Fraction(1, 5)]
bethe = []
for q in densities:
    lim = isotropic_limit(q, L_max=120, L_min=40) if q == Fraction(1, 5) else isotropic_limit(q, L_max=240, L_min=60)  # 1/5: lost at L = 125
    bethe.append((float(q), lim.v, lim.v_err))
    print(f"Q = {q}: Bethe v = {lim.v:.10f} +- {lim.v_err:.1e}, closed form {float(iso.entropy(Q=q, dps=15)):.10f}")

Qs = [k / 1000 for k in range(1, 333)]
v_closed = [float(iso.entropy(Q=q, dps=15)) for q in Qs]
eps = [float(iso.eps_of(Q=q, dps=15)) for q in Qs]
v_series = [float(iso.entropy_series_7_3(e, 2, 15)) for e in eps]

fig, (a, b) = plt.subplots(1, 2, figsize=(10.5, 4))
a.plot(Qs, v_closed, "-", c="k", lw=1.2, label="closed form (7.1)")
a.plot(Qs, v_series, "--", c="C1", lw=1, label="(7.3) corrected, leading order")
a.errorbar([r[0] for r in bethe], [r[1] for r in bethe], yerr=[r[2] for r in bethe], fmt="o", c="C0", ms=4,
           label="Bethe ansatz, L -> oo (independent)")
m = iso.maximum(dps=15)
a.axvline(float(m.Q_max), ls=":", c="0.5", lw=0.8)
a.axvline(float(m.Q0), ls=":", c="C2", lw=0.8)
a.annotate(f"max {float(m.v_max):.7f}\nat Q* = {float(m.Q_max):.4f}", (float(m.Q_max) - 0.17, 0.066), fontsize=8)
a.annotate("twelvefold point\nQ0 = (3 - sqrt3)/6", (float(m.Q0) + 0.005, 0.02), fontsize=8, color="C2")
a.set_xlim(0, 1 / 3)
a.set_ylim(0, 0.08)
a.set_xlabel("Q (bonds per site and direction)")
a.set_ylabel("entropy per site v")
a.legend(fontsize=8, loc="lower center")
a.set_title("chicken-wire model, isotropic line")

small = [10.0**-k for k in range(1, 9)] + [k / 100 for k in range(2, 21)]
small.sort()
g = [float(iso.entropy(Q=str(q), dps=20)) / (3 * q * q) + math.log(q) for q in small]
b.semilogx([1 / (3 * q) for q in small], g, "-", c="k", label="closed form: v/(3Q^2) + log Q")
b.semilogx([1 / (3 * r[0]) for r in bethe], [r[1] / (3 * r[0] ** 2) + math.log(r[0]) for r in bethe], "o", c="C0", ms=4,
           label="Bethe ansatz")
b.axhline(math.log(2) - 1.5, ls="--", c="C1", label="(7.4) corrected: log 2 - 3/2")
b.axhline(math.log(2) + 1.5, ls=":", c="C3", label="(7.4) as read before: log 2 + 3/2")
b.set_xlabel("hexagon side l = 1/(3Q)")
b.set_ylabel("entropy per hexagon minus log(3 l)")
b.set_ylim(-1.2, 2.5)
b.legend(fontsize=8)
b.set_title("entropy per grain: (7.4)")
fig.tight_layout()
out = Path("notes/figures/isotropic_entropy.png")
fig.savefig(out, dpi=120)
print(f"wrote {out}")
