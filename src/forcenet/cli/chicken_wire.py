"""``forcenet transfer``, ``forcenet bethe`` and ``forcenet entropy``: the chicken-wire model of Sec. 7.4."""

from __future__ import annotations

import argparse
from collections.abc import Callable
from fractions import Fraction
from typing import Any

from forcenet.core.errors import ArgumentError

from .common import (
    UsageError,
    add_force,
    add_format,
    add_quiet,
    given,
    integer,
    json_dumps,
    real,
    refuse_together,
    run_planned,
)
from .output import emit

__all__ = ["register"]


def _r(x: float) -> float:
    """A float rounded to 12 decimals, the eigensolvers' accuracy: identical runs print identical bytes
    (BLAS kernels may change the last bits from run to run)."""
    return round(float(x), 12) + 0.0  # + 0.0: no negative zero


def cmd_transfer(args: argparse.Namespace) -> int:
    from forcenet.numeric.chicken_wire.transfer import sector_entropy, transfer_plan

    L = args.L
    plan = transfer_plan(L, args.particles)
    sectors = [args.particles] if args.particles is not None else list(range(L + 1))

    def run(tick: Callable[..., None] | None) -> list[dict[str, Any]]:
        rows = []
        for n in sectors:
            lam, per_site = sector_entropy(L, particles=n)
            rows.append({"particles": n, "lambda": _r(lam), "entropy_per_site": _r(per_site)})
            if tick:
                tick()
        return rows

    rows = run_planned(plan, run, force=args.force, quiet=args.quiet)
    top = max(rows, key=lambda r: r["lambda"])
    out = {"L": L, "lambda_max": top["lambda"], "entropy_per_site": top["entropy_per_site"], "sectors": rows}
    bulk = [r for r in rows if r["particles"] > 0]
    if bulk and args.particles is None:
        best = max(bulk, key=lambda r: r["lambda"])
        out["bulk"] = {"particles": best["particles"], "entropy_per_site": best["entropy_per_site"]}
    if args.format == "json":
        emit(json_dumps(out), args.out)
        return 0
    lines = [f"chicken-wire transfer matrix, cylinder of width L = {L}: lambda_max = {top['lambda']:.15g}, "
             f"log(lambda)/L = {top['entropy_per_site']:.12g} per site"]
    lines += [f"  n = {r['particles']:2d}: lambda = {r['lambda']:.15g}   log(lambda)/L = {r['entropy_per_site']:.12g}" for r in rows]
    emit("\n".join(lines), args.out)
    return 0


def cmd_bethe(args: argparse.Namespace) -> int:
    from forcenet.core.errors import ConvergenceError
    from forcenet.numeric.chicken_wire.bethe_sector import default_sector, ground_state, ground_state_plan

    L = args.L
    n, m = default_sector(L, args.n, args.m)
    plan = ground_state_plan(L, n, m)

    def run(tick: Callable[..., None] | None) -> Any:
        try:
            return ground_state(L, n, m, progress=tick)
        except ConvergenceError as exc:
            raise UsageError(str(exc)) from None

    sol = run_planned(plan, run, force=args.force, quiet=args.quiet)
    out = {
        "L": L, "n": n, "m": m, "eigenvalue": _r(sol.eigenvalue), "entropy_per_site": _r(sol.entropy_per_site),
        "residual": float(f"{sol.residual:.1e}"),
        "w": [[round(float(z.real), 12), round(float(z.imag), 12)] for z in sol.w],
        "u": [[round(float(z.real), 12), round(float(z.imag), 12)] for z in sol.u],
    }
    if args.format == "json":
        emit(json_dumps(out), args.out)
        return 0
    lines = [f"Bethe ansatz, L = {L}, n = {n} particles, m = {m} left-movers: Lambda = {sol.eigenvalue:.15g}, "
             f"log(Lambda)/L = {sol.entropy_per_site:.15g} per site (max residual {sol.residual:.1e})",
             "  u: " + "  ".join(f"{z.real:+.10f}{z.imag:+.10f}i" for z in sol.u),
             "  w: " + "  ".join(f"{z.real:+.10f}{z.imag:+.10f}i" for z in sol.w)]
    emit("\n".join(lines), args.out)
    return 0


