"""Source positions: lark's tokens, metas and character offsets as :class:`~cga.errors.Span` s.

Shared by the tree → AST step (:mod:`cga.ast_builder`) and the syntax-error wording
(:mod:`cga.syntax_errors`), so both point at the same characters.
"""

from __future__ import annotations

import bisect
import re

from lark import Token

from .errors import Span

__all__ = ["Locator", "start_of", "end_of"]


def start_of(token: Token) -> tuple[int, int]:
    """``(line, column)`` where a lexed token starts (lark types positions as optional:
    only hand-made tokens lack them)."""
    if token.line is None or token.column is None:
        raise ValueError(f"token {token!r} has no position")
    return token.line, token.column


def end_of(token: Token) -> tuple[int, int]:
    """``(line, column)`` just after a lexed token."""
    if token.end_line is None or token.end_column is None:
        raise ValueError(f"token {token!r} has no position")
    return token.end_line, token.end_column


class Locator:
    """Turns lark positions (tokens, metas, character offsets) into :class:`Span` s."""

    def __init__(self, text: str, file: str):
        self.text = text
        self.file = file
        self._line_starts = [0] + [m.end() for m in re.finditer("\n", text)]

    def offset(self, line: int, column: int) -> int:
        return self._line_starts[line - 1] + column - 1

    def at_offset(self, offset: int, length: int = 1) -> Span:
        line = bisect.bisect_right(self._line_starts, offset)
        column = offset - self._line_starts[line - 1] + 1
        return Span(self.file, line, column, max(1, length))

    def token(self, token: Token) -> Span:
        return Span(self.file, *start_of(token), max(1, len(token)))

    def meta(self, meta) -> Span:
        return Span(self.file, meta.line, meta.column, max(1, meta.end_pos - meta.start_pos))

    def join(self, first: Span, last: Span) -> Span:
        """The span from the start of ``first`` to the end of ``last``."""
        start = self.offset(first.line, first.column)
        end = self.offset(last.line, last.column) + last.length
        return Span(self.file, first.line, first.column, max(1, end - start))

    def first_on_line(self, line: int, column: int) -> bool:
        """Whether only whitespace precedes this position on its line."""
        start = self._line_starts[line - 1]
        return self.text[start:start + column - 1].strip() == ""

    def rest_of_line(self, line: int, column: int) -> int:
        start = self.offset(line, column)
        end = self.text.find("\n", start)
        return (len(self.text) if end < 0 else end) - start
