"""The scaling limit of the response at any precision (mpmath).
"""

from .edge import (
    EDGE_EXPONENT,
    bulk_edge_coefficient,
    edge_amplitude,
    edge_scale,
    edge_sd_amplitude,
    tracy_widom_moments,
)
from .surface import bulk_response, lattice_response, level_curve, level_curve_slope, limit_surface

__all__ = ["level_curve", "level_curve_slope", "limit_surface", "bulk_response", "lattice_response",
           "EDGE_EXPONENT", "tracy_widom_moments", "edge_scale", "edge_amplitude", "edge_sd_amplitude",
           "bulk_edge_coefficient"]
