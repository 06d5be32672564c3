"""An exact table's paper and terminal forms, and the way back from its saved files.

* :func:`latex` — a ``booktabs`` table (``\\toprule``, ``\\midrule``,
  ``\\bottomrule``): exact fractions by default, ``digits`` correctly rounded
  decimals (the exact value rounded half to even, never a float's), chosen
  ``rows``; a row too long for one line is written one cell per line, so an
  editor opens the file (issue 53: N = 40 was 416 KB with lines of 20,009
  characters);
* :func:`abbreviated` — a value for the terminal: the exact fraction when
  short, else its decimal and the size of the fraction (the files hold it);
* :func:`from_json` / :func:`read` — a saved table (``forcenet table``'s
  ``.json`` or ``.csv``, or :meth:`~forcenet.Table.to_json`) back as its
  exact rows, checked: ``N`` rows, row ``i`` of ``i`` values;
* :func:`to_pandas` — one row per grain ``(i, j)``, one column per moment.

Examples
--------
>>> from fractions import Fraction as F
>>> print(latex({"N": 2, "mean_W": [[F(1)], [F(1, 3), F(2, 3)]]}, digits=3))
% \\langle W_{i,j}\\rangle for the fully mobilized triangle, N = 2 (forcenet; needs \\usepackage{booktabs})
\\begin{tabular}{rcc}
\\toprule
$i \\backslash j$ & 1 & 2 \\\\
\\midrule
1 & $1.000$ &  \\\\
2 & $0.333$ & $0.667$ \\\\
\\bottomrule
\\end{tabular}
<BLANKLINE>
"""

from __future__ import annotations

import importlib
import json
import os
from collections.abc import Iterable, Mapping, Sequence
from fractions import Fraction
from typing import Any

from forcenet.core.errors import ArgumentError, ArgumentTypeError
from forcenet.core.validation import check_int
from forcenet.exact.triangle.tables import fraction_from_text, fraction_str, integer_text

__all__ = ["abbreviated", "decimal", "from_json", "latex", "read", "row_latex", "scientific", "to_pandas"]

_LINE = 120  # a LaTeX row longer than this is written one cell per line
SHORT = 24  # a fraction longer than this is abbreviated on the terminal


def decimal(x: Fraction, digits: int) -> str:
    """``x`` with ``digits`` decimals, correctly rounded from the exact value (half to even).

    Examples
    --------
    >>> decimal(Fraction(1, 8), 2), decimal(Fraction(3, 8), 2), decimal(Fraction(-2, 3), 3), decimal(Fraction(5), 0)
    ('0.12', '0.38', '-0.667', '5')
    """
    scaled = Fraction(x) * 10**digits
    n = round(scaled)  # Fraction.__round__: the nearest integer, ties to even (exact)
    sign = "-" if n < 0 else ""
    whole, frac = divmod(abs(n), 10**digits)
    return f"{sign}{whole}" + (f".{frac:0{digits}d}" if digits else "")


def _latex_value(x: Fraction, digits: int | None) -> str:
    if digits is not None:
        return f"${decimal(x, digits)}$"
    if x.denominator == 1:
        return f"${integer_text(x.numerator)}$"
    return rf"$\frac{{{integer_text(x.numerator)}}}{{{integer_text(x.denominator)}}}$"


def _line(head: str, cells: list[str]) -> str:
    line = f"{head} & " + " & ".join(cells) + r" \\"
    if len(line) <= _LINE:
        return line
    return f"{head}\n  & " + "\n  & ".join(cells) + r" \\"  # a newline inside a row is a space to TeX


def _chosen(rows: Iterable[int] | None, N: int) -> list[int]:
    if rows is None:
        return list(range(1, N + 1))
    if isinstance(rows, (str, bytes)) or not isinstance(rows, Iterable):
        raise ArgumentTypeError(f"rows={rows!r} is not a sequence of layers: give e.g. rows=[1, 2, {N}]")
    chosen = [check_int(i, "rows", 1, N) for i in rows]
    if not chosen:
        raise ArgumentError(f"rows=[] chooses no layer: give layers in 1..{N}, e.g. rows=[1, {N}]")
    return chosen


