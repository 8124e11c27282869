"""The obstacles of one room's layout, indexed so a query filters its hits in bulk.

:class:`~.layout.Layout` tests every candidate pose against the walls, the door zones
and the parts of the items placed so far. A shapely :class:`~shapely.STRtree` finds
the obstacles a query geometry meets in C, but in a crowded room the strip an item
sweeps along a wall meets most of them, and deciding for each hit whether it blocks
(docs/furniture.md: a clearance box blocks bodies but not the item's family, door
zones block bodies, ...) one hit at a time in Python made every query cost O(n)
interpreter steps for n placed items. Here each obstacle's kind, owner and bounds are
numpy columns, so a query decides for all its hits at once and clips the rectangles
among them with bounds arithmetic.

The index is immutable: a layout builds one per state from :class:`ObstacleBlock`\\ s
(the walls and door zones, then one block per placed item) that it keeps between
states, so a rebuild concatenates arrays (or extends those of the state before the
last item was added) and builds one tree; and it keeps the index of each tuple of
blocks, as the solver comes back to the same states again and again.
"""

from __future__ import annotations

from collections.abc import Collection, Hashable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import shapely
from shapely import STRtree

__all__ = ["WALL", "BODY", "CLEARANCE", "DOOR", "KINDS", "ObstacleBlock", "ObstacleIndex",
           "complement"]

WALL, BODY, CLEARANCE, DOOR = range(4)
KINDS = ("wall", "body", "clearance", "door")
"""Obstacle kind names by code (the ``kind`` of :class:`~.layout.Conflict`)."""


@dataclass(frozen=True, eq=False)
class ObstacleBlock:
    """Obstacles that come and go together: a room's walls and door zones, or the body
    and clearance boxes of one placed item (:meth:`make`). Equal only to itself: a
    layout keeps an index per tuple of blocks."""

    columns: np.ndarray
    """``(n, 3)`` integers per obstacle: ``2 * kind`` (the row of :data:`_BLOCKED_BY`
    for a clearance box hitting it), the owner's id, and the owner's id again for a
    clearance box, else -1 (whose clearance the owner's family may stand in)."""
    geometries: np.ndarray
    bounds: np.ndarray
    """``(n, 4)``: ``(minx, minz, maxx, maxz)`` of an axis-aligned rectangle; NaN for any
    other shape (a door's swing, a turned item)."""
    shaped: np.ndarray
    """Whether each geometry is not the box of its bounds (a box meets another box iff
    their bounds meet; any other shape needs the exact test)."""

    @classmethod
    def make(cls, kinds: Sequence[int], owners: Sequence[int], geometries: np.ndarray,
             bounds: np.ndarray, boxes: bool = False) -> "ObstacleBlock":
        """A block of obstacles of ``kinds`` (:data:`WALL` ...) owned by the ids
        ``owners`` (an item or a label); ``boxes``: the geometries are known to be the
        boxes of their bounds, else each is tested."""
        columns = np.array([(2 * kind, owner, owner if kind == CLEARANCE else -1)
                            for kind, owner in zip(kinds, owners)], dtype=np.int64).reshape(-1, 3)
        shaped = np.zeros(len(geometries), dtype=bool) if boxes else _shaped(geometries, bounds)
        return cls(columns, geometries, bounds, shaped)


