"""Placing one item by its rule: corner, wall, around / beside / in front of a parent.

The strategies follow the thesis (§5.3.2-5.3.3, figures 3.3 and 3.4) with exact geometry
instead of stepwise movement (:meth:`.layout.Layout.free_intervals`):

* **corner** items try each convex corner of the free floor, nearest first, in both
  orientations (back against one wall or the other), flush with both walls after their
  clearances;
* **wall** items go to the nearest wall long enough for them, back to the wall (a side,
  for ``needsTurn``), front into the room, and slide along it to the free position
  nearest their start; then the next wall;
* **children** stand relative to their placed parent: ``canBeAround`` on the parent's
  free sides, facing it, spread evenly when several share a side (chairs round a table);
  ``isOnTheSide`` right beside it, same orientation, backs aligned (a nightstand by a
  bed); otherwise in front of it, facing it, ``minPairDistance``..``maxPairDistance``
  away (a coffee table), or against the wall opposite the parent when the child is a
  wall item (a tv board). A parent with no other children then shifts sideways to face
  such a child when that keeps everything valid;
* **free** items (no placement flag) stand at the free spot nearest their start;
* **non-colliding** items (rugs) lie in the middle of the room.

A strategy either places the item in the :class:`~.layout.Layout` or returns the reason
it could not, naming what blocked it. A pose that is free but breaks the passage rule
(:mod:`.passage`) is passed over like a blocked one, and the next is tried; when nothing
works and such a pose was seen, the reason says so too ("... ; where it fits, it would
block the passage to door 3").
"""

from __future__ import annotations

import math
from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from functools import cached_property
from typing import NamedTuple

import numpy as np
from shapely.geometry import Polygon
from shapely.geometry.polygon import orient

from cga.model import front_vector

from .clearance import Box, quarter_turn_towards
from .layout import Conflict, ItemSpec, Layout, Pose, nearest_in

__all__ = ["Edge", "Corner", "room_edges", "convex_corners", "Placer", "flush", "flush_box"]

_TOLERANCE = 1e-9
_FREE_SAMPLES = 8
"""Random extra start points a free-standing item tries when its own start is blocked."""
_LOOKAHEAD = 16
"""Candidate poses a parent tries for a place where all its children fit."""
_PASSAGE_KINDS = ("passage", "pocket")


def _side_normals(rotation: int) -> tuple[np.ndarray, ...]:
    f = np.array(front_vector(rotation))
    f.flags.writeable = False
    s = np.array([-f[1], f[0]])
    s.flags.writeable = False
    back, other_flank = -f, -s
    back.flags.writeable = other_flank.flags.writeable = False
    return f, back, s, other_flank


_SIDES = tuple(_side_normals(rotation) for rotation in range(4))
"""Per quarter turn, an item's side normals: front, back, then its two flanks (made
once: the solver asks for them for every child it seats; read-only, being shared)."""


@dataclass(frozen=True)
class Edge:
    """A straight piece of a room's free-floor boundary with the normal into the room.

    ``axis`` is 0 for an edge along x, 1 along z and None for a slanted edge (furniture
    turns in quarter turns, so only axis-aligned edges take wall items).
    """

    start: tuple[float, float]
    end: tuple[float, float]

    @cached_property
    def direction(self) -> np.ndarray:
        d = np.subtract(self.end, self.start)
        return d / np.linalg.norm(d)

    @cached_property
    def normal(self) -> np.ndarray:
        d = self.direction
        return np.array([-d[1], d[0]])  # left of a counter-clockwise ring: inward

    @cached_property
    def length(self) -> float:
        return math.dist(self.start, self.end)

    @cached_property
    def facing(self) -> int:
        """The quarter turns of an item with its back to this edge (front into the room)."""
        return quarter_turn_towards(self.normal)

    @cached_property
    def along(self) -> tuple[int, int]:
        """The quarter turns of an item facing along this edge, forwards and backwards."""
        return (quarter_turn_towards(self.direction), quarter_turn_towards(-self.direction))

    @cached_property
    def axis(self) -> int | None:
        dx, dz = np.subtract(self.end, self.start)
        if abs(dz) <= _TOLERANCE * max(1.0, abs(dx)):
            return 0
        if abs(dx) <= _TOLERANCE * max(1.0, abs(dz)):
            return 1
        return None

    @cached_property
    def line(self) -> float:
        """The edge's constant coordinate (z for an edge along x, x along z)."""
        return self.start[1] if self.axis == 0 else self.start[0]

    @cached_property
    def span(self) -> tuple[float, float]:
        """The edge's extent along its own axis."""
        i = 0 if self.axis == 0 else 1
        return (min(self.start[i], self.end[i]), max(self.start[i], self.end[i]))

    def distance_to(self, point: tuple[float, float]) -> float:
        """The distance from ``point`` to the nearest point of the edge.

        Plain float arithmetic: the wall search sorts every edge by it for each item, and
        numpy's cost per call on 2-vectors dominated. The operations are those of the
        numpy form ``norm(p - (a + clip(dot(p - a, d) / dot(d, d), 0, 1) * d))`` in the
        same order (``dot`` and ``norm`` of two components: two products and one sum,
        then a square root), so the floats are the same: checked to the bit on millions
        of random edges and points (numpy's ``dot`` of two components fuses no
        multiply-add), and by the tests.
        """
        ax, az = self.start
        dx, dz = self.end[0] - ax, self.end[1] - az
        px, pz = float(point[0]), float(point[1])
        t = min(max(((px - ax) * dx + (pz - az) * dz) / (dx * dx + dz * dz), 0.0), 1.0)
        vx, vz = px - (ax + t * dx), pz - (az + t * dz)
        return math.sqrt(vx * vx + vz * vz)


