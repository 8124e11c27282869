"""Door sites, door placement, the front door, swings, reachability doors, the graph."""

import math
from dataclasses import replace

import numpy as np
import pytest
from typing_checks import validate_typed_plan

from cga.errors import NoSolutionError
from cga.model import OUTSIDE, FloorSettings, Opening, Wall
from cga.operations.floorplan.rectangles import plan_from_rectangles
from cga.operations.roomtyping.doors import door_spans, door_swing, free_intervals, front_door_site
from cga.operations.roomtyping.room_graph import door_sites
from cga.operations.roomtyping.rules import parse_rule_table
from cga.operations.type_rooms import type_plan

HEADER = "Type;Size;Prob;Neighbours;isOutsideConnected;appearance;additionRoom"
THREE = [(0, 0, 6, 10), (6, 0, 14, 5), (6, 5, 14, 10)]


def rules(*rows):
    return parse_rule_table("\n".join([HEADER, *rows]), file="t.csv")


def write(tmp_path, table_rows):
    path = tmp_path / "rules.csv"
    path.write_text("\n".join([HEADER, *table_rows]) + "\n")
    return path


def wall_between(plan, a, b):
    return next(w for w in plan.walls if set(w.rooms) == {a, b})


def test_door_spans_keep_clear_of_the_walls_at_each_end():
    plan = plan_from_rectangles(THREE)
    spans = door_spans(plan)
    t = plan.settings.wall_thickness
    inner = wall_between(plan, 0, 1)  # (6,0) on the footprint → (6,5) a T-junction inside
    assert inner.start == (6.0, 0.0)
    assert spans[inner.id] == pytest.approx((0.1 + t, 5 - 0.1 - t / 2))
    outer = next(w for w in plan.walls if w.outer)
    assert spans[outer.id] == pytest.approx((0.1 + t, outer.length - 0.1 - t))


def test_free_intervals_skip_openings_with_margins():
    plan = plan_from_rectangles(THREE)
    wall = next(w for w in plan.walls if w.outer and w.length == 8)
    (window,) = wall.openings
    (a, b), (c, d) = free_intervals(wall, (0.3, 7.7))
    assert (a, b, c, d) == pytest.approx((0.3, window.center - 0.7, window.center + 0.7, 7.7))


def test_short_shared_wall_is_no_door_site_so_rooms_are_not_neighbours():
    # rooms 0 and 3 share 1.0 m of wall (x = 5, z 4..5): too short for 0.9 m + margins
    plan = plan_from_rectangles([(0, 0, 5, 5), (5, 0, 10, 4), (0, 5, 5, 10), (5, 4, 10, 10)])
    assert any(set(w.rooms) == {0, 3} for w in plan.walls)
    sites = door_sites(plan, door_spans(plan), plan.settings.door_width)
    assert (0, 3) not in sites.inner
    assert {(0, 1), (0, 2), (1, 3), (2, 3)} <= set(sites.inner)


def test_doors_follow_listed_types_and_swing_into_the_bigger_room(tmp_path):
    table = ["Livingroom;50;1;Kitchen, Bedroom;1;1;0", "Kitchen;30;0;Livingroom;0;1;0",
             "Bedroom;30;0;Livingroom;0;1;0"]
    plan = plan_from_rectangles(THREE)
    typed = type_plan(plan, rules(*table), np.random.default_rng(0), door_position="center")
    validate_typed_plan(typed, write(tmp_path, table))
    assert typed.room(0).type == "Livingroom"
    inner = [d for d in typed.doors if not d.is_front]
    assert sorted(d.rooms for d in inner) == [(0, 1), (0, 2)]
    for door in inner:
        assert door.swing_room == 0 and door.reason == "rule"
        wall = typed.wall(door.wall)
        centre = math.dist(wall.start, door.position)
        lo, hi = door_spans(plan)[wall.id]
        assert centre == pytest.approx((lo + hi) / 2)
        assert door.hinge == ("start" if centre <= wall.length / 2 else "end")
        assert typed.room(0).interior.buffer(1e-6).covers(door_swing(door, typed))


