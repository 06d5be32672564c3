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
    json_dumps,
    real,
    run_planned,
)
from .cluster import add_engine_options, engine_options, report_checkpoints
from .output import destination, emit, write_files

__all__ = ["register"]

_MAX_LAYERS = 128  # fluctuations.MAX_LAW_N: a lattice-direction grain's law by Pfaffians
_MAX_DP_LAYERS = 30  # the order-ideal DP: interior grains, contacts, layers, the ensemble


def _grain(text):
    """argparse type: ``i,j``."""
    parts = text.replace(" ", "").split(",")
    if len(parts) != 2:
        raise argparse.ArgumentTypeError(f"grain={text!r} is not a grain: give it as i,j (two integers, e.g. 12,6)")
    return tuple(integer(name, 1)(p) for name, p in zip(("grain i", "grain j"), parts))


def _what(args):
    """What to compute: ("grain", (i, j), kind) / ("layer", i) / ("ensemble",), validated against N."""
    from forcenet.core.validation import check_grain, check_int

    N = args.N
    if args.grain is not None:
        grain = check_grain(N, args.grain)
        if args.contact is None and grain[0] == 1:
            raise UsageError(f"--grain={grain[0]},{grain[1]}: W_11 = 1 is the overload, it has no density; i must be in 2..{N}")
        if args.contact is not None:
            from forcenet.exact.triangle.gaps import contact_spacing

            contact_spacing(N, grain, args.contact)  # refuses the contacts that are not random
        return ("grain", grain, args.contact)
    if args.contact is not None:
        raise UsageError("--contact needs --grain i,j (the grain whose contact force is wanted)")
    if args.layer is not None:
        return ("layer", check_int(args.layer, "layer", 2, N))
    return ("ensemble",)


def _floor_options(args, what, plan_seconds):
    """``--scheduler``/``--checkpoint`` for the floor's route (the one over primes here): (client, store)."""
    from forcenet.exact.triangle.pfaffian.tasks import checkpoint_store

    route = what[-1] if len(what) > 1 else None
    key = {"floor": "floor", "layers": "layer", "pfaffians": "ensemble"}.get(route)
    if key is not None and what[0] == "grain":
        key += "-grains"
    layer = what[1][0] if what[0] == "grain" else what[1] if what[0] == "layer" else None
    if key == "ensemble":  # one request per layer: the directory itself
        return engine_options(args, True, "", plan_seconds, lambda directory: directory)
    return engine_options(args, key is not None, "the de Bruijn Pfaffians of a layer (--layer i, --grain i,j beyond "
                          "the DP, off the lattice directions; --ensemble)", plan_seconds,
                          lambda directory: checkpoint_store(directory, key, args.N,
                                                             layer=layer if route == "layers" else None))


def _compute(args, what, tick=None, options=None):
    """Exact objects: (title, variable, pieces of the density, pieces of the CDF, extra fields)."""
    from forcenet.exact.triangle import distribution as D
    from forcenet.exact.triangle.gaps import contact_gap_law
    from forcenet.exact.triangle.pfaffian.layers import ensemble_pieces, layer_gap_law
    from forcenet.exact.triangle.pfaffian.fluctuations import single_grain_gap_law

    N = args.N
    if what[0] == "grain":
        (i, j), kind = what[1], what[2]
        gaps = (single_grain_gap_law(N, (i, j), what[3], tick, **(options or {})) if kind is None
                else contact_gap_law(N, (i, j), kind, tick))
        name = f"W_{{{i},{j}}}" if kind is None else f"(sqrt3/2) {kind}^{{({i},{j})}}"
        extra = {"mean": D.moment_from_gaps(gaps, 1), "second_moment": D.moment_from_gaps(gaps, 2)}
        return (name, "w", *D.grain_pieces(gaps), extra)
    if what[0] == "layer":
        i = what[1]
        gaps = layer_gap_law(N, i, what[2], tick, **(options or {}))
        return (f"P(f), f = {i} W_{{{i},j}} (layer {i})", "f", *D.layer_pieces_from_gaps(gaps, i), {})
    pieces = ensemble_pieces(N, what[1], tick, **(options or {}))
    return "P(f), f = i W_{i,j} over layers 2..N (ensemble)", "f", pieces, D.piecewise_cdf(pieces), {}


def _json(args, title, var, pieces, cdf_pieces, extra, grid):
    from forcenet.exact.triangle.distribution import poly_strings

    out = {"N": args.N, "quantity": title, "variable": var,
           "pieces": [{"lo": str(p.lo), "hi": str(p.hi), "degree": p.poly.degree(), "density": poly_strings(p.poly),
                       "cdf": poly_strings(F.poly)} for p, F in zip(pieces, cdf_pieces)],
           "coefficients": "constant term first, exact rationals"}
    out.update({k: str(v) for k, v in extra.items()})
    if grid is not None:
        x, p, F = grid
        out["grid"] = [{var: float(a), "density": float(b), "cdf": float(c)} for a, b, c in zip(x, p, F)]
    return json_dumps(out)


