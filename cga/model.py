"""The building model shared by the floor operations, the checks and the exporters.

``make_floor`` creates a :class:`FloorPlan` (rooms, walls, windows), ``type_rooms``
returns a copy with room types, a room graph and doors, ``add_furniture`` returns a copy
with furniture. Checks and exporters only read these objects (data flows one way).

Frames and conventions (docs/architecture.md, "Units and frames"):

* Plan coordinates are world ``(x, z)`` in metres; ``y`` is up.
* A room's ``polygon`` is bounded by wall centre lines (inner walls) and the footprint
  (outer walls). Its ``interior`` is the free floor: the polygon minus wall thickness.
* A wall is one DCEL edge (a half-edge pair): a straight segment ``start``→``end`` on the
  centre line of an inner wall, or on the footprint boundary for an outer wall, whose
  solid lies inside the footprint. Openings are positioned by the distance of their
  centre from ``start``.
* Furniture ``rotation`` is a number of quarter turns about +y; at rotation 0 the item's
  front faces −z. An item's ``yaw`` (radians, same sense) turns it further by a free
  angle (the disorder of chairs, docs/furniture.md). :func:`front_vector` and
  :func:`rotation_matrix` are the one source of this convention.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Any, Literal

import numpy as np
from shapely.geometry import LineString, Point, Polygon
from shapely.geometry.polygon import orient

if TYPE_CHECKING:  # pragma: no cover
    import networkx as nx

    from cga.operations.floorplan.dcel import DCEL

__all__ = [
    "OUTSIDE",
    "Diagnostic",
    "Opening",
    "Wall",
    "Room",
    "Door",
    "DOOR_STATES",
    "DOOR_OPEN_ANGLE",
    "Window",
    "FurnitureItem",
    "FloorSettings",
    "StairCore",
    "Flight",
    "Stair",
    "FloorPlan",
    "front_vector",
    "rotation_matrix",
]

OUTSIDE = -1
"""Room id of the outside (the DCEL's unbounded face)."""


@dataclass(frozen=True)
class Diagnostic:
    """A message for the user produced while building (shown in the summary and JSON)."""

    level: Literal["info", "warning", "error"]
    stage: str
    message: str
    floor: int | None = None
    room: int | None = None

    def __str__(self) -> str:
        where = []
        if self.floor is not None:
            where.append(f"floor {self.floor}")
        if self.room is not None:
            where.append(f"room {self.room}")
        prefix = f"[{', '.join(where)}] " if where else ""
        return f"{self.stage}: {prefix}{self.message}"


@dataclass(frozen=True)
class Opening:
    """A hole in a wall: ``center`` is the distance (m) of its middle from ``Wall.start``;
    ``sill`` is the height of its bottom above the walking surface (0 for doors)."""

    kind: Literal["door", "window"]
    center: float
    width: float
    height: float
    sill: float = 0.0


@dataclass(frozen=True)
class Wall:
    """A straight wall segment between two DCEL vertices.

    ``rooms`` is ``(left, right)`` seen walking from ``start`` to ``end``; ``right`` is
    :data:`OUTSIDE` for an outer wall whose outside lies to the right.
    """

    id: int
    start: tuple[float, float]
    end: tuple[float, float]
    outer: bool
    rooms: tuple[int, int]
    thickness: float
    openings: tuple[Opening, ...] = ()

    @property
    def length(self) -> float:
        return math.dist(self.start, self.end)

    @property
    def direction(self) -> np.ndarray:
        """The unit vector from ``start`` to ``end`` (:meth:`unit` as an array)."""
        return np.array(self.unit())

    def unit(self) -> tuple[float, float]:
        """The unit vector from ``start`` to ``end``. Walls along an axis (nearly all)
        skip numpy: their length is one coordinate's difference exactly, as
        ``np.linalg.norm`` gives it, so both ways give the same bits."""
        dx, dz = self.end[0] - self.start[0], self.end[1] - self.start[1]
        if (dx == 0.0) != (dz == 0.0):
            length = abs(dx) if dz == 0.0 else abs(dz)
            return (dx / length, dz / length)
        d = np.subtract(self.end, self.start)
        ux, uz = d / np.linalg.norm(d)
        return (float(ux), float(uz))

    @property
    def normal(self) -> np.ndarray:
        """The unit normal to the left of ``start``→``end``: it points into ``rooms[0]``."""
        return np.array(self._left())

    def _left(self) -> tuple[float, float]:
        """:attr:`normal` as plain floats (the unit vector turned a quarter left)."""
        ux, uz = self.unit()
        return (-uz, ux)

    def normal_into(self, room: int) -> np.ndarray:
        """The unit normal pointing from the wall line into ``room`` (one of
        :attr:`rooms`; :data:`OUTSIDE` gives the outward normal of an outer wall).

        Raises
        ------
        ValueError
            ``room`` is not on either side of this wall.
        """
        nx, nz = self._left()
        return np.array((nx, nz) if self._on_left(room) else (-nx, -nz))

    def _on_left(self, room: int) -> bool:
        if room not in self.rooms:
            raise ValueError(f"room {room} is not beside wall {self.id} (rooms {self.rooms})")
        return room == self.rooms[0]

    def band(self) -> tuple[float, float]:
        """Where the wall's solid lies across its line: offsets ``(lo, hi)`` along
        :attr:`normal`.

        An inner wall is centred on its line, ``(-t/2, t/2)``; an outer wall lies wholly
        on its room's side of the footprint boundary: ``(0, t)`` with the room on the
        left, ``(-t, 0)`` with it on the right.
        """
        t = self.thickness
        if not self.outer:
            return (-t / 2, t / 2)
        return (0.0, t) if self.rooms[1] == OUTSIDE else (-t, 0.0)

    def face_offset(self, room: int) -> float:
        """Distance from the wall line to the wall's face on ``room``'s side (0 on the
        outside of an outer wall); raises ValueError like :meth:`normal_into`."""
        lo, hi = self.band()
        return hi if self._on_left(room) else -lo

    def band_corners(self, before: float = 0.0, after: float = 0.0) -> np.ndarray:
        """The 4×2 corners of the wall's solid strip (:meth:`band` across), reaching
        ``before`` metres past ``start`` and ``after`` metres past ``end``.

        Worked out in plain floats, component by component in the order the vector
        formula ``a + n * lo`` (``a = start - d * before``, ...) takes, so the corners
        have the same bits as with numpy at a fraction of the cost."""
        (dx, dz), (nx, nz) = self.unit(), self._left()
        ax, az = self.start[0] - dx * before, self.start[1] - dz * before
        bx, bz = self.end[0] + dx * after, self.end[1] + dz * after
        lo, hi = self.band()
        return np.array([(ax + nx * lo, az + nz * lo), (bx + nx * lo, bz + nz * lo),
                         (bx + nx * hi, bz + nz * hi), (ax + nx * hi, az + nz * hi)])

    def point_at(self, distance: float) -> tuple[float, float]:
        """The point ``distance`` metres from ``start`` along the segment."""
        ux, uz = self.unit()
        return (float(self.start[0] + ux * distance), float(self.start[1] + uz * distance))

    def segment(self) -> LineString:
        return LineString([self.start, self.end])

    def with_opening(self, opening: Opening) -> "Wall":
        return replace(self, openings=self.openings + (opening,))


@dataclass(frozen=True)
class Room:
    """A room: a face of the floor's DCEL. ``type`` is None until ``type_rooms`` runs;
    ``circulation`` is set by ``make_floor`` for carved halls/corridors/stair cores and by
    ``type_rooms`` for types the table marks as circulation."""

    id: int
    polygon: Polygon
    interior: Polygon
    type: str | None = None
    circulation: bool = False
    """True for space whose job is to connect (hall, corridor, landing, stair core:
    docs/room_typing.md): drawn as circulation, never furnished as a private room, and where a
    stair core may stand."""
    private: bool = False
    """True when the room's rule forbids passing through it (``passThrough`` false:
    bedrooms, bathrooms), set by ``type_rooms``."""
    area_range: tuple[float, float | None] | None = None
    """The area (m²) the room's rule asks for: ``(Size, maxSize)``, None without a rule."""

    @property
    def area(self) -> float:
        """Area between wall centre lines (m²), the figure typing rules compare against."""
        return float(self.polygon.area)

    @property
    def label(self) -> str:
        return f"room{self.id}_{self.type}" if self.type else f"room{self.id}"


DoorState = Literal["closed", "open", "ajar"]

DOOR_STATES: tuple[DoorState, ...] = ("closed", "open", "ajar")
"""States a door leaf can be built in (docs/outputs.md)."""

DOOR_OPEN_ANGLE = math.pi / 2
"""rad: how far a leaf opens (its joint's upper limit): the quarter circle the plan draws
and the furniture clearance keeps free, so an open leaf never touches an item."""


@dataclass(frozen=True)
class Door:
    """A door in wall ``wall`` joining ``rooms`` (the second may be :data:`OUTSIDE`).

    ``position`` is the door's centre on the wall centre line. The leaf is hinged at the
    ``hinge`` end (``"start"`` or ``"end"`` of the wall direction) and swings into
    ``swing_room`` through a quarter circle of radius ``width``. ``state`` is how the
    build leaves it and ``angle`` (rad, 0 = closed, :data:`DOOR_OPEN_ANGLE` = open) how
    far the leaf is turned into ``swing_room``. A door without a ``leaf`` is a bare
    opening (the doorways and hallway junctions of ``usar_floor``): always open, with no
    leaf item, joint or swing.
    """

    id: int
    wall: int
    rooms: tuple[int, int]
    position: tuple[float, float]
    width: float
    height: float
    swing_room: int
    hinge: Literal["start", "end"] = "start"
    is_front: bool = False
    reason: Literal["rule", "reachability", "front", "stair"] = "rule"
    state: DoorState = "closed"
    angle: float = 0.0
    leaf: bool = True

    @property
    def passable(self) -> bool:
        """Whether a robot can drive through without opening the leaf first."""
        return self.state == "open"


@dataclass(frozen=True)
class Window:
    """A window in outer wall ``wall`` of room ``room``; ``position`` on the wall line."""

    id: int
    wall: int
    room: int
    position: tuple[float, float]
    width: float
    height: float
    sill: float


def _cos_sin(quarter_turns: int, yaw: float) -> tuple[float, float]:
    """Cosine and sine of the turn :func:`rotation_matrix` makes: integers when ``yaw`` is
    0 (so the matrix's ``-s`` is ``0.0``, never ``-0.0``)."""
    if yaw == 0.0:
        return [(1, 0), (0, 1), (-1, 0), (0, -1)][quarter_turns % 4]
    angle = (quarter_turns % 4) * math.pi / 2 + yaw
    return math.cos(angle), math.sin(angle)


def rotation_matrix(quarter_turns: int, yaw: float = 0.0) -> np.ndarray:
    """3×3 rotation about +y by ``quarter_turns`` × 90° plus ``yaw`` radians
    (right-handed); exact integers when ``yaw`` is 0."""
    c, s = _cos_sin(quarter_turns, yaw)
    return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]], dtype=float)


