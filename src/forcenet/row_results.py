"""One row of the exact tables (:class:`Row`): what :func:`forcenet.row` returns.

The renderings are the table's (exact values as ``"p/q"``), byte for byte those of ``forcenet table --row i``.

Examples
--------
>>> import forcenet
>>> forcenet.row(4, 4).mean_W
[Fraction(1, 7), Fraction(5, 14), Fraction(5, 14), Fraction(1, 7)]
"""

from __future__ import annotations

from fractions import Fraction
from typing import Any

from forcenet import table_formats
from forcenet.core.errors import ArgumentError
from forcenet.core.validation import check_int
from forcenet.exact.protocol import BoundedTable
from forcenet.exact.triangle.tables import exact_row
from forcenet.results import _Rendered

__all__ = ["Row"]


class Row(_Rendered):
    """One row (layer ``i``) of the exact tables: ``<W_ij^s>``, ``j = 1..i``, ``s = 1..moments``.

    Returned by :func:`row`; the renderings are byte for byte those of
    ``forcenet table --row i``.

    Parameters
    ----------
    N : int
        Number of layers.
    row : int
        The row (layer) ``i``.
    method : str
        The route that computed it (a row route, or a table method).
    why : str
        Why ``auto`` chose it (empty for an explicit method).
    rows : dict of int to list of Fraction
        ``{s: [<W_ij^s>, j = 1..i]}``.

    Examples
    --------
    >>> import forcenet
    >>> r = forcenet.row(5, 4, moments=2)
    >>> r.mean_W, r.moment(2) == forcenet.table(5, moments=2).moment(2)[3]
    ([Fraction(2, 11), Fraction(7, 22), Fraction(7, 22), Fraction(2, 11)], True)
    """

    def __init__(self, N: int, row: int, method: str, why: str, rows: dict[int, list[Fraction]]):
        self.N, self.row, self.method, self.why = N, row, method, why
        self._rows = {s: BoundedTable(values, (0, 1), "every W^s of the triangle lies in [0, 1]")
                      for s, values in rows.items()}
        self.moments = max(rows)

    def __repr__(self) -> str:
        return f"Row(N={self.N}, row={self.row}, moments={self.moments}, method={self.method!r})"

    @property
    def mean_W(self) -> list[Fraction]:
        """``<W_ij>``, ``j = 1..i``.

        Examples
        --------
        >>> import forcenet
        >>> forcenet.row(4, 4).mean_W
        [Fraction(1, 7), Fraction(5, 14), Fraction(5, 14), Fraction(1, 7)]
        """
        return self._rows[1]

    def moment(self, s: int = 2) -> list[Fraction]:
        """``<W_ij^s>``, ``j = 1..i``, for ``1 <= s <= moments``.

        Parameters
        ----------
        s : int
            The moment.

        Returns
        -------
        list of Fraction

        Raises
        ------
        ArgumentError
            If ``s`` was not computed.

        Examples
        --------
        >>> import forcenet
        >>> forcenet.row(4, 3, moments=2).moment(2)
        [Fraction(3, 28), Fraction(3, 14), Fraction(3, 28)]
        """
        s = check_int(s, "s", 1)
        if s not in self._rows:
            raise ArgumentError(f"s={s} is out of range: this row holds s = 1..{self.moments} "
                                f"(ask forcenet.table({self.N}, moments={s}, row={self.row}))")
        return self._rows[s]

    def to_latex(self, digits: int | None = None) -> str:
        """A paper-ready LaTeX table (``booktabs``) of this row, a line per moment: ``forcenet table --row i``'s.

        Parameters
        ----------
        digits : int, optional
            Decimals, correctly rounded from the exact values; default the exact fractions.

        Returns
        -------
        str

        Examples
        --------
        >>> import forcenet
        >>> print(forcenet.row(3, 3).to_latex().splitlines()[-3])
        1 & $\\frac{1}{4}$ & $\\frac{1}{2}$ & $\\frac{1}{4}$ \\\\
        """
        return table_formats.row_latex(self.to_dict(), digits)

    def to_dict(self) -> dict[str, Any]:
        """``{"N", "row", "count", "normalization", "mean_W", "mean_W2", ...}`` with exact values.

        Returns
        -------
        dict

        Examples
        --------
        >>> import forcenet
        >>> forcenet.row(4, 2).to_dict()["mean_W"]
        [Fraction(1, 2), Fraction(1, 2)]
        """

        return exact_row(self.N, self.row, self._rows)

    def to_text(self) -> str:
        """The row in words, one grain per line (a long fraction abbreviated: its exact digits are in the files).

        Returns
        -------
        str

        Examples
        --------
        >>> import forcenet
        >>> print(forcenet.row(3, 3).to_text())
        row 3 of the N = 3 triangle (fast):
          <W_3,1> = 1/4
          <W_3,2> = 1/2
          <W_3,3> = 1/4
        """
        lines = [f"row {self.row} of the N = {self.N} triangle ({self.method}):"]
        for s in sorted(self._rows):
            power = "" if s == 1 else f"^{s}"
            lines += [f"  <W{power}_{self.row},{j}> = {table_formats.abbreviated(value)}"
                      for j, value in enumerate(self._rows[s], 1)]
        return "\n".join(lines)
