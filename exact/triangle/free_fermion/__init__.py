"""Exact ``<W>`` tables of the fully mobilized triangle in polynomial time: free fermions, Schur Pfaffians.

The mean's route behind ``forcenet table --method pfaffian`` (derivation and
proofs in ``notes/free_fermions.md``; the method's table engine, higher
moments included, is :mod:`forcenet.exact.triangle.pfaffian_table`):

* :mod:`.schur`: Schur's Pfaffian, Pfaffian minor summation and the
  point-process kernel, exactly (Fractions; the reference for small ``N``);
* :mod:`.kernels`: the compiled word-size kernels (numba): the kernel's
  displacement generators and the displacement elimination;
* :mod:`.cost`: the primes and their cost; :mod:`.engine`: one prime, the
  survival table ``S[m][k]`` modulo ``p``;
* :mod:`.route`: primes, Chinese remaindering, worker processes, the
  ``<W>`` table (4.63)-(4.77), the lattice directions alone
  (``lattice_direction``, two eliminations per level point instead of ``n + 1``), the count (4.1), the plans;
* :mod:`.partial_sums`: ``<S_ij^2>`` of every partial sum and ``E[T^2]`` of
  every tableau entry, from the same evaluations with a second level functional;
  :mod:`.covers`: ``<W^2>`` of layer ``N - 1`` from them;
* :mod:`.fluctuations`: the exact gap laws of the lattice-direction grains.

Examples
--------
>>> from forcenet.exact.triangle.free_fermion import mean_W, count
>>> count(6), [str(x) for x in mean_W(4)[-1]]
(286, ['1/7', '5/14', '5/14', '1/7'])
"""

from .partial_sums import entry_moments, partial_sum_moments, partial_sum_moments_plan
from .route import (
                    count,
                    expected_entries,
                    lattice_direction,
                    lattice_direction_plan,
                    mean_plan,
                    mean_W,
                    normalization,
                    survival_table,
)

__all__ = ["count", "normalization", "expected_entries", "mean_W", "mean_plan", "lattice_direction",
           "lattice_direction_plan", "survival_table", "partial_sum_moments", "partial_sum_moments_plan",
           "entry_moments"]
