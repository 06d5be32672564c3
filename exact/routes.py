"""The routes of ``forcenet table``: one plan and one run per method.

=========  ==========================================================  ==========
method     engine                                                      reach
=========  ==========================================================  ==========
fast       order-ideal path sums (:mod:`.triangle.moments`)            N ~ 28-30
thesis     nested-matrix integration (:mod:`.thesis.nested`)           N <= 9
lambda     Lambda/Gamma recursions (:mod:`.thesis.recursions`)         N <= 12
maps       map counting of Sec. 4.6 (:mod:`.thesis.map_counting`)      N <= 9
pfaffian   Schur Pfaffians, minor summation (:mod:`.triangle.pfaffian`)  N ~ 64-100
=========  ==========================================================  ==========

Each engine owns its cost knowledge; :func:`table_plan` only asks it.

May import: every subpackage of :mod:`forcenet.exact` (this is the exact facade of the CLI).

Examples
--------
>>> table_plan("fast", 9).runnable
True
>>> tables = table_run("lambda", 5)
>>> [str(x) for x in tables[1][-1]]
['1/11', '1/4', '7/22', '1/4', '1/11']
"""

from __future__ import annotations

from .plan import Plan, combine
from .validation import check_int, check_layers
from .errors import ArgumentError

__all__ = ["METHODS", "table_plan", "table_run"]

METHODS = ("fast", "thesis", "lambda", "maps", "pfaffian")
MAX_MOMENTS = 50


def _engine(method: str):
    if method == "thesis":
        from .thesis import nested as engine
    elif method == "lambda":
        from .thesis import recursions as engine
    elif method == "maps":
        from .thesis import map_counting as engine
    elif method == "pfaffian":
        from .triangle.pfaffian import route as engine
    else:
        raise ArgumentError(f"method={method!r} is out of range: method must be one of {', '.join(METHODS)}")
    return engine


def _fast_plan(N: int, moments: int, memory_bytes: int | None) -> Plan:
    from .triangle.moments import mean_W_plan, moment_table_plan

    plans = [mean_W_plan(N, memory_bytes)] + [moment_table_plan(N, s, memory_bytes) for s in range(2, moments + 1)]
    what = plans[0].what if moments == 1 else f"exact tables N={N}, <W^s> for s = 1..{moments} (order ideals)"
    return combine(what, plans, "ideal")


def table_plan(method: str, N: int, moments: int = 1, memory_bytes: int | None = None, **options) -> Plan:
    """What ``forcenet table --method METHOD --N N --moments MOMENTS`` will cost.

    Parameters
    ----------
    method : {"fast", "thesis", "lambda", "maps", "pfaffian"}
    N : int
        Number of layers, ``>= 2``.
    moments : int
        Highest moment ``s`` of ``W^s``, ``1..50``.
    memory_bytes : int, optional
        Memory available to the run; a plan that needs more is refused.
    **options
        ``executor=``, ``checkpoint=`` of the multi-modular route (pfaffian).

    Returns
    -------
    :class:`~forcenet.exact.plan.Plan`
    """
    N = check_layers(N)
    moments = check_int(moments, "moments", 1, MAX_MOMENTS)
    options = _check_options(method, options)
    if method == "fast":
        return _fast_plan(N, moments, memory_bytes)
    return _engine(method).table_plan(N, moments, memory_bytes, **options)


def _check_options(method: str, options: dict) -> dict:
    """The given (not None) engine options; refused for a route that has no independent tasks."""
    given = {k: v for k, v in options.items() if v is not None}
    if given and method != "pfaffian":
        raise ArgumentError(f"{', '.join(f'{k}=' for k in given)} applies to method='pfaffian' only "
                         "(the route over independent primes)")
    return given


def table_run(method: str, N: int, moments: int = 1, progress=None, memory_bytes: int | None = None, **options) -> dict:
    """``{s: table of <W_{i,j}^s>}`` for ``s = 1..moments`` by the chosen route (exact Fractions).

    ``progress(k=1)`` is called with the plan's ticks; ``options`` as in :func:`table_plan`.
    """
    N = check_layers(N)
    moments = check_int(moments, "moments", 1, MAX_MOMENTS)
    options = _check_options(method, options)
    if method != "fast":
        return _engine(method).table_run(N, moments, progress=progress, **options)
    from .triangle.moments import _residue_budget, mean_W, moment_table

    tables = {1: mean_W(N, progress=progress, memory_bytes=_residue_budget(memory_bytes))}
    for s in range(2, moments + 1):
        tables[s] = moment_table(N, s, progress=progress)
    return tables
