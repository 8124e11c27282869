"""Reading the appearance tables (materials, lights): cells, numbers and ranges.

Both tables follow the project's CSV conventions (docs/appearance.md): delimiter ``;``
or ``,`` (sniffed from the header), header names in any case, an empty cell for "not
given", ``#`` starting a comment line. A range is ``lo..hi`` (or one number for a fixed
value). Every error is a :class:`~cga.errors.RuleTableError` naming the file, row and
column.
"""

from __future__ import annotations

import csv
import io
import math
from collections.abc import Iterator, Sequence
from dataclasses import dataclass

from cga.errors import RuleTableError, excerpt
from cga.textfiles import control_character

__all__ = ["MAX_ROWS", "Cells", "Range", "rows_of"]

MAX_ROWS = 1_000
"""Most rows an appearance table may have (docs/limits.md)."""


@dataclass(frozen=True)
class Range:
    """A closed interval ``lo..hi`` (``lo == hi`` for a fixed value)."""

    lo: float
    hi: float

    @property
    def mid(self) -> float:
        return (self.lo + self.hi) / 2

    def draw(self, rng: "object | None") -> float:
        """A uniform draw from ``rng`` (a numpy Generator), or the midpoint without one."""
        if rng is None or self.lo == self.hi:
            return self.mid
        return float(rng.uniform(self.lo, self.hi))  # type: ignore[attr-defined]


@dataclass(frozen=True)
class Cells:
    """One data row: its cells by (lower-case) column name, and where it is."""

    values: dict[str, str]
    file: str
    row: int

    def error(self, column: str, message: str) -> RuleTableError:
        return RuleTableError(message, file=self.file, row=self.row, column=column)

    def text(self, column: str, *, required: bool = False) -> str:
        value = self.values.get(column.lower(), "").strip()
        if required and not value:
            raise self.error(column, "the cell is empty")
        bad = control_character(value)
        if bad is not None:
            raise self.error(column, f"a control character ({bad}) in {excerpt(value)}")
        return value

    def names(self, column: str) -> tuple[str, ...]:
        """A ``;``/``|``-separated list of names (lower case), empty for "any"."""
        text = self.text(column).replace("|", ";")
        return tuple(sorted({n.strip().lower() for n in text.split(";") if n.strip()}))

    def number(self, column: str, lo: float, hi: float, default: float | None = None) -> float:
        text = self.text(column, required=default is None)
        if not text:
            assert default is not None
            return default
        value = self._float(column, text)
        if not lo <= value <= hi:
            raise self.error(column, f"expected a number in {lo:g}..{hi:g}, got {excerpt(text)}")
        return value

    def range(self, column: str, lo: float, hi: float, default: Range | None = None) -> Range:
        """``a..b`` or ``a`` within ``lo..hi``; empty gives ``default`` (required if None)."""
        text = self.text(column, required=default is None)
        if not text:
            assert default is not None
            return default
        parts = text.split("..")
        if len(parts) > 2:
            raise self.error(column, f"expected a number or a range lo..hi, got {excerpt(text)}")
        a, b = (self._float(column, p) for p in (parts if len(parts) == 2 else parts * 2))
        if not (lo <= a <= b <= hi):
            raise self.error(column, f"expected a range lo..hi with {lo:g} ≤ lo ≤ hi ≤ {hi:g}, "
                                     f"got {excerpt(text)}")
        return Range(a, b)

    def _float(self, column: str, text: str) -> float:
        try:
            value = float(text.strip())
        except ValueError:
            raise self.error(column, f"expected a number, got {excerpt(text)}") from None
        if not math.isfinite(value):
            raise self.error(column, f"expected a finite number, got {excerpt(text)}")
        return value


def rows_of(text: str, file: str, columns: Sequence[str], required: Sequence[str]
            ) -> Iterator[Cells]:
    """The data rows of a table whose header names ``columns`` (any case, any order).

    Raises
    ------
    RuleTableError
        An empty table, an unknown, repeated or missing column, a row with more cells
        than the header, or more than :data:`MAX_ROWS` rows.
    """
    lines = [(k, line) for k, line in enumerate(text.split("\n"), start=1)
             if line.strip() and not line.lstrip().startswith("#")]
    if not lines:
        raise RuleTableError(f"the table is empty; expected a header row: {';'.join(columns)}",
                             file=file)
    header_row, header = lines[0]
    delimiter = ";" if header.count(";") >= header.count(",") else ","
    names = [c.strip().lower() for c in _split(header, delimiter, file, header_row)]
    known = {c.lower() for c in columns}
    for name in names:
        if name not in known:
            raise RuleTableError(f"unknown column {excerpt(name)}; the columns are "
                                 f"{', '.join(columns)}", file=file, row=header_row, column=name)
        if names.count(name) > 1:
            raise RuleTableError("column given twice", file=file, row=header_row, column=name)
    for name in required:
        if name.lower() not in names:
            raise RuleTableError(f"missing column '{name}'", file=file, row=header_row)
    if len(lines) - 1 > MAX_ROWS:
        raise RuleTableError(f"{len(lines) - 1:,} rows; an appearance table may have at most "
                             f"{MAX_ROWS:,} (docs/limits.md)", file=file)
    for row, line in lines[1:]:
        cells = _split(line, delimiter, file, row)
        if len(cells) > len(names) and any(c.strip() for c in cells[len(names):]):
            raise RuleTableError(f"{len(cells)} cells but the header has {len(names)} columns",
                                 file=file, row=row)
        yield Cells(dict(zip(names, cells)), file, row)


def _split(line: str, delimiter: str, file: str, row: int) -> list[str]:
    try:
        return next(csv.reader(io.StringIO(line), delimiter=delimiter))
    except (csv.Error, StopIteration) as exc:
        raise RuleTableError(f"cannot split the row into cells ({exc})", file=file,
                             row=row) from None
