"""What the front door returns: an exact table (:class:`Table`; one row of it is :class:`forcenet.Row`).

Exact :class:`~fractions.Fraction` values that carry their bounds (every ``W``
lies in ``[0, 1]``, so :func:`forcenet.testing.compare` takes the bounded test
by default), ``count`` and ``normalization`` of Eq. (4.1), and the renderings
the command line writes, byte for byte.  Made by :func:`forcenet.table`.

Examples
--------
>>> import forcenet
>>> t = forcenet.table(4)
>>> t.mean_W[-1], t.mean_W.bounds
([Fraction(1, 7), Fraction(5, 14), Fraction(5, 14), Fraction(1, 7)], (0, 1))
"""

from __future__ import annotations

import os
from fractions import Fraction
from html import escape
from typing import TYPE_CHECKING, Any

import numpy as np

from forcenet import table_formats
from forcenet.core.errors import ArgumentError
from forcenet.core.validation import check_int
from forcenet.exact.protocol import BoundedTable
from forcenet.exact.triangle.staircase import ensemble_volume, free_force_count, tableau_count
from forcenet.exact.triangle.tables import _latex_fraction, fraction_str, to_csv, to_json
from forcenet.rendering import Rendered

if TYPE_CHECKING:  # pragma: no cover - annotations only
    from matplotlib.axes import Axes

__all__ = ["Table"]

_SHOWN = 12  # a bottom row longer than this: its first and last three values in the summary


class _Rendered(Rendered):
    """The exact renderings of a table or a row (JSON and CSV with exact values as ``"p/q"``), from :meth:`to_dict`."""

    def to_json(self) -> str:
        """The JSON ``forcenet table`` writes (``--format json`` prints it and a newline); exact values as ``"p/q"``.

        Returns
        -------
        str

        Examples
        --------
        >>> import forcenet
        >>> forcenet.table(3).to_json()
        '{"N": 3, "count": "1", "normalization": "1/6", "mean_W": [["1"], ["1/2", "1/2"], ["1/4", "1/2", "1/4"]]}'
        >>> forcenet.row(3, 2).to_json()
        '{"N": 3, "row": 2, "count": "1", "normalization": "1/6", "mean_W": ["1/2", "1/2"]}'
        """

        return to_json(self.to_dict())

    def to_csv(self) -> str:
        """The CSV of ``forcenet table --format csv``: ``i,j,mean_W[,mean_W2...]``, one line per grain.

        Returns
        -------
        str

        Examples
        --------
        >>> import forcenet
        >>> print(forcenet.table(2).to_csv(), end="")
        i,j,mean_W
        1,1,1
        2,1,1/2
        2,2,1/2
        >>> print(forcenet.row(3, 3).to_csv(), end="")
        i,j,mean_W
        3,1,1/4
        3,2,1/2
        3,3,1/4
        """

        return to_csv(self.to_dict())


