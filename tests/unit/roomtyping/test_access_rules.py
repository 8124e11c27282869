"""Access columns of typing tables (DESIGN §11): parsing, errors, and the doors they cut."""

from __future__ import annotations

import pytest

from cga.authoring import doors_between, floor_from_rectangles, rooms_of_type, type_floor
from cga.errors import NoSolutionError, RuleTableError
from cga.operations.roomtyping.rules import parse_rule_table

HEADER = ("Type;Size;Prob;Neighbours;isOutsideConnected;appearance;additionRoom;"
          "maxSize;enteredFrom;passThrough;needsWindow;circulation")
EN_SUITE = "\n".join([
    HEADER,
    "Hall;2;1;Bedroom, Bathroom;true;1;0;;;true;false;true",
    "Bedroom;9;0.5;Hall;0;2;0;18;Hall;false;true;false",
    "Bathroom;3;0.2;Bedroom;0;1;0;9;Bedroom;false;false;false",
])
# a hall along the bottom; two bedrooms above it; a bathroom behind the left bedroom
FLOOR = [(0, 0, 10, 1.6), (0, 1.6, 5, 5), (5, 1.6, 10, 5), (0, 5, 3, 8)]


def table(text):
    return parse_rule_table(text + "\n", file="access.csv")


def write(tmp_path, text):
    path = tmp_path / "access.csv"
    path.write_text(text + "\n")
    return path


def test_access_columns_parse_and_default():
    rules = table(EN_SUITE)
    assert rules.has_access and rules.circulation_rule.type == "Hall"
    bedroom = rules.rule_for("Bedroom")
    assert (bedroom.max_size, bedroom.entered_from, bedroom.pass_through,
            bedroom.needs_window, bedroom.circulation) == (18, ("Hall",), False, True, False)
    assert rules.rule_for("Hall").entered_from == ()  # front door room: from anywhere
    assert bedroom.may_be_entered_from("Hall") and not bedroom.may_be_entered_from("Bathroom")


def test_thesis_tables_without_access_columns_keep_the_thesis_meaning():
    rules = table("Type;Size;Prob;Neighbours;isOutsideConnected;appearance;additionRoom\n"
                  "Kitchen;0.25;0.5;Livingroom;0;1;0\nLivingroom;1;1;Kitchen;true;1;0")
    kitchen = rules.rule_for("Kitchen")
    assert not rules.has_access and kitchen.entered_from is None and kitchen.pass_through
    assert kitchen.may_be_entered_from("Livingroom") and not kitchen.may_be_entered_from("Hall")


def test_trailing_empty_access_cells_may_be_left_out():
    rules = table(HEADER + "\nHall;2;1;Bedroom;true;1;0\nBedroom;9;1;Hall;0;1;0;;Hall")
    assert rules.rule_for("Bedroom").entered_from == ("Hall",)
    assert rules.rule_for("Hall").circulation is False


@pytest.mark.parametrize("row, column, message", [
    ("Bedroom;9;1;Hall;0;1;0;5;Hall;false;true;false", "maxSize", "below Size"),
    ("Bedroom;9;1;Hall;0;1;0;x;Hall;false;true;false", "maxSize", "bad number"),
    ("Bedroom;9;1;Hall;0;1;0;;Hal;false;true;false", "enteredFrom", "did you mean 'Hall'"),
    ("Bedroom;9;1;Hall;0;1;0;;;false;true;false", "enteredFrom", "lists no type"),
    ("Bedroom;9;1;Hall;0;1;0;;Hall;maybe;true;false", "passThrough", "unknown boolean"),
    ("Bedroom;9;1;Hall;0;1;0;;Hall;false;2;false", "needsWindow", "unknown boolean"),
])
def test_access_column_errors_name_row_and_column(row, column, message):
    with pytest.raises(RuleTableError) as info:
        table(HEADER + "\nHall;2;1;Bedroom;true;1;0;;;true;false;true\n" + row)
    assert info.value.row == 3 and info.value.column == column
    assert message in str(info.value)


