"""The one base of every result the front door returns: its renderings from its own values.

A result (:class:`forcenet.Table`, :class:`forcenet.Law`, :class:`forcenet.Samples`, ...) says what it holds
once, in :meth:`Rendered.to_dict` (JSON-ready values: exact numbers as strings, floats where the result is
floating point) and in :meth:`Rendered.to_text` (what the command line prints, at most 80 columns); the base
derives the rest the same way for every result: :meth:`Rendered.to_json` (what ``--format json`` prints) and the
notebook display :meth:`Rendered._repr_html_`. A result whose JSON is one line sets nothing; one whose JSON is
indented sets :attr:`Rendered.json_indent`; a result with an exact rendering of its own (the triangle's tables)
overrides :meth:`Rendered.to_json`.

Examples
--------
>>> import forcenet
>>> m = forcenet.maps(4)
>>> isinstance(m, Rendered), m.to_json() == __import__("json").dumps(m.to_dict())
(True, True)
"""

from __future__ import annotations

import json
from abc import ABC, abstractmethod
from html import escape
from typing import Any, ClassVar

__all__ = ["Rendered"]


class Rendered(ABC):
    """What every result shares: JSON from :meth:`to_dict`, the notebook's display from :meth:`to_text`.

    Examples
    --------
    >>> import forcenet
    >>> count = forcenet.count_plan(6).run()
    >>> count.to_json(), count.to_text()
    ('{"N": 6, "count": "286"}', '286')
    """

    json_indent: ClassVar[int | None] = None  # None: JSON on one line; an int: indented, with a final newline

    @abstractmethod
    def to_dict(self) -> dict[str, Any]:
        """The result's values, ready for JSON (what :meth:`to_json` writes).

        Returns
        -------
        dict

        Examples
        --------
        >>> import forcenet
        >>> forcenet.maps(3).to_dict()
        {'N': 3, 'Z': '1', 'by_bottom_row': [{'bottom_row': [1], 'maps': '1'}]}
        """

    @abstractmethod
    def to_text(self) -> str:
        """The text the command line prints (and a newline), at most 80 columns.

        Returns
        -------
        str

        Examples
        --------
        >>> import forcenet
        >>> print(forcenet.maps(3).to_text())
        Z_1 = 1  (maps h of Sec. 4.6 for N = 3; equals the tableaux count)
        maps per bottom row h(N-2, 1..N-2), 1 rows with maps:
         1 : 1
        """

    def to_json(self) -> str:
        """The JSON ``--format json`` prints: :meth:`to_dict`, no NaN (it is not JSON).

        Returns
        -------
        str

        Examples
        --------
        >>> import forcenet
        >>> forcenet.maps(3).to_json()
        '{"N": 3, "Z": "1", "by_bottom_row": [{"bottom_row": [1], "maps": "1"}]}'
        """
        text = json.dumps(self.to_dict(), indent=self.json_indent, allow_nan=False)
        return text if self.json_indent is None else text + "\n"

    def _repr_html_(self) -> str:
        """The notebook's display: :meth:`to_text` as preformatted text."""
        return f"<pre>{escape(self.to_text())}</pre>"
