"""Command line interface: ``forcenet count|table|maps|limit|sample``.

Examples (shell)::

    forcenet count --N 40
    forcenet table --N 12                   # JSON + CSV + LaTeX files, summary, MC check
    forcenet table --N 12 --format json     # the exact table on stdout
    forcenet table --N 9 --format csv --moments 2 --out table.csv
    forcenet maps --N 8                     # Z_(N-2) and maps per bottom row
    forcenet limit --x 0.2 --z 0.6 --format json   # scaling limit of the response
    forcenet sample --N 30 --sampler exact --samples 1000 --seed 1 --format json
"""

from __future__ import annotations

import argparse
import math
import os
import sys
import time

__all__ = ["main", "build_parser"]


class _Parser(argparse.ArgumentParser):
    """argparse with one-line errors and exit code 2."""

    def error(self, message):
        self.exit(2, f"{self.prog}: error: {message}\n")


class UsageError(Exception):
    """Bad input detected after parsing; printed as one line, exit code 2."""


def _integer_at_least(name: str, minimum: int):
    """argparse type: an integer ``>= minimum``, errors naming the argument and range."""

    def parse(text):
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{name}={text!r} is not an integer: {name} must be an integer >= {minimum}") from None
        if value < minimum:
            raise argparse.ArgumentTypeError(f"{name}={value} is out of range: {name} must be an integer >= {minimum}")
        return value

    return parse


_layers = _integer_at_least("N", 2)


def _available_memory() -> int:
    try:
        with open("/proc/meminfo") as handle:
            for line in handle:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except OSError:
        pass
    return 16 * 2**30


