"""Options of the routes over independent primes: ``--scheduler`` (a Dask cluster), ``--checkpoint``, ``--no-checkpoint``.

``forcenet table --method pfaffian`` and the floor's route of ``forcenet dist``
hand their per-prime tasks to an executor (:func:`forcenet.exact.execution.run_tasks`);
this module turns the three options into that executor (a Dask client) and a
checkpoint store, refusing them for a route that does not run over primes.
"""

from __future__ import annotations

import os

from .common import FORCE_SECONDS, UsageError

__all__ = ["DISTRIBUTED_MISSING", "CONNECT_SECONDS", "connect_scheduler", "add_engine_options", "engine_options"]

DISTRIBUTED_MISSING = "--scheduler needs Dask's distributed scheduler: pip install 'forcenet[distributed]'"
CONNECT_SECONDS = 10  # waiting for the scheduler, then for its first worker


def connect_scheduler(address: str):
    """A Dask client of the scheduler at ``address`` (``tcp://host:port`` or a scheduler file), with a worker."""
    try:
        from distributed import Client
    except ImportError:
        raise UsageError(DISTRIBUTED_MISSING) from None
    if os.path.isfile(address):
        where = {"scheduler_file": address}
    elif "://" in address:
        where = {"address": address}
    else:
        raise UsageError(f"--scheduler={address}: give the tcp://host:port of a running `dask scheduler` "
                         "or its scheduler file")
    try:
        client = Client(**where, timeout=CONNECT_SECONDS, set_as_default=False)
    except (OSError, TimeoutError, ValueError) as exc:
        reason = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        raise UsageError(f"--scheduler={address}: cannot connect ({reason})") from None
    try:
        client.wait_for_workers(1, timeout=CONNECT_SECONDS)
    except (OSError, TimeoutError):
        client.close()
        raise UsageError(f"--scheduler={address}: the cluster has no workers (start `dask worker {address}`)") from None
    return client


def add_engine_options(p, what: str) -> None:
    """``--scheduler``, ``--checkpoint``, ``--no-checkpoint`` for a route over independent primes (``what`` names it)."""
    p.add_argument("--scheduler", metavar="ADDRESS",
                   help=f"run {what}'s per-prime tasks on a Dask cluster: the tcp://host:port of a running "
                        "`dask scheduler`, or its scheduler file (workers need forcenet installed; "
                        "pip install 'forcenet[distributed]')")
    p.add_argument("--checkpoint", metavar="DIR",
                   help=f"record every finished prime of {what} in DIR; a rerun of the same request "
                        "recomputes only what is missing (default for runs announced at over a minute: "
                        "$XDG_CACHE_HOME/forcenet, else ~/.cache/forcenet)")
    p.add_argument("--no-checkpoint", action="store_true", help="no checkpoints, even for runs over a minute")


def engine_options(args, applies: bool, what: str, plan_seconds: float, store_for):
    """``(client or None, checkpoint store or None)`` from :func:`add_engine_options`' arguments.

    ``applies``: the chosen route runs over primes (else the options are refused, naming ``what``).  Runs
    announced at over a minute checkpoint by default in the user's cache directory; ``store_for(directory)``
    makes the request's store.
    """
    from forcenet.exact.checkpoints import default_directory

    from .output import check_output_dir

    if args.checkpoint is not None and args.no_checkpoint:
        raise UsageError("--checkpoint and --no-checkpoint contradict each other: give one")
    if not applies:
        for name in ("scheduler", "checkpoint"):
            if getattr(args, name) is not None:
                raise UsageError(f"--{name} applies to {what} only (the route over independent primes)")
        return None, None
    directory = args.checkpoint
    if directory is not None:
        check_output_dir(directory, "--checkpoint")
    elif not args.no_checkpoint and plan_seconds > FORCE_SECONDS:
        directory = default_directory()
    store = None if directory is None else store_for(directory)
    client = connect_scheduler(args.scheduler) if args.scheduler is not None else None
    return client, store


def report_checkpoints(store, ticks: int) -> None:
    """The closing line on stderr about a run's checkpoints: a store's reuse, or the directory of a run with one
    request per layer (``store`` is then the directory itself)."""
    import sys

    if isinstance(store, str):
        print(f"forcenet: checkpoints in {store} (one request per layer)", file=sys.stderr)
    else:
        print(f"forcenet: checkpoints in {store.path}: reused {store.reused} of {ticks} primes, "
              f"computed {ticks - store.reused}", file=sys.stderr)
