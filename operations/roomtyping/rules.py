"""Room-typing rule tables: the thesis' semicolon CSV format, parsed and validated.

A table names one rule per row (docs/room_typing.md, thesis §5.2.1)::

    Type;Size;Prob;Neighbours;isOutsideConnected;appearance;additionRoom
    Kitchen;0.25;0.5;Livingroom;0;1;0
    Livingroom;1;1;Bathroom, Livingroom, Bedroom, Kitchen;true;1;0

The header row is required; its names are matched case-insensitively and give the column
order. Besides the thesis' seven columns, a table may add access columns (DESIGN §11;
each optional, so the thesis' tables work unchanged):

* ``maxSize``: the largest area (in the unit of ``Size``; empty: no limit);
* ``enteredFrom``: the types a room of this type may be entered from (comma list).
  When a table has this column, doors are cut only towards those types: adjacency
  alone makes no door, and ``Neighbours`` only says where the room is placed;
* ``passThrough``: whether other rooms may be reached through this one; false for
  private rooms, which is the default for types named like bedrooms and bathrooms
  (:func:`private_by_name`), true for the rest; a private room is the way into another
  room only when that room lists its type in ``enteredFrom`` (an en-suite bathroom);
* ``needsWindow``: the room must have a window (an outer wall on a floor without any;
  default false);
* ``circulation``: the type is a hall, corridor or landing (default false): it takes the
  corridors ``make_floor`` carves and is drawn as circulation.

Blank lines (also rows of bare semicolons, as spreadsheets export them) and lines
starting with ``#`` are ignored. A ``# units: m`` line above the header says ``Size`` and
``maxSize`` are m², whatever the grammar's ``units``; without it (the thesis' tables)
they are grammar units², scaled by ``units²`` (:mod:`cga.table_units`).
``Neighbours`` is a comma list; booleans accept 0/1/true/false in any case;
numbers may use a decimal comma (``0,25``), as German spreadsheets write them.

Everything the typing relies on is checked here, once, so the typing algorithm can trust
its input: every mistake raises :class:`~cga.errors.RuleTableError` naming the file, the
row (1-based line number) and the column, with a did-you-mean for misspelled names.
"""

from __future__ import annotations

import difflib
import math
from dataclasses import dataclass, replace
from functools import lru_cache
from pathlib import Path

from cga.errors import BudgetError, RuleTableError, excerpt
from cga.table_units import TableUnit, declared_unit, scale
from cga.textfiles import MAX_NAME_LENGTH, control_character, read_table_text

__all__ = [
    "COLUMNS",
    "ACCESS_COLUMNS",
    "DEFAULT_TYPE",
    "MAX_TYPE_RULES",
    "TypeRule",
    "RuleTable",
    "load_rule_table",
    "parse_rule_table",
    "private_by_name",
]

COLUMNS: tuple[str, ...] = (
    "Type", "Size", "Prob", "Neighbours", "isOutsideConnected", "appearance", "additionRoom",
)
"""The columns of a typing table, spelled as in the thesis."""

ACCESS_COLUMNS: tuple[str, ...] = (
    "maxSize", "enteredFrom", "passThrough", "needsWindow", "circulation",
)
"""Optional columns for access rules (DESIGN §11), in the order the docs list them."""

DEFAULT_TYPE = "Commonroom"
"""The type of rooms left over once every rule that could be placed has been placed."""

MAX_TYPE_RULES = 200
"""Most rules (room types) a typing table may have; the backtracker's work grows with
them (docs/limits.md)."""

PRIVATE_NAME_PARTS: tuple[str, ...] = ("bed", "bath", "toilet", "shower", "wc")
"""Parts of a type name (any case) that make its rooms private unless the table's
``passThrough`` says otherwise."""

_TRUE = frozenset({"1", "true"})
_FALSE = frozenset({"0", "false"})


@dataclass(frozen=True)
class TypeRule:
    """One row of a typing table.

    ``size`` is the minimum room area as written in the table, in the table's unit
    (:meth:`RuleTable.area_scale` converts it to m²). ``optional`` is the table's ``additionRoom``:
    mandatory rules (False) must all be placed; optional ones only fill rooms that remain.
    ``row`` is the rule's line in the file, for messages.
    """

    type: str
    size: float
    prob: float
    neighbours: tuple[str, ...]
    outside: bool
    appearance: int
    optional: bool
    row: int
    max_size: float | None = None
    entered_from: tuple[str, ...] | None = None
    pass_through: bool = True
    needs_window: bool = False
    circulation: bool = False

    def may_be_entered_from(self, other: str) -> bool:
        """Whether a door may lead into this room from a room of type ``other``:
        ``enteredFrom`` when the table has it (empty: from anywhere), else the
        thesis' rule (this rule lists ``other`` as a neighbour)."""
        if self.entered_from is None:
            return other in self.neighbours
        return not self.entered_from or other in self.entered_from

    @property
    def placement(self) -> tuple[str, ...]:
        """The types this room must adjoin to be placed: ``enteredFrom`` when given (a
        room must adjoin what it is entered from), else ``Neighbours``."""
        return self.entered_from if self.entered_from else self.neighbours


