"""``forcenet transfer``, ``forcenet bethe`` and ``forcenet entropy``: the chicken-wire model of Sec. 7.4."""

from __future__ import annotations

import argparse
from fractions import Fraction

import forcenet
from forcenet.core.errors import ArgumentError, ForcenetError
from forcenet.core.precision import check_within_pi

from .common import (
    UsageError,
    add_force,
    add_format,
    add_quiet,
    defer,
    given,
    integer,
    real,
    refuse_together,
    run_planned,
)
from .output import emit

__all__ = ["register"]


def cmd_transfer(args: argparse.Namespace) -> int:
    plan = forcenet.transfer_spectrum_plan(args.L, args.particles)
    spectrum = run_planned(plan.cost, plan.run, force=args.force, quiet=args.quiet)
    emit(spectrum.to_json() if args.format == "json" else spectrum.to_text(), args.out)
    return 0


def cmd_bethe(args: argparse.Namespace) -> int:
    plan = forcenet.bethe_ground_state_plan(args.L, args.n, args.m)
    # a ConvergenceError (no ground state converged) is of the family: one line, its message, exit code 2
    state = run_planned(plan.cost, plan.run, force=args.force, quiet=args.quiet)
    emit(state.to_json() if args.format == "json" else state.to_text(), args.out)
    return 0


def _density(text: str) -> Fraction:
    """--Q: a number or a fraction c/a in [0, 1/3], kept exact."""
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
    if not text.isascii():
        raise argparse.ArgumentTypeError(f"phi={text!r} is not a number: use the ASCII digits 0-9")
    try:  # a finite number in range, one check (the front door checks it again for a Python caller)
        return str(check_within_pi(text, "phi")).strip()
    except ForcenetError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None


def _side(text: str) -> str:
    """--F: the hexagon side l of Eq. (7.4), a finite number > 0, kept as the string given (read at full precision)."""
    real("F", 0, low_open=True)(text)
    return text.strip()


def cmd_entropy(args: argparse.Namespace) -> int:
    if args.max and args.bethe:
        raise UsageError("--bethe goes with --phi or --Q (the maximum comes from the closed form)")
    refuse_together(args, "max", "F", "the maxima do not depend on the hexagon side l of Eq. (7.4)")
    if given(args, "L_max") and not args.bethe:
        raise UsageError("--L-max sets the widths of --bethe: add --bethe or drop --L-max")
    if args.max:
        plan = forcenet.isotropic_maximum_plan(args.dps)
    else:
        plan = forcenet.isotropic_point_plan(args.phi, args.Q, dps=args.dps, side=args.F, bethe=args.bethe,
                                             L_max=args.L_max if args.bethe else None)
    result = run_planned(plan.cost, plan.run, force=args.force, quiet=args.quiet)
    emit(result.to_json() if args.format == "json" else result.to_text(), args.out)
    return 0


def register(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    p = sub.add_parser("transfer", help="chicken-wire model (Sec. 7.4): largest transfer-matrix eigenvalue per particle sector")
    # --L and --particles: read as integers; their ranges are the front door's check (once)
    p.add_argument("--L", type=integer("L", 2, 14, deferred=True), required=True, help="cylinder width (2..14)")
    p.add_argument("--particles", type=integer("particles", 0, deferred=True), default=None,
                   help="only this particle sector, 0..L (default: all)")
    defer(p, "L", "--L")
    defer(p, "particles", "--particles")
    add_format(p)
    add_force(p)
    add_quiet(p)
    p.set_defaults(func=cmd_transfer)

    p = sub.add_parser("bethe", help="chicken-wire model: Bethe roots and the largest eigenvalue of a sector")
    p.add_argument("--L", type=integer("L", 3, 5000, deferred=True), required=True, help="cylinder width (3..5000)")
    p.add_argument("--n", type=integer("n", 2, deferred=True), default=None, help="particles per row (default 2 round(L/6))")
    p.add_argument("--m", type=integer("m", 1, deferred=True), default=None, help="left-movers among them (default n/2)")
    for name in ("L", "n", "m"):  # ranges: the front door's check (once)
        defer(p, name, f"--{name}")
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
    p.add_argument("--dps", type=integer("dps", 5, 10000, deferred=True), default=50, help="decimal digits (5..10000, default 50)")
    p.add_argument("--F", type=_side, default=None,
                   help="hexagon side l (force scale) of Eq. (7.4), a finite number > 0 (default 1), read at full "
                        "precision like --phi")
    p.add_argument("--bethe", action="store_true", help="also the independent Bethe-ansatz value of v (announces its cost)")
    p.add_argument("--L-max", type=integer("L_max", 60, 1200, deferred=True), default=240,
                   help="largest Bethe-ansatz width (60..1200, default 240)")
    defer(p, "dps", "--dps")  # --dps and --L-max: ranges checked once, by the front door
    defer(p, "L_max", "--L-max")
    add_format(p)
    add_force(p)
    add_quiet(p)
    p.set_defaults(func=cmd_entropy)
