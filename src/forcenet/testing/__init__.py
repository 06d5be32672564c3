"""Test a sampler or a formula against the exact ensemble in a few lines.

Assertions (numpy and scipy only, :mod:`.assertions`):

* :func:`assert_agrees` / :func:`compare` — samples (independent, or a
  Markov chain with ``chain=True``) of one value or a whole table against
  the exact values, at a level ``alpha`` that bounds the false-alarm rate
  of a correct sampler for the whole table (at every number of samples
  with ``bounds=(lo, hi)``); the failure message names the worst values,
  their z-scores and the chain's integrated time; samples that cannot
  support a verdict raise :class:`CannotJudgeError` with the reason;
* :func:`assert_means_agree` — means with trusted standard errors;
* :func:`exact_mean_W` — exact tables of the triangle and of fully mobilized
  packings, shaped as the samplers' output;
* :func:`cross_check` / :func:`cross_check_plan` — the Monte Carlo
  cross-check of ``forcenet table``'s main job and its cost (:mod:`.cross_check`).

Hypothesis strategies (:mod:`forcenet.testing.strategies`, needs
``pip install 'forcenet[testing]'``): triangle sizes and grains, exact
uniform force networks, feasible packing scenes, chicken-wire
configurations on small tori.

How-to: ``notes/testing_against_exact.md``.

Examples
--------
>>> from forcenet.testing import assert_agrees, exact_mean_W
>>> from forcenet.numeric.triangle.exact_sampler import ExactSampler
>>> assert_agrees(ExactSampler(4, seed=0).sample_W(200), exact_mean_W(4), bounds=(0, 1)).passed
True
"""

import importlib
from types import ModuleType

from .assertions import (
    CannotJudgeError,
    DisagreementError,
    TableAgreement,
    assert_agrees,
    assert_means_agree,
    compare,
    exact_array,
)
from .counterparts import exact_mean_W
from .cross_check import cross_check, cross_check_plan

__all__ = [
    "CannotJudgeError",
    "DisagreementError",
    "TableAgreement",
    "assert_agrees",
    "assert_means_agree",
    "compare",
    "cross_check",
    "cross_check_plan",
    "exact_array",
    "exact_mean_W",
    "strategies",
]


def __getattr__(name: str) -> ModuleType:
    if name == "strategies":  # imported on first use: it needs hypothesis
        return importlib.import_module(f"{__name__}.strategies")
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
