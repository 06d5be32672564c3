"""Floating-point numerics and samplers for the force network ensemble (``forcenet.numeric``).

One subpackage per model, named as in :mod:`forcenet.exact`:

* :mod:`.triangle`: the exact sampler and the Metropolis sampler of the triangle;
* :mod:`.packing`: the N x P packing, its scenes, sampler and response;
* :mod:`.chicken_wire`: transfer matrix, Monte Carlo, Bethe ansatz, isotropic line;
* :mod:`.limit_shape`: the scaling limit at any precision;
* :mod:`.autocorr`: integrated autocorrelation times (shared by the samplers).

``forcenet.numeric`` may import :mod:`forcenet.exact`; never the other way.
"""


__all__: list[str] = []  # the samplers live in the subpackages; importing one module stays light
