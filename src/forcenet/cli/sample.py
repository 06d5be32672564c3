"""``forcenet sample``: Monte Carlo <W> with standard errors (exact sampler or Metropolis).

The JSON is a function of the arguments, ``--seed`` and ``--workers`` only
(identical bytes on every run): it reports the *effective sample size*
(``effective_samples``: the number of samples for the exact sampler, and for
Metropolis ``min`` over the grains of ``sum_k n_k / tau_k`` over the chains),
while the rate per second, which depends on the machine and its load, goes to
stderr; ``--timing`` adds ``seconds`` and ``effective_samples_per_second`` to
the JSON for those who want them there (and gives up identical bytes).
"""

from __future__ import annotations

import argparse
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

from .common import (
    UsageError,
    add_force,
    add_format,
    add_layers,
    add_quiet,
    add_seed,
    available_memory,
    integer,
    json_dumps,
    real,
    run_planned,
)
from .output import emit

if TYPE_CHECKING:
    import numpy as np

    from forcenet.core.plan import Plan
    from forcenet.numeric.packing.scene import Scene

__all__ = ["register"]


def _scene(args: argparse.Namespace) -> Scene | None:
    """The N x P scene of --P/--pv/--mg/--j0, or None for the triangle under the overload."""
    if args.P is None:
        for name in ("pv", "mg", "j0"):
            if getattr(args, name) is not None:
                raise UsageError(f"--{name} needs the full packing: give its width with --P")
        return None
    from forcenet.numeric.packing.scene import Scene

    if args.sampler == "exact":
        raise UsageError("--P: the exact sampler is the fully mobilized triangle; use --sampler metropolis for the packing")
    return Scene(N=args.N, P=args.P, F=args.F, j0=args.j0, pv=args.pv or 0.0, mg=args.mg or 0.0, ph=args.ph)


# loads of the packing (and the triangle's ph/F): their squares enter the error bars, so they stay far from overflow
_LOAD_RANGE = (1e-100, 1e100)


def _check_loads(args: argparse.Namespace) -> None:
    """Refuse loads whose squares would overflow or vanish (the triangle's F alone scales out: any finite F)."""
    low, high = _LOAD_RANGE
    if args.P is not None:
        for name in ("F", "pv", "mg", "ph"):
            value = getattr(args, name)
            if value is not None and value != 0 and not low <= value <= high:
                raise UsageError(f"{name}={value:g} is out of range: with --P the loads --F, --pv, --mg, --ph must lie "
                                 f"in [{low:g}, {high:g}] (0 allowed for --pv, --mg)")
    elif args.ph is not None and not low <= args.ph / args.F <= high:
        raise UsageError(f"ph={args.ph:g} with F={args.F:g}: the ratio ph/F must lie in [{low:g}, {high:g}]")


def _finite(mean: np.ndarray, stderr: np.ndarray, extra: dict[str, Any]) -> None:
    """Never a nan or an infinity as a result: refuse it (an overflow of the model's numbers)."""
    from forcenet.numeric.autocorr import all_finite

    values = [mean, stderr, extra["effective_samples"]] + [extra[k] for k in ("G", "stderr_G") if k in extra]
    if not all_finite(values):
        raise UsageError("the run produced non-finite values (the loads overflow the floating-point range); "
                         f"give loads in [{_LOAD_RANGE[0]:g}, {_LOAD_RANGE[1]:g}]")


def _plan(args: argparse.Namespace, scene: Scene | None, burn: int) -> Plan:
    from forcenet.numeric.parallel_chains import parallel_plan

    memory = available_memory()
    K = args.workers
    if args.sampler == "exact":
        from forcenet.numeric.triangle.exact_sampler import sample_plan

        plan = sample_plan(args.N, args.samples, memory)
    elif scene is None:
        from forcenet.numeric.triangle.metropolis import metropolis_plan

        plan = metropolis_plan(args.N, args.samples, burn * K, memory, ph=args.ph is not None, move=args.move)
    else:
        from forcenet.numeric.packing.metropolis import packing_plan

        plan = packing_plan(scene, args.samples, burn * K, 2 if args.response else 1, memory, move=args.move)
    return parallel_plan(plan, K, memory)  # K processes on the machine's cores, each with its own share