class ObstacleIndex:
    """An STRtree over the obstacles of ``blocks`` with their columns, in block order
    (row order decides which conflict a query reports first).

    ``base``, when given, is the index of all of ``blocks`` but the last: its columns are
    extended by the last block's rather than all blocks' concatenated again (the same
    arrays; in a crowded room, where each item is added after a hundred others, the
    concatenation cost more than the tree)."""

    def __init__(self, blocks: Sequence[ObstacleBlock], base: ObstacleIndex | None = None):
        parts: Sequence[ObstacleBlock | ObstacleIndex] = (
            blocks if base is None else (base, blocks[-1]))
        self.columns: np.ndarray = np.concatenate([b.columns for b in parts])
        self.geometries: np.ndarray = np.concatenate([b.geometries for b in parts])
        self.bounds: np.ndarray = np.concatenate([b.bounds for b in parts])
        self.is_rectangle = ~np.isnan(self.bounds[:, 0])
        self.shaped: np.ndarray = np.concatenate([b.shaped for b in parts])
        self.any_shaped = bool(self.shaped.any())
        self.tree = STRtree(self.geometries)
        self._lists: list[list[int]] | None = None
        self.answers: dict[tuple[Hashable, ...], Any] = {}
        """Answers worked out from this state, by question (:class:`~.layout.Layout`
        keeps them here)."""

    def kind(self, row: int) -> str:
        """The kind name of obstacle ``row`` (see :data:`KINDS`)."""
        return KINDS[int(self.columns[row, 0]) // 2]

    def owner(self, row: int) -> int:
        """The owner id of obstacle ``row``."""
        return int(self.columns[row, 1])

    def hits(self, geometries: np.ndarray, boxes: bool = False
             ) -> tuple[np.ndarray, np.ndarray]:
        """``(query index, row)`` of every obstacle each of ``geometries`` intersects.

        ``boxes``: the geometries are axis-aligned boxes, so the predicate is evaluated
        only for the obstacles that are not (the tree's envelope test decides the rest).
        """
        if not boxes:
            found = self.tree.query(geometries, predicate="intersects")
            return found[0], found[1]
        found = self.tree.query(geometries)
        if not self.any_shaped:
            return found[0], found[1]
        shaped = self.shaped[found[1]]
        if np.count_nonzero(shaped):
            keep = ~shaped
            keep[shaped] = shapely.intersects(geometries[found[0, shaped]],
                                              self.geometries[found[1, shaped]])
            found = found[:, keep]
        return found[0], found[1]

    def blocking(self, rows: np.ndarray, part_is_body: np.ndarray, owner: int,
                 non_collision: bool, related: Collection[int]) -> np.ndarray:
        """Which obstacles ``rows`` block the parts they were hit by (``part_is_body``:
        the part is the item's body), for the item ``owner``; ``related`` are the ids
        of its parent and children (see :meth:`.layout.Layout.conflicts`)."""
        table = _RUG_BLOCKED_BY if non_collision else _BLOCKED_BY
        columns = self.columns[rows]
        blocked = table[columns[:, 0] + part_is_body] & (columns[:, 1] != owner)
        if related and not non_collision:
            for member in related:  # the family may stand in each other's clearances
                blocked &= columns[:, 2] != member
        return blocked

    def blocking_few(self, part_rows: list[int], rows: list[int], owner: int,
                     non_collision: bool, related: Collection[int]) -> list[tuple[int, int]]:
        """:meth:`blocking` for the few hits ``(part_rows[k], rows[k])`` of a query in an
        ordinary room, without numpy's cost per call: ``(row, part)`` of each hit that
        blocks its part, in query order (one call per query, the hits tested inline)."""
        codes, owners, clearance_owners = self.lists
        table = _RUG_BLOCKED_BY_LIST if non_collision else _BLOCKED_BY_LIST
        return [(row, part) for part, row in zip(part_rows, rows)
                if owners[row] != owner and table[codes[row] + (part == 0)]
                and (non_collision or clearance_owners[row] not in related)]

    @property
    def lists(self) -> list[list[int]]:
        """:attr:`columns` as a Python list per column (made on first use). Not a list per
        row: a layout keeps indexes for later (:meth:`.layout.Layout._index`), and the
        garbage collector walks every list they hold, each time it runs."""
        if self._lists is None:
            self._lists = self.columns.T.tolist()
        return self._lists


_BLOCKED_BY = np.array([
    # a clearance box, the body hit by an obstacle of kind ...
    True, True,    # wall
    True, True,    # body
    False, True,   # clearance (but the family's, in :meth:`ObstacleIndex.blocking`)
    False, True,   # door zone
])
_RUG_BLOCKED_BY = np.array([True, True, False, False, False, False, False, False])
"""What blocks what (docs/furniture.md), by ``2 * kind + is_body``; a non-colliding
item (a rug) is blocked by the walls only."""
_BLOCKED_BY_LIST = _BLOCKED_BY.tolist()
_RUG_BLOCKED_BY_LIST = _RUG_BLOCKED_BY.tolist()


def _shaped(geometries: np.ndarray, bounds: np.ndarray) -> np.ndarray:
    """Which of ``geometries`` are not the boxes of their ``bounds`` (NaN: not a
    rectangle). A polygon without holes whose every edge runs along a side of its bounds
    is that box: its outline is a closed curve in the box's outline, so all of it."""
    shaped = np.isnan(bounds[:, 0]) | (shapely.get_num_interior_rings(geometries) > 0)
    check = np.flatnonzero(~shaped)
    if len(check):
        coords, which = shapely.get_coordinates(geometries[check], return_index=True)
        b = bounds[check][which]
        sides = np.stack([coords[:, 0] == b[:, 0], coords[:, 1] == b[:, 1],
                          coords[:, 0] == b[:, 2], coords[:, 1] == b[:, 3]], axis=1)
        along = (sides[1:] & sides[:-1]).any(axis=1) | (which[1:] != which[:-1])
        shaped[check] = np.bincount(which[1:][~along], minlength=len(check)) > 0
    return shaped


def complement(starts: np.ndarray, ends: np.ndarray, lo: float, hi: float
               ) -> list[tuple[float, float]]:
    """``[lo, hi]`` minus the union of the open intervals ``(starts[k], ends[k])``, as
    disjoint closed intervals in increasing order.

    A sweep over the intervals sorted by start: the points before interval ``k`` not
    known to be forbidden begin at the largest end seen so far (a running maximum), and
    interval ``k`` leaves a gap when it starts at or after that point.
    """
    order = np.lexsort((ends, starts))
    starts, ends = starts[order], ends[order]
    cursors = np.maximum.accumulate(np.concatenate(([lo], ends)))
    before = cursors[:-1]
    gap = (starts >= before) & (before <= hi)
    free = list(zip(before[gap].tolist(), np.minimum(starts[gap], hi).tolist()))
    last = float(cursors[-1])
    if last <= hi:
        free.append((last, float(hi)))
    return free