def test_front_door_takes_the_longest_free_outer_stretch_and_opens_inwards():
    table = rules("Livingroom;50;1;Kitchen;1;1;0", "Kitchen;10;0;Livingroom;0;1;0")
    typed = type_plan(plan_from_rectangles(THREE), table, np.random.default_rng(3),
                      door_position="center")
    (front,) = [d for d in typed.doors if d.is_front]
    assert front.rooms == (0, OUTSIDE) and front.swing_room == 0 and front.reason == "front"
    wall = typed.wall(front.wall)
    assert wall.outer and 0 in wall.rooms
    # room 0's outer walls are 6, 10 and 6 m, one centred window each: the 10 m wall has
    # the longest stretch beside its window
    assert wall.length == 10
    assert len(typed.windows) == len(plan_from_rectangles(THREE).windows)
    assert typed.room(0).interior.buffer(1e-6).covers(door_swing(front, typed))


def test_front_door_replaces_a_window_when_no_gap_takes_it():
    settings = FloorSettings(window_width=2.0)
    plan = plan_from_rectangles([(0, 0, 3, 3), (3, 0, 6, 3)], settings=settings)
    table = rules("Livingroom;5;1;Kitchen;1;1;0", "Kitchen;5;0;Livingroom;0;1;0")
    typed = type_plan(plan, table, np.random.default_rng(0))
    front = typed.front_door()
    wall = typed.wall(front.wall)
    assert [o.kind for o in wall.openings] == ["door"]
    assert len(typed.windows) == len(plan.windows) - 1
    assert all(w.wall != wall.id for w in typed.windows)
    note = next(d for d in typed.diagnostics if "replaces 1 window" in d.message)
    assert note.level == "info"


def test_front_door_fits_a_stretch_exactly_its_width():
    """A 1.5 m hall end between 0.2 m walls leaves 0.9 m for a 0.9 m door, give or take
    the rounding of 0.1 + 0.2 (the hall of a 1.5 m centre-line corridor)."""
    wall = Wall(0, (0.0, 0.0), (1.5, 0.0), True, (0, OUTSIDE), 0.2)
    span = door_spans(plan_from_rectangles([(0, 0, 1.5, 6)]))[0]
    assert span[1] - span[0] < 0.9  # 0.8999999999999999
    chosen, centre, replaces = front_door_site([(wall, span)], 0.9, np.random.default_rng(0),
                                               "random")
    assert chosen is wall and not replaces and centre == pytest.approx(0.75)


def test_front_door_takes_one_windows_place_not_two():
    # 6 m walls with two windows each leave no gap for the door; between the windows it
    # would remove both, centred on one it removes one
    plan = plan_from_rectangles([(0, 0, 6, 3.5), (6, 0, 12, 3.5)],
                                settings=FloorSettings(windows_per_wall=2))
    table = rules("Livingroom;5;1;Kitchen;1;1;0", "Kitchen;5;0;Livingroom;0;1;0")
    for seed in range(5):
        typed = type_plan(plan, table, np.random.default_rng(seed))
        wall = typed.wall(typed.front_door().wall)
        assert wall.length == 6
        assert sorted(o.kind for o in wall.openings) == ["door", "window"]
        assert len(typed.windows) == len(plan.windows) - 1


def test_fewest_extra_doors_make_every_room_reachable(tmp_path):
    # nobody lists anybody useful: only the front door comes from the rules
    table = ["Hall;1;1;Hall;1;1;0", "Cell;1;0;Nothing;0;9;1", "Nothing;1;0;Hall;0;0;1"]
    rects = [(0, 0, 4, 4), (4, 0, 8, 4), (8, 0, 12, 4), (0, 4, 4, 8), (4, 4, 8, 8), (8, 4, 12, 8)]
    typed = type_plan(plan_from_rectangles(rects), rules(*table), np.random.default_rng(0))
    validate_typed_plan(typed, write(tmp_path, table))
    extra = [d for d in typed.doors if d.reason == "reachability"]
    assert len(extra) == len(rects) - 1  # a spanning tree: the fewest possible
    notes = [d for d in typed.diagnostics if "so every room can be reached" in d.message]
    assert len(notes) == len(extra) and all(n.level == "warning" for n in notes)
    entry = typed.front_door().swing_room
    # hubs first: every extra door that can touch the entry room does
    assert sum(entry in d.rooms for d in extra) == len(
        door_sites(typed, door_spans(typed), 0.9).adjacency(range(6))[entry])


