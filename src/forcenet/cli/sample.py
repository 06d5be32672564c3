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
import sys
import time
from collections.abc import Callable
from typing import TYPE_CHECKING

import forcenet

from .common import (
    UsageError,
    add_force,
    add_format,
    add_layers,
    add_quiet,
    add_seed,
    available_memory,
    integer,
    real,
    run_planned,
)
from .output import emit

if TYPE_CHECKING:
    from forcenet import Samples, Scene

__all__ = ["register"]


def _scene(args: argparse.Namespace) -> Scene | None:
    """The N x P scene of --P/--pv/--mg/--j0, or None for the triangle under the overload."""
    if args.P is None:
        for name in ("pv", "mg", "j0"):
            if getattr(args, name) is not None:
                raise UsageError(f"--{name} needs the full packing: give its width with --P")
        return None

    if args.sampler == "exact":
        raise UsageError("--P: the exact sampler is the fully mobilized triangle; use --sampler metropolis for the packing")
    return forcenet.Scene(N=args.N, P=args.P, F=args.F, j0=args.j0, pv=args.pv or 0.0, mg=args.mg or 0.0, ph=args.ph)


def _check_packing_loads(args: argparse.Namespace) -> None:
    """The packing's load range in the flags' words (forcenet.sample_plan refuses the same, in its arguments')."""
    low, high = forcenet.SamplePlan.load_range
    if args.P is not None:
        for name in ("F", "pv", "mg", "ph"):
            value = getattr(args, name)
            if value is not None and value != 0 and not low <= value <= high:
                raise UsageError(f"{name}={value:g} is out of range: with --P the loads --F, --pv, --mg, --ph must lie "
                                 f"in [{low:g}, {high:g}] (0 allowed for --pv, --mg)")


def cmd_sample(args: argparse.Namespace) -> int:
    K, workers = args.samples, args.workers
    if args.sampler == "exact" and args.ph is not None:
        raise UsageError("--ph applies to --sampler metropolis only (the exact sampler is the fully mobilized ensemble)")
    _check_packing_loads(args)
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
    plan = forcenet.sample_plan(args.N, K, sampler=args.sampler, seed=args.seed, workers=workers, F=args.F,
                                ph=args.ph, scene=scene, burn_in=args.burn_in, response=args.response,
                                move=args.move, memory_bytes=available_memory())

    def run(tick: Callable[..., None] | None) -> Samples:
        return plan.run(progress=tick)

    t0 = time.perf_counter()
    result = run_planned(plan.cost, run, force=args.force, quiet=args.quiet)
    seconds = time.perf_counter() - t0
    ess = result.effective_samples
    if not args.quiet:
        print(f"forcenet: {ess:.0f} effective samples in {seconds:.1f} s: {ess / seconds:.4g} per second "
              f"({workers} worker{'s' if workers > 1 else ''}, {result.kernel} kernel)", file=sys.stderr)
    if args.format == "json":
        emit(result.to_json(seconds if args.timing else None), args.out)
    else:
        emit(result.to_text(), args.out)
    return 0


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("sample", help="Monte Carlo <W> with standard errors (exact sampler or Metropolis)")
    add_layers(p, deferred=True)  # N: checked once, by the front door
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
