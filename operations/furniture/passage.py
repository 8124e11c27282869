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

The test is incremental and local. The eroded floor of the items already placed is kept
(keyed by their footprints) with its pieces, their areas and the approaches they meet,
and with the **clusters** of its obstacles: the grown footprints and the plane around the
eroded room, closed sets grouped by touching. The pieces are the regions the obstacles
leave free, so (Alexander duality; the Mayer–Vietoris sequence of the obstacles and one
more box) a box that meets the obstacles in ``c`` separate places, belonging to ``k``
clusters, cuts ``c - k`` pieces in two, less the pieces it covers whole. A candidate that
meets each cluster in one place only changes the area of the piece it stands on, by a
rectangle clip of the floor; the obstacles it meets come from comparing boxes, the
places from a handful of overlaps around it. A candidate asked again once items have
been added (the solver tries the same poses for item after item in a full room) has its
own pieces from its last test updated the same way, item by item. The rule is judged on
the areas so found unless a threshold lies within their rounding. Only a candidate that
cuts a piece in two afresh, stands at a door or is that close to a threshold costs the
exact difference with the floor (a tenth of a millisecond for a floor of some hundred
vertices) and the pieces of the result.
"""

from __future__ import annotations

from collections.abc import Collection, Iterable, Sequence
from dataclasses import dataclass, field
from functools import cached_property

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
_CHAIN = 16
"""Most items added since a candidate's last test that its pieces are updated by."""
_LOCAL = 16
"""Obstacles from which on a candidate is updated locally: with fewer, the floor has so
few vertices that the exact difference costs no more."""
_ROUNDING = 1e-10
"""A bound on how far one local update moves the floor's areas from those of the exact
difference, per squared metre of the room's largest coordinate: both are sums of some
thousand products of coordinates at most, each rounded by 1e-16 of its size."""
_UPDATES = 256
"""Local updates at most between exact computations of a candidate's pieces."""


@dataclass(frozen=True)
class Blockage:
    """Why a layout fails the passage rule: ``kind`` ``"door"`` (``what`` names the door
    cut off) or ``"pocket"`` (``what`` is the share of the eroded floor walled off)."""

    kind: str
    what: str


_UNKNOWN = Blockage("", "")
"""Marks a state whose verdict has not been computed yet."""
_UNSURE = Blockage("?", "")
"""A verdict that the rounding of locally updated areas could change."""


@dataclass(frozen=True)
class _Pieces:
    """The pieces of an eroded floor: every part with an area (slivers too), its area,
    whether it meets each approach, and a shape containing it (the part itself when it
    was computed exactly; after local updates, the part it was cut from), and how many
    local updates the areas carry."""

    shapes: np.ndarray
    areas: list[float]
    meets: list[list[bool]]
    bounds: list[Box]
    updates: int = 0


@dataclass(frozen=True)
class _Obstacles:
    """Grown footprints and their clusters.

    The nodes are the parts of the plane around the eroded room (nodes ``0 .. around-1``:
    outside it, and each hole) and the boxes (box ``i``, column ``i`` of ``bounds``, rows
    minx, minz, maxx, maxz, is node ``around + i``), all closed sets; two nodes have the
    same label iff a chain of touching nodes joins them.
    """

    bounds: np.ndarray
    labels: tuple[int, ...]
    around: int

    def meeting(self, box: Box) -> list[int]:
        """The boxes that meet ``box`` (touching counts)."""
        b = self.bounds
        return np.flatnonzero((b[0] <= box[2]) & (b[2] >= box[0])
                              & (b[1] <= box[3]) & (b[3] >= box[1])).tolist()

    def plus(self, box: Box, around: Iterable[int], met: Iterable[int]) -> _Obstacles:
        """These obstacles and ``box``, which meets the nodes ``around`` of the plane
        around the room and the boxes ``met``."""
        joined = {self.labels[node] for node in around}
        joined.update(self.labels[self.around + i] for i in met)
        label = min(joined) if joined else len(self.labels)  # a cluster's lowest node
        labels = self.labels
        if len(joined) > 1:
            labels = tuple(label if k in joined else k for k in labels)
        return _Obstacles(np.concatenate([self.bounds, np.reshape(box, (4, 1))], axis=1),
                          labels + (label,), self.around)