@dataclass(frozen=True)
class RuleTable:
    """The rules of one file, in file order."""

    file: str
    rules: tuple[TypeRule, ...]
    has_access: bool = False
    """True when the table has an ``enteredFrom`` column: doors follow access rules."""
    unit: TableUnit | None = None
    """The unit its ``# units:`` line declares (None: none, so grammar units)."""

    def area_scale(self, units: float) -> float:
        """m² per unit of ``Size``/``maxSize`` under a grammar of ``units`` metres per
        unit: 1 for a metre table, else ``units²``."""
        return scale(self.unit, units) ** 2

    @property
    def mandatory(self) -> tuple[TypeRule, ...]:
        return tuple(r for r in self.rules if not r.optional)

    @property
    def has_max_size(self) -> bool:
        """Whether any rule caps its rooms' area (``maxSize``)."""
        return any(r.max_size is not None for r in self.rules)

    @property
    def optional(self) -> tuple[TypeRule, ...]:
        return tuple(r for r in self.rules if r.optional)

    @property
    def outside_rule(self) -> TypeRule | None:
        """The rule whose room gets the front door, if the table has one."""
        return next((r for r in self.rules if r.outside), None)

    @property
    def circulation_rule(self) -> TypeRule | None:
        """The type carved corridors and halls get: the front-door rule when it is
        circulation, else the first circulation rule."""
        outside = self.outside_rule
        if outside is not None and outside.circulation:
            return outside
        return next((r for r in self.rules if r.circulation), None)

    def rule_for(self, type_name: str) -> TypeRule | None:
        """The rule defining ``type_name`` (None for the default type without a rule)."""
        return next((r for r in self.rules if r.type == type_name), None)


def load_rule_table(path: str | Path) -> RuleTable:
    """Read and parse a typing table from a file.

    Raises
    ------
    RuleTableError
        The file cannot be read as UTF-8 text, or its content is malformed
        (see :func:`parse_rule_table`).
    BudgetError
        The file is too large (:data:`cga.textfiles.MAX_TABLE_BYTES`).
    """
    return parse_rule_table(read_table_text(path), file=str(path))


@lru_cache(maxsize=16)
def parse_rule_table(text: str, *, file: str = "<rules>") -> RuleTable:
    """Parse the text of a typing table (each text once per process: a batch builds
    thousands of houses from one table, and the table is immutable).

    Parameters
    ----------
    text:
        The table: a header row naming the seven :data:`COLUMNS`, then one rule per row.
    file:
        The name used in error messages.

    Returns
    -------
    RuleTable
        The rules in file order; neighbour names spelled as the rule defining them.

    Raises
    ------
    RuleTableError
        A missing or unknown column, a row with too few cells, an empty type, a bad number
        or boolean, a type defined twice, a neighbour type that no rule defines (the
        default type ``Commonroom`` is always known), more than one ``isOutsideConnected``
        rule, an optional ``isOutsideConnected`` rule, or no mandatory rule.
    """
    unit = declared_unit(text, file=file)
    rows = [(number, line) for number, line in enumerate(text.splitlines(), start=1)
            if line.replace(";", "").strip() and not line.lstrip().startswith("#")]
    if not rows:
        raise RuleTableError("the table is empty; it needs a header row "
                             f"'{';'.join(COLUMNS)}' and at least one rule", file=file)
    if len(rows) > MAX_TYPE_RULES + 1:
        raise BudgetError(f"{file}: the table has {len(rows) - 1:,} rules; at most "
                          f"{MAX_TYPE_RULES:,} room types are allowed (docs/limits.md)")
    header_row, header_line = rows[0]
    order = _column_order(header_line, file=file, row=header_row)
    drafts = [_parse_row(line, order, file=file, row=number) for number, line in rows[1:]]
    if not drafts:
        raise RuleTableError("the table has a header but no rules", file=file)
    rules = _resolve_neighbours(drafts, file=file)
    _check_table(rules, file=file)
    return RuleTable(file=file, rules=rules, has_access="enteredFrom" in order, unit=unit)


def _cells(line: str) -> list[str]:
    return [cell.strip() for cell in line.split(";")]


