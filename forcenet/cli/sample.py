"""``forcenet sample``: Monte Carlo <W> with standard errors (exact sampler or Metropolis)."""

from __future__ import annotations

from .common import (
    UsageError,
    add_force,
    add_format,
    add_layers,
    add_quiet,
    add_seed,
    available_memory,
    check_output_path,
    emit,
    integer,
    json_dumps,
    real,
    run_planned,
)

__all__ = ["register"]


def _scene(args):
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


def _plan(args, scene, burn):
    memory = available_memory()
    if args.sampler == "exact":
        from forcenet.numeric.triangle.exact_sampler import sample_plan

        return sample_plan(args.N, args.samples, memory)
    if scene is None:
        from forcenet.numeric.triangle.metropolis import metropolis_plan

        return metropolis_plan(args.N, args.samples, burn, memory)
    from forcenet.numeric.packing.metropolis import packing_plan

    return packing_plan(scene, args.samples, burn, 2 if args.response else 1, memory)


def cmd_sample(args):
    import numpy as np

    N, K = args.N, args.samples
    check_output_path(args.out)
    if args.sampler == "exact" and args.ph is not None:
        raise UsageError("--ph applies to --sampler metropolis only (the exact sampler is the fully mobilized ensemble)")
    scene = _scene(args)
    if args.response and scene is None:
        raise UsageError("--response needs the full packing (--P): on the triangle G(i, j) = <W_ij>/F")
    burn = args.burn_in if args.burn_in is not None else max(100, K // 10)
    plan = _plan(args, scene, burn)

    def run(tick):
        extra = {}
        if args.sampler == "exact":
            from forcenet.numeric.triangle.exact_sampler import ExactSampler

            mean, stderr = ExactSampler(N, seed=args.seed).mean_W(K, progress=tick)
            return mean * args.F, stderr * args.F, extra
        from forcenet.numeric.autocorr import AutocorrError, mean_and_stderr

        try:
            if scene is None:
                from forcenet.numeric.triangle.metropolis import TriangleMetropolis

                ph = None if args.ph is None else args.ph / args.F
                sampler = TriangleMetropolis(N, seed=args.seed, ph=ph)
                chain = sampler.run(K, burn_in=burn, progress=tick) * args.F
            else:
                from forcenet.numeric.packing.metropolis import PackingMetropolis, response

                sampler = PackingMetropolis(scene, seed=args.seed)
                chain = sampler.run(K, burn_in=burn, progress=tick)
                extra = {"scene": scene.name, "P": scene.P, "F": scene.F, "j0": scene.j0,
                         "pv": scene.pv, "mg": scene.mg, "ph": scene.ph}
            mean, stderr, tau = mean_and_stderr(chain)
            if args.response:
                G, G_err, _ = response(scene, K, burn, seed=args.seed, progress=tick)
                extra["G"], extra["stderr_G"] = G, G_err
        except AutocorrError as exc:
            raise UsageError(f"samples={K}: {exc}; run more sweeps") from None
        extra.update({"burn_in": burn, "acceptance": sampler.acceptance_rate, "tau_max": float(tau.max())})
        extra["std_W"] = chain.std(axis=0, ddof=1)
        return mean, stderr, extra

    mean, stderr, extra = run_planned(plan, run, force=args.force, quiet=args.quiet)
    if scene is None:
        rows = lambda a: [[float(a[i, j]) for j in range(i + 1)] for i in range(N)]
    else:
        rows = lambda a: [[float(v) for v in row] for row in a]
    out = {"N": N, "sampler": args.sampler, "samples": K, "seed": args.seed}
    out.update({k: (rows(v) if isinstance(v, np.ndarray) else v) for k, v in extra.items()})
    out.update({"mean_W": rows(mean), "stderr_W": rows(stderr)})
    if args.format == "json":
        emit(json_dumps(out), args.out)
        return 0
    where = "triangle" if scene is None else f"{scene.name} packing, P = {scene.P}"
    lines = [f"{args.sampler} sampler, N = {N} ({where}), {K} samples",
             "  bottom row <W_N,j>: " + " ".join(f"{m:.4f}±{e:.4f}" for m, e in zip(mean[-1], stderr[-1]))]
    if args.response:
        lines.append("  bottom row G(N,j): " + " ".join(f"{m:.4f}±{e:.4f}" for m, e in zip(extra["G"][-1], extra["stderr_G"][-1])))
    emit("\n".join(lines), args.out)
    return 0


def register(sub):
    p = sub.add_parser("sample", help="Monte Carlo <W> with standard errors (exact sampler or Metropolis)")
    add_layers(p)
    p.add_argument("--sampler", choices=["exact", "metropolis"], default="exact")
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
    add_format(p)
    add_force(p)
    add_quiet(p)
    p.set_defaults(func=cmd_sample)
