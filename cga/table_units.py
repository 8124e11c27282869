"""The unit a rule table's sizes are written in, declared by the table itself.

A grammar's ``units`` (metres per grammar unit) scales every length the grammar writes.
Rule tables are separate files, often shared between grammars: the project's own tables
are in metres and must stay metres under any ``units``, while the thesis' tables were
written for its 1:10 grammars and are in grammar units. A table says which by a comment
line before its header (docs/room_typing.md, "Units")::

    # units: m
    Type;Size;Prob;...

``# units: m`` (also ``metres``/``meters``): sizes are metres (areas m²), whatever the
grammar's ``units``. ``# units: grammar``: sizes are grammar units (areas grammar
units²), multiplied by ``units`` (``units²``). A table without the line is in grammar
units, as the thesis' tables are; a build under ``units`` ≠ 1 says so in its
diagnostics, and a typing that fails while the sizes look scaled by mistake says how to
fix it.
"""

from __future__ import annotations

import re
from typing import Literal

from .errors import RuleTableError, excerpt

__all__ = ["TableUnit", "declared_unit", "scale", "describe_unit", "unit_note"]

TableUnit = Literal["m", "grammar"]

_LINE = re.compile(r"^#\s*units\s*[:=]\s*(.*?)\s*$", re.IGNORECASE)
_METRES = frozenset({"m", "metre", "metres", "meter", "meters"})
_GRAMMAR = frozenset({"grammar", "u", "grammar units", "grammar unit"})


def declared_unit(text: str, *, file: str) -> TableUnit | None:
    """The unit named by a ``# units: ...`` comment above the header, None without one.

    Only comment and blank lines before the header are looked at; spreadsheet exports
    that pad the line with separators (``# units: m;;;;``) are accepted.

    Raises
    ------
    RuleTableError
        A ``# units:`` line naming another unit (at its row).
    """
    for row, line in enumerate(text.splitlines(), start=1):
        stripped = line.strip().rstrip(";,\t").strip()
        if not stripped:
            continue
        if not stripped.startswith("#"):
            return None  # the header: no declaration above it
        match = _LINE.match(stripped)
        if match is None:
            continue
        value = match.group(1).lower()
        if value in _METRES:
            return "m"
        if value in _GRAMMAR:
            return "grammar"
        raise RuleTableError(f"unknown unit {excerpt(match.group(1))}; write '# units: m' "
                             "(sizes in metres, whatever the grammar's units) or "
                             "'# units: grammar' (sizes in grammar units)", file=file, row=row)
    return None


def scale(unit: TableUnit | None, units: float) -> float:
    """Metres per table length unit: 1 for a metre table, else the grammar's ``units``."""
    return 1.0 if unit == "m" else float(units)


def describe_unit(unit: TableUnit | None, units: float, *, power: int = 1) -> str:
    """How the table's numbers are read, for messages: ``"m²"`` or ``"grammar units²
    (× 100 m² each at units = 10)"``."""
    mark = "²" if power == 2 else ""
    if unit == "m":
        return f"m{mark}"
    factor = float(units) ** power
    return f"grammar units{mark} (× {factor:g} m{mark} each at units = {units:g})"


def unit_note(file: str, unit: TableUnit | None, units: float, what: str) -> str | None:
    """The diagnostic saying how a table's sizes are read when that depends on the
    grammar (``units`` ≠ 1); None when the reading is plain metres."""
    if units == 1:
        return None
    if unit == "m":
        return (f"{file} is in metres ('# units: m'): its {what} are not scaled by the "
                f"grammar's units = {units:g}")
    declared = "'# units: grammar'" if unit == "grammar" else "no '# units:' line"
    return (f"{file} has {declared}, so its {what} are read in grammar units and scaled by "
            f"units = {units:g}; write '# units: m' at its top if they are metres")