@dataclass(frozen=True)
class _Step:
    """How a state was made from its parent, the state one box smaller: the boxes of the
    parent the added box meets, the cluster of each place it meets the parent's
    obstacles, the parent floor's area under it, and whether it meets an approach; what
    updating a candidate's pieces from the parent takes."""

    met: list[int]
    places: list[int]
    area: float
    at_door: bool


@dataclass
class _State:
    """The eroded floor left by one set of obstacles (``key``), and the verdicts with each
    candidate tested against it so far (the solver tries the same pose against the same
    items again while it seats families and goes back and forth between attempts).

    A state made from the one a box smaller keeps it as ``parent`` with the grown box
    ``added``. The floor's verdict and pieces, the obstacles' clusters and the step from
    the parent are made when first asked for. ``less`` keeps, by grown candidate box, the
    floor less the box with its pieces and verdict where a candidate's test computed them
    exactly: the state that adds the candidate is made from them, not again (the solver
    adds most items right after testing them)."""

    floor: BaseGeometry
    key: frozenset[Box]
    parent: _State | None = None
    added: Box = (0.0, 0.0, 0.0, 0.0)
    verdict: Blockage | None = _UNKNOWN
    pieces: _Pieces | None = None
    with_candidate: dict[Box, Blockage | None] = field(default_factory=dict)
    obstacles: _Obstacles | None = None
    step: _Step | None = None
    less: dict[Box, tuple[BaseGeometry, _Pieces, Blockage | None]] = field(
        default_factory=dict)


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
        zones = shapely.buffer(np.array([d.zone(self.radius + APPROACH_MARGIN) for d in doors],
                                        dtype=object), -_TOUCH, join_style="mitre")
        pieces, areas = _parts(eroded)
        pieces = pieces[np.greater(areas, _AREA_EPS)]
        meets = _meets(pieces, zones)
        used = np.flatnonzero(meets.any(axis=0))  # doors a robot can use in the empty room
        meets = meets[:, used]
        self.labels = [doors[int(k)].label for k in used]
        self.approaches = zones[used]
        self.groups = _groups(meets)
        self.floor = shapely.union_all(pieces[meets.any(axis=1)])
        self._approach_bounds = [tuple(b) for b in shapely.bounds(self.approaches).tolist()]
        reach = max(np.abs(self.floor.bounds).max(), 1.0) if self.active else 1.0
        self._rounding = _ROUNDING * reach * reach
        self._around_met: dict[Box, list[tuple[int, np.ndarray]]] = {}
        self._insides: dict[Box, bool] = {}
        self._states: dict[frozenset[Box], _State] = {}
        self._last: dict[Box, tuple[_State, _Pieces, list[int] | None]] = {}

    @cached_property
    def _around(self) -> list[BaseGeometry]:
        """The connected parts of the plane around the eroded room (outside it, and each
        hole), as far as any obstacle can reach: the nodes of the obstacles' clusters
        beside the boxes (made when a floor is first updated locally)."""
        minx, minz, maxx, maxz = self.floor.bounds
        pad = 2 * (maxx - minx + maxz - minz) + 1.0
        frame = shapely.box(minx - pad, minz - pad, maxx + pad, maxz + pad)
        parts = _parts(frame.difference(self.floor))[0]
        joined = _components(len(parts), _touching_pairs(parts))
        return [shapely.union_all(parts[np.equal(joined, k)]) for k in sorted(set(joined))]

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
        set's floor is made from that of the set one item smaller when it is known. In a
        room of :data:`_LOCAL` obstacles or more, a candidate is judged from the pieces
        of the floor, or from its own pieces against a set a few items smaller, updated
        locally (module docstring): tens of microseconds. Only when neither update is
        certain does it cost the exact difference with the floor and the pieces of the
        result.
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
        met = None
        if len(state.key) >= _LOCAL:
            updated, met = self._updated(state, candidate, grown)
            if updated is None:
                obstacles = self._obstacles(state)
                if met is None:
                    met = obstacles.meeting(grown)
                updated = self._cut(obstacles, state.floor, self._pieces(state), grown, met)
            if updated is not None:
                verdict = self._judge(updated)
                if verdict is not _UNSURE:
                    self._last[candidate] = (state, updated, met)
                    return verdict
        box = shapely.box(*grown)
        if not state.floor.intersects(box):
            pieces, verdict = self._pieces(state), self._state_verdict(state)
        else:
            less = state.floor.difference(box)
            pieces = self._exact(less)
            verdict = self._judge(pieces)
            state.less[grown] = (less, pieces, verdict)
        self._last[candidate] = (state, pieces, met)
        return verdict

    def _updated(self, state: _State, candidate: Box, grown: Box
                 ) -> tuple[_Pieces | None, list[int] | None]:
        """The pieces of ``state``'s floor less the grown candidate, updated box by box
        from those of the state a few boxes smaller it was last tested against (None when
        there is none, or an update is not local), and the boxes it meets (None when
        not known)."""
        last = self._last.get(candidate)
        if last is None:
            return None, None
        children: list[_State] = []
        ancestor = state
        while (ancestor is not last[0] and ancestor.parent is not None
               and len(children) < _CHAIN):
            children.append(ancestor)
            ancestor = ancestor.parent
        if ancestor is not last[0]:
            return None, None
        _, pieces, met = last
        if met is None:
            met = self._obstacles(ancestor).meeting(grown)
        updated: _Pieces | None = pieces
        for child in reversed(children):
            if updated is not None:
                updated = self._after(child, updated, met, grown)
            if _meet(child.added, grown):  # the added box is the child's last
                boxes = self._obstacles(child).bounds.shape[1]
                met = met + [boxes - 1]
        return updated, met

    def _after(self, child: _State, pieces: _Pieces, met: list[int],
               grown: Box) -> _Pieces | None:
        """The pieces of ``child``'s floor less the grown box ``grown``, from those of its
        parent's floor less ``grown`` (``pieces``; ``met``: the parent's boxes ``grown``
        meets)."""
        assert child.parent is not None
        step = self._step(child)
        if step.at_door:
            return None
        parent, before = child.parent, self._obstacles(child.parent)
        if _meet(child.added, grown):
            obstacles = before.plus(grown, self._around_nodes(grown), met)
            return self._cut(obstacles, parent.floor, pieces, child.added,
                             step.met + [len(before.labels) - before.around], grown)
        # the box meets the obstacles in the same places as before, but the clusters
        # that ``grown`` meets are joined
        joined = {before.labels[node] for node in self._around_nodes(grown)}
        joined.update(before.labels[before.around + i] for i in met)
        places = step.places
        if len(joined) > 1:
            places = [-1 if label in joined else label for label in places]
        if len(set(places)) < len(places):
            return None
        return _less(pieces, child.added, step.area)

    def _cut(self, obstacles: _Obstacles, floor: BaseGeometry, pieces: _Pieces, cut: Box,
             met: list[int], extra: Box | None = None) -> _Pieces | None:
        """The pieces of ``floor`` (``pieces``; less the grown box ``extra`` if given) once
        the grown box ``cut``, which meets the boxes ``met`` of ``obstacles``, is taken out
        too; None unless ``cut`` cuts no piece in two, meets no approach and takes area
        from one piece at most."""
        if self._at_door(cut):
            return None
        places = self._places(obstacles, cut, met)
        if len(set(places)) < len(places):
            return None
        removed = _clipped_area(floor, cut)
        if extra is not None:
            overlap = (max(cut[0], extra[0]), max(cut[1], extra[1]),
                       min(cut[2], extra[2]), min(cut[3], extra[3]))
            if overlap[0] < overlap[2] and overlap[1] < overlap[3]:
                removed -= _clipped_area(floor, overlap)
        return _less(pieces, cut, removed)

    def _at_door(self, box: Box) -> bool:
        return any(_meet(box, b) for b in self._approach_bounds)

    def _places(self, obstacles: _Obstacles, box: Box, met: list[int]) -> list[int]:
        """The cluster of each separate place where ``box`` meets ``obstacles`` (``met``:
        the boxes it meets); a cluster met in two places closes a ring."""
        around = [] if self._inside(box) else self._around_contacts(box)
        labels = [obstacles.labels[node] for node, _ in around]
        labels += [obstacles.labels[obstacles.around + i] for i in met]
        if len(set(labels)) == len(labels):
            return labels
        # contacts with one cluster are one place if they touch inside the box
        x0, z0, x1, z1 = box
        overlaps = [(max(b[0], x0), max(b[1], z0), min(b[2], x1), min(b[3], z1))
                    for b in obstacles.bounds[:, met].T.tolist()]
        n = len(around)
        pairs = [(n + i, n + j) for i, a in enumerate(overlaps)
                 for j in range(i + 1, len(overlaps))
                 if labels[n + i] == labels[n + j] and _meet(a, overlaps[j])]
        for k, (_, parts) in enumerate(around):
            for i, overlap in enumerate(overlaps):
                if labels[n + i] == labels[k] and (
                        not self._within(overlap) if n == 1  # then the one place
                        else any(p.intersects(shapely.box(*overlap)) for p in parts)):
                    pairs.append((k, n + i))
        place = _components(len(labels), pairs)
        return [labels[k] for k in range(len(labels)) if place[k] == k]

    def _around_contacts(self, box: Box) -> list[tuple[int, np.ndarray]]:
        """Where ``box`` meets the plane around the eroded room: per connected place, the
        node it belongs to and its parts (kept per box: the solver asks for few boxes)."""
        found = self._around_met.get(box)
        if found is None:
            found = []
            if self._inside(box):
                pass
            elif self._room is not None:
                found = [(0, shapely.box(*np.array(place).T))
                         for place in _outside_box(self._room, box)]
            else:
                shape = shapely.box(*box)
                for node, around in enumerate(self._around):
                    parts = shapely.get_parts(shapely.intersection(around, shape))
                    joined = _components(len(parts), _touching_pairs(parts))
                    found += [(node, parts[np.equal(joined, k)]) for k in sorted(set(joined))]
            self._around_met[box] = found
        return found

    def _around_nodes(self, box: Box) -> list[int]:
        """The nodes of the plane around the eroded room that ``box`` meets."""
        if len(self._around) == 1:  # the usual case: no need to know where
            return [] if self._inside(box) else [0]
        return sorted({node for node, _ in self._around_contacts(box)})

    def _inside(self, box: Box) -> bool:
        """:meth:`_within`, kept per box."""
        inside = self._insides.get(box)
        if inside is None:
            inside = self._insides[box] = self._within(box)
        return inside

    def _within(self, box: Box) -> bool:
        """Whether ``box`` lies in the interior of the eroded room."""
        room = self._room
        if room is not None:
            return (room[0] < box[0] and box[2] < room[2]
                    and room[1] < box[1] and box[3] < room[3])
        shapely.prepare(self.floor)  # once: then a no-op
        return self.floor.contains_properly(shapely.box(*box))

    @cached_property
    def _room(self) -> Box | None:
        """The eroded room's bounds when it is that box (the usual case: then where a box
        meets the plane around it is bounds arithmetic)."""
        bounds = self.floor.bounds
        if isinstance(self.floor, Polygon) and self.floor.equals(shapely.box(*bounds)):
            return bounds
        return None

    def _grown(self, footprint: Box) -> Box:
        r = self.radius
        return (footprint[0] - r, footprint[1] - r, footprint[2] + r, footprint[3] + r)

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
                tested = smaller.less.get(grown)
                if tested is not None:  # the same difference, its pieces and verdict
                    return _State(tested[0], key, smaller, grown, tested[2], tested[1])
                box = shapely.box(*grown)
                if not smaller.floor.intersects(box):
                    return _State(smaller.floor, key, smaller, grown, smaller.verdict,
                                  smaller.pieces)
                return _State(smaller.floor.difference(box), key, smaller, grown)
        if not key:
            return _State(self.floor, key)
        return _State(self.floor.difference(
            shapely.union_all([shapely.box(*self._grown(b)) for b in key])), key)

    def _obstacles(self, state: _State) -> _Obstacles:
        """The clusters of ``state``'s obstacles, from those of its nearest ancestor that
        has them."""
        line = [state]  # the state and its ancestors without clusters
        while line[-1].obstacles is None and line[-1].parent is not None:
            line.append(line[-1].parent)
        root = line.pop()
        if root.obstacles is None:  # a state made from scratch
            root.obstacles = _Obstacles(np.empty((4, 0)), tuple(range(len(self._around))),
                                        len(self._around))
            for footprint in root.key:
                root.obstacles = self._plus(root.obstacles, self._grown(footprint))
        obstacles = root.obstacles
        for child in reversed(line):
            obstacles = child.obstacles = self._plus(obstacles, child.added)
        return obstacles

    def _plus(self, obstacles: _Obstacles, box: Box) -> _Obstacles:
        return obstacles.plus(box, self._around_nodes(box), obstacles.meeting(box))

    def _step(self, child: _State) -> _Step:
        """How ``child`` was made from its parent (:class:`_Step`)."""
        if child.step is None:
            assert child.parent is not None
            before = self._obstacles(child.parent)
            met = before.meeting(child.added)
            child.step = _Step(met, self._places(before, child.added, met),
                               _clipped_area(child.parent.floor, child.added),
                               self._at_door(child.added))
        return child.step

    def _pieces(self, state: _State) -> _Pieces:
        if state.pieces is None:
            state.pieces = self._exact(state.floor)
        return state.pieces

    def _state_verdict(self, state: _State) -> Blockage | None:
        if state.verdict is _UNKNOWN:
            state.verdict = self._judge(self._pieces(state))
        return state.verdict

    def _exact(self, floor: BaseGeometry) -> _Pieces:
        parts, areas = _parts(floor)
        bounds = ([parts[0].bounds] if len(parts) == 1
                  else [tuple(b) for b in shapely.bounds(parts).tolist()])
        return _Pieces(parts, areas, _meets(parts, self.approaches).tolist(), bounds)

    def _judge(self, pieces: _Pieces) -> Blockage | None:
        """The rule on the pieces of a floor; :data:`_UNSURE` when the areas carry local
        updates whose rounding could change the verdict."""
        sure = pieces.updates * self._rounding  # bounds the error of any sum of areas
        kept = []
        for k, area in enumerate(pieces.areas):
            if sure and abs(area - _AREA_EPS) <= sure:
                return _UNSURE
            if area > _AREA_EPS:
                kept.append(k)
        if not kept:
            return Blockage("door", self.labels[0])
        meets = [pieces.meets[k] for k in kept]
        if len(kept) == 1 and all(meets[0]):  # the usual case: nothing cut off
            return None
        areas = [pieces.areas[k] for k in kept]
        if self.groups:
            cut_off = self._door_cut_off(meets, areas, sure)
            if cut_off is not None:
                return cut_off
        total = sum(areas)
        reached_area = sum(area for row, area in zip(meets, areas) if any(row))
        limit = self.min_share * total - _AREA_EPS
        if sure and abs(reached_area - limit) <= 2 * sure:
            return _UNSURE
        if reached_area < limit:
            share = 1 - reached_area / total
            if sure and abs(share * 100 % 1 - 0.5) <= 200 * sure / total:
                return _UNSURE
            return Blockage("pocket", f"{share:.0%}")
        return None

    def _door_cut_off(self, meets: list[list[bool]], areas: list[float],
                      sure: float) -> Blockage | None:
        """Rule 1 on pieces meeting the approaches ``meets`` with ``areas``."""
        doors = range(len(self.labels))
        reached = [any(row[k] for row in meets) for k in doors]
        pairs: list[tuple[int, int]] = []  # a door joins the pieces its approach meets
        touched = []
        for row, area in zip(meets, areas):
            met = [k for k in doors if row[k]]
            if met:
                touched.append((met[0], area))
                pairs += zip(met, met[1:])
        # each class of doors named by its lowest door, so ties break the same way always
        name = _components(len(self.labels), pairs)
        for group in self.groups:
            classes = {name[k] for k in group if reached[k]}
            if len(classes) == 1 and all(reached[k] for k in group):
                continue
            class_area = dict.fromkeys(classes, 0.0)
            for k, area in touched:
                if name[k] in class_area:
                    class_area[name[k]] += area
            largest = sorted(class_area.values())[-2:]
            if sure and len(largest) == 2 and largest[1] - largest[0] <= 2 * sure:
                return _UNSURE
            main = max(classes, key=lambda c: (class_area[c], -c), default=-1)
            cut = next(k for k in group if not reached[k] or name[k] != main)
            return Blockage("door", self.labels[cut])
        return None