def _column_order(line: str, *, file: str, row: int) -> list[str]:
    """The canonical column name of each header cell, checking that all are present."""
    canonical = {name.lower(): name for name in COLUMNS + ACCESS_COLUMNS}
    names = _cells(line)
    while names and not names[-1]:  # trailing empty cells from spreadsheet exports
        names.pop()
    order: list[str] = []
    for name in names:
        known = canonical.get(name.lower())
        if known is None:
            close = difflib.get_close_matches(name.lower(), canonical, n=1, cutoff=0.6)
            hint = f"; did you mean '{canonical[close[0]]}'?" if close else ""
            raise RuleTableError(f"unknown column {excerpt(name)} in the header{hint} The header "
                                 f"must be '{';'.join(COLUMNS)}', optionally with "
                                 f"{', '.join(ACCESS_COLUMNS)}", file=file, row=row,
                                 column=name)
        if known in order:
            raise RuleTableError(f"column '{known}' appears twice in the header",
                                 file=file, row=row, column=known)
        order.append(known)
    for name in COLUMNS:
        if name not in order:
            raise RuleTableError(f"missing column '{name}'; the header must name "
                                 f"'{';'.join(COLUMNS)}'", file=file, row=row, column=name)
    return order


def _parse_row(line: str, order: list[str], *, file: str, row: int) -> TypeRule:
    cells = _cells(line)
    while len(cells) < len(order) and order[len(cells)] in ACCESS_COLUMNS:
        cells.append("")  # spreadsheets drop empty trailing cells of optional columns
    if len(cells) < len(order):
        missing = order[len(cells)]
        raise RuleTableError(f"the row has {len(cells)} cells but the header has "
                             f"{len(order)}; '{missing}' is missing", file=file, row=row,
                             column=missing)
    if any(cells[len(order):]):
        raise RuleTableError(f"the row has more cells than the header's {len(order)} "
                             f"columns: {excerpt(';'.join(c for c in cells[len(order):] if c))}",
                             file=file, row=row)
    value = dict(zip(order, cells))

    def error(column: str, message: str) -> RuleTableError:
        return RuleTableError(message, file=file, row=row, column=column)

    for column in order:
        bad = control_character(value[column])
        if bad is not None:
            raise error(column, f"a control character ({bad}) in {excerpt(value[column])}; "
                                "names and values must be printable text")
    type_name = value["Type"]
    if not type_name:
        raise error("Type", "the room type is empty")
    if "," in type_name:
        raise error("Type", f"{excerpt(type_name)} is one type per row; a comma is not allowed")
    size = _number(value["Size"], error("Size", f"bad number {excerpt(value['Size'])}"))
    if size < 0:
        raise error("Size", f"Size is a minimum area and cannot be negative ({size:g})")
    prob = _number(value["Prob"], error("Prob", f"bad number {excerpt(value['Prob'])}"))
    if not 0.0 <= prob <= 1.0:
        raise error("Prob", f"Prob is a probability between 0 and 1, got {prob:g}")
    neighbours = tuple(dict.fromkeys(n.strip() for n in value["Neighbours"].split(",")
                                     if n.strip()))
    for column, name in [("Type", type_name), *(("Neighbours", n) for n in neighbours)]:
        if len(name) > MAX_NAME_LENGTH:
            raise error(column, f"the type name {excerpt(name)} is longer than "
                                f"{MAX_NAME_LENGTH} characters")
    if not neighbours:
        raise error("Neighbours", f"{type_name} lists no neighbour types; list at least "
                                  "one type this room may adjoin, separated by commas")
    outside = _boolean(value["isOutsideConnected"], error(
        "isOutsideConnected", f"unknown boolean {excerpt(value['isOutsideConnected'])}; use "
                              "0, 1, true or false"))
    optional = _boolean(value["additionRoom"], error(
        "additionRoom", f"unknown boolean {excerpt(value['additionRoom'])}; use 0 (mandatory), "
                        "1 (optional), true or false"))
    appearance = _count(value["appearance"], error(
        "appearance", f"appearance must be a whole number of rooms, got "
                      f"{excerpt(value['appearance'])}"))
    if appearance < 1 and not optional:
        raise error("appearance", f"{type_name} is mandatory (additionRoom=0) but "
                                  "appearance is 0; a mandatory type needs at least one room")

    def flag(column: str, default: bool) -> bool:
        if not value.get(column):
            return default
        return _boolean(value[column], error(column, f"unknown boolean {excerpt(value[column])}; "
                                                     "use 0, 1, true or false"))

    max_size = None
    if value.get("maxSize"):
        max_size = _number(value["maxSize"],
                           error("maxSize", f"bad number {excerpt(value['maxSize'])}"))
        if max_size < size:
            raise error("maxSize", f"maxSize {max_size:g} is below Size {size:g}; a room "
                                   "cannot be both")
    entered_from = None
    if "enteredFrom" in order:
        entered_from = tuple(dict.fromkeys(n.strip() for n in value["enteredFrom"].split(",")
                                           if n.strip()))
        for name in entered_from:
            if len(name) > MAX_NAME_LENGTH:
                raise error("enteredFrom", f"the type name {excerpt(name)} is longer than "
                                           f"{MAX_NAME_LENGTH} characters")
        if not entered_from and not (outside or flag("circulation", False)):
            raise error("enteredFrom", f"{type_name} lists no type it may be entered from; "
                                       "list at least one (e.g. Hall, Corridor); only the "
                                       "front-door room and circulation may leave it empty "
                                       "(entered from anywhere)")

    return TypeRule(type=type_name, size=size, prob=prob, neighbours=neighbours,
                    outside=outside, appearance=appearance, optional=optional, row=row,
                    max_size=max_size, entered_from=entered_from,
                    pass_through=flag("passThrough", not private_by_name(type_name)),
                    needs_window=flag("needsWindow", False),
                    circulation=flag("circulation", False))


