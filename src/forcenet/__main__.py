"""``python -m forcenet`` and the ``forcenet`` command: the command line, after numba's vector width is chosen.

numba reads its CPU features when it is imported, and :mod:`forcenet.cli`
imports it, so :func:`run` lets the kernels use 512-bit vectors
(:func:`forcenet.core.compiled.prefer_wide_vectors`) before importing the
command line.  It also makes SIGTERM (``kill PID``) end a run as Ctrl-C
does: the worker processes stopped, nothing half-written, exit code 143.
"""

import signal
import sys


def run() -> int:
    """The ``forcenet`` command: wide vectors where the machine has them, SIGTERM as Ctrl-C, then the command line."""
    from forcenet.core.compiled import prefer_wide_vectors

    prefer_wide_vectors()
    from forcenet.cli import main

    terminated = []

    def on_terminate(signum, frame):  # the path of Ctrl-C: the pool's workers terminated, no partial output
        terminated.append(signum)
        handler = signal.getsignal(signal.SIGINT)
        if callable(handler):  # Python's, or the one that defers an interrupt out of numba's callbacks
            handler(signal.SIGINT, frame)
        else:  # SIGINT ignored (a background job): the interrupt all the same
            raise KeyboardInterrupt

    signal.signal(signal.SIGTERM, on_terminate)
    code = main()
    return 128 + signal.SIGTERM if terminated and code == 130 else code


if __name__ == "__main__":
    sys.exit(run())
