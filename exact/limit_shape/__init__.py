"""Closed forms of the scaling limit of the response, as exact sympy expressions.
"""

from .closed_forms import (
    bottom_row_limit,
    bulk_edge_coefficient,
    diagonal_limit,
    edge_density_coefficient,
    edge_profile,
    edge_scale,
    kesten_mckay_edge_coefficient,
    lattice_direction_limit,
    level_curve_expr,
)

__all__ = ["level_curve_expr", "diagonal_limit", "lattice_direction_limit", "bottom_row_limit", "edge_profile",
           "edge_density_coefficient", "kesten_mckay_edge_coefficient", "edge_scale", "bulk_edge_coefficient"]
