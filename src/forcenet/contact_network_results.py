"""What :func:`forcenet.network` returns: every contact force's exact and/or sampled moments, and its renderings.

``to_json()`` is the output of ``forcenet network --format json``:
``{"dimension": d, "contacts": [{"i": .., "j": .., "mean": .., "second": .., "error": ..}, ...]}`` in the
input's order (``j`` null for a wall); exact values are strings (``"5/16"``, ``"2*sqrt(3)/9"``), sampled ones
numbers with their standard ``error`` (and ``second_error``); with both, the sampled ones are
``sampled_mean``, ``sampled_second``. With friction each contact also has ``tangential`` (the same keys).

Examples
--------
>>> import forcenet
>>> net = forcenet.contact_network(1, [[0, None, "-3/5", "-4/5"], [0, None, "3/5", "-4/5"], [0, None, 0, -1]],
...                                [[0, 0, -1]])
>>> result = forcenet.network(net, exact=True, moments=2)
>>> result.to_json().splitlines()[:3]
['{', '  "dimension": 1,', '  "grains": 1,']
>>> [c["mean"] for c in result.to_dict()["contacts"]]
['5/16', '5/16', '1/2']
"""

from __future__ import annotations

import html
import textwrap
from dataclasses import dataclass
from typing import Any

import numpy as np

from forcenet.core.errors import ArgumentError
from forcenet.core.validation import check_int
from forcenet.exact.contact_network.polytope import exact_polytope
from forcenet.exact.contact_network.triangulation_moments import density_at
from forcenet.rendering import Rendered

__all__ = ["NetworkResult"]


def _exact_text(value: Any) -> str:
    return str(value)


