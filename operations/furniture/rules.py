"""Furniture rule tables: the 17-column CSV of the thesis, parsed and checked.

A rule places one item in every room of its type (docs/furniture.md, thesis §5.3.1)::

    Room;Name;isInCorner;isAlongWall;hasPair;PairWith;minPairDistance;maxPairDistance;needsTurn;
    clearanceSide;clearanceFront;clearanceBack;canCloseWindow;canBeAround;nonCollision;isDetail;isOnTheSide

The parser accepts the table as the thesis prints it: delimiter ``;``, ``,`` or tab
(sniffed from the header), ``<null>`` for an empty cell, header names in any case and in
the thesis' spellings (``hasPaar``, ``PaarWith``, ``needInTurn``, ...), a leading
``Regel`` column of row numbers, trailing empty columns. Missing columns take their
default (false / 0); unknown columns are errors, so a misspelt header never silently
turns a rule off.

Meaning of the columns beyond the thesis' own words:

* ``Name`` names the item and its model; a numeric suffix repeats a model (``chair1``
  uses ``chair``) unless a model of the full name exists.
* A row with ``PairWith`` is a *child* of the rule it names (matched case-insensitively
  within the same room type); ``hasPair`` without ``PairWith`` marks a parent, as in the
  thesis.
* ``maxPairDistance`` 0 (or empty) means no upper bound.
* ``needsTurn`` (never explained in the thesis): the item stands with a *side* against
  its wall instead of its back (a bed with its long side on the wall).
* Distances are in grammar units, or in metres when a ``# units: m`` line stands above
  the header (:mod:`cga.table_units`); :meth:`FurnitureRules.scaled` converts them to
  metres. Other lines starting with ``#`` are comments.

Optional columns beyond the thesis: ``sizeJitter`` (one fraction, or three for width,
height and depth, by which each placed item's extents vary; :mod:`.variation`) and
``isMovable`` (whether disorder may move the item; empty: the chairs; :mod:`.disorder`)
``layout`` (``perimeter``: as many copies of the item as fit along the walls, each
with its children; :mod:`.desks`) and ``disorder`` (0..1 for the row's items, instead of
the build's ``disorder``).

Errors are :class:`~cga.errors.RuleTableError` naming the file, row and column.
"""

from __future__ import annotations

import csv
import difflib
import io
import re
from collections.abc import Iterator
from dataclasses import dataclass, fields, replace
from pathlib import Path

from cga.errors import BudgetError, RuleTableError, excerpt
from cga.table_units import TableUnit, declared_unit, scale
from cga.textfiles import MAX_NAME_LENGTH, control_character, read_table_text

__all__ = ["MAX_FURNITURE_ROWS", "MAX_SIZE_JITTER", "FurnitureRule", "FurnitureRules", "parse_furniture_rules",
           "load_furniture_rules"]

MAX_FURNITURE_ROWS = 1_000
"""Most rows a furniture table may have (docs/limits.md). The shipped tables have about
a hundred; every row is an item to place in each room of its type."""

_NULL = {"", "<null>", "null", "none"}
_TRUE = {"true", "1", "yes", "y", "wahr"}
_FALSE = {"false", "0", "no", "n", "falsch"} | _NULL

# canonical field → accepted header spellings (lower case)
_COLUMNS: dict[str, tuple[str, ...]] = {
    "room": ("room", "roomtype"),
    "name": ("name",),
    "is_in_corner": ("isincorner",),
    "is_along_wall": ("isalongwall", "isallongwall"),
    "has_pair": ("haspair", "haspaar", "haspillar"),
    "pair_with": ("pairwith", "paarwith"),
    "min_pair_distance": ("minpairdistance", "minpaardistance"),
    "max_pair_distance": ("maxpairdistance", "maxpaardistance"),
    "needs_turn": ("needsturn", "needinturn", "needsinturn", "needturn", "needsinitium"),
    "clearance_side": ("clearanceside",),
    "clearance_front": ("clearancefront",),
    "clearance_back": ("clearanceback",),
    "can_close_window": ("canclosewindow",),
    "can_be_around": ("canbearound",),
    "non_collision": ("noncollision",),
    "is_detail": ("isdetail",),
    "is_on_the_side": ("isontheside",),
    "size_jitter": ("sizejitter",),
    "is_movable": ("ismovable", "movable"),
    "layout": ("layout",),
    "disorder": ("disorder",),
}
_HEADER_TO_FIELD = {alias: key for key, aliases in _COLUMNS.items() for alias in aliases}
_ROW_NUMBER_COLUMNS = {"regel", "rule", "item", "#", "no", "nr"}
_DISTANCES = ("min_pair_distance", "max_pair_distance", "clearance_side", "clearance_front",
              "clearance_back")
