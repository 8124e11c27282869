"""Reading the files users hand to cga: grammars, lots, rule tables (CSV) and their cells.

Tables come from spreadsheets and other machines: a UTF-8 byte-order mark, ``\\r\\n`` or
old Mac ``\\r`` line endings are all normal and read as plain text. What is not text —
bytes that are not UTF-8, a NUL or another control character inside a name — is refused
with the row and column, because such a name would end up in SVG, JSON and glTF files
that other programs must parse (issue 19). Sizes are bounded before parsing
(docs/limits.md).
"""

from __future__ import annotations

import os
from pathlib import Path

from .errors import (PATH_LIMIT, BudgetError, ResourceNotFoundError, RuleTableError,
                     UsageError, shown)
from .resources import is_regular_file

__all__ = ["MAX_TABLE_BYTES", "MAX_NAME_LENGTH", "read_input_bytes", "read_table_text",
           "control_character"]

MAX_TABLE_BYTES = 5_000_000
"""Largest rule table read (5 MB). The shipped tables have a few kilobytes."""


MAX_NAME_LENGTH = 100
"""Longest room type or furniture name in a table; names become file, node and label
text in every output."""


def read_input_bytes(path: str | Path, what: str, limit: int) -> bytes:
    """The bytes of an input file (``what``: "grammar", "lot file"), at most ``limit``.

    Raises
    ------
    ResourceNotFoundError
        Not a regular file: missing, a name the OS rejects (too long, a NUL byte) or a
        symbolic-link loop.
    UsageError
        The file cannot be read (no permission, ...).
    BudgetError
        The file has more than ``limit`` bytes.
    """
    name = shown(str(path), PATH_LIMIT)
    if not is_regular_file(path):
        raise ResourceNotFoundError(what, name, [shown(os.path.abspath(path), PATH_LIMIT)])
    try:
        with open(path, "rb") as file:
            data = file.read(limit + 1)
    except OSError as error:
        raise UsageError(f"{name}: cannot read the {what} ({error.strerror})") from None
    if len(data) > limit:
        raise BudgetError(f"{name}: the {what} has more than {limit:,} bytes; at most "
                          f"{limit:,} are read (docs/limits.md)")
    return data


def read_table_text(path: str | Path, *, hint: str = "save the table as UTF-8 CSV") -> str:
    """The text of a rule table: UTF-8 without a byte-order mark, lines ending in ``\\n``.

    Raises
    ------
    RuleTableError
        The file cannot be read or is not UTF-8 text (naming the line and byte).
    BudgetError
        The file is larger than :data:`MAX_TABLE_BYTES`.
    """
    file = str(path)
    try:
        size = Path(path).stat().st_size
        if size > MAX_TABLE_BYTES:
            raise BudgetError(f"{file}: the table has {size:,} bytes; at most "
                              f"{MAX_TABLE_BYTES:,} are read (docs/limits.md)")
        data = Path(path).read_bytes()
    except OSError as exc:
        raise RuleTableError(f"cannot read the file: {exc.strerror}", file=file) from None
    try:
        text = data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        line = data.count(b"\n", 0, exc.start) + 1
        raise RuleTableError(f"not UTF-8 text ({exc.reason} at byte {exc.start}); {hint}",
                             file=file, row=line) from None
    return text.replace("\r\n", "\n").replace("\r", "\n")


def control_character(text: str) -> str | None:
    """A description of the first control or other non-printable character in ``text``
    (``"U+0000 at character 4"``), or None when every character prints."""
    for index, char in enumerate(text, start=1):
        if not char.isprintable():
            return f"U+{ord(char):04X} at character {index}"
    return None
