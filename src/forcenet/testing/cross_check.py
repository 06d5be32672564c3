"""The main job's Monte Carlo cross-check: exact-sampler samples of every free grain against the exact table.

``forcenet table`` (without ``--format``/``--out``) plans
(:func:`cross_check_plan`) and runs (:func:`cross_check`) it after the exact
table; the comparison is :func:`forcenet.testing.compare` with the bounds
``0 <= W <= 1``, so its false-alarm rate is bounded at every number of
samples.  The cost model sits here, next to the computation it describes.

Examples
--------
>>> from forcenet.exact.triangle.moments import mean_W
>>> cross_check(4, mean_W(4), 200, seed=1).passed
True
>>> cross_check_plan(4, 200).runnable
True
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import replace
from fractions import Fraction
from typing import Any

import numpy as np

from forcenet.core.plan import Plan
from forcenet.exact.triangle.staircase import dimension
from forcenet.numeric.triangle.exact_sampler import ExactSampler, sample_plan

from .assertions import TableAgreement, compare

__all__ = ["CROSS_CHECK_COPIES", "CROSS_CHECK_SECONDS_PER_VALUE", "cross_check_plan", "cross_check"]

# peak bytes of the comparison per stored value (samples x free grains doubles): the matrix, its
# concatenation, and the centred and scaled copies of forcenet.testing.compare (5.5-5.7 measured at N = 40, 60, 100)
CROSS_CHECK_COPIES = 6
# seconds per stored value of the comparison (the autocorrelation guard, z-scores, the bounded betting test):
# 0.6-0.75 us measured at 20000 rows of 780-4950 grains before the betting test; with it, 0.49-0.53 us of CPU at
# 20000 rows of 190 and 780 grains (benchmarks/cross_check_cost.py, 2026-11-25, on the loaded 2-core machine)
CROSS_CHECK_SECONDS_PER_VALUE = 7e-7


def cross_check_plan(N: int, samples: int, memory_bytes: int | None = None) -> Plan:
    """The cost of :func:`cross_check`: drawing the samples, and the time and memory of comparing every free grain.

    Parameters
    ----------
    N : int
        Number of layers, ``>= 2``.
    samples : int
        Independent exact-sampler samples, ``>= 2``.
    memory_bytes : int, optional
        Memory available (None: not checked); a plan that needs more is refused.

    Returns
    -------
    Plan

    Examples
    --------
    >>> cross_check_plan(40, 20000, memory_bytes=2**20).runnable
    False
    """

    plan = sample_plan(N, samples)
    grains = dimension(N)
    return replace(plan, seconds=plan.seconds + CROSS_CHECK_SECONDS_PER_VALUE * samples * grains,
                   nbytes=plan.nbytes + CROSS_CHECK_COPIES * 8 * samples * grains).within_memory(memory_bytes)


def cross_check(N: int, means: Sequence[Sequence[Fraction]], samples: int, seed: int,
                progress: Callable[..., Any] | None = None) -> TableAgreement:
    """Exact-sampler samples of every free grain against the exact ``<W>`` table (:func:`~.assertions.compare`).

    Parameters
    ----------
    N : int
        Number of layers, ``>= 2``.
    means : list of lists of Fraction
        The exact table, rows ``i = 1..N``, ``j = 1..i``.
    samples : int
        Independent samples of :class:`~forcenet.numeric.triangle.exact_sampler.ExactSampler`, ``>= 2``.
    seed : int
        The sampler's seed.
    progress : callable, optional
        Called as ``progress(k)`` after each batch of ``k`` samples.

    Returns
    -------
    TableAgreement
        The verdict over the ``N(N-1)/2`` free grains (``W_{i,i}`` is one
        minus the others); every ``W`` lies in ``[0, 1]``.

    Examples
    --------
    >>> from forcenet.exact.triangle.moments import mean_W
    >>> cross_check(3, mean_W(3), 100, seed=2).values
    3
    """

    grains = [(i, j) for i in range(2, N + 1) for j in range(1, i)]  # W_{i,i} = 1 - the others
    sampler = ExactSampler(N, seed=seed)
    rows = []
    done = 0
    while done < samples:
        k = min(sampler.batch, samples - done)
        W = sampler.sample_W(k)
        rows.append(np.stack([W[:, i - 1, j - 1] for i, j in grains], axis=1))
        done += k
        if progress is not None:
            progress(k)
    exact = [means[i - 1][j - 1] for i, j in grains]
    return compare(np.concatenate(rows), exact, keys=grains, bounds=(0, 1))  # every W lies in [0, 1]: any K