def _density(text: str) -> Fraction:
    """--Q: a number or a fraction c/a in [0, 1/3], kept exact."""
    import argparse
    from fractions import Fraction

    try:
        if not text.isascii():
            raise ArgumentError(text)
        q = Fraction(text.strip())
    except (ValueError, ZeroDivisionError):
        raise argparse.ArgumentTypeError(f"Q={text!r} is not a number: Q must be a number or fraction in [0, 1/3]") from None
    if not 0 <= q <= Fraction(1, 3):
        raise argparse.ArgumentTypeError(f"Q={text} is out of range: Q must lie in [0, 1/3]")
    return q


def _phi(text: str) -> str:
    """--phi: a finite number in [-pi/2, pi/2] (compared with pi/2 at the digits given), kept as the string given."""
    import argparse

    from forcenet.numeric.chicken_wire import isotropic as iso

    real("phi")(text)  # a finite ASCII number
    text = text.strip()
    if not iso.phi_within_range(text):
        raise argparse.ArgumentTypeError(f"phi={text} is out of range: phi must lie in [-pi/2, pi/2] "
                                         "= [-1.5707963267948966192..., 1.5707963267948966192...]")
    return text


def _side(text: str) -> str:
    """--F: the hexagon side l of Eq. (7.4), a finite number > 0, kept as the string given (read at full precision)."""
    real("F", 0, low_open=True)(text)
    return text.strip()


def _inside(args: argparse.Namespace) -> bool:
    """Whether the point is strictly inside ``0 < Q < 1/3`` (``|phi| < pi/2``), decided exactly."""
    from fractions import Fraction

    from forcenet.numeric.chicken_wire import isotropic as iso

    if args.Q is not None:
        return 0 < args.Q < Fraction(1, 3)
    return iso.phi_within_range(args.phi, strict=True)


def _closed_form_rows(args: argparse.Namespace, dps: int) -> list[tuple[str, str, Any]]:
    """Every quantity at the point, named by what it is (mpmath values)."""
    import mpmath

    from forcenet.numeric.chicken_wire import isotropic as iso

    point = {"phi": args.phi} if args.phi is not None else {"Q": args.Q}
    if args.phi is not None:
        Q = iso.density_Q(args.phi, dps)
        with mpmath.workdps(dps):
            phi_value = mpmath.mpf(args.phi)
    else:
        with mpmath.workdps(dps):
            Q = mpmath.mpf(args.Q.numerator) / args.Q.denominator
        phi_value = iso.phi_of_density(args.Q, dps)
    eps = iso.eps_of(**point, dps=dps)
    rows = [
        ("phi", "parameter of Eqs. (7.1)-(7.2)", phi_value),
        ("Q", "bonds per site in each of the three directions, Eq. (7.2)", Q),
        ("v_per_site", "entropy per chicken-wire site, Eq. (7.1)", iso.entropy(**point, dps=dps)),
        ("empty_per_site", "empty sites per site = square-triangle tiling vertices per site, 1 - 3Q + 3Q^2", iso.empty_density(**point, dps=dps)),
        ("s_per_tiling_vertex", "entropy per square-triangle tiling vertex, v / e", iso.tiling_entropy(**point, dps=dps)),
    ]
    if _inside(args):
        rows.append(("mu", "log-fugacity of each bond direction, -(1/3) dv/dQ", iso.chemical_potential(**point, dps=dps)))
    if eps > 0:
        rows.append(("eps", "pi/2 - phi", eps))
        rows.append(_series_row(args, eps, rows[2][2], dps))
    side = "1" if args.F is None else args.F
    rows.append(("g_per_grain_7_4", f"entropy per grain in the continuum limit, Eq. (7.4) corrected: log(6 l) - 3/2 at l = {side}",
                 iso.entropy_per_grain(side, dps)))
    return rows


