"""Refit of the finite-size corrections of the response on exact tables and lattice columns (issues 18 and 26).

``notes/scaling_limit.md`` asks whether the correction on the lattice
directions is ``N^-1``, ``N^-2/3`` or a mix.  With the Pfaffian route the exact
tables reach far beyond the order-ideal DP's N = 28; this script reads them
(``out/mean_W_N{N}.json``, written by ``forcenet table --method pfaffian --N N
--format json --out ...`` or ``benchmarks/pfaffian_table.py table --save out``;
missing small ones are computed), and

* fits the deviation from the limit ``delta(N) = exact - limit`` on the lattice
  direction (``z = 1/4, 1/2, 3/4``, N a multiple of 4 so that ``z N`` is a row)
  and in the bulk with three models, least squares in ``log |delta|`` for the
  power law and relative least squares for the two-term laws:

  - ``A N^-alpha`` (free exponent),
  - ``a N^-1 + b N^-2`` (analytic corrections),
  - ``a N^-2/3 + b N^-1`` (an edge term plus an analytic one), and with ``+ c N^-4/3``,
  - ``a N^-1/2 + b N^-1``;

* prints the local exponents ``-d log|delta| / d log N`` between neighbours;
* extrapolates each fit to the exact-sampler values of ``notes/scaling_limit.md``
  Sec. 3 (N = 100 ... 2000), which none of the fits saw;
* draws ``notes/figures/scaling_refit.png``.

The exact files are large (the column at N = 160: megabytes of digits) and stay
out of the repository; ``notes/data/lattice_columns.json`` keeps what the refit
needs of each finished column (25 digits, correctly rounded, and the SHA-256 of
the exact file), so a later session refits without recomputing and extends
the frontier from there (issue 26).

Usage::

    python benchmarks/scaling_refit.py --lattice 112 120 --dir out --checkpoint ckpt  # exact <W_(i,1)> only (19 and 27 min), resumable
    python benchmarks/scaling_refit.py --record --digest notes/data/lattice_columns.json --dir out  # keep the derived numbers
    python benchmarks/scaling_refit.py --edge-N 32 48 64 80 96 112 120 128 --fit-from 32 \
        --digest notes/data/lattice_columns.json --dir out   # the lattice-direction refit from the digest
    python benchmarks/scaling_refit.py --N 8 12 16 20 24 28 32 36 40 44 48 52 56 60 64 72 80 88 100 \
        --edge-N 112 120 --fit-from 32 --dir out      # the data of notes/scaling_limit.md Sec. 4
"""

from __future__ import annotations

import argparse
import functools
import json
import os
from fractions import Fraction

import numpy as np

from forcenet.exact.triangle.tables import fraction_from_text
from forcenet.numeric.limit_shape.surface import bulk_response, lattice_response

# exact-sampler deviations from the limit, notes/scaling_limit.md Sec. 3 (seed 2026, 16384 ... 200 samples): N -> (delta, stderr)
SAMPLED = {
    0.5: {50: (0.03085, 0.00011), 100: (0.01757, 0.00009), 200: (0.01048, 0.00007), 500: (0.00526, 0.00006),
          1000: (0.00318, 0.00005), 2000: (0.00199, 0.00007)},
    0.75: {50: (0.01247, 0.00005), 100: (0.00718, 0.00004), 200: (0.00411, 0.00003), 500: (0.00203, 0.00002),
           1000: (0.00127, 0.00002), 2000: (0.00069, 0.00003)},
}


DIGEST_DIGITS = 25  # significant digits kept of each exact <W_(i,1)> in the digest (the deviations are ~1e-2..1e-3)
DIGEST_FORMAT = 1
BULK_ROWS = (0.25, 0.5, 0.75)  # the rows i = z N a full table's digest keeps whole (the bulk probes read them)
BULK_PROBES = {"bulk z=1/2, x~0 (N<W>)": 0.5, "bulk z=3/4, x~0 (N<W>)": 0.75}


