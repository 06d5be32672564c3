"""forcenet: exact enumeration and Monte Carlo for the force network ensemble of static granular matter.

The front door (one flat namespace, loaded on first use so ``import forcenet`` stays cheap):

* :func:`table` / :func:`plan` — the exact ``<W_ij>`` (and ``<W_ij^s>``) table of the fully
  mobilized triangle and its cost, by the fastest route (:mod:`forcenet.front_door`);
* :func:`law` / :func:`law_plan` — one load's exact law (a grain's ``W_ij``, a contact force, a layer's or
  the ensemble's pooled ``P(f)``): density, CDF and moments as exact polynomials, and its cost
  (:mod:`forcenet.laws`);
* :func:`count`, :func:`normalization` — the tableaux count and the volume, Eq. (4.1);
  :func:`count_plan` — its cost and its decimal digits (:class:`CountPlan`, :class:`TableauxCount`);
* :func:`maps` — the maps of Sec. 4.6 per bottom row, Eq. (4.88) (:class:`MapCounts`);
* :func:`limit_shape` — the scaling limit of the response at ``(x, z)``, bulk, lattice direction and edge
  (:class:`LimitShape`);
* :func:`density`, :func:`cdf`, :func:`contact_density` — one load's exact law (Beta mixtures);
* :func:`sample` / :func:`sample_plan` — Monte Carlo ``<W_ij>`` with standard errors (the exact sampler or the
  Metropolis chain, on the triangle or on the N x P packing of a :class:`Scene`) and its cost
  (:mod:`forcenet.sampling`); :meth:`Law.compare_with_samples` — a pooled ``P(f)`` against sampled histograms;
* :class:`ExactSampler`, :class:`TriangleMetropolis` — the exact sampler and the thesis's Metropolis chain;
* :func:`entropy`, :func:`tiling_entropy` — the chicken-wire entropy (7.1) and the square-triangle tiling's;
* :func:`transfer_spectrum`, :func:`bethe_ground_state`, :func:`isotropic_point`, :func:`isotropic_maximum`
  (each with its ``..._plan``) — the chicken-wire model's transfer spectrum, Bethe ground states and the
  quantities on its isotropic line, Eqs. (7.1)-(7.4) (:mod:`forcenet.chicken_wire_sectors`,
  :mod:`forcenet.chicken_wire_isotropic`);
* :func:`clusters`, :func:`scaling` / :func:`scaling_plan` — clusters of large forces and their finite-size
  scaling (Part III, Eqs. 6.8, 6.12): users' force networks, or percolation and the q-models of Sec. 7.3
  generated at several sizes (:mod:`forcenet.force_chains`, :class:`ForceChainScaling`);
* :func:`network` / :func:`network_plan` — any contact network's force network ensemble (Sec. 2.3): every
  contact force's exact moments (Normaliz) or sampled ones (hit-and-run), :func:`network_response`
  (:func:`contact_network` builds one; :mod:`forcenet.contact_networks`);
* :func:`yield_stress`, :func:`shear_scaling` / :func:`shear_scaling_plan` — force networks under shear
  (Ch. 8): the yield stress exactly, the anisotropic scaling of Eqs. (8.2)-(8.9) (:mod:`forcenet.shear`);
* :mod:`forcenet.testing` — test your own sampler or formula against the exact ensemble;
* the exception family (:mod:`forcenet.core.errors`): :class:`ForcenetError`, the base of every
  expected failure, :class:`ArgumentError` (also a ``ValueError``), :class:`ArgumentTypeError`
  (also a ``TypeError``) and :class:`ConvergenceError` (also a ``RuntimeError``), and the warning
  :class:`PrecisionWarning` (a binary float accepted where an exact number was expected).

Behind it: :mod:`forcenet.exact` (exact results, one subpackage per model), :mod:`forcenet.numeric`
(samplers, floating point), :mod:`forcenet.cli` (the command line, which calls these same functions).
The map of the package is ``notes/architecture.md``.

Examples
--------
>>> import forcenet
>>> from importlib.metadata import version
>>> forcenet.__version__ == version("forcenet")
True
>>> issubclass(forcenet.ArgumentError, forcenet.ForcenetError), issubclass(forcenet.ArgumentError, ValueError)
(True, True)
>>> forcenet.table(5).mean_W[-1][2], forcenet.count(6)
(Fraction(7, 22), 286)
"""

from __future__ import annotations

