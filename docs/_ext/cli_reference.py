"""The command-line reference, generated from the parser (``forcenet.cli.build_parser``) at build time.

Also ``forcenet-command-costs``: the command line page's list of commands with their costs, read from
``docs/_data/performance.json`` by :mod:`performance_data`.

The directive ``forcenet-cli`` renders, for every command the parser knows (the commands other modules add
appear by themselves), its one-line summary, its description, a table of its options (flags, values,
default, help as ``forcenet COMMAND --help`` prints it) and its epilog; then the top-level options and the
exit codes of ``forcenet --help``. Nothing is written by hand, so the page cannot drift from ``--help``.
"""

from __future__ import annotations

import argparse
import json
import re
from typing import Any

from docutils import nodes
from docutils.statemachine import StringList
from performance_data import DATA, command_cost_lines  # docs/_ext, on the path as this module is
from sphinx.application import Sphinx
from sphinx.util.docutils import SphinxDirective
from sphinx.util.nodes import nested_parse_with_titles


def _literal(text: str) -> str:
    """``text`` as an inline literal cell (backquotes escaped by splitting the literal)."""
    return "``" + text.replace("``", "`` ``") + "``" if text else ""


_OPTION = re.compile(r"(?<![\w-])(--?[A-Za-z][\w-]*)")


def _escape(text: str) -> str:
    """Plain text safe inside rST (no markup is read from a help string); options (``--N``) as literals, so
    that no typography turns their dashes into an en dash."""
    parts = _OPTION.split(text)
    out = []
    for k, part in enumerate(parts):
        if k % 2:
            out.append(_literal(part))
        else:
            out.append(part.replace("\\", "\\\\").replace("*", "\\*").replace("`", "\\`").replace("|", "\\|")
                       .replace("_", "\\_"))
    return _join(out)


def _join(out: list[str]) -> str:
    """Join text and literals; a literal glued to a word needs an escaped space to be recognized."""
    text = ""
    for piece in out:
        if piece.startswith("``") and text and not text[-1].isspace() and text[-1] not in "([{/'\"":
            text += "\\ "
        elif text.endswith("``") and piece and not piece[0].isspace() and piece[0] not in ".,;:)]}'\"/!?":
            text += "\\ "
        text += piece
    return text


def _flags(action: argparse.Action) -> str:
    """``--N N``, ``--format {json,csv,latex}``, ``--force``: the option as typed."""
    if action.nargs == 0:
        return ", ".join(action.option_strings)
    if action.choices is not None:
        value = "{" + ",".join(str(c) for c in action.choices) + "}"
    else:
        value = action.metavar or action.dest.upper()
        if isinstance(value, tuple):
            value = " ".join(value)
    return ", ".join(f"{o} {value}" for o in action.option_strings)


def _help(parser: argparse.ArgumentParser, action: argparse.Action) -> str:
    """The help string with its ``%(default)s`` expanded, as ``--help`` prints it."""
    if not action.help or action.help == argparse.SUPPRESS:
        return ""
    formatter = parser._get_formatter()
    return " ".join(formatter._expand_help(action).split())


def _options_table(parser: argparse.ArgumentParser) -> list[str]:
    rows = []
    for action in parser._actions:
        if isinstance(action, argparse._HelpAction) or action.help == argparse.SUPPRESS:
            continue
        if not action.option_strings:  # a positional argument
            name = action.metavar or action.dest
            rows.append((str(name), _help(parser, action)))
            continue
        rows.append((_flags(action), _help(parser, action)))
    if not rows:
        return []
    lines = [".. list-table::", "   :header-rows: 1", "   :widths: 30 70", "", "   * - option", "     - meaning"]
    for flags, text in rows:
        lines += [f"   * - {_literal(flags)}", f"     - {_escape(text) or ' '}"]
    return lines + [""]


def _block(text: str) -> list[str]:
    return ["::", "", *("   " + line for line in text.splitlines()), ""]


def reference_lines() -> list[str]:
    """The reference as rST lines (one section per command)."""
    from forcenet.cli import build_parser

    parser = build_parser()
    subactions = [a for a in parser._actions if isinstance(a, argparse._SubParsersAction)]
    lines: list[str] = []
    for sub in subactions:
        summaries = {a.dest: a.help for a in sub._choices_actions}
        for name, command in sub.choices.items():
            title = f"forcenet {name}"
            lines += [title, "~" * len(title), ""]
            if summaries.get(name):
                lines += [_escape(" ".join(str(summaries[name]).split())), ""]
            lines += _block(command.format_usage().strip())
            if command.description:
                lines += _block(command.description)
            lines += _options_table(command)
            if command.epilog:
                lines += _block(command.epilog)
    title = "Options of every command"
    lines += [title, "~" * len(title), ""]
    lines += _options_table(parser)
    title = "The exit codes, as forcenet --help prints them"
    lines += [title, "~" * len(title), ""]
    exit_codes = (parser.epilog or "").split("exit codes:", 1)
    if len(exit_codes) == 2:
        lines += _block("exit codes:" + exit_codes[1])
    return lines


class CommandLineReference(SphinxDirective):
    """``.. forcenet-cli::``: every command of the parser, with its options."""

    has_content = False

    def run(self) -> list[nodes.Node]:
        container = nodes.section()
        container.document = self.state.document
        nested_parse_with_titles(self.state, StringList(reference_lines(), source="forcenet.cli.build_parser"),
                                 container)
        return list(container.children)


class CommandCosts(SphinxDirective):
    """``.. forcenet-command-costs::``: every example command with its measured cost; with content, only the
    commands listed there (one a line, as written in the data file)."""

    has_content = True

    def run(self) -> list[nodes.Node]:
        self.env.note_dependency(str(DATA))
        only = [line.strip() for line in self.content if line.strip()] or None
        text = "\n".join(command_cost_lines(json.loads(DATA.read_text(encoding="utf-8")), only))
        block = nodes.literal_block(text, text)  # a node, not markup: the same in rST and MyST pages
        block["language"] = "bash"
        return [block]


def setup(app: Sphinx) -> dict[str, Any]:
    app.add_directive("forcenet-cli", CommandLineReference)
    app.add_directive("forcenet-command-costs", CommandCosts)
    return {"version": "1", "parallel_read_safe": True, "parallel_write_safe": True}
