"""How hard a built floor is for a robot: measured, for every build (DESIGN §13).

The UvA generator (Zwennes 2011) sets a difficulty knob and its operators rated the
result; this module measures what the rules change, so any build (any grammar, not only
the grid mode) states its difficulty in numbers. Two kinds of metric:

* from the plan: the door graph (cycle rank ``E − V + C``, doors per room, dead ends),
  corridor length, clutter (items per m²);
* from the navigability check's grids (:class:`cga.checks.navigability.DriveSpace`,
  reused, not recomputed): free-area share, mean and narrowest free width at the robot
  radius, tortuosity of the shortest paths from the start to every room, reachable
  share of the floor, and an exploration proxy (:mod:`.exploration`). Without the check
  (``--no-physics``) these are None.

Every formula is in docs/difficulty.md.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import asdict, dataclass, fields
from typing import TYPE_CHECKING, Any

import numpy as np
import shapely

from cga.checks._distance import disc_dilation, disc_dilations, squared_reach
from cga.model import OUTSIDE, FloorPlan

if TYPE_CHECKING:  # pragma: no cover
    import networkx as nx

    from cga.checks.navigability import DriveSpace, FloorReach, NavigabilityReport
    from cga.scene import Scene

__all__ = ["FloorDifficulty", "DifficultyReport", "door_graph", "cycle_rank", "dead_ends",
           "doors_per_room", "corridor_length", "items_per_m2", "grid_metrics",
           "measure_floor", "measure_scene", "mean_metrics", "METRICS"]

MIN_TORTUOSITY_DISTANCE = 1.0
"""Rooms whose target lies closer than this (m, straight line) to the start are left
out of the tortuosity: a ratio of two tiny lengths says nothing."""


@dataclass(frozen=True)
class FloorDifficulty:
    """The difficulty metrics of one floor (docs/difficulty.md). Grid metrics are None
    when the navigability check did not run."""

    floor: int
    rooms: int
    cycle_rank: int
    doors_per_room: float
    dead_ends: int
    corridor_length_m: float
    items_per_m2: float
    free_area_share: float | None = None
    mean_free_width_m: float | None = None
    narrowest_free_width_m: float | None = None
    tortuosity: float | None = None
    reachable_share: float | None = None
    exploration_path_m: float | None = None

    def to_dict(self) -> dict[str, Any]:
        return {k: (round(v, 4) if isinstance(v, float) else v) for k, v in asdict(self).items()}


METRICS: tuple[str, ...] = tuple(f.name for f in fields(FloorDifficulty)
                                 if f.name not in ("floor", "rooms"))
"""The metric names, in report order."""


@dataclass(frozen=True)
class DifficultyReport:
    """The metrics of every floor and of the whole building (:meth:`totals`)."""

    floors: tuple[FloorDifficulty, ...]
    radius: float | None

    def totals(self) -> dict[str, float | int | None]:
        """The building's metrics: counts and lengths summed over floors, ratios
        weighted by rooms (doors per room) or taken over all rooms, the narrowest width
        the least of the floors', shares and tortuosity the mean of the floors'."""
        out: dict[str, float | int | None] = {}
        floors = self.floors
        rooms = sum(f.rooms for f in floors)
        for name in METRICS:
            values = [getattr(f, name) for f in floors if getattr(f, name) is not None]
            if not values:
                out[name] = None
            elif name in ("cycle_rank", "dead_ends"):
                out[name] = int(sum(values))
            elif name in ("corridor_length_m", "exploration_path_m"):
                out[name] = round(float(sum(values)), 4)
            elif name == "narrowest_free_width_m":
                out[name] = round(float(min(values)), 4)
            elif name == "doors_per_room":
                out[name] = round(sum(f.doors_per_room * f.rooms for f in floors) / rooms, 4) \
                    if rooms else 0.0
            else:
                out[name] = round(float(np.mean(values)), 4)
        return out

    def summary(self) -> str:
        """One line for the terminal."""
        t = self.totals()

        def fmt(name: str, text: str) -> str | None:
            value = t[name]
            return None if value is None else text.format(value)

        parts = [fmt("cycle_rank", "cycle rank {}"), fmt("doors_per_room", "{:.2f} doors/room"),
                 fmt("dead_ends", "{} dead ends"), fmt("corridor_length_m", "corridors {:.1f} m"),
                 fmt("items_per_m2", "{:.2f} items/m²"),
                 fmt("free_area_share", "free {:.0%}"),
                 fmt("mean_free_width_m", "width {:.2f} m mean"),
                 fmt("narrowest_free_width_m", "{:.2f} m narrowest"),
                 fmt("tortuosity", "tortuosity {:.2f}"),
                 fmt("reachable_share", "reachable {:.0%}"),
                 fmt("exploration_path_m", "exploration {:.0f} m")]
        return "difficulty: " + ", ".join(p for p in parts if p)

    def to_dict(self) -> dict[str, Any]:
        return {"robot_radius_m": self.radius, "totals": self.totals(),
                "floors": [f.to_dict() for f in self.floors]}


# -- plan metrics ----------------------------------------------------------------------


def door_graph(plan: FloorPlan) -> nx.MultiGraph:
    """Rooms joined by one edge per door between two rooms (doors to the outside left
    out): two doors between the same rooms are a cycle a robot can drive round."""
    import networkx as nx

    graph = nx.MultiGraph()
    graph.add_nodes_from(room.id for room in plan.rooms)
    graph.add_edges_from(door.rooms for door in plan.doors if OUTSIDE not in door.rooms)
    return graph


def cycle_rank(plan: FloorPlan) -> int:
    """``E − V + C`` of :func:`door_graph`: independent cycles (loops) of the floor."""
    import networkx as nx

    graph = door_graph(plan)
    return (graph.number_of_edges() - graph.number_of_nodes()
            + nx.number_connected_components(graph))


def _door_counts(plan: FloorPlan) -> dict[int, int]:
    counts = {room.id: 0 for room in plan.rooms}
    for door in plan.doors:
        for room in door.rooms:
            if room != OUTSIDE:
                counts[room] += 1
    return counts


def doors_per_room(plan: FloorPlan) -> float:
    """Mean over rooms of the doors in a room's walls (a front door counts)."""
    counts = _door_counts(plan)
    return sum(counts.values()) / len(counts) if counts else 0.0


