"""``forcenet limit``: the scaling limit of the response at reduced coordinates (x, z)."""

from __future__ import annotations

import argparse
from collections.abc import Callable

from .common import (
    UsageError,
    add_format,
    integer,
    json_dumps,
    real,
)
from .output import emit

__all__ = ["register"]


def cmd_limit(args: argparse.Namespace) -> int:
    import mpmath

    from forcenet.numeric.limit_shape.edge import EDGE_EXPONENT, edge_amplitude, edge_sd_amplitude
    from forcenet.numeric.limit_shape.surface import bulk_response, lattice_response

    z, x, dps = args.z, args.x, args.dps
    if not abs(float(x)) <= float(z):
        raise UsageError(f"x={x} is out of range: x must lie in [-z, z] = [-{z}, {z}]")
    lattice = lattice_response(z, dps=dps)
    on_lattice = abs(float(x)) == float(z) and float(z) < 1  # the bulk density diverges there
    bulk = None if on_lattice else bulk_response(x, z, dps=dps)
    bulk_text = "inf" if on_lattice else mpmath.nstr(bulk, dps)
    # the N^(-2/3) edge correction of <W_(i,1)> (Tracy-Widom GUE at the end of the level curves)
    edge = (edge_amplitude(z, dps=dps), edge_sd_amplitude(z, dps=dps)) if on_lattice else None
    if args.format == "json":
        out = {"x": float(x), "z": float(z), "dps": dps, "N_W_bulk": None if on_lattice else bulk_text,
               "W_lattice": mpmath.nstr(lattice, dps), "on_lattice_direction": on_lattice,
               "edge_exponent": str(EDGE_EXPONENT) if edge else None,
               "edge_amplitude": mpmath.nstr(edge[0], dps) if edge else None,
               "edge_sd_amplitude": mpmath.nstr(edge[1], dps) if edge else None}
        emit(json_dumps(out), args.out)
        return 0
    lines = [f"scaling limit at x = {x}, z = {z} ({dps} digits)"]
    if on_lattice:
        lines.append("  bulk:              N <W>  -> infinity (|x| = z is a lattice direction: <W> itself stays finite)")
    else:
        lines.append(f"  bulk:              N <W>  -> {bulk_text}")
    lines.append(f"  lattice direction: <W>    -> {mpmath.nstr(lattice, dps)}  (= (1 - sqrt(z(2-z)))/2)")
    if edge:
        lines.append(f"  edge correction:   <W> - limit = {mpmath.nstr(edge[0], dps)} N^(-{EDGE_EXPONENT}) + O(1/N)")
        lines.append(f"  edge fluctuation:  sd(W) = {mpmath.nstr(edge[1], dps)} N^(-{EDGE_EXPONENT})  (Tracy-Widom GUE)")
    emit("\n".join(lines), args.out)
    return 0


def register(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    p = sub.add_parser("limit", help="scaling limit of the response at reduced coordinates (x, z)")
    # the coordinates stay strings: they are converted inside mpmath.workdps, so every digit given counts
    p.add_argument("--x", type=_decimal("x", -1, 1), required=True, help="horizontal coordinate (2j - i - 1)/N, |x| <= z; "
                   "read at full precision (every digit given counts)")
    p.add_argument("--z", type=_decimal("z", 0, 1, low_open=True), required=True, help="depth i/N in (0, 1]")
    p.add_argument("--dps", type=integer("dps", 5, 1000), default=20,
                   help="decimal digits (5..1000, default 20; on a lattice direction 5..60 for the edge law: "
                        "20 digits ~3 s, 60 digits minutes)")
    add_format(p)
    p.set_defaults(func=cmd_limit)


def _decimal(name: str, low: float | None, high: float | None, low_open: bool = False) -> Callable[[str], str]:
    """A finite number in range, kept as the string given (full precision later)."""
    check = real(name, low, high, low_open=low_open)

    def parse(text: str) -> str:
        check(text)
        return text.strip()

    parse.__name__ = "value"
    return parse