def front_vector(quarter_turns: int, yaw: float = 0.0) -> tuple[float, float]:
    """The item's front direction in plan ``(x, z)`` for a rotation (0 → (0, −1)).

    This is :func:`rotation_matrix` applied to ``(0, 0, −1)``: each component sums a
    ``±0`` product, an exact ``+0`` and ``∓sin`` or ``−cos``, which any summation order
    rounds to ``0.0 − sin`` and ``0.0 − cos`` (a zero comes out ``+0``), so it is written
    that way, without building the matrix."""
    c, s = _cos_sin(quarter_turns, yaw)
    return (0.0 - s, 0.0 - c)


@dataclass(frozen=True)
class FurnitureItem:
    """A placed item. ``size`` is the model's (width x, height y, depth z) before rotation
    (a jittered item's own size, docs/furniture.md); ``position`` the centre of its
    footprint on the walking surface. ``elevation`` lifts the model's origin above the
    walking surface (a window item: its opening's sill). ``yaw`` turns the item by a free
    angle (radians, right-handed about +y) beyond its ``rotation`` quarter turns: the
    disorder of movable items; 0 for everything the solver places by its rules."""

    name: str
    model: str
    room: int
    position: tuple[float, float]
    rotation: int
    size: tuple[float, float, float]
    parent: str | None = None
    is_detail: bool = False
    non_collision: bool = False
    elevation: float = 0.0
    door: int | None = None
    """The id of the door this item is the leaf of (``detail_items``); its pose then
    comes from the door's hinge and angle (:mod:`cga.doors`), not from ``rotation``."""
    yaw: float = 0.0

    @property
    def front(self) -> tuple[float, float]:
        return front_vector(self.rotation, self.yaw)

    @property
    def heading(self) -> float:
        """The item's whole turn about +y in radians: quarter turns plus ``yaw``."""
        return (self.rotation % 4) * math.pi / 2 + self.yaw

    def footprint(self) -> Polygon:
        """The item's rectangle in plan, rotated and placed.

        The corners are those of ``box`` turned and moved by ``shapely.affinity``
        (``rotate`` by the quarter turns, by ``yaw`` when it is not 0, then ``translate``),
        worked out on four points in plain floats with the same formulas in the same order,
        so the coordinates have the same bits: the plans ask for thousands of these, and
        each affinity call costs a geometry round trip."""
        w, _, d = self.size
        corners = [(w / 2, -d / 2), (w / 2, d / 2), (-w / 2, d / 2), (-w / 2, -d / 2)]
        corners = _rotated(corners, -90 * (self.rotation % 4) * math.pi / 180.0)
        if self.yaw:
            corners = _rotated(corners, -self.yaw)
        x0, z0 = self.position
        return Polygon([(1.0 * x + 0.0 * z + x0, 0.0 * x + 1.0 * z + z0) for x, z in corners])


