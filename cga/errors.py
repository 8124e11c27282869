"""The project's error tree.

Every failure caused by user input (a grammar, a rule table, a command-line option, a
missing file) is raised as a :class:`CGAError` subclass. The CLI prints ``str(error)``
and exits with status 2; no traceback reaches the user. Errors that point into a source
file carry a :class:`Span`; the source text is attached once, at the boundary
(:meth:`SourceError.with_source`), so nodes and operations only need to know where they
came from, not the whole text.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

__all__ = [
    "Span",
    "CGAError",
    "SourceError",
    "GrammarSyntaxError",
    "DerivationError",
    "RuleTableError",
    "NoSolutionError",
    "ResourceNotFoundError",
    "ResourceAccessError",
    "BudgetError",
    "UsageError",
    "ExportError",
    "EXCERPT_LIMIT",
    "PATH_LIMIT",
    "excerpt",
    "shown",
]

EXCERPT_LIMIT = 80
"""Most characters of user data (a CSV cell, a header line, a name) an error message quotes."""

PATH_LIMIT = 300
"""Most characters of a file path an error message shows (paths are longer than names)."""


def excerpt(text: str, limit: int = EXCERPT_LIMIT) -> str:
    """``text`` quoted for an error message: at most ``limit`` characters, control
    characters escaped (``\\x00``, ``\\n``), an ellipsis and the full length when cut.

    A message never carries more than a short, printable excerpt of a file, so a 10 MB
    header line or a binary file read as a table cannot flood a terminal or smuggle
    escape sequences into it (issue 19).
    """
    cut = text[:limit]
    shown = "".join(ch if ch.isprintable() or ch == " " else repr(ch)[1:-1] for ch in cut)
    if len(text) > limit:
        shown += f"… ({len(text):,} characters)"
    return f"'{shown}'"


def shown(text: str, limit: int = EXCERPT_LIMIT) -> str:
    """``text`` as is when it is at most ``limit`` characters and printable (a path, a
    name), else its :func:`excerpt`."""
    if len(text) <= limit and text.isprintable():
        return text
    return excerpt(text, limit)


@dataclass(frozen=True)
class Span:
    """A position in a source file: 1-based line and column, and the length to underline."""

    file: str
    line: int
    column: int
    length: int = 1

    def __str__(self) -> str:
        return f"{self.file}:{self.line}:{self.column}"


_LINE_WINDOW = 120
"""Most characters of a source line an error excerpt shows."""


class CGAError(Exception):
    """Base class of every error caused by user input.

    ``diagnostics`` are the warnings and notes the build gave before it failed (a
    derivation attaches them), so a cause found early ("made 4 rooms instead of 51")
    is not lost when a later step fails; :meth:`report` shows them after the message.
    :meth:`add_hint` appends a line that a caller knowing more context adds on the way
    out (e.g. that the lot's size may be in the wrong unit); it is printed after the
    message as ``hint: ...``.
    """

    diagnostics: tuple[Any, ...] = ()
    hints: tuple[str, ...] = ()

    def report(self) -> str:
        """The message, then the diagnostics given before the error, one per line."""
        if not self.diagnostics:
            return str(self)
        return (f"{self}\nbefore this error the build reported:"
                + "".join(f"\n  {d.level} {d}" for d in self.diagnostics))

    def add_hint(self, hint: str) -> "CGAError":
        self.hints = (*self.hints, hint)
        return self

    def _hint_lines(self) -> str:
        return "".join(f"\n  hint: {hint}" for hint in self.hints)

    def __str__(self) -> str:
        return super().__str__() + self._hint_lines()


class SourceError(CGAError):
    """An error that points at a place in a grammar file."""

    def __init__(self, message: str, span: Span | None = None, *, source: str | None = None,
                 hint: str | None = None):
        super().__init__(message)
        self.message = message
        self.span = span
        self.source = source
        self.hint = hint

    def with_source(self, source: str) -> "SourceError":
        """Attach the text of the file the span points into (once, at the API boundary)."""
        if self.source is None:
            self.source = source
        return self

    def __str__(self) -> str:
        if self.span is None:
            text = f"error: {self.message}"
        else:
            text = f"{self.span}: error: {self.message}"
            excerpt = self._excerpt()
            if excerpt:
                text += "\n" + excerpt
        if self.hint:
            text += f"\n  hint: {self.hint}"
        return text + self._hint_lines()

    def _excerpt(self) -> str:
        if self.source is None or self.span is None:
            return ""
        # Lines are counted at "\n" only, as the parser counts them (str.splitlines
        # would also split at form feeds and other separators and shift the excerpt).
        lines = self.source.split("\n")
        if not 1 <= self.span.line <= len(lines):
            return ""
        line = lines[self.span.line - 1].rstrip("\r").replace("\t", " ")
        caret_col = max(self.span.column, 1)
        if len(line) > _LINE_WINDOW:  # show a window around the caret, not a huge line
            start = max(0, min(caret_col - 1 - _LINE_WINDOW // 4, len(line) - _LINE_WINDOW))
            line = ("…" if start else "") + line[start:start + _LINE_WINDOW] + \
                ("…" if start + _LINE_WINDOW < len(line) else "")
            caret_col -= start - (1 if start else 0)
        line = "".join(ch if ch.isprintable() else "?" for ch in line)
        underline = "^" + "~" * max(0, min(self.span.length, len(line) - caret_col + 1) - 1)
        gutter = f"{self.span.line:>4} | "
        return f"{gutter}{line}\n{' ' * (len(gutter) + caret_col - 1)}{underline}"


class GrammarSyntaxError(SourceError):
    """The grammar text does not follow the language (docs/language.md)."""


class BudgetError(SourceError):
    """An input would exceed a documented limit (shapes, cells, rows, vertices, depth);
    raised before the work starts, with the numbers (docs/limits.md). Points into the
    grammar when a rule asked for the work."""


class DerivationError(SourceError):
    """A rule could not be applied: unknown operation, bad argument, recursion too deep."""


class RuleTableError(CGAError):
    """A CSV rule table is malformed; names the file, row and column."""

    def __init__(self, message: str, *, file: str, row: int | None = None,
                 column: str | None = None):
        where = shown(file, PATH_LIMIT)
        if row is not None:
            where += f", row {row}"
        if column is not None:
            where += f", column {excerpt(column)}"
        super().__init__(f"{where}: {message}")
        self.file = file
        self.row = row
        self.column = column


class NoSolutionError(CGAError):
    """A constraint problem (room typing, strict reachability) has no solution; says why."""

    def __init__(self, message: str, reasons: list[str] | None = None):
        self.reasons = list(reasons or [])
        text = message + "".join(f"\n  - {r}" for r in self.reasons)
        super().__init__(text)


class ResourceNotFoundError(CGAError):
    """A file named by the user (grammar, rule table, model, lot) does not exist."""

    def __init__(self, what: str, name: str, searched: list[str] | None = None):
        self.searched = list(searched or [])
        text = f"{what} not found: {name}"
        if self.searched:
            text += "\n  looked in:" + "".join(f"\n    {p}" for p in self.searched)
        super().__init__(text)


class ResourceAccessError(CGAError):
    """A file named by a grammar lies outside the folders a build may read (the sandbox)."""

    def __init__(self, message: str, *, path: str):
        super().__init__(message)
        self.path = path




class UsageError(CGAError):
    """A command-line option or API argument is invalid (e.g. a bad ``--lot``)."""


class ExportError(CGAError):
    """An output could not be written."""
