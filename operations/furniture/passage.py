"""The passage rule: furniture must leave a robot a way between a room's doors.

Furniture that satisfies every clearance can still cut a room in two: a double bed and a
wardrobe half a metre apart leave no way to the bathroom door behind them. A wheeled
robot (or a person) needs a passage; :class:`Passage` tests a layout for one, exactly,
with shapely:

* the robot's centre may go wherever the room's free floor (``Room.interior`` minus the
  footprints of the solid items) is at least ``width / 2`` away from every obstacle: the
  free floor eroded by ``width / 2``. Computed as the room eroded once, minus each item's
  footprint grown by ``width / 2``. Both use mitred joins, so the robot is taken as an
  axis-aligned square of side ``width``; that contains the round robot of diameter
  ``width`` and is stricter only where two corners face each other diagonally;
* a door's **approach** is where the robot stands right after coming through it: the
  band in front of the door, door-wide, ``width / 2 +`` :data:`APPROACH_MARGIN` deep from
  the wall face (:meth:`.clearance.OpeningStrip.zone`); the robot comes from the door
  opening, so a door whose approach meets two pieces of the eroded floor joins them;
* rule 1: doors whose approaches are connected in the empty room stay connected;
* rule 2: the pieces a robot reaches from the doors keep at least :data:`MIN_REACHED_SHARE`
  of the eroded floor, so no item walls off a sizeable pocket of the room. Parts of the
  empty room that no door reaches (a nook behind a neck narrower than the robot) do not
  count.

Every solid item counts as an obstacle: they all stand on the floor and reach into a
robot's height band. Rugs do not. A room without a door a robot can use is not tested.

The test is incremental: the eroded floor of the items already placed is kept (keyed by
their footprints), and a candidate costs one rectangle difference and a few predicates.
"""

from __future__ import annotations

from collections.abc import Collection, Sequence
from dataclasses import dataclass, field

import numpy as np
import shapely
from shapely.geometry import Polygon
from shapely.geometry.base import BaseGeometry

from .clearance import Box, OpeningStrip

__all__ = ["PASSAGE_WIDTH", "MIN_REACHED_SHARE", "APPROACH_MARGIN", "Blockage", "Passage"]

PASSAGE_WIDTH = 0.6
"""Default passage width (m): a robot of 0.5 m diameter plus a 5 cm margin on each side."""

MIN_REACHED_SHARE = 0.85
"""Share of the eroded free floor that must stay reachable from the room's doors."""

APPROACH_MARGIN = 0.1
"""How far (m) a door's approach reaches beyond the first spot a robot's centre can take."""

_AREA_EPS = 1e-9
_TOUCH = 1e-7
"""Approaches are shrunk by this much, so a piece merely touching one does not meet it."""
_CACHE = 16
"""Eroded floors kept per room (the layouts a family search goes back and forth between)."""


@dataclass(frozen=True)
class Blockage:
    """Why a layout fails the passage rule: ``kind`` ``"door"`` (``what`` names the door
    cut off) or ``"pocket"`` (``what`` is the share of the eroded floor walled off)."""

    kind: str
    what: str


_UNKNOWN = Blockage("", "")
"""Marks a state whose verdict has not been computed yet."""


@dataclass
class _State:
    """The eroded floor left by one set of obstacles, its verdict once known, and the
    verdicts with each candidate tested against it so far (the solver tries the same
    pose against the same items again while it seats families and goes back and forth
    between attempts)."""

    floor: BaseGeometry
    verdict: Blockage | None = _UNKNOWN
    with_candidate: dict[Box, Blockage | None] = field(default_factory=dict)