@dataclass(frozen=True)
class Corner:
    """A convex corner of the free floor: the vertex and the edges meeting there."""

    vertex: tuple[float, float]
    edges: tuple[Edge, Edge]


def room_edges(interior: Polygon) -> list[Edge]:
    """The edges of a room's free floor, counter-clockwise, collinear pieces merged."""
    ring = list(orient(interior, sign=1.0).exterior.coords)[:-1]
    points: list[tuple[float, float]] = []
    for i, p in enumerate(ring):
        prev, nxt = np.asarray(ring[i - 1]), np.asarray(ring[(i + 1) % len(ring)])
        a, b = np.asarray(p) - prev, nxt - np.asarray(p)
        cross = a[0] * b[1] - a[1] * b[0]
        if abs(cross) > _TOLERANCE * np.linalg.norm(a) * np.linalg.norm(b) or np.dot(a, b) < 0:
            points.append((float(p[0]), float(p[1])))
    return [Edge(points[i], points[(i + 1) % len(points)]) for i in range(len(points))]


def convex_corners(edges: list[Edge]) -> list[Corner]:
    """The right-angled convex corners between consecutive axis-aligned edges."""
    corners = []
    for i, out in enumerate(edges):
        inc = edges[i - 1]
        if inc.axis is None or out.axis is None or inc.axis == out.axis:
            continue
        a, b = inc.direction, out.direction
        if a[0] * b[1] - a[1] * b[0] > 0:
            corners.append(Corner(out.start, (inc, out)))
    return corners


def flush_box(spec: ItemSpec, rotation: int) -> Box:
    """The box around ``spec``'s body and clearances at ``rotation`` (relative to its
    centre): what must fit between the walls."""
    return spec.extent(rotation)


def flush(bbox: Box, normal: np.ndarray, line: float) -> tuple[int, float]:
    """(axis, centre coordinate) that puts ``bbox`` against the wall at ``line`` whose
    inward normal is ``normal``."""
    axis = 0 if abs(normal[0]) > 0.5 else 1
    if normal[axis] > 0:
        return axis, line - bbox[axis]
    return axis, line - bbox[axis + 2]


class _Stretch(NamedTuple):
    """A wall a wall item may slide along: its turn, the axis it slides along, its
    centre's fixed coordinate across it, the range of the sliding coordinate and the
    point of that range nearest the item's start."""

    rotation: int
    axis: int
    fixed: float
    lo: float
    hi: float
    preferred: float


