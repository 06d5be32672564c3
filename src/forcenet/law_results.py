"""What :func:`forcenet.law` returns: one load's exact law (:class:`Law`), rendered as ``forcenet dist`` renders it.

The density and the distribution function as pieces (sympy ``Poly`` over
``QQ`` on rational intervals), exact moments and values at a point, and the
renderings the command line writes, byte for byte.  It shares the renderings'
interface with :class:`forcenet.results.Table` (``_Rendered``).

Examples
--------
>>> import forcenet
>>> law = forcenet.law(3, (3, 2))
>>> law.density[0].poly.as_expr(), law.cdf_at("1/2")
(-6*w**2 + 6*w, Fraction(1, 2))
"""

from __future__ import annotations

import json
import math
import re
import textwrap
from collections.abc import Callable
from fractions import Fraction
from html import escape
from typing import TYPE_CHECKING, Any

import sympy

from forcenet.core.errors import ArgumentError, ArgumentTypeError
from forcenet.core.validation import check_exponent, check_int, check_rational, is_binary_float
from forcenet.exact.triangle.distribution import poly_strings
from forcenet.numeric.triangle.force_distribution import density_grid
from forcenet.results import _Rendered
from forcenet.sampled_comparison import comparison_plan

if TYPE_CHECKING:  # pragma: no cover - annotations only
    import numpy as np
    from matplotlib.axes import Axes

    from forcenet.sampled_comparison import SampledComparison

__all__ = ["GRID_MAX", "GRID_SECONDS", "MOMENT_MAX", "Law", "check_grid"]

GRID_MAX = 100000  # points of a grid (``grid=``, ``K``, ``points``; ``forcenet dist --grid``): ~40 s at N = 12
GRID_SECONDS = 60.0  # a grid planned longer than this is refused, naming the K that fits
GRID_POINT_SECONDS = 1e-7  # measured: a point of a degree-d law takes ~(6-10)e-8 d^2 s (N = 8..24, both curves)
MOMENT_MAX = 10000  # ``moment(s)``: exact integrals of x^s grow with s (s = 10**5 takes ~2 s at N = 20)


def check_grid(K: Any, degree: int, name: str = "grid") -> int:
    """``K`` checked as a grid of ``K + 1`` points of a law of polynomial ``degree``: an integer in ``1..GRID_MAX``
    whose planned cost is at most :data:`GRID_SECONDS`, else refused naming the ``K`` that fits.

    Each point is an exact evaluation of degree ``d`` at a float's exact value, ~``d^2`` big-integer work
    (:data:`GRID_POINT_SECONDS`).  The command line checks ``--grid`` with the request's bound on the degree
    (``LawRequest.degree``) before the law is computed; :meth:`Law.grid` with the law's own degree.

    Parameters
    ----------
    K : int
        The grid's intervals.
    degree : int
        The degree of the law's pieces (or a bound on it).
    name : str
        The argument's name in the refusal.

    Returns
    -------
    int
        ``K``.

    Raises
    ------
    ArgumentError, ArgumentTypeError
        ``K`` not an integer in range, or its grid planned over :data:`GRID_SECONDS`.

    Examples
    --------
    >>> check_grid(100, 15)
    100
    >>> check_grid(10**5, 1000)
    Traceback (most recent call last):
    ...
    forcenet.core.errors.ArgumentError: grid=100000 is out of range here: 100001 exact evaluations of degree 1000 take ~10000 s; grid must be an integer in 1..599 for this law
    """
    K = check_int(K, name, 1, GRID_MAX)  # as forcenet dist --grid: 1..GRID_MAX
    per_point = GRID_POINT_SECONDS * max(degree, 1) ** 2
    if (K + 1) * per_point > GRID_SECONDS:
        fits = max(1, int(GRID_SECONDS / per_point) - 1)
        raise ArgumentError(f"{name}={K} is out of range here: {K + 1} exact evaluations of degree {degree} take "
                            f"~{(K + 1) * per_point:.0f} s; {name} must be an integer in 1..{fits} for this law")
    return K


