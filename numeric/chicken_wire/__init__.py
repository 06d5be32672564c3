"""The chicken-wire model of Sec. 7.4 in floating point and at any precision.

* :mod:`.transfer`: the transfer matrix (matrix-product operator, sparse sectors), certified Perron roots;
* :mod:`.monte_carlo`: the hexagon shrink/expand Monte Carlo of Fig. 7.8;
* :mod:`.bethe`: the nested Bethe ansatz (to L ~ 1000), with a photon fugacity;
* :mod:`.isotropic`: the entropy on the isotropic line, (7.1)-(7.4).
"""