class Passage:
    """The passage rule of one room (see the module docstring).

    Parameters
    ----------
    interior:
        The room's free floor.
    doors:
        The room's doors seen from the room (:func:`.clearance.door_strips`).
    width:
        Passage width in metres (> 0).
    min_share:
        Share of the reachable eroded floor that must stay reachable.
    """

    def __init__(self, interior: Polygon, doors: Sequence[OpeningStrip], width: float, *,
                 min_share: float = MIN_REACHED_SHARE):
        self.radius = width / 2
        self.min_share = min_share
        eroded = interior.buffer(-self.radius, join_style="mitre")
        zones = np.array([d.zone(self.radius + APPROACH_MARGIN).buffer(-_TOUCH,
                                                                       join_style="mitre")
                          for d in doors], dtype=object)
        pieces = _pieces(eroded)
        meets = _meets(pieces, zones)
        used = np.flatnonzero(meets.any(axis=0))  # doors a robot can use in the empty room
        meets = meets[:, used]
        self.labels = [doors[int(k)].label for k in used]
        self.approaches = zones[used]
        self.groups = _groups(meets)
        self.floor = shapely.union_all(pieces[meets.any(axis=1)])
        self._states: dict[frozenset[Box], _State] = {}

    @property
    def active(self) -> bool:
        """False when no door of the room can be reached even in the empty room."""
        return len(self.labels) > 0

    def blockage(self, obstacles: Collection[Box], candidate: Box) -> Blockage | None:
        """What breaks the rule with ``candidate`` added to ``obstacles`` (None if nothing).

        Parameters
        ----------
        obstacles:
            Footprints ``(minx, minz, maxx, maxz)`` of the solid items already placed.
        candidate:
            The footprint of the item being placed.

        Notes
        -----
        The eroded floors of the last few obstacle sets are kept with the verdicts of the
        candidates tested against them (a candidate tested again costs a look-up), and a
        set's floor is made from that of the set one item smaller when it is known; when
        the grown candidate does not meet the floor, the verdict is that of ``obstacles``.
        Otherwise a candidate costs one rectangle difference, the pieces and their
        intersections with the approaches: tens of microseconds.
        """
        if not self.active:
            return None
        state = self._state(frozenset(obstacles))
        verdict = state.with_candidate.get(candidate, _UNKNOWN)
        if verdict is _UNKNOWN:
            verdict = state.with_candidate[candidate] = self._candidate_verdict(state,
                                                                                candidate)
        return verdict

    def _candidate_verdict(self, state: _State, candidate: Box) -> Blockage | None:
        grown = self._grown(candidate)
        if not state.floor.intersects(grown):
            if state.verdict is _UNKNOWN:
                state.verdict = self._verdict(state.floor)
            return state.verdict
        return self._verdict(state.floor.difference(grown))

    def _grown(self, footprint: Box) -> Polygon:
        r = self.radius
        return shapely.box(footprint[0] - r, footprint[1] - r, footprint[2] + r,
                           footprint[3] + r)

    def _state(self, key: frozenset[Box]) -> _State:
        state = self._states.pop(key, None)
        if state is None:
            state = self._derive(key)
            if len(self._states) >= _CACHE:
                self._states.pop(next(iter(self._states)))
        self._states[key] = state  # most recently used last
        return state

    def _derive(self, key: frozenset[Box]) -> _State:
        # the kept sets one item smaller, by the item they lack (asking the cache for
        # ``key`` less each item in turn would build n sets of n items)
        smaller_by = {next(iter(key - k)): state for k, state in self._states.items()
                      if len(k) + 1 == len(key) and k < key}
        for footprint in key:
            smaller = smaller_by.get(footprint)
            if smaller is not None:
                grown = self._grown(footprint)
                if not smaller.floor.intersects(grown):
                    return _State(smaller.floor, smaller.verdict)
                return _State(smaller.floor.difference(grown))
        if not key:
            return _State(self.floor)
        return _State(self.floor.difference(shapely.union_all([self._grown(b) for b in key])))

    def _verdict(self, floor: BaseGeometry) -> Blockage | None:
        pieces = _pieces(floor)
        doors = range(len(self.labels))
        if not len(pieces):
            return Blockage("door", self.labels[0])
        meets = _meets(pieces, self.approaches).tolist()
        if len(pieces) == 1 and all(meets[0]):  # the usual case: nothing cut off
            return None
        areas = shapely.area(pieces).tolist()
        reached = [any(row[k] for row in meets) for k in doors]
        from networkx.utils import UnionFind  # here: `cga check` needs no networkx

        joined = UnionFind(doors)  # a door joins the pieces its approach meets
        touched = []
        for row, area in zip(meets, areas):
            met = [k for k in doors if row[k]]
            if met:
                touched.append((met[0], area))
                joined.union(*met)
        # each class of doors named by its lowest door, so ties break the same way always
        name = {k: min(members) for members in joined.to_sets() for k in members}
        for group in self.groups:
            classes = {name[k] for k in group if reached[k]}
            if len(classes) == 1 and all(reached[k] for k in group):
                continue
            class_area = dict.fromkeys(classes, 0.0)
            for k, area in touched:
                if name[k] in class_area:
                    class_area[name[k]] += area
            main = max(classes, key=lambda c: (class_area[c], -c), default=-1)
            cut = next(k for k in group if not reached[k] or name[k] != main)
            return Blockage("door", self.labels[cut])
        total = sum(areas)
        reached_area = sum(area for _, area in touched)
        if reached_area < self.min_share * total - _AREA_EPS:
            return Blockage("pocket", f"{1 - reached_area / total:.0%}")
        return None


def _pieces(geometry: BaseGeometry) -> np.ndarray:
    """The polygons of ``geometry`` with an area."""
    if isinstance(geometry, Polygon):  # the usual case, without get_parts' overhead
        parts = np.empty(1, dtype=object)
        parts[0] = geometry
        return parts if geometry.area > _AREA_EPS else parts[:0]
    parts = shapely.get_parts(geometry)
    return parts[shapely.area(parts) > _AREA_EPS] if len(parts) else parts


def _meets(pieces: np.ndarray, zones: np.ndarray) -> np.ndarray:
    """``bool[piece, zone]``: the piece meets the zone."""
    if not len(pieces) or not len(zones):
        return np.zeros((len(pieces), len(zones)), dtype=bool)
    return shapely.intersects(pieces[:, None], zones[None, :])


def _groups(meets: np.ndarray) -> list[list[int]]:
    """Doors connected in the empty room, as sorted lists of door indices ordered by
    their lowest door (more than one door each: a door alone cannot be cut off from
    itself)."""
    from networkx.utils import UnionFind  # here: `cga check` needs no networkx

    joined = UnionFind(range(meets.shape[1]))
    for row in meets:
        joined.union(*np.flatnonzero(row).tolist())
    return sorted(sorted(g) for g in joined.to_sets() if len(g) > 1)
