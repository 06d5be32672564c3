"""``python -m forcenet`` and the ``forcenet`` command: the command line, after numba's vector width is chosen.

numba reads its CPU features when it is imported, and :mod:`forcenet.cli`
imports it, so :func:`run` lets the kernels use 512-bit vectors
(:func:`forcenet.core.compiled.prefer_wide_vectors`) before importing the
command line.
"""

import sys


def run() -> int:
    """The ``forcenet`` command: wide vectors where the machine has them, then :func:`forcenet.cli.main`."""
    from forcenet.core.compiled import prefer_wide_vectors

    prefer_wide_vectors()
    from forcenet.cli import main

    return main()


if __name__ == "__main__":
    sys.exit(run())