class Table(_Rendered):
    """An exact table of the fully mobilized triangle: ``<W_ij^s>`` for ``s = 1..moments``.

    Rows ``i = 1..N`` (layer ``i`` holds ``i`` grains), entries ``j = 1..i``,
    every value a :class:`~fractions.Fraction`.  Returned by :func:`table`;
    the text renderings are byte for byte the command line's.

    Parameters
    ----------
    N : int
        Number of layers.
    method : str
        The route that computed it.
    why : str
        Why ``auto`` chose that route (empty for an explicit method).
    tables : dict of int to list of lists of Fraction
        ``{s: <W^s> rows}``; the highest ``s`` is the table's ``moments``.

    Examples
    --------
    >>> import forcenet
    >>> t = forcenet.table(4)
    >>> t
    Table(N=4, moments=1, method='fast')
    >>> t.to_numpy().round(4)[-1]
    array([0.1429, 0.3571, 0.3571, 0.1429])
    """

    def __init__(self, N: int, method: str, why: str, tables: dict[int, list[list[Fraction]]]):
        self.N, self.method, self.why = N, method, why
        # every W_ij lies in [0, 1], so W^s too: forcenet.testing.compare then uses the bounded test by default
        self._tables = {s: BoundedTable(rows, (0, 1), "every W^s of the triangle lies in [0, 1]" if s > 1
                                      else "every W of the triangle lies in [0, 1]")
                        for s, rows in tables.items()}
        self.moments = max(tables)

    def __repr__(self) -> str:
        return f"Table(N={self.N}, moments={self.moments}, method={self.method!r})"

    def __eq__(self, other: object) -> bool:
        """Equal values: the same ``N`` and the same exact moment tables (the route that made them aside)."""
        if not isinstance(other, Table):
            return NotImplemented
        return self.N == other.N and {s: list(t) for s, t in self._tables.items()} == {
            s: list(t) for s, t in other._tables.items()}

    __hash__ = None  # type: ignore[assignment]  # mutable lists inside: not hashable

    @classmethod
    def from_json(cls, text: str) -> Table:
        """The table whose :meth:`to_json` is ``text`` (``forcenet table``'s ``.json`` file read back).

        Parameters
        ----------
        text : str

        Returns
        -------
        Table
            ``method`` is ``"json"``.

        Raises
        ------
        ArgumentError
            If ``text`` is not a whole table's JSON.

        Examples
        --------
        >>> import forcenet
        >>> t = forcenet.table(5, moments=2)
        >>> forcenet.Table.from_json(t.to_json()) == t
        True
        """
        N, tables = table_formats.from_json(text)
        return cls(N, "json", "", tables)

    @classmethod
    def read(cls, path: str | os.PathLike[str]) -> Table:
        """A table saved by ``forcenet table`` (its ``.json`` or ``.csv`` file) or by :meth:`to_json`.

        Parameters
        ----------
        path : str or path-like

        Returns
        -------
        Table
            ``method`` is ``"json"`` or ``"csv"``.

        Examples
        --------
        >>> import os, tempfile, forcenet
        >>> path = os.path.join(tempfile.mkdtemp(), "N6.json")
        >>> _ = open(path, "w").write(forcenet.table(6).to_json())
        >>> forcenet.Table.read(path) == forcenet.table(6)
        True
        """
        N, tables = table_formats.read(path)
        return cls(N, "csv" if os.fspath(path).endswith(".csv") else "json", "", tables)

    def to_pandas(self, exact: bool = False) -> Any:
        """A :class:`pandas.DataFrame`, one row per grain ``(i, j)``, one column per moment (needs pandas).

        Parameters
        ----------
        exact : bool
            Keep the :class:`~fractions.Fraction` values (default: correctly rounded floats).

        Returns
        -------
        pandas.DataFrame

        Examples
        --------
        >>> import forcenet
        >>> forcenet.table(4, moments=2).to_pandas().loc[4].round(4)
           mean_W  mean_W2
        j...
        1  0.1429   0.0357
        2  0.3571   0.1607
        3  0.3571   0.1607
        4  0.1429   0.0357
        """
        return table_formats.to_pandas(self._tables, exact)

    def to_latex(self, digits: int | None = None, rows: Any = None) -> str:
        """A paper-ready LaTeX table (``booktabs``) of ``<W_ij>``: what ``forcenet table`` writes as ``.tex``.

        Parameters
        ----------
        digits : int, optional
            Decimals, correctly rounded from the exact values; default the exact fractions.
        rows : sequence of int, optional
            The layers ``i`` to include (default all).

        Returns
        -------
        str

        Examples
        --------
        >>> import forcenet
        >>> print(forcenet.table(3).to_latex().splitlines()[-3])
        3 & $\\frac{1}{4}$ & $\\frac{1}{2}$ & $\\frac{1}{4}$ \\\\
        >>> print(forcenet.table(8).to_latex(digits=3, rows=[8]).splitlines()[5][:46])
        8 & $0.034$ & $0.104$ & $0.164$ & $0.197$ & $0
        """
        return table_formats.latex(self.to_dict(), digits=digits, rows=rows)

    @property
    def mean_W(self) -> list[list[Fraction]]:
        """``<W_ij>``: row ``i - 1`` holds ``j = 1..i`` (a list that carries its bounds, ``[0, 1]``, for
        :func:`forcenet.testing.compare`).

        Examples
        --------
        >>> import forcenet
        >>> forcenet.table(3).mean_W
        [[Fraction(1, 1)], [Fraction(1, 2), Fraction(1, 2)], [Fraction(1, 4), Fraction(1, 2), Fraction(1, 4)]]
        """
        return self._tables[1]

    def moment(self, s: int = 1) -> list[list[Fraction]]:
        """``<W_ij^s>`` for ``1 <= s <= moments``.

        Parameters
        ----------
        s : int
            The moment.

        Returns
        -------
        list of lists of Fraction

        Raises
        ------
        ArgumentError
            If ``s`` was not computed.

        Examples
        --------
        >>> import forcenet
        >>> forcenet.table(3, moments=2).moment(2)[-1]
        [Fraction(1, 10), Fraction(3, 10), Fraction(1, 10)]
        """
        s = check_int(s, "s", 1)
        if s not in self._tables:
            raise ArgumentError(f"s={s} is out of range: this table holds s = 1..{self.moments} "
                                f"(ask forcenet.table({self.N}, moments={s}))")
        return self._tables[s]

    @property
    def count(self) -> int:
        """Standard shifted staircase tableaux: ``d! * normalization``, Eq. (4.1).

        Examples
        --------
        >>> import forcenet
        >>> forcenet.table(6).count
        286
        """

        return tableau_count(self.N)  # N checked once, by the request (forcenet.exact.routes.check_request)

    @property
    def normalization(self) -> Fraction:
        """The volume of the space of force networks, Eq. (4.1).

        Examples
        --------
        >>> import forcenet
        >>> forcenet.table(4).normalization
        Fraction(1, 360)
        """

        return ensemble_volume(self.N)

    def to_dict(self) -> dict[str, Any]:
        """``{"N", "count", "normalization", "mean_W", "mean_W2", ...}`` with exact values (the renderers' input).

        Returns
        -------
        dict

        Examples
        --------
        >>> import forcenet
        >>> sorted(forcenet.table(4, moments=2).to_dict())
        ['N', 'count', 'mean_W', 'mean_W2', 'normalization']
        """
        out: dict[str, Any] = {"N": self.N, "count": self.count, "normalization": self.normalization}
        out.update({"mean_W" if s == 1 else f"mean_W{s}": rows for s, rows in sorted(self._tables.items())})
        return out

    def to_text(self) -> str:
        """The table in words, what the main job prints first (:meth:`summary`).

        Returns
        -------
        str

        Examples
        --------
        >>> import forcenet
        >>> forcenet.table(4).to_text() == forcenet.table(4).summary()
        True
        """
        return self.summary()

    def summary(self) -> str:
        """The readable summary the main job (``forcenet table --N N``) prints first: the triangle's size and
        dimension, the count and the normalization of Eq. (4.1), and the bottom row, each value as a decimal and
        exactly.

        Returns
        -------
        str
            The lines, without a final newline.

        Examples
        --------
        >>> import forcenet
        >>> print(forcenet.table(4).summary())
        Fully mobilized triangle, N = 4 layers, d = 6 free forces
          W_ij: load on grain j of layer i in units of the overload; rows sum to 1
          tableaux count (d! * normalization): 2
          normalization (Eq. 4.1):             1/360
          <W_N,j> on the bottom row:
            j =  1: 0.1428571429  = 1/7
            j =  2: 0.3571428571  = 5/14
            j =  3: 0.3571428571  = 5/14
            j =  4: 0.1428571429  = 1/7

        References
        ----------
        Ostojic (2006), Eq. (4.1) (count and normalization), Eq. (4.3) (``d = N (N - 1)/2``), Sec. 4.2.
        """
        lines = [
            f"Fully mobilized triangle, N = {self.N} layers, d = {free_force_count(self.N)} free forces",
            "  W_ij: load on grain j of layer i in units of the overload; rows sum to 1",
            f"  tableaux count (d! * normalization): {table_formats.abbreviated(Fraction(self.count))}",
            f"  normalization (Eq. 4.1):             {_short(self.normalization)}",
            "  <W_N,j> on the bottom row:",
        ]
        bottom = list(enumerate(self.mean_W[-1], start=1))
        shown = bottom if self.N <= _SHOWN else [*bottom[:3], None, *bottom[-3:]]  # the files hold every value
        lines += ["    ..." if item is None else f"    j = {item[0]:2d}: {float(item[1]):.10f}  = {table_formats.abbreviated(item[1])}"
                  for item in shown]
        return "\n".join(lines)

    def to_numpy(self, s: int = 1) -> np.ndarray:
        """``<W_ij^s>`` as an ``(N, N)`` float array (correctly rounded), NaN where ``j > i``.

        Parameters
        ----------
        s : int
            The moment.

        Returns
        -------
        numpy.ndarray

        Examples
        --------
        >>> import forcenet
        >>> forcenet.table(3).to_numpy()[2]
        array([0.25, 0.5 , 0.25])
        """

        out = np.full((self.N, self.N), np.nan)
        for i, row in enumerate(self.moment(s)):
            out[i, :len(row)] = [float(x) for x in row]  # float(Fraction) rounds correctly
        return out

    def _repr_latex_(self) -> str | None:
        if self.N > 10:
            return None

        rows = [" & ".join(_latex_fraction(x) for x in row) + " & " * (self.N - len(row)) for row in self.mean_W]
        body = r" \\ ".join(rows)
        return rf"$\langle W_{{ij}}\rangle,\ N={self.N}:\ \left(\begin{{array}}{{{'c' * self.N}}}{body}\end{{array}}\right)$"

    def _repr_html_(self) -> str:
        rows = range(1, self.N + 1) if self.N <= 12 else [*range(1, 7), *range(self.N - 2, self.N + 1)]
        cells = []
        for i in rows:
            texts = [fraction_str(x) for x in self.mean_W[i - 1]]
            shown = [escape(t) if len(t) < 16 else f"{float(x):.6g}" for t, x in zip(texts, self.mean_W[i - 1])]
            cells.append(f"<tr><th>{i}</th>" + "".join(f"<td>{t}</td>" for t in shown) + "</tr>")
        head = f"<p>&lt;W<sub>ij</sub>&gt;, N = {self.N} ({escape(self.method)})</p>"
        return head + "<table>" + "".join(cells) + "</table>"

    def plot(self, s: int = 1, ax: Axes | None = None) -> Axes:
        """The triangle drawn as it stands: grain ``(i, j)`` at ``(j - (i + 1)/2, -i)``, coloured by ``<W_ij^s>``.

        The colour scale is logarithmic (the loads span decades between the
        apex and the bottom row's edges).

        Parameters
        ----------
        s : int
            The moment.
        ax : matplotlib.axes.Axes, optional
            Where to draw (default: a new figure).

        Returns
        -------
        matplotlib.axes.Axes

        Examples
        --------
        >>> import matplotlib
        >>> matplotlib.use("Agg")
        >>> import forcenet
        >>> ax = forcenet.table(8).plot()
        >>> ax.get_title(), type(ax.collections[0].norm).__name__
        ('N = 8', 'LogNorm')
        """
        import matplotlib.pyplot as plt

        if ax is None:
            _, ax = plt.subplots(figsize=(5, 4.5))
        xs, ys, cs = [], [], []
        for i, row in enumerate(self.moment(s), start=1):
            for j, value in enumerate(row, start=1):
                xs.append(j - (i + 1) / 2)
                ys.append(-i)
                cs.append(float(value))
        from matplotlib.colors import LogNorm

        size = max(4.0, 2400 / self.N**2)
        positive = min(cs) > 0  # a log scale: the small loads near the edges and deep layers stay distinct
        points = ax.scatter(xs, ys, c=cs, s=size, cmap="viridis", norm=LogNorm() if positive else None)
        ax.figure.colorbar(points, ax=ax, label=r"$\langle W_{ij}\rangle$" if s == 1 else rf"$\langle W_{{ij}}^{s}\rangle$")
        ax.set_aspect("equal")
        ax.set_axis_off()
        ax.set_title(f"N = {self.N}")
        return ax


def _short(x: Fraction) -> str:
    """An exact value for the terminal: the fraction when short, else its decimal (scientific) and its size."""
    text = table_formats.abbreviated(x)
    return text if "digits" not in text else f"{table_formats.scientific(x)} ({text})"