def private_by_name(type_name: str) -> bool:
    """Whether rooms of this type are private when the table does not say: the name
    holds one of :data:`PRIVATE_NAME_PARTS` (Bedroom, MasterBedroom, Bathroom, WC). The
    thesis' tables have no ``passThrough`` column, yet their bedrooms and bathrooms must
    not become the only way into another room (DESIGN §11)."""
    name = type_name.lower()
    return any(part in name for part in PRIVATE_NAME_PARTS)


def _number(text: str, error: RuleTableError) -> float:
    candidate = text.replace(",", ".") if text.count(",") == 1 and "." not in text else text
    try:
        number = float(candidate)
    except ValueError:
        raise error from None
    if not math.isfinite(number):
        raise error
    return number


def _count(text: str, error: RuleTableError) -> int:
    number = _number(text, error)
    if number < 0 or number != int(number):
        raise error
    return int(number)


def _boolean(text: str, error: RuleTableError) -> bool:
    lowered = text.lower()
    if lowered in _TRUE:
        return True
    if lowered in _FALSE:
        return False
    raise error


def _resolve_neighbours(drafts: list[TypeRule], *, file: str) -> tuple[TypeRule, ...]:
    """Check type names are unique and spell every neighbour as its defining rule does."""
    defined: dict[str, TypeRule] = {}
    for rule in drafts:
        previous = defined.get(rule.type.lower())
        if previous is not None:
            raise RuleTableError(
                f"type {excerpt(rule.type)} is already defined in row {previous.row}; use "
                "'appearance' to allow several rooms of one type", file=file, row=rule.row,
                column="Type")
        defined[rule.type.lower()] = rule
    known = {name: rule.type for name, rule in defined.items()}
    known.setdefault(DEFAULT_TYPE.lower(), DEFAULT_TYPE)
    resolved = []
    for rule in drafts:
        resolved.append(replace(
            rule, neighbours=_spelled(rule.neighbours, known, rule, file, "Neighbours"),
            entered_from=(None if rule.entered_from is None else
                          _spelled(rule.entered_from, known, rule, file, "enteredFrom"))))
    return tuple(resolved)


def _spelled(names: tuple[str, ...], known: dict[str, str], rule: TypeRule, file: str,
             column: str) -> tuple[str, ...]:
    """The names as their rules spell them; an unknown name is an error at ``column``."""
    out = []
    for name in names:
        spelled = known.get(name.lower())
        if spelled is None:
            close = difflib.get_close_matches(name.lower(), known, n=1, cutoff=0.6)
            hint = f"; did you mean '{known[close[0]]}'?" if close else ""
            label = "neighbour" if column == "Neighbours" else "entered-from"
            raise RuleTableError(
                f"{label} type {excerpt(name)} is not defined by any rule{hint} "
                f"Known types: {', '.join(sorted(known.values()))}", file=file,
                row=rule.row, column=column)
        out.append(spelled)
    return tuple(dict.fromkeys(out))


def _check_table(rules: tuple[TypeRule, ...], *, file: str) -> None:
    outside = [r for r in rules if r.outside]
    if len(outside) > 1:
        raise RuleTableError(
            f"only one rule may set isOutsideConnected (the room with the front door); "
            f"both {outside[0].type} (row {outside[0].row}) and {outside[1].type} do",
            file=file, row=outside[1].row, column="isOutsideConnected")
    if outside and outside[0].optional:
        raise RuleTableError(
            f"{outside[0].type} gets the front door (isOutsideConnected) so it must be "
            "mandatory; set additionRoom to 0", file=file, row=outside[0].row,
            column="additionRoom")
    if not any(not r.optional for r in rules):
        raise RuleTableError("no mandatory rule: set additionRoom to 0 for at least one "
                             "type (the typing starts from a mandatory rule)", file=file,
                             column="additionRoom")