# the leading term of (7.3) is shown as an approximation of v where it is one: within 1 % of v
_SERIES_TOLERANCE = 0.01


def _series_row(args: argparse.Namespace, eps: Any, v: Any, dps: int) -> tuple[str, str, Any]:
    """The leading term of (7.3) at ``eps``, described with its deviation from ``v`` where it is no approximation."""
    import mpmath

    from forcenet.numeric.chicken_wire import isotropic as iso

    series = iso.leading_series_at(eps, dps, args.Q)
    what = "approximation of v by the leading term of Eq. (7.3), corrected: eps^2 (log(108/eps^2) - 3)/18"
    if not abs(series - v) <= _SERIES_TOLERANCE * v:
        what += (f"; NOT VALID here: eps = {mpmath.nstr(eps, 3)} is not small, it differs from v by "
                 f"{mpmath.nstr(abs(series - v), 2)}")
    return ("v_series_7_3", what, series)


def _maximum_rows(dps: int) -> list[tuple[str, str, Any]]:
    from forcenet.numeric.chicken_wire import isotropic as iso

    m = iso.maximum(dps)
    return [
        ("v_max_per_site", "maximal entropy per chicken-wire site (where mu = 0)", m.v_max),
        ("Q_max", "its bond density per direction", m.Q_max),
        ("phi_max", "its parameter phi", m.phi_max),
        ("s_max_per_tiling_vertex", "maximal entropy per square-triangle tiling vertex, log 108 - 2 sqrt3 log(2 + sqrt3)", m.s_max),
        ("Q0", "its bond density per direction (phi = 0, the twelvefold point), (3 - sqrt3)/6", m.Q0),
        ("v_per_site_at_Q0", "entropy per chicken-wire site there (half of s_max)", m.v_at_Q0),
        ("empty_per_site_at_Q0", "tiling vertices per site there", m.empty_per_site),
        ("Y_per_site_at_Q0", "Y vertices (one kind) per site there, 3 Q0^2", m.y_per_site),
        ("squares_per_tiling_vertex", "squares per tiling vertex there", m.squares_per_vertex),
        ("triangles_per_tiling_vertex", "triangles per tiling vertex there (half upright, half rotated)", m.triangles_per_vertex),
        ("squares_per_triangle", "squares per triangle there, sqrt3/4", m.squares_per_triangle),
    ]


def cmd_entropy(args: argparse.Namespace) -> int:
    import mpmath

    from forcenet.core.plan import combine
    from forcenet.numeric.chicken_wire.isotropic import closed_form_plan

    dps = args.dps
    if args.max and args.bethe:
        raise UsageError("--bethe goes with --phi or --Q (the maximum comes from the closed form)")
    refuse_together(args, "max", "F", "the maxima do not depend on the hexagon side l of Eq. (7.4)")
    if given(args, "L_max") and not args.bethe:
        raise UsageError("--L-max sets the widths of --bethe: add --bethe or drop --L-max")
    closed = closed_form_plan(dps, maximum=args.max)
    plans = [closed]
    if args.bethe:
        from forcenet.numeric.chicken_wire.isotropic_bethe import isotropic_entropy_plan

        plans.append(isotropic_entropy_plan(args.Q, args.L_max))
    plan = combine(plans[-1].what if args.bethe else closed.what, plans, plans[-1].unit)

    def run(tick: Callable[..., None] | None) -> tuple[list[tuple[str, str, Any]], dict[str, Any] | None]:
        rows = _maximum_rows(dps) if args.max else _closed_form_rows(args, dps)
        bethe = _bethe(args, rows) if args.bethe else None
        if tick:
            tick()
        return rows, bethe

    rows, bethe = run_planned(plan, run, force=args.force, quiet=args.quiet)
    out = {"dps": dps}
    out.update({key: mpmath.nstr(value, dps) for key, _, value in rows})
    out.update({f"{key}_note": what.split("; ", 1)[1] for key, what, _ in rows if "; NOT VALID here" in what})
    if bethe:
        out.update(bethe)
    if args.format == "json":
        emit(json_dumps(out), args.out)
        return 0
    width = max(len(key) for key, _, _ in rows)
    lines = [f"{key:<{width}} = {mpmath.nstr(value, dps)}   ({what})" for key, what, value in rows]
    if bethe:
        lines.append(f"{'v_bethe':<{width}} = {bethe['v_bethe']:.12f} +- {bethe['v_bethe_error']:.1e}   "
                     f"(entropy per site from the Bethe ansatz, densities {', '.join(bethe['bethe_densities'])}, L <= {args.L_max})")
    emit("\n".join(lines), args.out)
    return 0


