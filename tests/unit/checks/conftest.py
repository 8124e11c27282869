"""Hand-built scenes for the check tests: floors from rectangles, doors cut by hand, wall
solids and furniture as boxes. Independent of the meshing code the checks will meet in a
real build, so a bug there cannot hide a bug in the checks."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest
import trimesh
from shapely.geometry import Point

from cga.model import OUTSIDE, Door, FloorPlan, FloorSettings, Opening
from cga.operations.floorplan.rectangles import plan_from_rectangles
from cga.scene import Scene, SceneNode
from cga.shape import Mass, Shape
from items import item_info


def box_mesh(extents, centre) -> trimesh.Trimesh:
    mesh = trimesh.creation.box(extents=extents)
    mesh.apply_translation(centre)
    return mesh


def add_door(plan: FloorPlan, wall_id: int, *, width: float = 0.9, height: float = 2.1,
             at: float | None = None, front: bool = False) -> FloorPlan:
    """The plan with a door in wall ``wall_id`` (centred unless ``at`` is given)."""
    wall = plan.wall(wall_id)
    centre = wall.length / 2 if at is None else at
    door = Door(id=len(plan.doors), wall=wall_id, rooms=wall.rooms,
                position=wall.point_at(centre), width=width, height=height,
                swing_room=wall.rooms[0], is_front=front,
                reason="front" if front else "rule")
    opened = wall.with_opening(Opening("door", centre, width, height))
    walls = tuple(opened if w.id == wall_id else w for w in plan.walls)
    return plan.with_changes(walls=walls, doors=plan.doors + (door,))


def find_wall(plan: FloorPlan, rooms: tuple[int, int]) -> int:
    """Id of the (first) wall between two rooms, in either order (OUTSIDE allowed)."""
    for wall in plan.walls:
        if set(wall.rooms) == set(rooms):
            return wall.id
    raise KeyError(rooms)


def wall_nodes(plan: FloorPlan) -> list[SceneNode]:
    """Box solids for every wall: inner walls centred on their line, outer walls inside the
    footprint; full storey height except where openings are cut."""
    nodes = []
    y0 = plan.floor_y
    top = plan.elevation + plan.height
    for wall in plan.walls:
        d = wall.direction
        normal = np.array([-d[1], d[0]])
        t = wall.thickness
        mid = np.asarray(wall.point_at(wall.length / 2))
        if wall.outer:
            side = 1.0 if plan.footprint.covers(Point(*(mid + normal * 0.01))) else -1.0
            offset, a, b = side * t / 2, 0.0, wall.length
        else:
            offset, a, b = 0.0, -t / 2, wall.length + t / 2
        pieces = []  # (along from, along to, y from, y to)
        cuts = sorted((o.center - o.width / 2, o.center + o.width / 2, o) for o in wall.openings)
        cursor = a
        for lo, hi, opening in cuts:
            pieces.append((cursor, lo, y0, top))
            if opening.sill > 0:
                pieces.append((lo, hi, y0, y0 + opening.sill))
            pieces.append((lo, hi, y0 + opening.sill + opening.height, top))
            cursor = hi
        pieces.append((cursor, b, y0, top))
        rotation = np.eye(4)
        rotation[:3, 0] = (d[0], 0, d[1])
        rotation[:3, 2] = (-d[1], 0, d[0])
        meshes = []
        for lo, hi, ya, yb in pieces:
            if hi - lo <= 1e-9 or yb - ya <= 1e-9:
                continue
            piece = trimesh.creation.box(extents=(hi - lo, yb - ya, t))
            piece.apply_translation(((lo + hi) / 2, (ya + yb) / 2, 0))
            piece.apply_transform(rotation)
            start = np.asarray(wall.start) + normal * offset
            piece.apply_translation((start[0], 0, start[1]))
            meshes.append(piece)
        for k, mesh in enumerate(meshes):
            nodes.append(SceneNode(f"floor{plan.index}/wall{wall.id}_{k}", "wall", mesh))
    return nodes


def slab_node(plan: FloorPlan) -> SceneNode:
    minx, minz, maxx, maxz = plan.footprint.bounds
    t = plan.settings.slab_thickness
    mesh = box_mesh((maxx - minx, t, maxz - minz),
                    ((minx + maxx) / 2, plan.elevation + t / 2, (minz + maxz) / 2))
    return SceneNode(f"floor{plan.index}/slab", "slab", mesh)


def structure(plan: FloorPlan) -> list[SceneNode]:
    return [slab_node(plan), *wall_nodes(plan)]


def box_item(name: str, size, position, *, floor_y: float = 0.2, lift: float = 0.0,
             room: int = 0, floor: int = 0, static: bool = False,
             mass: float = 30.0) -> SceneNode:
    """A box-shaped furniture node of ``size`` (w, h, d) standing at plan ``position``."""
    w, h, d = size
    mesh = box_mesh((w, h, d), (position[0], floor_y + lift + h / 2, position[1]))
    return SceneNode(f"floor{floor}/room{room}/furniture/{name}", "furniture", mesh,
                     item=item_info(name, room=room, mass=mass),
                     static=static, parts=(mesh,))


def scene_of(*plans: FloorPlan) -> Scene:
    terminals = [Shape(symbol="Floor", path=("Lot", f"Floor[{p.index}]"), scope=None,
                       geometry=Mass(p.footprint, p.elevation, p.height), plan=p)
                 for p in plans]
    return Scene(name="test", seed=0, units=1.0, terminals=terminals)


@pytest.fixture
def kit() -> SimpleNamespace:
    """Scene-building helpers (see the module docstring)."""
    return SimpleNamespace(add_door=add_door, find_wall=find_wall, structure=structure,
                           box_item=box_item, box_mesh=box_mesh, scene_of=scene_of,
                           plan_from_rectangles=plan_from_rectangles, OUTSIDE=OUTSIDE,
                           FloorSettings=FloorSettings)


@pytest.fixture
def two_rooms() -> FloorPlan:
    """Rooms 0 (x 0–4) and 1 (x 4–8), 4 m deep; front door in room 0's wall at z = 0,
    an inner door between the rooms. No windows."""
    settings = FloorSettings(windows_per_wall=0)
    plan = plan_from_rectangles([(0, 0, 4, 4), (4, 0, 8, 4)], settings=settings)
    front_wall = next(w.id for w in plan.walls
                      if w.outer and 0 in w.rooms and w.start[1] == 0 and w.end[1] == 0)
    plan = add_door(plan, front_wall, front=True)
    return add_door(plan, find_wall(plan, (0, 1)))