def test_doors_only_where_entering_is_allowed_and_en_suite_through_the_bedroom(tmp_path):
    plan = floor_from_rectangles(FLOOR, circulation=[0])
    for seed in range(10):
        typed = type_floor(plan, write(tmp_path, EN_SUITE), seed=seed)
        assert typed.room(0).type == "Hall"
        (bath,) = rooms_of_type(typed, "Bathroom")
        assert bath.id == 3 and bath.private
        assert [d.rooms for d in doors_between(typed, 3, "Bedroom")] == [(1, 3)]
        assert not doors_between(typed, 1, 2)  # adjacency alone makes no door
        assert len(typed.doors) == 4  # front door + one door into every room
        assert typed.front_door().rooms[0] == 0


def test_a_room_that_may_only_be_entered_from_an_absent_type_has_no_typing(tmp_path):
    text = EN_SUITE.replace("Bathroom;3;0.2;Bedroom;0;1;0;9;Bedroom", "Bathroom;3;0.2;Hall;0;1;0;9;Hall")
    plan = floor_from_rectangles(FLOOR, circulation=[0])
    with pytest.raises(NoSolutionError):
        type_floor(plan, write(tmp_path, text), seed=0)


def test_circulation_is_never_entered_through_a_private_room():
    """A stair landing reached only through a bedroom would make the bedroom the way
    upstairs: the access doors refuse it and name the landing."""
    from shapely.geometry import box

    from cga.model import Room
    from cga.operations.roomtyping.room_graph import DoorSites, access_pairs

    rules = table(EN_SUITE)
    rooms = [Room(0, box(0, 0, 10, 1.6), box(0, 0, 10, 1.6), "Hall", circulation=True),
             Room(1, box(0, 1.6, 5, 5), box(0, 1.6, 5, 5), "Bedroom", private=True),
             Room(2, box(0, 5, 3, 8), box(0, 5, 3, 8), "Stair", circulation=True)]
    behind_the_bedroom = DoorSites(inner={(0, 1): (), (1, 2): ()}, outer={})
    with pytest.raises(NoSolutionError, match="room 2"):
        access_pairs(rooms, behind_the_bedroom, rules, entry=0)
    beside_the_hall = DoorSites(inner={(0, 1): (), (1, 2): (), (0, 2): ()}, outer={})
    assert access_pairs(rooms, beside_the_hall, rules, entry=0) == [(0, 1), (0, 2)]


def test_a_room_no_rule_takes_is_never_entered_through_a_private_room():
    """A leftover room (the default type, no rule) behind a bedroom would make the
    bedroom the way into it: its door comes from the hall when the hall adjoins it, and
    with only private neighbours the layout has no doors (the typing re-draws it)."""
    from shapely.geometry import box

    from cga.model import Room
    from cga.operations.roomtyping.room_graph import DoorSites, NoDoorsError, access_pairs

    rules = table(EN_SUITE)
    rooms = [Room(0, box(0, 0, 10, 1.6), box(0, 0, 10, 1.6), "Hall", circulation=True),
             Room(1, box(0, 1.6, 5, 5), box(0, 1.6, 5, 5), "Bedroom", private=True),
             Room(2, box(0, 5, 3, 8), box(0, 5, 3, 8), "Commonroom")]
    both = DoorSites(inner={(0, 1): (), (1, 2): (), (0, 2): ()}, outer={})
    assert access_pairs(rooms, both, rules, entry=0) == [(0, 1), (0, 2)]
    behind_the_bedroom = DoorSites(inner={(0, 1): (), (1, 2): ()}, outer={})
    with pytest.raises(NoDoorsError, match="room 2 .*any neighbour but a private room"):
        access_pairs(rooms, behind_the_bedroom, rules, entry=0)

