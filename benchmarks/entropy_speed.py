"""Speed against error for the chicken-wire entropy on the isotropic line: closed form (7.1), series (7.3),
Bethe ansatz, transfer matrix.  The closed form at 50 more digits is the reference.

Run:  python benchmarks/entropy_speed.py          (about 2 minutes on the 2-core machine)
Prints a markdown table: route, setting, seconds (min of repeats for the fast ones), correct digits.
"""

import time
from fractions import Fraction
from functools import partial

import mpmath

from forcenet.numeric.chicken_wire import isotropic as iso
from forcenet.numeric.chicken_wire.isotropic_bethe import isotropic_limit
from forcenet.numeric.chicken_wire.transfer import isotropic_entropy


def timed(f, repeats=3):
    best, value = float("inf"), None
    for _ in range(repeats):
        t0 = time.perf_counter()
        value = f()
        best = min(best, time.perf_counter() - t0)
    return value, best


def digits(value, reference):
    with mpmath.workdps(10100):
        err = abs(mpmath.mpf(value) - reference)
        return float("inf") if err == 0 else float(-mpmath.log10(err / abs(reference)))


rows = []
Q = Fraction(1, 6)
for D in (15, 50, 100, 1000, 9000):
    with mpmath.workdps(D + 60):
        reference = iso.entropy(Q=Q, dps=D + 50)
    value, seconds = timed(partial(iso.entropy, Q=Q, dps=D), 3 if D < 9000 else 1)
    rows.append(("closed form (7.1)", f"Q = 1/6, dps = {D}", seconds, min(digits(value, reference), D)))

with mpmath.workdps(120):
    reference = iso.entropy(Q=Q, dps=100)
for L_max in (60, 120, 240):
    lim, seconds = timed(partial(isotropic_limit, Q, L_max=L_max, L_min=max(24, L_max // 4)), 1)
    rows.append(("Bethe ansatz", f"Q = 1/6, L <= {L_max} (quoted error {lim.v_err:.1e})", seconds, digits(lim.v, reference)))

for L in (8, 10, 12):
    (s, q), seconds = timed(partial(isotropic_entropy, L, 0.9), 1)
    with mpmath.workdps(60):
        exact = iso.entropy(Q=mpmath.mpf(q), dps=40)
    rows.append(("transfer matrix", f"cylinder L = {L}, bond fugacity 0.9 (Q = {q:.4f})", seconds, digits(s, exact)))

small = "1e-3"
with mpmath.workdps(80):
    eps = iso.eps_of(Q=small, dps=60)
    reference = iso.entropy(Q=small, dps=60)
for order in (2, 3, 4):
    value, seconds = timed(partial(iso.entropy_series_7_3, eps, order, 30))
    rows.append(("series (7.3) corrected", f"Q = 1e-3 (eps = {mpmath.nstr(eps, 4)}), order eps^{order}", seconds, digits(value, reference)))
value, seconds = timed(lambda: iso.entropy(Q=small, dps=30))
rows.append(("closed form (7.1)", "Q = 1e-3, dps = 30", seconds, min(digits(value, reference), 30)))

print("| route | setting | seconds | correct digits |")
print("| --- | --- | --- | --- |")
for route, setting, seconds, d in rows:
    print(f"| {route} | {setting} | {seconds:.3g} | {d:.1f} |")
