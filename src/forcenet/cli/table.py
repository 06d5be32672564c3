"""``forcenet count``, ``forcenet table`` (the main job) and ``forcenet maps``."""

from __future__ import annotations

import argparse
import os
import textwrap
from collections.abc import Callable
from typing import TYPE_CHECKING, Any, cast

import forcenet
from forcenet.core.plan import combine_by_time, phase_progress
from forcenet.exact.routes import (
    MAX_MOMENTS,
    METHODS,
    ROW_LAYER_ROUTES,
    ROW_PRIME_ROUTES,
    over_primes,
    over_primes_text,
    takes,
)

from .cluster import add_engine_options, engine_options, report_checkpoints
from .common import (
    UsageError,
    add_force,
    add_layers,
    add_quiet,
    available_memory,
    defer,
    given,
    integer,
    refuse_together,
    run_planned,
)
from .output import EXIT_CANNOT_JUDGE, EXIT_DISAGREES, check_output_dir, emit, write_files, write_stdout

if TYPE_CHECKING:
    from forcenet import Table, TablePlan
    from forcenet.testing import TableAgreement

__all__ = ["register"]

_EXTENSIONS = {".json": "json", ".csv": "csv", ".tex": "latex"}


def cmd_count(args: argparse.Namespace) -> int:
    request = forcenet.count_plan(args.N, memory_bytes=available_memory())
    text = run_planned(request.cost, lambda tick: request.run(progress=tick).to_text(), force=args.force,
                       quiet=args.quiet)
    emit(text, args.out)
    return 0


def _samples(text: str) -> int:
    """--samples of the cross-check: 0 (none) or an integer >= 2 (an error bar needs two)."""
    value = integer("samples", 0)(text)
    if value == 1:
        raise argparse.ArgumentTypeError("samples=1 is out of range: samples must be 0 (no cross-check) or an integer >= 2")
    return value


def _output_format(args: argparse.Namespace) -> str | None:
    """--format, or the format implied by the extension of --out."""
    if args.format is not None or args.out is None:
        return args.format
    ext = os.path.splitext(args.out)[1].lower()
    if ext not in _EXTENSIONS:
        raise UsageError(f"--out={args.out}: give --format json|csv|latex or a file ending in .json, .csv or .tex")
    return _EXTENSIONS[ext]


def _refuse_ignored(args: argparse.Namespace) -> None:
    """What the main job alone uses, refused beside --format or --out (it would be ignored)."""
    single = next((name for name in ("format", "out") if given(args, name)), None)
    if single is not None:
        for name in ("out_dir", "samples", "seed", "verbose"):
            refuse_together(args, name, single, f"--{name.replace('_', '-')} belongs to the main job (three files "
                            "and a Monte Carlo cross-check), which --format and --out replace by one exact table")
        if _output_format(args) != "latex":
            for name in ("digits", "rows"):
                refuse_together(args, name, single, f"--{name} shapes the LaTeX table only (--format latex, an "
                                ".tex file, or the main job's .tex)")
    elif args.samples == 0:
        refuse_together(args, "seed", "samples", "the seed drives the cross-check's samples, and --samples 0 asks for none")


def _request(args: argparse.Namespace, memory: int | None, client: Any = None,
             directory: str | None = None) -> TablePlan:
    """The front door's plan of the request (:func:`forcenet.plan`); ``auto`` with ``--scheduler`` or
    ``--checkpoint`` chooses among the routes that take them."""

    method = args.method
    if client is None and directory is None and (args.scheduler or args.checkpoint):
        method = over_primes(method)  # not yet connected: the registry's routes that take the options
    return forcenet.plan(args.N, args.moments, method, executor=client, checkpoint=directory, memory_bytes=memory).check()


