"""The furniture of one room while it is being placed: exact conflict tests and sweeps.

A :class:`Layout` holds the room's free floor, its door keep-out zones and window strips,
and the items placed so far (body and clearance boxes, :mod:`.clearance`). It answers two
questions exactly, with shapely polygons indexed by a :class:`shapely.STRtree`:

* :meth:`Layout.conflicts`: what blocks an item at a given pose;
* :meth:`Layout.free_intervals`: for an item sliding along the x or z axis, every centre
  coordinate at which nothing blocks it. This replaces the thesis' stepwise movement of
  clones (thesis §5.3.2): each obstacle forbids one open interval of positions, found by
  clipping the obstacle with the strip the item sweeps and projecting the pieces.

What blocks what (docs/furniture.md):

* the walls (everything outside the free floor) block bodies and clearance boxes;
* a solid item's body blocks other bodies and clearance boxes;
* a clearance box blocks other bodies, except those of the item's own parent or
  children (chairs stand in the table's clearance, the coffee table in the sofa's);
* door keep-out zones block bodies; window strips block the bodies of ``canCloseWindow``
  items;
* non-colliding items (rugs) block nothing and are blocked only by the walls;
* with a :class:`~.passage.Passage`, a solid item that would cut a door off from the
  others, or wall off a pocket of the room, is blocked too. That test runs last, only for
  a pose nothing else blocks, and :meth:`Layout.free_intervals` leaves it out (callers
  test the positions they pick with :meth:`Layout.conflicts`).

Touching is allowed: boxes are shrunk by :data:`EPS` before testing, so two items may
share an edge and a wall item may stand flush against its wall.
"""

from __future__ import annotations

from collections.abc import Callable, Hashable, Sequence
from dataclasses import dataclass, replace
from functools import cached_property, lru_cache
from typing import TypeVar

import numpy as np
import shapely
from shapely import affinity
from shapely.geometry import Polygon

from .clearance import Box, EnvelopePart, Keepout, OpeningStrip, envelope
from .obstacles import BODY, CLEARANCE, DOOR, WALL, ObstacleBlock, ObstacleIndex, complement
from .passage import Passage
from .rules import FurnitureRule

__all__ = ["EPS", "ItemSpec", "Pose", "Conflict", "Layout", "body_polygon", "nearest_in"]

EPS = 1e-6
"""Boxes are shrunk by this much (m) before intersection tests: touching is not overlap."""

_AREA_EPS = 1e-12
_MAX_PARTS = 8
"""More than the parts of an envelope (a body and four clearance boxes)."""
_FEW_HITS = 16
"""Up to this many obstacles met, a query tests them one by one; past it, with numpy."""
_KEPT_POSES = 4096
"""Poses (and segments) whose parts an item keeps (:meth:`ItemSpec.parts_at`,
:meth:`ItemSpec.strips`); past it they are dropped."""
_KEPT_INDEXES = 256
"""Obstacle indexes a room's layouts keep (:meth:`Layout._index`)."""

_K = TypeVar("_K", bound=Hashable)
_V = TypeVar("_V")