def dead_ends(plan: FloorPlan) -> int:
    """Rooms with exactly one door: a robot must turn and leave the way it came."""
    return sum(1 for n in _door_counts(plan).values() if n == 1)


def corridor_length(plan: FloorPlan) -> float:
    """Σ over circulation rooms of ``area / width``, width the diameter of the largest
    circle inside the room's free floor: a corridor's length along its centre line."""
    total = 0.0
    for room in plan.rooms:
        if not room.circulation or room.interior.is_empty:
            continue
        radius = shapely.maximum_inscribed_circle(room.interior).length
        if radius > 0:
            total += room.interior.area / (2 * radius)
    return total


def items_per_m2(plan: FloorPlan) -> float:
    """Furniture items (not door leaves or window panes) per m² of the rooms' free floor."""
    area = sum(room.interior.area for room in plan.rooms)
    items = sum(1 for item in plan.furniture if not item.is_detail)
    return items / area if area > 0 else 0.0


# -- grid metrics ----------------------------------------------------------------------


def _geodesic(reached: np.ndarray, start: tuple[int, int], resolution: float,
              targets: np.ndarray) -> np.ndarray:
    """Shortest 8-connected path length (m) from ``start`` over the reached cells to
    each of ``targets`` (flat indices of reached cells)."""
    from scipy.sparse.csgraph import dijkstra

    from .exploration import _grid_graph

    graph, index = _grid_graph(reached, resolution)
    distances = dijkstra(graph, directed=True, indices=int(index[start]))
    return np.asarray(distances[index.ravel()[targets]])


WIDTH_STEP = 0.1
"""Resolution (m) of the local width: discs are tried at radii in steps of half this."""

MAX_WIDTH = 6.0
"""Local widths are counted up to this (m): beyond it a space is simply open."""


