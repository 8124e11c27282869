"""Navigability: rooms reachable through doors, unreachable ones reported with the reason."""

from __future__ import annotations

import json

import pytest
from shapely.geometry import Point

from cga.checks import check_navigability
from cga.scene import SceneNode

FRONT, INNER = 0, 1  # door ids of the two_rooms fixture


def _rooms(report, floor=0):
    return {r.room: r for r in report.floors[floor].rooms}


def test_clear_floor_is_reachable(kit, two_rooms):
    report = check_navigability(kit.scene_of(two_rooms), kit.structure(two_rooms))
    floor = report.floors[0]
    assert report.passed and floor.passed
    assert floor.start == "front_door" and floor.start_door == FRONT and floor.start_room == 0
    assert all(r.reachable and r.reachable_fraction == 1.0 for r in floor.rooms)
    # The start point is outside the building, in front of the front door.
    assert not two_rooms.footprint.contains(Point(floor.start_point))


def test_narrowest_passage_is_the_narrower_door(kit):
    settings = kit.FloorSettings(windows_per_wall=0)
    plan = kit.plan_from_rectangles([(0, 0, 4, 4), (4, 0, 8, 4)], settings=settings)
    plan = kit.add_door(plan, kit.find_wall(plan, (0, kit.OUTSIDE)), width=1.0, front=True)
    plan = kit.add_door(plan, kit.find_wall(plan, (0, 1)), width=0.7)
    rooms = _rooms(check_navigability(kit.scene_of(plan), kit.structure(plan)))
    assert rooms[0].narrowest.door == 0
    assert 0.4 <= rooms[0].narrowest.clearance <= 0.5
    assert rooms[1].narrowest.door == 1
    assert 0.27 <= rooms[1].narrowest.clearance <= 0.35
    assert rooms[1].narrowest.width == pytest.approx(2 * rooms[1].narrowest.clearance)


def test_wardrobe_in_the_doorway_makes_the_room_unreachable(kit, two_rooms):
    # The inner door is centred at (4, 2); the wardrobe stands against it in room 1.
    wardrobe = kit.box_item("wardrobe", (0.6, 2.0, 1.2), (4.4, 2.0), room=1)
    report = check_navigability(kit.scene_of(two_rooms), kit.structure(two_rooms) + [wardrobe])
    rooms = _rooms(report)
    assert not report.passed
    assert rooms[0].reachable
    assert not rooms[1].reachable
    assert rooms[1].blocked_doors == (INNER,)
    assert rooms[1].blocking_items == (wardrobe.path,)
    assert any(f"door {INNER}" in r and "blocked" in r and wardrobe.path in r
               for r in rooms[1].reasons)
    assert report.floors[0].unreachable == [rooms[1]]


def test_wardrobe_away_from_the_door_leaves_it_reachable(kit, two_rooms):
    wardrobe = kit.box_item("wardrobe", (0.6, 2.0, 1.2), (7.5, 2.0), room=1)
    report = check_navigability(kit.scene_of(two_rooms), kit.structure(two_rooms) + [wardrobe])
    rooms = _rooms(report)
    assert report.passed
    assert rooms[1].reachable and rooms[1].reachable_fraction == 1.0


def test_blocked_front_door_cuts_off_the_floor(kit, two_rooms):
    chest = kit.box_item("chest", (1.2, 0.9, 0.5), (2.0, 0.45), room=0)
    rooms = _rooms(check_navigability(kit.scene_of(two_rooms),
                                      kit.structure(two_rooms) + [chest]))
    assert not rooms[0].reachable and not rooms[1].reachable
    assert rooms[0].blocked_doors == (FRONT,)
    assert any("outside" in r and "blocked" in r for r in rooms[0].reasons)
    assert any(f"door {INNER}" in r and "unreachable itself" in r for r in rooms[1].reasons)


def test_room_full_of_furniture(kit, two_rooms):
    blob = kit.box_item("blob", (3.7, 1.0, 3.5), (6.0, 2.0), room=1)
    rooms = _rooms(check_navigability(kit.scene_of(two_rooms),
                                      kit.structure(two_rooms) + [blob]))
    assert not rooms[1].reachable
    assert any(r.startswith("fully blocked by furniture") for r in rooms[1].reasons)
    assert blob.path in rooms[1].blocking_items


def test_furniture_cutting_a_room_in_two(kit, two_rooms):
    # A shelf wall across room 0 separates the front door from the inner door.
    shelf = kit.box_item("shelf", (0.4, 2.0, 3.6), (3.0, 2.0), room=0)
    rooms = _rooms(check_navigability(kit.scene_of(two_rooms),
                                      kit.structure(two_rooms) + [shelf]))
    assert rooms[0].reachable and rooms[0].reachable_fraction < 0.95
    assert not rooms[1].reachable
    assert rooms[1].blocked_doors == ()
    assert any("cuts its approach off" in r and shelf.path in r for r in rooms[1].reasons)


def test_room_without_a_door(kit):
    settings = kit.FloorSettings(windows_per_wall=0)
    plan = kit.plan_from_rectangles([(0, 0, 4, 4), (4, 0, 8, 4)], settings=settings)
    plan = kit.add_door(plan, kit.find_wall(plan, (0, kit.OUTSIDE)), front=True)
    rooms = _rooms(check_navigability(kit.scene_of(plan), kit.structure(plan)))
    assert rooms[0].reachable
    assert not rooms[1].reachable and rooms[1].reasons == ("has no door",)


