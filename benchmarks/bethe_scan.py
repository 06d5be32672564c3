"""Entropy per site of the chicken-wire model from the Bethe ansatz, versus particle density.

Run:  python benchmarks/bethe_scan.py
Ground states along (L, n, m) = k (a, 2, 1) (density n/L = 2/a, equal numbers
of left- and right-movers) by continuation to L ~ 600; the limit L -> oo at
fixed density from a fit s(L) = s_oo + c/L^2 over the last points; prints a
table (used in notes/chicken_wire.md) and the time per step.
"""

import time

import numpy as np

from forcenet.numeric.chicken_wire.bethe import ground_state_sequence

for a in (5, 6, 7, 8, 10, 4):
    t0 = time.perf_counter()
    k_max = 600 // a
    try:
        seq = ground_state_sequence(k_max, ratio=(a, 2, 1))
    except RuntimeError as exc:
        print(f"n/L = 2/{a}: {exc} ({time.perf_counter() - t0:.0f} s)", flush=True)
        continue
    dt = time.perf_counter() - t0
    Ls = np.array([s.L for s in seq[-6:]], dtype=float)
    ss = np.array([s.entropy_per_site for s in seq[-6:]])
    A = np.vstack([np.ones_like(Ls), 1 / Ls**2]).T
    coef, *_ = np.linalg.lstsq(A, ss, rcond=None)
    spread = np.abs(A @ coef - ss).max()
    print(
        f"n/L = 2/{a}: L = {seq[-1].L}: s = {seq[-1].entropy_per_site:.12f}, "
        f"extrapolated s_oo = {coef[0]:.12f} (fit residual {spread:.1e}), max Bethe residual "
        f"{max(s.residual for s in seq):.1e}, {dt:.0f} s for {len(seq)} systems",
        flush=True,
    )
