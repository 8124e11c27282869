"""A small hand-built two-storey scene for the exporter tests.

8 m × 6 m footprint, 0.2 m walls, three rooms per floor (a big room on the west side,
two small ones on the east side), doors between them, a front door on the north wall
(z = 6) of floor 0, windows on outer walls, and a few furniture items. Nodes are plain
trimesh boxes: wall pieces around the openings, slabs, furniture boxes with one convex
part each. Floor 1 has a bed whose centre is at world x = 2, z = 3 (the frames test).
"""

from __future__ import annotations

import math

import networkx as nx
import numpy as np
import pytest
import trimesh
from shapely.geometry import LineString, Point, box
from shapely.ops import unary_union

from cga.model import (OUTSIDE, Door, FloorPlan, FloorSettings, FurnitureItem, Opening, Room,
                       Wall, Window)
from cga.scene import Scene, SceneNode
from cga.shape import Mass, Shape
from items import item_info
from reports import FixedReport


STOREY = 3.0
SETTINGS = FloorSettings()
T = SETTINGS.wall_thickness
FOOTPRINT = box(0.0, 0.0, 8.0, 6.0)

# (id, start, end, outer, rooms): rooms (left, right) walking from start to end
WALLS = [
    (0, (0.0, 0.0), (5.0, 0.0), True, (0, OUTSIDE)),
    (1, (5.0, 0.0), (8.0, 0.0), True, (1, OUTSIDE)),
    (2, (8.0, 0.0), (8.0, 3.0), True, (1, OUTSIDE)),
    (3, (8.0, 3.0), (8.0, 6.0), True, (2, OUTSIDE)),
    (4, (8.0, 6.0), (5.0, 6.0), True, (2, OUTSIDE)),
    (5, (5.0, 6.0), (0.0, 6.0), True, (0, OUTSIDE)),
    (6, (0.0, 6.0), (0.0, 0.0), True, (0, OUTSIDE)),
    (7, (5.0, 0.0), (5.0, 3.0), False, (0, 1)),
    (8, (5.0, 3.0), (5.0, 6.0), False, (0, 2)),
    (9, (5.0, 3.0), (8.0, 3.0), False, (2, 1)),
]
ROOM_BOXES = {0: (0.0, 0.0, 5.0, 6.0), 1: (5.0, 0.0, 8.0, 3.0), 2: (5.0, 3.0, 8.0, 6.0)}


def _interior(polygon):
    inner = unary_union([LineString([s, e]).buffer(T / 2, cap_style="flat")
                         for _, s, e, outer, _ in WALLS if not outer])
    return polygon.intersection(FOOTPRINT.buffer(-T, join_style="mitre")).difference(inner)


def _doors(floor: int) -> tuple[Door, ...]:
    # open: the scene has no door leaves, so its doorways are free
    opened = {"state": "open", "angle": math.pi / 2}
    doors = [
        Door(0, 7, (0, 1), (5.0, 1.5), 0.9, 2.1, swing_room=1, hinge="start", **opened),
        Door(1, 9, (1, 2), (6.5, 3.0), 0.9, 2.1, swing_room=2, hinge="end", **opened),
    ]
    if floor == 0:
        doors.append(Door(2, 5, (0, OUTSIDE), (2.5, 6.0), 1.0, 2.1, swing_room=0,
                          hinge="start", is_front=True, reason="front", **opened))
    return tuple(doors)


def _windows() -> tuple[Window, ...]:
    return (
        Window(0, 0, 0, (2.5, 0.0), 1.2, 1.2, 0.9),
        Window(1, 2, 1, (8.0, 1.5), 1.2, 1.2, 0.9),
        Window(2, 6, 0, (0.0, 3.0), 1.2, 1.2, 0.9),
    )


def _walls(doors, windows) -> tuple[Wall, ...]:
    walls = []
    for wid, start, end, outer, rooms in WALLS:
        wall = Wall(wid, start, end, outer, rooms, T)
        for d in doors:
            if d.wall == wid:
                wall = wall.with_opening(Opening("door", math.dist(start, d.position),
                                                 d.width, d.height))
        for w in windows:
            if w.wall == wid:
                wall = wall.with_opening(Opening("window", math.dist(start, w.position),
                                                 w.width, w.height, w.sill))
        walls.append(wall)
    return tuple(walls)


def make_plan(index: int, types: tuple[str, str, str],
              furniture: tuple[FurnitureItem, ...]) -> FloorPlan:
    rooms = tuple(Room(i, box(*ROOM_BOXES[i]), _interior(box(*ROOM_BOXES[i])), types[i])
                  for i in range(3))
    doors = _doors(index)
    windows = _windows()
    graph = nx.Graph()
    graph.add_nodes_from([OUTSIDE, 0, 1, 2])
    graph.add_edges_from([(0, 1), (1, 2)] + ([(0, OUTSIDE)] if index == 0 else []))
    return FloorPlan(index=index, elevation=index * STOREY, height=STOREY, footprint=FOOTPRINT,
                     settings=SETTINGS, rooms=rooms, walls=_walls(doors, windows),
                     windows=windows, doors=doors, furniture=furniture, room_graph=graph,
                     is_top=index == 1)