@dataclass(frozen=True)
class ItemSpec:
    """An item to place: its rule (distances in metres) and its model's size in metres."""

    rule: FurnitureRule
    model: str
    size: tuple[float, float, float]

    @property
    def name(self) -> str:
        return self.rule.name

    @property
    def width(self) -> float:
        return self.size[0]

    @property
    def depth(self) -> float:
        return self.size[2]

    def parts(self, rotation: int) -> tuple[EnvelopePart, ...]:
        """Body and clearance boxes relative to the centre (see :func:`.clearance.envelope`)."""
        return self._parts[rotation % 4]

    def boxes(self, rotation: int) -> np.ndarray:
        """The boxes of :meth:`parts` as a ``(parts, 4)`` array (made once per shape)."""
        return self._boxes[rotation % 4]

    def extent(self, rotation: int) -> Box:
        """The box around :meth:`parts`, relative to the centre: what must fit between
        the walls (made once per shape; the placement asks for it at every wall and
        corner)."""
        return self._extents[rotation % 4]

    def parts_at(self, rotation: int, x: float, z: float) -> PartsAt:
        """The parts at ``(x, z)`` turned by ``rotation`` (no free yaw), made once per
        pose: the solver tests most poses more than once (a spot for item after item,
        a child's spot for each candidate pose of its parent) and adds the ones it
        tested, and shapely boxes cost more than the look-up."""
        return _kept(self._poses, (rotation % 4, x, z), _KEPT_POSES,
                     lambda: PartsAt(_part_boxes(self.boxes(rotation), x, z)))

    def strips(self, rotation: int, axis: int, fixed: float, lo: float, hi: float) -> Strips:
        """The strips the parts sweep with the centre sliding along ``axis`` from ``lo``
        to ``hi`` (:meth:`Layout.free_intervals`), made once per segment: the solver
        sweeps most segments more than once (the same wall for item after item)."""
        def make() -> Strips:
            return Strips.make(self.boxes(rotation), axis, fixed, lo, hi)

        if not _same_strips(lo, hi):
            return make()
        return _kept(self._strips, (rotation % 4, axis, fixed, lo, hi), _KEPT_POSES, make)

    # the solver asks for an item's parts thousands of times: kept on the item, so a call
    # is a tuple index rather than a cache look-up keyed by six numbers
    @cached_property
    def _parts(self) -> tuple[tuple[EnvelopePart, ...], ...]:
        r = self.rule
        return tuple(_envelope(self.width, self.depth, rotation, r.clearance_front,
                               r.clearance_back, r.clearance_side) for rotation in range(4))

    @cached_property
    def _boxes(self) -> tuple[np.ndarray, ...]:
        r = self.rule
        return tuple(_envelope_boxes(self.width, self.depth, rotation, r.clearance_front,
                                     r.clearance_back, r.clearance_side)
                     for rotation in range(4))

    @cached_property
    def _extents(self) -> tuple[Box, ...]:
        extents = []
        for rotation in range(4):
            boxes = [part.box for part in self.parts(rotation)]
            extents.append((min(b[0] for b in boxes), min(b[1] for b in boxes),
                            max(b[2] for b in boxes), max(b[3] for b in boxes)))
        return tuple(extents)

    @cached_property
    def _poses(self) -> dict[tuple[int, float, float], PartsAt]:
        return {}

    @cached_property
    def _strips(self) -> dict[tuple[int, int, float, float, float], Strips]:
        return {}


def _kept(store: dict[_K, _V], key: _K, limit: int, make: Callable[[], _V]) -> _V:
    """``store[key]``, made by ``make`` on first use; a store of ``limit`` entries is
    emptied first (a room's solver comes back to recent keys, rarely to old ones)."""
    found = store.get(key)
    if found is None:
        if len(store) >= limit:
            store.clear()
        found = store[key] = make()
    return found


def _same_strips(lo: float, hi: float) -> bool:
    """Whether the strips swept over ``[lo, hi]`` are those of any equal ``lo`` and
    ``hi``: unless one is zero, whose sign would carry into the strips of an item with a
    side at its centre (of size zero)."""
    return bool(lo and hi)


class PartsAt:
    """An item's parts at one pose without a free yaw (:meth:`ItemSpec.parts_at`).

    A plain class with slots: one is made for each pose tested, most of them never
    tested again in a crowded room, where a dataclass' cost per instance showed."""

    __slots__ = ("shapes", "blocks", "_bounds")

    def __init__(self, shapes: np.ndarray):
        self.shapes = shapes
        """The parts as shapely boxes shrunk by :data:`EPS` (:func:`_part_boxes`; never
        written)."""
        self.blocks: dict[int, ObstacleBlock] = {}
        """The obstacles they make in a layout, by the item's id there
        (:meth:`Layout.add`)."""
        self._bounds: np.ndarray | None = None

    @property
    def bounds(self) -> np.ndarray:
        """The bounds of :attr:`shapes`, ``(parts, 4)`` (made when the item is added)."""
        if self._bounds is None:
            self._bounds = shapely.bounds(self.shapes)
        return self._bounds