def _parts(geometry: BaseGeometry) -> tuple[np.ndarray, list[float]]:
    """The polygons of ``geometry`` with an area, and their areas."""
    if isinstance(geometry, Polygon):  # the usual case, without get_parts' overhead
        parts = np.empty(1, dtype=object)
        parts[0] = geometry
        area = geometry.area
        return (parts, [area]) if area > 0 else (parts[:0], [])
    parts = shapely.get_parts(geometry)
    areas = shapely.area(parts)
    return parts[areas > 0], areas[areas > 0].tolist()


def _meets(pieces: np.ndarray, zones: np.ndarray) -> np.ndarray:
    """``bool[piece, zone]``: the piece meets the zone."""
    if not len(pieces) or not len(zones):
        return np.zeros((len(pieces), len(zones)), dtype=bool)
    return shapely.intersects(pieces[:, None], zones[None, :])


def _meet(a: Box, b: Box) -> bool:
    """Whether two boxes meet (touching counts)."""
    return a[0] <= b[2] and a[2] >= b[0] and a[1] <= b[3] and a[3] >= b[1]


def _less(pieces: _Pieces, cut: Box, removed: float) -> _Pieces | None:
    """``pieces`` with ``removed`` m² taken from the one piece ``cut`` meets (None when
    ``cut`` meets more than one)."""
    near = [k for k, b in enumerate(pieces.bounds) if _meet(cut, b)]
    if len(near) > 1:
        shape = shapely.box(*cut)
        near = [k for k in near if pieces.shapes[k].intersects(shape)]
    if len(near) != 1:
        return pieces if not near and removed == 0 else None
    if pieces.updates == _UPDATES:
        return None
    areas = list(pieces.areas)
    areas[near[0]] -= removed
    return _Pieces(pieces.shapes, areas, pieces.meets, pieces.bounds, pieces.updates + 1)