def load_column(N: int, directory: str, digest: dict | None = None):
    """``<W_{i,1}>``, ``i = 1..N``: from the full table if there is one, else from ``lattice_N{N}.json``,
    else from the digest of exact columns and tables (``--digest``), else computed (``N <= 40``)."""
    full = os.path.join(directory, f"mean_W_N{N}.json")
    path = os.path.join(directory, f"lattice_N{N}.json")
    if os.path.exists(full):
        return [row[0] for row in load_table(N, directory)]
    if os.path.exists(path):
        with open(path) as handle:
            return [float(fraction_from_text(x)) for x in json.load(handle)["W_i1"]]
    for kind in ("columns", "tables"):  # a full table's digest keeps its first column too
        if digest is not None and str(N) in digest.get(kind, {}):
            return [float(x) for x in digest[kind][str(N)]["W_i1"]]
    if N <= 40:
        return [row[0] for row in load_table(N, directory)]
    raise SystemExit(f"{path} is missing: python benchmarks/scaling_refit.py --lattice {N} --dir {directory}")


def decimal_text(x: Fraction, digits: int = DIGEST_DIGITS) -> str:
    """``x`` correctly rounded to ``digits`` significant digits (decimal division is correctly rounded)."""
    import decimal

    with decimal.localcontext() as context:
        context.prec = digits
        return str(decimal.Decimal(x.numerator) / decimal.Decimal(x.denominator))


def read_digest(path: str | None) -> dict | None:
    if path is None or not os.path.exists(path):
        return None
    with open(path) as handle:
        digest = json.load(handle)
    if digest.get("format") != DIGEST_FORMAT:
        raise SystemExit(f"{path}: digest format {digest.get('format')!r}, this script reads {DIGEST_FORMAT}")
    return digest


def record_digest(path: str, directory: str) -> list[int]:
    """Add every exact ``lattice_N{N}.json`` and full table ``mean_W_N{N}.json`` (N a multiple of 4) of
    ``directory`` to the digest at ``path`` (written atomically); the N added, columns and tables alike.

    The digest keeps what the refit needs of each exact column, its values to
    ``DIGEST_DIGITS`` digits, and the SHA-256 of the exact file, so that a
    rebuild (the command in the digest) can be checked byte for byte.  Of a
    full table it keeps the rows ``z N``, ``z`` in ``BULK_ROWS`` (the bulk
    probes), and its first column must equal a recorded lattice column of the
    same N digit for digit (two routes).
    """
    import glob
    import hashlib

    from forcenet.exact.triangle.tables import write_atomic

    digest = read_digest(path) or {
        "format": DIGEST_FORMAT,
        "what": "exact <W_(i,1)>, i = 1..N, of the fully mobilized triangle (the lattice direction), "
                f"{DIGEST_DIGITS} significant digits, correctly rounded; sha256: of the exact lattice_N{{N}}.json",
        "rebuild": "python benchmarks/scaling_refit.py --lattice N --dir out --checkpoint ckpt",
        "columns": {},
    }

    def exact_files(pattern):  # (file name, N, parsed data, sha256 of its bytes) of each exact file of directory
        for name in sorted(glob.glob(os.path.join(directory, pattern))):
            with open(name, "rb") as handle:
                raw = handle.read()
            data = json.loads(raw)
            yield name, int(data["N"]), data, hashlib.sha256(raw).hexdigest()

    def keep(records, name, N, entry):  # a second run of the same N must give the same bytes
        old = records.get(str(N))
        if old is not None and old["sha256"] != entry["sha256"]:
            raise SystemExit(f"{name}: its sha256 differs from the digest's record of N = {N}: two exact runs disagree")
        if old is None:
            added.append(N)
        records[str(N)] = entry

    columns = {N: (name, {"sha256": sha, "W_i1": [decimal_text(fraction_from_text(x)) for x in data["W_i1"]]})
               for name, N, data, sha in exact_files("lattice_N*.json")}
    full = {N: (name, {"sha256": sha, "W_i1": [decimal_text(fraction_from_text(row[0])) for row in data["mean_W"]],
                       "rows": {str(i): [decimal_text(fraction_from_text(x)) for x in data["mean_W"][i - 1]]
                                for i in bulk_row_indices(N)}})
            for name, N, data, sha in exact_files("mean_W_N*.json") if N % 4 == 0}
    if "tables" not in digest:
        digest["tables_what"] = ("full tables <W_ij>: the rows i = z N, z = 1/4, 1/2, 3/4 (the bulk probes), and the "
                                 f"first column, {DIGEST_DIGITS} significant digits; sha256: of the exact mean_W_N{{N}}.json")
        digest["tables_rebuild"] = "forcenet table --method pfaffian --N N --out out/mean_W_N{N}.json --force"
    tables = digest.setdefault("tables", {})
    # the two routes meet, whichever was recorded first: a table's first column is the lattice column
    first = {int(N): r["W_i1"] for N, r in tables.items()} | {N: e["W_i1"] for N, (_, e) in full.items()}
    lattice = {int(N): r["W_i1"] for N, r in digest["columns"].items()} | {N: e["W_i1"] for N, (_, e) in columns.items()}
    for N in sorted(set(first) & set(lattice)):
        if first[N] != lattice[N]:
            name = (full.get(N) or columns.get(N) or (path,))[0]
            raise SystemExit(f"{name}: the full table's first column differs from the lattice column of N = {N}: "
                             "two exact routes disagree")
    added: list[int] = []
    for records, fresh in ((digest["columns"], columns), (tables, full)):
        for N, (name, entry) in sorted(fresh.items()):
            keep(records, name, N, entry)
    digest["tables"] = {k: tables[k] for k in sorted(tables, key=int)}
    digest["columns"] = {k: digest["columns"][k] for k in sorted(digest["columns"], key=int)}
    write_atomic(path, json.dumps(digest, indent=1) + "\n")
    return sorted(set(added))