def cmd_sample(args: argparse.Namespace) -> int:
    import sys
    import time

    import numpy as np

    N, K, workers = args.N, args.samples, args.workers
    if args.sampler == "exact" and args.ph is not None:
        raise UsageError("--ph applies to --sampler metropolis only (the exact sampler is the fully mobilized ensemble)")
    _check_loads(args)
    scene = _scene(args)
    if args.response and scene is None:
        raise UsageError("--response needs the full packing (--P): on the triangle G(i, j) = <W_ij>/F")
    if args.move != "metropolis" and args.sampler == "exact":
        raise UsageError("--move applies to --sampler metropolis only")
    if args.burn_in is not None and args.sampler == "exact":
        raise UsageError("--burn-in applies to --sampler metropolis only (exact samples need none)")
    if args.timing and args.format != "json":
        raise UsageError(f"--timing and --format {args.format} contradict each other: --timing adds to the JSON "
                         "(the text output has its rate on stderr)")
    if workers > K:
        raise UsageError(f"--workers={workers}: more workers than samples ({K}); use at most {K}")
    burn = args.burn_in if args.burn_in is not None else max(100, K // 10)
    plan = _plan(args, scene, burn)

    def run(tick: Callable[..., None] | None) -> tuple[np.ndarray, np.ndarray, dict[str, Any]]:
        from forcenet.numeric.autocorr import AutocorrError
        from forcenet.numeric.parallel_chains import sample_in_parallel

        try:
            result = sample_in_parallel(args.sampler, N, K, seed=args.seed, workers=workers, F=args.F, ph=args.ph,
                                        scene=scene, burn_in=burn, response=args.response, move=args.move,
                                        progress=tick)
        except AutocorrError as exc:
            raise UsageError(f"samples={K}: {exc}; run more sweeps") from None
        return result.mean, result.stderr, result.extra

    t0 = time.perf_counter()
    mean, stderr, extra = run_planned(plan, run, force=args.force, quiet=args.quiet)
    seconds = time.perf_counter() - t0
    _finite(mean, stderr, extra)
    ess = extra["effective_samples"]
    if not args.quiet:
        print(f"forcenet: {ess:.0f} effective samples in {seconds:.1f} s: {ess / seconds:.4g} per second "
              f"({workers} worker{'s' if workers > 1 else ''}, {extra['kernel']} kernel)", file=sys.stderr)
    def rows(a: np.ndarray) -> list[list[float]]:
        if scene is None:  # the triangle: the rows of the lower triangle
            return [[float(a[i, j]) for j in range(i + 1)] for i in range(N)]
        return [[float(v) for v in row] for row in a]

    out = {"N": N, "sampler": args.sampler, "samples": K, "seed": args.seed, "workers": workers}
    out.update({k: (rows(v) if isinstance(v, np.ndarray) else v) for k, v in extra.items()})
    if args.timing:  # opt-in: wall-clock figures make the output differ from run to run
        out.update({"seconds": seconds, "effective_samples_per_second": ess / seconds})
    out.update({"mean_W": rows(mean), "stderr_W": rows(stderr)})
    if args.format == "json":
        emit(json_dumps(out), args.out)
        return 0
    where = "triangle" if scene is None else f"{scene.name} packing, P = {scene.P}"
    lines = [f"{args.sampler} sampler, N = {N} ({where}), {K} samples, {ess:.0f} effective",
             "  bottom row <W_N,j>: " + " ".join(_plus_minus(m, e) for m, e in zip(mean[-1], stderr[-1]))]
    if args.response:
        lines.append("  bottom row G(N,j): " + " ".join(_plus_minus(m, e) for m, e in zip(extra["G"][-1], extra["stderr_G"][-1])))
    emit("\n".join(lines), args.out)
    return 0



def _plus_minus(mean: float, stderr: float) -> str:
    """``mean±stderr``: four decimals at ordinary scales, significant digits at extreme loads (``--F 1e300``)."""
    scale = max(abs(mean), abs(stderr))
    if scale == 0 or 1e-3 <= scale < 1e6:
        return f"{mean:.4f}±{stderr:.4f}"
    return f"{mean:.5g}±{stderr:.2g}"


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("sample", help="Monte Carlo <W> with standard errors (exact sampler or Metropolis)")
    add_layers(p)
    p.add_argument("--sampler", choices=["exact", "metropolis"], default="exact",
                   help="exact: independent exact samples of the triangle (default); metropolis: a Markov chain "
                        "of the thesis's moves (also the full N x P packing, --P)")
    p.add_argument("--samples", type=integer("samples", 2), default=1000,
                   help="independent samples, or recorded sweeps (metropolis); an integer >= 2 (default 1000)")
    p.add_argument("--burn-in", type=integer("burn-in", 0), default=None, help="metropolis burn-in sweeps (default max(100, samples/10))")
    add_seed(p)
    p.add_argument("--F", type=real("F", 0, low_open=True), default=1.0, help="overload on grain (1, j0), a finite number > 0 (default 1)")
    p.add_argument("--ph", type=real("ph", 0, low_open=True), default=None,
                   help="side (left-wall) pressure, metropolis only; default: large (fully mobilized)")
    p.add_argument("--P", type=integer("P", 2), default=None, help="grains per layer: model the full N x P packing (metropolis)")
    p.add_argument("--pv", type=real("pv", 0), default=None, help="top pressure per grain (packing; default 0)")
    p.add_argument("--mg", type=real("mg", 0), default=None, help="grain weight (packing; default 0)")
    p.add_argument("--j0", type=integer("j0", 1), default=None, help="overload column 1..P (default the middle)")
    p.add_argument("--response", action="store_true", help="also G(i,j) = (<W>_{p+F} - <W>_p)/F from a second chain (packing)")
    p.add_argument("--move", choices=["metropolis", "slice"], default="metropolis",
                   help="metropolis: the thesis's single-q move (default); slice: each q drawn from its conditional "
                        "law on its allowed interval (compiled kernel; shorter autocorrelation times)")
    p.add_argument("--workers", type=integer("workers", 1, 64), default=1,
                   help="processes: independent chains (metropolis) or batches of samples (exact), the samples split "
                        "evenly, seeds SeedSequence(seed).spawn(workers); the result depends on --seed and --workers "
                        "only (default 1)")
    p.add_argument("--timing", action="store_true",
                   help="add wall-clock seconds and effective samples per second to the JSON (then it differs "
                        "from run to run; without it the effective samples per second go to stderr)")
    add_format(p)
    add_force(p)
    add_quiet(p)
    p.set_defaults(func=cmd_sample)
