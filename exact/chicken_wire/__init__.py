"""The chicken-wire vertex model of Sec. 7.4, exactly.

* :mod:`.model`: the six vertices, the row transfer matrix, counts on tori;
* :mod:`.sectors`: exact characteristic polynomials per particle sector;
* :mod:`.closed_form`: the entropy on the isotropic line, Eqs. (7.1)-(7.4), as sympy expressions.
"""

from .model import (
    VERTICES,
    count_torus,
    count_torus_by_enumeration,
    row_transitions,
    transfer_matrix,
    vertex_counts_torus,
)
from .sectors import sector_polynomial_factors

__all__ = [
    "VERTICES", "row_transitions", "transfer_matrix", "count_torus", "count_torus_by_enumeration",
    "vertex_counts_torus", "sector_polynomial_factors",
]
