"""Independent reference routes: they implement the definitions directly and share no code
with the routes they check (the exact core, the thesis's routes).

* :mod:`.integration`: sympy integration over the polytope (4.8)-(4.9);
* :mod:`.linear_extensions`: averages over linear extensions (networkx);
* :mod:`.dictionary_dp`: the plain dictionary dynamic program (also the benchmark baseline).
"""