def bulk_row_indices(N: int) -> list[int]:
    """The rows ``i = z N``, ``z`` in ``BULK_ROWS``, that a full table's digest keeps (``N`` a multiple of 4)."""
    return [round(z * N) for z in BULK_ROWS]


def load_rows(N: int, directory: str, digest: dict | None = None) -> dict[int, list[float]]:
    """The rows ``i = z N`` of the full table of ``N`` (``bulk_row_indices``): from ``mean_W_N{N}.json`` in
    ``directory`` (computed on the fly for ``N <= 40``), else from the digest's record of that table."""
    if not os.path.exists(os.path.join(directory, f"mean_W_N{N}.json")) and digest is not None \
            and str(N) in digest.get("tables", {}):
        return {int(i): [float(x) for x in row] for i, row in digest["tables"][str(N)]["rows"].items()}
    table = load_table(N, directory)
    return {i: table[i - 1] for i in bulk_row_indices(N)}


def write_lattice(N: int, directory: str, checkpoint: str | None = None):
    """Exact ``<W_{i,1}>`` by :func:`forcenet.exact.triangle.free_fermion.route.lattice_direction` into ``lattice_N{N}.json``."""
    import resource
    import time

    from forcenet.exact.triangle.free_fermion.route import lattice_direction, lattice_direction_plan
    from forcenet.exact.triangle.tables import integer_text, write_atomic

    def children():  # cumulative over the process's life: take differences
        usage = resource.getrusage(resource.RUSAGE_CHILDREN)
        return usage.ru_utime + usage.ru_stime

    plan = lattice_direction_plan(N)
    t0, c0, k0 = time.perf_counter(), time.process_time(), children()
    column = lattice_direction(N, checkpoint=checkpoint)  # finished primes survive a kill: rerun to resume
    wall = time.perf_counter() - t0
    cpu = time.process_time() - c0 + children() - k0
    write_atomic(os.path.join(directory, f"lattice_N{N}.json"),
                 json.dumps({"N": N, "W_i1": [f"{integer_text(x.numerator)}/{integer_text(x.denominator)}"  # "1/1" kept:
                                              for x in column]}) + "\n")  # the digest's sha256 are of these bytes
    print(f"N={N}: lattice direction exact, {plan.ticks} primes, plan {plan.seconds:.0f} s, "
          f"wall {wall:.0f} s, CPU {cpu:.0f} s, load {os.getloadavg()[0]:.1f}", flush=True)


@functools.lru_cache(maxsize=4)
def load_table(N: int, directory: str):
    path = os.path.join(directory, f"mean_W_N{N}.json")
    if not os.path.exists(path):
        if N > 40:
            raise SystemExit(f"{path} is missing: run forcenet table --method pfaffian --N {N} --format json --out {path} --force")
        from forcenet.exact.triangle.free_fermion.route import mean_W
        from forcenet.exact.triangle.tables import exact_table, to_json, write_atomic

        write_atomic(path, to_json(exact_table(N, mean_table=mean_W(N))) + "\n")
    with open(path) as handle:
        data = json.load(handle)
    return [[float(fraction_from_text(x)) for x in row] for row in data["mean_W"]]


