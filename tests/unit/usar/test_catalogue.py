"""The UvA room catalogue: the shipped table is the paper's Appendix A; mistakes name the
row and the column."""

from __future__ import annotations

import pytest

from cga.errors import RuleTableError
from cga.operations.usar.catalogue import load_catalogue, parse_catalogue
from cga.resources import resolve_resource
from usar_paper import PAPER



def test_shipped_catalogue_is_the_papers():
    rooms = load_catalogue(resolve_resource("usar_rooms.csv", "rules"))
    assert [(r.name, r.width, r.depth, r.difficulty) for r in rooms] == PAPER


def test_every_shipped_room_is_furnished_by_the_shipped_table():
    from cga.operations.furniture.rules import load_furniture_rules

    rooms = load_catalogue(resolve_resource("usar_rooms.csv", "rules"))
    table = load_furniture_rules(resolve_resource("furniture_usar.csv", "rules"))
    bare = {"Dark", "Empty"}  # the paper's empty rooms
    for room in rooms:
        assert room.furniture in bare or table.for_room(room.furniture), room.name


HEADER = "Name;Width;Depth;Difficulty;Furniture\n"


@pytest.mark.parametrize("text, row, column", [
    (HEADER + "a;1;1;11;Empty\n", 2, "Difficulty"),
    (HEADER + "a;1;1;x;Empty\n", 2, "Difficulty"),
    (HEADER + "a;1.5;1;2;Empty\n", 2, "Width"),
    (HEADER + "a;1;0;2;Empty\n", 2, "Depth"),
    (HEADER + "a;1;1;2;\n", 2, "Furniture"),
    (HEADER + "a;1;1;2;Empty\nA;2;2;3;Empty\n", 3, "Name"),
    ("Name;Width;Depth;Difficulty;Furnture\n", 1, "Furnture"),
    ("Name;Width;Depth;Difficulty\n", 1, "Furniture"),
])
def test_errors_name_row_and_column(text, row, column):
    with pytest.raises(RuleTableError) as info:
        parse_catalogue(text, file="rooms.csv")
    assert info.value.row == row and info.value.column == column
    assert f"rooms.csv, row {row}, column" in str(info.value)


def test_header_in_any_order_and_case():
    rooms = parse_catalogue("furniture;difficulty;name;depth;width\nOffice;5;office;1;2\n")
    assert (rooms[0].name, rooms[0].width, rooms[0].depth, rooms[0].difficulty) == ("office", 2, 1, 5.0)


def test_empty_catalogue_is_an_error():
    with pytest.raises(RuleTableError, match="empty"):
        parse_catalogue("")
    with pytest.raises(RuleTableError, match="no rooms"):
        parse_catalogue(HEADER)
