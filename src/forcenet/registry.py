"""The one registry of engines, keyed by model, quantity and method (:class:`forcenet.core.registry.Registry`).

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

from forcenet.core.registry import Registry

__all__ = ["REGISTRY"]

REGISTRY = Registry()
REGISTRY.add_loader("contact-network", "forcenet.contact_network_engines")