def _rotated(points: list[tuple[float, float]], angle: float) -> list[tuple[float, float]]:
    """``points`` turned by ``angle`` radians about the origin, exactly as
    ``shapely.affinity.rotate(geom, angle, origin=(0, 0), use_radians=True)`` turns a
    geometry's coordinates: a sine or cosine under 2.5e-16 counts as 0, and the matrix's
    offsets (0 for this origin) are added last."""
    cosp, sinp = math.cos(angle), math.sin(angle)
    if abs(cosp) < 2.5e-16:
        cosp = 0.0
    if abs(sinp) < 2.5e-16:
        sinp = 0.0
    xoff, zoff = 0.0 - 0.0 * cosp + 0.0 * sinp, 0.0 - 0.0 * sinp - 0.0 * cosp
    return [(cosp * x + -sinp * z + xoff, sinp * x + cosp * z + zoff) for x, z in points]


@dataclass(frozen=True)
class FloorSettings:
    """Opening and structure sizes for one floor, in metres."""

    wall_thickness: float = 0.2
    windows_per_wall: int = 1
    window_width: float = 1.2
    window_height: float = 1.2
    window_sill: float = 0.9
    door_width: float = 0.9
    door_height: float = 2.1
    slab_thickness: float = 0.2


Point2 = tuple[float, float]


