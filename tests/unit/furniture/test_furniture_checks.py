"""The independent furniture validator catches every kind of broken guarantee."""

from __future__ import annotations

import pytest

from furniture_checks import furniture_violations

from cga.model import FurnitureItem

# build_room(5, 4): free floor x 0.2..4.8, z 0.2..3.8; the door (wall 0, at 0.3, hinge at
# its start) swings into x 1.05..1.95, z 0.2..1.1; the window spans x 1.9..3.1 on z = 4.


def sofa(x=2.5, z=0.65, rotation=2, **changes):
    return FurnitureItem("sofa", "sofa", 0, (x, z), rotation, (2.0, 0.85, 0.9), **changes)


def child(name, x, z, rotation, size, parent="sofa"):
    return FurnitureItem(name, name.lower(), 0, (x, z), rotation, size, parent=parent)


@pytest.fixture
def check(room_plan, rules_dir):
    plan = room_plan(5.0, 4.0)

    def run(*items):
        return furniture_violations(plan.with_changes(furniture=items),
                                    rules_dir / "furniture_thesis.csv")
    return run


def test_a_valid_arrangement_passes(check):
    table = child("SofaTable", 3.3, 1.7, 0, (1.1, 0.45, 0.6))  # 0.3 m in front, facing it
    tv = child("tvboard", 3.3, 3.59, 0, (1.6, 1.29, 0.42))
    assert check(sofa(3.3), table, tv) == []


def test_overlaps_and_rugs(check):
    shelf = FurnitureItem("bookshelf", "bookshelf", 0, (3.0, 1.0), 0, (0.8, 1.9, 0.3))
    assert any("overlaps bookshelf" in p for p in check(sofa(3.3), shelf))
    rug = FurnitureItem("bookshelf1", "rug", 0, (3.0, 1.0), 0, (2.0, 0.01, 1.4),
                        non_collision=True)
    assert not any("overlaps" in p for p in check(sofa(3.3), rug))


def test_outside_the_room(check):
    assert any("not inside" in p for p in check(sofa(3.3, 0.5)))


def test_door_swing(check):
    problems = check(sofa(2.0, 1.0))
    assert any("in the swing of door 0" in p for p in problems)


def test_windows_only_for_items_that_can_close_them(check):
    shelf = FurnitureItem("bookshelf", "bookshelf", 0, (2.5, 3.65), 0, (0.8, 1.9, 0.3))
    assert any("covers window 0" in p for p in check(shelf))
    off = FurnitureItem("bookshelf", "bookshelf", 0, (4.0, 3.65), 0, (0.8, 1.9, 0.3))
    assert check(off) == []
    assert not any("window" in p for p in check(sofa(2.5, 3.35, 0)))


def test_clearances(check):
    near_wall = FurnitureItem("tableBig", "tablebig", 0, (2.5, 0.7), 0, (2.2, 0.76, 1.0))
    problems = check(near_wall)
    assert any("tableBig (room 0): clearance" in p and "into a wall" in p for p in problems)
    stool = FurnitureItem("FloorLamp", "floorlamp", 0, (3.3, 1.25), 0, (0.36, 1.7, 0.38))
    assert any("clearance front blocked by FloorLamp" in p for p in check(sofa(3.3), stool))


def test_pair_distances_and_orientation(check):
    far = child("SofaTable", 3.3, 2.5, 0, (1.1, 0.45, 0.6))
    assert any("above 0.4" in p for p in check(sofa(3.3), far))
    near = child("SofaTable", 3.3, 1.3, 0, (1.1, 0.45, 0.6))
    assert any("below 0.2" in p for p in check(sofa(3.3), near))
    turned = child("SofaTable", 3.3, 1.5, 2, (1.1, 0.45, 0.6))
    assert any("does not face sofa" in p for p in check(sofa(3.3), turned))
    aside = child("SofaTable", 4.5, 1.5, 0, (0.5, 0.45, 0.6))
    assert any("off to the side of sofa" in p for p in check(sofa(3.3), aside))
    orphan = child("SofaTable", 3.3, 1.5, 0, (1.1, 0.45, 0.6))
    assert any("parent sofa is not in the room" in p for p in check(orphan))


def test_children_around_must_look_at_the_parent(check):
    table = FurnitureItem("tableBig", "tablebig", 0, (2.5, 2.0), 0, (2.2, 0.76, 1.0))
    facing = child("chair", 2.5, 2.73, 0, (0.44, 0.9, 0.46), parent="tableBig")
    away = child("chair", 2.5, 2.73, 2, (0.44, 0.9, 0.46), parent="tableBig")
    assert check(table, facing) == []
    assert any("chair (room 0) does not face tableBig" in p for p in check(table, away))