def _point(x: Any, name: str = "x") -> tuple[Fraction, bool]:
    """``x`` checked as a point: ``(its exact value, True for a binary float)``; NaN, infinities, non-numbers and
    booleans refused in the exception family."""
    if is_binary_float(x):
        if not math.isfinite(x):
            raise ArgumentError(f"{name}={x} is out of range: {name} must be a finite number")
        return Fraction(float(x)), True
    if isinstance(x, str):
        check_exponent(x, name)
        try:
            return Fraction(x), False
        except ZeroDivisionError:
            raise ArgumentError(f"{name}={x!r} is out of range: a zero denominator") from None
        except ValueError:
            raise ArgumentTypeError(f"{name}={x!r} is not a number: {name} must be an int, a Fraction, a 'p/q' "
                                    "string or a finite float") from None
    return check_rational(x, name), False


def _fraction(x: Any) -> Fraction:
    """A sympy Rational (or int) as a Fraction."""
    return Fraction(int(x.p), int(x.q)) if hasattr(x, "q") else Fraction(x)


class Law(_Rendered):
    """One load's exact law: a piecewise-polynomial density and its distribution function, exact rationals.

    Returned by :func:`forcenet.law`; the renderings are byte for byte those of ``forcenet dist`` (``grid=K``:
    its ``--grid K``).  A grain's ``W_ij`` (variable ``w`` on ``[0, 1]``, Eqs. (4.5)-(4.9)), a contact force in
    units of ``2/sqrt3`` (Eq. (3.8)), a layer's pooled ``P(f)``, ``f = i W_ij``, or the ensemble's.

    Parameters
    ----------
    N : int
        Number of layers.
    quantity, variable : str
        What the law is of (as ``forcenet dist`` titles it) and its variable (``"w"`` or ``"f"``).
    density, cdf : list of Piece
        The density and its distribution function on the same intervals (sympy ``Poly`` over ``QQ``).
    method, why : str
        The route that computed it, and why ``auto`` chose it (empty for an explicit method).
    extra : dict, optional
        Exact fields ``forcenet dist`` prints besides (a grain's ``mean`` and ``second_moment``).
    pool : "ensemble", int or None
        A pooled ``P(f)``'s grains: ``"ensemble"`` (layers ``2..N``) or a layer ``i``; None for a grain's or a
        contact's law.

    Examples
    --------
    >>> import forcenet
    >>> law = forcenet.law(4, (4, 2))
    >>> law
    Law(N=4, quantity='W_{4,2}', method='ideals')
    >>> law.density[0].poly.as_expr(), law.mean
    (-15*w**5 + 30*w**4 - 30*w**2 + 15*w, Fraction(5, 14))
    """

    GRID_MAX = GRID_MAX  # the cap of grid=, K, points (and of forcenet dist --grid)
    MOMENT_MAX = MOMENT_MAX  # the cap of moment(s)

    def __init__(self, N: int, quantity: str, variable: str, density: list[Any], cdf: list[Any], method: str,
                 why: str = "", extra: dict[str, Any] | None = None, pool: str | int | None = None):
        self.N, self.quantity, self.variable, self.method, self.why = N, quantity, variable, method, why
        self.density, self.cdf, self.extra, self.pool = density, cdf, dict(extra or {}), pool

    def __repr__(self) -> str:
        return f"Law(N={self.N}, quantity={self.quantity!r}, method={self.method!r})"

    @property
    def support(self) -> tuple[Fraction, Fraction]:
        """``(lo, hi)``: the density vanishes outside.

        Examples
        --------
        >>> import forcenet
        >>> forcenet.law(5, layer=4).support
        (Fraction(0, 1), Fraction(4, 1))
        """
        return _fraction(self.density[0].lo), _fraction(self.density[-1].hi)

    def moment(self, s: int = 1) -> Fraction:
        """``E[x^s]``, exactly: ``sum over pieces of int_lo^hi x^s p(x) dx``.

        Parameters
        ----------
        s : int
            The moment, ``s >= 0`` (``s = 0``: the total mass, 1).

        Returns
        -------
        Fraction

        Examples
        --------
        >>> import forcenet
        >>> law = forcenet.law(6, (6, 2))
        >>> law.moment(2) == forcenet.table(6, moments=2).moment(2)[5][1]
        True
        >>> forcenet.law(6, layer=5).moment(0)
        Fraction(1, 1)
        """
        s = check_int(s, "s", 0, MOMENT_MAX)  # capped: the integrals' numerators grow with s
        total = Fraction(0)
        for piece in self.density:
            lo, hi = _fraction(piece.lo), _fraction(piece.hi)
            for m, c in enumerate(reversed(piece.poly.all_coeffs())):
                k = m + s + 1
                total += _fraction(c) * (hi**k - lo**k) / k
        return total

    @property
    def mean(self) -> Fraction:
        """``E[x]`` (:meth:`moment` with ``s = 1``).

        Examples
        --------
        >>> import forcenet
        >>> forcenet.law(5, layer=5).mean  # f = i W over a layer: mean 1
        Fraction(1, 1)
        """
        return self.moment(1)

    def _at(self, pieces: list[Any], x: Any, below: int, above: int) -> Fraction | float:
        x, binary = _point(x)
        if binary:  # a binary float: its exact value, the answer rounded once
            return float(self._at(pieces, x, below, above))
        lo, hi = self.support
        if x < lo or x > hi:
            return Fraction(below if x < lo else above)
        piece = next(p for p in pieces if x < _fraction(p.hi) or p is pieces[-1])
        return sum((_fraction(c) * x**m for m, c in enumerate(reversed(piece.poly.all_coeffs()))), Fraction(0))

    def density_at(self, x: Any) -> Fraction | float:
        """The density at ``x``: exact for an int, a Fraction or a ``"p/q"`` string; a float gets the exact value at
        that float, rounded once.

        Parameters
        ----------
        x : int, Fraction, str or float
            Where to evaluate: exact for an int, a Fraction or ``"p/q"``; a float is taken at its exact value.

        Returns
        -------
        Fraction or float
            Exact for an exact ``x``; for a float, the exact value rounded once.

        Examples
        --------
        >>> import forcenet
        >>> law = forcenet.law(3, (3, 2))
        >>> law.density_at("1/3"), law.density_at(0.5), law.density_at(2)
        (Fraction(4, 3), 1.5, Fraction(0, 1))
        """
        return self._at(self.density, x, 0, 0)

    def cdf_at(self, x: Any) -> Fraction | float:
        """``P(<= x)``, exact as :meth:`density_at`.

        Parameters
        ----------
        x : int, Fraction, str or float
            Where to evaluate, as in :meth:`density_at`.

        Returns
        -------
        Fraction or float
            Exact for an exact ``x``; for a float, the exact value rounded once.

        Examples
        --------
        >>> import forcenet
        >>> forcenet.law(3, (3, 2)).cdf_at("1/2")
        Fraction(1, 2)
        """
        return self._at(self.cdf, x, 0, 1)

    def grid(self, K: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(x, density, cdf)`` at ``K + 1`` equally spaced points of the support, exact values rounded once.

        Parameters
        ----------
        K : int
            Number of intervals (``K + 1`` points).

        Returns
        -------
        tuple of three numpy.ndarray
            The points, the density and the CDF there.

        Examples
        --------
        >>> import forcenet
        >>> forcenet.law(3, layer=3).grid(3)[2].tolist()
        [0.0, 0.5555555555555556, 0.8888888888888888, 1.0]
        """
        return self._grid(K, "K")

    def _grid(self, K: Any, name: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """:meth:`grid` with ``K`` checked as the argument ``name`` (``K``, ``grid``, ``points``), capped."""

        degree = max(max(p.poly.degree() for p in pieces) for pieces in (self.density, self.cdf))
        return density_grid(self.density, self.cdf, check_grid(K, degree, name))

    def to_dict(self, grid: int | None = None) -> dict[str, Any]:
        """What ``forcenet dist --format json`` writes, exact values as ``"p/q"`` strings (``grid``: ``--grid``).

        Parameters
        ----------
        grid : int, optional
            Also the values at ``grid + 1`` equally spaced points of the support (``forcenet dist --grid``).

        Returns
        -------
        dict
            The JSON object, exact values as strings.

        Examples
        --------
        >>> import forcenet
        >>> forcenet.law(3, (3, 2)).to_dict()["pieces"]
        [{'lo': '0', 'hi': '1', 'degree': 2, 'density': ['0', '6', '-6'], 'cdf': ['0', '0', '3', '-2']}]
        """

        out: dict[str, Any] = {
            "N": self.N, "quantity": self.quantity, "variable": self.variable,
            "pieces": [{"lo": str(p.lo), "hi": str(p.hi), "degree": p.poly.degree(), "density": poly_strings(p.poly),
                        "cdf": poly_strings(F.poly)} for p, F in zip(self.density, self.cdf)],
            "coefficients": "constant term first, exact rationals"}
        out.update({k: str(v) for k, v in self.extra.items()})
        if grid is not None:
            x, p, F = self._grid(grid, "grid")
            out["grid"] = [{self.variable: float(a), "density": float(b), "cdf": float(c)} for a, b, c in zip(x, p, F)]
        return out

    def to_json(self, grid: int | None = None) -> str:
        """``forcenet dist --format json`` (without its newline).

        Parameters
        ----------
        grid : int, optional
            Also the values at ``grid + 1`` equally spaced points of the support (``forcenet dist --grid``).

        Returns
        -------
        str

        Examples
        --------
        >>> import forcenet
        >>> forcenet.law(2, (2, 1)).to_json()  # doctest: +ELLIPSIS
        '{"N": 2, "quantity": "W_{2,1}", "variable": "w", "pieces": [{"lo": "0", "hi": "1", "degree": 0, ...}'
        """

        return json.dumps(self.to_dict(grid), allow_nan=False)

    def to_csv(self, grid: int | None = None) -> str:
        """``forcenet dist --format csv``: ``lo,hi,power,density,cdf`` coefficient rows, or with ``grid`` the values.

        Parameters
        ----------
        grid : int, optional
            Also the values at ``grid + 1`` equally spaced points of the support (``forcenet dist --grid``).

        Returns
        -------
        str

        Examples
        --------
        >>> import forcenet
        >>> print(forcenet.law(3, (3, 2)).to_csv())
        lo,hi,power,density,cdf
        0,1,0,0,0
        0,1,1,6,0
        0,1,2,-6,3
        0,1,3,0,-2
        """

        var = self.variable
        if grid is not None:
            x, p, F = self._grid(grid, "grid")
            return "\n".join([f"{var},density,cdf"] + [f"{a!r},{b!r},{c!r}" for a, b, c in
                                                         zip(x.tolist(), p.tolist(), F.tolist())])
        lines = ["lo,hi,power,density,cdf"]
        for piece, F in zip(self.density, self.cdf):
            dens, cum = poly_strings(piece.poly), poly_strings(F.poly)
            dens += ["0"] * (len(cum) - len(dens))
            lines += [f"{piece.lo},{piece.hi},{m},{a},{b}" for m, (a, b) in enumerate(zip(dens, cum))]
        return "\n".join(lines)

    def _cases(self, pieces: list[Any]) -> str:
        var = self.variable
        if len(pieces) == 1:
            return sympy.latex(pieces[0].poly.as_expr()) + rf" \qquad ({pieces[0].lo} \le {var} \le {pieces[0].hi})"
        rows = [rf"{sympy.latex(p.poly.as_expr())} & {p.lo} \le {var} < {p.hi}" for p in pieces]
        return r"\begin{cases} " + r" \\ ".join(rows) + r" \end{cases}"

    def to_latex(self, grid: int | None = None) -> str:
        """``forcenet dist --format latex``: the density and the CDF as cases, and the ``grid`` as a tabular.

        Parameters
        ----------
        grid : int, optional
            Also the values at ``grid + 1`` equally spaced points of the support (``forcenet dist --grid``).

        Returns
        -------
        str

        Examples
        --------
        >>> import forcenet
        >>> print(forcenet.law(3, (3, 2)).to_latex().splitlines()[2])
        p(w) &= - 6 w^{2} + 6 w \\qquad (0 \\le w \\le 1) \\\\
        """
        var = self.variable
        lines = [f"% {self.quantity}", r"\begin{align*}", rf"p({var}) &= {self._cases(self.density)} \\",
                 rf"P(\le {var}) &= {self._cases(self.cdf)}", r"\end{align*}"]
        if grid is not None:
            x, p, F = self._grid(grid, "grid")
            lines += [r"\begin{tabular}{rrr}", rf"${var}$ & density & CDF \\ \hline"]
            lines += [rf"{a:.6g} & {b:.10g} & {c:.10g} \\" for a, b, c in zip(x, p, F)]
            lines += [r"\end{tabular}"]
        return "\n".join(lines)

    def to_text(self, grid: int | None = None) -> str:
        """``forcenet dist``'s text: each piece's degree and lowest coefficients, the extra fields, the ``grid``.

        Parameters
        ----------
        grid : int, optional
            Also the values at ``grid + 1`` equally spaced points of the support (``forcenet dist --grid``).

        Returns
        -------
        str

        Examples
        --------
        >>> import forcenet
        >>> print(forcenet.law(3, (3, 2)).to_text().splitlines()[1])
          on [0, 1]: polynomial of degree 2 in w; lowest coefficients 0, 6, -6, ...
        """
        var = self.variable
        lines = textwrap.wrap(f"N = {self.N}: exact density of {self.quantity} (exact; all coefficients: "
                              "--format json)", 80, subsequent_indent="  ", break_on_hyphens=False)
        for p in self.density:  # lines of at most 80 columns (issue 53), a long coefficient on its own
            lead = ", ".join(str(c) for c in list(reversed(p.poly.all_coeffs()))[:3])
            lines += textwrap.wrap(f"on [{p.lo}, {p.hi}]: polynomial of degree {p.poly.degree()} in {var}; lowest "
                                   f"coefficients {lead}, ...", 78, initial_indent="  ", subsequent_indent="    ",
                                   break_on_hyphens=False, break_long_words=False)
        lines += [f"  {k} = {v}" for k, v in self.extra.items()]
        lines.append(f"  density at {var} = 0: {self.density[0].poly.eval(0)}")
        if grid is not None:
            lines.append(f"  {var:>10}  {'density':>14}  {'cdf':>14}")
            lines += [f"  {a:10.6g}  {b:14.8g}  {c:14.8g}" for a, b, c in zip(*self._grid(grid, "grid"))]
        return "\n".join(lines)

    def _repr_latex_(self) -> str | None:
        if sum(p.poly.degree() + 1 for p in self.density) > 60:
            return None
        return rf"$p({self.variable}) = {self._cases(self.density)}$"

    def _repr_html_(self) -> str:
        head = f"<p>{escape(self.quantity)}, N = {self.N} ({escape(self.method)}): mean {self.mean}</p>"
        rows = "".join(f"<tr><td>[{p.lo}, {p.hi}]</td><td>{p.poly.degree()}</td></tr>" for p in self.density)
        return head + "<table><tr><th>piece</th><th>degree</th></tr>" + rows + "</table>"

    def compare_with_samples(self, samples: int = 20000, sweeps: int = 3000, bins: int = 40, f_max: float = 4.0,
                             seed: int = 0, progress: Callable[..., Any] | bool | None = None) -> SampledComparison[Law]:
        """This pooled ``P(f)`` against the exact sampler's and Metropolis's histograms (``forcenet dist --plot``).

        Both samplers draw the pooled force ``f = i W_ij`` of :attr:`pool`
        on ``bins`` equal bins of ``[0, f_max]``; each histogram is set
        against the exact bin masses of this density by a chi-square (the
        chain's error bars from its integrated autocorrelation time,
        Sec. 3.2.4).  The defaults are those of ``forcenet dist --plot``.

        Parameters
        ----------
        samples : int
            Independent exact samples, ``>= 2``.
        sweeps : int
            Metropolis sweeps, ``>= 2`` (burn-in ``max(100, sweeps // 10)``).
        bins : int
            Equal bins of ``[0, f_max]``, ``1..1000``.
        f_max : float
            The histograms' range, a finite number ``> 0``.
        seed : int
            Both samplers' seed, ``>= 0``.
        progress : callable, bool or None
            ``progress(k)`` per ``k`` samples or sweeps; ``True``: a progress bar.

        Returns
        -------
        SampledComparison
            The histograms, the exact bin masses, the chi-square notes and the figure (:meth:`~SampledComparison.png`).

        Raises
        ------
        ArgumentError
            If this is a grain's or a contact's law (not pooled), or an argument is out of range.

        Examples
        --------
        >>> import forcenet
        >>> c = forcenet.law(6, layer=6).compare_with_samples(samples=2000, sweeps=2000, bins=10, seed=1)
        >>> [bins for _, bins, _ in c.chi_squares.values()]
        [10, 10]
        >>> forcenet.law(6, (6, 3)).compare_with_samples()  # doctest: +ELLIPSIS
        Traceback (most recent call last):
        ...
        forcenet.core.errors.ArgumentError: compare_with_samples compares a pooled P(f) with sampled histograms: ...
        """

        return comparison_plan(self.N, self.pool, samples=samples, sweeps=sweeps, bins=bins, f_max=f_max, seed=seed,
                               law=self).check().run(progress)

    def plot(self, ax: Axes | None = None, points: int = 400) -> Axes:
        """The density over its support (exact values rounded once, ``points + 1`` points).

        Parameters
        ----------
        ax : matplotlib.axes.Axes, optional
            Where to draw (default: a new figure).
        points : int
            Number of intervals of the drawn curve.

        Returns
        -------
        matplotlib.axes.Axes

        Examples
        --------
        >>> import matplotlib
        >>> matplotlib.use("Agg")
        >>> import forcenet
        >>> ax = forcenet.law(12, (12, 6)).plot()
        >>> ax.get_title(), ax.get_legend_handles_labels()[1]
        ('N = 12: $W_{12,6}$', ['exact density of $W_{12,6}$'])
        """
        x, p, _ = self._grid(points, "points")  # the points checked before matplotlib is loaded
        import matplotlib.pyplot as plt

        if ax is not None and not isinstance(ax, plt.Axes):
            raise ArgumentTypeError(f"ax={ax!r} is not a matplotlib Axes: give one, or None for a new figure")
        if ax is None:
            _, ax = plt.subplots(figsize=(5, 3.5))
        ax.plot(x, p, label=f"exact density of {_mathtext(self.quantity)}")
        ax.set_xlabel(self.variable)
        ax.set_ylabel(f"p({self.variable})")
        ax.set_title(f"N = {self.N}: {_mathtext(self.quantity)}")
        ax.legend(loc="best", fontsize="small")
        return ax


def _mathtext(text: str) -> str:
    """A quantity's name for matplotlib: its TeX-like pieces (``W_{12,6}``, ``F1^{(5,2)}``) set as math.

    Examples
    --------
    >>> _mathtext("W_{12,6}"), _mathtext("F1^{(5,2)} of grain 2")
    ('$W_{12,6}$', '$F1^{(5,2)}$ of grain 2')
    """
    text = text.replace("(sqrt3/2)", r"$(\sqrt{3}/2)$")
    return re.sub(r"\b([A-Za-z][A-Za-z0-9]*(?:[_^]\{[^}]*\})+)", r"$\1$", text)
