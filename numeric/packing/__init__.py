"""The N x P packing of Secs. 3.2-3.3: scenes, forces, the Metropolis sampler, the response.

* :mod:`.scene`: boundary conditions and forces from q or from the lateral forces;
* :mod:`.metropolis`: the sampler and the response G(i, j);
* :mod:`.networks`: the independent rejection route and the maximin network.
"""

from .metropolis import PackingMetropolis, response
from .networks import maximin_network, uniform_networks
from .scene import Scene, contact_forces, forces_from_lateral, forces_from_q, lateral_forces

__all__ = [
    "Scene", "forces_from_q", "forces_from_lateral", "lateral_forces", "contact_forces",
    "PackingMetropolis", "response", "uniform_networks", "maximin_network",
]
