"""Exact tables: JSON, CSV and LaTeX renderings and atomic file output.

Examples
--------
>>> from forcenet.exact.triangle.tables import exact_table, to_json
>>> print(to_json(exact_table(2)))
{"N": 2, "count": "1", "normalization": "1", "mean_W": [["1"], ["1/2", "1/2"]]}
"""

from __future__ import annotations

import json
import os
import re
import sys
from fractions import Fraction

from forcenet.core import atomic_files
from forcenet.core.errors import ArgumentError
from forcenet.core.validation import check_layers, check_moments

from ..protocol import Progress
from .moments import mean_W, moment_table
from .staircase import count, normalization

__all__ = ["exact_table", "exact_row", "to_json", "to_csv", "to_latex", "write_atomic", "fraction_str", "integer_text",
           "fraction_from_text"]

_RATIONAL = re.compile(r"([+-]?)([0-9]+)(?:/([0-9]+))?", re.ASCII)  # what fraction_str writes


def integer_text(n: int) -> str:
    """The decimal digits of ``n``, however long: Python's limit on ``str(int)`` does not apply.

    Python refuses ``str(n)`` beyond ``sys.get_int_max_str_digits()`` digits
    (4300 by default); the exact tables pass it from N = 160 on (the lattice
    column's denominators).  Longer integers are split by a power of ten and
    their halves converted separately.  The global limit is never changed.

    Parameters
    ----------
    n : int
        Any integer.

    Returns
    -------
    str
        ``str(n)`` as if there were no limit.

    Examples
    --------
    >>> integer_text(-1234567)
    '-1234567'
    >>> len(integer_text(7 ** 10000))  # 8451 digits, twice the default limit
    8451
    """
    limit = sys.get_int_max_str_digits()  # 0: no limit
    if limit == 0 or n.bit_length() <= 3 * limit:  # 3 bits make less than one digit
        return str(n)
    if n < 0:
        return "-" + integer_text(-n)
    k = n.bit_length() * 30103 // 200000  # about half the digits (log10(2) = 0.30103)
    high, low = divmod(n, 10**k)
    return integer_text(high) + integer_text(low).zfill(k)


def _integer_from_digits(digits: str) -> int:
    """``int(digits)`` for validated ASCII digits, however many (halves below the limit)."""
    limit = sys.get_int_max_str_digits()
    if limit == 0 or len(digits) <= limit:
        return int(digits)
    k = len(digits) // 2
    return _integer_from_digits(digits[:-k]) * 10**k + _integer_from_digits(digits[-k:])


def fraction_from_text(text: str) -> Fraction:
    """The exact rational written ``"p/q"`` or ``"p"`` (as :func:`fraction_str` writes it), however long.

    Parameters
    ----------
    text : str
        Decimal numerator, optionally ``/`` and a positive decimal denominator.

    Returns
    -------
    Fraction
        The value, in lowest terms.

    Raises
    ------
    ArgumentError
        If ``text`` is not of that form or the denominator is 0.

    Examples
    --------
    >>> fraction_from_text("41/132"), fraction_from_text("-3")
    (Fraction(41, 132), Fraction(-3, 1))
    >>> x = Fraction(7 ** 10000, 3 ** 9000)
    >>> fraction_from_text(fraction_str(x)) == x
    True
    """
    match = _RATIONAL.fullmatch(text.strip())
    if match is None:
        raise ArgumentError(f"text must be an exact rational 'p/q' or 'p' in decimal digits, got {text[:40]!r}")
    sign, numerator, denominator = match.groups()
    q = _integer_from_digits(denominator) if denominator else 1
    if q == 0:
        raise ArgumentError(f"text must have a positive denominator, got {text[:40]!r}")
    p = _integer_from_digits(numerator)
    return Fraction(-p if sign == "-" else p, q)


def fraction_str(x: Fraction | int | str) -> str:
    """``"p/q"`` or ``"p"`` for an exact rational, however long (:func:`integer_text`).

    Examples
    --------
    >>> fraction_str(Fraction(3, 6)), fraction_str(Fraction(4, 2))
    ('1/2', '2')
    """
    x = Fraction(x)
    if x.denominator == 1:
        return integer_text(x.numerator)
    return f"{integer_text(x.numerator)}/{integer_text(x.denominator)}"


def exact_table(N: int, moments: int = 1, mean_table: list[list[Fraction]] | None = None, progress: Progress | None = None,
                moment_tables: dict[int, list[list[Fraction]]] | None = None) -> dict:
    """The exact table as a dict of exact values (Fractions and ints).

    Keys: ``N``, ``count``, ``normalization``, ``mean_W`` and, for
    ``moments >= 2``, ``mean_W2`` ... ``mean_W{moments}``.
    """
    N = check_layers(N)
    moments = check_moments(moments)
    table = {
        "N": N,
        "count": count(N),
        "normalization": normalization(N),
        "mean_W": mean_table if mean_table is not None else mean_W(N, progress),
    }
    for s in range(2, moments + 1):  # moment_tables: {s: table} from another route, if given
        table[f"mean_W{s}"] = (moment_tables or {}).get(s) or moment_table(N, s)
    return table


