"""``python -m forcenet`` and the ``forcenet`` command: the command line, after numba's vector width is chosen.

numba reads its CPU features when it is imported, and :mod:`forcenet.cli`
imports it, so :func:`run` lets the kernels use 512-bit vectors
(:func:`forcenet.core.compiled.prefer_wide_vectors`) before importing the
command line.  It also makes SIGTERM (``kill PID``) and SIGHUP (the
terminal closed) end a run as Ctrl-C does: the worker processes stopped,
nothing half-written, exit code 143 or 129 (``128 + signal``).  A SIGKILL
cannot be caught: the workers then end by their parent-death signal
(:func:`forcenet.core.execution.die_with_parent`).
"""

import signal
import sys
from types import FrameType

from forcenet.core.compiled import check_environment, prefer_wide_vectors
from forcenet.core.errors import ArgumentError  # the standard library only: numba is not imported yet


def run() -> int:
    """The ``forcenet`` command: wide vectors where the machine has them, SIGTERM and SIGHUP as Ctrl-C, then the
    command line."""

    try:
        check_environment()  # before numba is imported: some settings abort the process inside LLVM
    except ArgumentError as refusal:
        print(f"forcenet: error: {refusal}", file=sys.stderr)
        return 2
    prefer_wide_vectors()
    from forcenet.cli import main

    terminated = []

    def on_terminate(signum: int, frame: FrameType | None) -> None:  # the path of Ctrl-C: the pool's workers terminated, no partial output
        terminated.append(signum)
        handler = signal.getsignal(signal.SIGINT)
        if callable(handler):  # Python's, or the one that defers an interrupt out of numba's callbacks
            handler(signal.SIGINT, frame)
        else:  # SIGINT ignored (a background job): the interrupt all the same
            raise KeyboardInterrupt

    for name in ("SIGTERM", "SIGHUP"):
        if hasattr(signal, name) and signal.getsignal(getattr(signal, name)) is not signal.SIG_IGN:
            signal.signal(getattr(signal, name), on_terminate)  # SIGHUP ignored (nohup): left ignored
    code = main()
    return 128 + terminated[0] if terminated and code == 130 else code


if __name__ == "__main__":
    sys.exit(run())