@dataclass(frozen=True)
class StairCore:
    """A building's stair core (DESIGN §12): the rectangle reserved on every storey of
    the stack it serves, in the same place, before the storey is partitioned.

    ``polygon`` is the core between wall centre lines. The stair is laid out in the
    core's own frame: ``u`` runs from the landing end along the flights, ``v`` across
    them, both unit plan vectors; ``origin`` is the interior corner ``(u, v) = (0, 0)``
    (``wall_thickness`` inside the polygon). The floor landing is the interior strip
    ``0 ≤ u ≤ landing_depth``. ``risers``, ``rise`` and ``going`` are the design of one
    storey's stair; ``storeys`` is how many storeys the core serves.
    """

    polygon: Polygon
    origin: Point2
    u: Point2
    v: Point2
    kind: Literal["straight", "U"]
    width: float
    well: float
    landing_depth: float
    risers: int
    rise: float
    going: float
    storeys: int

    @property
    def flight_risers(self) -> int:
        """Risers per flight: all of them for a straight stair, half for a U stair."""
        return self.risers if self.kind == "straight" else self.risers // 2

    @property
    def run(self) -> float:
        """Plan length of one flight (its treads; the last riser lands on a landing)."""
        return (self.flight_risers - 1) * self.going

    @property
    def interior_width(self) -> float:
        return self.width if self.kind == "straight" else 2 * self.width + self.well

    @property
    def interior_length(self) -> float:
        """Floor landing, flight, and the top landing (straight) or half landing (U)."""
        return 2 * self.landing_depth + self.run

    @property
    def interior(self) -> Polygon:
        """The core inside its walls: the stair's rectangle, and beside it the lobby a
        core stretched across a narrow bay keeps (``polygon`` shrunk by the walls)."""
        wall = Point(self.origin).distance(self.polygon.exterior)
        return self.polygon.buffer(-wall, join_style="mitre")

    def at(self, u: float, v: float) -> Point2:
        """The plan point at core coordinates ``(u, v)``."""
        return (self.origin[0] + u * self.u[0] + v * self.v[0],
                self.origin[1] + u * self.u[1] + v * self.v[1])

    def rect(self, u0: float, u1: float, v0: float, v1: float) -> Polygon:
        """The plan rectangle ``u0..u1 × v0..v1`` of the core frame, counter-clockwise."""
        ring = [self.at(u0, v0), self.at(u1, v0), self.at(u1, v1), self.at(u0, v1)]
        return orient(Polygon(ring), sign=1.0)