import importlib
from importlib.metadata import PackageNotFoundError, version
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:  # the type checker sees the names; at run time __getattr__ loads them on first use
    from forcenet.chicken_wire_isotropic import (
        IsotropicPlan,
        isotropic_maximum,
        isotropic_maximum_plan,
        isotropic_point,
        isotropic_point_plan,
    )
    from forcenet.chicken_wire_results import BetheGroundState, IsotropicEntropy, TransferSpectrum
    from forcenet.chicken_wire_sectors import (
        BetheGroundStatePlan,
        TransferSpectrumPlan,
        bethe_ground_state,
        bethe_ground_state_plan,
        transfer_spectrum,
        transfer_spectrum_plan,
    )
    from forcenet.contact_network_results import NetworkResult
    from forcenet.contact_networks import (
        ContactNetwork,
        NetworkPlan,
        contact_network,
        network,
        network_plan,
        network_response,
    )
    from forcenet.core.errors import (
        ArgumentError,
        ArgumentTypeError,
        ClusterError,
        ConvergenceError,
        ForcenetError,
        PrecisionWarning,
    )
    from forcenet.exact.triangle.distribution import cdf, contact_density, density
    from forcenet.exact.triangle.staircase import count, normalization
    from forcenet.force_chains import ScalingPlan, clusters, scaling, scaling_plan
    from forcenet.force_chains_results import ForceChainScaling
    from forcenet.front_door import RowPlan, TablePlan, plan, row, row_plan, table
    from forcenet.law_results import Law
    from forcenet.laws import LawPlan, law, law_plan
    from forcenet.map_counts import MapCounts, maps
    from forcenet.numeric.chicken_wire.isotropic import entropy, tiling_entropy
    from forcenet.numeric.packing.scene import Scene
    from forcenet.numeric.triangle import ExactSampler, TriangleMetropolis
    from forcenet.results import Table
    from forcenet.row_results import Row
    from forcenet.sample_results import Samples
    from forcenet.sampled_comparison import SampledComparison, SampledComparisonPlan
    from forcenet.sampling import SamplePlan, sample, sample_plan
    from forcenet.scaling_limit import LimitShape, limit_shape
    from forcenet.shear import ShearPlan, shear_scaling, shear_scaling_plan, yield_stress
    from forcenet.shear_results import ShearScaling, YieldStressResult
    from forcenet.tableaux_count import CountPlan, TableauxCount, count_plan

# name -> the module that defines it, imported on first use (forcenet.exact costs about a second to import)
_FRONT_DOOR = {
    "table": "forcenet.front_door",
    "plan": "forcenet.front_door",
    "Table": "forcenet.results",
    "TablePlan": "forcenet.front_door",
    "row": "forcenet.front_door",
    "row_plan": "forcenet.front_door",
    "RowPlan": "forcenet.front_door",
    "Row": "forcenet.row_results",
    "law": "forcenet.laws",
    "law_plan": "forcenet.laws",
    "Law": "forcenet.law_results",
    "LawPlan": "forcenet.laws",
    "count": "forcenet.exact.triangle.staircase",
    "normalization": "forcenet.exact.triangle.staircase",
    "count_plan": "forcenet.tableaux_count",
    "CountPlan": "forcenet.tableaux_count",
    "TableauxCount": "forcenet.tableaux_count",
    "maps": "forcenet.map_counts",
    "MapCounts": "forcenet.map_counts",
    "limit_shape": "forcenet.scaling_limit",
    "LimitShape": "forcenet.scaling_limit",
    "density": "forcenet.exact.triangle.distribution",
    "cdf": "forcenet.exact.triangle.distribution",
    "contact_density": "forcenet.exact.triangle.distribution",
    "sample": "forcenet.sampling",
    "sample_plan": "forcenet.sampling",
    "Samples": "forcenet.sample_results",
    "SamplePlan": "forcenet.sampling",
    "Scene": "forcenet.numeric.packing.scene",
    "SampledComparison": "forcenet.sampled_comparison",
    "SampledComparisonPlan": "forcenet.sampled_comparison",
    "ExactSampler": "forcenet.numeric.triangle",
    "TriangleMetropolis": "forcenet.numeric.triangle",
    "entropy": "forcenet.numeric.chicken_wire.isotropic",
    "tiling_entropy": "forcenet.numeric.chicken_wire.isotropic",
    "transfer_spectrum": "forcenet.chicken_wire_sectors",
    "transfer_spectrum_plan": "forcenet.chicken_wire_sectors",
    "TransferSpectrum": "forcenet.chicken_wire_results",
    "TransferSpectrumPlan": "forcenet.chicken_wire_sectors",
    "bethe_ground_state": "forcenet.chicken_wire_sectors",
    "bethe_ground_state_plan": "forcenet.chicken_wire_sectors",
    "BetheGroundState": "forcenet.chicken_wire_results",
    "BetheGroundStatePlan": "forcenet.chicken_wire_sectors",
    "isotropic_point": "forcenet.chicken_wire_isotropic",
    "isotropic_point_plan": "forcenet.chicken_wire_isotropic",
    "isotropic_maximum": "forcenet.chicken_wire_isotropic",
    "isotropic_maximum_plan": "forcenet.chicken_wire_isotropic",
    "IsotropicEntropy": "forcenet.chicken_wire_results",
    "IsotropicPlan": "forcenet.chicken_wire_isotropic",
    "ForcenetError": "forcenet.core.errors",
    "ArgumentError": "forcenet.core.errors",
    "ArgumentTypeError": "forcenet.core.errors",
    "ConvergenceError": "forcenet.core.errors",
    "ClusterError": "forcenet.core.errors",
    "PrecisionWarning": "forcenet.core.errors",
    "clusters": "forcenet.force_chains",
    "scaling": "forcenet.force_chains",
    "scaling_plan": "forcenet.force_chains",
    "ScalingPlan": "forcenet.force_chains",
    "ForceChainScaling": "forcenet.force_chains_results",
    "network": "forcenet.contact_networks",
    "network_plan": "forcenet.contact_networks",
    "network_response": "forcenet.contact_networks",
    "NetworkPlan": "forcenet.contact_networks",
    "NetworkResult": "forcenet.contact_network_results",
    "ContactNetwork": "forcenet.contact_networks",
    "contact_network": "forcenet.contact_networks",
    "yield_stress": "forcenet.shear",
    "shear_scaling": "forcenet.shear",
    "shear_scaling_plan": "forcenet.shear",
    "ShearScaling": "forcenet.shear_results",
    "ShearPlan": "forcenet.shear",
    "YieldStressResult": "forcenet.shear_results",
}

