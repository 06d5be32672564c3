"""The measured costs the pages quote, from ``docs/_data/performance.json`` (no Sphinx needed: conf.py uses it).

The file holds the performance page's tables (``dp``, ``pfaffian``) and the example commands with their
costs (``commands``); a cost written ``{pfaffian.table_seconds@64}`` in a command's comment is that cell of
the file, and conf.py's MyST substitutions (``{{ pfaffian_table_seconds_64 }}``) are every cell, so a
number lives in one place.
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

DATA = Path(__file__).resolve().parents[1] / "_data" / "performance.json"
_CELL = re.compile(r"\{(\w+)\.(\w+)@(\d+)\}")


def duration(seconds: float) -> str:
    """A measured time as the pages write it: ``2 s``, ``21 s``, ``1.6 min``, ``35 min``, ``1.2 h``.

    >>> [duration(s) for s in (2, 0.51, 2.5, 21, 95, 444, 2082, 4300)]
    ['2 s', '0.51 s', '2.5 s', '21 s', '1.6 min', '7.4 min', '35 min', '1.2 h']
    """
    if seconds < 10:
        return f"{seconds:.2g} s"
    if seconds < 90:
        return f"{seconds:.0f} s"
    if seconds < 3600:
        minutes = seconds / 60
        return f"{minutes:.1f} min" if minutes < 10 else f"{minutes:.0f} min"
    return f"{seconds / 3600:.1f} h"


def cell(data: dict[str, Any], table: str, column: str, N: int) -> str:
    """The cell ``column`` of the row ``N`` of ``data[table]``: a time (a ``*seconds`` column) or as written."""
    columns = data[table]["columns"]
    row = next((r for r in data[table]["rows"] if r[0] == N), None)
    if row is None or column not in columns:
        raise KeyError(f"performance.json has no {table}.{column} at N = {N}")
    value = row[columns.index(column)]
    return duration(value) if column.endswith("seconds") else str(value)


def performance_substitutions(data: dict[str, Any]) -> dict[str, str]:
    """``{"pfaffian_table_seconds_64": "1.6 min", ...}``: every cell of every table of ``data``, for MyST."""
    return {f"{table}_{column}_{row[0]}": cell(data, table, column, row[0])
            for table, part in data.items() if isinstance(part, dict) and table != "commands"
            for row in part["rows"] for column, value in zip(part["columns"][1:], row[1:]) if value is not None}


def command_cost_lines(data: dict[str, Any], only: list[str] | None = None) -> list[str]:
    """The commands with their costs, one a line (``command  # comment``), every ``{table.column@N}`` filled from
    ``data``; ``only``: just those commands, as written in the data."""
    rows = [(command, _CELL.sub(lambda m: cell(data, m[1], m[2], int(m[3])), comment))
            for command, comment in data["commands"]["rows"] if only is None or command in only]
    missing = set(only or ()) - {command for command, _ in rows}
    if missing:
        raise KeyError(f"performance.json lists no command {sorted(missing)}")
    width = min(48, max(len(command) for command, _ in rows))
    return [f"{command.ljust(width)}  # {comment}" for command, comment in rows]
