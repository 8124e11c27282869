"""The room catalogue of the UvA generator: a semicolon CSV a user may replace.

The paper's catalogue (Zwennes 2011, Appendix A) lists the pre-made USARSim rooms with
their size in grid cells and a difficulty in [0, 10]; the shipped ``usar_rooms.csv`` is
that table, its ``Furniture`` column naming the room type of a furniture table
(``furniture_usar.csv``) that furnishes the room with our models::

    Name;Width;Depth;Difficulty;Furniture
    dark;1;1;0.5;Dark
    Maze2;6;6;9.5;BigMaze

``Width`` runs along x (columns), ``Depth`` along z (rows), both whole cells; the
``Furniture`` type becomes the room's type, so ``add_furniture`` finds its rows. Every
mistake raises :class:`~cga.errors.RuleTableError` naming the row and the column.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

from cga.errors import BudgetError, RuleTableError, excerpt
from cga.textfiles import MAX_NAME_LENGTH, control_character, read_table_text

__all__ = ["COLUMNS", "MAX_ROOMS", "MAX_CELLS", "CatalogueRoom", "load_catalogue",
           "parse_catalogue"]

COLUMNS: tuple[str, ...] = ("Name", "Width", "Depth", "Difficulty", "Furniture")

MAX_ROOMS = 500
"""Most rooms a catalogue may list."""

MAX_CELLS = 50
"""Largest room side, in cells."""


@dataclass(frozen=True)
class CatalogueRoom:
    """One pre-made room: ``width`` × ``depth`` cells, annotated ``difficulty``."""

    name: str
    width: int
    depth: int
    difficulty: float
    furniture: str
    row: int = 0


def load_catalogue(path: str | Path) -> tuple[CatalogueRoom, ...]:
    """Read and parse a catalogue file (see :func:`parse_catalogue`)."""
    return parse_catalogue(read_table_text(path), file=str(path))


def parse_catalogue(text: str, *, file: str = "<catalogue>") -> tuple[CatalogueRoom, ...]:
    """Parse a catalogue's text.

    Raises
    ------
    RuleTableError
        An empty table, a header that is not ``Name;Width;Depth;Difficulty;Furniture``
        (any case, any order), a row with the wrong number of cells, an empty or
        duplicate name, a size that is not a whole number from 1 to :data:`MAX_CELLS`, a
        difficulty that is not a number in [0, 10], an empty furniture type.
    BudgetError
        More than :data:`MAX_ROOMS` rooms.
    """
    rows = [(n, line) for n, line in enumerate(text.splitlines(), start=1)
            if line.replace(";", "").strip()]
    if not rows:
        raise RuleTableError(f"the catalogue is empty; it needs a header row "
                             f"'{';'.join(COLUMNS)}' and at least one room", file=file)
    if len(rows) - 1 > MAX_ROOMS:
        raise BudgetError(f"{file}: the catalogue lists {len(rows) - 1:,} rooms; at most "
                          f"{MAX_ROOMS:,} are allowed")
    header_row, header = rows[0]
    order = _header(header, file, header_row)
    rooms: list[CatalogueRoom] = []
    seen: dict[str, int] = {}
    for number, line in rows[1:]:
        room = _room(line, order, file, number)
        if room.name.lower() in seen:
            raise RuleTableError(f"room {excerpt(room.name)} is listed twice (first on row "
                                 f"{seen[room.name.lower()]})", file=file, row=number,
                                 column="Name")
        seen[room.name.lower()] = number
        rooms.append(room)
    if not rooms:
        raise RuleTableError("the catalogue has a header but no rooms", file=file)
    return tuple(rooms)


def _header(line: str, file: str, row: int) -> list[str]:
    canonical = {name.lower(): name for name in COLUMNS}
    names = [cell.strip() for cell in line.split(";")]
    while names and not names[-1]:
        names.pop()
    order = []
    for name in names:
        known = canonical.get(name.lower())
        if known is None or known in order:
            what = "appears twice" if known else "is not a catalogue column"
            raise RuleTableError(f"header cell {excerpt(name)} {what}; the header must name "
                                 f"{';'.join(COLUMNS)}", file=file, row=row, column=name)
        order.append(known)
    missing = [name for name in COLUMNS if name not in order]
    if missing:
        raise RuleTableError(f"missing column '{missing[0]}'; the header must name "
                             f"{';'.join(COLUMNS)}", file=file, row=row, column=missing[0])
    return order


def _room(line: str, order: list[str], file: str, row: int) -> CatalogueRoom:
    cells = [cell.strip() for cell in line.split(";")]
    while len(cells) > len(order) and not cells[-1]:
        cells.pop()
    if len(cells) != len(order):
        raise RuleTableError(f"the row has {len(cells)} cells but the header has {len(order)}",
                             file=file, row=row)
    value = dict(zip(order, cells))

    def error(column: str, message: str) -> RuleTableError:
        return RuleTableError(message, file=file, row=row, column=column)

    for column in ("Name", "Furniture"):
        text = value[column]
        if not text:
            raise error(column, f"the {column.lower()} is empty")
        if len(text) > MAX_NAME_LENGTH:
            raise error(column, f"longer than {MAX_NAME_LENGTH} characters")
        bad = control_character(text)
        if bad is not None:
            raise error(column, f"a control character ({bad}) in {excerpt(text)}")
    sizes = []
    for column in ("Width", "Depth"):
        try:
            size = float(value[column].replace(",", "."))
        except ValueError:
            size = math.nan
        if not (size.is_integer() and 1 <= size <= MAX_CELLS):
            raise error(column, f"{excerpt(value[column])} is not a whole number of cells "
                                f"from 1 to {MAX_CELLS}")
        sizes.append(int(size))
    try:
        difficulty = float(value["Difficulty"].replace(",", "."))
    except ValueError:
        difficulty = math.nan
    if not 0 <= difficulty <= 10:
        raise error("Difficulty", f"{excerpt(value['Difficulty'])} is not a number from 0 to 10")
    return CatalogueRoom(value["Name"], sizes[0], sizes[1], difficulty, value["Furniture"], row)