@dataclass(frozen=True)
class NetworkResult(Rendered):
    """Moments of every contact force of a contact network's ensemble: what :func:`forcenet.network` returns.

    Parameters
    ----------
    network : forcenet.exact.contact_network.model.ContactNetwork
        The network.
    labels : tuple of str
        ``f{c}`` (contact ``c``'s normal force), ``t{c}`` (its tangential force, with friction).
    dimension : int
        The polytope's dimension.
    exact_mean, exact_second : tuple or None
        Exact sympy numbers per variable (``exact=True``).
    sampled_mean, sampled_error, sampled_second, second_error, tau : numpy.ndarray or None
        Sampled means, standard errors, ``<f^2>``, its error and the integrated autocorrelation times.
    samples : numpy.ndarray or None
        The chain (one row per sweep), kept for ``P(f)`` and figures.
    methods : tuple of str
        The engines that ran.
    exact_density : tuple of (int, list of DensityPiece) or None
        Per variable asked for (``density=``, ``--density``) its exact density, a piecewise polynomial
        (:mod:`forcenet.exact.contact_network.marginal_density`).

    Examples
    --------
    >>> import forcenet
    >>> net = forcenet.contact_network(1, [[0, None, 0, -1]], [[0, 0, -1]])  # one grain on the floor
    >>> result = forcenet.network(net, exact=True)
    >>> result.dimension, result.exact_mean
    (0, (1,))
    """

    json_indent = 2  # forcenet network --format json: indented, with a final newline

    network: Any
    labels: tuple[str, ...]
    dimension: int
    exact_mean: tuple[Any, ...] | None = None
    exact_second: tuple[Any, ...] | None = None
    sampled_mean: np.ndarray | None = None
    sampled_error: np.ndarray | None = None
    sampled_second: np.ndarray | None = None
    second_error: np.ndarray | None = None
    tau: np.ndarray | None = None
    samples: np.ndarray | None = None
    methods: tuple[str, ...] = ()
    exact_density: tuple[tuple[int, list[Any]], ...] | None = None

    def _density(self, k: int) -> list[Any] | None:
        return dict(self.exact_density).get(k) if self.exact_density else None

    def _entry(self, k: int) -> dict[str, Any]:
        entry: dict[str, Any] = {}
        sampled = self.sampled_mean is not None
        if self.exact_mean is not None:
            entry["mean"] = _exact_text(self.exact_mean[k])
            if self.exact_second:
                entry["second"] = _exact_text(self.exact_second[k])
        prefix = "sampled_" if self.exact_mean is not None else ""
        if sampled and self.sampled_mean is not None and self.sampled_error is not None:
            entry[f"{prefix}mean"] = float(self.sampled_mean[k])
            entry["error"] = float(self.sampled_error[k])
            if self.sampled_second is not None and self.second_error is not None:
                entry[f"{prefix}second"] = float(self.sampled_second[k])
                entry["second_error"] = float(self.second_error[k])
        pieces = self._density(k)
        if pieces is not None:
            entry["density"] = [{"from": str(p.lo), "to": str(p.hi), "polynomial": str(p.poly.as_expr())}
                                for p in pieces]
        return entry

    def to_dict(self) -> dict[str, Any]:
        """The JSON document as Python values.

        Returns
        -------
        dict
            ``dimension``, ``grains``, ``methods`` and one entry per contact, in the input's order.

        Examples
        --------
        >>> import forcenet
        >>> net = forcenet.contact_network(1, [[0, None, 0, -1]], [[0, 0, -1]])
        >>> forcenet.network(net, exact=True).to_dict()["contacts"]
        [{'i': 0, 'j': None, 'mean': '1'}]
        """
        index = {label: k for k, label in enumerate(self.labels)}
        contacts = []
        for c, (i, j, _, _) in enumerate(self.network.contacts):
            entry: dict[str, Any] = {"i": i, "j": j, **self._entry(index[f"f{c}"])}
            if f"t{c}" in index:
                entry["tangential"] = self._entry(index[f"t{c}"])
            contacts.append(entry)
        return {"dimension": self.dimension, "grains": self.network.grains, "methods": list(self.methods),
                "contacts": contacts}

    def to_csv(self) -> str:
        """One row per force: ``contact,kind,i,j,mean,second,error,second_error`` (sampled with exact: extra columns).

        Returns
        -------
        str
            The CSV text.

        Examples
        --------
        >>> import forcenet
        >>> net = forcenet.contact_network(1, [[0, None, 0, -1]], [[0, 0, -1]])
        >>> forcenet.network(net, exact=True, moments=2).to_csv().splitlines()
        ['contact,kind,i,j,mean,second', '0,normal,0,,1,1']
        """
        index = {label: k for k, label in enumerate(self.labels)}
        rows, header = [], None
        for c, (i, j, _, _) in enumerate(self.network.contacts):
            for kind, label in (("normal", f"f{c}"), ("tangential", f"t{c}")):
                if label not in index:
                    continue
                entry = self._entry(index[label])
                entry.pop("density", None)  # pieces do not fit a row: --format json or text
                header = header or list(entry)
                rows.append(",".join([str(c), kind, str(i), "" if j is None else str(j)] +
                                     [str(entry[key]) for key in header]))
        return "\n".join([",".join(["contact", "kind", "i", "j", *(header or [])]), *rows]) + "\n"

    def to_text(self) -> str:
        """A readable table: one line per contact force.

        Returns
        -------
        str
            The table, one line per contact force.

        Examples
        --------
        >>> import forcenet
        >>> net = forcenet.contact_network(1, [[0, None, 0, -1]], [[0, 0, -1]])
        >>> print(forcenet.network(net, exact=True).to_text())
        contact network: 1 grains, 1 contacts (1 with walls), frictionless, exact data;
              dimension 0
          f0 (0-wall): mean 1
        <BLANKLINE>
        """
        lines = [f"contact network: {self.network.describe()}; dimension {self.dimension}"]
        index = {label: k for k, label in enumerate(self.labels)}
        for c, (i, j, _, _) in enumerate(self.network.contacts):
            for kind, label in (("f", f"f{c}"), ("t", f"t{c}")):
                if label not in index:
                    continue
                entry = self._entry(index[label])
                parts = []
                for key, value in entry.items():
                    if key in ("error", "second_error", "density"):
                        continue
                    text = f"{value:.6g}" if isinstance(value, float) else value
                    error_key = "error" if key.endswith("mean") else "second_error"
                    if isinstance(value, float) and error_key in entry:
                        text += f" +- {entry[error_key]:.2g}"
                    parts.append(f"{key} {text}")
                other = "wall" if j is None else str(j)
                lines.append(f"  {kind}{c} ({i}-{other}): " + ", ".join(parts))
                lines += [f"    density on [{p['from']}, {p['to']}]: {p['polynomial']}" for p in entry.get("density", [])]
        # at most 80 columns (issue 53): a long line continues below, indented; no number is split
        return "".join(part + "\n" for line in lines for part in textwrap.wrap(
            line, 80, subsequent_indent="      ", break_long_words=False, break_on_hyphens=False))

    def density(self, contact: int, points: list[Any]) -> list[Any]:
        """The exact density of contact ``contact``'s normal force at ``points`` (exact data; Normaliz slice
        volumes, :func:`forcenet.exact.contact_network.triangulation_moments.density_at`).

        Parameters
        ----------
        contact : int
            The contact's index in the input.
        points : list
            Exact values of the force (int, Fraction, sympy numbers such as ``sqrt(3)/3``).

        Returns
        -------
        list
            Exact densities.

        Raises
        ------
        ArgumentError
            Floats in the network, a force that balance fixes (no density), or a point that is not rational in
            the force's unit.

        Examples
        --------
        >>> import forcenet
        >>> from fractions import Fraction
        >>> net = forcenet.contact_network(1, [[0, None, "-3/5", "-4/5"], [0, None, "3/5", "-4/5"],
        ...                                    [0, None, 0, -1]], [[0, 0, -1]])
        >>> forcenet.network(net).density(2, [Fraction(1, 2)])  # the floor's force is uniform on [0, 1]
        [1]
        """
        contact = check_int(contact, "contact", 0, len(self.network.contacts) - 1)
        return density_at(exact_polytope(self.network), self.labels.index(f"f{contact}"), list(points))

    def _pooled(self) -> list[int]:
        """The normal forces pooled in ``P(f)``: positive mean, not fixed by balance alone (a point mass)."""
        if self.sampled_mean is None or self.sampled_error is None:
            return []
        return [k for k, label in enumerate(self.labels)
                if label.startswith("f") and self.sampled_mean[k] > 0 and self.sampled_error[k] > 0]

    def exact_force_distribution(self, f: Any) -> np.ndarray:
        """The exact pooled ``P(f)``, ``f = F / <F>`` (thesis Sec. 2.4), from the exact densities:
        ``P(f) = (1/n) sum_c <F_c> p_c(<F_c> f)`` over the forces of ``density=True`` (floats: for figures).

        Parameters
        ----------
        f : array_like
            Where to evaluate.

        Returns
        -------
        numpy.ndarray

        Raises
        ------
        ArgumentError
            Without exact densities (``exact=True, density=True``).

        Examples
        --------
        >>> import forcenet
        >>> from forcenet.exact.contact_network.geometries import triangle
        >>> r = forcenet.network(triangle(3).network, exact=True, density=True)
        >>> grid = np.linspace(0, 8, 20001)
        >>> bool(abs(np.trapezoid(r.exact_force_distribution(grid), grid) - 1) < 1e-3)  # jumps: trapezoids
        True
        """
        if not self.exact_density or self.exact_mean is None:
            raise ArgumentError("the exact P(f) needs the exact densities: forcenet.network(..., exact=True, "
                                "density=True) (--exact --density)")
        f = np.asarray(f, dtype=float)
        total = np.zeros_like(f)
        for k, pieces in self.exact_density:
            mean = float(self.exact_mean[k])
            x = mean * f
            for piece in pieces:
                inside = (x >= float(piece.lo)) & (x < float(piece.hi))
                coefficients = [float(c) for c in piece.poly.all_coeffs()]
                total[inside] += mean * np.polyval(coefficients, x[inside])
        return total / len(self.exact_density)

    def force_distribution(self, bins: int = 30) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``P(f)`` of the normal forces pooled, ``f = F / <F>`` per contact (thesis Sec. 2.4), from the samples.

        Parameters
        ----------
        bins : int, optional
            Equal bins from 0 to the largest ``f``.

        Returns
        -------
        (edges, density, error)
            The histogram's bin edges, its density and the spread of the density over ten blocks of the chain.

        Examples
        --------
        >>> import forcenet
        >>> from forcenet.exact.contact_network.geometries import triangle
        >>> result = forcenet.network(triangle(3).network, samples=1000, seed=1)
        >>> edges, density, error = result.force_distribution(10)
        >>> bool(abs((density * np.diff(edges)).sum() - 1) < 1e-9)
        True
        """
        if self.samples is None or self.sampled_mean is None:
            raise ArgumentError("force_distribution needs samples: run forcenet.network(..., samples=K)")
        keep = self._pooled()
        scaled = self.samples[:, keep] / self.sampled_mean[keep]
        edges = np.linspace(0.0, max(1e-12, float(scaled.max())), bins + 1)
        density, _ = np.histogram(scaled.ravel(), bins=edges, density=True)
        blocks = np.array_split(scaled, 10)
        per_block = np.array([np.histogram(b.ravel(), bins=edges, density=True)[0] for b in blocks if b.size])
        error = per_block.std(axis=0, ddof=1) / np.sqrt(len(per_block)) if len(per_block) > 1 else np.zeros(bins)
        return edges, density, error

    def plot_force_distribution(self, bins: int = 30, ax: Any = None) -> Any:
        """A matplotlib figure of :meth:`force_distribution` with its error bars.

        Parameters
        ----------
        bins : int, optional
            As in :meth:`force_distribution`.
        ax : matplotlib.axes.Axes, optional
            Where to draw (default: a new figure).

        Returns
        -------
        matplotlib.figure.Figure
            The figure drawn on.

        Examples
        --------
        >>> import forcenet, matplotlib
        >>> matplotlib.use("Agg")
        >>> from forcenet.exact.contact_network.geometries import triangle
        >>> fig = forcenet.network(triangle(3).network, samples=500, seed=1).plot_force_distribution()
        >>> fig.axes[0].get_xlabel()
        'f = F / <F>'
        """
        import matplotlib.pyplot as plt

        edges, density, error = self.force_distribution(bins)
        if ax is None:
            fig, ax = plt.subplots(figsize=(5, 3.5))
        else:
            fig = ax.figure
        centres = 0.5 * (edges[1:] + edges[:-1])
        ax.errorbar(centres, density, yerr=error, fmt="o", ms=3, label="hit-and-run")
        if self.exact_density:
            grid = np.linspace(0.0, float(edges[-1]), 400)
            ax.plot(grid, self.exact_force_distribution(grid), "-", lw=1.2, label="exact (triangulation)")
        ax.set_xlabel("f = F / <F>")
        ax.set_ylabel("P(f)")
        ax.legend()
        return fig

    def _repr_html_(self) -> str:
        head = f"<p>{html.escape(self.network.describe())}; dimension {self.dimension}</p>"
        rows = []
        index = {label: k for k, label in enumerate(self.labels)}
        for c, (i, j, _, _) in enumerate(self.network.contacts):
            entry = self._entry(index[f"f{c}"])
            cells = "".join(f"<td>{html.escape(str(v))}</td>" for v in entry.values())
            rows.append(f"<tr><td>{c}</td><td>{i}</td><td>{'wall' if j is None else j}</td>{cells}</tr>")
        keys = list(self._entry(0)) if self.labels else []
        header = "".join(f"<th>{html.escape(k)}</th>" for k in ["contact", "i", "j", *keys])
        return f"{head}<table><tr>{header}</tr>{''.join(rows[:200])}</table>"
