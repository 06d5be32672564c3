"""What :func:`forcenet.yield_stress` and :func:`forcenet.shear_scaling` return (thesis Ch. 8).

:class:`YieldStressResult` (the yield stress, exact and floating) and :class:`ShearScaling` (the anisotropic
scaling's exponents and anisotropy with their errors), with the renderings ``forcenet yield-stress`` and
``forcenet shear`` write (``to_json``, ``to_text``).

Examples
--------
>>> from forcenet.shear import yield_stress
>>> yield_stress("hexagonal", 3, exact=False).to_dict()["tau_max_float"]
0.57735026919
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

from forcenet.rendering import Rendered

__all__ = ["YieldStressResult", "ShearScaling"]


@dataclass(frozen=True)
class YieldStressResult(Rendered):
    """The yield stress of a packing (Sec. 8.2): exact and floating.

    Parameters
    ----------
    geometry : str
        ``"hexagonal"``: the ``size x size`` periodic hexagonal packing.
    size : int
        Its period.
    tau_max : str or None
        Exact (e.g. ``"sqrt(3)/3"``), None when only the floating route ran.
    value : float
        ``tau_max`` as a float (the exact one's when there is one).
    float_lp : float
        The floating linear program's (HiGHS) value.
    witness_zeros : int or None
        Contacts carrying no force in the exact witness network at ``tau_max``.

    Examples
    --------
    >>> from forcenet.shear import example, yield_stress
    >>> yield_stress("hexagonal", 5, exact=False).value > 0.577
    True
    """

    geometry: str
    size: int
    tau_max: str | None
    value: float
    float_lp: float
    witness_zeros: int | None

    def to_dict(self) -> dict[str, Any]:
        """The values as a dict (what :meth:`to_json` writes).

        Returns
        -------
        dict

        Examples
        --------
        >>> from forcenet.shear import example, yield_stress
        >>> yield_stress("hexagonal", 4, exact=False).to_dict()["tau_max"] is None
        True
        """
        return {"geometry": self.geometry, "size": self.size, "tau_max": self.tau_max,
                "tau_max_float": round(self.value, 12), "float_lp": round(self.float_lp, 12),
                "witness_zeros": self.witness_zeros}

    def to_text(self) -> str:
        """A short report.

        Returns
        -------
        str

        Examples
        --------
        >>> from forcenet.shear import example, yield_stress
        >>> print(yield_stress("hexagonal", 3).to_text())
        yield stress of the 3 x 3 periodic hexagonal packing: tau_max = sqrt(3)/3 = 0.577350269190 (exact, proven by a primal network and a dual certificate); floating LP 0.577350269190
        """
        exact = (f"{self.tau_max} = {self.value:.12f} (exact, proven by a primal network and a dual certificate)"
                 if self.tau_max is not None else f"{self.value:.12f} (floating LP only)")
        return (f"yield stress of the {self.size} x {self.size} periodic hexagonal packing: tau_max = {exact}; "
                f"floating LP {self.float_lp:.12f}")


@dataclass(frozen=True)
class ShearScaling(Rendered):
    """The anisotropic scaling of the clusters of large forces under shear (Sec. 8.3).

    Parameters
    ----------
    taus : tuple of float
        The shear stresses.
    nu_M, nu_M_error, nu_m, nu_m_error : list of float
        Per ``tau``, the correlation-length exponents along and across the largest stress (the strips' collapses).
    gamma_2_M, gamma_2_m : list of float
        Per ``tau``, ``gamma_2`` of the two strip families.
    r, r_error : list of float
        Per ``tau``, the anisotropy ``r = xi_m^(0)/xi_M^(0) = b_M/b_m`` (Eqs. (8.4), (8.8)) and its bootstrap error.
    theta, theta_error : float
        The exponent of Eq. (8.9) (``2 gamma_2``), shared by every ``tau``.
    details : dict
        What was run, the peak heights per shape and ``tau``, the fit's residual, the time.

    Examples
    --------
    >>> from forcenet.shear import example, yield_stress
    >>> example().details["L"]
    16
    """

    taus: tuple[float, ...]
    nu_M: list[float]
    nu_M_error: list[float]
    nu_m: list[float]
    nu_m_error: list[float]
    gamma_2_M: list[float]
    gamma_2_m: list[float]
    r: list[float]
    r_error: list[float]
    theta: float
    theta_error: float
    details: dict[str, Any] = field(default_factory=dict)

    def to_dict(self) -> dict[str, Any]:
        """The values as a dict (what :meth:`to_json` writes; NaN as null).

        Returns
        -------
        dict

        Examples
        --------
        >>> from forcenet.shear import example, yield_stress
        >>> sorted(example().to_dict())[:4]
        ['details', 'gamma_2_M', 'gamma_2_m', 'nu_M']
        """
        def clean(x: Any) -> Any:
            if isinstance(x, float):
                return round(x, 6) if math.isfinite(x) else None
            if isinstance(x, (list, tuple)):
                return [clean(v) for v in x]
            if isinstance(x, dict):
                return {k: clean(v) for k, v in x.items()}
            return x

        return clean({"taus": list(self.taus), "nu_M": self.nu_M, "nu_M_error": self.nu_M_error, "nu_m": self.nu_m,
                      "nu_m_error": self.nu_m_error, "gamma_2_M": self.gamma_2_M, "gamma_2_m": self.gamma_2_m,
                      "r": self.r, "r_error": self.r_error, "theta": self.theta, "theta_error": self.theta_error,
                      "details": self.details})

    def to_text(self) -> str:
        """A table: per ``tau``, ``nu_M``, ``nu_m`` and ``r`` with errors.

        Returns
        -------
        str

        Examples
        --------
        >>> from forcenet.shear import example, yield_stress
        >>> example().to_text().splitlines()[1].split()[:4]
        ['tau', 'nu_M', 'nu_m', 'r(tau)']
        """
        d = self.details
        lines = [f"anisotropic scaling under shear ({d.get('model')}, torus L={d.get('L')}, {d.get('samples')} "
                 f"samples per tau, {d.get('seconds', 0.0):.1f} s)",
                 f"{'tau':>6} {'nu_M':>14} {'nu_m':>14} {'r(tau)':>14}"]
        for k, t in enumerate(self.taus):
            lines.append(f"{t:6.3f} {self.nu_M[k]:7.3f} +- {self.nu_M_error[k]:<4.2f} {self.nu_m[k]:7.3f} +- "
                         f"{self.nu_m_error[k]:<4.2f} {self.r[k]:7.3f} +- {self.r_error[k]:<4.2f}")
        lines.append(f"theta = 2 gamma_2 = {self.theta:.3f} +- {self.theta_error:.3f} (Eq. 8.9; thesis: "
                     f"2 x 0.89 = 1.78); thesis nu_M = nu_m = 1.65 +- 0.1 away from yield")
        return "\n".join(lines)