MODELS = {
    "A N^-alpha": None,
    "a/N + b/N^2": (1.0, 2.0),
    "a/N^(2/3) + b/N": (2.0 / 3.0, 1.0),
    "a/N^(2/3) + b/N + c/N^(4/3)": (2.0 / 3.0, 1.0, 4.0 / 3.0),
    "a/N^(1/2) + b/N": (0.5, 1.0),
}


def power_fit(powers, Ns, devs):
    """``sum_k c_k N^-e_k`` (``e_k`` in ``powers``) fitted to ``devs`` by relative least squares:
    the amplitudes and the relative RMS residual."""
    Ns, devs = np.asarray(Ns, float), np.asarray(devs, float)
    X = np.stack([Ns**-e for e in powers], axis=1) / np.abs(devs)[:, None]
    coef, *_ = np.linalg.lstsq(X, devs / np.abs(devs), rcond=None)
    return tuple(float(c) for c in coef), float(np.sqrt(np.mean((X @ coef - devs / np.abs(devs)) ** 2)))


def power_value(coef, powers, N):
    """``sum_k c_k N^-e_k`` (``N`` a number or an array)."""
    return sum(c * N**-e for c, e in zip(coef, powers))


def fit(model, Ns, devs):
    """Parameters and relative RMS residual of one model."""
    if MODELS[model] is not None:
        return power_fit(MODELS[model], Ns, devs)
    Ns, devs = np.asarray(Ns, float), np.asarray(devs, float)
    slope, intercept = np.polyfit(np.log(Ns), np.log(np.abs(devs)), 1)
    params = (float(np.sign(devs[-1]) * np.exp(intercept)), float(-slope))
    pred = params[0] * Ns ** -params[1]
    return params, float(np.sqrt(np.mean(((pred - devs) / devs) ** 2)))


EXPONENT_GRID = np.linspace(0.40, 1.00, 601)


def fit_free_exponent(Ns, devs, grid=EXPONENT_GRID):
    """``a N^-g + b N^-1 + c N^-2g`` with ``g`` free (a series in ``N^-g`` beside the analytic ``1/N``).

    For each ``g`` on the grid, ``a, b, c`` by relative least squares; returns
    ``(g, a, b, c)`` and the relative RMS residual at the best ``g``.  For
    ``g = 2/3`` this is the three-term model of the notes.
    """
    best = None
    for g in grid:
        coef, rms = power_fit((g, 1.0, 2 * g), Ns, devs)
        if best is None or rms < best[1]:
            best = ((float(g), *coef), rms)
    return best


SERIES = (2 / 3, 1.0, 4 / 3, 5 / 3)  # the N^(-1/3) series from N^(-2/3), four terms


def series_value(amps, N):
    """``sum_k a_k N^-e_k`` over ``SERIES`` (``N`` a number or an array)."""
    return power_value(amps, SERIES, N)


def free_value(params, N):
    """``a N^-g + b/N + c N^-2g`` for the ``(g, a, b, c)`` of :func:`fit_free_exponent`."""
    g, a, b, c = params
    return a * N**-g + b / N + c * N ** (-2 * g)


def drift_under_series(Ns, devs, N_maxes, step=8):
    """The free fit's ``g`` at each ``N_max`` if the deviations were exactly the four-term ``N^(-1/3)`` series.

    The series ``sum_k a_k N^-e_k`` (``SERIES``) is fitted to ``devs`` (relative
    least squares), its values replace the data on the grid ``Ns`` and continue
    every ``step`` beyond it, and :func:`fit_free_exponent` is run on each
    prefix ending at ``N_max``.  If the exact ``g`` drifts like this synthetic
    one, the data are what a series with leading exponent 2/3 looks like from
    here.  Returns ``(amplitudes, relative RMS residual of the series, {N_max: g})``.
    """
    Ns = np.asarray(Ns, float)
    amps, rms = power_fit(SERIES, Ns, devs)
    grid = [*Ns, *np.arange(Ns[-1] + step, max(N_maxes) + 1, step)]
    drift = {}
    for N_max in N_maxes:
        use = np.array([N for N in grid if N <= N_max], float)
        truth = series_value(amps, use)
        (g, *_), _ = fit_free_exponent(use, truth)
        drift[N_max] = g
    return list(amps), rms, drift


