"""Floating-point numerics and samplers for the force network ensemble.

``numeric`` may import :mod:`exact`; :mod:`exact` never imports ``numeric``.
"""

from .exact_sampler import ExactSampler, sample_tableaux

__all__ = ["ExactSampler", "sample_tableaux"]
