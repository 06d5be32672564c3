"""The thesis's own routes of chapter 4, reconstructed and verified.

* :mod:`.coefficients`: gamma (4.15), the index range (4.32)/(4.86), the defect line;
* :mod:`.fundamental`: the printed fundamental relations (4.14)-(4.32), (4.46), (4.49);
* :mod:`.recursions`: Lambda (4.50)-(4.51), the boundary (4.67), Gamma (4.73)-(4.77);
* :mod:`.map_counting`: the maps of Sec. 4.6 (4.86)-(4.91) and their bijection with tableaux;
* :mod:`.nested`: the layer-by-layer nested-matrix integration (4.14)-(4.46);
* :mod:`.symbolic`: the same layers as sympy matrices, step by step, for small N (``notes/symbolic_session.md``).
"""

from .coefficients import gamma_coefficient
from .fundamental import index_tuples, integral_I, normalization_fundamental, psi_fundamental, right_vector
from .map_counting import (
    count_maps,
    is_map,
    map_from_tableau,
    maps,
    maps_by_bottom_row,
    mean_W_by_maps,
    mean_W_thesis_maps,
    moment_thesis_maps,
    moments_by_maps,
    tableau_from_map,
)
from .nested import integrate_layers, mean_W_nested, moment_nested, moment_table_nested, normalization_nested
from .recursions import (
    boundary_mean_W,
    count_lambda,
    count_lambda_chain,
    gamma_bulk_integer,
    gamma_sums,
    lambda_table,
    mean_W_gamma,
    normalization_lambda,
)
from .symbolic import integrate_layer_step, moment_symbolic, nested_layers

__all__ = [
    "gamma_coefficient", "integral_I", "index_tuples", "psi_fundamental", "right_vector", "normalization_fundamental",
    "lambda_table", "count_lambda", "count_lambda_chain", "normalization_lambda", "boundary_mean_W",
    "gamma_sums", "gamma_bulk_integer", "mean_W_gamma",
    "maps", "is_map", "count_maps", "maps_by_bottom_row", "map_from_tableau", "tableau_from_map",
    "mean_W_thesis_maps", "moment_thesis_maps", "moments_by_maps", "mean_W_by_maps",
    "integrate_layers", "normalization_nested", "moment_nested", "moment_table_nested", "mean_W_nested",
    "nested_layers", "integrate_layer_step", "moment_symbolic",
]