_DETAIL_KINDS = ("door", "window")
_LAYOUTS = ("perimeter",)
MAX_SIZE_JITTER = 0.5
"""Largest ``sizeJitter`` fraction: an extent may vary by at most half of itself."""
_MOVABLE_MODELS = re.compile(r"chair$")
"""Models movable by default (``isMovable`` empty): the chairs, which the TFG's
disorder moves (§3.4)."""


@dataclass(frozen=True)
class FurnitureRule:
    """One row of a furniture table. Distances are in the table's units (see
    :meth:`FurnitureRules.scaled`); ``row`` is the 1-based line in the file."""

    room: str
    name: str
    row: int = 0
    is_in_corner: bool = False
    is_along_wall: bool = False
    has_pair: bool = False
    pair_with: str | None = None
    min_pair_distance: float = 0.0
    max_pair_distance: float = 0.0
    needs_turn: bool = False
    clearance_side: float = 0.0
    clearance_front: float = 0.0
    clearance_back: float = 0.0
    can_close_window: bool = False
    can_be_around: bool = False
    non_collision: bool = False
    is_detail: bool = False
    is_on_the_side: bool = False
    size_jitter: tuple[float, float, float] = (0.0, 0.0, 0.0)
    is_movable: bool | None = None
    layout: str = ""
    disorder: float | None = None

    @property
    def is_child(self) -> bool:
        """True for a rule placed relative to the rule named in ``pair_with``."""
        return self.pair_with is not None

    @property
    def max_gap(self) -> float | None:
        """The upper pair distance, or None when unbounded (0 in the table)."""
        return self.max_pair_distance if self.max_pair_distance > 0 else None

    @property
    def detail_kind(self) -> str | None:
        """``"door"`` or ``"window"`` for a detail row, else None."""
        if not self.is_detail:
            return None
        lowered = self.name.lower()
        return next((kind for kind in _DETAIL_KINDS if kind in lowered), None)

    def movable(self, model: str) -> bool:
        """Whether disorder may move the item: ``isMovable`` when given, else whether its
        model (canonical name) is a chair."""
        if self.is_movable is not None:
            return self.is_movable
        return bool(_MOVABLE_MODELS.search(model))

    def model_candidates(self) -> tuple[str, ...]:
        """Model names to look up, best first: the full name, then without a numeric suffix."""
        base = re.sub(r"\d+$", "", self.name)
        return (self.name,) if base in ("", self.name) else (self.name, base)


@dataclass(frozen=True)
class FurnitureRules:
    """The rules of one table, in table order, and the file they came from."""

    rules: tuple[FurnitureRule, ...]
    file: str = "<rules>"
    unit: TableUnit | None = None
    """The unit its ``# units:`` line declares (None: none, so grammar units)."""

    def __iter__(self) -> Iterator[FurnitureRule]:
        return iter(self.rules)

    def __len__(self) -> int:
        return len(self.rules)

    def room_types(self) -> list[str]:
        """Room types named by the table, in first-appearance order."""
        return list(dict.fromkeys(r.room for r in self.rules))

    def for_room(self, room_type: str) -> list[FurnitureRule]:
        """The placeable (non-detail) rules of a room type in placement order.

        Table order, except that a child whose parent appears later in the table is moved
        right after it (the thesis skipped such children). Matching is case-insensitive.
        """
        mine = [r for r in self.rules if r.room.lower() == room_type.lower() and not r.is_detail]
        ordered: list[FurnitureRule] = []
        emitted: set[str] = set()
        waiting: dict[str, list[FurnitureRule]] = {}

        def emit(rule: FurnitureRule) -> None:
            ordered.append(rule)
            emitted.add(rule.name)
            for child in waiting.pop(rule.name, []):
                emit(child)

        for rule in mine:
            if rule.pair_with is None or rule.pair_with in emitted:
                emit(rule)
            else:
                waiting.setdefault(rule.pair_with, []).append(rule)
        return ordered

    def details(self, room_type: str | None) -> list[FurnitureRule]:
        """The detail (door/window) rules of a room type."""
        if room_type is None:
            return []
        return [r for r in self.rules if r.is_detail and r.room.lower() == room_type.lower()]

    def scaled(self, units: float) -> "FurnitureRules":
        """A copy with every distance in metres under a grammar of ``units`` metres per
        unit: multiplied by ``units`` unless the table is in metres."""
        factor = scale(self.unit, units)
        if factor == 1:
            return self
        return replace(self, rules=tuple(
            replace(r, **{k: getattr(r, k) * factor for k in _DISTANCES}) for r in self.rules))


