"""The one registry of engines, keyed by model, quantity and method (:data:`forcenet.core.registry.REGISTRY`).

Each model's engines register themselves when their module is imported; the
registry imports a model's module the first time that model is asked for
(``REGISTRY.add_loader``), so ``import forcenet`` loads no engine.  A new
model enters with one line here and its own engine module: nothing else of
the house changes (``notes/architecture.md``, "Adding a model").

Examples
--------
>>> from forcenet.registry import REGISTRY
>>> isinstance(REGISTRY.models(), tuple)
True
"""

from __future__ import annotations

from forcenet.core.registry import REGISTRY  # the one instance: core holds it, so every layer's engines register

__all__ = ["REGISTRY"]

REGISTRY.add_loader("triangle", "forcenet.exact.routes")  # tables, rows, laws (forcenet.exact.routes.ENGINES)

# the force-chain models (Part III, issue 52): finite-size scaling of the clusters of large forces
for _model in ("percolation", "q-independent", "q-microcanonical", "snooker", "disordered", "averaged"):
    REGISTRY.add_loader(_model, "forcenet.numeric.force_chains.engines")
REGISTRY.add_loader("contact-network", "forcenet.contact_network_engines")
REGISTRY.add_loader("shear", "forcenet.numeric.force_chains.sheared_ensembles")  # Ch. 8: the sheared ensemble