def _memory_budget() -> int:
    """Residue-table budget: 3/4 of the available memory, at most 12 GiB (peak ~ budget + 2^(N-1) * 16 B)."""
    return min(_available_memory() * 3 // 4, 12 * 2**30)


def _largest_feasible(budget: int) -> int:
    from forcenet.exact.triangle.ideal_dp import estimate_survival_cost

    N = 2
    while estimate_survival_cost(N + 1, budget).nbytes <= budget:
        N += 1
    return N


def _check_table_cost(N: int, moments: int):
    """Refuse runs that cannot fit in memory; announce long ones."""
    from forcenet.exact.triangle.ideal_dp import estimate_survival_cost

    budget = _memory_budget()
    if N > 40:  # 2**39 masks: beyond any machine, skip the estimate itself
        raise UsageError(f"N={N} is out of range for the exact table: N must be in 2..{_largest_feasible(budget)} here")
    est = estimate_survival_cost(N, budget)
    if est.nbytes > budget:
        raise UsageError(
            f"N={N} is out of range for the exact table: it needs {est} but {budget / 2**30:.1f} GiB is available; "
            f"N must be in 2..{_largest_feasible(budget)} here"
        )
    if moments >= 2 and N > 18:
        raise UsageError(f"--moments {moments} with N={N}: higher-moment tables need N in 2..18")
    return est


def _duration(seconds: float) -> str:
    """``seconds`` as a readable duration: 40 s, 12 min, 3.5 h, 90 days."""
    if seconds < 120:
        return f"{seconds:.0f} s"
    if seconds < 7200:
        return f"{seconds / 60:.0f} min"
    if seconds < 2 * 86400:
        return f"{seconds / 3600:.1f} h"
    return f"{seconds / 86400:.0f} days"


def _progress(total: int, desc: str, unit: str = "it"):
    """A tqdm bar on stderr; large counts (ideals, samples) get SI prefixes."""
    from tqdm import tqdm

    return tqdm(total=total, desc=desc, unit=unit, unit_scale=total >= 10_000, file=sys.stderr, leave=False)


def _announced(what: str, seconds: float, total: int, unit: str, quiet: bool, run):
    """Announce the estimated cost on stderr, then ``run(progress)`` under a progress bar."""
    if seconds <= 2 or quiet:
        return run(None)
    print(f"forcenet: {what}: estimated ~{_duration(seconds)}", file=sys.stderr)
    bar = _progress(total, what, unit)
    try:
        return run(lambda: bar.update(1))
    finally:
        bar.close()


def _exact_mean_table(N: int, est, quiet: bool):
    from forcenet.exact.triangle.ideal_dp import _prime_chunks, survival_primes
    from forcenet.exact.triangle.moments import mean_W

    if est.seconds < 2 or quiet:
        return mean_W(N, memory_bytes=_memory_budget())
    print(f"forcenet: exact table N={N}: estimated {est}", file=sys.stderr)
    budget = _memory_budget()
    chunks = len(_prime_chunks(N - 1, survival_primes(N), budget))
    bar = _progress(chunks * (1 << (N - 1)), f"N={N} ideals", "ideal")
    try:
        return mean_W(N, progress=bar.update, memory_bytes=budget)
    finally:
        bar.close()


def _cross_check(N: int, table, samples: int, seed: int):
    """Exact-sampler estimate of <W> against the exact table (in standard errors)."""
    import numpy as np

    from forcenet.numeric.triangle.exact_sampler import ExactSampler

    t0 = time.perf_counter()
    mean, stderr = ExactSampler(N, seed=seed).mean_W(samples)
    seconds = time.perf_counter() - t0
    worst, where, zs = 0.0, None, []
    for i, row in enumerate(table, start=1):
        for j, exact in enumerate(row, start=1):
            err = stderr[i - 1, j - 1]
            if err > 0:
                z = abs(mean[i - 1, j - 1] - float(exact)) / err
                zs.append(z)
                if z > worst:
                    worst, where = z, (i, j)
    rms = float(np.sqrt(np.mean([(mean[i, j] - float(table[i][j])) ** 2 for i in range(N) for j in range(i + 1)])))
    return worst, where, rms, seconds, float(np.sqrt(np.mean(np.square(zs)))), len(zs)


def _cmd_count(args):
    from forcenet.exact.triangle.staircase import count

    print(count(args.N))
    return 0


# Nested-matrix integration (forcenet.exact.thesis.nested, modular engine): measured seconds and peak
# bytes of one integration on the 2-core machine; the table needs N(N+1)/2 + 1 of them.
# N = 10 would need bonds of ~4e5 index tuples (about 1e10 matrix entries): out of reach.
_THESIS_COST = {2: (0.01, 5e7), 3: (0.01, 5e7), 4: (0.01, 5e7), 5: (0.01, 5e7), 6: (0.01, 6e7),
                7: (0.01, 1e8), 8: (0.13, 3e8), 9: (15.0, 2e9)}  # N = 9: 6-48 s, 1.2-1.9 GB per grain


# Measured per bulk grain of the Gamma route (seconds, peak bytes) on the 2-core machine
# (benchmarks/gamma_table.py); the table has (N-1)(N-2)/2 of them.
_LAMBDA_COST = {10: (0.1, 1e8), 11: (2.5, 5e8), 12: (170.0, 2.2e10)}  # N = 12: one grain peaks at 20 GB


def _nested_tables(N: int, moments: int, tick):
    from forcenet.exact.thesis.nested import integrate_layers, moment_table_nested

    volume = integrate_layers(N)  # once for every s
    return {s: moment_table_nested(N, s, progress=tick, volume=volume) for s in range(1, moments + 1)}


def _thesis_tables(N: int, moments: int, force: bool, quiet: bool):
    """``<W^s>`` tables, ``s = 1..moments``, by the nested-matrix integration."""
    if N not in _THESIS_COST:
        raise UsageError(f"N={N} is out of range for --method thesis: N must be in 2..9 (the nested bonds outgrow memory at N = 10)")
    if moments > 3:
        raise UsageError(f"--moments={moments} with --method thesis: 1..3 (the s-th order defects grow fast: N = 9, s = 3 needs 12 GB)")
    per_run, nbytes = _THESIS_COST[N]
    runs = N * (N + 1) // 2 + 1
    # cost of s = 1, 2, 3 relative to s = 1, measured at the costliest grain (N, 3):
    # N = 8 time x2.4, x4.8; N = 9 time x3.2, x8.0 and memory x2.6, x6.5
    time_factor = (1.0, 2.4, 4.8) if N <= 8 else (1.0, 3.2, 8.0)
    memory_factor = (1.0, 2.6, 6.5)
    seconds = per_run * runs * sum(time_factor[:moments])
    nbytes *= memory_factor[moments - 1]
    if nbytes > _available_memory():
        raise UsageError(f"N={N} --moments {moments} with --method thesis needs ~{nbytes / 2**30:.0f} GiB of memory; "
                         f"use a smaller N or --moments")
    if seconds > 60 and not force:
        raise UsageError(f"N={N} --moments {moments} with --method thesis takes ~{_duration(seconds)} "
                         f"({(runs - 1) * moments + 1} nested integrations); add --force to run it")
    return _announced(f"--method thesis N={N}, nested integrations", seconds, (runs - 1) * moments, "grain", quiet,
                      lambda tick: _nested_tables(N, moments, tick))


def _cmd_table(args):
    from forcenet.exact.triangle.tables import exact_table, fraction_str, to_csv, to_json, to_latex, write_atomic

    quiet = args.quiet  # the cost and the progress bar go to stderr, never into --format output
    higher = None
    if args.method == "lambda":
        from forcenet.exact.thesis import mean_W_gamma

        if args.moments > 1:
            raise UsageError("--moments with --method lambda: only --moments 1 (higher moments use the fast method)")
        if args.N > 12:
            raise UsageError(f"N={args.N} is out of range for --method lambda: N must be in 2..12 (the index boxes of (4.32) outgrow memory)")
        per_grain, nbytes = _LAMBDA_COST.get(args.N, (0.01, 0))
        grains = (args.N - 1) * (args.N - 2) // 2
        seconds = per_grain * grains
        if nbytes > _available_memory():
            raise UsageError(f"N={args.N} with --method lambda needs ~{nbytes / 2**30:.0f} GiB of memory; N must be in 2..11 here")
        if seconds > 60 and not args.force:
            raise UsageError(f"N={args.N} with --method lambda takes ~{seconds / 60:.0f} min ({grains} Gamma recursions); add --force to run it")
        means = _announced(f"--method lambda N={args.N}, Gamma recursions", seconds, grains, "grain", quiet,
                           lambda tick: mean_W_gamma(args.N, progress=tick))
    elif args.method == "maps":
        from forcenet.exact.triangle.staircase import count
        from forcenet.exact.thesis import mean_W_thesis_maps, moments_by_maps

        if args.N > 9:
            raise UsageError(f"N={args.N} is out of range for --method maps: it would enumerate {count(args.N):.3g} maps per grain; N must be in 2..9")
        grains = (args.N - 1) * (args.N - 2) // 2
        seconds = count(args.N) * (args.N * (args.N - 1) // 2) * 3e-6  # measured: 1.4 s at N = 7, 34 min at N = 8
        if seconds > 60 and not args.force:
            raise UsageError(f"N={args.N} with --method maps enumerates {count(args.N)} maps for each of {grains} grains "
                             f"(~{_duration(seconds)}); add --force to run it")
        means = _announced(f"--method maps N={args.N}, map sums", seconds, grains, "grain", quiet,
                           lambda tick: mean_W_thesis_maps(args.N, progress=tick))
        if args.moments > 1:  # <W^s> by map counting through the tableau bijection
            _, mom, _ = moments_by_maps(args.N, args.moments)
            higher = {s: [[mom[s][(i, j)] for j in range(1, i + 1)] for i in range(1, args.N + 1)] for s in range(2, args.moments + 1)}
    elif args.method == "thesis":
        tables = _thesis_tables(args.N, args.moments, args.force, quiet)
        means = tables.pop(1)
        higher = tables or None
    else:
        est = _check_table_cost(args.N, args.moments)
        means = _exact_mean_table(args.N, est, quiet)
    table = exact_table(args.N, args.moments, mean_table=means, moment_tables=higher)
    render = {"json": to_json, "csv": to_csv, "latex": to_latex}
    if args.format is not None:
        text = render[args.format](table)
        if args.out:
            write_atomic(args.out, text if text.endswith("\n") else text + "\n")
        else:
            sys.stdout.write(text if text.endswith("\n") else text + "\n")
        return 0
    # the main job: three files, a readable summary and the Monte Carlo check
    out_dir = args.out_dir
    stem = os.path.join(out_dir, f"mean_W_N{args.N}")
    for ext, fmt in (("json", "json"), ("csv", "csv"), ("tex", "latex")):
        text = render[fmt](table)
        write_atomic(f"{stem}.{ext}", text if text.endswith("\n") else text + "\n")
    N = args.N
    bottom = table["mean_W"][-1]
    print(f"Fully mobilized triangle, N = {N} layers, d = {N * (N - 1) // 2} free forces")
    print(f"  tableaux count (d! * normalization): {table['count']}")
    print(f"  normalization (Eq. 4.1):             {fraction_str(table['normalization'])}")
    print("  <W_N,j> on the bottom row:")
    for j, value in enumerate(bottom, start=1):
        print(f"    j = {j:2d}: {float(value):.10f}  = {fraction_str(value)}")
    print(f"  exact tables written: {stem}.json, {stem}.csv, {stem}.tex")
    if args.samples:
        worst, where, rms, seconds, rms_z, grains = _cross_check(N, table["mean_W"], args.samples, args.seed)
        verdict = "agrees" if worst < 5 else "DISAGREES"
        print(
            f"Monte Carlo cross-check (exact sampler, {args.samples} independent samples, seed {args.seed}, {seconds:.1f} s):"
        )
        print(f"  max |sampled - exact| / stderr = {worst:.2f} at grain {where} (largest of {grains} grains)")
        print(f"  RMS of (sampled - exact) / stderr = {rms_z:.2f} (1 expected); RMS deviation {rms:.2e}")
        print(f"  {verdict} within 5 standard errors")
        return 0 if worst < 5 else 1
    return 0


_MAPS_MAX_N = 10


def _cmd_maps(args):
    import json

    from forcenet.exact.thesis import lambda_table

    N = args.N
    if not 3 <= N <= _MAPS_MAX_N:
        raise UsageError(f"N={N} is out of range for maps: N must be in 3..{_MAPS_MAX_N}")
    table = lambda_table(N - 2)  # maps per bottom row h(N-2, .), Eq. (4.88)
    Z = sum(table.values())
    if args.format == "json":
        rows = [{"bottom_row": list(j), "maps": str(v)} for j, v in sorted(table.items())]
        print(json.dumps({"N": N, "Z": str(Z), "by_bottom_row": rows}))
        return 0
    print(f"Z_{N - 2} = {Z}  (maps h of Sec. 4.6 for N = {N}; equals the tableaux count)")
    print(f"maps per bottom row h(N-2, 1..N-2), {len(table)} rows with maps:")
    for j, v in sorted(table.items()):
        print(" ".join(f"{x:2d}" for x in j), ":", v)
    return 0


def _cmd_limit(args):
    import json

    import mpmath

    from forcenet.numeric.limit_shape.surface import bulk_response, lattice_response

    z, x, dps = args.z, args.x, args.dps
    if not 0 < z <= 1:
        raise UsageError(f"z={z} is out of range: z must lie in (0, 1]")
    if not abs(x) <= z:
        raise UsageError(f"x={x} is out of range: x must lie in [-z, z] = [{-z}, {z}]")
    if not 5 <= dps <= 1000:
        raise UsageError(f"dps={dps} is out of range: dps must be in 5..1000")
    bulk = bulk_response(x, z, dps=dps)
    lattice = lattice_response(z, dps=dps)
    if args.format == "json":
        print(json.dumps({"x": x, "z": z, "dps": dps, "N_W_bulk": mpmath.nstr(bulk, dps), "W_lattice": mpmath.nstr(lattice, dps)}))
    else:
        print(f"scaling limit at x = {x}, z = {z} ({dps} digits)")
        print(f"  bulk:              N <W>  -> {mpmath.nstr(bulk, dps)}")
        print(f"  lattice direction: <W>    -> {mpmath.nstr(lattice, dps)}  (= (1 - sqrt(z(2-z)))/2)")
    return 0


def _packing_scene(args):
    """The N x P scene of --P/--pv/--mg/--j0, or None for the triangle under the overload."""
    if args.P is None:
        for name in ("pv", "mg", "j0"):
            if getattr(args, name) is not None:
                raise UsageError(f"--{name} needs the full packing: give its width with --P")
        return None
    from forcenet.numeric.packing import Scene

    if args.sampler == "exact":
        raise UsageError("--P: the exact sampler is the fully mobilized triangle; use --sampler metropolis for the packing")
    try:
        return Scene(
            N=args.N, P=args.P, F=args.F, j0=args.j0, pv=args.pv or 0.0, mg=args.mg or 0.0, ph=args.ph
        )
    except (TypeError, ValueError) as exc:
        raise UsageError(str(exc)) from None


def _cmd_sample(args):
    import json

    import numpy as np

    N, K = args.N, args.samples
    if K < 2:
        raise UsageError(f"samples={K} is out of range: samples must be >= 2")
    if args.ph is not None and not args.ph > 0:
        raise UsageError(f"ph={args.ph} is out of range: ph must be > 0 (omit it for the fully mobilized limit)")
    if not (args.F > 0 and math.isfinite(args.F)):
        raise UsageError(f"F={args.F} is out of range: the overload must be a finite number > 0")
    scene = _packing_scene(args)
    if args.sampler == "exact" and args.ph is not None:
        raise UsageError("--ph applies to --sampler metropolis only (the exact sampler is the fully mobilized ensemble)")
    if args.response and scene is None:
        raise UsageError("--response needs the full packing (--P): on the triangle G(i, j) = <W_ij>/F")
    width = N if scene is None else scene.P
    chains = 2 if args.response else 1
    bar = _progress(K * chains, f"{args.sampler} N={N}", "sample") if K * N * width > 2_000_000 else None
    tick = bar.update if bar else None
    t0 = time.perf_counter()
    extra = {}
    try:
        if args.sampler == "exact":
            from forcenet.numeric.triangle.exact_sampler import ExactSampler

            mean, stderr = ExactSampler(N, seed=args.seed).mean_W(K, progress=tick)
            mean, stderr = mean * args.F, stderr * args.F
        else:
            from forcenet.numeric.autocorr import AutocorrError, mean_and_stderr

            burn = args.burn_in if args.burn_in is not None else max(100, K // 10)
            try:
                if scene is None:
                    from forcenet.numeric.triangle.metropolis import TriangleMetropolis

                    ph = None if args.ph is None else args.ph / args.F
                    sampler = TriangleMetropolis(N, seed=args.seed, ph=ph)
                    chain = sampler.run(K, burn_in=burn, progress=tick) * args.F
                else:
                    from forcenet.numeric.packing import PackingMetropolis, response

                    sampler = PackingMetropolis(scene, seed=args.seed)
                    chain = sampler.run(K, burn_in=burn, progress=tick)
                    extra = {"scene": scene.name, "P": scene.P, "F": scene.F, "j0": scene.j0,
                             "pv": scene.pv, "mg": scene.mg, "ph": scene.ph}
                mean, stderr, tau = mean_and_stderr(chain)
                if args.response:
                    G, G_err, info = response(scene, K, burn, seed=args.seed, progress=tick)
            except AutocorrError as exc:
                raise UsageError(f"samples={K}: {exc}; run more sweeps") from None
            except ValueError as exc:
                raise UsageError(str(exc)) from None
            extra.update({"burn_in": burn, "acceptance": sampler.acceptance_rate, "tau_max": float(tau.max())})
            extra["std_W"] = chain.std(axis=0, ddof=1)
            if args.response:
                extra["G"], extra["stderr_G"] = G, G_err
    finally:
        if bar:
            bar.close()
    seconds = time.perf_counter() - t0
    if scene is None:
        rows = lambda a: [[float(a[i, j]) for j in range(i + 1)] for i in range(N)]
    else:
        rows = lambda a: [[float(v) for v in row] for row in a]
    out = {"N": N, "sampler": args.sampler, "samples": K, "seconds": seconds, "seed": args.seed}
    out.update({k: (rows(v) if isinstance(v, np.ndarray) else v) for k, v in extra.items()})
    out.update({"mean_W": rows(mean), "stderr_W": rows(stderr)})
    if args.format == "json":
        print(json.dumps(out))
    else:
        where = "triangle" if scene is None else f"{scene.name} packing, P = {scene.P}"
        print(f"{args.sampler} sampler, N = {N} ({where}), {K} samples, {seconds:.1f} s")
        print("  bottom row <W_N,j>: " + " ".join(f"{m:.4f}±{e:.4f}" for m, e in zip(mean[-1], stderr[-1])))
        if args.response:
            print("  bottom row G(N,j): " + " ".join(f"{m:.4f}±{e:.4f}" for m, e in zip(G[-1], G_err[-1])))
    return 0


_TRANSFER_SECONDS = {8: 0.3, 9: 2, 10: 15, 11: 70, 12: 150, 13: 900}


def _cmd_transfer(args):
    import json

    from forcenet.numeric.chicken_wire.transfer import largest_eigenvalue

    L = args.L
    if not 2 <= L <= 13:
        raise UsageError(f"L={L} is out of range: the chicken-wire transfer matrix runs for 2 <= L <= 13")
    if args.particles is not None and not 0 <= args.particles <= L:
        raise UsageError(f"particles={args.particles} is out of range: 0..L = 0..{L}")
    sectors = [args.particles] if args.particles is not None else list(range(L + 1))
    cost = _TRANSFER_SECONDS.get(L, 0)
    if cost > 5 and args.particles is None:
        print(f"forcenet: {L + 1} sectors of 3^{L} states, about {cost} s", file=sys.stderr)
    t0 = time.perf_counter()
    bar = _progress(len(sectors), f"transfer L={L}", "sector") if cost > 5 else None
    rows = []
    try:
        for n in sectors:
            lam = largest_eigenvalue(L, particles=n)
            rows.append({"particles": n, "lambda": lam, "entropy_per_site": math.log(lam) / L})
            if bar:
                bar.update(1)
    finally:
        if bar:
            bar.close()
    top = max(rows, key=lambda r: r["lambda"])
    out = {"L": L, "seconds": time.perf_counter() - t0, "lambda_max": top["lambda"],
           "entropy_per_site": top["entropy_per_site"], "sectors": rows}
    bulk = [r for r in rows if r["particles"] > 0]
    if bulk and args.particles is None:
        best = max(bulk, key=lambda r: r["lambda"])
        out["bulk"] = {"particles": best["particles"], "entropy_per_site": best["entropy_per_site"]}
    if args.format == "json":
        print(json.dumps(out))
    else:
        print(f"chicken-wire transfer matrix, cylinder of width L = {L}: lambda_max = {top['lambda']:.15g}, "
              f"log(lambda)/L = {top['entropy_per_site']:.12g}")
        for r in rows:
            print(f"  n = {r['particles']:2d}: lambda = {r['lambda']:.15g}   log(lambda)/L = {r['entropy_per_site']:.12g}")
    return 0


def _cmd_bethe(args):
    import json

    from forcenet.numeric.chicken_wire.bethe import ground_state_sequence, solve_ground_state

    L = args.L
    n = args.n if args.n is not None else 2 * max(1, round(L / 6))
    m = args.m if args.m is not None else n // 2
    if not 2 <= L <= 5000:
        raise UsageError(f"L={L} is out of range: 2..5000")
    if not (1 <= m < n < L):
        raise UsageError(f"(L, n, m) = ({L}, {n}, {m}) is out of range: need 1 <= m < n < L")
    t0 = time.perf_counter()
    try:
        if L > 24 and L % 6 == 0 and n == L // 3 and m == n // 2:
            k = L // 6
            bar = _progress(k - 1, f"bethe continuation to L={L}") if k > 40 else None
            sol = ground_state_sequence(k, progress=bar.update if bar else None)[-1]
            if bar:
                bar.close()
        else:
            sol = solve_ground_state(L, n, m)
    except RuntimeError as exc:
        raise UsageError(str(exc)) from None
    out = {
        "L": L, "n": n, "m": m, "seconds": time.perf_counter() - t0,
        "eigenvalue": sol.eigenvalue, "entropy_per_site": sol.entropy_per_site, "residual": sol.residual,
        "w": [[float(z.real), float(z.imag)] for z in sol.w],
        "u": [[float(z.real), float(z.imag)] for z in sol.u],
    }
    if args.format == "json":
        print(json.dumps(out))
    else:
        print(f"Bethe ansatz, L = {L}, n = {n} particles, m = {m} left-movers: "
              f"Lambda = {sol.eigenvalue:.15g}, log(Lambda)/L = {sol.entropy_per_site:.15g} "
              f"(max residual {sol.residual:.1e}, {out['seconds']:.2f} s)")
        print("  u: " + "  ".join(f"{z.real:+.10f}{z.imag:+.10f}i" for z in sol.u))
        print("  w: " + "  ".join(f"{z.real:+.10f}{z.imag:+.10f}i" for z in sol.w))
    return 0


def _fraction_density(text):
    """argparse type for --Q: a fraction p/q with 0 < Q < 1/3."""
    from fractions import Fraction

    try:
        q = Fraction(text)
    except (ValueError, ZeroDivisionError):
        raise argparse.ArgumentTypeError(f"--Q={text!r}: must be a fraction such as 1/6") from None
    if not (0 < q < Fraction(1, 3)) or q.denominator > 60:
        raise argparse.ArgumentTypeError(f"--Q={text!r} is out of range: a fraction c/a with 0 < Q < 1/3 and a <= 60")
    return q


def _cmd_entropy(args):
    import json

    import mpmath

    from forcenet.numeric.chicken_wire import isotropic as iso

    dps = args.dps
    if not 5 <= dps <= 1000:
        raise UsageError(f"--dps={dps} is out of range: 5..1000")
    if not 60 <= args.L_max <= 1200:
        raise UsageError(f"--L-max={args.L_max} is out of range: 60..1200")
    if not args.F > 0:
        raise UsageError(f"--F={args.F} is out of range: the force scale must be > 0")
    L_min = max(24, args.L_max // 4)
    t0 = time.perf_counter()
    out = {"dps": dps, "L_max": args.L_max}

    def bar_for(count, what):
        print(f"forcenet: {what}: {count} Bethe-ansatz sequence(s) to L = {args.L_max} "
              f"(about {round(count * 6 * (args.L_max / 120) ** 2)} s on one core)", file=sys.stderr)
        return _progress(count, what) if not args.quiet else None

    try:
        if args.max:
            bar = bar_for(3, "entropy maximum")
            q_star, v_star, err, limits = iso.entropy_maximum(L_max=args.L_max, L_min=L_min, progress=bar.update if bar else None)
            if bar:
                bar.close()
            out.update({
                "Q_max": q_star, "phi_max": float(iso.phi_of_density(q_star, dps=20)),
                "v_max": v_star, "v_max_error": err,
                "from": [{"Q": str(f), "v": lim.v, "v_error": lim.v_err, "mu": lim.mu, "mu_error": lim.mu_err} for f, lim in sorted(limits.items())],
            })
        else:
            with mpmath.workdps(dps + 10):
                if args.phi is not None:
                    try:
                        phi = mpmath.mpf(args.phi)
                    except (ValueError, TypeError):
                        raise UsageError(f"--phi={args.phi!r}: must be a number") from None
                    Q = iso.density_Q(phi, dps)
                else:
                    Q = mpmath.mpf(args.Q.numerator) / args.Q.denominator
                    phi = iso.phi_of_density(args.Q, dps)
                eps = mpmath.pi / 2 - phi
            out.update({
                "phi": mpmath.nstr(phi, dps), "Q": mpmath.nstr(Q, dps), "eps": mpmath.nstr(eps, dps),
                "v_series_7_3": mpmath.nstr(iso.entropy_small_parameter(eps, dps), dps) if eps > 0 else None,
                "F": args.F, "g_7_4": mpmath.nstr(iso.entropy_per_grain(args.F, dps), dps),
            })
            if not args.no_bethe and 0 < Q < mpmath.mpf(1) / 3:
                if args.Q is not None:
                    bar = bar_for(1, f"entropy at Q = {args.Q}")
                    lim = iso.isotropic_limit(args.Q, args.L_max, L_min)
                    v, err = lim.v, lim.v_err
                    out["bethe_densities"] = [str(args.Q)]
                else:
                    bar = bar_for(2, "entropy at phi")
                    v, err, (a, b) = iso.isotropic_entropy(float(Q), args.L_max, L_min)
                    out["bethe_densities"] = [str(a.Q), str(b.Q)]
                if bar:
                    bar.close()
                out.update({"v_bethe": v, "v_bethe_error": err})
    except ValueError as exc:
        raise UsageError(str(exc)) from None
    except RuntimeError as exc:
        raise UsageError(f"Bethe ansatz: {exc}") from None
    out["seconds"] = time.perf_counter() - t0
    if args.format == "json":
        print(json.dumps(out))
        return 0
    if args.max:
        print(f"maximum entropy per site on the isotropic line (Bethe ansatz, L <= {args.L_max}): "
              f"v* = {out['v_max']:.10f} +- {out['v_max_error']:.1e} at Q* = {out['Q_max']:.6f} (phi* = {out['phi_max']:.6f})")
        for row in out["from"]:
            print(f"  Q = {row['Q']:>5}: v = {row['v']:.10f} +- {row['v_error']:.1e}, mu = {row['mu']:+.8f} +- {row['mu_error']:.1e}")
    else:
        print(f"phi = {out['phi']}")
        print(f"Q   = {out['Q']}   (Eq. 7.2, density per direction)")
        if out.get("v_series_7_3") is not None:
            print(f"v   ~ {out['v_series_7_3']}   (Eq. 7.3 as reconstructed, leading order in eps = pi/2 - phi)")
        print(f"g   = {out['g_7_4']}   (Eq. 7.4 as reconstructed, F = {args.F})")
        if "v_bethe" in out:
            print(f"v   = {out['v_bethe']:.10f} +- {out['v_bethe_error']:.1e}   "
                  f"(Bethe ansatz, isotropic line, densities {', '.join(out['bethe_densities'])}, L <= {args.L_max})")
        print("(Eq. 7.1 itself is not reconstructed; see notes/chicken_wire.md)")
    return 0


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="forcenet", description="Exact results for the force network ensemble.")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)

    p = sub.add_parser("count", help="number of standard shifted staircase tableaux, d! * normalization")
    p.add_argument("--N", type=_layers, required=True, help="number of layers (>= 2)")
    p.set_defaults(func=_cmd_count)

    p = sub.add_parser("table", help="exact table of <W_ij> (and higher moments)")
    p.add_argument("--N", type=_layers, required=True, help="number of layers (>= 2)")
    p.add_argument("--format", choices=["json", "csv", "latex"], help="print one format instead of the main job")
    p.add_argument("--moments", type=_integer_at_least("moments", 1), default=1, help="highest moment s of W^s (default 1)")
    p.add_argument("--out", help="write the --format output to this file (atomically)")
    p.add_argument("--out-dir", default="forcenet-tables", help="directory of the main job's files")
    p.add_argument("--samples", type=int, default=20000, help="exact-sampler samples of the cross-check (0: none)")
    p.add_argument("--seed", type=int, default=2006, help="seed of the cross-check")
    p.add_argument(
        "--method",
        choices=["fast", "thesis", "lambda", "maps"],
        default="fast",
        help="fast: order-ideal DP (default); thesis: the nested-matrix integration of Secs. 4.3-4.5; "
        "lambda: the integer recursions Lambda (4.50) and Gamma (4.73)-(4.77); "
        "maps: the map-counting formulas (4.67), (4.90)-(4.91) of Sec. 4.6",
    )
    p.add_argument("--force", action="store_true", help="run a method beyond its quick reach")
    p.add_argument("--quiet", action="store_true", help="no cost announcement, no progress bar (stderr)")
    p.set_defaults(func=_cmd_table)

    p = sub.add_parser("maps", help="Z_(N-2) and the number of maps h per bottom row (Sec. 4.6)")
    p.add_argument("--N", type=_layers, required=True, help=f"number of layers (3..{_MAPS_MAX_N})")
    p.add_argument("--format", choices=["text", "json"], default="text")
    p.set_defaults(func=_cmd_maps)

    p = sub.add_parser("limit", help="scaling limit of the response at reduced coordinates (x, z)")
    p.add_argument("--x", type=float, required=True, help="horizontal coordinate (2j - i - 1)/N, |x| <= z")
    p.add_argument("--z", type=float, required=True, help="depth i/N in (0, 1]")
    p.add_argument("--dps", type=int, default=20, help="decimal digits (5..1000)")
    p.add_argument("--format", choices=["text", "json"], default="text")
    p.set_defaults(func=_cmd_limit)

    p = sub.add_parser("sample", help="Monte Carlo <W> with standard errors (exact sampler or Metropolis)")
    p.add_argument("--N", type=_layers, required=True, help="number of layers (>= 2)")
    p.add_argument("--sampler", choices=["exact", "metropolis"], default="exact")
    p.add_argument("--samples", type=int, default=1000, help="independent samples, or recorded sweeps (metropolis)")
    p.add_argument("--burn-in", type=int, default=None, help="metropolis burn-in sweeps (default max(100, samples/10))")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--F", type=float, default=1.0, help="overload on grain (1, j0) (default 1)")
    p.add_argument("--ph", type=float, default=None, help="side (left-wall) pressure, metropolis only; default: large (fully mobilized)")
    p.add_argument("--P", type=_integer_at_least("P", 2), default=None, help="grains per layer: model the full N x P packing (metropolis)")
    p.add_argument("--pv", type=float, default=None, help="top pressure per grain (packing; default 0)")
    p.add_argument("--mg", type=float, default=None, help="grain weight (packing; default 0)")
    p.add_argument("--j0", type=_integer_at_least("j0", 1), default=None, help="overload column 1..P (default the middle)")
    p.add_argument("--response", action="store_true", help="also G(i,j) = (<W>_{p+F} - <W>_p)/F from a second chain (packing)")
    p.add_argument("--format", choices=["text", "json"], default="text")
    p.set_defaults(func=_cmd_sample)
    p = sub.add_parser("transfer", help="chicken-wire model (Sec. 7.4): largest transfer-matrix eigenvalue per particle sector")
    p.add_argument("--L", type=int, required=True, help="cylinder width (2..13)")
    p.add_argument("--particles", type=int, default=None, help="only this particle sector (default: all)")
    p.add_argument("--format", choices=["text", "json"], default="text")
    p.set_defaults(func=_cmd_transfer)

    p = sub.add_parser("bethe", help="chicken-wire model: Bethe roots and the largest eigenvalue of a sector")
    p.add_argument("--L", type=int, required=True, help="cylinder width")
    p.add_argument("--n", type=int, default=None, help="particles per row (default 2 round(L/6))")
    p.add_argument("--m", type=int, default=None, help="left-movers among them (default n/2)")
    p.add_argument("--format", choices=["text", "json"], default="text")
    p.set_defaults(func=_cmd_bethe)

    p = sub.add_parser("entropy", help="chicken-wire model: entropy per site on the isotropic line (Eqs. 7.1-7.4)")
    mode = p.add_mutually_exclusive_group(required=True)
    mode.add_argument("--phi", help="parameter of Eqs. (7.1)-(7.2), -pi/2 <= phi <= pi/2 (any number of digits)")
    mode.add_argument("--Q", type=_fraction_density, help="density per direction as a fraction c/a, 0 < Q < 1/3")
    mode.add_argument("--max", action="store_true", help="the maximum over the density")
    p.add_argument("--dps", type=int, default=50, help="decimal digits of the closed forms (5..1000, default 50)")
    p.add_argument("--L-max", type=int, default=240, help="largest Bethe-ansatz width (60..1200, default 240)")
    p.add_argument("--F", type=float, default=1.0, help="force scale of Eq. (7.4) (default 1)")
    p.add_argument("--no-bethe", action="store_true", help="closed forms only (instant)")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.add_argument("--format", choices=["text", "json"], default="text")
    p.set_defaults(func=_cmd_entropy)
    return parser


def main(argv=None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    if getattr(args, "samples", 0) and args.samples < 0:
        parser.error(f"--samples={args.samples} is out of range: must be >= 0")
    try:
        return args.func(args)
    except UsageError as exc:
        print(f"forcenet: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("forcenet: interrupted; no partial output was written", file=sys.stderr)
        return 130
    except BrokenPipeError:  # e.g. `forcenet maps --N 9 | head`
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
