"""``--help`` as plain text: the module docstrings and option help without reStructuredText markup.

The subcommands' descriptions are their module docstrings, written for the API reference
(double backticks, ``:func:`` roles, simple tables). :class:`PlainFormatter` shows them as a
terminal reader expects: literals bare, roles as the name they point to, table rules
dropped, and each paragraph wrapped on its own (a table or a list keeps its lines).
"""

from __future__ import annotations

import argparse
import re
import textwrap

__all__ = ["plain", "PlainFormatter"]

_ROLE = re.compile(r":(?:func|class|mod|meth|attr|data|doc|ref|obj|exc):`~?([^`<]+?)(?:\s*<[^>]*>)?`")
_LITERAL = re.compile(r"``(.+?)``")
_RULE = re.compile(r"^\s*=+(\s+=+)*\s*$")
_KEEP_LINES = re.compile(r"^\s*([-*] |\S.*\S {2,}\S)")  # a list item, or a table row (a gap of 2+ spaces)


def plain(text: str | None) -> str | None:
    """``text`` without reST markup: ``x`` -> x, :func:`a.b` -> a.b, table rules removed."""
    if not text:
        return text
    text = _ROLE.sub(lambda m: m.group(1).strip(), text)
    text = _LITERAL.sub(r"\1", text)
    return "\n".join(line for line in text.splitlines() if not _RULE.match(line))


class PlainFormatter(argparse.HelpFormatter):
    """argparse's formatter with :func:`plain` text, wrapped paragraph by paragraph."""

    def _fill_text(self, text: str, width: int, indent: str) -> str:
        paragraphs = re.split(r"\n\s*\n", textwrap.dedent(plain(text) or "").strip())
        out = []
        for para in paragraphs:
            lines = para.splitlines()
            if len(lines) > 1 and all(_KEEP_LINES.match(line) for line in lines):
                out.append("\n".join(indent + line for line in lines))
            else:
                out.append(
                    textwrap.fill(
                        " ".join(para.split()), width, initial_indent=indent, subsequent_indent=indent
                    )
                )
        return "\n\n".join(out)

    def _expand_help(self, action: argparse.Action) -> str:
        return plain(super()._expand_help(action)) or ""
