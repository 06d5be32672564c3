"""Exact load laws beyond the mean in polynomial time: de Bruijn's Pfaffians of the floor and of every layer.

The gap-law route (derivations in ``notes/fluctuations.md`` Sec. 5-6): the
floor's loads from its Legendre ensemble, every layer above it with the floor
integrated out, each as a Pfaffian on a ``(s, w)`` grid modulo word-size
primes (one task per prime, :mod:`forcenet.exact.triangle.prime_tasks`):

* :mod:`.floor`: the floor's pooled law and every floor load's law, their plan;
* :mod:`.layers`: the same for any layer above the floor;
* :mod:`.floor_kernels`, :mod:`.floor_displacement`, :mod:`.layer_kernels`:
  the compiled grids and Pfaffians (numba, primes below ``2^22``).

The choice between these and the order-ideal DP is
:mod:`forcenet.exact.triangle.law_routes`; every moment of every load
(``forcenet table --method pfaffian --moments s``) is
:mod:`forcenet.exact.triangle.pfaffian_table`.

Examples
--------
>>> from forcenet.exact.triangle.de_bruijn.floor import floor_gap_laws
>>> floor_gap_laws(4)[2].counts  # W_(4,2): the rank gap is 2 or 3
(0, 0, 1, 1, 0, 0, 0, 0)
"""

__all__: list[str] = []  # the routes are in the modules; the package exports nothing of its own
