"""Figures of the full-packing scenes (analogs of the thesis's Figs. 3.10 and 3.12).

Run:  python benchmarks/figures_packing.py [--quick]

Gravity (p_v = 0, m g = 1, p_h large, F/mg = 100 and 1000) and isotropic
(p_h = p_v = 1, g = 0, F/p = 3 and 10) responses G(i, j) with error bars
from the integrated autocorrelation time; the isotropic q-distributions at
the overload's lattice direction.  Writes notes/figures/response_gravity.png,
notes/figures/response_isotropic.png and prints the run statistics.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from numeric.packing import Scene, response  # noqa: E402

FIG = Path(__file__).resolve().parents[1] / "notes" / "figures"


def panel(ax, scene, sweeps, burn, layers, seed):
    t0 = time.perf_counter()
    G, err, info = response(scene, sweeps, burn, seed=seed)
    dt = time.perf_counter() - t0
    x = np.arange(1, scene.P + 1) - scene.j0
    for i in layers:
        ax.errorbar(x, G[i - 1], yerr=err[i - 1], marker=".", ms=3, lw=0.8, capsize=1.5, label=f"i = {i}")
    print(
        f"{scene.name:9s} N={scene.N} P={scene.P} F={scene.F:g}: {2 * sweeps} sweeps in {dt:.0f} s, "
        f"acceptance {info['acceptance'][0]:.2f}/{info['acceptance'][1]:.2f}, tau_max {info['tau_max']:.0f} sweeps, "
        f"max stderr {err.max():.4f}"
    )
    ax.set_xlabel("j - j0")
    ax.set_ylabel("G(i, j)")
    ax.legend(fontsize=7)


def main(quick: bool = False):
    FIG.mkdir(parents=True, exist_ok=True)
    n_g, n_i = (8, 8) if quick else (20, 12)
    s_g, s_i = (600, 3000) if quick else (4000, 40000)
    fig, axes = plt.subplots(1, 2, figsize=(10, 3.8))
    for ax, F in zip(axes, (100.0, 1000.0)):
        scene = Scene(N=n_g, P=2 * n_g + 1, F=F, mg=1.0)
        panel(ax, scene, s_g, s_g // 10, [2, n_g // 2, n_g], seed=1)
        ax.set_title(f"gravity, F/mg = {F:g}, N = {n_g}")
    fig.tight_layout()
    fig.savefig(FIG / "response_gravity.png", dpi=130)
    fig, axes = plt.subplots(1, 2, figsize=(10, 3.8))
    for ax, F in zip(axes, (3.0, 10.0)):
        scene = Scene(N=n_i, P=2 * n_i + 1, F=F, pv=1.0, ph=1.0)
        panel(ax, scene, s_i, s_i // 10, [2, n_i // 2, n_i], seed=2)
        ax.set_title(f"isotropic, F/p = {F:g}, N = {n_i}")
    fig.tight_layout()
    fig.savefig(FIG / "response_isotropic.png", dpi=130)


if __name__ == "__main__":
    main(quick="--quick" in sys.argv)