@dataclass(frozen=True)
class Flight:
    """One straight run of steps. The first riser stands at plan point ``start`` (the
    middle of the flight's width) and rises from ``base_y``; each of the ``risers``
    risers is ``rise`` high and each tread ``going`` deep along ``direction``; the
    last riser lands on the landing beyond the last tread."""

    start: Point2
    direction: Point2
    width: float
    base_y: float
    risers: int
    rise: float
    going: float

    @property
    def run(self) -> float:
        return (self.risers - 1) * self.going

    @property
    def top_y(self) -> float:
        return self.base_y + self.risers * self.rise

    def _point(self, along: float, across: float) -> Point2:
        dx, dz = self.direction
        return (self.start[0] + along * dx - across * dz, self.start[1] + along * dz + across * dx)

    def _rect(self, a0: float, a1: float) -> Polygon:
        h = self.width / 2
        return orient(Polygon([self._point(a0, -h), self._point(a1, -h), self._point(a1, h),
                               self._point(a0, h)]), sign=1.0)

    def treads(self) -> list[tuple[Polygon, float]]:
        """Each tread's plan rectangle and the height of its top (bottom to top)."""
        return [(self._rect(k * self.going, (k + 1) * self.going), self.base_y + (k + 1) * self.rise)
                for k in range(self.risers - 1)]

    def polygon(self) -> Polygon:
        """The flight's plan rectangle (its treads)."""
        return self._rect(0.0, self.run)