class Placer:
    """Places items one by one into a :class:`~.layout.Layout` by their rules.

    Parameters
    ----------
    layout:
        The room's layout; strategies add (and may move) items in it.
    specs:
        Every item of the room (to know parents and children).
    rng:
        Random stream for free-standing items' extra start points and orientations.
    edges:
        The room's :func:`room_edges`, when known (each attempt of the solver places
        into the same room).

    Notes
    -----
    A parent is placed together with its family: at each candidate pose (nearest first)
    its children are seated at once, and the first pose that seats them all is kept
    (else the one seating most, among the first :data:`_LOOKAHEAD`). The thesis placed
    the sofa first and found out only later that the tv board had no wall left.
    """

    def __init__(self, layout: Layout, specs: Sequence[ItemSpec], rng: np.random.Generator,
                 edges: Sequence[Edge] | None = None):
        self.layout = layout
        self.edges = list(edges) if edges is not None else room_edges(layout.interior)
        self.corners = convex_corners(self.edges)
        self.rng = rng
        self.children: dict[str, list[ItemSpec]] = {}
        for spec in specs:
            if spec.rule.pair_with is not None:
                self.children.setdefault(spec.rule.pair_with, []).append(spec)
        self.related = {s.name: frozenset([c.name for c in self.children.get(s.name, [])]
                                          + ([s.rule.pair_with] if s.rule.pair_with else []))
                        for s in specs}
        self.sides: dict[str, tuple[str, int]] = {}  # around-child → (parent, side index)
        self._passage: Conflict | None = None  # the first passage conflict of this item

    # -- helpers -------------------------------------------------------------------------
    def _conflict(self, spec: ItemSpec, pose: Pose) -> Conflict | None:
        found = self.layout.conflicts(spec, pose, self.related.get(spec.name, frozenset()),
                                      first=True)
        if not found:
            return None
        if found[0].kind in _PASSAGE_KINDS and self._passage is None:
            self._passage = found[0]
        return found[0]

    def _try(self, spec: ItemSpec, pose: Pose) -> Conflict | None:
        """Add ``spec`` at ``pose`` if nothing blocks it; else return the conflict."""
        conflict = self._conflict(spec, pose)
        if conflict is None:
            self.layout.add(spec, pose)
        return conflict

    def _free_poses(self, spec: ItemSpec, rotation: int, axis: int, fixed: float, lo: float,
                    hi: float, preferred: float) -> Iterator[Pose]:
        """Poses on a segment at which nothing blocks ``spec``: per free interval the
        point nearest ``preferred``, nearest intervals first; then the ends and middles
        of the intervals (where the nearest points break the passage rule)."""
        related = self.related.get(spec.name, frozenset())
        intervals = self.layout.free_intervals(spec, rotation, axis, fixed, lo, hi, related)
        nearest = sorted(v for v in (nearest_in([iv], preferred) for iv in intervals)
                         if v is not None)
        nearest.sort(key=lambda v: abs(v - preferred))
        others = sorted({v for a, b in intervals for v in (a, (a + b) / 2, b)}
                        - set(nearest), key=lambda v: abs(v - preferred))
        for value in nearest + others:
            pose = _pose(axis, value, 1 - axis, fixed, rotation)
            if self._conflict(spec, pose) is None:
                yield pose

    def _slide(self, spec: ItemSpec, rotation: int, axis: int, fixed: float, lo: float,
               hi: float, preferred: float) -> Pose | None:
        """Add ``spec`` at the free position on the segment nearest ``preferred``."""
        pose = next(self._free_poses(spec, rotation, axis, fixed, lo, hi, preferred), None)
        if pose is not None:
            self.layout.add(spec, pose)
        return pose

    # -- dispatch ------------------------------------------------------------------------
    def place(self, spec: ItemSpec, start: tuple[float, float] | None) -> str | None:
        """Place ``spec`` by its rule; None on success, else the reason it was left out.

        ``start`` is the item's steered start position (None for children). An item
        already seated with its parent's family is left as it is.
        """
        if spec.name in self.layout.placed:
            return None
        self._passage = None
        reason = self._place(spec, start)
        passage = self._passage.describe() if self._passage is not None else None
        if reason is None or passage is None or passage in reason:
            return reason
        return f"{reason}; where it fits, it {passage}"

    def pass_over(self, spec: ItemSpec) -> None:
        """Leave ``spec`` unplaced without trying it, but take from the random stream
        what :meth:`place` would have taken (a free-standing item's orientation and
        extra start points): the solver gives up an attempt that can no longer place
        more than its best, and the attempts and rooms after it must draw the same
        numbers as if it had run to the end."""
        if spec.name not in self.layout.placed and self._strategy(spec) == "free":
            self._free_draws()

    @staticmethod
    def _strategy(spec: ItemSpec) -> str:
        """Which of the strategies :meth:`place` uses for ``spec``."""
        rule = spec.rule
        if rule.pair_with is not None:
            return "child"
        if rule.non_collision:
            return "middle"
        if rule.is_in_corner:
            return "corner"
        if rule.is_along_wall:
            return "wall"
        return "free"

    def _place(self, spec: ItemSpec, start: tuple[float, float] | None) -> str | None:
        strategy = self._strategy(spec)
        if strategy == "child":
            if spec.rule.pair_with not in self.layout.placed:
                return f"parent {spec.rule.pair_with} not placed"
            return self._place_child(spec)
        if strategy == "middle":
            return self.middle(spec)
        centre = start if start is not None else self._room_centre()
        if strategy == "corner":
            return self.corner(spec, centre)
        if strategy == "wall":
            return self.along_wall(spec, centre)
        return self.free(spec, centre)

    def _place_child(self, spec: ItemSpec) -> str | None:
        parent = spec.rule.pair_with
        assert parent is not None
        if spec.rule.can_be_around:
            return self.around(spec, parent)
        if spec.rule.is_on_the_side:
            return self.beside(spec, parent)
        return self.in_front(spec, parent)

    def seat_family(self, spec: ItemSpec, pose: Pose) -> bool:
        """Add ``spec`` at ``pose`` with all its descendants seated by their rules, or
        leave the layout as it was and return False (:mod:`.desks` lays out desks with
        their chairs this way)."""
        if self._conflict(spec, pose) is not None:
            return False
        self.layout.add(spec, pose)
        seated: list[str] = []
        for child in self._descendants(spec.name):
            if self._place_child(child) is not None:
                for name in (*seated, spec.name):
                    self.layout.remove(name)
                    self.sides.pop(name, None)
                return False
            seated.append(child.name)
        return True

    def _descendants(self, name: str) -> list[ItemSpec]:
        out = []
        for child in self.children.get(name, []):
            out.append(child)
            out.extend(self._descendants(child.name))
        return out

    def _commit(self, spec: ItemSpec, poses: Iterator[Pose]) -> bool:
        """Place ``spec`` at the first of ``poses`` where its whole family fits (see the
        class notes); False when ``poses`` is empty."""
        family = self._descendants(spec.name)
        best: tuple[int, Pose] | None = None
        for count, pose in enumerate(poses, start=1):
            self.layout.add(spec, pose)
            seated = [c.name for c in family if c.rule.pair_with in self.layout.placed
                      and self._place_child(c) is None]
            if len(seated) == len(family):
                return True
            if best is None or len(seated) > best[0]:
                best = (len(seated), pose)
            for name in (*seated, spec.name):
                self.layout.remove(name)
                self.sides.pop(name, None)
            if count >= _LOOKAHEAD:
                break
        if best is None:
            return False
        self.layout.add(spec, best[1])
        for child in family:
            if child.rule.pair_with in self.layout.placed:
                self._place_child(child)
        return True

    def _room_centre(self) -> tuple[float, float]:
        c = self.layout.interior.centroid
        if not self.layout.interior.contains(c):
            c = self.layout.interior.representative_point()
        return (c.x, c.y)

    # -- parents and single items --------------------------------------------------------
    def _corner_poses(self, spec: ItemSpec, start: tuple[float, float]) -> Iterator[Pose]:
        """``spec`` in each convex corner, nearest ``start`` first, its back against
        either wall, flush with both after its clearances."""
        for corner in sorted(self.corners, key=lambda c: math.dist(c.vertex, start)):
            for back_edge in corner.edges:
                rotation = back_edge.facing
                bbox = spec.extent(rotation)
                coords = [0.0, 0.0]
                for edge in corner.edges:
                    axis, value = flush(bbox, edge.normal, edge.line)
                    coords[axis] = value
                yield Pose(coords[0], coords[1], rotation)

    def corner(self, spec: ItemSpec, start: tuple[float, float]) -> str | None:
        """Put ``spec`` in the nearest free corner, trying both orientations."""
        if not self.corners:
            return "the room has no right-angled corner"
        blocked: list[Conflict] = []

        def poses() -> Iterator[Pose]:
            for pose in self._corner_poses(spec, start):
                conflict = self._conflict(spec, pose)
                if conflict is None:
                    yield pose
                else:
                    blocked.append(conflict)

        if self._commit(spec, poses()):
            return None
        return f"every corner is blocked (nearest: {blocked[0].describe()})"

    def _wall_rotations(self, spec: ItemSpec, edge: Edge) -> list[int]:
        if not spec.rule.needs_turn:
            return [edge.facing]
        return list(edge.along)

    def _wall_stretches(self, spec: ItemSpec, start: tuple[float, float]
                        ) -> tuple[list[_Stretch], float] | str:
        """Where ``spec`` may slide with its back (a side, for ``needsTurn``) against a
        wall long enough for it, nearest wall to ``start`` first, and the least wall
        length it needs; or why there is no such wall."""
        candidates = []
        for edge in self.edges:
            if edge.axis is None:
                continue
            for rotation in self._wall_rotations(spec, edge):
                bbox = spec.extent(rotation)
                candidates.append((edge, rotation, bbox[edge.axis + 2] - bbox[edge.axis]))
        if not candidates:
            return "the room has no straight axis-aligned wall"
        need = min(c[2] for c in candidates)
        usable = sorted((c for c in candidates if c[0].length >= c[2] - 1e-9),
                        key=lambda c: c[0].distance_to(start))
        if not usable:
            return f"no wall long enough for {spec.name} (needs {need:.2f} m)"
        stretches = []
        for edge, rotation, _ in usable:
            axis = edge.axis
            assert axis is not None
            body = spec.parts(rotation)[0].box
            _, fixed = flush(spec.extent(rotation), edge.normal, edge.line)
            lo, hi = edge.span
            lo, hi = lo - body[axis], hi - body[axis + 2]
            stretches.append(_Stretch(rotation, axis, fixed, lo, hi,
                                      min(max(start[axis], lo), hi)))
        return stretches, need

    def along_wall(self, spec: ItemSpec, start: tuple[float, float]) -> str | None:
        """Put ``spec`` against the nearest wall with room, at the spot nearest ``start``."""
        found = self._wall_stretches(spec, start)
        if isinstance(found, str):
            return found
        stretches, need = found
        blocked: list[Conflict] = []

        def poses() -> Iterator[Pose]:
            # first the spot nearest the start on each wall, nearest wall first; then, for
            # a parent whose children did not fit, the ends and middles of the free stretches
            later: list[Pose] = []
            for rotation, axis, fixed, lo, hi, preferred in stretches:
                related = self.related.get(spec.name, frozenset())
                intervals = self.layout.free_intervals(spec, rotation, axis, fixed, lo, hi,
                                                       related)
                if not intervals and not blocked:
                    conflict = self._conflict(spec, _pose(axis, preferred, 1 - axis, fixed,
                                                          rotation))
                    if conflict is not None:
                        blocked.append(conflict)
                values = sorted({v for a, b in intervals for v in (a, (a + b) / 2, b)},
                                key=lambda v: abs(v - preferred))
                nearest = nearest_in(intervals, preferred)
                for value in ([nearest] if nearest is not None else []) + values:
                    pose = _pose(axis, value, 1 - axis, fixed, rotation)
                    if value == nearest:
                        if self._conflict(spec, pose) is None:
                            yield pose
                    elif nearest is None or abs(value - nearest) > 1e-6:
                        later.append(pose)
            for pose in later:
                if self._conflict(spec, pose) is None:
                    yield pose

        if self._commit(spec, poses()):
            return None
        reason = f"no free wall long enough for {spec.name} ({need:.2f} m)"
        return f"{reason}; nearest wall: {blocked[0].describe()}" if blocked else reason

    def never_fits(self, spec: ItemSpec) -> bool:
        """Whether the room itself (its walls, door zones and windows) blocks every
        place a corner or wall item's strategy can try, so that no layout, whatever
        else it holds, takes ``spec``: other items and the passage rule only ever add
        conflicts to a pose the room blocks, and a wall item's free stretches only
        shrink. False for the other strategies. Asked of an empty layout.

        The solver stops retrying a room once an attempt places all but such items
        (and their children): no later attempt could place more."""
        assert not self.layout.placed
        strategy = self._strategy(spec)
        centre = self._room_centre()  # any start: it only orders the places
        if strategy == "corner":
            return all(self.layout.blocked_by_room(spec, pose)
                       for pose in self._corner_poses(spec, centre))
        if strategy != "wall":
            return False
        found = self._wall_stretches(spec, centre)
        return isinstance(found, str) or not any(
            self.layout.free_intervals(spec, s.rotation, s.axis, s.fixed, s.lo, s.hi)
            for s in found[0])

    def free(self, spec: ItemSpec, start: tuple[float, float]) -> str | None:
        """Put a free-standing item (a dining or meeting table) at the free spot nearest
        the middle of the room, else nearest its start or a few random points."""
        rotations, extra = self._free_draws()
        minx, minz, maxx, maxz = self.layout.interior.bounds
        blocked: list[Conflict] = []

        def poses() -> Iterator[Pose]:
            for point in [self._room_centre(), start, *map(tuple, extra)]:
                options = []
                for rotation in rotations:
                    pose = Pose(point[0], point[1], rotation)
                    conflict = self._conflict(spec, pose)
                    if conflict is None:
                        options.append((0.0, rotation, 0, pose))
                        continue
                    blocked.append(conflict)
                    for axis in (0, 1):
                        lo, hi = (minx, maxx) if axis == 0 else (minz, maxz)
                        for pose in self._free_poses(spec, rotation, axis, point[1 - axis],
                                                     lo, hi, point[axis]):
                            options.append((abs(_coordinate(pose, axis) - point[axis]),
                                            rotation, axis, pose))
                            break
                yield from (pose for *_, pose in sorted(options, key=lambda o: o[:3]))

        if self._commit(spec, poses()):
            return None
        return f"no free spot for {spec.name} ({blocked[0].describe()})"

    def _free_draws(self) -> tuple[list[int], np.ndarray]:
        """A free-standing item's draws: the orientation it tries first and
        :data:`_FREE_SAMPLES` extra start points in the room's bounds."""
        rotations = [0, 1] if self.rng.random() < 0.5 else [1, 0]
        minx, minz, maxx, maxz = self.layout.interior.bounds
        return rotations, self.rng.uniform((minx, minz), (maxx, maxz),
                                           size=(_FREE_SAMPLES, 2))

    def middle(self, spec: ItemSpec) -> str | None:
        """Lay a non-colliding item (a rug) in the middle of the room, long side along the
        room's long side."""
        minx, minz, maxx, maxz = self.layout.interior.bounds
        along_x = (maxx - minx >= maxz - minz) == (spec.width >= spec.depth)
        x, z = self._room_centre()
        poses = (Pose(x, z, rotation) for rotation in ((0, 1) if along_x else (1, 0))
                 if self._conflict(spec, Pose(x, z, rotation)) is None)
        if self._commit(spec, poses):
            return None
        return f"{spec.name} does not fit in the middle of the room"

    # -- children ------------------------------------------------------------------------
    def _parent(self, name: str) -> tuple[ItemSpec, Pose, Box]:
        spec, pose = self.layout.placed[name]
        b = spec.parts(pose.rotation)[0].box
        return spec, pose, (pose.x + b[0], pose.z + b[1], pose.x + b[2], pose.z + b[3])

    @staticmethod
    def _sides(pose: Pose) -> tuple[np.ndarray, ...]:
        """The parent's side normals: front, back, then its two flanks (:data:`_SIDES`)."""
        return _SIDES[pose.rotation % 4]

    def around(self, spec: ItemSpec, parent: str) -> str | None:
        """Put a child on a free side of its parent, facing it; siblings sharing a side
        are spread evenly along it."""
        pspec, ppose, pbox = self._parent(parent)
        gap = spec.rule.min_pair_distance
        sides = self._sides(ppose)
        count = [sum(1 for p, i in self.sides.values() if p == parent and i == k)
                 for k in range(4)]
        order = sorted(range(4), key=lambda k: (count[k], k))
        first: Conflict | None = None
        for k in order:
            normal = sides[k]
            rotation = quarter_turn_towards(-normal)
            geometry = self._side_geometry(spec, rotation, pbox, normal, gap)
            if self._spread(spec, parent, k, rotation, geometry):
                self.sides[spec.name] = (parent, k)
                return None
            axis, fixed, lo, hi = geometry
            half = _half(spec, rotation, axis)
            if hi - lo >= 2 * half and self._slide(spec, rotation, axis, fixed, lo + half,
                                                   hi - half, (lo + hi) / 2) is not None:
                self.sides[spec.name] = (parent, k)
                return None
            if first is None:
                first = self._conflict(spec, _pose(axis, (lo + hi) / 2, 1 - axis, fixed,
                                                   rotation))
        detail = f" ({first.describe()})" if first else ""
        return f"no free side of {parent}{detail}"

    def _side_geometry(self, spec: ItemSpec, rotation: int, pbox: Box, normal: np.ndarray,
                       gap: float) -> tuple[int, float, float, float]:
        """(slide axis, fixed centre coordinate, side start, side end) of a child standing
        ``gap`` off the parent's side with outward ``normal``."""
        body = spec.parts(rotation)[0].box
        n_axis = 0 if abs(normal[0]) > 0.5 else 1
        if normal[n_axis] > 0:
            fixed = pbox[n_axis + 2] + gap - body[n_axis]
        else:
            fixed = pbox[n_axis] - gap - body[n_axis + 2]
        axis = 1 - n_axis
        return axis, fixed, pbox[axis], pbox[axis + 2]

    def _spread(self, spec: ItemSpec, parent: str, side: int, rotation: int,
                geometry: tuple[int, float, float, float]) -> bool:
        """Try to seat ``spec`` with the siblings already on ``side``, all evenly spaced."""
        axis, fixed, lo, hi = geometry
        siblings = sorted((n for n, (p, k) in self.sides.items() if p == parent and k == side),
                          key=lambda n: _coordinate(self.layout.placed[n][1], axis))
        width = 2 * _half(spec, rotation, axis)
        count = len(siblings) + 1
        if count > 1 and count * width > hi - lo + 1e-9:
            return False
        slots = [lo + (i + 0.5) * (hi - lo) / count for i in range(count)]
        saved = {n: self.layout.remove(n) for n in siblings}
        for new_slot in range(count - 1, -1, -1):
            order = siblings[:new_slot] + [spec.name] + siblings[new_slot:]
            seated = []
            for name, slot in zip(order, slots):
                item = spec if name == spec.name else saved[name][0]
                pose_rotation = rotation if name == spec.name else saved[name][1].rotation
                if self._try(item, _pose(axis, slot, 1 - axis, fixed, pose_rotation)) is not None:
                    break
                seated.append(name)
            if len(seated) == count:
                return True
            for name in seated:
                self.layout.remove(name)
        for name, (item, pose) in saved.items():
            self.layout.add(item, pose)
        return False

    def beside(self, spec: ItemSpec, parent: str) -> str | None:
        """Put a child right beside its parent, same orientation, backs aligned."""
        pspec, ppose, pbox = self._parent(parent)
        rule = spec.rule
        rotation = ppose.rotation
        # the child's centre along the parent's front axis: backs on one line
        centre = np.array([ppose.x, ppose.z]) + self._sides(ppose)[0] * (
            spec.depth - pspec.depth) / 2
        first: Conflict | None = None
        for normal in self._sides(ppose)[2:]:
            axis, near, _, _ = self._side_geometry(spec, rotation, pbox, normal,
                                                   rule.min_pair_distance)
            side_axis = 1 - axis  # ``axis`` runs along the parent's front
            conflict = self._try(spec, _pose(side_axis, near, axis, float(centre[axis]),
                                             rotation))
            if conflict is None:
                return None
            first = first or conflict
            if rule.max_gap is not None and rule.max_gap > rule.min_pair_distance:
                _, far, _, _ = self._side_geometry(spec, rotation, pbox, normal, rule.max_gap)
                lo, hi = sorted((near, far))
                if self._slide(spec, rotation, side_axis, float(centre[axis]), lo, hi,
                               near) is not None:
                    return None
        assert first is not None
        return f"both sides of {parent} are blocked ({first.describe()})"

    def in_front(self, spec: ItemSpec, parent: str) -> str | None:
        """Put a child in front of its parent, facing it (a wall item: against the wall
        opposite the parent)."""
        if spec.rule.is_along_wall:
            return self._opposite_wall(spec, parent)
        pspec, ppose, pbox = self._parent(parent)
        rule = spec.rule
        f = self._sides(ppose)[0]
        rotation = (ppose.rotation + 2) % 4
        axis = 0 if abs(f[0]) > 0.5 else 1  # the axis the gap is measured along
        lateral_axis = 1 - axis
        minx, minz, maxx, maxz = self.layout.interior.bounds
        limit = max(maxx - minx, maxz - minz)
        lo_gap, hi_gap = rule.min_pair_distance, rule.max_gap if rule.max_gap else limit
        preferred_gap = (lo_gap + hi_gap) / 2 if rule.max_gap else lo_gap
        _, near, _, _ = self._side_geometry(spec, rotation, pbox, f, lo_gap)
        _, far, _, _ = self._side_geometry(spec, rotation, pbox, f, hi_gap)
        _, want, _, _ = self._side_geometry(spec, rotation, pbox, f, preferred_gap)
        lateral = _coordinate(ppose, lateral_axis)
        lo, hi = sorted((near, far))
        if self._slide(spec, rotation, axis, lateral, lo, hi, want) is not None:
            return None
        first = self._conflict(spec, _pose(axis, want, lateral_axis, lateral, rotation))
        plo, phi = pbox[lateral_axis], pbox[lateral_axis + 2]
        for along in dict.fromkeys((want, near, far)):
            pose = self._slide(spec, rotation, lateral_axis, along, plo, phi, lateral)
            if pose is not None:
                self._face_child(parent, spec.name, lateral_axis,
                                 _coordinate(pose, lateral_axis))
                return None
        detail = f" ({first.describe()})" if first else ""
        return f"no free spot in front of {parent}{detail}"

    def _opposite_wall(self, spec: ItemSpec, parent: str) -> str | None:
        pspec, ppose, pbox = self._parent(parent)
        f = self._sides(ppose)[0]
        axis = 0 if abs(f[0]) > 0.5 else 1
        lateral_axis = 1 - axis
        rotation = (ppose.rotation + 2) % 4
        plo, phi = pbox[lateral_axis], pbox[lateral_axis + 2]
        front_line = pbox[axis + 2] if f[axis] > 0 else pbox[axis]
        facing = []
        for edge in self.edges:
            if edge.axis != lateral_axis or np.dot(edge.normal, f) > -0.5:
                continue
            elo, ehi = edge.span
            ahead = (edge.line - front_line) * f[axis]
            if ahead > 0 and min(ehi, phi) > max(elo, plo):
                facing.append((ahead, edge))
        if not facing:
            return f"no wall opposite {parent}"
        lateral = _coordinate(ppose, lateral_axis)
        first: Conflict | None = None
        for ahead, edge in sorted(facing, key=lambda item: item[0]):
            body = spec.parts(rotation)[0].box
            _, fixed = flush(spec.extent(rotation), edge.normal, edge.line)
            gap = abs(fixed - front_line) - (body[axis + 2] - body[axis]) / 2
            if gap < spec.rule.min_pair_distance - 1e-9:
                first = None
                continue
            elo, ehi = edge.span
            lo = max(elo - body[lateral_axis], plo)
            hi = min(ehi - body[lateral_axis + 2], phi)
            pose = self._slide(spec, rotation, lateral_axis, fixed, lo, hi, lateral)
            if pose is not None:
                self._face_child(parent, spec.name, lateral_axis,
                                 _coordinate(pose, lateral_axis))
                return None
            if first is None:
                centre = min(max(lateral, lo), hi)
                first = self._conflict(spec, _pose(lateral_axis, centre, axis, fixed, rotation))
        detail = f" ({first.describe()})" if first else ""
        return f"the wall opposite {parent} has no room for {spec.name}{detail}"

    def _face_child(self, parent: str, child: str, axis: int, value: float) -> None:
        """Shift ``parent`` sideways to line up with ``child`` if it has no other children
        placed, is not a corner item and nothing blocks the new position."""
        pspec, ppose = self.layout.placed[parent]
        if pspec.rule.is_in_corner or abs(_coordinate(ppose, axis) - value) < 1e-9:
            return
        others = [n for n in self.related.get(parent, frozenset())
                  if n != child and n != pspec.rule.pair_with and n in self.layout.placed]
        if others:
            return
        self.layout.remove(parent)
        if self._try(pspec, ppose.moved(axis, value)) is not None:
            self.layout.add(pspec, ppose)


def _half(spec: ItemSpec, rotation: int, axis: int) -> float:
    body = spec.parts(rotation)[0].box
    return (body[axis + 2] - body[axis]) / 2


def _coordinate(pose: Pose, axis: int) -> float:
    return pose.x if axis == 0 else pose.z


def _pose(axis_a: int, value_a: float, axis_b: int, value_b: float, rotation: int) -> Pose:
    coords = [0.0, 0.0]
    coords[axis_a], coords[axis_b] = value_a, value_b
    return Pose(coords[0], coords[1], rotation)