@dataclass(frozen=True)
class Strips:
    """The strips an item's parts sweep along one segment (:meth:`ItemSpec.strips`)."""

    shapes: np.ndarray
    """Per part, the box its centre line sweeps, shrunk by :data:`EPS` across (never
    written)."""
    bounds: np.ndarray
    """Their bounds, ``(parts, 4)``."""
    rows: list[list[float]]
    """:attr:`bounds` as lists."""

    @classmethod
    def make(cls, boxes: np.ndarray, axis: int, fixed: float, lo: float, hi: float
             ) -> "Strips":
        a0, a1 = (boxes[:, 0], boxes[:, 2]) if axis == 0 else (boxes[:, 1], boxes[:, 3])
        p0, p1 = (boxes[:, 1], boxes[:, 3]) if axis == 0 else (boxes[:, 0], boxes[:, 2])
        along = (lo + a0, hi + a1)
        across = (fixed + p0 + EPS, fixed + p1 - EPS)
        shapes = (shapely.box(along[0], across[0], along[1], across[1]) if axis == 0
                  else shapely.box(across[0], along[0], across[1], along[1]))
        bounds = shapely.bounds(shapes)
        return cls(shapes, bounds, bounds.tolist())


@lru_cache(maxsize=4096)
def _envelope(width: float, depth: float, rotation: int, front: float, back: float,
              side: float) -> tuple[EnvelopePart, ...]:
    return envelope(width, depth, rotation, front=front, back=back, side=side)


@lru_cache(maxsize=4096)
def _envelope_boxes(width: float, depth: float, rotation: int, front: float, back: float,
                    side: float) -> np.ndarray:
    boxes = np.array([p.box for p in _envelope(width, depth, rotation, front, back, side)])
    boxes.flags.writeable = False
    return boxes


@dataclass(frozen=True)
class Pose:
    """Where an item stands: the centre of its footprint, its quarter turns and a free
    ``yaw`` beyond them (radians, right-handed about +y; only the disorder of movable
    items sets it, :mod:`.disorder`)."""

    x: float
    z: float
    rotation: int
    yaw: float = 0.0

    def moved(self, axis: int, value: float) -> "Pose":
        """A copy with the centre coordinate ``axis`` (0 = x, 1 = z) set to ``value``."""
        return replace(self, x=value) if axis == 0 else replace(self, z=value)


@dataclass(frozen=True)
class Conflict:
    """Part ``part`` of an item is blocked by ``blocker`` (an item name or a label) of
    kind ``"wall"``, ``"body"``, ``"clearance"``, ``"door"`` or ``"window"``; or the item
    breaks the passage rule: kind ``"passage"`` (``blocker`` names the door it would cut
    off) or ``"pocket"`` (``blocker`` is the share of the floor it would wall off)."""

    part: str
    kind: str
    blocker: str

    def describe(self) -> str:
        """A short reason, e.g. ``"clearance front blocked by sofa"``."""
        if self.part != "body":
            what = "a wall" if self.kind == "wall" else self.blocker
            return f"clearance {self.part} blocked by {what}"
        return {
            "wall": "does not fit between the walls",
            "body": f"overlaps {self.blocker}",
            "clearance": f"stands in the clearance of {self.blocker}",
            "door": f"blocks {self.blocker}",
            "window": f"covers {self.blocker}",
            "passage": f"would block the passage to {self.blocker}",
            "pocket": f"would wall off {self.blocker} of the free floor from the doors",
        }[self.kind]


def _rectangle(geometry: Polygon) -> Box | None:
    """The bounds when ``geometry`` is an axis-aligned rectangle, else None."""
    minx, miny, maxx, maxy = geometry.bounds
    if len(geometry.interiors) or abs(geometry.area - (maxx - minx) * (maxy - miny)) > _AREA_EPS:
        return None
    return (minx, miny, maxx, maxy)


def _part_boxes(boxes: np.ndarray, x: float, z: float) -> np.ndarray:
    """The part ``boxes`` (:meth:`ItemSpec.boxes`) placed at ``(x, z)`` as shapely boxes
    shrunk by :data:`EPS`."""
    b = boxes + np.array([x + EPS, z + EPS, x - EPS, z - EPS])
    return shapely.box(b[:, 0], b[:, 1], b[:, 2], b[:, 3])


def _part_shapes(spec: ItemSpec, pose: Pose) -> np.ndarray:
    """The parts of ``spec`` placed at ``pose`` (shrunk by :data:`EPS`)."""
    if not pose.yaw:
        return spec.parts_at(pose.rotation, pose.x, pose.z).shapes
    return _turned(spec.boxes(pose.rotation), pose)


def _turned(boxes: np.ndarray, pose: Pose) -> np.ndarray:
    """The part ``boxes`` placed at ``pose`` (shrunk by :data:`EPS`), turned by its free
    yaw about the item's centre (the sense of :meth:`cga.model.FurnitureItem.footprint`)."""
    return np.array([affinity.rotate(b, -pose.yaw, origin=(pose.x, pose.z), use_radians=True)
                     for b in _part_boxes(boxes, pose.x, pose.z)], dtype=object)