def cmd_table(args: argparse.Namespace) -> int:
    _refuse_ignored(args)
    fmt = _output_format(args)
    if args.row is not None:
        return _table_row(args, fmt)
    if fmt is None and args.out is not None:  # pragma: no cover - _output_format infers it
        raise UsageError("--out needs --format")
    if fmt is None:
        check_output_dir(args.out_dir, files=[f"mean_W_N{args.N}.{ext}" for ext in ("json", "csv", "tex")])
    memory = available_memory()
    request = _request(args, memory)
    # --scheduler, --checkpoint (default: the user's cache for runs announced at over a minute)
    client, directory = engine_options(args, takes(request.method, "checkpoint"), over_primes_text(), request.seconds,
                                       lambda directory: directory)
    try:
        if client is not None or directory is not None:  # a cluster or recorded primes change the plan
            request = _request(args, memory, client, directory)
        return _table(args, fmt, memory, request)
    finally:
        if client is not None:
            client.close()


def _rows(text: str | None) -> list[int] | None:
    """``--rows 1,2,40`` as a list (each layer checked by the table's ``to_latex``)."""
    if text is None:
        return None
    try:
        return [int(part) for part in text.split(",")]
    except ValueError:
        raise UsageError(f"--rows={text}: give layers as integers separated by commas, e.g. --rows 1,2,40") from None


def _table_row(args: argparse.Namespace, fmt: str | None) -> int:
    """``--row i``: row ``i`` of ``<W^s>``, ``s <= --moments``, by the fastest exact route for that row, announced
    (:func:`forcenet.row_plan`)."""

    if fmt is None:
        raise UsageError("--row gives one row in one format: give --format json|csv|latex or --out FILE "
                         "(the main job's three files and cross-check are for the whole table)")
    refuse_together(args, "rows", "row", "--rows chooses a whole table's layers; --row gives one layer")
    if fmt != "latex":
        refuse_together(args, "digits", "row", "--digits shapes the LaTeX only (--format latex or a .tex file)")
    memory = available_memory()
    request = forcenet.row_plan(args.N, args.row, args.moments, args.method, memory_bytes=memory).check()
    explicit = args.scheduler is not None or args.checkpoint is not None  # then only the routes that take them
    applies = explicit or request.method in ROW_PRIME_ROUTES
    client, directory = engine_options(args, applies, f"a row's routes over primes ({', '.join(ROW_PRIME_ROUTES[:3])})",
                                       request.seconds, lambda directory: directory)
    try:
        if client is not None or directory is not None:  # a cluster or a checkpoint store changes the plan
            request = forcenet.row_plan(args.N, args.row, args.moments, args.method, executor=client, checkpoint=directory,
                               memory_bytes=memory).check()
        row = run_planned(request.cost, lambda tick: request.run(progress=tick), force=args.force, quiet=args.quiet)
    finally:
        if client is not None:
            client.close()
    if directory is not None and not args.quiet and request.method in ROW_LAYER_ROUTES:
        report_checkpoints(directory, request.cost.ticks)
    emit({"json": row.to_json, "csv": row.to_csv, "latex": lambda: row.to_latex(digits=args.digits)}[fmt](),
         args.out)
    return 0


