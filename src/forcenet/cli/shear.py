"""``forcenet shear`` and ``forcenet yield-stress``: force networks under shear (thesis Ch. 8).

``forcenet yield-stress --size L``: the largest shear stress ``tau = sigma_xy/sigma_xx`` the ``L x L``
periodic hexagonal packing admits, exactly (with its proof) and by floating LP (``--float``: that one only).
``forcenet shear --tau 0 0.1 0.2``: the anisotropic finite-size scaling of Sec. 8.3 (``nu_M``, ``nu_m``, the
anisotropy ``r(tau)``), planned and announced, each ``tau`` checkpointed with ``--checkpoint DIR``.  Both
parse, call the front door (:func:`forcenet.yield_stress`, :func:`forcenet.shear_scaling_plan`) and render
the result's ``to_json()`` / ``to_text()``; bad input is one line and exit code 2.
"""

from __future__ import annotations

import argparse
from collections.abc import Callable
from typing import TYPE_CHECKING

import forcenet

from .common import add_force, add_format, add_quiet, add_seed, integer, real, run_planned
from .output import emit

if TYPE_CHECKING:
    from forcenet import ShearScaling

__all__ = ["register"]


def cmd_yield(args: argparse.Namespace) -> int:
    result = forcenet.yield_stress(args.geometry, args.size, exact=not args.float)
    emit({"json": result.to_json, "text": result.to_text}[args.format](), args.out)
    return 0


def cmd_shear(args: argparse.Namespace) -> int:
    plan = forcenet.shear_scaling_plan(tuple(args.tau), L=args.L, samples=args.samples, thin=args.thin,
                                       replicas=args.replicas, seed=args.seed, model=args.model,
                                       checkpoint=args.checkpoint)

    def run(tick: Callable[..., None] | None) -> ShearScaling:
        return plan.run(progress=tick)

    result = run_planned(plan.cost, run, force=args.force, quiet=args.quiet)
    emit({"json": result.to_json, "text": result.to_text}[args.format](), args.out)
    return 0


def register(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    p = sub.add_parser("yield-stress", help="the largest shear stress a packing's force networks admit (Sec. 8.2)")
    p.add_argument("--geometry", choices=["hexagonal"], default="hexagonal",
                   help="the periodic hexagonal packing (default)")
    p.add_argument("--size", type=integer("size", 3, 40), default=3,
                   help="its period L (3..6 exactly; up to 40 with --float; default 3)")
    p.add_argument("--float", action="store_true", help="the floating linear program only (no exact proof)")
    add_format(p)
    p.set_defaults(func=cmd_yield)
    q = sub.add_parser("shear", help="anisotropic scaling of the clusters of large forces under shear (Sec. 8.3)")
    q.add_argument("--tau", type=real("tau"), nargs="+", default=[0.0, 0.1, 0.2, 0.3],
                   help="shear stresses sigma_xy/sigma_xx, |tau| < 1/sqrt(3) (default 0 0.1 0.2 0.3)")
    q.add_argument("--L", type=integer("L", 6, 4096), default=40, help="the torus' period (default 40)")
    q.add_argument("--samples", type=integer("samples", 4), default=200, help="networks per tau (default 200)")
    q.add_argument("--thin", type=integer("thin", 1), default=20, help="wheel-move sweeps between networks (20)")
    q.add_argument("--replicas", type=integer("replicas", 0, 10000), default=30, help="bootstrap replicas (30)")
    q.add_argument("--model", choices=["ensemble", "independent"], default="ensemble",
                   help="the sheared ensemble (default) or independent forces (the percolation control)")
    q.add_argument("--checkpoint", default=None, help="a folder keeping every finished tau (a rerun reuses them)")
    add_seed(q)
    add_format(q)
    add_force(q)
    add_quiet(q)
    q.set_defaults(func=cmd_shear)
