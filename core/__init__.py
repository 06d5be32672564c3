"""Neutral ground of forcenet: what every layer (exact, numeric, the command line, testing) shares.

* :mod:`.errors`: the exception family (``ForcenetError`` and its argument, type and convergence errors);
* :mod:`.validation`: argument checks, each raising an error that names the argument and its range;
* :mod:`.plan`: the cost of a computation announced before it runs (:class:`~.plan.Plan`), and work chunks
  short enough for Ctrl-C;
* :mod:`.precision`: the precision policy (inputs converted inside ``mpmath.workdps`` with guard digits).
"""
