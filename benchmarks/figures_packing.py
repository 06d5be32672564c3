"""Figures of the full-packing scenes (analogs of the thesis's Figs. 3.10, 3.12 and 3.8).

Run:  python benchmarks/figures_packing.py [gravity|isotropic|plot] [metropolis|slice]

Gravity (p_v = 0, m g = 1, p_h large, F/mg = 100 and 1000, N = 20, P = 41)
and isotropic (p_h = p_v = 1, g = 0, F/p = 3 and 10, N = 8, P = 17)
responses G(i, j) = (<W>_{p+F} - <W>_p)/F from two chains each, error bars
from the integrated autocorrelation time; q-distributions of the isotropic
loaded chain on the lattice direction and below the overload.  Chains are
cached in out/packing_*.npz; `plot` redraws notes/figures/response_gravity.png,
notes/figures/response_isotropic.png and notes/figures/q_distributions_isotropic.png.
"""

from __future__ import annotations

import sys
import time
from dataclasses import replace
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from forcenet.numeric.autocorr import AutocorrError, integrated_time, mean_and_stderr
from forcenet.numeric.packing import PackingMetropolis, Scene

ROOT = Path(__file__).resolve().parents[1]
FIG = ROOT / "notes" / "figures"
OUT = ROOT / "out"

# (scene, records, thin): every chain runs records * thin sweeps after a burn-in of a tenth of that, and keeps
# every thin-th state (compiled kernel; the reference kernel took 311 s for 44000 isotropic sweeps)
SCENES = {
    "gravity": [(Scene(N=20, P=41, F=F, mg=1.0), 20_000, 2) for F in (100.0, 1000.0)],
    "isotropic": [(Scene(N=8, P=17, F=3.0, pv=1.0, ph=1.0), 100_000, 4),
                  (Scene(N=8, P=17, F=10.0, pv=1.0, ph=1.0), 100_000, 20)],
}


def run(name: str, move: str = "metropolis"):
    OUT.mkdir(exist_ok=True)
    for k, (scene, sweeps, thin) in enumerate(SCENES[name]):
        if move == "slice":  # the slice move decorrelates ~30x faster per sweep on the isotropic scene
            thin = max(1, thin * 2 // 5)
        t0 = time.perf_counter()
        loaded = PackingMetropolis(scene, seed=2 * k + 1, move=move)
        W1, q1 = loaded.run(sweeps, sweeps * thin // 10, record_q=True, thin=thin)
        base = PackingMetropolis(replace(scene, F=0.0), seed=2 * k + 2, move=move)
        W0 = base.run(sweeps, sweeps * thin // 10, thin=thin)
        dt = time.perf_counter() - t0
        np.savez_compressed(
            OUT / f"packing_{name}_{k}.npz", W1=W1, W0=W0, q1=q1[:, :, :].astype(np.float32),
            acceptance=[loaded.acceptance_rate, base.acceptance_rate], seconds=dt, thin=thin, move=move,
        )
        print(f"{name} F={scene.F:g} ({move}): {2 * sweeps * thin} sweeps in {dt:.0f} s", flush=True)


def plot():
    for name, layers in (("gravity", (2, 10, 20)), ("isotropic", (2, 4, 8))):
        fig, axes = plt.subplots(1, 2, figsize=(10, 3.8))
        for k, ((scene, sweeps, thin), ax) in enumerate(zip(SCENES[name], axes)):
            path = OUT / f"packing_{name}_{k}.npz"
            if not path.exists():
                print(f"missing {path}; run `python benchmarks/figures_packing.py {name}` first")
                continue
            data = np.load(path)
            thin = int(data["thin"]) if "thin" in data else thin
            move = str(data["move"]) if "move" in data else "metropolis"
            trusted = True
            try:
                m1, e1, t1 = mean_and_stderr(data["W1"])
                m0, e0, t0 = mean_and_stderr(data["W0"])
            except AutocorrError as exc:  # honest: no error bars from a chain too short to trust
                trusted = False
                print(f"{name} F={scene.F:g}: {exc}")
                m1, m0 = data["W1"].mean(axis=0), data["W0"].mean(axis=0)
                t1 = integrated_time(data["W1"].reshape(sweeps, -1), quiet=True)
                t0 = integrated_time(data["W0"].reshape(sweeps, -1), quiet=True)
                e1 = e0 = np.full_like(m1, np.nan)
            t1, t0 = t1 * thin, t0 * thin  # in sweeps
            G, err = (m1 - m0) / scene.F, np.hypot(e1, e0) / scene.F
            for i in layers:
                x = np.arange(1, scene.P + 1) - scene.j0 - (i - 1) / 2  # real-space offset (grain diameters)
                if trusted:
                    ax.errorbar(x, G[i - 1], yerr=err[i - 1], marker=".", ms=3, lw=0.8, capsize=1.5, label=f"i = {i}")
                else:
                    ax.plot(x, G[i - 1], ls="--", marker=".", ms=3, lw=0.8, label=f"i = {i}")
            if not trusted:
                ax.text(0.02, 0.95, f"tau ~ {np.nanmax(np.r_[t1, t0]):.0f} sweeps > chain/50:\nno error bars (means only)",
                        transform=ax.transAxes, fontsize=7, va="top", color="crimson")
            ax.set_xlabel("horizontal offset from the overload, j - j0 - (i-1)/2")
            ax.set_ylabel("G(i, j)")
            ax.legend(fontsize=7)
            label = "F/mg" if name == "gravity" else "F/p"
            ax.set_title(f"{name}, {label} = {scene.F:g}, N = {scene.N}, P = {scene.P} ({move})", fontsize=9)
            acc = data["acceptance"]
            print(
                f"{name:9s} N={scene.N} P={scene.P} F={scene.F:g} {move}: {2 * sweeps * thin} sweeps in {float(data['seconds']):.0f} s, "
                f"acceptance {acc[0]:.2f}/{acc[1]:.2f}, tau_max {np.nanmax(np.r_[t1, t0]):.0f} sweeps, "
                f"max stderr of G {np.nanmax(err) if trusted else float('nan'):.4f}, sum_j G(N, j) = {G[-1].sum():.12f}"
            )
        fig.tight_layout()
        fig.savefig(FIG / f"response_{name}.png", dpi=130)
        plt.close(fig)
    # q-distributions in the isotropic scene (Fig. 3.8 analog)
    fig, axes = plt.subplots(1, 2, figsize=(10, 3.6))
    for k, ((scene, _, _), ax) in enumerate(zip(SCENES["isotropic"], axes)):
        path = OUT / f"packing_isotropic_{k}.npz"
        if not path.exists():
            continue
        q = np.load(path)["q1"]
        j0 = scene.j0 - 1
        for i, j, label in ((1, j0, "(2, j0): left lattice direction"), (3, j0 + 1, "(4, j0+1): below the overload"),
                            (3, 0, "(4, 1): far from it")):
            ax.hist(q[:, i, j], bins=50, range=(0, 1), density=True, histtype="step", label=label)
        ax.set_xlabel("q")
        ax.set_ylabel("p(q)")
        ax.set_title(f"isotropic, F/p = {scene.F:g}")
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(FIG / "q_distributions_isotropic.png", dpi=130)


if __name__ == "__main__":
    what = sys.argv[1] if len(sys.argv) > 1 else "plot"
    if what in SCENES:
        run(what, sys.argv[2] if len(sys.argv) > 2 else "metropolis")
    elif what == "plot":
        plot()
    else:
        raise SystemExit(f"unknown argument {what!r}: gravity, isotropic or plot")