def predict_ahead(Ns, devs, target):
    """Predictions for an exact column not yet computed, to be written down before it is.

    Fits on ``(Ns, devs)`` the four-term series (``SERIES``), the three-term
    model and the free-exponent fit, and continues each to ``N = target``.
    Returns a dict: ``series``, ``three_term`` and ``free`` (predicted
    deviations), ``g_series`` (the free fit's ``g`` at ``N_max = target`` if the
    series is the truth) and ``g_stays`` (the same if the free fit is).
    """
    amps, _, drift = drift_under_series(Ns, devs, [target])
    free = free_value(fit_free_exponent(Ns, devs)[0], target)
    (g_stays, *_), _ = fit_free_exponent([*Ns, target], [*devs, free])
    model = "a/N^(2/3) + b/N + c/N^(4/3)"
    params, _ = fit(model, Ns, devs)
    return {"series": series_value(amps, target), "three_term": predict(model, params, target),
            "free": free, "g_series": drift[target], "g_stays": g_stays}


BULK_SERIES = {"analytic, two terms": (1.0, 2.0), "analytic, three terms": (1.0, 2.0, 3.0),
               "edge-like": (2 / 3, 1.0, 4 / 3)}  # the bulk's candidate corrections (notes/scaling_limit.md Sec. 4)


def predict_bulk(Ns, devs, target):
    """Predictions of a bulk probe's deviation ``N <W> - G`` at ``N = target``, to be written down before.

    Each series of ``BULK_SERIES`` (powers of ``1/N``) is fitted on
    ``(Ns, devs)`` by relative least squares and continued to ``target``.
    Returns ``{name: (prediction, relative RMS residual of the fit)}``.
    """
    out = {}
    for name, powers in BULK_SERIES.items():
        coef, rms = power_fit(powers, Ns, devs)
        out[name] = (float(power_value(coef, powers, target)), rms)
    return out