def test_strict_refuses_to_add_doors_and_says_which_rooms_are_cut_off():
    table = rules("Livingroom;1;1;Kitchen;1;1;0", "Kitchen;1;0;Livingroom;0;1;0",
                  "Storageroom;1;0;Kitchen;0;1;1")
    # Storageroom can only be placed next to the kitchen and gets its door from its rule;
    # the bedroom-less third room becomes a Commonroom, which no rule lists
    plan = plan_from_rectangles([(0, 0, 5, 5), (5, 0, 10, 5), (10, 0, 15, 5), (15, 0, 20, 5)])
    with pytest.raises(NoSolutionError) as info:
        for seed in range(20):
            type_plan(plan, table, np.random.default_rng(seed), strict=True)
    assert "strict" in str(info.value)
    assert any("Commonroom" in r and "lists nothing (no rule)" in r for r in info.value.reasons)


def test_upper_floor_has_no_front_door_and_enters_by_the_outside_rule_room(tmp_path):
    table = ["Livingroom;1;1;Kitchen, Bedroom;1;1;0", "Kitchen;1;0;Livingroom;0;1;0",
             "Bedroom;1;0;Livingroom;0;1;0"]
    plan = plan_from_rectangles(THREE, index=1)
    typed = type_plan(plan, rules(*table), np.random.default_rng(0))
    validate_typed_plan(typed, write(tmp_path, table), front_door=False)
    entry = typed.entry
    assert typed.room(entry).type == "Livingroom"
    assert not typed.room_graph.edges(OUTSIDE)
    assert any("upper floor" in d.message for d in typed.diagnostics)


def test_ground_floor_without_outside_rule_warns_and_enters_by_the_largest_room():
    table = rules("Office;1;1;Office;0;3;0")
    typed = type_plan(plan_from_rectangles(THREE), table, np.random.default_rng(0))
    assert typed.front_door() is None
    assert typed.entry == 0  # 60 m², the largest
    warning = next(d for d in typed.diagnostics if "no front door" in d.message)
    assert warning.level == "warning" and "isOutsideConnected" in warning.message


def test_room_graph_nodes_types_and_edges():
    table = rules("Livingroom;1;1;Kitchen, Bedroom;1;1;0", "Kitchen;1;0;Livingroom;0;1;0",
                  "Bedroom;1;0;Livingroom;0;1;0")
    typed = type_plan(plan_from_rectangles(THREE), table, np.random.default_rng(0))
    graph = typed.room_graph
    assert graph.nodes[OUTSIDE]["type"] == "outside"
    assert {graph.nodes[r.id]["type"] for r in typed.rooms} == {"Livingroom", "Kitchen", "Bedroom"}
    for a, b, data in graph.edges(data=True):
        door = typed.doors[data["door"]]
        assert set(door.rooms) == {a, b} and data["wall"] == door.wall
        assert data["reason"] == door.reason


def test_existing_openings_on_inner_walls_are_respected():
    plan = plan_from_rectangles(THREE)
    wall = wall_between(plan, 0, 1)
    blocked = wall.with_opening(Opening("door", center=2.55, width=4.5, height=2.1))
    plan = plan.with_changes(walls=tuple(blocked if w.id == wall.id else w for w in plan.walls))
    sites = door_sites(plan, door_spans(plan), 0.9)
    assert (0, 1) not in sites.inner


def test_leaf_swings_into_the_smaller_room_when_the_bigger_is_too_narrow():
    # a 30 m² corridor only 0.7 m deep inside its walls, and a 24 m² room
    plan = plan_from_rectangles([(0, 0, 30, 1.0), (0, 1.0, 6, 5)])
    table = rules("Corridor;1;1;Room;1;1;0", "Room;1;0;Corridor;0;1;0")
    typed = type_plan(plan, table, np.random.default_rng(0))
    (door,) = [d for d in typed.doors if not d.is_front]
    assert typed.room(0).area > typed.room(1).area
    assert door.swing_room == 1
    assert typed.room(1).interior.buffer(1e-6).covers(door_swing(door, typed))


