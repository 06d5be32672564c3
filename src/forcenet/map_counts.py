"""The front door for the maps of Sec. 4.6: :func:`maps` and what it returns (:class:`MapCounts`).

``forcenet.maps(N)`` is what ``forcenet maps --N N`` computes, to the same
bytes: the number of maps ``h`` of Sec. 4.6 for each bottom row
``h(N-2, 1..N-2)``, which is the integer ``Lambda^(N-2)`` of the recursion
(4.50) (Eq. (4.88)), and their sum ``Z_(N-2)``, the tableaux count of
Eq. (4.1). The engine is :func:`forcenet.exact.thesis.recursions.lambda_table`.

Examples
--------
>>> import forcenet
>>> m = forcenet.maps(5)
>>> m.by_bottom_row
{(1, 1, 1): 1, (1, 2, 1): 2, (1, 3, 1): 2, (2, 1, 1): 1, (2, 2, 1): 2, (2, 3, 1): 2, (2, 4, 1): 2}
>>> m.Z == forcenet.count(5)
True
"""

from __future__ import annotations

from typing import Any

from forcenet.core.validation import check_layers
from forcenet.exact.thesis.recursions import lambda_table
from forcenet.rendering import Rendered

__all__ = ["MAPS_MAX_N", "MapCounts", "maps"]

MAPS_MAX_N = 10  # every bottom row is listed: N = 10 has 391189 of them (~3 s), and the table grows over tenfold per layer


class MapCounts(Rendered):
    """The maps of Sec. 4.6 per bottom row, for ``N`` layers: what :func:`maps` returns.

    Its renderings are byte for byte those of ``forcenet maps``
    (:meth:`to_text`, :meth:`to_json`).

    Parameters
    ----------
    N : int
        Number of layers.
    by_bottom_row : dict of tuple of int to int
        ``(h(N-2, 1), ..., h(N-2, N-2))`` -> the number of maps with that bottom row (nonzero entries only).

    Examples
    --------
    >>> import forcenet
    >>> forcenet.maps(6)
    MapCounts(N=6, Z=286, rows=37)
    >>> forcenet.MapCounts.MAX_N  # the largest N forcenet.maps lists (the command line's range)
    10
    """

    MAX_N = MAPS_MAX_N

    def __init__(self, N: int, by_bottom_row: dict[tuple[int, ...], int]):
        self.N = N
        self.by_bottom_row = dict(sorted(by_bottom_row.items()))

    def __repr__(self) -> str:
        return f"MapCounts(N={self.N}, Z={self.Z}, rows={len(self.by_bottom_row)})"

    @property
    def Z(self) -> int:
        """``Z_(N-2)``: all the maps, the tableaux count of Eq. (4.1).

        Examples
        --------
        >>> import forcenet
        >>> forcenet.maps(8).Z
        23178480
        """
        return sum(self.by_bottom_row.values())

    def to_dict(self) -> dict[str, Any]:
        """The values of ``forcenet maps --format json``, integers as decimal strings.

        Returns
        -------
        dict
            ``N``, ``Z`` and ``by_bottom_row``: a list of ``{"bottom_row": [...], "maps": "..."}``.

        Examples
        --------
        >>> import forcenet
        >>> forcenet.maps(4).to_dict()
        {'N': 4, 'Z': '2', 'by_bottom_row': [{'bottom_row': [1, 1], 'maps': '1'}, {'bottom_row': [2, 1], 'maps': '1'}]}
        """
        rows = [{"bottom_row": list(j), "maps": str(v)} for j, v in self.by_bottom_row.items()]
        return {"N": self.N, "Z": str(self.Z), "by_bottom_row": rows}

    def to_text(self) -> str:
        """The text ``forcenet maps`` prints (and a newline): ``Z``, then one line per bottom row.

        Returns
        -------
        str

        Examples
        --------
        >>> import forcenet
        >>> print(forcenet.maps(4).to_text())
        Z_2 = 2  (maps h of Sec. 4.6 for N = 4; equals the tableaux count)
        maps per bottom row h(N-2, 1..N-2), 2 rows with maps:
         1  1 : 1
         2  1 : 1
        """
        N = self.N
        lines = [f"Z_{N - 2} = {self.Z}  (maps h of Sec. 4.6 for N = {N}; equals the tableaux count)",
                 f"maps per bottom row h(N-2, 1..N-2), {len(self.by_bottom_row)} rows with maps:"]
        lines += [" ".join(f"{x:2d}" for x in j) + " : " + str(v) for j, v in self.by_bottom_row.items()]
        return "\n".join(lines)


def maps(N: int) -> MapCounts:
    """The number of maps ``h`` of Sec. 4.6 for each bottom row ``h(N-2, 1..N-2)``, and their sum ``Z_(N-2)``.

    A map ``h`` of Sec. 4.6 encodes a linear extension of the triangle's
    poset; the maps with bottom row ``(j_1, ..., j_(N-2))`` number
    ``Lambda^(N-2)_(j_1..j_(N-2))`` of the recursion (4.50) (Eq. (4.88)), and
    all of them ``Z_(N-2)``, the tableaux count ``d! * normalization`` of
    Eq. (4.1). What ``forcenet maps`` prints, byte for byte.

    Parameters
    ----------
    N : int
        Number of layers, ``3..10``.

    Returns
    -------
    MapCounts
        ``by_bottom_row`` (bottom row -> maps, nonzero only, sorted), ``Z``; ``to_text``, ``to_json``.

    Raises
    ------
    ArgumentError
        If ``N`` is not an integer in ``3..10``.

    Examples
    --------
    >>> import forcenet
    >>> m = forcenet.maps(7)
    >>> m.Z, m.by_bottom_row[(1, 2, 3, 4, 1)]
    (33592, 148)
    >>> forcenet.maps(11)
    Traceback (most recent call last):
    ...
    forcenet.core.errors.ArgumentError: N=11 is out of range: N must be an integer in 3..10

    References
    ----------
    Ostojic (2006), Sec. 4.6, Eqs. (4.86)-(4.88) (the maps and their count
    per bottom row), Eq. (4.50) (the recursion Lambda), Eq. (4.1).
    """
    N = check_layers(N, minimum=3, maximum=MAPS_MAX_N)
    return MapCounts(N, lambda_table(N - 2))  # maps per bottom row h(N-2, .), Eq. (4.88)