def _footprint(spec: ItemSpec, pose: Pose) -> Box:
    """The body box of ``spec`` placed at ``pose``, exact; for a pose with a free yaw,
    the bounds of the turned body (the passage rule then sees a slightly larger
    obstacle, never a smaller one)."""
    b = spec.parts(pose.rotation)[0].box
    if pose.yaw:
        minx, minz, maxx, maxz = _turned(spec.boxes(pose.rotation)[:1], pose)[0].bounds
        return (minx - EPS, minz - EPS, maxx + EPS, maxz + EPS)
    return (pose.x + b[0], pose.z + b[1], pose.x + b[2], pose.z + b[3])


def body_polygon(spec: ItemSpec, pose: Pose) -> Polygon:
    """The exact footprint of ``spec`` at ``pose`` (turned by its free yaw)."""
    b = spec.parts(pose.rotation)[0].box
    body = shapely.box(pose.x + b[0], pose.z + b[1], pose.x + b[2], pose.z + b[3])
    if pose.yaw:
        body = affinity.rotate(body, -pose.yaw, origin=(pose.x, pose.z), use_radians=True)
    return body


def _outside_pieces(interior: Polygon, margin: float = 1.0) -> list[Polygon]:
    """The region around ``interior`` (out to ``margin``) as hole-free pieces: the frame
    cut into vertical slabs at every vertex x. Clipping a strip against these is far
    cheaper than against one polygon with a hole."""
    minx, minz, maxx, maxz = interior.bounds
    xs = sorted({minx - margin, maxx + margin, *(x for x, _ in interior.exterior.coords)})
    slabs = shapely.box(np.array(xs[:-1]), minz - margin, np.array(xs[1:]), maxz + margin)
    pieces = shapely.get_parts(shapely.difference(slabs, interior))
    return [p for p in pieces if p.area > _AREA_EPS]


def nearest_in(intervals: list[tuple[float, float]], preferred: float) -> float | None:
    """The point of the closed ``intervals`` nearest to ``preferred`` (None if empty)."""
    best, best_distance = None, float("inf")
    for lo, hi in intervals:
        value = min(max(preferred, lo), hi)
        if abs(value - preferred) < best_distance:
            best, best_distance = value, abs(value - preferred)
    return best