_LOWEST_BITS = np.array([(1 << n) - 1 for n in range(9)], dtype=np.uint8)
"""The byte with its ``n`` lowest bits set, for ``n`` from 0 to 8."""

_BIT_LENGTH = np.array([b.bit_length() for b in range(256)], dtype=np.uint8)
"""The position of each byte's highest bit plus 1 (0 for 0)."""


def local_width(clearance: np.ndarray, resolution: float) -> np.ndarray:
    """The local width (thickness) of the free space at every cell: the diameter of the
    largest free disc that covers the cell, to :data:`WIDTH_STEP`.

    A disc of radius ``r`` centred on a cell whose clearance is at least ``r`` is free, so
    a cell lies in a free disc of radius ``r`` exactly when it is within ``r`` of such a
    centre: one dilation of the centres by the disc per radius (Hildebrand and
    Rüegsegger 1997 define the same thickness), eight radii at a time in the bit planes
    of one byte grid (:func:`disc_dilations`), on the bounding box of the smallest
    radius's centres grown by the largest radius (no cell farther out is within reach of
    a centre). A cell's width is twice the largest radius whose disc covers it; the
    radii are counted in small integers and turned into widths once. Cells in no free
    disc (the obstacles) get 0.
    """
    radii = _radii()
    count = np.zeros(clearance.shape, dtype=np.uint8)  # radii[count - 1] the largest
    row_best, col_best = clearance.max(axis=1), clearance.max(axis=0)
    best = row_best.max()
    for first in range(0, len(radii), 8):
        group = [radius for radius in radii[first:first + 8] if radius <= best]
        if not group:
            break
        rows, cols = np.flatnonzero(row_best >= group[0]), np.flatnonzero(col_best >= group[0])
        reaches = [squared_reach(radius, resolution) for radius in group]
        grow = math.isqrt(reaches[-1])
        box = (slice(max(0, int(rows[0]) - grow), int(rows[-1]) + grow + 1),
               slice(max(0, int(cols[0]) - grow), int(cols[-1]) + grow + 1))
        # the centres of radius group[j] in bit j: the radii a cell admits are the first
        # ones (those up to its clearance), so its bits are the lowest ones
        part, admitted = clearance[box], np.zeros(count[box].shape, dtype=np.uint8)
        for radius in group:
            admitted += part >= radius
        planes = disc_dilations(_LOWEST_BITS[admitted], reaches)
        counts = _BIT_LENGTH + np.uint8(first)  # a byte's radii: up to its highest bit's
        counts[0] = 0
        np.maximum(count[box], counts[planes], out=count[box])
    return np.array([0.0] + [2 * radius for radius in radii])[count]


def _radii() -> list[float]:
    """The disc radii :func:`local_width` tries: multiples of half :data:`WIDTH_STEP` up
    to half :data:`MAX_WIDTH`, accumulated step by step (so each is the same float
    however the loop runs)."""
    out, radius = [], WIDTH_STEP / 2
    while radius <= MAX_WIDTH / 2:
        out.append(radius)
        radius += WIDTH_STEP / 2
    return out