def test_doors_swing_out_of_the_hall_into_the_rooms_it_serves():
    # a 22 m² hall, bigger than every room it serves
    from cga.authoring import floor_from_rectangles, type_floor

    plan = floor_from_rectangles([(0, 4, 14, 5.6), (0, 0, 5, 4), (5, 0, 8.2, 4),
                                  (8.2, 0, 10.4, 4), (10.4, 0, 14, 4), (0, 5.6, 4, 10),
                                  (4, 5.6, 8, 10), (8, 5.6, 11, 10), (11, 5.6, 14, 10)],
                                 circulation=[0])
    for seed in range(10):
        typed = type_floor(plan, "house_types.csv", seed=seed)
        hall = typed.room(0)
        assert hall.circulation and hall.area > max(r.area for r in typed.rooms[1:])
        inner = [d for d in typed.doors if not d.is_front and hall.id in d.rooms]
        assert len(inner) >= 4
        for door in inner:
            (room,) = set(door.rooms) - {hall.id}
            assert door.swing_room == room
            assert typed.room(room).interior.buffer(1e-6).covers(door_swing(door, typed))


MAX_SIZE_TABLE = [
    "Type;Size;Prob;Neighbours;isOutsideConnected;appearance;additionRoom;maxSize;enteredFrom;"
    "passThrough;needsWindow;circulation",
    "Hall;3;1;Bathroom, Room;true;1;0;;;true;false;true",
    "Bathroom;2;0;Hall;false;1;0;9;Hall;false;false;false",
    "Room;5;0.5;Hall;false;2;1;;Hall;true;false;false",
]
# a hall with a 10 m² room, the smallest, for a bathroom of at most 9 m²
HALL_AND_BIG_ROOMS = [(0, 4, 10, 5.5), (0, 0, 2.5, 4), (2.5, 0, 10, 4), (0, 5.5, 10, 9.5)]


def test_sizes_are_raised_with_a_warning_rather_than_fail_the_floor(tmp_path):
    from cga.authoring import floor_from_rectangles, type_floor
    from cga.quality import floor_quality

    path = tmp_path / "types.csv"
    path.write_text("\n".join(MAX_SIZE_TABLE) + "\n")
    plan = floor_from_rectangles(HALL_AND_BIG_ROOMS, circulation=[0])
    typed = type_floor(plan, path, seed=0)
    (bathroom,) = [r for r in typed.rooms if r.type == "Bathroom"]
    assert bathroom.area == pytest.approx(10.0) and bathroom.area_range == (2.0, 9.0)
    (warning,) = [d for d in typed.diagnostics if "over its maxSize" in d.message]
    assert warning.level == "warning" and warning.room == bathroom.id
    assert "raised by 1.25x" in warning.message
    assert floor_quality(typed)["area_out_of_range"] == [
        {"room": bathroom.id, "type": "Bathroom", "area": 10.0, "range": [2.0, 9.0]}]
    with pytest.raises(NoSolutionError):
        type_floor(plan, path, seed=0, strict=True)


def test_sizes_are_raised_no_further_than_half_again(tmp_path):
    from cga.authoring import floor_from_rectangles, type_floor

    path = tmp_path / "types.csv"
    path.write_text("\n".join(MAX_SIZE_TABLE).replace(";0;9;Hall;", ";0;6;Hall;") + "\n")
    plan = floor_from_rectangles(HALL_AND_BIG_ROOMS, circulation=[0])
    with pytest.raises(NoSolutionError) as failed:
        type_floor(plan, path, seed=0)
    assert "nor with every maxSize raised by 1.5x" in str(failed.value)


# A row of rooms: living room (front door), bathroom, laundry: the thesis' table joins
# the laundry to the bathroom alone; the hall-like strip below touches all three.
ROW_AND_STRIP = [(0, 3, 6, 8), (6, 3, 10, 8), (10, 3, 14, 8), (0, 0, 14, 3)]
LAUNDRY_BEHIND_BATHROOM = ["Livingroom;1;1;Bathroom, Livingroom, Kitchen;1;1;0",
                           "Bathroom;1;0;Livingroom;0;1;0",
                           "Laundryroom;1;0;Bathroom;0;1;0",
                           "Kitchen;1;0;Livingroom;0;1;0"]