class Layout:
    """The items placed in one room so far; see the module docstring.

    Parameters
    ----------
    interior:
        The room's free floor.
    keepouts:
        Door keep-out zones in this room.
    windows:
        The room's windows.
    passage:
        The room's passage rule; None: none.
    """

    def __init__(self, interior: Polygon, keepouts: Sequence[Keepout] = (),
                 windows: Sequence[OpeningStrip] = (), passage: Passage | None = None):
        self.interior = interior
        self._ids: dict[str, int] = {}
        self._names: list[str] = []
        walls = _outside_pieces(interior)
        self._static = self._block(
            [WALL] * len(walls) + [DOOR] * len(keepouts),
            ["a wall"] * len(walls) + [k.label for k in keepouts],
            np.array([*walls, *(k.polygon for k in keepouts)], dtype=object))
        self.windows = tuple(windows)
        self.passage = passage if passage is not None and passage.active else None
        self.placed: dict[str, tuple[ItemSpec, Pose]] = {}
        self._item_blocks: dict[str, ObstacleBlock] = {}
        self._footprints: dict[str, Box] = {}
        self._obstacle_set: frozenset[Box] | None = None
        self._obstacles: ObstacleIndex | None = None
        self._indexes: dict[tuple[ObstacleBlock, ...], ObstacleIndex] = {}
        self._last: tuple[tuple[ObstacleBlock, ...], ObstacleIndex] | None = None
        self._window_zones: dict[float, list[tuple[str, Polygon]]] = {}

    def emptied(self) -> "Layout":
        """An empty layout of the same room: the walls, door zones, windows and passage
        rule are shared, not made again (the solver's attempts start from this), and so
        are the obstacle indexes and window strips kept."""
        empty = object.__new__(Layout)
        empty.__dict__.update(self.__dict__)
        empty._ids, empty._names = dict(self._ids), list(self._names)
        empty.placed, empty._item_blocks, empty._footprints = {}, {}, {}
        empty._changed()
        return empty

    def _id(self, name: str) -> int:
        """A stable integer for an item name or a label (the owner column)."""
        if name not in self._ids:
            self._ids[name] = len(self._names)
            self._names.append(name)
        return self._ids[name]

    def _block(self, kinds: list[int], owners: list[str], geometries: np.ndarray,
               bounds: np.ndarray | None = None) -> ObstacleBlock:
        """Obstacles as an :class:`.obstacles.ObstacleBlock`; ``bounds`` when all of
        them are known to be the boxes of their bounds, else each shape is tested."""
        boxes = bounds is not None
        if bounds is None:
            bounds = np.array([_rectangle(g) or (np.nan,) * 4 for g in geometries],
                              dtype=float).reshape(-1, 4)
        return ObstacleBlock.make(kinds, [self._id(o) for o in owners], geometries, bounds,
                                  boxes)

    # -- state ---------------------------------------------------------------------------
    def add(self, spec: ItemSpec, pose: Pose) -> None:
        """Place ``spec`` at ``pose`` (no check; call :meth:`conflicts` first)."""
        self.placed[spec.name] = (spec, pose)
        if not spec.rule.non_collision:
            self._footprints[spec.name] = _footprint(spec, pose)
            self._item_blocks[spec.name] = (
                self._item_block(spec, pose.rotation, _turned(spec.boxes(pose.rotation), pose),
                                 None) if pose.yaw else self._placed_block(spec, pose))
        self._changed()

    def _placed_block(self, spec: ItemSpec, pose: Pose) -> ObstacleBlock:
        """The obstacles of ``spec`` at ``pose`` without a free yaw, made once per pose
        and item id (the solver adds a parent at the same pose again and again while it
        seats the family, :meth:`.placement.Placer._commit`)."""
        parts = spec.parts_at(pose.rotation, pose.x, pose.z)
        owner = self._id(spec.name)
        block = parts.blocks.get(owner)
        if block is None:
            block = parts.blocks[owner] = self._item_block(spec, pose.rotation, parts.shapes,
                                                            parts.bounds)
        return block

    def _item_block(self, spec: ItemSpec, rotation: int, shapes: np.ndarray,
                    bounds: np.ndarray | None) -> ObstacleBlock:
        """The parts ``shapes`` of ``spec`` as obstacles (``bounds``: see :meth:`_block`)."""
        parts = spec.parts(rotation)
        return self._block([BODY if part.is_body else CLEARANCE for part in parts],
                           [spec.name] * len(parts), shapes, bounds)

    def remove(self, name: str) -> tuple[ItemSpec, Pose]:
        """Take an item out again; returns what it was."""
        self._item_blocks.pop(name, None)
        self._footprints.pop(name, None)
        self._changed()
        return self.placed.pop(name)

    def _changed(self) -> None:
        self._obstacles = None
        self._obstacle_set = None

    def pose(self, name: str) -> Pose | None:
        entry = self.placed.get(name)
        return entry[1] if entry else None

    def _index(self) -> ObstacleIndex:
        """The obstacles in the order the old one-by-one scan met them: walls, door
        zones, then the items in the order they were (last) added.

        Kept by its blocks for the layouts of the room (:meth:`emptied` shares them):
        half the states a house's solver queries it had queried before (a parent at a
        pose tried again, a family taken out and put back)."""
        if self._obstacles is None:
            blocks = (self._static, *self._item_blocks.values())
            last = self._last  # the state before an item was added: extended
            base = last[1] if last is not None and last[0] == blocks[:-1] else None
            index = _kept(self._indexes, blocks, _KEPT_INDEXES,
                          lambda: ObstacleIndex(blocks, base))
            self._obstacles = index
            self._last = (blocks, index)
        return self._obstacles

    def _obstacles_without(self, name: str) -> frozenset[Box]:
        """The footprints of the solid items placed, but that of ``name`` (the passage
        rule's obstacles when ``name`` is being placed), kept between changes."""
        if self._obstacle_set is None:
            self._obstacle_set = frozenset(self._footprints.values())
        if name not in self._footprints:
            return self._obstacle_set
        return frozenset(b for n, b in self._footprints.items() if n != name)

    def _windows_for(self, spec: ItemSpec) -> list[tuple[str, Polygon]]:
        """The strips in front of the windows that ``spec`` must not cover, by label;
        kept by their depth for the layouts of the room (:meth:`emptied` shares them)."""
        if not spec.rule.can_close_window or not self.windows:
            return []
        depth = spec.depth + spec.rule.clearance_front
        zones = self._window_zones.get(depth)
        if zones is None:
            zones = self._window_zones[depth] = [(w.label, w.zone(depth)) for w in self.windows]
        return zones

    def _blocking_hits(self, index: ObstacleIndex, spec: ItemSpec, part_rows: np.ndarray,
                       rows: np.ndarray, related: frozenset[str], *, first: bool = False
                       ) -> list[tuple[int, int]]:
        """The hits ``(part_rows, rows)`` that block ``spec`` (docs/furniture.md), as
        ``(row, part)`` by row, then part (with ``first``, the first of them only):
        numpy for many hits (a crowded room), a plain loop for the few of an ordinary
        room, where numpy's cost per call dominates."""
        if len(rows) > _FEW_HITS:
            rows, part_rows = self._blocking_rows(index, spec, part_rows, rows, related)
            keys = rows * _MAX_PARTS + part_rows
            order = (keys.min(keepdims=True) if first and len(keys) else np.sort(keys))
            return [divmod(k, _MAX_PARTS) for k in order.tolist()]
        family = [self._ids[n] for n in related if n in self._ids]
        return sorted(index.blocking_few(part_rows.tolist(), rows.tolist(),
                                         self._ids.get(spec.name, -1), spec.rule.non_collision,
                                         family))

    def _blocking_rows(self, index: ObstacleIndex, spec: ItemSpec, part_rows: np.ndarray,
                       rows: np.ndarray, related: frozenset[str]
                       ) -> tuple[np.ndarray, np.ndarray]:
        """The hits that block ``spec`` among many, ``(rows, part_rows)`` in query order."""
        blocking = index.blocking(rows, part_rows == 0, self._ids.get(spec.name, -1),
                                  spec.rule.non_collision,
                                  [self._ids[n] for n in related if n in self._ids])
        return rows[blocking], part_rows[blocking]

    # -- queries -------------------------------------------------------------------------
    def conflicts(self, spec: ItemSpec, pose: Pose, related: frozenset[str] = frozenset(),
                  *, first: bool = False) -> list[Conflict]:
        """What blocks ``spec`` at ``pose``; ``related`` names its parent and children.

        With ``first=True`` the search stops at the first conflict found (walls first).

        The obstacles and windows met are kept with the state's index (a third of the
        questions a house's solver asks repeat one asked of the same state); the passage
        rule, which keeps its own answers, is asked each time as before.
        """
        index = self._index()
        key = ("conflicts", id(spec), pose.x, pose.z, pose.rotation, pose.yaw, related, first)
        kept = index.answers.get(key)
        if kept is None:  # kept with the item, whose id then stays its own
            kept = index.answers[key] = (spec, self._blockers(index, spec, pose, related,
                                                              first))
        found = list(kept[1])
        if not found and self.passage is not None and not spec.rule.non_collision:
            blockage = self.passage.blockage(self._obstacles_without(spec.name),
                                             _footprint(spec, pose))
            if blockage is not None:
                found.append(Conflict("body", "passage" if blockage.kind == "door" else
                                      "pocket", blockage.what))
        return found

    def _blockers(self, index: ObstacleIndex, spec: ItemSpec, pose: Pose,
                  related: frozenset[str], first: bool) -> tuple[Conflict, ...]:
        """The obstacles and windows that block ``spec`` at ``pose`` (:meth:`conflicts`
        without the passage rule)."""
        parts = spec.parts(pose.rotation)
        geometries = _part_shapes(spec, pose)
        found: list[Conflict] = []
        part_rows, rows = index.hits(geometries, boxes=not pose.yaw)
        if len(rows):
            for row, part in self._blocking_hits(index, spec, part_rows, rows, related,
                                                 first=first):
                found.append(Conflict(parts[part].kind, index.kind(row),
                                      self._names[index.owner(row)]))
                if first:  # the first by obstacle, then part (walls come first)
                    return tuple(found)
        for label, zone in self._windows_for(spec):
            if zone.intersects(geometries[0]):
                found.append(Conflict("body", "window", label))
                if first:
                    break
        return tuple(found)

    def blocked_by_room(self, spec: ItemSpec, pose: Pose) -> bool:
        """Whether the room itself (walls, door zones, windows) blocks ``spec`` at
        ``pose``: :meth:`conflicts` of an empty layout without the passage rule, which
        holds in every layout of the room."""
        assert not self.placed
        return bool(self._blockers(self._index(), spec, pose, frozenset(), True))

    def fits(self, spec: ItemSpec, pose: Pose, related: frozenset[str] = frozenset()) -> bool:
        """True when nothing blocks ``spec`` at ``pose``."""
        return not self.conflicts(spec, pose, related, first=True)

    def free_intervals(self, spec: ItemSpec, rotation: int, axis: int, fixed: float,
                       lo: float, hi: float, related: frozenset[str] = frozenset()
                       ) -> list[tuple[float, float]]:
        """Centre coordinates along ``axis`` in ``[lo, hi]`` where nothing blocks ``spec``.

        Parameters
        ----------
        spec, rotation:
            The item and its quarter turns.
        axis:
            0 to slide along x (the centre's z is ``fixed``), 1 to slide along z.
        lo, hi:
            The range of the sliding centre coordinate.
        related:
            The item's parent and children (see :meth:`conflicts`).

        Returns
        -------
        list of (start, end)
            Disjoint closed intervals in increasing order (a single free position gives a
            zero-length interval).

        Notes
        -----
        Exact: every obstacle clipped to the strip a part sweeps forbids the open interval
        of centres at which the part overlaps it. Cost O(k log n) for k obstacles near the
        strip among n. The forbidden intervals are kept with the state's index (half the
        sweeps of a house's solver repeat one of the same state).
        """
        if hi < lo:
            return []
        index = self._index()
        key = ("intervals", id(spec), rotation, axis, fixed, lo, hi, related)
        keep = _same_strips(lo, hi)
        kept = index.answers.get(key) if keep else None
        if kept is None:  # kept with the item, whose id then stays its own
            kept = (spec, self._forbidden(index, spec, rotation, axis, fixed, lo, hi, related))
            if keep:
                index.answers[key] = kept
        forbidden = kept[1]
        if isinstance(forbidden, list):
            return _complement_few(forbidden, lo, hi)
        starts, ends = forbidden
        return complement(starts, ends, lo, hi)

    def _forbidden(self, index: ObstacleIndex, spec: ItemSpec, rotation: int, axis: int,
                   fixed: float, lo: float, hi: float, related: frozenset[str]
                   ) -> list[tuple[float, float]] | tuple[np.ndarray, np.ndarray]:
        """The open intervals of centres where something blocks ``spec`` sliding along
        ``axis`` over ``[lo, hi]`` (:meth:`free_intervals`): a list when few, else
        ``(starts, ends)`` arrays."""
        boxes = spec.boxes(rotation)
        a0, a1 = (boxes[:, 0], boxes[:, 2]) if axis == 0 else (boxes[:, 1], boxes[:, 3])
        swept = spec.strips(rotation, axis, fixed, lo, hi)
        strips, strip_bounds = swept.shapes, swept.bounds
        part_rows, rows = index.hits(strips, boxes=True)
        windows = [zone for _, zone in self._windows_for(spec) if zone.intersects(strips[0])]
        # in any order: the complement sorts the spans
        if len(rows) > _FEW_HITS:
            rows, part_rows = self._blocking_rows(index, spec, part_rows, rows, related)
            hits = None
        else:
            hits = self._blocking_hits(index, spec, part_rows, rows, related)
        if (len(rows) if hits is None else len(hits)) + len(windows) <= _FEW_HITS:
            if hits is None:
                hits = list(zip(rows.tolist(), part_rows.tolist()))
            spans = self._spans_few(index, hits, windows, strips, swept.rows, axis)
            return [(s0 - a1[i], s1 - a0[i]) for i, s0, s1 in spans]
        if hits is not None:
            rows = np.array([row for row, _ in hits], dtype=np.int64)
            part_rows = np.array([part for _, part in hits], dtype=np.int64)
        rectangle = index.is_rectangle[rows]
        rect_parts, rect_bounds = part_rows[rectangle], index.bounds[rows[rectangle]]
        shape_parts = part_rows[~rectangle].tolist()
        shapes = index.geometries[rows[~rectangle]].tolist()
        for zone in windows:
            zone_bounds = _rectangle(zone)
            if zone_bounds is None:
                shape_parts.append(0)
                shapes.append(zone)
            else:
                rect_parts = np.append(rect_parts, 0)
                rect_bounds = np.vstack([rect_bounds, zone_bounds])
        span_parts, span_lo, span_hi = _clip_rectangles(rect_parts, rect_bounds, strip_bounds,
                                                        axis)
        if shapes:
            shape_spans = _clip_shapes(shape_parts, shapes, strips, axis)
            span_parts = np.concatenate([span_parts, [i for i, _, _ in shape_spans]])
            span_lo = np.concatenate([span_lo, [v for _, v, _ in shape_spans]])
            span_hi = np.concatenate([span_hi, [v for _, _, v in shape_spans]])
        span_parts = span_parts.astype(np.int64)
        return span_lo - a1[span_parts], span_hi - a0[span_parts]

    @staticmethod
    def _spans_few(index: ObstacleIndex, hits: list[tuple[int, int]], windows: list[Polygon],
                   strips: np.ndarray, strip_bounds: list[list[float]], axis: int
                   ) -> list[tuple[int, float, float]]:
        """The few blocking ``hits`` and window ``windows`` clipped to the strips of their
        parts, one by one: ``(part, start, end)`` along ``axis``."""
        rectangles: list[tuple[int, Box]] = []
        shapes: list[tuple[int, Polygon]] = []
        for row, part in hits:
            if index.is_rectangle[row]:
                rectangles.append((part, index.bounds[row].tolist()))
            else:
                shapes.append((part, index.geometries[row]))
        for zone in windows:
            zone_bounds = _rectangle(zone)
            if zone_bounds is None:
                shapes.append((0, zone))
            else:
                rectangles.append((0, zone_bounds))
        spans: list[tuple[int, float, float]] = []
        for i, r in rectangles:  # clipping a rectangle is bounds arithmetic
            b = strip_bounds[i]
            c = (max(r[0], b[0]), max(r[1], b[1]), min(r[2], b[2]), min(r[3], b[3]))
            if (c[2] - c[0]) * (c[3] - c[1]) > _AREA_EPS and c[2] > c[0] and c[3] > c[1]:
                spans.append((i, c[axis], c[axis + 2]))
        if shapes:
            spans += _clip_shapes([i for i, _ in shapes], [g for _, g in shapes], strips, axis)
        return spans


