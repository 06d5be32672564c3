"""What :func:`forcenet.clusters` and :func:`forcenet.scaling` return: :class:`ForceChainScaling`.

The exponents of the best collapse (6.12) with their errors (the bootstrap
over blocks of samples, the window variation, the change without the
smallest size, in quadrature), the standard estimators, every size's
``<s^2>(f)`` curve, and the renderings ``forcenet clusters`` and
``forcenet scaling`` write (``to_json``, ``to_text``, ``figures``).

Examples
--------
>>> from forcenet.force_chains import example
>>> result = example()      # a small percolation run (forcenet.scaling), made once
>>> [k for k in result.summary()][:6]
['f_c', 'f_c_error', 'nu', 'nu_error', 'gamma_2', 'gamma_2_error']
"""

from __future__ import annotations

import io
import math
import textwrap
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from forcenet.numeric.force_chains.finite_size_scaling import NAMES, ScalingFit, SizeBlocks, peak
from forcenet.rendering import Rendered

__all__ = ["ForceChainScaling"]

# Table 7.1 of the thesis: (gamma_2, its error, nu, its error); percolation's exact values
THESIS_TABLE = {
    "snooker": (0.89, 0.01, 1.65, 0.1),
    "q-independent": (0.70, 0.01, 3.0, 0.1),
    "q-microcanonical": (0.81, 0.01, 1.65, 0.1),
    "percolation": (43 / 48, 0.0, 4 / 3, 0.0),
}


def _number(x: float) -> float | None:
    return round(float(x), 6) if math.isfinite(x) else None


