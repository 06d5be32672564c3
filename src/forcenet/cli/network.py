"""``forcenet network FILE``: the force network ensemble on the user's own contact network (thesis Sec. 2.3).

The file is JSON: ``{"grains": n, "contacts": [[i, j, "nx", "ny"], ...], "loads": [[g, "fx", "fy"], ...]}``
(``j`` null for a wall; numbers exact as strings such as ``"1/2"`` or ``"sqrt(3)/2"``; optional
``"friction"``, ``"radii"``, ``"positions"``).  ``--exact``: every contact force's exact mean (and second
moment, ``--moments 2``) through Normaliz, and with ``--density`` its exact density (piecewise
polynomials); ``--samples K --seed S``: hit-and-run samples, means with error bars (``--checkpoint DIR``:
resumable).  A bad network (not balanced, infeasible, unbounded, not JSON, ...) is one line and exit code 2.
"""

from __future__ import annotations

import argparse
from collections.abc import Callable
from typing import TYPE_CHECKING

import forcenet

from .common import add_force, add_format, add_quiet, integer, run_planned
from .output import emit

if TYPE_CHECKING:
    from forcenet import NetworkResult

__all__ = ["register"]


def cmd_network(args: argparse.Namespace) -> int:
    plan = forcenet.network_plan(args.file, exact=True if args.exact else None if args.samples is None else False,
                                 moments=args.moments, samples=args.samples, seed=args.seed, burn_in=args.burn_in,
                                 method=args.method, thin=args.thin, chains=args.chains,
                                 checkpoint=args.checkpoint,
                                 density=None if args.density is None else (args.density or True))

    def run(tick: Callable[..., None] | None) -> NetworkResult:
        return plan.run(progress=tick)

    result = run_planned(plan.cost, run, force=args.force, quiet=args.quiet)
    text = {"json": result.to_json, "csv": result.to_csv, "text": result.to_text}[args.format]()
    emit(text, args.out)
    return 0


def register(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    p = sub.add_parser("network", help="the force network ensemble on your own contact network (JSON file)")
    p.add_argument("file", help="the contact network, a JSON file: {\"grains\": n, \"contacts\": [[i, j, \"nx\", \"ny\"], "
                                "...], \"loads\": [[g, \"fx\", \"fy\"], ...]}")
    p.add_argument("--exact", action="store_true",
                   help="exact moments through Normaliz (the default without --samples; needs exact data)")
    p.add_argument("--moments", type=integer("moments", 1, 2), default=1, help="1: means; 2: and second moments")
    p.add_argument("--samples", type=integer("samples", 2), default=None,
                   help="hit-and-run sweeps recorded (an integer >= 2): sampled means with error bars")
    p.add_argument("--seed", type=integer("seed", 0, 2**63 - 1), default=0, help="random seed (default 0)")
    p.add_argument("--burn-in", type=integer("burn-in", 0), default=None,
                   help="sweeps discarded first (default max(100, samples/10))")
    p.add_argument("--thin", type=integer("thin", 1), default=1,
                   help="sweeps between two recorded samples (default 1; memory is samples x contacts)")
    p.add_argument("--chains", type=integer("chains", 1), default=1,
                   help="independent chains sharing --samples, one worker process each (default 1)")
    p.add_argument("--density", nargs="*", type=integer("density", 0), metavar="C", default=None,
                   help="with --exact: the exact density of contact C's normal force (several: C C ...; none "
                        "given: every contact's force that balance does not fix), a piecewise polynomial from "
                        "the triangulation, in the text and json output")
    p.add_argument("--checkpoint", metavar="DIR", default=None,
                   help="record the sampler's finished blocks (or chains) in DIR; the same command run again "
                        "(after Ctrl-C) resumes there, with the same numbers as an uninterrupted run")
    p.add_argument("--method", choices=["auto", "triangulation", "volumes"], default="auto",
                   help="the exact route (default auto: the faster by the plans)")
    add_format(p, choices=("text", "json", "csv"))
    add_force(p)
    add_quiet(p)
    p.set_defaults(func=cmd_network)
