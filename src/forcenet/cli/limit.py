"""``forcenet limit``: the scaling limit of the response at reduced coordinates (x, z)."""

from __future__ import annotations

import argparse
from collections.abc import Callable

import forcenet

from .common import add_format, defer, integer, real
from .output import emit

__all__ = ["register"]


def cmd_limit(args: argparse.Namespace) -> int:
    result = forcenet.limit_shape(args.x, args.z, dps=args.dps)  # x in [-z, z] checked there, exactly
    emit(result.to_json() if args.format == "json" else result.to_text(), args.out)
    return 0


def register(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    p = sub.add_parser("limit", help="scaling limit of the response at reduced coordinates (x, z)")
    # the coordinates stay strings: forcenet.limit_shape reads them exactly, so every digit given counts
    p.add_argument("--x", type=_decimal("x", -1, 1), required=True, help="horizontal coordinate (2j - i - 1)/N, |x| <= z; "
                   "read at full precision (every digit given counts)")
    p.add_argument("--z", type=_decimal("z", 0, 1, low_open=True), required=True, help="depth i/N in (0, 1]")
    p.add_argument("--dps", type=integer("dps", 5, 10000, deferred=True), default=20,
                   help="decimal digits (5..10000, default 20; 10000 digits ~6 s; on a lattice direction 5..60 "
                        "for the edge law: 20 digits ~3 s, 60 digits ~90 s)")
    defer(p, "dps", "--dps")  # the range (and the edge's 60) checked once, by forcenet.limit_shape
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