def _table(args: argparse.Namespace, fmt: str | None, memory: int | None, request: TablePlan) -> int:
    plans = [request.cost]
    cross = fmt is None and args.samples > 0
    if cross:
        plans.append(forcenet.testing.cross_check_plan(args.N, args.samples, memory))
    if len(plans) == 1:
        plan = plans[0]
    else:  # primes or ideals, then samples: one bar in estimated seconds
        what, _, why = plans[0].what.partition("; ")  # the reason stays last: the announcement's second line
        plan = combine_by_time(f"{what} and its Monte Carlo cross-check" + (f"; {why}" if why else ""), plans)

    def run(tick: Callable[..., None] | None) -> tuple[Table, TableAgreement | None]:
        phase = [tick] * len(plans) if len(plans) == 1 else [phase_progress(tick, p) for p in plans]
        table = cast("Table", request.run(progress=phase[0]))  # a plan without row=: a whole table
        check = forcenet.testing.cross_check(args.N, table.mean_W, args.samples, args.seed, phase[-1]) if cross else None
        return table, check

    table, check = run_planned(plan, run, force=args.force, quiet=args.quiet)
    if request.checkpoint is not None and not args.quiet:
        report_checkpoints(request.checkpoint, plans[0].ticks)
    render = {"json": table.to_json, "csv": table.to_csv,
              "latex": lambda: table.to_latex(digits=args.digits, rows=_rows(args.rows))}
    if fmt is not None:
        emit(render[fmt](), args.out)
        return 0
    # the main job: three files (all or none), a readable summary and the Monte Carlo check
    N = args.N
    stem = os.path.join(args.out_dir, f"mean_W_N{N}")
    files = {f"{stem}.{ext}": render[fmt_name]() for ext, fmt_name in (("json", "json"), ("csv", "csv"), ("tex", "latex"))}
    lines = table.summary().splitlines()
    lines.append(f"  exact tables written: {stem}.json, .csv, .tex")
    if check is not None:
        lines += textwrap.wrap(f"Monte Carlo cross-check: {args.samples} independent exact samples (seed "
                               f"{args.seed}) of the {check.values} free grains against the exact table:", 78,
                               subsequent_indent="  ")
        if args.verbose:  # the statistics' details; its last line: the verdict or "cannot judge: ..."
            lines += ["  " + line for line in check.summary().splitlines()]
            if check.verdict != "cannot judge":
                lines.append(f"  RMS of (sampled - exact)/stderr = {check.rms_z:.2f} (about 1 expected)")
        else:
            lines += ["  " + line for line in check.plain().splitlines()]
    # the summary is printed once the files are in place; if standard output fails, they are taken back
    write_files(files, name="--out-dir", make_dir=args.out_dir, then=lambda: write_stdout("\n".join(lines) + "\n"))
    if check is None or check.passed:
        return 0
    return EXIT_CANNOT_JUDGE if check.verdict == "cannot judge" else EXIT_DISAGREES


def cmd_maps(args: argparse.Namespace) -> int:
    result = forcenet.maps(args.N)  # maps per bottom row h(N-2, .), Eq. (4.88)
    emit(result.to_json() if args.format == "json" else result.to_text(), args.out)
    return 0


