"""Navigability check: can a round robot drive from the front door into every room?

A world for embodied-AI research is only valid if the agent can get everywhere it is
asked to go. For each floor, this check builds the occupancy grid of the robot's height
band (:mod:`cga.checks.occupancy`), grows every obstacle by the robot's radius (a
Euclidean distance transform: a cell is drivable when its clearance, the distance from
its centre to the nearest obstacle, is at least the radius), and floods the drivable
cells from the start. The ground floor starts outside its front door, so a wardrobe in
front of the door shows up as the door being blocked.

The building is one check (DESIGN §12): floors are taken bottom up, and a floor reached
by a stair starts on the stair's top landing, but only when the robot reached the
stair's bottom landing on the floor below and the stair is wide enough for it
(``2 × radius``). Steps and stairwells are obstacles on the grids (wheels do not climb);
the stair is the edge between the two landing cells. A floor whose stair cannot be used
reports every room unreachable and says where: the bottom landing it never reached, or
the top landing that is blocked (and by what). A floor with neither a front door nor a
stair (a building without stairs) starts in its entry room, or the largest room, and
the report says so.

Doors: a robot (or its planner) can open a door, so a room counts as reachable through
any door whatever its state; the report also says which rooms the robot reaches with the
doors as the build leaves them (``reachable_as_built``) and which doors are not open
(``closed_doors``, docs/outputs.md), so a planner knows which doors it must open.

For each room the report gives whether the robot reaches it, what share of the room's
drivable floor it reaches, and the narrowest passage on the way there: the bottleneck of
the widest path, read off a maximum spanning tree of the grid weighted by clearance
(widest paths are spanning-tree paths, Hu 1961). For a room it cannot reach it says
why, in words: no door, a doorway too narrow for the robot, a doorway blocked by named
items, a room filled by furniture, or a door that leads only through a room that is
itself cut off.
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any, Literal

import numpy as np
import shapely
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import breadth_first_order, minimum_spanning_tree
from shapely.geometry import Point
from shapely.geometry.base import BaseGeometry

from cga.model import OUTSIDE, Door, FloorPlan, Room, Stair
from cga.scene import Scene, SceneNode

from ._distance import component_labels, diamond_dilation, disc_dilation, distance_to_false
from .occupancy import OccupancyGrid, occupancy_grid

__all__ = [
    "Arrival",
    "DriveSpace",
    "FloorReach",
    "NavigabilityReport",
    "Bottleneck",
    "RoomReach",
    "check_floor_navigability",
    "check_navigability",
]

_OPEN = 100.0
"""Clearance (m) standing for "unbounded" (open ground, a grid without obstacles)."""


StartKind = Literal["front_door", "stair", "entry_room", "largest_room"]
"""Where the robot starts on a floor (see :class:`FloorReach`)."""

@dataclass(frozen=True)
class Bottleneck:
    """The tightest point on the best path to a room.

    ``clearance`` is the distance (m) from that point to the nearest obstacle, so the
    passage is about ``width = 2 × clearance`` wide; ``at`` is its plan ``(x, z)``;
    ``door`` the door whose doorway it lies in (if any), ``room`` the room it lies in.
    """

    clearance: float
    at: tuple[float, float]
    door: int | None = None
    room: int | None = None

    @property
    def width(self) -> float:
        return 2.0 * self.clearance

    def to_dict(self) -> dict[str, Any]:
        return {"clearance_m": round(self.clearance, 3), "width_m": round(self.width, 3),
                "at": [round(self.at[0], 3), round(self.at[1], 3)], "door": self.door,
                "room": self.room}


@dataclass(frozen=True)
class Arrival:
    """How the robot comes onto a floor by stair: ``stair`` and the stairs before it
    (``via``, from the ground floor up); ``problem`` says why it cannot (None: it can)."""

    stair: Stair
    via: tuple[int, ...]
    problem: str | None = None


@dataclass(frozen=True)
class RoomReach:
    """One room's result. ``reachable_fraction`` is the share of the room's drivable
    cells the robot reaches (below 1 when furniture cuts off a corner); ``narrowest``
    is None for the room a robot starts in and for unreachable rooms. ``reasons`` explain an
    unreachable room; ``blocked_doors`` and ``blocking_items`` name the culprits.
    ``reachable_as_built`` is False for a room the robot reaches only by opening doors."""

    room: int
    type: str | None
    reachable: bool
    reachable_fraction: float
    narrowest: Bottleneck | None = None
    reasons: tuple[str, ...] = ()
    blocked_doors: tuple[int, ...] = ()
    blocking_items: tuple[str, ...] = ()
    reachable_as_built: bool = True

    @property
    def label(self) -> str:
        return f"room {self.room} ({self.type})" if self.type else f"room {self.room}"

    def to_dict(self) -> dict[str, Any]:
        return {
            "room": self.room,
            "type": self.type,
            "reachable": self.reachable,
            "reachable_fraction": round(self.reachable_fraction, 3),
            "narrowest": self.narrowest.to_dict() if self.narrowest else None,
            "reasons": list(self.reasons),
            "blocked_doors": list(self.blocked_doors),
            "blocking_items": list(self.blocking_items),
            "reachable_as_built": self.reachable_as_built,
        }


@dataclass(frozen=True)
class DriveSpace:
    """The grids one floor's check computed, kept for the difficulty metrics
    (:mod:`cga.difficulty`) so they measure the same space instead of rasterising again.

    ``clearance`` is the distance (m) from each cell centre to the nearest obstacle with
    every door open; ``reached`` the cells the robot's centre reaches from ``start``
    (a cell, or None when the robot has no room to start); ``room_masks`` each room's
    free floor (shrunk by one cell, so doorway cells belong to no room); ``furniture``
    the cells the furniture (not the door leaves) occupies.
    """

    grid: OccupancyGrid
    clearance: np.ndarray
    reached: np.ndarray
    start: tuple[int, int] | None
    room_masks: dict[int, np.ndarray]
    furniture: np.ndarray


@dataclass(frozen=True)
class FloorReach:
    """One floor's result. ``start`` is ``"front_door"`` (the robot starts outside door
    ``start_door``), ``"stair"`` (on the top landing of the stair ``via_stairs[-1]``, in
    its core room ``start_room``), ``"entry_room"`` (inside ``start_room``, the room
    typing made the floor's entry: floors without a stair) or ``"largest_room"``
    (untyped floors); ``note`` says why. ``closed_doors`` are the doors the build
    leaves closed or ajar.
    ``elapsed_seconds`` (wall-clock) is left out of :meth:`to_dict`, which is deterministic."""

    floor: int
    start: StartKind
    start_point: tuple[float, float]
    start_room: int | None
    start_door: int | None
    note: str
    rooms: tuple[RoomReach, ...]
    elapsed_seconds: float
    closed_doors: tuple[int, ...] = ()
    via_stairs: tuple[int, ...] = ()
    """The stairs on the way from the front door to this floor, bottom up."""
    stair_up_reached: bool | None = None
    """Whether the robot reaches the bottom landing of the stair leaving this floor."""
    space: DriveSpace | None = field(default=None, repr=False, compare=False)
    """The grids behind the result (not in :meth:`to_dict`)."""

    @property
    def passed(self) -> bool:
        return all(r.reachable for r in self.rooms)

    @property
    def unreachable(self) -> list[RoomReach]:
        return [r for r in self.rooms if not r.reachable]

    def to_dict(self) -> dict[str, Any]:
        return {
            "floor": self.floor,
            "passed": self.passed,
            "start": self.start,
            "start_point": [round(self.start_point[0], 3), round(self.start_point[1], 3)],
            "start_room": self.start_room,
            "start_door": self.start_door,
            "via_stairs": list(self.via_stairs),
            "stair_up_reached": self.stair_up_reached,
            "note": self.note,
            "reachable_rooms": [r.room for r in self.rooms if r.reachable],
            "unreachable_rooms": [r.room for r in self.unreachable],
            "closed_doors": list(self.closed_doors),
            "rooms_behind_closed_doors": [r.room for r in self.rooms
                                          if r.reachable and not r.reachable_as_built],
            "rooms": [r.to_dict() for r in self.rooms],
        }


@dataclass(frozen=True)
class NavigabilityReport:
    """The result of :func:`check_navigability`: one :class:`FloorReach` per floor."""

    floors: tuple[FloorReach, ...]
    radius: float
    resolution: float
    band: tuple[float, float]

    @property
    def passed(self) -> bool:
        return all(f.passed for f in self.floors)

    def summary(self) -> str:
        """One line for the terminal."""
        total = sum(len(f.rooms) for f in self.floors)
        bad = [(f.floor, r) for f in self.floors for r in f.unreachable]
        text = (f"navigability: {total - len(bad)}/{total} rooms reachable "
                f"(robot radius {self.radius:g} m)")
        if bad:
            text += "; " + "; ".join(f"floor {fl} {r.label}: {' / '.join(r.reasons)}"
                                     for fl, r in bad)
        return text

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready form for the scene file (``checks.navigability``)."""
        return {
            "passed": self.passed,
            "radius_m": self.radius,
            "resolution_m": self.resolution,
            "band_m": list(self.band),
            "floors": [f.to_dict() for f in self.floors],
        }


def check_navigability(scene: Scene, nodes: Sequence[SceneNode] | None = None, *,
                       radius: float = 0.25, resolution: float = 0.05,
                       band: tuple[float, float] = (0.05, 1.2)) -> NavigabilityReport:
    """Check that a round robot reaches every room of every floor through doors.

    Parameters
    ----------
    scene
        The built scene (its floor plans give rooms, doors and footprints).
    nodes
        The nodes to check; default ``scene.nodes``, the build's own meshes (made once
        per scene).
    radius
        Robot radius (m); obstacles are grown by it.
    resolution
        Grid cell size (m).
    band
        Heights above each floor's walking surface (m) in which obstacles block the robot.

    Returns
    -------
    NavigabilityReport
        ``passed`` when every room of every floor is reachable.

    Raises
    ------
    ValueError
        ``radius`` or ``resolution`` is not positive.

    Notes
    -----
    Per floor: one occupancy grid, two distance transforms, a connected-component
    labelling and a minimum spanning tree over the reached cells of a grid of
    (footprint + margin) / resolution cells; about 40 ms for a furnished 14 m × 10 m
    floor at 5 cm.
    """
    if not radius > 0:
        raise ValueError(f"check_navigability: radius must be positive, got {radius!r}")
    if nodes is None:
        nodes = scene.nodes
    floors: list[FloorReach] = []
    landings: dict[int, tuple[FloorReach, Stair]] = {}  # stair id → the floor it leaves
    for plan in scene.floors:
        arrival = _arrival(plan, landings, radius)
        reach = check_floor_navigability(plan, nodes, radius=radius, resolution=resolution,
                                         band=band, arrival=arrival)
        floors.append(reach)
        if plan.stair_up is not None:
            landings[plan.stair_up.id] = (reach, plan.stair_up)
    return NavigabilityReport(floors=tuple(floors), radius=radius, resolution=resolution,
                              band=band)


def _arrival(plan: FloorPlan, landings: dict[int, tuple[FloorReach, Stair]],
             radius: float) -> Arrival | None:
    """How the robot may come onto ``plan`` by the stair arriving there (None: no stair)."""
    stair = plan.stair_down
    if stair is None or plan.front_door() is not None:
        return None
    below, _ = landings.get(stair.id, (None, stair))
    lower = stair.floors[0]
    via = (below.via_stairs if below is not None else ()) + (stair.id,)
    x, z = stair.landing_points[0]
    if below is None or not below.stair_up_reached:
        return Arrival(stair, via, f"the only way up is stair {stair.id} from floor {lower}, "
                                   f"whose bottom landing at ({x:.2f}, {z:.2f}) on floor "
                                   f"{lower} the robot does not reach")
    if stair.width < 2 * radius:
        return Arrival(stair, via, f"stair {stair.id} from floor {lower} is {stair.width:.2f} m "
                                   f"wide, too narrow for a robot of radius {radius:g} m")
    return Arrival(stair, via)


def check_floor_navigability(plan: FloorPlan, nodes: Sequence[SceneNode], *,
                             radius: float = 0.25, resolution: float = 0.05,
                             band: tuple[float, float] = (0.05, 1.2),
                             arrival: Arrival | None = None) -> FloorReach:
    """The navigability of one floor (see :func:`check_navigability`); ``arrival`` is
    the stair the robot comes up by, when the floor has no front door."""
    if not resolution > 0:
        raise ValueError(f"check_navigability: resolution must be positive, got {resolution!r}")
    started = time.perf_counter()
    margin = max(0.5, plan.settings.wall_thickness / 2 + 2 * radius + 4 * resolution)
    grid = occupancy_grid(plan, nodes, resolution=resolution, band=band, margin=margin)
    return _FloorCheck(plan, grid, radius, arrival).run(started)


def _path_minima(values: np.ndarray, parent: np.ndarray, root: int) -> tuple[np.ndarray, np.ndarray]:
    """For every node of a rooted tree, the least value on its path to the root and the
    node holding it, by pointer jumping: O(n log depth) in numpy instead of a walk.
    Nodes outside the tree (``parent`` negative, not the root) get ``inf``."""
    n = len(values)
    ancestor = np.where(parent >= 0, parent, np.arange(n))
    ancestor[root] = root
    least = values.astype(float).copy()
    where = np.arange(n)
    outside = (parent < 0) & (np.arange(n) != root)
    # Invariant: least[v] is the minimum from v up to, not including, ancestor[v].
    while True:
        lower = least[ancestor] <= least  # ties: keep the point nearest the start
        least = np.where(lower, least[ancestor], least)
        where = np.where(lower, where[ancestor], where)
        jumped = ancestor[ancestor]
        if np.array_equal(jumped, ancestor):
            break
        ancestor = jumped
    least[outside] = np.inf
    return least, where


def _short_reach(radius: float, res: float) -> int:
    """The largest squared cell distance ``d2`` whose clearance, as
    :meth:`_FloorCheck._clearance` computes it (``sqrt(d2) * res - res / 2``, float64),
    is below ``radius``; -1 when none is. The clearance grows with ``d2``, so a cell is
    drivable exactly when no blocked cell lies within this squared distance."""

    def short(d2: int) -> bool:
        return math.sqrt(d2) * res - res / 2 < radius

    if not short(0):
        return -1
    d2 = max(0, math.floor(((radius + res / 2) / res) ** 2))
    while short(d2 + 1):
        d2 += 1
    while d2 > 0 and not short(d2):
        d2 -= 1
    return d2


class _FloorCheck:
    """The state of one floor's check: grids, clearances, labels, room masks."""

    def __init__(self, plan: FloorPlan, grid: OccupancyGrid, radius: float,
                 arrival: Arrival | None = None):
        self.plan = plan
        self.grid = grid
        self.radius = radius
        self.res = grid.resolution
        self.front = plan.front_door()
        self.arrival = arrival
        self.start_problem: str | None = None
        self.start_items: list[str] = []
        outside_blocked = np.zeros(grid.shape, dtype=bool) if self.front else ~grid.free_mask
        self.furniture = [o for o in grid.obstacles if o.kind == "furniture" and o.door is None]
        structure = grid.occupied_by(o.path for o in grid.obstacles if o.kind != "furniture")
        # every door open: what the robot can reach; as built: what it reaches unaided
        opened = grid.occupied_by(o.path for o in grid.obstacles if o.door is None)
        self.clear = self._clearance(opened | outside_blocked)
        self.drivable_as_built = self._drivable(grid.occupied | outside_blocked)
        self.bare = structure | outside_blocked
        self.drivable = self.clear >= radius
        self.drivable_bare = self._drivable(self.bare)
        self.masks = {room.id: self._room_mask(room) for room in plan.rooms}
        self.labels = component_labels(self.drivable)
        self.reached = np.zeros(grid.shape, dtype=bool)
        self._item_masks: dict[str, np.ndarray] = {}

    def _clearance(self, blocked: np.ndarray) -> np.ndarray:
        """Distance (m) from each cell centre to the nearest blocked cell's edge."""
        if not blocked.any():
            return np.full(blocked.shape, np.inf)
        return distance_to_false(~blocked) * self.res - self.res / 2

    def _drivable(self, blocked: np.ndarray) -> np.ndarray:
        """``self._clearance(blocked) >= self.radius``, the very cells, without the
        distances: those farther from every blocked cell than :func:`_short_reach`."""
        if not blocked.any():
            return np.ones(blocked.shape, dtype=bool)
        return ~disc_dilation(blocked, _short_reach(self.radius, self.res))

    @cached_property
    def clear_bare(self) -> np.ndarray:
        """The clearance of the empty floor, only wanted to explain an unreachable room."""
        return self._clearance(self.bare)

    def _room_mask(self, room: Room) -> np.ndarray:
        """The room's free floor shrunk by one cell, so doorway cells belong to no room."""
        mask = self.grid.rasterise(room.interior.buffer(-self.res, join_style="mitre"))
        return mask if mask.any() else self.grid.rasterise(room.interior)

    def run(self, started: float) -> FloorReach:
        start_kind, start_point, start_room, note = self._start()
        cell = self._landing_cell() if start_kind == "stair" else self._start_cell(start_point)
        as_built = np.zeros(self.grid.shape, dtype=bool)
        if cell is not None:
            self.reached = self.labels == self.labels[cell]
            if self.drivable_as_built[cell]:
                labels = component_labels(self.drivable_as_built)
                as_built = labels == labels[cell]
        reached = self.reached
        reachable = {rid: bool((m & reached).any()) for rid, m in self.masks.items()}
        inside_start = start_room if start_kind != "front_door" else None
        narrowest = self._narrowest(cell, reached, inside_start) if cell is not None else {}
        rooms = []
        for room in self.plan.rooms:
            mask = self.masks[room.id]
            drivable = mask & self.drivable
            fraction = float((mask & reached).sum() / drivable.sum()) if drivable.any() else 0.0
            if reachable[room.id]:
                rooms.append(RoomReach(room.id, room.type, True, fraction,
                                       narrowest.get(room.id),
                                       reachable_as_built=bool((mask & as_built).any())))
                continue
            reasons, doors, items = self._why(room, cell, reachable, start_kind)
            rooms.append(RoomReach(room.id, room.type, False, fraction, None, tuple(reasons),
                                   tuple(doors), tuple(items), reachable_as_built=False))
        up = self.plan.stair_up
        landing_reached = (bool((self.grid.rasterise(up.landings[0]) & reached).any())
                           if up is not None else None)
        return FloorReach(floor=self.plan.index, start=start_kind, start_point=start_point,
                          start_room=start_room,
                          start_door=self.front.id if self.front else None, note=note,
                          rooms=tuple(rooms), elapsed_seconds=time.perf_counter() - started,
                          closed_doors=tuple(d.id for d in self.plan.doors if not d.passable),
                          via_stairs=self.arrival.via if self.arrival else (),
                          stair_up_reached=landing_reached,
                          space=DriveSpace(self.grid, self.clear, reached, cell, self.masks,
                                           self.grid.occupied_by(o.path for o in self.furniture)))

    # -- the start ---------------------------------------------------------------------

    def _start(self) -> tuple[StartKind, tuple[float, float], int | None, str]:
        if self.front is not None:
            inside = next((r for r in self.front.rooms if r != OUTSIDE), None)
            return ("front_door", self._outside_of(self.front), inside,
                    f"the robot starts outside front door {self.front.id}")
        if self.arrival is not None:
            stair = self.arrival.stair
            x, z = stair.landing_points[1]
            self.start_problem = self.arrival.problem
            return ("stair", (x, z), stair.rooms[1],
                    f"the robot comes up stair {stair.id} from floor {stair.floors[0]} and "
                    f"starts on its top landing at ({x:.2f}, {z:.2f})")
        why = ("upper floor" if self.plan.index > 0 else "floor without a front door")
        kind: StartKind
        if self.plan.entry is not None:
            room = self.plan.room(self.plan.entry)
            kind, which = "entry_room", "the entry room where the stair arrives"
        else:
            room = max(self.plan.rooms, key=lambda r: (r.area, -r.id))
            kind, which = "largest_room", "the largest room"
        where = np.where(self.masks[room.id], self.clear, -np.inf)
        row, col = np.unravel_index(int(np.argmax(where)), where.shape)
        return (kind, self.grid.cell_to_world(int(row), int(col)), room.id,
                f"{why} without a stair: the robot starts in {which} "
                f"(room {room.id}, {room.area:.1f} m²), at its most open point")

    def _outside_of(self, door: Door) -> tuple[float, float]:
        """A point outside the front door, far enough from the wall for the robot."""
        wall = self.plan.wall(door.wall)
        dx, dz = wall.direction
        normal = np.array([-dz, dx])
        centre = np.asarray(door.position, dtype=float)
        if self.plan.footprint.covers(Point(*(centre + normal * 0.01))):
            normal = -normal
        reach = wall.thickness / 2 + self.radius + 3 * self.res
        point = centre + normal * reach
        return (float(point[0]), float(point[1]))

    def _landing_cell(self) -> tuple[int, int] | None:
        """The drivable cell of the arrival's top landing nearest where the stair ends,
        or None (with ``start_problem`` set) when the stair cannot be used."""
        assert self.arrival is not None
        if self.start_problem is not None:
            return None
        stair = self.arrival.stair
        landing = self.grid.rasterise(stair.landings[1]) & self.drivable
        x, z = stair.landing_points[1]
        if not landing.any():
            area = self.grid.rasterise(stair.landings[1])
            self.start_items = self._items_touching(area)
            self.start_problem = (
                f"the only way up is stair {stair.id} from floor {stair.floors[0]}, and its top "
                f"landing at ({x:.2f}, {z:.2f}) on floor {self.plan.index} is blocked"
                + (f" by {', '.join(self.start_items)}" if self.start_items else
                   f" (no room for a robot of radius {self.radius:g} m)"))
            return None
        rows, cols = np.nonzero(landing)
        row, col = self.grid.world_to_cell(x, z)
        k = int(np.argmin((rows - row) ** 2 + (cols - col) ** 2))
        return int(rows[k]), int(cols[k])

    def _start_cell(self, point: tuple[float, float]) -> tuple[int, int] | None:
        """The drivable cell at (or, within one robot radius, nearest to) ``point``."""
        row, col = self.grid.world_to_cell(*point)
        span = math.ceil(self.radius / self.res)
        best, best_d = None, math.inf
        for r in range(row - span, row + span + 1):
            for c in range(col - span, col + span + 1):
                if self.grid.in_bounds(r, c) and self.drivable[r, c]:
                    d = (r - row) ** 2 + (c - col) ** 2
                    if d < best_d:
                        best, best_d = (r, c), d
        return best

    # -- narrowest passages ------------------------------------------------------------

    def _narrowest(self, cell: tuple[int, int], reached: np.ndarray,
                   start_room: int | None) -> dict[int, Bottleneck]:
        """The bottleneck of the widest path from the start to each reachable room.

        The widest (maximin) paths between all cells are the paths of a maximum spanning
        tree of the grid graph whose edges weigh the smaller clearance of their two cells
        (Hu 1961), so one spanning tree and one traversal give every room's bottleneck:
        the least clearance on the tree path to the room's best-connected cell. The open
        ground outside the front door does not count as a passage.
        """
        shape = self.grid.shape
        flat = np.flatnonzero(reached)
        index = np.full(shape[0] * shape[1], -1, dtype=np.int64)
        index[flat] = np.arange(len(flat))
        index = index.reshape(shape)
        clear = np.where(self.grid.free_mask, self.clear, np.inf) if self.front else self.clear
        clear = np.minimum(clear, _OPEN).ravel()[flat]
        pairs = []
        for a, b in (((slice(None), slice(None, -1)), (slice(None), slice(1, None))),
                     ((slice(None, -1), slice(None)), (slice(1, None), slice(None)))):
            both = reached[a] & reached[b]
            pairs.append((index[a][both], index[b][both]))
        u = np.concatenate([p[0] for p in pairs])
        v = np.concatenate([p[1] for p in pairs])
        weight = (_OPEN + 1.0) - np.minimum(clear[u], clear[v])
        graph = coo_matrix((weight, (u, v)), shape=(len(flat), len(flat))).tocsr()
        tree = minimum_spanning_tree(graph)
        root = int(index[cell])
        _, parent = breadth_first_order(tree, root, directed=False, return_predecessors=True)
        least, where = _path_minima(clear, parent, root)
        out = {}
        for rid, mask in self.masks.items():
            inside = index[mask & reached]
            if rid == start_room or inside.size == 0:
                continue
            best = inside[int(np.argmax(least[inside]))]
            row, col = divmod(int(flat[where[best]]), shape[1])
            x, z = self.grid.cell_to_world(row, col)
            out[rid] = Bottleneck(clearance=float(least[best]), at=(x, z),
                               door=self._door_at(x, z), room=self._room_at(row, col))
        return out

    def _door_at(self, x: float, z: float) -> int | None:
        point = Point(x, z)
        for door in self.plan.doors:
            if self._doorway(door, self.radius + 2 * self.res).covers(point):
                return door.id
        return None

    def _room_at(self, row: int, col: int) -> int | None:
        point = Point(*self.grid.cell_to_world(row, col))
        return next((r.id for r in self.plan.rooms if r.polygon.covers(point)), None)

    # -- reasons -----------------------------------------------------------------------

    def _doorway(self, door: Door, reach: float) -> BaseGeometry:
        """The door's opening, ``reach`` metres deep beyond the wall line on both sides
        (plus the wall thickness, so it spans the solid however the wall sits on its line)."""
        depth = self.plan.wall(door.wall).thickness + reach
        return self._door_rect(door, -depth, depth)

    def _door_rect(self, door: Door, near: float, far: float) -> BaseGeometry:
        """The rectangle across the door's width between signed distances ``near`` and
        ``far`` from the wall line (positive to the wall's left)."""
        dx, dz = self.plan.wall(door.wall).direction
        cx, cz = door.position
        half = door.width / 2
        corners = [(-half, near), (half, near), (half, far), (-half, far)]
        return shapely.Polygon([(cx + a * dx - b * dz, cz + a * dz + b * dx) for a, b in corners])

    def _passable(self, door: Door, drivable: np.ndarray) -> bool:
        """Whether drivable cells cross the door's opening from one side to the other."""
        depth = self.plan.wall(door.wall).thickness + 2 * self.res
        inside = drivable & self.grid.rasterise(self._door_rect(door, -depth, depth))
        labels = component_labels(inside)
        ends = [self.grid.rasterise(self._door_rect(door, lo, hi))
                for lo, hi in ((-depth, -depth + self.res), (depth - self.res, depth))]
        return bool(np.intersect1d(labels[ends[0] & inside], labels[ends[1] & inside]).size)

    def _why(self, room: Room, cell: tuple[int, int] | None, reachable: dict[int, bool],
             start_kind: str) -> tuple[list[str], list[int], list[str]]:
        """Reasons, blocked door ids and blocking item paths of an unreachable room."""
        if cell is None:
            if self.start_problem is not None:
                return [self.start_problem], [], list(self.start_items)
            where = "outside the front door" if start_kind == "front_door" else "in the start room"
            return [f"the robot has no room to start {where}"], [], []
        mask = self.masks[room.id]
        reasons: list[str] = []
        blocked: list[int] = []
        items: list[str] = []
        if not (mask & self.drivable_bare).any():
            space = float(self.clear_bare[mask].max()) if mask.any() else 0.0
            reasons.append(f"too narrow for a robot of radius {self.radius:g} m even when empty "
                           f"(largest clearance {space:.2f} m)")
        elif not (mask & self.drivable).any():
            names = self._items_touching(mask)
            items.extend(names)
            reasons.append("fully blocked by furniture" + (f": {', '.join(names)}" if names else ""))
        doors = [d for d in self.plan.doors if room.id in d.rooms]
        if not doors:
            reasons.append("has no door")
        for door in doors:
            other = door.rooms[1] if door.rooms[0] == room.id else door.rooms[0]
            where = "outside" if other == OUTSIDE else self._label(other)
            if not self._passable(door, self.drivable_bare):
                reasons.append(self._why_closed(door, where))
            elif not self._passable(door, self.drivable):
                blocked.append(door.id)
                names = self._items_touching(self.grid.rasterise(
                    self._doorway(door, 2 * self.res).buffer(self.radius)))
                items.extend(n for n in names if n not in items)
                reasons.append(f"doorway of door {door.id} to {where} is blocked by furniture"
                               + (f": {', '.join(names)}" if names else ""))
            elif other == OUTSIDE:
                reasons.append(f"door {door.id} leads outside, "
                               + ("whose approach furniture cuts off" if self.front
                                  else "which is not on this floor's map (no front door)"))
            elif not reachable[other]:
                reasons.append(f"door {door.id} leads to {where}, which is unreachable itself")
            else:
                near = self._items_near_door(door, other)
                items.extend(n for n in near if n not in items)
                reasons.append(f"door {door.id} to {where} is clear, but furniture cuts its "
                               f"approach off from the rest of {where}"
                               + (f": {', '.join(near)}" if near else ""))
        return reasons, blocked, items

    def _why_closed(self, door: Door, where: str) -> str:
        """Why the bare structure leaves no passage through a door: the opening itself is
        narrower than the robot, or something built stands in or before it (named)."""
        if door.width <= 2 * self.radius:
            return (f"door {door.id} to {where} is too narrow for the robot "
                    f"({door.width:.2f} m wide, needs more than {2 * self.radius:.2f} m)")
        doorway = self.grid.rasterise(self._doorway(door, self.radius + 2 * self.res))
        names = [o.path for o in self.grid.obstacles
                 if o.kind not in ("furniture", "wall") and o.door is None
                 and (self.grid.occupied_by([o.path]) & doorway).any()]
        shown = ", ".join(names[:3]) + (f" and {len(names) - 3} more" if len(names) > 3 else "")
        return (f"door {door.id} to {where} is {door.width:.2f} m wide, but the building "
                f"itself leaves no passage {2 * self.radius:.2f} m wide through it"
                + (f": blocked by {shown}" if names else ""))

    def _label(self, room_id: int) -> str:
        room = self.plan.room(room_id)
        return f"room {room.id} ({room.type})" if room.type else f"room {room.id}"

    def _items_near_door(self, door: Door, room_id: int) -> list[str]:
        """Furniture of room ``room_id`` that separates the drivable patch behind the door
        from the part of the room the robot reaches: items bordering both (or, when no
        item borders both, every item bordering the patch)."""
        strip = self.grid.rasterise(self._doorway(door, 0.0)) & self.drivable
        patch = np.isin(self.labels, np.unique(self.labels[strip]))
        reach = math.ceil(self.radius / self.res) + 1
        near_patch = self._items_touching(diamond_dilation(patch, reach),
                                          room_id)
        rest = self.reached & self.masks[room_id]
        near_rest = set(self._items_touching(diamond_dilation(rest, reach),
                                             room_id))
        between = [path for path in near_patch if path in near_rest]
        return between or near_patch

    def _items_touching(self, mask: np.ndarray, room_id: int | None = None) -> list[str]:
        """Paths of the furniture obstacles (of room ``room_id``, when given) that occupy
        any cell of ``mask``."""
        out = []
        for obstacle in self.furniture:
            if room_id is not None and obstacle.room not in (None, room_id):
                continue
            cells = self._item_masks.get(obstacle.path)
            if cells is None:
                cells = self._item_masks[obstacle.path] = self.grid.occupied_by([obstacle.path])
            if (cells & mask).any():
                out.append(obstacle.path)
        return out
