"""End to end: the furnished house demo over many seeds, through its physics and
navigability checks.

Each seed is built exactly as ``cga build`` does (checks included, no files written), on
two worker processes. Physics must be clean on every seed: no item overlapping anything
by more than 5 mm, none moving more than 1 cm. Navigability may fail (furniture can wall
a room off), but then the report must say which rooms and why, and the share of seeds
with every room reachable is printed. An independent checker (exact shapely geometry
instead of the check's grid) confirms the rooms reported reachable: every room that a
robot more cautious than the check's reaches, the check must report reachable too.

The check's settle stops once every item has rested for 0.1 s (see
``cga.checks.physics``), so the short settle needs no special setting here. The seed
count can be changed with ``CGA_CHECK_SEEDS`` (default 200).
"""

from __future__ import annotations

import multiprocessing
import os
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import pytest
import shapely
from shapely.geometry import Point, Polygon

from cga.pipeline import build
from cga.model import OUTSIDE, FloorPlan

pytestmark = [pytest.mark.slow, pytest.mark.physics]

HOUSE = Path(__file__).resolve().parents[2] / "demos" / "house.grammar"
SEEDS = int(os.environ.get("CGA_CHECK_SEEDS", "200"))
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


def _run(seed: int) -> dict:
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


@pytest.fixture(scope="module")
def results() -> list[dict]:
    context = multiprocessing.get_context("fork")
    with ProcessPoolExecutor(max_workers=2, mp_context=context) as pool:
        return list(pool.map(_run, range(SEEDS), chunksize=4))


def test_house_is_furnished(results):
    assert all(r["items"] >= 20 for r in results), [r["items"] for r in results]


def test_no_item_overlaps_or_moves(results):
    bad = [(r["seed"], item) for r in results for item in r["bad_items"]]
    problems = sum(len(r["physics_problems"]) for r in results)
    print(f"\nphysics: {len(results)} seeds, {sum(r['items'] for r in results)} items, "
          f"{len(bad)} overlapping > 5 mm or moving > 1 cm, {problems} with any problem")
    assert not bad, bad[:10]


def test_unreachable_rooms_are_named_with_reasons(results):
    complete = sum(r["passed"] for r in results)
    print(f"\nnavigability (radius {RADIUS} m): every room reachable in {complete}/{len(results)} "
          f"seeds ({100 * complete / len(results):.1f} %)")
    for r in results:
        for floor in r["floors"]:
            unreachable = [room["room"] for room in floor["unreachable"]]
            assert sorted(floor["reachable"] + unreachable) == floor["rooms"], (r["seed"], floor)
            for room in floor["unreachable"]:
                assert room["reasons"], (r["seed"], floor["floor"], room)
                for door in room["blocked_doors"]:
                    assert room["room"] in floor["doors"][door], (r["seed"], room)
                assert set(room["blocking_items"]) <= r["furniture"], (r["seed"], room)
            if unreachable:
                print(f"  seed {r['seed']} floor {floor['floor']}: " + "; ".join(
                    f"room {room['room']} ({room['type']}): {' / '.join(room['reasons'])}"
                    for room in floor["unreachable"]))


def test_rooms_a_cautious_robot_reaches_are_reported_reachable(results):
    missed = [(r["seed"], f["floor"], sorted(set(f["cautious"]) - set(f["reachable"])))
              for r in results for f in r["floors"] if set(f["cautious"]) - set(f["reachable"])]
    assert not missed, missed[:10]