FURNITURE = {
    0: (
        FurnitureItem("sofa", "sofa", 0, (2.5, 1.0), 0, (2.0, 0.8, 0.9)),
        FurnitureItem("rug", "rug", 0, (2.5, 3.0), 0, (2.0, 0.01, 1.4), non_collision=True),
        FurnitureItem("table", "dining table", 1, (6.8, 1.5), 1, (1.2, 0.75, 0.8)),
        FurnitureItem("shelf", "shelf", 2, (7.5, 5.0), 3, (1.0, 1.8, 0.4)),
    ),
    1: (
        FurnitureItem("bed", "double bed", 0, (2.0, 3.0), 1, (1.6, 0.5, 2.0)),
        FurnitureItem("desk", "desk", 1, (6.5, 0.6), 2, (1.2, 0.75, 0.6)),
    ),
}
TYPES = {0: ("Livingroom", "Kitchen", "Bathroom"), 1: ("Bedroom", "Office", "Bathroom")}


def _box_node(path, kind, lo, hi, *, static=True, extras=None, parts=False, item=None):
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)
    mesh = trimesh.creation.box(extents=hi - lo)
    mesh.apply_translation((lo + hi) / 2)
    return SceneNode(path, kind, mesh, dict(extras or {}), static, (mesh.copy(),) if parts else (),
                     item)


def _inward(wall: Wall) -> np.ndarray:
    d = wall.direction
    n = np.array([-d[1], d[0]])
    mid = np.add(wall.start, wall.end) / 2
    return n if FOOTPRINT.contains(Point(*(mid + n * T / 2))) else -n


def _wall_nodes(plan: FloorPlan) -> list[SceneNode]:
    nodes = []
    floor_y, top = plan.floor_y, plan.elevation + plan.height
    for wall in plan.walls:
        room = plan.room(next(r for r in wall.rooms if r != OUTSIDE))
        d = np.append(wall.direction, 0.0)
        n = _inward(wall) if wall.outer else np.array([-d[1], d[0]])
        across = (0.0, T) if wall.outer else (-T / 2, T / 2)
        cuts = sorted((o.center - o.width / 2, o.center + o.width / 2, o) for o in wall.openings)
        edges = sorted({0.0, wall.length, *[c for a, b, _ in cuts for c in (a, b)]})
        pieces = []
        for a, b in zip(edges, edges[1:]):
            hole = next((o for s, e, o in cuts if s <= a and b <= e), None)
            spans = [(0.0, top - floor_y)] if hole is None else [
                (0.0, hole.sill), (hole.sill + hole.height, top - floor_y)]
            pieces += [(a, b, y0, y1) for y0, y1 in spans if y1 - y0 > 1e-9]
        for k, (a, b, y0, y1) in enumerate(pieces):
            corners = [np.asarray(wall.start) + wall.direction * s + n * c
                       for s in (a, b) for c in across]
            xs, zs = zip(*corners)
            nodes.append(_box_node(f"floor{plan.index}/{room.label}/wall{wall.id}_{k}", "wall",
                                   (min(xs), floor_y + y0, min(zs)),
                                   (max(xs), floor_y + y1, max(zs))))
    return nodes


def make_nodes(plans: list[FloorPlan]) -> list[SceneNode]:
    nodes = []
    for plan in plans:
        x0, z0, x1, z1 = plan.footprint.bounds
        nodes.append(_box_node(f"floor{plan.index}/slab", "slab", (x0, plan.elevation, z0),
                               (x1, plan.floor_y, z1)))
        nodes += _wall_nodes(plan)
        for item in plan.furniture:
            fx0, fz0, fx1, fz1 = item.footprint().bounds
            y = plan.floor_y + item.elevation
            nodes.append(_box_node(
                f"floor{plan.index}/{plan.room(item.room).label}/furniture/{item.name}",
                "furniture", (fx0, y, fz0), (fx1, y + item.size[1], fz1),
                static=item.non_collision or item.is_detail, parts=True,
                item=item_info(item.name, model=item.model, room=item.room,
                               rotation=item.rotation, mass=20.0 + 10 * item.size[1])))
    return nodes


def make_scene() -> tuple[Scene, list[SceneNode]]:
    plans = [make_plan(i, TYPES[i], FURNITURE[i]) for i in (0, 1)]
    terminals = [Shape("Floor", ("Lot", f"Floor[{p.index}]"),
                       Mass(p.footprint, p.elevation, p.height).scope(),
                       Mass(p.footprint, p.elevation, p.height), {"floor": p.index}, p)
                 for p in plans]
    scene = Scene(name="house", seed=7, units=1.0, terminals=terminals,
                  timings={"derive": 0.12, "export": 0.05},
                  checks={"navigability": FixedReport(details={"unreachable": []})})
    return scene, make_nodes(plans)


@pytest.fixture(scope="session")
def small_scene() -> tuple[Scene, list[SceneNode]]:
    """The hand-built scene and its nodes (shared, treat as read-only)."""
    return make_scene()