def load_furniture_rules(path: str | Path) -> FurnitureRules:
    """Read and check a furniture rule table.

    Parameters
    ----------
    path:
        The CSV file (UTF-8, a BOM is accepted).

    Returns
    -------
    FurnitureRules
        The rules in table order, distances in the table's units.

    Raises
    ------
    RuleTableError
        Malformed table, naming the file, row and column.
    BudgetError
        More than :data:`MAX_FURNITURE_ROWS` rows, or a file larger than
        :data:`cga.textfiles.MAX_TABLE_BYTES`.
    """
    return parse_furniture_rules(read_table_text(path), file=str(path))


def parse_furniture_rules(text: str, *, file: str = "<rules>") -> FurnitureRules:
    """Parse the text of a furniture table; see :func:`load_furniture_rules`."""
    lines = [(n, line) for n, line in enumerate(text.splitlines(), start=1)
             if line.strip() and not line.lstrip().startswith("#")]
    if not lines:
        raise RuleTableError("the table is empty; expected a header row "
                             "'Room;Name;isInCorner;...'", file=file)
    if len(lines) > MAX_FURNITURE_ROWS + 1:
        raise BudgetError(f"{file}: the table has {len(lines) - 1:,} rows; at most "
                          f"{MAX_FURNITURE_ROWS:,} are allowed (docs/limits.md)")
    header_row, header_line = lines[0]
    delimiter = _sniff_delimiter(header_line)
    columns = _header_columns(_split(header_line, delimiter, file, header_row), file,
                              header_row)
    rules: list[FurnitureRule] = []
    decimal_comma = delimiter != ","
    for row, line in lines[1:]:
        cells = _split(line, delimiter, file, row)
        if len(cells) > len(columns) and any(c.strip() for c in cells[len(columns):]):
            raise RuleTableError(f"{len(cells)} cells but the header has {len(columns)} columns",
                                 file=file, row=row)
        values: dict[str, object] = {}
        for (header, key), cell in zip(columns, cells):
            if key is not None:
                values[key] = _convert(key, cell.strip(), decimal_comma, file, row, header)
        for key in ("room", "name", "pair_with"):
            _check_name(values.get(key), key, file, row)
        for key in ("room", "name"):
            if not values.get(key):
                raise RuleTableError(f"the {key} cell is empty", file=file, row=row,
                                     column=_COLUMNS[key][0].capitalize())
        rules.append(FurnitureRule(row=row, **values))  # type: ignore[arg-type]
    checked = _check_rules(rules, file)
    return FurnitureRules(tuple(checked), file, unit=declared_unit(text, file=file))


def _split(line: str, delimiter: str, file: str, row: int) -> list[str]:
    """The cells of one line (quotes as in CSV)."""
    try:
        return next(csv.reader(io.StringIO(line), delimiter=delimiter))
    except csv.Error as exc:  # a cell over the csv module's field limit (131,072)
        raise RuleTableError(f"cannot split the row into cells ({exc})", file=file,
                             row=row) from None


def _check_name(value: object, key: str, file: str, row: int) -> None:
    """A room type or item name: printable and at most MAX_NAME_LENGTH characters."""
    if not isinstance(value, str):
        return
    column = _pretty(key)
    bad = control_character(value)
    if bad is not None:
        raise RuleTableError(f"a control character ({bad}) in {excerpt(value)}; names must be "
                             f"printable text", file=file, row=row, column=column)
    if len(value) > MAX_NAME_LENGTH:
        raise RuleTableError(f"the name {excerpt(value)} is longer than {MAX_NAME_LENGTH} "
                             f"characters", file=file, row=row, column=column)


def _sniff_delimiter(header: str) -> str:
    counts = {d: header.count(d) for d in (";", "\t", ",")}
    delimiter = max(counts, key=lambda d: counts[d])
    return delimiter if counts[delimiter] else ";"