def test_no_bedroom_or_bathroom_is_the_only_way_into_a_room(tmp_path):
    path = write(tmp_path, LAUNDRY_BEHIND_BATHROOM)
    plan = plan_from_rectangles(ROW_AND_STRIP)
    for seed in range(12):
        typed = type_plan(plan, rules(*LAUNDRY_BEHIND_BATHROOM), np.random.default_rng(seed))
        validate_typed_plan(typed, path)  # checks the property independently
        laundry = next(r.id for r in typed.rooms if r.type == "Laundryroom")
        bathroom = next(r.id for r in typed.rooms if r.type == "Bathroom")
        ways_in = {sum(d.rooms) - laundry for d in typed.doors if laundry in d.rooms}
        assert bathroom in ways_in  # the rule's door stays
        assert ways_in - {bathroom}, "the laundry is entered only through the bathroom"
        assert any("only through a bedroom or bathroom" in d.message
                   for d in typed.diagnostics if d.room in ways_in | {laundry})


def test_types_named_like_bedrooms_and_bathrooms_are_private_unless_the_table_says():
    table = parse_rule_table("\n".join([
        HEADER + ";passThrough",
        "Livingroom;1;1;Bedroom;1;1;0;", "Bedroom;1;0;Livingroom;0;1;0;",
        "MasterBedroom;1;0;Livingroom;0;1;1;", "GuestWC;1;0;Livingroom;0;1;1;",
        "Bathroom;1;0;Livingroom;0;1;1;true"]), file="t.csv")
    private = {rule.type for rule in table.rules if not rule.pass_through}
    assert private == {"Bedroom", "MasterBedroom", "GuestWC"}


def test_a_room_only_a_bathroom_adjoins_is_kept_with_a_warning(tmp_path):
    # three rooms in a row: where the laundry ends up at the end beside the bathroom,
    # no layout of this floor gives it another way in
    rows = ["Livingroom;1;1;Bathroom, Livingroom;1;1;0", "Bathroom;1;0;Livingroom;0;1;0",
            "Laundryroom;1;0;Bathroom;0;1;0"]
    plan = plan_from_rectangles([(0, 0, 8, 5), (8, 0, 11, 5), (11, 0, 14, 5)])
    warned = 0
    for seed in range(10):
        typed = type_plan(plan, rules(*rows), np.random.default_rng(seed))
        validate_typed_plan(typed, write(tmp_path, rows))  # exempts only the warned case
        laundry = next(r for r in typed.rooms if r.type == "Laundryroom")
        ways_in = {typed.room(sum(d.rooms) - laundry.id).type
                   for d in typed.doors if laundry.id in d.rooms}
        warning = [d for d in typed.diagnostics if d.level == "warning"
                   and d.room == laundry.id and "reached only through" in d.message]
        assert bool(warning) == (ways_in == {"Bathroom"}), (seed, ways_in)
        warned += bool(warning)
    assert warned


def test_a_door_is_hung_clear_of_the_sweep_of_a_door_already_hung():
    from cga.operations.roomtyping.doors import door_swing_on, make_door, place_door

    plan = plan_from_rectangles([(0, 0, 6, 5), (6, 0, 10, 5)])
    wall = wall_between(plan, 0, 1)  # x = 6, from z = 0 to 5
    natural = make_door(0, wall, 1.0, (0, 1), plan, reason="rule")
    in_the_way = door_swing_on(natural, wall)
    # nothing in the way: hung as make_door hangs it
    assert place_door(1, [(wall, 1.0)], (0, 1), plan, reason="rule")[0] == replace(natural, id=1)
    door, sweep = place_door(1, [(wall, 1.0), (wall, 4.0)], (0, 1), plan, reason="rule",
                      avoid=[in_the_way])
    assert sweep.equals(door_swing_on(door, wall))
    assert sweep.intersection(in_the_way).area < 1e-3
    assert (door.hinge, door.swing_room) != (natural.hinge, natural.swing_room)
    assert math.dist(door.position, wall.point_at(1.0)) < 1e-9  # hung otherwise, not moved
    # every way of hanging it at 1.0 m meets a sweep on both sides: it moves along the wall
    both = [in_the_way, sweep,
            *(door_swing_on(replace(natural, hinge=h, swing_room=r), wall)
              for h in ("start", "end") for r in (0, 1))]
    moved, _ = place_door(1, [(wall, 1.0), (wall, 4.0)], (0, 1), plan, reason="rule", avoid=both)
    assert math.dist(moved.position, wall.point_at(4.0)) < 1e-9