def _clip_shapes(parts: list[int], shapes: list[Polygon], strips: np.ndarray, axis: int
                 ) -> list[tuple[int, float, float]]:
    """Obstacles that are not axis-aligned rectangles clipped exactly to the strips of
    their parts: ``(part, start, end)`` along ``axis`` of each piece with an area."""
    index = np.array(parts, dtype=np.int64)
    clipped = shapely.intersection(np.array(shapes, dtype=object), strips[index])
    pieces, owner = shapely.get_parts(clipped, return_index=True)
    keep = shapely.area(pieces) > _AREA_EPS
    return [(int(i), b[axis], b[axis + 2])
            for i, b in zip(index[owner[keep]], shapely.bounds(pieces[keep]).tolist())]


def _complement_few(forbidden: list[tuple[float, float]], lo: float, hi: float
                    ) -> list[tuple[float, float]]:
    """:func:`.obstacles.complement` for a few intervals, in plain Python."""
    free = []
    cursor = lo  # the smallest point not known to be forbidden
    for start, end in sorted(forbidden):
        if cursor > hi:
            break
        if start >= cursor:
            free.append((cursor, min(start, hi)))
        cursor = max(cursor, end)
    if cursor <= hi:
        free.append((cursor, hi))
    return free

def _clip_rectangles(parts: np.ndarray, bounds: np.ndarray, strip_bounds: np.ndarray,
                     axis: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Clip each rectangle ``bounds[k]`` to the strip of its part ``parts[k]``: the parts
    whose strip it overlaps with an area, and the extent of the overlap along ``axis``
    (start, end). Bounds arithmetic; ties keep the rectangle's own coordinate, as
    Python's ``max``/``min`` do."""
    strips = strip_bounds[parts]
    clipped = np.where((strips - bounds) * _INWARD > 0, strips, bounds)
    size = clipped[:, 2:] - clipped[:, :2]
    keep = (size[:, 0] * size[:, 1] > _AREA_EPS) & (size > 0).all(axis=1)
    return parts[keep], clipped[keep, axis], clipped[keep, axis + 2]


_INWARD = np.array([1.0, 1.0, -1.0, -1.0])
"""Signs that make "the strip's side lies inside the rectangle's" a positive difference."""