def latex(table: dict[str, Any], key: str = "mean_W", digits: int | None = None,
          rows: Iterable[int] | None = None) -> str:
    """The ``booktabs`` LaTeX of one moment table of ``table`` (a :meth:`~forcenet.Table.to_dict`).

    Parameters
    ----------
    table : dict
        ``{"N": N, key: rows}``, row ``i - 1`` holding ``<W_ij^s>``, ``j = 1..i``.
    key : str
        ``"mean_W"`` or ``"mean_W<s>"``.
    digits : int, optional
        Decimals, correctly rounded; default the exact fractions.
    rows : iterable of int, optional
        The layers ``i`` to write, in that order (default all).

    Returns
    -------
    str
        The ``tabular``, a comment line first, a newline last.

    Examples
    --------
    >>> import forcenet
    >>> print(latex(forcenet.table(4).to_dict(), rows=[4]).splitlines()[5])
    4 & $\\frac{1}{7}$ & $\\frac{5}{14}$ & $\\frac{5}{14}$ & $\\frac{1}{7}$ \\\\

    References
    ----------
    Ostojic (2006), Sec. 4.2 (the exact tables of ``<W_ij>``).
    """
    if digits is not None:
        digits = check_int(digits, "digits", 0, 1000)
    N = table["N"]
    chosen = _chosen(rows, N)
    width = max(chosen)
    label = r"\langle W_{i,j}\rangle" if key == "mean_W" else rf"\langle W_{{i,j}}^{{{key[6:]}}}\rangle"
    lines = [rf"% {label} for the fully mobilized triangle, N = {N} (forcenet; needs \usepackage{{booktabs}})",
             r"\begin{tabular}{r" + "c" * width + "}", r"\toprule",
             r"$i \backslash j$ & " + " & ".join(str(j) for j in range(1, width + 1)) + r" \\", r"\midrule"]
    for i in chosen:
        values = table[key][i - 1]
        lines.append(_line(str(i), [_latex_value(x, digits) for x in values] + [""] * (width - len(values))))
    lines += [r"\bottomrule", r"\end{tabular}"]
    return "\n".join(lines) + "\n"


def row_latex(row: dict[str, Any], digits: int | None = None) -> str:
    """The ``booktabs`` LaTeX of one row ``i`` (a :meth:`~forcenet.Row.to_dict`): a line per moment ``s``.

    Examples
    --------
    >>> import forcenet
    >>> print(row_latex(forcenet.row(4, 3, moments=2).to_dict(), digits=3).splitlines()[6])
    2 & $0.107$ & $0.214$ & $0.107$ \\\\
    """
    if digits is not None:
        digits = check_int(digits, "digits", 0, 1000)
    i = row["row"]
    keys = sorted((k for k in row if k.startswith("mean_W")), key=lambda k: int(k[6:] or 1))
    lines = [rf"% \langle W_{{{i},j}}^s\rangle for the fully mobilized triangle, N = {row['N']} (forcenet; needs "
             r"\usepackage{booktabs})", r"\begin{tabular}{r" + "c" * i + "}", r"\toprule",
             r"$s \backslash j$ & " + " & ".join(str(j) for j in range(1, i + 1)) + r" \\", r"\midrule"]
    lines += [_line(k[6:] or "1", [_latex_value(x, digits) for x in row[k]]) for k in keys]
    lines += [r"\bottomrule", r"\end{tabular}"]
    return "\n".join(lines) + "\n"