@pytest.mark.parametrize("width, radius, ok", [(0.45, 0.25, False), (0.9, 0.25, True),
                                               (0.9, 0.5, False)])
def test_door_width_against_robot_radius(kit, width, radius, ok):
    settings = kit.FloorSettings(windows_per_wall=0)
    plan = kit.plan_from_rectangles([(0, 0, 4, 4), (4, 0, 8, 4)], settings=settings)
    plan = kit.add_door(plan, kit.find_wall(plan, (0, kit.OUTSIDE)), width=1.6, front=True)
    plan = kit.add_door(plan, kit.find_wall(plan, (0, 1)), width=width)
    report = check_navigability(kit.scene_of(plan), kit.structure(plan), radius=radius)
    room = _rooms(report)[1]
    assert room.reachable is ok
    if not ok:
        assert any("door 1" in r and "too narrow" in r for r in room.reasons)


def test_floor_without_front_door_starts_in_its_largest_room(kit):
    settings = kit.FloorSettings(windows_per_wall=0)
    plan = kit.plan_from_rectangles([(0, 0, 3, 4), (3, 0, 8, 4)], settings=settings,
                                    index=1, elevation=3.0)
    plan = kit.add_door(plan, kit.find_wall(plan, (0, 1)))
    report = check_navigability(kit.scene_of(plan), kit.structure(plan))
    floor = report.floors[0]
    assert floor.start == "largest_room" and floor.start_room == 1
    assert "stair" in floor.note and "largest room" in floor.note
    assert floor.passed
    rooms = _rooms(report)
    assert rooms[1].narrowest is None
    assert rooms[0].narrowest.door == 0


def test_upper_floor_starts_in_the_entry_room_typing_chose(kit):
    settings = kit.FloorSettings(windows_per_wall=0)
    plan = kit.plan_from_rectangles([(0, 0, 3, 4), (3, 0, 8, 4)], settings=settings,
                                    index=1, elevation=3.0)
    plan = kit.add_door(plan, kit.find_wall(plan, (0, 1)))
    plan = plan.with_changes(entry=0)
    floor = check_navigability(kit.scene_of(plan), kit.structure(plan)).floors[0]
    assert floor.start == "entry_room" and floor.start_room == 0
    assert "entry room" in floor.note
    assert floor.passed


def test_rugs_and_door_leaves_do_not_block(kit, two_rooms):
    rug = kit.box_item("rug", (2.0, 0.02, 3.0), (4.0, 2.0), room=0, static=True)
    leaf = kit.box_item("door", (0.05, 2.0, 0.9), (4.0, 2.0), room=0, static=True)
    report = check_navigability(kit.scene_of(two_rooms), kit.structure(two_rooms) + [rug, leaf])
    assert report.passed


def test_report_dict_and_summary(kit, two_rooms):
    wardrobe = kit.box_item("wardrobe", (0.6, 2.0, 1.2), (4.4, 2.0), room=1)
    report = check_navigability(kit.scene_of(two_rooms), kit.structure(two_rooms) + [wardrobe])
    data = json.loads(json.dumps(report.to_dict()))
    floor = data["floors"][0]
    assert data["passed"] is False and data["radius_m"] == 0.25
    assert floor["reachable_rooms"] == [0] and floor["unreachable_rooms"] == [1]
    assert floor["rooms"][1]["blocked_doors"] == [INNER]
    assert "1/2 rooms reachable" in report.summary()
    assert "room 1" in report.summary() and wardrobe.path in report.summary()


def test_invalid_radius(kit, two_rooms):
    with pytest.raises(ValueError, match="radius"):
        check_navigability(kit.scene_of(two_rooms), [], radius=0)


def test_a_facade_across_the_front_door_is_named_not_called_narrow(kit, two_rooms):
    """A wide door shut by built geometry (a facade face left uncut) used to read
    "door 0 … is too narrow for the robot (0.90 m wide, needs more than 0.50 m)"."""
    pane = kit.box_mesh((4.0, 2.8, 0.002), (2.0, 0.2 + 1.4, -0.001))
    nodes = kit.structure(two_rooms) + [SceneNode("Lot/Storey/Facade[0]/Pane", "face", pane)]
    room = _rooms(check_navigability(kit.scene_of(two_rooms), nodes))[0]
    assert not room.reachable
    [reason] = [r for r in room.reasons if f"door {FRONT}" in r]
    assert "too narrow" not in reason
    assert "0.90 m wide" in reason and "Lot/Storey/Facade[0]/Pane" in reason


def test_room_narrower_than_the_robot_even_when_empty(kit):
    """A 0.45 m deep closet (0.25 m of floor between its walls) admits no robot of radius
    0.25 m: the reason gives its largest clearance, about half its free depth."""
    settings = kit.FloorSettings(windows_per_wall=0)
    plan = kit.plan_from_rectangles([(0, 0, 4, 4), (4, 0, 4.45, 4)], settings=settings)
    plan = kit.add_door(plan, kit.find_wall(plan, (0, kit.OUTSIDE)), front=True)
    plan = kit.add_door(plan, kit.find_wall(plan, (0, 1)))
    room = _rooms(check_navigability(kit.scene_of(plan), kit.structure(plan)))[1]
    assert not room.reachable
    reason = next(r for r in room.reasons if "even when empty" in r)
    clearance = float(reason.split("largest clearance ")[1].split(" m")[0])
    assert clearance == pytest.approx(0.125, abs=0.05)
