"""Samplers of the fully mobilized triangle.

* :mod:`.exact_sampler`: independent uniform samples (random tableaux, no Markov chain);
* :mod:`.metropolis`: the Metropolis sampler in q of Sec. 3.2.4 and the q-model contrast;
* :mod:`.force_distribution`: exact densities in floating point, sampled P(f) histograms with error bars.
"""

from .exact_sampler import ExactSampler, sample_tableaux
from .metropolis import TriangleMetropolis, q_model_samples

__all__ = ["ExactSampler", "sample_tableaux", "TriangleMetropolis", "q_model_samples"]