def _clipped_area(geometry: BaseGeometry, box: Box) -> float:
    """The area of ``geometry`` inside ``box`` (a rectangle clip: exact, and linear in
    the vertices without the overlay's graph)."""
    return float(shapely.clip_by_rect(geometry, *box).area)


def _outside_box(room: Box, box: Box) -> list[list[Box]]:
    """Where ``box`` meets the plane around the box ``room`` (outside it, closed): the
    parts of ``box`` beyond each side of ``room``, grouped into connected places. The
    parts beyond two adjacent sides meet; those beyond opposite sides only through a
    third."""
    x0, z0, x1, z1 = box
    left = (x0, z0, min(x1, room[0]), z1) if x0 <= room[0] else None
    right = (max(x0, room[2]), z0, x1, z1) if x1 >= room[2] else None
    bottom = (x0, z0, x1, min(z1, room[1])) if z0 <= room[1] else None
    top = (x0, max(z0, room[3]), x1, z1) if z1 >= room[3] else None
    if left and right and not (bottom or top):
        return [[left], [right]]
    if bottom and top and not (left or right):
        return [[bottom], [top]]
    return [[part for part in (left, right, bottom, top) if part]]


def _touching_pairs(shapes: np.ndarray) -> list[tuple[int, int]]:
    if len(shapes) < 2:
        return []
    a, b = np.nonzero(np.triu(shapely.intersects(shapes[:, None], shapes[None, :]), 1))
    return list(zip(a.tolist(), b.tolist()))


def _components(n: int, pairs: Iterable[tuple[int, int]]) -> list[int]:
    """The connected components of nodes ``0 .. n-1`` joined by ``pairs``: each node's
    lowest fellow."""
    parent = list(range(n))

    def root(a: int) -> int:
        while parent[a] != a:
            parent[a] = a = parent[parent[a]]
        return a

    for a, b in pairs:
        ra, rb = root(a), root(b)
        if ra != rb:  # the lower root stays a root, so a root is its component's lowest
            parent[max(ra, rb)] = min(ra, rb)
    return [root(a) for a in range(n)]


def _groups(meets: np.ndarray) -> list[list[int]]:
    """Doors connected in the empty room, as sorted lists of door indices ordered by
    their lowest door (more than one door each: a door alone cannot be cut off from
    itself)."""
    pairs: list[tuple[int, int]] = []
    for row in meets:
        met = np.flatnonzero(row).tolist()
        pairs += zip(met, met[1:])
    name = _components(meets.shape[1], pairs)
    members: dict[int, list[int]] = {}
    for k, lowest in enumerate(name):
        members.setdefault(lowest, []).append(k)
    return sorted(g for g in members.values() if len(g) > 1)