def exact_row(N: int, row: int, moment_rows: dict) -> dict:
    """One row ``i`` of the exact tables as a dict: ``N``, ``row``, ``count``, ``normalization``, ``mean_W``,
    ``mean_W2``, ... (lists over ``j = 1..i``); rendered by :func:`to_json`, :func:`to_csv`, :func:`to_latex`.

    Examples
    --------
    >>> from fractions import Fraction
    >>> print(to_csv(exact_row(3, 2, {1: [Fraction(1, 2)] * 2, 2: [Fraction(3, 10)] * 2})), end="")
    i,j,mean_W,mean_W2
    2,1,1/2,3/10
    2,2,1/2,3/10
    """
    N = check_layers(N)
    out = {"N": N, "row": row, "count": count(N), "normalization": normalization(N)}
    for s in sorted(moment_rows):
        out["mean_W" if s == 1 else f"mean_W{s}"] = moment_rows[s]
    return out


def _moment_keys(table: dict) -> list[str]:
    return [k for k in table if k.startswith("mean_W")]


def to_json(table: dict) -> str:
    """JSON with exact values as strings (schema in the README)."""
    out = {"N": table["N"], "count": integer_text(table["count"]), "normalization": fraction_str(table["normalization"])}
    if "row" in table:  # one row (exact_row)
        out = {"N": table["N"], "row": table["row"], **{k: v for k, v in out.items() if k != "N"}}
        out.update({key: [fraction_str(x) for x in table[key]] for key in _moment_keys(table)})
        return json.dumps(out)
    for key in _moment_keys(table):
        out[key] = [[fraction_str(x) for x in row] for row in table[key]]
    return json.dumps(out)


def to_csv(table: dict) -> str:
    """One line per grain: ``i,j,mean_W[,mean_W2...]`` with exact values."""
    keys = _moment_keys(table)
    lines = ["i,j," + ",".join(keys)]
    if "row" in table:  # one row (exact_row)
        i = table["row"]
        lines += [f"{i},{j}," + ",".join(fraction_str(table[k][j - 1]) for k in keys)
                  for j in range(1, len(table["mean_W"]) + 1)]
        return "\n".join(lines) + "\n"
    for i, row in enumerate(table["mean_W"], start=1):
        for j in range(1, len(row) + 1):
            lines.append(f"{i},{j}," + ",".join(fraction_str(table[k][i - 1][j - 1]) for k in keys))
    return "\n".join(lines) + "\n"


def _latex_fraction(x: Fraction | int | str) -> str:
    x = Fraction(x)
    if x.denominator == 1:
        return integer_text(x.numerator)
    return rf"\frac{{{integer_text(x.numerator)}}}{{{integer_text(x.denominator)}}}"


def to_latex(table: dict, key: str = "mean_W") -> str:
    """A LaTeX ``tabular`` of one moment table, row ``i`` per line (of one row: a line per moment ``s``)."""
    if "row" in table:
        return _row_latex(table)
    rows = table[key]
    N = len(rows)
    label = {"mean_W": r"\langle W_{i,j}\rangle"}.get(key, rf"\langle W_{{i,j}}^{{{key[6:]}}}\rangle")
    lines = [
        rf"% {label} for the fully mobilized triangle, N = {N} (forcenet)",
        r"\begin{tabular}{r|" + "c" * N + "}",
        r"$i \backslash j$ & " + " & ".join(str(j) for j in range(1, N + 1)) + r" \\ \hline",
    ]
    for i, row in enumerate(rows, start=1):
        cells = [f"${_latex_fraction(x)}$" for x in row] + [""] * (N - len(row))
        lines.append(f"{i} & " + " & ".join(cells) + r" \\")
    lines.append(r"\end{tabular}")
    return "\n".join(lines) + "\n"


def _row_latex(table: dict) -> str:
    """Row ``i`` of every moment table in ``table`` (:func:`exact_row`): ``<W_{i,j}^s>``, a line per ``s``."""
    i, keys = table["row"], _moment_keys(table)
    lines = [
        rf"% \langle W_{{{i},j}}^s\rangle for the fully mobilized triangle, N = {table['N']} (forcenet)",
        r"\begin{tabular}{r|" + "c" * i + "}",
        r"$s \backslash j$ & " + " & ".join(str(j) for j in range(1, i + 1)) + r" \\ \hline",
    ]
    for key in keys:
        cells = [f"${_latex_fraction(x)}$" for x in table[key]]
        lines.append(f"{key[6:] or 1} & " + " & ".join(cells) + r" \\")
    lines.append(r"\end{tabular}")
    return "\n".join(lines) + "\n"


def write_atomic(path: str | os.PathLike[str], text: str) -> None:
    """Write ``text`` to ``path`` atomically, its folder created if missing (:mod:`forcenet.core.atomic_files`).

    An interrupted run (Ctrl-C included) leaves either the old file or none,
    never a truncated one; an existing file keeps its mode, a link its
    target replaced, a device is written in place, a read-only file refused
    (:class:`~forcenet.core.atomic_files.DestinationError`).

    Examples
    --------
    >>> import os, tempfile
    >>> path = os.path.join(tempfile.mkdtemp(), "tables", "N2.json")
    >>> write_atomic(path, to_json(exact_table(2)))
    >>> open(path).read()[:7]
    '{"N": 2'
    """
    path = os.fspath(path)
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    atomic_files.write_atomic(path, text)