def scientific(x: Fraction, digits: int = 7) -> str:
    """``x`` as ``m.mmmmmme+k`` with ``digits`` significant digits, from the exact value (no float underflow).

    Examples
    --------
    >>> scientific(Fraction(1, 7)), scientific(Fraction(2, 10**4000)), scientific(Fraction(0))
    ('1.428571e-1', '2.000000e-4000', '0')
    """
    x = Fraction(x)
    if x == 0:
        return "0"
    a = abs(x)
    e = (len(integer_text(a.numerator // a.denominator)) - 1 if a >= 1
         else -len(integer_text(a.denominator // a.numerator)))
    while a / Fraction(10) ** e >= 10:  # the length of the quotient may be one off: settle 1 <= a / 10^e < 10
        e += 1
    while a / Fraction(10) ** e < 1:
        e -= 1
    m = round(a / Fraction(10) ** e * 10 ** (digits - 1))
    if m >= 10**digits:  # rounded up to 10.000...
        m, e = m // 10, e + 1
    text = integer_text(m)
    sign = "-" if x < 0 else ""
    return f"{sign}{text[0]}.{text[1:]}e{e:+d}" if digits > 1 else f"{sign}{text}e{e:+d}"


def abbreviated(x: Fraction) -> str:
    """``x`` for a terminal: ``"1/7"`` when short, else its size (``forcenet table``'s files hold it exactly).

    Examples
    --------
    >>> abbreviated(Fraction(5, 14)), abbreviated(Fraction(10**30 + 1, 3 * 10**31))
    ('5/14', 'p/q of 31/32 digits')
    >>> abbreviated(Fraction(10**40))
    '1.000000e+40 (41 digits)'
    """
    text = fraction_str(x)
    if len(text) <= SHORT:
        return text
    if x.denominator == 1:
        return f"{scientific(x)} ({len(integer_text(abs(x.numerator)))} digits)"
    return f"p/q of {len(integer_text(abs(x.numerator)))}/{len(integer_text(x.denominator))} digits"


def from_json(text: str) -> tuple[int, dict[int, list[list[Fraction]]]]:
    """``(N, {s: rows})`` from the JSON of :meth:`~forcenet.Table.to_json` (``forcenet table``'s ``.json``).

    Raises
    ------
    ArgumentError
        Not such a JSON: not an object, ``N`` missing, a moment table of the wrong shape, a value not ``"p/q"``.

    Examples
    --------
    >>> from_json('{"N": 2, "count": "1", "normalization": "1", "mean_W": [["1"], ["1/2", "1/2"]]}')
    (2, {1: [[Fraction(1, 1)], [Fraction(1, 2), Fraction(1, 2)]]})
    """
    try:
        data = json.loads(text)
    except (TypeError, ValueError) as exc:
        raise ArgumentError(f"text is not JSON ({exc}): give the text of Table.to_json() or of forcenet table's "
                            ".json file") from None
    if not isinstance(data, dict) or "N" not in data or "mean_W" not in data or "row" in data:
        raise ArgumentError("text is not a whole table's JSON: expected an object with 'N' and 'mean_W' (one row's "
                            "JSON, with 'row', cannot make a Table)")
    N = check_int(data["N"], "N", 1)
    tables: dict[int, list[list[Fraction]]] = {}
    for key, rows in data.items():
        if not key.startswith("mean_W"):
            continue
        s = int(key[6:] or 1)
        if not isinstance(rows, list) or [len(r) if isinstance(r, list) else -1 for r in rows] != list(range(1, N + 1)):
            raise ArgumentError(f"{key}: expected {N} rows, row i of i values")
        tables[s] = [[fraction_from_text(str(v)) for v in row] for row in rows]
    return N, tables


def read(path: str | os.PathLike[str]) -> tuple[int, dict[int, list[list[Fraction]]]]:
    """``(N, {s: rows})`` from a saved table: ``forcenet table``'s ``.json`` or ``.csv`` file.

    Examples
    --------
    >>> import os, tempfile, forcenet
    >>> path = os.path.join(tempfile.mkdtemp(), "t.csv")
    >>> _ = open(path, "w").write(forcenet.table(3, moments=2).to_csv())
    >>> read(path)[1][2][2]
    [Fraction(1, 10), Fraction(3, 10), Fraction(1, 10)]
    """
    path = os.fspath(path)
    with open(path, encoding="utf-8") as handle:
        text = handle.read()
    if not path.endswith(".csv"):
        return from_json(text)
    lines = text.splitlines()
    head = lines[0].split(",") if lines else []
    if head[:3] != ["i", "j", "mean_W"]:
        raise ArgumentError(f"{path}: not forcenet's CSV (its first line must start 'i,j,mean_W')")
    keys = [int(k[6:] or 1) for k in head[2:]]
    cells = [line.split(",") for line in lines[1:] if line]
    N = max((int(c[0]) for c in cells), default=0)
    tables: dict[int, list[list[Fraction]]] = {s: [[Fraction(0)] * i for i in range(1, N + 1)] for s in keys}
    if len(cells) != N * (N + 1) // 2 or any(len(c) != len(head) for c in cells):
        raise ArgumentError(f"{path}: expected one line per grain (i, j), {len(head)} fields each")
    for c in cells:
        i, j = int(c[0]), int(c[1])
        for s, text_value in zip(keys, c[2:]):
            tables[s][i - 1][j - 1] = fraction_from_text(text_value)
    return N, tables


def to_pandas(tables: Mapping[int, Sequence[Sequence[Fraction]]], exact: bool = False) -> Any:
    """A :class:`pandas.DataFrame`: index ``(i, j)``, columns ``mean_W``, ``mean_W2``, ...

    Floats (correctly rounded) by default; ``exact=True`` keeps the
    :class:`~fractions.Fraction` objects (``object`` columns).

    Examples
    --------
    >>> import forcenet
    >>> frame = to_pandas({1: forcenet.table(3).mean_W})
    >>> frame.loc[(3, 2), "mean_W"]
    np.float64(0.5)
    """
    pd: Any = importlib.import_module("pandas")  # optional, and without type information: Any

    index = pd.MultiIndex.from_tuples([(i, j) for i, row in enumerate(tables[1], 1) for j in range(1, len(row) + 1)],
                                      names=["i", "j"])
    columns = {("mean_W" if s == 1 else f"mean_W{s}"): [x if exact else float(x) for row in rows for x in row]
               for s, rows in sorted(tables.items())}
    return pd.DataFrame(columns, index=index)
