"""The furnished house demo built with its checks, summarised for
``tests/e2e/test_checks_house.py``, and the independent reach checker it compares the
navigability check with (exact shapely geometry instead of the check's grid).

Kept outside the test module so that worker processes started afresh (``spawn``) can
import :func:`run_seed`: a worker forked from a test process that has run Ray can crash
in Ray's library.
"""

from __future__ import annotations

from pathlib import Path

import shapely
from shapely.geometry import Point, Polygon

from cga.model import OUTSIDE, FloorPlan
from cga.pipeline import build

__all__ = ["RADIUS", "run_seed"]

HOUSE = Path(__file__).resolve().parents[2] / "demos" / "house.grammar"
RADIUS = 0.25
CAUTION = 0.1
"""m added to the robot radius by the independent checker: more than the check's grid can
err (half a cell of clearance, one cell of outline), so what the cautious robot reaches
the check must reach."""
BAND = (0.05, 1.2)


def _cautious_reach(plan: FloorPlan, radius: float) -> set[int]:
    """Rooms a disc of ``radius`` reaches, from exact plan geometry: free floor = room
    interiors and door openings (plus an apron outside the front door), minus the plan
    rectangles of the solid items reaching into the band, shrunk by the radius."""
    pieces = [room.interior for room in plan.rooms]
    start = None
    for door in plan.doors:
        wall = plan.wall(door.wall)
        (dx, dz), (cx, cz) = wall.direction, door.position
        half, depth = door.width / 2, wall.thickness + 0.01
        far = depth
        if OUTSIDE in door.rooms:
            outward = 1.0 if not plan.footprint.covers(Point(cx - dz * 0.01, cz + dx * 0.01)) else -1.0
            far = depth + 2.0
            if door.is_front:
                start = Point(cx - dz * outward * 1.5, cz + dx * outward * 1.5)
        else:
            outward = 1.0
        near_b, far_b = (-depth, far) if outward > 0 else (-far, depth)
        corners = [(-half, near_b), (half, near_b), (half, far_b), (-half, far_b)]
        pieces.append(Polygon([(cx + a * dx - b * dz, cz + a * dz + b * dx) for a, b in corners]))
    solid = [item.footprint() for item in plan.furniture
             if not (item.is_detail or item.non_collision)
             and item.elevation < BAND[1] and item.elevation + item.size[1] > BAND[0]]
    free = shapely.union_all(pieces)
    if solid:
        free = free.difference(shapely.union_all(solid))
    space = free.buffer(-radius)
    parts = list(getattr(space, "geoms", [space]))
    if start is None:
        largest = max(plan.rooms, key=lambda r: (r.area, -r.id))
        candidates = [p for p in parts if p.intersects(largest.interior)]
        if not candidates:
            return set()
        component = max(candidates, key=lambda p: p.intersection(largest.interior).area)
    else:
        component = next((p for p in parts if p.distance(start) < 1e-9), None)
        if component is None:
            return set()
    return {room.id for room in plan.rooms if component.intersects(room.interior)}


def run_seed(seed: int) -> dict:
    """Build one seed with its checks; summarise what the test asserts."""
    scene = build(HOUSE, seed=seed, formats=(), quiet=True)
    physics = scene.checks["physics"].to_dict()
    reach = scene.checks["navigability"].to_dict()
    floors = []
    for plan, floor in zip(scene.floors, reach["floors"]):
        floors.append({
            "floor": plan.index,
            "rooms": sorted(room.id for room in plan.rooms),
            "doors": {door.id: list(door.rooms) for door in plan.doors},
            "reachable": floor["reachable_rooms"],
            "unreachable": [r for r in floor["rooms"] if not r["reachable"]],
            "cautious": sorted(_cautious_reach(plan, RADIUS + CAUTION)),
        })
    return {
        "seed": seed,
        "items": physics["item_count"],
        "furniture": {f"floor{plan.index}/{plan.room(i.room).label}/furniture/{i.name}"
                      for plan in scene.floors for i in plan.furniture},
        "bad_items": [(i["path"], i["penetration_m"], i["displacement_m"])
                      for i in physics["items"]
                      if i["penetration_m"] > 0.005 or i["displacement_m"] > 0.01],
        "physics_problems": [(i["path"], i["problems"]) for i in physics["items"]
                             if not i["passed"]],
        "floors": floors,
        "passed": reach["passed"],
    }