@dataclass(frozen=True)
class Stair:
    """The stair between floor ``floors[0]`` and the floor above, ``floors[1]``.

    ``polygon`` is its plan outline without the floor landings (flights and any half
    landing): the stairwell cut into the upper floor's slab. ``landings`` are the floor
    landings (bottom on the lower floor, top on the upper floor) and ``landing_points``
    where a walker steps off the stair onto each; ``rooms`` the core room on each floor.
    """

    id: int
    floors: tuple[int, int]
    kind: Literal["straight", "U"]
    polygon: Polygon
    landings: tuple[Polygon, Polygon]
    landing_points: tuple[Point2, Point2]
    flights: tuple[Flight, ...]
    half_landing: Polygon | None
    rooms: tuple[int, int]
    width: float
    rise: float
    going: float
    risers: int
    bottom_y: float
    top_y: float
    thickness: float = 0.2

    @property
    def treads(self) -> int:
        """Steps a walker treads on (the landings not counted)."""
        return sum(f.risers - 1 for f in self.flights)


@dataclass(frozen=True)
class FloorPlan:
    """One storey: rooms, walls, openings, furniture and the DCEL they come from.

    ``elevation`` is the y of the bottom of the floor slab, ``height`` the storey height;
    the walking surface is at :attr:`floor_y`. ``dcel`` is the half-edge structure built
    by ``make_floor``. ``type_rooms`` sets ``room_graph`` (nodes: room ids and
    :data:`OUTSIDE`, attribute ``type``; one edge per door, attributes ``door``, ``wall``,
    ``reason``) and ``entry``, the room the floor is entered by: the front door's room,
    or where the stair arrives on a floor without one. Every room is reachable from it.
    """

    index: int
    elevation: float
    height: float
    footprint: Polygon
    settings: FloorSettings
    rooms: tuple[Room, ...]
    walls: tuple[Wall, ...]
    dcel: "DCEL | None" = None
    windows: tuple[Window, ...] = ()
    doors: tuple[Door, ...] = ()
    furniture: tuple[FurnitureItem, ...] = ()
    room_graph: "nx.Graph | None" = None
    diagnostics: tuple[Diagnostic, ...] = ()
    is_top: bool = False
    entry: int | None = None
    core: StairCore | None = None
    """The building's stair core when this storey is one it serves (set by make_floor)."""
    core_room: int | None = None
    """The room (face) the core occupies on this floor."""
    stairs: tuple[Stair, ...] = ()
    """Stairs that start or end on this floor (set once the storeys are stacked)."""

    def with_stair_core(self, core: StairCore, room: int = 0) -> "FloorPlan":
        """The plan with face ``room`` (make_floor's first fixed face) as the stair core,
        typed ``Stair``: a circulation room the typing rules never take."""
        rooms = tuple(replace(r, type="Stair", circulation=True) if r.id == room else r
                      for r in self.rooms)
        return replace(self, rooms=rooms, core=core, core_room=room)

    @property
    def stair_up(self) -> Stair | None:
        """The stair from this floor to the one above."""
        return next((s for s in self.stairs if s.floors[0] == self.index), None)

    @property
    def stair_down(self) -> Stair | None:
        """The stair arriving on this floor from the one below."""
        return next((s for s in self.stairs if s.floors[1] == self.index), None)

    @property
    def stairwell(self) -> Polygon | None:
        """The opening cut into this floor's slab for the stair below, if any."""
        below = self.stair_down
        return below.polygon if below is not None else None
    layout: Any = None
    """How ``make_floor`` drew this floor (``cga.operations.floorplan.layout.LayoutRecipe``),
    so a typing that finds none can ask for a re-draw; None for hand-made floors."""

    @property
    def floor_y(self) -> float:
        return self.elevation + self.settings.slab_thickness

    def room(self, room_id: int) -> Room:
        for r in self.rooms:
            if r.id == room_id:
                return r
        raise KeyError(room_id)

    def wall(self, wall_id: int) -> Wall:
        for w in self.walls:
            if w.id == wall_id:
                return w
        raise KeyError(wall_id)

    def walls_of(self, room_id: int) -> list[Wall]:
        return [w for w in self.walls if room_id in w.rooms]

    def front_door(self) -> Door | None:
        return next((d for d in self.doors if d.is_front), None)

    def with_changes(self, **changes: Any) -> "FloorPlan":
        return replace(self, **changes)

    def contains_point(self, x: float, z: float) -> bool:
        return self.footprint.covers(Point(x, z))