def register(sub: argparse._SubParsersAction) -> None:
    """Add ``count``, ``table`` and ``maps`` to the subcommands."""

    what = ("how many force networks: standard shifted staircase tableaux, d! * normalization (4.1) "
            "(d = N(N-1)/2 free forces; an exact integer)")
    p = sub.add_parser("count", help=what, description=what[0].upper() + what[1:] + ".")
    add_layers(p, deferred=True)  # N: checked once, by the front door
    p.add_argument("--out", help="write the integer to this file (atomically; its directory must exist)")
    add_force(p)
    add_quiet(p)
    p.set_defaults(func=cmd_count)

    p = sub.add_parser(
        "table", help="exact table of <W_ij> (and higher moments): the main job",
        formatter_class=argparse.RawDescriptionHelpFormatter,
        description="The exact mean weight <W_ij> of every grain of the fully mobilized\n"
                    "triangle of N layers (Sec. 4.2), as exact fractions.",
        epilog="the main job (no --format, no --out) writes three files into\n"
               "./forcenet-tables/ (--out-dir): mean_W_N<N>.json, .csv and .tex, the same\n"
               "exact table in three formats; prints a summary (the count, the\n"
               "normalization, the bottom row) and checks the table against 20000\n"
               "independent exact-sampler samples (--samples; --seed 2006 fixes them):\n"
               "a Monte Carlo cross-check with a stated false-alarm rate (exit code 3 if\n"
               "it disagrees, 4 if the samples are too few to judge; 1 is only ever a\n"
               "bug). --seed affects only that cross-check, never the exact table.\n"
               "with --format or --out: one format of the exact table only, no files in\n"
               "./forcenet-tables/, no cross-check.\n\n"
               "examples:\n"
               "  forcenet table --N 12                 # the main job (~2 s)\n"
               "  forcenet table --N 9 --out table.csv  # one CSV file (format: extension)\n"
               "  forcenet table --N 40 --format latex --digits 4 --rows 1,2,40\n"
               "  forcenet table --N 40 --moments 2 --row 39 --format json\n"
               "                                        # <W>, <W^2> of layer 39")
    add_layers(p, deferred=True)  # N: checked once, by the request (forcenet.plan)
    p.add_argument("--format", choices=["json", "csv", "latex"], help="print one format of the exact table instead of "
                                                                       "the main job (no files, no cross-check)")
    p.add_argument("--out", help="write that format to this file (atomically; its directory must exist); "
                                 "the format follows the extension .json/.csv/.tex if --format is not given")
    p.add_argument("--moments", type=integer("moments", 1, MAX_MOMENTS, deferred=True), default=1,
                   help=f"highest moment s of W^s (1..{MAX_MOMENTS}, default 1)")
    p.add_argument("--row", type=integer("row", 1, deferred=True), default=None,
                   help="only row (layer) i of <W> .. <W^s>, by the fastest exact route for that row, announced: "
                        "for s = 2 the rows 2, 3 and N-1 are one-time (each cell uniform between its covers, the "
                        "price of the mean; notes/fluctuations.md Sec. 3.1), other rows one layer's de Bruijn "
                        "Pfaffians; needs --format or --out")
    p.add_argument("--digits", type=integer("digits", 0, 1000), default=None,
                   help="the LaTeX table (.tex, --format latex) in decimals, correctly rounded "
                        "(default: exact fractions)")
    p.add_argument("--rows", default=None,
                   help="the LaTeX table's layers only, e.g. --rows 1,2,40 (default: all)")
    p.add_argument("--verbose", action="store_true",
                   help="the cross-check's statistics in full (z, p-values, the test used)")
    defer(p, "moments", "--moments")  # N, moments and row: checked once, by the request (forcenet.plan)
    defer(p, "row", "--row")
    p.add_argument("--out-dir", default="forcenet-tables",
                   help="directory of the main job's three files (default ./forcenet-tables, created if missing; "
                        "its parent must exist)")
    p.add_argument("--samples", type=_samples, default=20000,
                   help="exact-sampler samples of the main job's cross-check (0: none, else >= 2; default 20000)")
    p.add_argument("--seed", type=integer("seed", 0, 2**63 - 1), default=2006,
                   help="seed of the main job's cross-check samples, an integer >= 0 (default 2006); "
                        "the exact table does not depend on it")
    p.add_argument(
        "--method", choices=list(METHODS), default="auto",
        help="auto: the fastest exact route for the request by the routes' plans, announced with the reason (default); "
        "fast: order-ideal DP, a dynamic program over the 2^(N-1) order ideals (sets of grains closed "
        "upwards), exact, as far as memory allows (forcenet.plan(N, method='fast') says); thesis: the nested-matrix integration of Secs. 4.3-4.5; "
        "lambda: the integer recursions Lambda (4.50) and Gamma (4.73)-(4.77); "
        "maps: the map-counting formulas (4.67), (4.90)-(4.91) of Sec. 4.6; "
        "pfaffian: Schur Pfaffians and minor summation, polynomial in N, for large N (notes/free_fermions.md); "
        "with --moments s >= 2, every load's gap law by de Bruijn Pfaffians, layer by layer, polynomial but "
        "steep (notes/fluctuations.md Sec. 6)",
    )
    add_engine_options(p, over_primes_text())
    add_force(p)
    add_quiet(p)
    p.set_defaults(func=cmd_table)

    p = sub.add_parser("maps", help="Z_(N-2) and the number of maps h per bottom row (Sec. 4.6)")
    add_layers(p, maximum=forcenet.MapCounts.MAX_N, minimum=3, deferred=True)  # N: checked by forcenet.maps
    p.add_argument("--format", choices=["text", "json"], default="text", help="output format (default text)")
    p.add_argument("--out", help="write the output to this file (atomically; its directory must exist)")
    p.set_defaults(func=cmd_maps)
