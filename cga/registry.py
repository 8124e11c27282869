"""The operation registry: grammar operation names → :class:`~cga.operation.Operation`.

:data:`DEFAULT_OPERATIONS` maps operation names to ``"module:Class"`` entries in the
operation library (``cga.operations``, one module per operation); an
evaluator copies the table (jinja2's ``DEFAULT_FILTERS.copy()`` pattern), so a user can
register an operation of their own without touching globals::

    registry = OperationRegistry()
    registry.register(MyOperation())

Entries are imported on first use, so ``cga check`` never pays for the geometry and
physics libraries the floor operations need.
"""

from __future__ import annotations

import difflib
import importlib
from collections.abc import Iterator, Mapping

from .operation import Operation

__all__ = ["DEFAULT_OPERATIONS", "OperationRegistry", "UnknownOperation"]

DEFAULT_OPERATIONS: dict[str, str] = {
    "extrude": "cga.operations.extrude:Extrude",
    "split": "cga.operations.split:Split",
    "repeated_split": "cga.operations.repeated_split:RepeatedSplit",
    "component_split": "cga.operations.component_split:ComponentSplit",
    "make_floor": "cga.operations.make_floor:MakeFloor",
    "type_rooms": "cga.operations.type_rooms:TypeRooms",
    "add_furniture": "cga.operations.add_furniture:AddFurniture",
    "usar_floor": "cga.operations.usar_floor:UsarFloor",
}


class UnknownOperation(KeyError):
    """Raised by :meth:`OperationRegistry.__getitem__`; carries close matches for hints."""

    def __init__(self, name: str, suggestions: list[str]):
        super().__init__(name)
        self.name = name
        self.suggestions = suggestions


class OperationRegistry(Mapping[str, Operation]):
    """Name → operation, importing default entries lazily on first lookup."""

    def __init__(self, entries: Mapping[str, str | Operation] | None = None):
        self._entries: dict[str, str | Operation] = dict(
            DEFAULT_OPERATIONS if entries is None else entries)

    def register(self, operation: Operation) -> None:
        self._entries[operation.name] = operation

    def modules(self) -> list[str]:
        """The modules of the entries not imported yet (a batch imports them up front)."""
        return [entry.split(":")[0] for entry in self._entries.values() if isinstance(entry, str)]

    def copy(self) -> "OperationRegistry":
        return OperationRegistry(self._entries)

    def __getitem__(self, name: str) -> Operation:
        try:
            entry = self._entries[name]
        except KeyError:
            raise UnknownOperation(name, difflib.get_close_matches(name, self._entries, n=3)) from None
        if isinstance(entry, str):
            module_name, class_name = entry.split(":")
            entry = getattr(importlib.import_module(module_name), class_name)()
            self._entries[name] = entry
        return entry

    def __iter__(self) -> Iterator[str]:
        return iter(self._entries)

    def __len__(self) -> int:
        return len(self._entries)
