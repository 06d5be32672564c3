"""The scaling limit of the response at any precision (mpmath).

May import: :mod:`forcenet.core.validation`, :mod:`forcenet.exact.limit_shape`.
"""

from .surface import bulk_response, lattice_response, level_curve, level_curve_slope, limit_surface

__all__ = ["level_curve", "level_curve_slope", "limit_surface", "bulk_response", "lattice_response"]