_SUBPACKAGES = frozenset({"exact", "numeric", "testing"})

__all__ = [  # the keys of _FRONT_DOOR (tests/test_front_door.py), written out for the linters
    "table", "plan", "Table", "TablePlan", "Row", "row", "row_plan", "RowPlan", "law", "law_plan", "Law", "LawPlan",
    "count", "normalization", "count_plan", "CountPlan", "TableauxCount", "maps", "MapCounts",
    "limit_shape", "LimitShape", "density", "cdf", "contact_density",
    "sample", "sample_plan", "Samples", "SamplePlan", "Scene", "SampledComparison", "SampledComparisonPlan",
    "ExactSampler", "TriangleMetropolis", "entropy", "tiling_entropy",
    "transfer_spectrum", "transfer_spectrum_plan", "TransferSpectrum", "TransferSpectrumPlan",
    "bethe_ground_state", "bethe_ground_state_plan", "BetheGroundState", "BetheGroundStatePlan",
    "isotropic_point", "isotropic_point_plan", "isotropic_maximum", "isotropic_maximum_plan", "IsotropicEntropy",
    "IsotropicPlan",
    "ForcenetError", "ArgumentError", "ArgumentTypeError", "ConvergenceError", "ClusterError", "PrecisionWarning",
    "clusters", "scaling", "scaling_plan", "ScalingPlan", "ForceChainScaling",
    "__version__",
    "network", "network_plan", "network_response", "NetworkPlan", "NetworkResult", "ContactNetwork", "contact_network",
    "yield_stress", "shear_scaling", "shear_scaling_plan", "ShearScaling", "ShearPlan", "YieldStressResult",
]

try:
    __version__: str = version("forcenet")  # one source: pyproject.toml, through the installed metadata
except PackageNotFoundError:  # imported from a tree that was never installed (not a supported way to run)
    __version__ = "0+unknown"


def __getattr__(name: str) -> Any:
    """The front door's names, imported on first use."""
    if name in _FRONT_DOOR:
        value = getattr(importlib.import_module(_FRONT_DOOR[name]), name)
        globals()[name] = value
        return value
    if name in _SUBPACKAGES:  # forcenet.testing.compare without a separate import
        return importlib.import_module(f"forcenet.{name}")
    raise AttributeError(f"module 'forcenet' has no attribute {name!r}")


def __dir__() -> list[str]:
    """The front door's names, its subpackages and ``__version__``: no helper of this module (issue 53)."""
    return sorted({*_FRONT_DOOR, *_SUBPACKAGES, "__version__"})