def _csv(var, pieces, cdf_pieces, grid):
    from forcenet.exact.triangle.distribution import poly_strings

    if grid is not None:
        x, p, F = grid
        return "\n".join([f"{var},density,cdf"] + [f"{a!r},{b!r},{c!r}" for a, b, c in zip(x.tolist(), p.tolist(), F.tolist())])
    lines = ["lo,hi,power,density,cdf"]
    for piece, F in zip(pieces, cdf_pieces):
        dens, cum = poly_strings(piece.poly), poly_strings(F.poly)
        dens += ["0"] * (len(cum) - len(dens))
        lines += [f"{piece.lo},{piece.hi},{m},{a},{b}" for m, (a, b) in enumerate(zip(dens, cum))]
    return "\n".join(lines)


def _latex(title, var, pieces, cdf_pieces, grid):
    import sympy

    def cases(ps):
        if len(ps) == 1:
            return sympy.latex(ps[0].poly.as_expr()) + rf" \qquad ({ps[0].lo} \le {var} \le {ps[0].hi})"
        rows = [rf"{sympy.latex(p.poly.as_expr())} & {p.lo} \le {var} < {p.hi}" for p in ps]
        return r"\begin{cases} " + r" \\ ".join(rows) + r" \end{cases}"

    lines = [f"% {title}", r"\begin{align*}", rf"p({var}) &= {cases(pieces)} \\", rf"P(\le {var}) &= {cases(cdf_pieces)}",
             r"\end{align*}"]
    if grid is not None:
        x, p, F = grid
        lines += [r"\begin{tabular}{rrr}", rf"${var}$ & density & CDF \\ \hline"]
        lines += [rf"{a:.6g} & {b:.10g} & {c:.10g} \\" for a, b, c in zip(x, p, F)]
        lines += [r"\end{tabular}"]
    return "\n".join(lines)


def _text(args, title, var, pieces, cdf_pieces, extra, grid):
    lines = [f"N = {args.N}: exact density of {title} (exact rationals; --format json for all coefficients)"]
    for p in pieces:
        lead = ", ".join(str(c) for c in list(reversed(p.poly.all_coeffs()))[:3])
        lines.append(f"  on [{p.lo}, {p.hi}]: polynomial of degree {p.poly.degree()} in {var}; lowest coefficients {lead}, ...")
    for k, v in extra.items():
        lines.append(f"  {k} = {v}")
    lines.append(f"  density at {var} = 0: {pieces[0].poly.eval(0)}")
    if grid is not None:
        lines.append(f"  {var:>10}  {'density':>14}  {'cdf':>14}")
        lines += [f"  {a:10.6g}  {b:14.8g}  {c:14.8g}" for a, b, c in zip(*grid)]
    return "\n".join(lines)