def _header_columns(cells: list[str], file: str, row: int) -> list[tuple[str, str | None]]:
    """(header text, field or None for an ignored column) per column."""
    names = [c.strip() for c in cells]
    while names and not names[-1]:
        names.pop()
    columns: list[tuple[str, str | None]] = []
    seen: dict[str, str] = {}
    for index, name in enumerate(names):
        key = _HEADER_TO_FIELD.get(name.lower())
        if key is None:
            if index == 0 and name.lower() in _ROW_NUMBER_COLUMNS:
                columns.append((name, None))
                continue
            close = difflib.get_close_matches(name.lower(), list(_HEADER_TO_FIELD), n=1)
            hint = (f"; did you mean '{_pretty(_HEADER_TO_FIELD[close[0]])}'?" if close
                    else f"; known columns: {', '.join(_pretty(k) for k in _COLUMNS)}")
            raise RuleTableError(f"unknown column {excerpt(name)}{hint}", file=file, row=row,
                                 column=name or f"#{index + 1}")
        if key in seen:
            raise RuleTableError(f"column given twice ({excerpt(seen[key])} and "
                                 f"{excerpt(name)})", file=file,
                                 row=row, column=name)
        seen[key] = name
        columns.append((name, key))
    for key in ("room", "name"):
        if key not in seen:
            raise RuleTableError(f"missing column '{_pretty(key)}'", file=file, row=row)
    return columns


def _pretty(key: str) -> str:
    """Canonical header spelling of a field, e.g. ``is_in_corner`` → ``isInCorner``."""
    special = {"room": "Room", "name": "Name", "pair_with": "PairWith"}
    if key in special:
        return special[key]
    head, *rest = key.split("_")
    return head + "".join(part.capitalize() for part in rest)


_FIELD_TYPES = {f.name: f.type for f in fields(FurnitureRule)}


def _convert(key: str, cell: str, decimal_comma: bool, file: str, row: int,
             header: str) -> object:
    kind = _FIELD_TYPES[key]
    lowered = cell.lower()
    if key == "size_jitter":
        return _size_jitter(cell, decimal_comma, file, row, header)
    if key == "layout":
        if lowered in _NULL:
            return ""
        if lowered not in _LAYOUTS:
            raise RuleTableError(f"unknown layout {excerpt(cell)}; expected "
                                 f"{' or '.join(map(repr, _LAYOUTS))} or an empty cell",
                                 file=file, row=row, column=header)
        return lowered
    if key == "disorder":
        if lowered in _NULL:
            return None
        value = _number(cell, decimal_comma, file, row, header, "a disorder")
        if value > 1:
            raise RuleTableError(f"disorder is a number in 0..1, got {excerpt(cell)}",
                                 file=file, row=row, column=header)
        return value
    if kind == "bool | None":
        if lowered in _NULL:
            return None
        kind = "bool"
    if kind == "bool":
        if lowered in _TRUE:
            return True
        if lowered in _FALSE:
            return False
        raise RuleTableError(f"expected true/false (or 1/0), got {excerpt(cell)}", file=file, row=row,
                             column=header)
    if kind == "float":
        return 0.0 if lowered in _NULL else _number(cell, decimal_comma, file, row, header)
    if key == "pair_with":
        return None if lowered in _NULL else cell
    return "" if lowered in _NULL else cell


def _number(cell: str, decimal_comma: bool, file: str, row: int, header: str,
            what: str = "a distance") -> float:
    """A finite number ≥ 0 (a decimal comma when the delimiter is not a comma)."""
    text = cell.replace(",", ".") if decimal_comma else cell
    try:
        value = float(text)
    except ValueError:
        raise RuleTableError(f"expected a number, got {excerpt(cell)}", file=file, row=row,
                             column=header) from None
    if value < 0 or value != value or value == float("inf"):
        raise RuleTableError(f"expected {what} ≥ 0, got {excerpt(cell)}", file=file, row=row,
                             column=header)
    return value


def _size_jitter(cell: str, decimal_comma: bool, file: str, row: int, header: str
                 ) -> tuple[float, float, float]:
    """``sizeJitter``: one fraction for all three extents, or three (width height
    depth) separated by spaces, each in [0, :data:`MAX_SIZE_JITTER`]."""
    words = [] if cell.lower() in _NULL else cell.split()
    if len(words) not in (0, 1, 3):
        raise RuleTableError(f"sizeJitter takes one fraction or three (width height depth), "
                             f"got {excerpt(cell)}", file=file, row=row, column=header)
    values = []
    for word in words:
        text = word.replace(",", ".") if decimal_comma else word
        try:
            value = float(text)
        except ValueError:
            raise RuleTableError(f"expected a fraction, got {excerpt(word)}", file=file,
                                 row=row, column=header) from None
        if not 0 <= value <= MAX_SIZE_JITTER:
            raise RuleTableError(f"a size jitter is a fraction of the extent in 0..{MAX_SIZE_JITTER:g} "
                                 f"(0.1 = ±10 %), got {excerpt(word)}", file=file, row=row,
                                 column=header)
        values.append(value)
    if not values:
        return (0.0, 0.0, 0.0)
    if len(values) == 1:
        return (values[0], values[0], values[0])
    return (values[0], values[1], values[2])


