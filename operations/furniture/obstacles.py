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
states, so a rebuild concatenates arrays and builds one tree.
"""

from __future__ import annotations

from collections.abc import Collection, Sequence
from dataclasses import dataclass

import numpy as np
from shapely import STRtree

__all__ = ["WALL", "BODY", "CLEARANCE", "DOOR", "KINDS", "ObstacleBlock", "ObstacleIndex",
           "complement"]

WALL, BODY, CLEARANCE, DOOR = range(4)
KINDS = ("wall", "body", "clearance", "door")
"""Obstacle kind names by code (the ``kind`` of :class:`~.layout.Conflict`)."""


@dataclass(frozen=True)
class ObstacleBlock:
    """Obstacles that come and go together: a room's walls and door zones, or the body
    and clearance boxes of one placed item.

    ``kinds`` holds codes (:data:`WALL` ...), ``owners`` the id of the item or label
    each obstacle belongs to, ``geometries`` the shapely polygons and ``bounds`` one
    row ``(minx, minz, maxx, maxz)`` per obstacle that is an axis-aligned rectangle,
    NaN for any other shape (a door's swing, a turned item)."""

    kinds: np.ndarray
    owners: np.ndarray
    geometries: np.ndarray
    bounds: np.ndarray


class ObstacleIndex:
    """An STRtree over the obstacles of ``blocks`` with their columns, in block order
    (row order decides which conflict a query reports first)."""

    def __init__(self, blocks: Sequence[ObstacleBlock]):
        self.kinds = np.concatenate([b.kinds for b in blocks])
        self.owners = np.concatenate([b.owners for b in blocks])
        self.geometries = np.concatenate([b.geometries for b in blocks])
        self.bounds = np.concatenate([b.bounds for b in blocks])
        self.is_rectangle = ~np.isnan(self.bounds[:, 0])
        self.tree = STRtree(self.geometries)

    def hits(self, geometries: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``(query index, row)`` of every obstacle each of ``geometries`` intersects."""
        found = self.tree.query(geometries, predicate="intersects")
        return found[0], found[1]

    def blocking(self, rows: np.ndarray, part_is_body: np.ndarray, owner: int,
                 non_collision: bool, related: Collection[int]) -> np.ndarray:
        """Which obstacles ``rows`` block the parts they were hit by (``part_is_body``:
        the part is the item's body), for the item ``owner``; ``related`` are the ids
        of its parent and children (see :meth:`.layout.Layout.conflicts`)."""
        kinds, owners = self.kinds[rows], self.owners[rows]
        table = _RUG_BLOCKED_BY if non_collision else _BLOCKED_BY
        blocked = table[2 * kinds + part_is_body] & (owners != owner)
        if not non_collision:
            clearance = kinds == CLEARANCE
            for member in related:  # the family may stand in each other's clearances
                blocked &= ~(clearance & (owners == member))
        return blocked


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