@dataclass(frozen=True)
class ForceChainScaling(Rendered):
    """The finite-size scaling of the clusters of large forces (thesis Ch. 6-7).

    Parameters
    ----------
    model : str
        The model (``percolation``, ``q-independent``, ``q-microcanonical``) or ``"data"`` (users' networks).
    data : list of SizeBlocks
        Every size's blocks of cluster statistics.
    fit : ScalingFit
        The collapse and the estimators, with errors.
    seconds : float
        Wall time of the run.
    details : dict
        What was run (sizes, samples, seed, lattice, sources).

    Examples
    --------
    >>> from forcenet.force_chains import example
    >>> r = example()                       # what forcenet.scaling returns
    >>> r.model, len(r.data), sorted(r.fit.value)
    ('percolation', 4, ['f_c', 'gamma_2', 'nu'])
    """

    json_indent = 2  # forcenet clusters/scaling --format json: indented, with a final newline

    model: str
    data: list[SizeBlocks]
    fit: ScalingFit
    seconds: float
    details: dict[str, Any] = field(default_factory=dict)

    def to_dict(self) -> dict[str, Any]:
        """The exponents and their errors: what :meth:`to_json` writes (the same as :meth:`summary`).

        Returns
        -------
        dict

        Examples
        --------
        >>> from forcenet.force_chains import example
        >>> example().to_dict() == example().summary()
        True
        """
        return self.summary()

    def summary(self) -> dict[str, Any]:
        """The command line's JSON: ``f_c``, ``nu``, ``gamma_2`` with ``..._error``, ``sizes`` and the details.

        Returns
        -------
        dict
            Plain numbers (floats rounded to 6 decimals, None for a missing estimate), lists and strings.

        Examples
        --------
        >>> from forcenet.force_chains import example
        >>> r = example()
        >>> r.summary()["sizes"][0]["L"], r.summary()["sizes"][0]["M"]
        (8, 128)
        """
        out: dict[str, Any] = {}
        for name in ("f_c", "nu", "gamma_2"):
            out[name] = _number(self.fit.value[name])
            out[f"{name}_error"] = _number(self.fit.error[name])
        out["nu_method"] = "collapse"
        width, width_error = self.fit.estimators.get("nu_width", math.nan), self.fit.estimator_errors.get("nu_width")
        if self.fit.pinned and math.isfinite(width):  # the collapse does not fix nu: the peak widths do
            out["nu"], out["nu_error"] = _number(width), _number(width_error if width_error is not None else math.nan)
            out["nu_method"] = "peak widths (the collapse's optimum is pinned at its window's limit)"
        out["nu_collapse"] = _number(self.fit.value["nu"])
        sizes = []
        for d in self.data:
            fp, h = peak(d.thresholds, d.s2())
            sizes.append({"L": int(d.label) if d.label else None, "M": int(d.M), "S": _number(d.S), "samples": int(d.samples.sum()),
                          "blocks": d.blocks, "peak_f": _number(fp), "peak_s2": _number(h)})
        out["sizes"] = sizes
        out["errors"] = {name: {"bootstrap": _number(self.fit.bootstrap[name]),
                                "window": _number(self.fit.window_spread[name]),
                                "sizes": _number(self.fit.sizes_spread[name])} for name in NAMES}
        out["window"] = [_number(w) for w in self.fit.window]
        out["chi2"] = _number(self.fit.cost)
        out["estimators"] = {k: _number(v) for k, v in self.fit.estimators.items()}
        out["estimator_errors"] = {k: _number(v) for k, v in self.fit.estimator_errors.items()}
        out["replicas"] = self.fit.replicas
        out["nu_pinned"] = self.fit.pinned
        out["model"] = self.model
        out["seconds"] = round(self.seconds, 2)
        out["details"] = self.details
        if self.model in THESIS_TABLE:
            g, ge, n, ne = THESIS_TABLE[self.model]
            out["thesis"] = {"gamma_2": round(g, 6), "gamma_2_error": ge, "nu": round(n, 6), "nu_error": ne}
        return out

    def to_text(self) -> str:
        """A short report: the exponents with their errors, the thesis's row, the sizes.

        Returns
        -------
        str
            What the commands print by default.

        Examples
        --------
        >>> from forcenet.force_chains import example
        >>> r = example()
        >>> r.to_text().splitlines()[0]
        'percolation: finite-size scaling of large-force clusters (Eqs. 6.8, 6.12)'
        """
        s = self.summary()
        lines = [f"{self.model}: finite-size scaling of large-force clusters (Eqs. 6.8, 6.12)"]
        for name in ("f_c", "gamma_2", "nu"):
            e = s["errors"][name]
            if name == "nu" and s["nu_method"] != "collapse":
                lines.append(f"  nu       = {s['nu']} +- {s['nu_error']}   (from the {s['nu_method']}; the collapse's "
                             f"{s['nu_collapse']})")
                continue
            lines.append(f"  {name:8s} = {s[name]} +- {s[name + '_error']}   (bootstrap {e['bootstrap']}, "
                         f"window {e['window']}, sizes {e['sizes']})")
        if "thesis" in s:
            t = s["thesis"]
            lines.append(f"  thesis (Table 7.1): gamma_2 = {t['gamma_2']} +- {t['gamma_2_error']}, "
                         f"nu = {t['nu']} +- {t['nu_error']}")
        est = s["estimators"]
        err = s["estimator_errors"]
        lines.append(f"  estimators: peak heights gamma_2 = {est['gamma_2']} +- {err['gamma_2']}; peak widths "
                     f"nu = {est['nu_width']} +- {err['nu_width']}; peak shift f_c = {est['f_c']}, nu = {est['nu']}; "
                     f"wrapping crossings f_c = {est['f_c_crossing']} +- {err['f_c_crossing']}")
        lines.append(f"  window x in {s['window']}, chi2 = {s['chi2']}, {s['replicas']} bootstrap replicas, "
                     f"{s['seconds']} s")
        if self.fit.pinned:
            lines.append("  WARNING: the collapse's optimum lies on its window's limit (chi^2 still falls towards "
                         "nu -> 0): nu is not fixed by the collapse here; see the peak-shift estimator")
        for size in s["sizes"]:
            lines.append(f"  L = {size['L'] or '-':>4}  M = {size['M']:7d}  samples = {size['samples']:6d}  "
                         f"peak <s^2> = {size['peak_s2']} at f = {size['peak_f']}")
        # at most 80 columns (issue 53): a long line continues below, indented; no number is split
        return "".join(part + "\n" for line in lines for part in textwrap.wrap(
            line, 80, subsequent_indent="      ", break_long_words=False, break_on_hyphens=False))

    def figures(self) -> dict[str, bytes]:
        """Two PNG figures: ``s2.png`` (``<s^2>(f, M)`` for every size, as Fig. 7.2 a) and ``collapse.png``
        (``M^-gamma_2 <s^2>`` against ``(f - f_c) M^(1/(2 nu))`` at the best collapse, Fig. 7.2 b).

        Returns
        -------
        dict
            File name -> PNG bytes.

        Examples
        --------
        >>> from forcenet.force_chains import example
        >>> r = example()
        >>> sorted(r.figures()), r.figures()["s2.png"][:4]
        (['collapse.png', 's2.png'], b'\\x89PNG')
        """
        import matplotlib

        matplotlib.use("Agg")
        from matplotlib.figure import Figure

        g, nu, fc = (self.fit.value[n] for n in NAMES)
        out = {}
        for name in ("s2.png", "collapse.png"):
            fig = Figure(figsize=(5.5, 4.0))
            ax = fig.add_subplot()
            for d in self.data:
                y = d.s2()
                if name == "s2.png":
                    ax.plot(d.thresholds, y, label=f"M={d.M}")
                else:
                    ax.plot((d.thresholds - fc) * d.S ** (1 / (2 * nu)), y * d.S ** (-g), label=f"M={d.M}")
            if name == "s2.png":
                ax.set_xlabel("threshold f")
                ax.set_ylabel("<s^2>")
            else:
                w = self.fit.window
                ax.set_xlim(w[0] - (w[1] - w[0]), w[1] + (w[1] - w[0]))
                ax.axvspan(w[0], w[1], color="0.9")
                ax.set_xlabel("(f - f_c) S^(1/(2 nu))")
                ax.set_ylabel("S^(-gamma_2) <s^2>")
                ax.set_title(f"gamma_2 = {g:.3f}, nu = {nu:.2f}, f_c = {fc:.4f}")
            ax.legend(fontsize=7)
            buffer = io.BytesIO()
            fig.savefig(buffer, format="png", dpi=100)
            out[name] = buffer.getvalue()
        return out

    def curves(self) -> dict[str, np.ndarray]:
        """Every size's thresholds and ``<s^2>``, wrapping probability and largest cluster fraction.

        Returns
        -------
        dict
            ``f_L..``, ``s2_L..``, ``wrapping_L..``, ``largest_L..`` arrays per size (``M..`` for users' data).

        Examples
        --------
        >>> from forcenet.force_chains import example
        >>> r = example()
        >>> r.curves()["s2_L8"].shape == r.curves()["f_L8"].shape
        True
        """
        out = {}
        for d in self.data:
            key = f"L{int(d.label)}" if d.label else f"M{d.M}"
            out[f"f_{key}"] = d.thresholds
            out[f"s2_{key}"] = d.s2()
            out[f"wrapping_{key}"] = d.wrapping()
            out[f"largest_{key}"] = d.largest_fraction()
        return out