def predict(model, params, N):
    if MODELS[model] is None:
        return params[0] * N ** -params[1]
    return power_value(params, MODELS[model], N)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--N", type=int, nargs="*", default=[],
                        help="full tables (the bulk probes and the lattice direction); none: the lattice direction only")
    parser.add_argument("--dir", default="out")
    parser.add_argument("--fit-from", type=int, default=16, help="smallest N used in the fits")
    parser.add_argument("--figures", default="notes/figures")
    parser.add_argument("--edge-N", type=int, nargs="*", default=[], help="further N with the lattice direction only")
    parser.add_argument("--lattice", type=int, nargs="*", default=[], help="compute lattice_N{N}.json for these N and stop")
    parser.add_argument("--checkpoint", default=None, help="record --lattice's finished primes in this directory (resumable)")
    parser.add_argument("--digest", default=None,
                        help="JSON digest of exact lattice columns (notes/data/lattice_columns.json): read for "
                             "--edge-N without an exact file in --dir; with --record, written")
    parser.add_argument("--predict", type=int, default=None, metavar="N",
                        help="also print the fits' predictions for the lattice column at N, and with --N for the "
                             "bulk probes of the full table at N (before they are computed)")
    parser.add_argument("--record", action="store_true",
                        help="add every lattice_N*.json and mean_W_N*.json of --dir to --digest and stop")
    args = parser.parse_args(argv)
    if args.lattice:
        for N in args.lattice:
            write_lattice(N, args.dir, args.checkpoint)
        return
    if args.record:
        if args.digest is None:
            parser.error("--record needs --digest FILE")
        added = record_digest(args.digest, args.dir)
        print(f"{args.digest}: added N = {added}" if added else f"{args.digest}: nothing new")
        return
    digest = read_digest(args.digest)
    Ns = sorted(N for N in args.N if N % 4 == 0)
    rows = {N: load_rows(N, args.dir, digest) for N in Ns}
    edge_Ns = sorted(set(Ns) | {N for N in args.edge_N if N % 4 == 0})
    columns = {N: load_column(N, args.dir, digest) for N in edge_Ns}

    def edge(z):
        return lambda N: (columns[N][round(z * N) - 1], float(lattice_response(round(z * N) / N)))

    def bulk(z):
        def probe(N):
            i = round(z * N)
            j = i // 2 + 1 if i % 2 else i // 2  # x = (2j - i - 1)/N = 0 or -1/N
            x = (2 * j - i - 1) / N
            return N * rows[N][i][j - 1], float(bulk_response(x, i / N))

        return probe

    probes = [("edge z=1/4", edge(0.25), None, edge_Ns), ("edge z=1/2", edge(0.5), 0.5, edge_Ns),
              ("edge z=3/4", edge(0.75), 0.75, edge_Ns)]
    if Ns:  # the bulk needs full tables
        probes += [(name, bulk(z), None, Ns) for name, z in BULK_PROBES.items()]
    fitted = {}
    print("| probe | limit | " + " | ".join(f"N={N}" for N in edge_Ns) + " |")
    print("|" + " --- |" * (len(edge_Ns) + 2))
    for name, probe, _, sizes in probes:
        values = {N: probe(N) for N in sizes}
        fitted[name] = {N: ex - lim for N, (ex, lim) in values.items()}
        cells = " | ".join(f"{fitted[name][N]:+.5f}" if N in sizes else "-" for N in edge_Ns)
        print(f"| {name} | {values[sizes[-1]][1]:.5f} | {cells} |")
    print("\nlocal exponents -dlog|delta|/dlogN between neighbouring N:")
    for name, devs in fitted.items():
        sizes = sorted(devs)
        loc = [-np.log(abs(devs[b] / devs[a])) / np.log(b / a) for a, b in zip(sizes, sizes[1:])]
        print(f"  {name}: " + ", ".join(f"{a}-{b}: {v:.2f}" for (a, b), v in zip(zip(sizes, sizes[1:]), loc)))
    print(f"\nfits over N >= {args.fit_from} (relative RMS residual), and the fit's prediction of the sampled deviations:")
    print("| probe | model | N range | parameters | rel. RMS | " + " | ".join(f"N={N} sampled" for N in SAMPLED[0.5]) + " |")
    print("|" + " --- |" * (5 + len(SAMPLED[0.5])))
    results = {}
    for name, _, z, sizes in probes:
        use = [N for N in sizes if N >= args.fit_from]
        devs = [fitted[name][N] for N in use]
        for model in MODELS:
            params, rms = fit(model, use, devs)
            results[(name, model)] = params
            cells = ""
            if z is not None:
                cells = " | ".join(f"{predict(model, params, N):.5f} vs {d:.5f}±{e:.5f} ({(predict(model, params, N) - d) / e:+.1f} sigma)" for N, (d, e) in SAMPLED[z].items())
            else:
                cells = " | ".join("-" for _ in SAMPLED[0.5])
            print(f"| {name} | {model} | {use[0]}-{use[-1]} | " + ", ".join(f"{p:.4g}" for p in params) + f" | {rms:.2e} | {cells} |")

    print("\nthe leading exponent g of a N^-g + b/N + c N^-2g fitted freely on N = fit-from..N_max, as N_max grows:")
    for name, _, z, sizes in probes[:3]:
        use = [N for N in sizes if N >= args.fit_from]
        cells = []
        for k in range(5, len(use) + 1):  # at least five points for four parameters
            (g, *_), rms = fit_free_exponent(use[:k], [fitted[name][N] for N in use[:k]])
            cells.append(f"{use[k - 1]}: {g:.3f} ({rms:.1e})")
        print(f"  {name}: " + ", ".join(cells))
        if z is not None and len(use) >= 5:  # the free fit on all of the exact range, extrapolated to the sampled N
            (g, *rest), _ = fit_free_exponent(use, [fitted[name][N] for N in use])
            pred = {N: free_value((g, *rest), N) for N in SAMPLED[z]}
            print(f"    g = {g:.3f} extrapolated: " + ", ".join(f"N={N} {(pred[N] - d) / e:+.1f} sigma" for N, (d, e) in SAMPLED[z].items()))
    print("\nif the truth were the N^(-1/3) series from N^(-2/3) (four terms fitted on the exact range), the free"
          " fit's g as N_max grows (the exact range, then every 8):")
    for name, _, _z, sizes in probes[:3]:
        use = [N for N in sizes if N >= args.fit_from]
        if len(use) < 5:
            continue
        later = [N for N in (160, 200, 300, 500, 1000, 2000) if N > use[-1]]
        amps, rms, drift = drift_under_series(use, [fitted[name][N] for N in use], use[4:] + later)
        print(f"  {name}: amplitudes " + ", ".join(f"{a:.4g}" for a in amps) + f" ({rms:.1e}); g: "
              + ", ".join(f"{N}: {g:.3f}" for N, g in drift.items()))
        if _z is not None:  # the series, extrapolated to the sampled deviations it never saw
            print("    the series extrapolated: " + ", ".join(
                f"N={N} {(series_value(amps, N) - d) / err:+.1f} sigma"
                for N, (d, err) in SAMPLED[_z].items()))
    if args.predict is not None:
        print(f"\npredictions for N = {args.predict}, fitted on N = {args.fit_from}..{edge_Ns[-1]}:")
        for name, _, _z, sizes in probes[:3]:
            use = [N for N in sizes if N >= args.fit_from]
            if len(use) < 5:
                continue
            ahead = predict_ahead(use, [fitted[name][N] for N in use], args.predict)
            print(f"  {name}: deviation: series {ahead['series']:.7f}, three-term {ahead['three_term']:.7f}, "
                  f"free exponent {ahead['free']:.7f}; free g at N_max = {args.predict}: "
                  f"{ahead['g_series']:.3f} (series), {ahead['g_stays']:.3f} (exponent stays put)")
        for name, _, _z, sizes in probes[3:]:  # the grid point x = 0 or -1/N goes with the parity of the row z N
            z = BULK_PROBES[name]
            use = [N for N in sizes if N >= args.fit_from and round(z * N) % 2 == round(z * args.predict) % 2]
            if len(use) < 4:
                continue
            ahead = predict_bulk(use, [fitted[name][N] for N in use], args.predict)
            print(f"  {name} fitted on N = {use[0]}..{use[-1]}: deviation: " + ", ".join(
                f"{series} {value:.7f} ({rms:.1e})" for series, (value, rms) in ahead.items()))
    print("\nout of sample: the three-term fit on N < N_max predicts N_max (relative error):")
    model = "a/N^(2/3) + b/N + c/N^(4/3)"
    for name, _, _z, sizes in probes[:3]:
        use = [N for N in sizes if N >= args.fit_from]
        cells = []
        for k in range(4, len(use)):
            params, _ = fit(model, use[:k], [fitted[name][N] for N in use[:k]])
            target = use[k]
            cells.append(f"{target}: {(predict(model, params, target) - fitted[name][target]) / fitted[name][target]:+.1e}")
        print(f"  {name}: " + ", ".join(cells))

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    os.makedirs(args.figures, exist_ok=True)
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.5))
    grid = np.geomspace(args.fit_from, 2500, 200)
    for ax, (name, z) in zip(axes, (("edge z=1/2", 0.5), ("edge z=3/4", 0.75))):
        sizes = sorted(fitted[name])
        ax.loglog(sizes, [abs(fitted[name][N]) for N in sizes], "ko", ms=4, label="exact (Pfaffian route)")
        sN = list(SAMPLED[z])
        ax.errorbar(sN, [SAMPLED[z][N][0] for N in sN], yerr=[SAMPLED[z][N][1] for N in sN], fmt="s", color="C3",
                    ms=4, label="exact sampler (not fitted)")
        for k, model in enumerate(MODELS):
            ax.loglog(grid, [abs(predict(model, results[(name, model)], N)) for N in grid], f"C{k}-", lw=1, label=f"fit {model}")
        ax.set_title(f"lattice direction, z = {z}: <W_(i,1)> - limit")
        ax.set_xlabel("N")
        ax.legend(fontsize=7)
    fig.tight_layout()
    path = os.path.join(args.figures, "scaling_refit.png")
    fig.savefig(path, dpi=110)
    print(f"\nfigure: {path}")


if __name__ == "__main__":
    main()