def _plot_plan(args):
    from forcenet.core.plan import combine
    from forcenet.numeric.triangle.exact_sampler import sample_plan
    from forcenet.numeric.triangle.metropolis import metropolis_plan

    memory = available_memory()
    burn = max(100, args.sweeps // 10)
    return [sample_plan(args.N, args.samples, memory), metropolis_plan(args.N, args.sweeps, burn, memory)], combine


def cmd_dist(args):
    from forcenet.exact.triangle.distribution import distribution_plan
    from forcenet.exact.triangle.pfaffian.layers import ensemble_route, layer_route
    from forcenet.exact.triangle.pfaffian.fluctuations import single_grain_route

    N = args.N
    what = _what(args)
    if args.plot is not None:
        if what[0] == "grain":
            raise UsageError("--plot compares a pooled P(f) with sampled histograms: use it with --ensemble or --layer")
        if not args.plot.lower().endswith(".png"):
            raise UsageError(f"--plot={args.plot}: the figure is a PNG; give a file name ending in .png")
        if args.out is not None and destination(args.out).target == destination(args.plot, "--plot").target:
            raise UsageError(f"--out={args.out} and --plot={args.plot} name the same file")
    elif (args.samples is not None or args.sweeps is not None or args.bins is not None or args.f_max is not None
          or given(args, "seed")):
        raise UsageError("--samples, --sweeps, --bins, --f-max and --seed set the sampled histograms of --plot")
    memory = available_memory()
    if what[0] == "grain" and what[2] is None:  # a grain's W: the faster of the DP and, on a lattice direction, Pfaffians
        route, plan = single_grain_route(N, what[1], memory)
        what = (*what, route)
        plans = [plan]
    elif what[0] == "layer":  # the faster of the DP and de Bruijn Pfaffians
        route, plan = layer_route(N, what[1], memory)
        what = (*what, route)
        plans = [plan]
    elif what[0] == "ensemble":  # the faster of the DP and every layer's de Bruijn Pfaffians
        route, plan = ensemble_route(N, memory)
        what = (*what, route)
        plans = [plan]
    else:
        plans = [distribution_plan(N, "contact", memory)]
    client, store = _floor_options(args, what, plans[0].seconds)
    options = {k: v for k, v in (("executor", client), ("checkpoint", store)) if v is not None}
    try:
        return _dist(args, what, plans, options, store)
    finally:
        if client is not None:
            client.close()


def _dist(args, what, plans, options, store):
    if isinstance(store, str):  # one request per layer (the ensemble): the records every layer holds count
        from forcenet.core.checkpoints import resumed_plan

        plans = [resumed_plan(plans[0], store, args.N, ("pfaffian-layer", "pfaffian-floor")), *plans[1:]]
    if args.plot is not None:
        args.samples = 20000 if args.samples is None else args.samples
        args.sweeps = 3000 if args.sweeps is None else args.sweeps
        args.bins = 40 if args.bins is None else args.bins
        args.f_max = 4.0 if args.f_max is None else args.f_max
        more, combine = _plot_plan(args)
        plan = combine(f"{plans[0].what} with its sampled comparison", plans + more, "step")
    else:
        plan = plans[0]

    def run(tick):
        from forcenet.numeric.triangle.force_distribution import density_grid

        title, var, pieces, cdf_pieces, extra = _compute(args, what, tick, options)
        grid = density_grid(pieces, cdf_pieces, args.grid) if args.grid is not None else None
        png = _figure(args, what, pieces, tick) if args.plot is not None else None
        return title, var, pieces, cdf_pieces, extra, grid, png

    from forcenet.core.checkpoints import run_distrusting  # one retry of a run whose reused records fail its checks

    title, var, pieces, cdf_pieces, extra, grid, png = run_distrusting(
        store, args.N, lambda: run_planned(plan, run, force=args.force, quiet=args.quiet))
    if store is not None and not args.quiet:
        report_checkpoints(store, plans[0].ticks)
    text = {"json": lambda: _json(args, title, var, pieces, cdf_pieces, extra, grid),
            "csv": lambda: _csv(var, pieces, cdf_pieces, grid),
            "latex": lambda: _latex(title, var, pieces, cdf_pieces, grid),
            "text": lambda: _text(args, title, var, pieces, cdf_pieces, extra, grid)}[args.format]()
    if png is None:
        emit(text, args.out)
        return 0
    files = {args.plot: png}
    if args.out is not None:
        files[args.out] = text if text.endswith("\n") else text + "\n"
    write_files(files, name="--plot", names={args.out: "--out"} if args.out is not None else None)
    if args.out is None:
        emit(text)
    return 0


def _figure(args, what, pieces, tick):
    """The sampled histograms and the figure (PNG bytes); a summary line per sampler on stderr."""
    import sys

    from forcenet.exact.triangle.distribution import bin_probabilities
    from forcenet.numeric.triangle.force_distribution import (
        chi_square,
        comparison_png,
        exact_sampler_histogram,
        histogram_edges,
        metropolis_histogram,
    )

    pool = "ensemble" if what[0] == "ensemble" else what[1]
    edges = histogram_edges(args.f_max, args.bins)
    exact_bins = bin_probabilities(pieces, edges)
    hists = {f"exact sampler, {args.samples} samples": exact_sampler_histogram(args.N, args.samples, edges, pool, args.seed, tick),
             f"Metropolis, {args.sweeps} sweeps": metropolis_histogram(args.N, args.sweeps, edges, pool, seed=args.seed,
                                                                       progress=tick)}
    notes = []
    for label, h in hists.items():
        chi2, bins, p = chi_square(h, exact_bins)
        flag = "" if h.reliable else f"; chain shorter than 50 tau (tau = {h.tau:.0f} sweeps): error bars unreliable"
        notes.append(f"{label.split(',')[0]}: chi2 = {chi2:.1f} over {bins} bins (p = {p:.2g}), tau = {h.tau:.1f}{flag}")
    if not args.quiet:
        for line in notes:
            print(f"forcenet: {line}", file=sys.stderr)
    pool_text = "every grain of layers 2..N, f = i W_ij" if pool == "ensemble" else f"layer {pool}, f = {pool} W_{pool},j"
    title = f"N = {args.N}: exact P(f) ({pool_text}) against sampled histograms (1 sigma error bars)\n" + "; ".join(notes)
    return comparison_png(pieces, exact_bins, hists, title, args.f_max)


def register(sub):
    p = sub.add_parser("dist", help="exact force distributions: density and CDF of a grain or contact, pooled P(f)")
    add_layers(p, _MAX_LAYERS, help_text=f"number of layers (2..{_MAX_LAYERS}: every grain, layer and the ensemble by "
                                          f"Pfaffians, polynomial; the contacts 2..{_MAX_DP_LAYERS}, one pass over the "
                                          f"2^(N-1) ideals per layer; the faster route by the plans)")
    which = p.add_mutually_exclusive_group(required=True)
    which.add_argument("--grain", type=_grain, help="i,j: the density of W_ij (or of its contact force with --contact)")
    which.add_argument("--layer", type=integer("layer", 2), help="P(f) of layer i, f = i W_ij pooled over j (2..N)")
    which.add_argument("--ensemble", action="store_true", help="P(f) pooled over every grain of layers 2..N, f = i W_ij")
    p.add_argument("--contact", choices=["F1", "F2", "F5", "F6"], help="with --grain: a contact force, in units of 2/sqrt3 (Eq. 3.8)")
    p.add_argument("--grid", type=integer("grid", 1, 100000), help="also the values on K + 1 equally spaced points (K in 1..100000)")
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
