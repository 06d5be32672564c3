"""``forcenet dist``: exact force distributions (densities, CDFs, pooled P(f)) and the sampled comparison.

Examples (shell)::

    forcenet dist --N 12 --grain 12,6 --format json            # density and CDF of W_{12,6}, "p/q" coefficients
    forcenet dist --N 12 --grain 6,3 --contact F5 --grid 10     # a contact force (units of 2/sqrt3), on a grid
    forcenet dist --N 12 --layer 12 --format csv                # P(f) of the floor, f = N W
    forcenet dist --N 40 --layer 40 --grid 50                   # the floor beyond the DP: de Bruijn Pfaffians
    forcenet dist --N 16 --ensemble --plot out.png              # exact P(f) against exact-sampler and Metropolis histograms
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Callable
from typing import TYPE_CHECKING

import forcenet
from forcenet.exact.routes import LAW_CONTACTS, LAW_DP_MAX_N, LAW_MAX_N

from .cluster import add_engine_options, engine_options, report_checkpoints
from .common import (
    UsageError,
    add_force,
    add_format,
    add_layers,
    add_quiet,
    add_seed,
    available_memory,
    given,
    integer,
    real,
    run_planned,
)
from .output import destination, emit, write_files

if TYPE_CHECKING:
    from forcenet import Law, LawPlan

__all__ = ["register"]

# the routes that take --scheduler and --checkpoint, as their refusal for any other route names them
_PRIMES = ("the de Bruijn Pfaffians of a layer (--layer i, --grain i,j beyond the DP, off the lattice directions; "
           "--ensemble)")


def _grain(text: str) -> tuple[int, ...]:
    """argparse type: ``i,j``."""
    parts = text.replace(" ", "").split(",")
    if len(parts) != 2:
        raise argparse.ArgumentTypeError(f"grain={text!r} is not a grain: give it as i,j (two integers, e.g. 12,6)")
    return tuple(integer(name, 1)(p) for name, p in zip(("grain i", "grain j"), parts))


def _request(args: argparse.Namespace) -> LawPlan:
    """The front door's plan of the request (:func:`forcenet.law_plan`): validated, its route chosen, once."""
    if args.contact is not None and args.grain is None:
        raise UsageError("--contact needs --grain i,j (the grain whose contact force is wanted)")
    request = forcenet.law_plan(args.N, args.grain, layer=args.layer, contact=args.contact,
                                memory_bytes=available_memory())
    if args.grid is not None:  # the grid's degree-based refusal with the request's, before any law is computed
        request.check_grid(args.grid)
    return request


def cmd_dist(args: argparse.Namespace) -> int:
    request = _request(args)
    if args.plot is not None:
        if request.request.grain is not None:
            raise UsageError("--plot compares a pooled P(f) with sampled histograms: use it with --ensemble or --layer")
        if not args.plot.lower().endswith(".png"):
            raise UsageError(f"--plot={args.plot}: the figure is a PNG; give a file name ending in .png")
        if args.out is not None and destination(args.out).target == destination(args.plot, "--plot").target:
            raise UsageError(f"--out={args.out} and --plot={args.plot} name the same file")
    elif (args.samples is not None or args.sweeps is not None or args.bins is not None or args.f_max is not None
          or given(args, "seed")):
        raise UsageError("--samples, --sweeps, --bins, --f-max and --seed set the sampled histograms of --plot")
    # --scheduler, --checkpoint (default: the user's cache for runs announced at over a minute): the routes over primes
    client, directory = engine_options(args, request.over_primes, _PRIMES, request.seconds, lambda directory: directory)
    try:
        return _dist(args, request.with_options(executor=client, checkpoint=directory))
    finally:
        if client is not None:
            client.close()


def _dist(args: argparse.Namespace, request: LawPlan) -> int:
    if args.plot is not None:  # the options given; the others keep the face's defaults (those of --help)
        chosen = {name: getattr(args, name) for name in ("samples", "sweeps", "bins", "f_max")
                  if getattr(args, name) is not None}
        comparison = request.with_sampled_comparison(seed=args.seed, **chosen)

        def run(tick: Callable[..., None] | None) -> tuple[Law, bytes | None]:
            compared = comparison.run(progress=tick)
            if not args.quiet:  # the chi-square of each sampler, on stderr as the run ends
                for line in compared.notes:
                    print(f"forcenet: {line}", file=sys.stderr)
            return compared.law, compared.png()

        law, png = run_planned(comparison.cost, run, force=args.force, quiet=args.quiet)
    else:
        law, png = run_planned(request.cost, lambda tick: request.run(progress=tick), force=args.force,
                               quiet=args.quiet), None
    if request.checkpoint is not None and not args.quiet:
        report_checkpoints(request.checkpoint, request.cost.ticks)
    text = {"json": law.to_json, "csv": law.to_csv, "latex": law.to_latex, "text": law.to_text}[args.format](args.grid)
    if png is None:
        emit(text, args.out)
        return 0
    files: dict[str, str | bytes] = {args.plot: png}
    if args.out is not None:
        files[args.out] = text if text.endswith("\n") else text + "\n"
    write_files(files, name="--plot", names={args.out: "--out"} if args.out is not None else None)
    if args.out is None:
        emit(text)
    return 0


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("dist", help="exact force distributions: density and CDF of a grain or contact, pooled P(f)")
    add_layers(p, LAW_MAX_N, help_text=f"number of layers (2..{LAW_MAX_N}: every grain, layer and the ensemble by "
                                         f"Pfaffians, polynomial; the contacts 2..{LAW_DP_MAX_N}, one pass over the "
                                         f"2^(N-1) ideals per layer; the faster route by the plans)", deferred=True)
    which = p.add_mutually_exclusive_group(required=True)
    which.add_argument("--grain", type=_grain, help="i,j: the density of W_ij (or of its contact force with --contact)")
    which.add_argument("--layer", type=integer("layer", 2), help="P(f) of layer i, f = i W_ij pooled over j (2..N)")
    which.add_argument("--ensemble", action="store_true", help="P(f) pooled over every grain of layers 2..N, f = i W_ij")
    p.add_argument("--contact", choices=list(LAW_CONTACTS), help="with --grain: a contact force, in units of 2/sqrt3 (Eq. 3.8)")
    grid_max = forcenet.Law.GRID_MAX  # Law's grid=: one cap
    p.add_argument("--grid", type=integer("grid", 1, grid_max),
                   help=f"also the values on K + 1 equally spaced points (K in 1..{grid_max})")
    add_format(p, ("text", "json", "csv", "latex"))
    p.add_argument("--plot", help="with --ensemble or --layer: a PNG comparing the exact P(f) with sampled histograms (atomic)")
    p.add_argument("--samples", type=integer("samples", 2), default=None, help="exact samples for --plot (default 20000)")
    p.add_argument("--sweeps", type=integer("sweeps", 2), default=None, help="Metropolis sweeps for --plot (default 3000)")
    p.add_argument("--bins", type=integer("bins", 1, 1000), default=None, help="histogram bins for --plot (default 40)")
    p.add_argument("--f-max", type=real("f-max", 0, low_open=True), default=None, help="histogram range [0, f-max] for --plot (default 4)")
    add_seed(p)
    add_engine_options(p, "the floor's de Bruijn Pfaffians (--layer N, --grain N,j beyond the DP)")
    add_force(p)
    add_quiet(p)
    p.set_defaults(func=cmd_dist)
