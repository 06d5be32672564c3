"""``forcenet clusters`` and ``forcenet scaling``: clusters of large forces and their finite-size scaling (Part III).

``forcenet clusters FILES...`` reads users' force networks (CSV ``sample,i,j,f``, one file per system size);
``forcenet scaling --model MODEL`` generates a model's networks at several sizes (planned, announced, in blocks
on local processes or a Dask cluster, checkpointed).  Both print the result's own JSON or text
(:class:`forcenet.ForceChainScaling`), and ``--plot DIR`` writes its two figures there.
"""

from __future__ import annotations

import argparse
import os
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import forcenet

from .cluster import connect_scheduler
from .common import UsageError, add_force, add_format, add_quiet, add_seed, defer, integer, run_planned
from .output import check_output_dir, emit, write_files

if TYPE_CHECKING:
    from forcenet import ForceChainScaling

__all__ = ["register"]

MODELS = ("percolation", "q-independent", "q-microcanonical", "snooker", "disordered", "averaged")


def _sizes(text: str) -> tuple[int, ...]:
    """``--sizes 16,32,64``: the integers (their range is the front door's)."""
    parts = [p.strip() for p in text.split(",") if p.strip()]
    if not parts or not all(p.isascii() and p.isdigit() for p in parts):
        raise argparse.ArgumentTypeError(f"sizes={text!r}: expected integers separated by commas, e.g. 16,32,64")
    return tuple(int(p) for p in parts)


_sizes.__name__ = "value"


def _render(result: ForceChainScaling, args: argparse.Namespace) -> None:
    text = result.to_json() if args.format == "json" else result.to_text()
    if args.plot_dir is not None:
        files: dict[str, str | bytes] = {os.path.join(args.plot_dir, name): png for name, png in result.figures().items()}
        write_files(files, name="--plot", make_dir=args.plot_dir)
    emit(text, args.out)


def _check_plot(args: argparse.Namespace) -> None:
    if args.plot_dir is not None:
        check_output_dir(args.plot_dir, "--plot", ("s2.png", "collapse.png"))


def cmd_clusters(args: argparse.Namespace) -> int:
    _check_plot(args)
    for path in args.files:  # a folder, a FIFO or a device: the front door's check names what it is
        if not os.path.lexists(path):
            raise UsageError(f"{path}: no such file (give one CSV file sample,i,j,f per system size)")
    result = forcenet.clusters(args.files, thresholds=args.thresholds, replicas=args.replicas, seed=args.seed)
    _render(result, args)
    return 0


def cmd_scaling(args: argparse.Namespace) -> int:
    _check_plot(args)
    if args.checkpoint is not None:  # the one check, named as the command line's option
        check_output_dir(args.checkpoint, "--checkpoint")
    executor: Any = None
    plan = forcenet.scaling_plan(args.model, args.sizes, args.samples, args.seed, lattice=args.lattice,
                                 thresholds=args.thresholds, replicas=args.replicas, workers=args.workers,
                                 checkpoint=args.checkpoint, average=args.average)
    if args.scheduler is not None:
        executor = connect_scheduler(args.scheduler)

    def run(tick: Callable[..., None] | None) -> ForceChainScaling:
        return plan.run(progress=tick, executor=executor)

    try:
        result = run_planned(plan.cost, run, force=args.force, quiet=args.quiet)
    finally:
        if executor is not None:
            executor.close()
    _render(result, args)
    return 0


def _common(p: argparse.ArgumentParser) -> None:
    p.add_argument("--thresholds", type=integer("thresholds", 20, 20000), default=600,
                   help="number of thresholds (quantiles 1..99 %% of the forces; default 600)")
    p.add_argument("--replicas", type=integer("replicas", 0, 10000), default=100,
                   help="bootstrap resamples for the error bars (default 100)")
    p.add_argument("--plot", dest="plot_dir", default=None,
                   help="a folder for the figures s2.png (<s^2>(f) per size) and collapse.png (created if missing)")
    add_seed(p)
    add_format(p)


def register(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    p = sub.add_parser("clusters", help="clusters of large forces of your force networks and their finite-size scaling")
    p.add_argument("files", nargs="+", help="CSV files sample,i,j,f: one per system size (at least 3)")
    _common(p)
    p.set_defaults(func=cmd_clusters)

    p = sub.add_parser("scaling", help="finite-size scaling of the clusters of large forces of a model (Table 7.1)")
    p.add_argument("--model", choices=list(MODELS), required=True, metavar="MODEL",
                   help="percolation (independent uniform forces: the control, exact 43/48 and 4/3), q-independent, "
                        "q-microcanonical (Sec. 7.3), snooker, disordered, averaged (the force network ensemble, "
                        "Sec. 7.2)")
    p.add_argument("--sizes", type=_sizes, default=None, help="linear sizes L, e.g. 32,64,128 (default: the model's)")
    p.add_argument("--samples", type=integer("samples", 2, deferred=True), default=None,
                   help="networks per size (default: the model's, fewer at larger sizes)")
    defer(p, "samples", "--samples")
    p.add_argument("--lattice", choices=["square", "triangular", "honeycomb"], default="square",
                   help="percolation's periodic lattice (default square)")
    p.add_argument("--average", type=integer("average", 1, 64), default=4,
                   help="the averaged model's P: each network the average of P networks of the ensemble (default 4)")
    p.add_argument("--workers", type=integer("workers", 1, 256), default=1, help="local processes (default 1)")
    p.add_argument("--checkpoint", default=None, help="a folder keeping every finished block (a rerun reuses them)")
    p.add_argument("--scheduler", default=None, help="a running Dask scheduler's address: the blocks run there")
    _common(p)
    add_force(p)
    add_quiet(p)
    p.set_defaults(func=cmd_scaling)