def _check_rules(rules: list[FurnitureRule], file: str) -> list[FurnitureRule]:
    """Cross-row checks; returns the rules with ``pair_with`` set to the parent's exact name."""
    by_room: dict[str, dict[str, FurnitureRule]] = {}
    for rule in rules:
        names = by_room.setdefault(rule.room.lower(), {})
        if rule.name.lower() in names:
            first = names[rule.name.lower()]
            raise RuleTableError(f"item '{rule.name}' appears twice for room type {rule.room} "
                                 f"(first in row {first.row}); give repeats a numeric suffix "
                                 f"({rule.name}1)", file=file, row=rule.row, column="Name")
        names[rule.name.lower()] = rule
    checked = []
    for rule in rules:
        _check_flags(rule, file)
        if rule.pair_with is not None:
            parent = by_room[rule.room.lower()].get(rule.pair_with.lower())
            if parent is None:
                known = ", ".join(r.name for r in by_room[rule.room.lower()].values()
                                  if r is not rule and not r.is_detail)
                raise RuleTableError(
                    f"PairWith '{rule.pair_with}' names no item of room type {rule.room}"
                    f" (items: {known or 'none'})", file=file, row=rule.row, column="PairWith")
            if parent.is_detail:
                raise RuleTableError(f"PairWith '{rule.pair_with}' is a detail row (door or "
                                     f"window), not furniture", file=file, row=rule.row,
                                     column="PairWith")
            rule = replace(rule, pair_with=parent.name)
        checked.append(rule)
    _check_cycles(checked, file)
    return checked


def _check_flags(rule: FurnitureRule, file: str) -> None:
    def fail(message: str, column: str) -> None:
        raise RuleTableError(message, file=file, row=rule.row, column=column)

    if rule.is_detail:
        if rule.detail_kind is None:
            fail(f"detail rows name the door or window model; '{rule.name}' names neither",
                 "Name")
        return
    if rule.is_in_corner and rule.is_along_wall:
        fail("isInCorner and isAlongWall are both true; choose one", "isAlongWall")
    if rule.pair_with is not None and not rule.has_pair:
        fail(f"PairWith '{rule.pair_with}' is given but hasPair is false", "hasPair")
    if rule.pair_with is not None and rule.is_in_corner:
        fail("a child (PairWith) is placed relative to its parent and cannot also be "
             "isInCorner", "isInCorner")
    if rule.can_be_around and rule.is_on_the_side:
        fail("canBeAround and isOnTheSide are both true; choose one", "isOnTheSide")
    for flag, column in ((rule.can_be_around, "canBeAround"), (rule.is_on_the_side,
                                                                "isOnTheSide")):
        if flag and rule.pair_with is None:
            fail(f"{column} needs a parent in PairWith", column)
    if rule.layout == "perimeter" and (rule.pair_with is not None or rule.is_in_corner
                                       or rule.non_collision):
        fail("layout 'perimeter' lays out as many copies of a free parent as fit along the "
             "walls; it cannot be a child (PairWith), a corner item or non-colliding",
             "layout")
    if rule.max_gap is not None and rule.max_pair_distance < rule.min_pair_distance:
        fail(f"maxPairDistance {rule.max_pair_distance:g} is below minPairDistance "
             f"{rule.min_pair_distance:g}", "maxPairDistance")


def _check_cycles(rules: list[FurnitureRule], file: str) -> None:
    parents = {(r.room.lower(), r.name): r for r in rules}
    for rule in rules:
        seen = [rule.name]
        current = rule
        while current.pair_with is not None:
            current = parents[(rule.room.lower(), current.pair_with)]
            if current.name in seen:
                chain = " → ".join(seen + [current.name])
                raise RuleTableError(f"PairWith forms a cycle: {chain}", file=file,
                                     row=rule.row, column="PairWith")
            seen.append(current.name)