def _bethe(args: argparse.Namespace, rows: list[tuple[str, str, Any]]) -> dict[str, Any]:
    """The independent Bethe-ansatz value of v at the point (float, with its error)."""
    from forcenet.core.errors import ConvergenceError
    from forcenet.numeric.chicken_wire.isotropic_bethe import isotropic_entropy

    Q = args.Q if args.Q is not None else float(dict((key, value) for key, _, value in rows)["Q"])
    try:
        v, err, densities = isotropic_entropy(Q, args.L_max)
    except ConvergenceError as exc:
        raise UsageError(f"Bethe ansatz: {exc}") from None
    return {"v_bethe": v, "v_bethe_error": err, "bethe_densities": [str(f) for f in densities]}


def register(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    p = sub.add_parser("transfer", help="chicken-wire model (Sec. 7.4): largest transfer-matrix eigenvalue per particle sector")
    p.add_argument("--L", type=integer("L", 2, 13), required=True, help="cylinder width (2..13)")
    p.add_argument("--particles", type=integer("particles", 0), default=None, help="only this particle sector, 0..L (default: all)")
    add_format(p)
    add_force(p)
    add_quiet(p)
    p.set_defaults(func=cmd_transfer)

    p = sub.add_parser("bethe", help="chicken-wire model: Bethe roots and the largest eigenvalue of a sector")
    p.add_argument("--L", type=integer("L", 3, 5000), required=True, help="cylinder width (3..5000)")
    p.add_argument("--n", type=integer("n", 2), default=None, help="particles per row (default 2 round(L/6))")
    p.add_argument("--m", type=integer("m", 1), default=None, help="left-movers among them (default n/2)")
    add_format(p)
    add_force(p)
    add_quiet(p)
    p.set_defaults(func=cmd_bethe)

    p = sub.add_parser("entropy", help="chicken-wire model: entropy on the isotropic line, Eqs. (7.1)-(7.4), closed form")
    mode = p.add_mutually_exclusive_group(required=True)
    mode.add_argument("--phi", type=_phi, help="parameter of Eqs. (7.1)-(7.2), -pi/2 <= phi <= pi/2; read at full precision: every digit given "
                           "counts (0.3 is exactly 3/10, not the nearest float)")
    mode.add_argument("--Q", type=_density, help="bond density per direction, a number or fraction in [0, 1/3]")
    mode.add_argument("--max", action="store_true", help="the maxima: per site (mu = 0) and per tiling vertex (phi = 0)")
    p.add_argument("--dps", type=integer("dps", 5, 10000), default=50, help="decimal digits (5..10000, default 50)")
    p.add_argument("--F", type=_side, default=None,
                   help="hexagon side l (force scale) of Eq. (7.4), a finite number > 0 (default 1), read at full "
                        "precision like --phi")
    p.add_argument("--bethe", action="store_true", help="also the independent Bethe-ansatz value of v (announces its cost)")
    p.add_argument("--L-max", type=integer("L-max", 60, 1200), default=240, help="largest Bethe-ansatz width (60..1200, default 240)")
    add_format(p)
    add_force(p)
    add_quiet(p)
    p.set_defaults(func=cmd_entropy)
