"""The fully mobilized triangle (Sec. 4.2): the exact core.

* :mod:`.staircase`: tableau counts, the normalization, grain <-> cell;
* :mod:`.ideal_dp`: multi-modular path sums over order ideals (the engine);
* :mod:`.moments`: ``<W>``, ``<W^s>``, correlations, exactly;
* :mod:`.spacings`: Dirichlet spacings given the ranks;
* :mod:`.configuration`: one configuration, W <-> q <-> partial sums <-> contact forces;
* :mod:`.gaps`, :mod:`.joint_gaps`: exact laws of rank gaps (the spacings W, F1, F2, F5, F6; q);
* :mod:`.distribution`: exact densities, CDFs and pooled P(f) (sympy polynomials);
* :mod:`.tables`: JSON / CSV / LaTeX tables, atomic writes.
* :mod:`.free_fermion`: the mean in polynomial time (free fermions, Schur Pfaffians);
  :mod:`.de_bruijn`: the floor's and every layer's load laws (de Bruijn's Pfaffians);
  :mod:`.pfaffian_table`: ``--method pfaffian``; :mod:`.law_routes`: the DP against the Pfaffians for a law;
  below both, :mod:`.residues`, :mod:`.prime_tasks` (the per-prime tasks, the one plan over primes), :mod:`.gap_counts`.
"""

from .configuration import W_from_q, contact_forces, in_ensemble, partial_sums, q_from_W
from .distribution import cdf, contact_density, density, layer_force_density, triangle_force_density
from .moments import correlation, covariance, mean_W, mean_W_grain, moment, moment_table, variance_table
from .staircase import cell_to_grain, count, count_by_hooks, dimension, grain_to_cell, normalization

__all__ = [
    "count", "count_by_hooks", "dimension", "normalization", "grain_to_cell", "cell_to_grain",
    "mean_W", "mean_W_grain", "moment", "moment_table", "correlation", "covariance", "variance_table",
    "W_from_q", "q_from_W", "partial_sums", "in_ensemble", "contact_forces",
    "density", "cdf", "contact_density", "layer_force_density", "triangle_force_density",
]
