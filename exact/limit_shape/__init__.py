"""Closed forms of the scaling limit of the response, as exact sympy expressions.

May import: nothing of the package.
"""

from .closed_forms import bottom_row_limit, diagonal_limit, edge_profile, lattice_direction_limit, level_curve_expr

__all__ = ["level_curve_expr", "diagonal_limit", "lattice_direction_limit", "bottom_row_limit", "edge_profile"]