def grid_metrics(plan: FloorPlan, space: "DriveSpace", reach: "FloorReach",
                 radius: float) -> dict[str, float | None]:
    """The metrics read off the navigability check's grids (docs/difficulty.md)."""
    grid = space.grid
    res = grid.resolution
    in_rooms = np.zeros(grid.shape, dtype=bool)
    for mask in space.room_masks.values():
        in_rooms |= mask
    structure_free = in_rooms & ~(grid.occupied & ~space.furniture)
    room_cells = int(structure_free.sum())
    free = structure_free & ~space.furniture
    out: dict[str, float | None] = {
        "free_area_share": float(free.sum() / room_cells) if room_cells else None}
    reached = space.reached
    # the floor the robot's body covers: cells within the radius of a reached centre
    body = disc_dilation(reached, squared_reach(radius, res))
    out["reachable_share"] = float((body & free).sum() / free.sum()) if free.any() else None
    clear = np.minimum(space.clearance, 100.0)
    floor = body & free
    if floor.any():  # the widths of the floor the robot covers, on its bounding box
        rows, cols = np.nonzero(floor)
        box = (slice(max(0, rows.min() - 1), rows.max() + 2),
               slice(max(0, cols.min() - 1), cols.max() + 2))
        out["mean_free_width_m"] = float(local_width(clear[box], res)[floor[box]].mean())
    else:
        out["mean_free_width_m"] = None
    widths = [r.narrowest.width for r in reach.rooms if r.narrowest is not None]
    out["narrowest_free_width_m"] = float(min(widths)) if widths else None
    out["tortuosity"] = None
    out["exploration_path_m"] = None
    if space.start is None or not reached[space.start]:
        return out
    rooms = [(mask, cells) for mask in space.room_masks.values()
             if (cells := np.flatnonzero(mask & reached)).size]
    # each reached room's target: its reached cell of most clearance (the first of equals)
    targets = np.array([int(cells[np.argmax(clear.ravel()[cells])]) for _, cells in rooms],
                       dtype=np.int64)
    distances = _geodesic(reached, space.start, res, targets)
    ratios = []
    start_xz = np.asarray(grid.cell_to_world(*space.start))
    for target, distance in zip(targets.tolist(), distances.tolist()):
        row, col = divmod(target, clear.shape[1])
        straight = float(np.linalg.norm(np.subtract(grid.cell_to_world(row, col), start_xz)))
        if straight >= MIN_TORTUOSITY_DISTANCE and math.isfinite(distance):
            ratios.append(max(1.0, distance / straight))
    out["tortuosity"] = float(np.mean(ratios)) if ratios else None
    seen = np.zeros(grid.shape, dtype=bool)
    for mask, _ in rooms:
        seen |= mask & free
    from .exploration import exploration_path

    out["exploration_path_m"] = exploration_path(seen, grid.occupied & ~_door_leaves(space),
                                                 reached, space.start, res)
    return out


def _door_leaves(space: "DriveSpace") -> np.ndarray:
    """Cells of door leaves (open doors stand against their jambs; a robot opens the
    others), which do not stop the explorer's view through an open doorway."""
    grid = space.grid
    return grid.occupied_by(o.path for o in grid.obstacles if o.door is not None)


def measure_floor(plan: FloorPlan, reach: "FloorReach | None" = None,
                  radius: float | None = None) -> FloorDifficulty:
    """All metrics of one floor; grid metrics only when ``reach`` carries its grids."""
    base = FloorDifficulty(
        floor=plan.index, rooms=len(plan.rooms), cycle_rank=cycle_rank(plan),
        doors_per_room=doors_per_room(plan), dead_ends=dead_ends(plan),
        corridor_length_m=corridor_length(plan), items_per_m2=items_per_m2(plan))
    if reach is None or reach.space is None or radius is None:
        return base
    values = grid_metrics(plan, reach.space, reach, radius)
    return FloorDifficulty(**{**asdict(base), **values})


def measure_scene(scene: "Scene") -> DifficultyReport | None:
    """The difficulty of a built scene (None without floors), reusing the navigability
    check's grids when it ran."""
    floors = scene.floors
    if not floors:
        return None
    nav: NavigabilityReport | None = scene.checks.get("navigability")  # type: ignore[assignment]
    by_index = {f.floor: f for f in nav.floors} if nav is not None else {}
    radius = nav.radius if nav is not None else None
    return DifficultyReport(tuple(measure_floor(p, by_index.get(p.index), radius) for p in floors),
                            radius)


def mean_metrics(rows: Iterable[dict[str, Any]]) -> dict[str, float | None]:
    """Mean of every metric over records of :meth:`DifficultyReport.totals` (None values
    left out), for batch and sweep reports."""
    rows = list(rows)
    out: dict[str, float | None] = {}
    for name in METRICS:
        values: Sequence[float] = [r[name] for r in rows if r.get(name) is not None]
        out[name] = round(float(np.mean(values)), 4) if values else None
    return out
