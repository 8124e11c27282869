"""Room typing (docs/room_typing.md, thesis §3.3 and §5.2): the algorithms behind ``type_rooms``.

One concern per module:

:mod:`.rules`       the thesis' semicolon rule tables: parsing and validation
:mod:`.assign`      the typing process: first rule by ``Prob``, mandatory, optional, default
:mod:`.backtrack`   placing the mandatory rules: greedy pass + complete correction search
:mod:`.explain`     why the rules do not fit, in numbers
:mod:`.doors`       where a door fits in a wall, where it goes, how it swings
:mod:`.room_graph`  door-capable adjacency, rule edges, fewest extra doors, the graph

The grammar operation and the floor-plan wiring are in :mod:`cga.operations.type_rooms`;
rule authors test their tables with :mod:`cga.authoring`.
"""

from importlib import import_module
from typing import TYPE_CHECKING, Any

from .rules import COLUMNS, DEFAULT_TYPE, RuleTable, TypeRule, load_rule_table, parse_rule_table

if TYPE_CHECKING:
    from .assign import Typing, TypingNote, assign_types
    from .backtrack import RoomSet, RuleSpec

_LAZY = {"Typing": "assign", "TypingNote": "assign", "assign_types": "assign",
         "RoomSet": "backtrack", "RuleSpec": "backtrack"}
"""Names imported on first use (PEP 562): ``cga check`` reads rule tables only."""


def __getattr__(name: str) -> Any:
    module = _LAZY.get(name)
    if module is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    return getattr(import_module(f".{module}", __name__), name)

__all__ = [
    "COLUMNS",
    "DEFAULT_TYPE",
    "RoomSet",
    "RuleSpec",
    "RuleTable",
    "TypeRule",
    "Typing",
    "TypingNote",
    "assign_types",
    "load_rule_table",
    "parse_rule_table",
]
