"""The furniture rule-table parser: formats, aliases, defaults and errors."""

from __future__ import annotations

import pytest

from cga.errors import RuleTableError
from cga.operations.furniture.rules import load_furniture_rules, parse_furniture_rules

HEADER = ("Room;Name;isInCorner;isAlongWall;hasPair;PairWith;minPairDistance;maxPairDistance;"
          "needsTurn;clearanceSide;clearanceFront;clearanceBack;canCloseWindow;canBeAround;"
          "nonCollision;isDetail;isOnTheSide")


def table(*rows: str, header: str = HEADER) -> str:
    return "\n".join((header, *rows)) + "\n"


def error_of(text: str) -> RuleTableError:
    with pytest.raises(RuleTableError) as caught:
        parse_furniture_rules(text, file="t.csv")
    return caught.value


def test_thesis_table_parses_verbatim(rules_dir):
    rules = load_furniture_rules(rules_dir / "furniture_thesis.csv")
    assert [r.name for r in rules] == ["window", "door", "tableBig", "chair", "chair1", "chair2",
                                       "sofa", "tvboard", "FloorLamp", "bookshelf", "bookshelf1",
                                       "SofaTable"]
    by_name = {r.name: r for r in rules}
    assert by_name["window"].is_detail and by_name["window"].detail_kind == "window"
    assert by_name["tvboard"].pair_with == "sofa"  # written "Sofa" in the thesis
    assert by_name["SofaTable"].min_pair_distance == 0.2
    assert by_name["SofaTable"].max_pair_distance == 0.4
    assert by_name["chair1"].can_be_around and by_name["chair1"].clearance_back == 0.1
    assert by_name["FloorLamp"].is_in_corner
    assert by_name["bookshelf"].can_close_window
    assert by_name["tableBig"].pair_with is None and not by_name["tableBig"].is_child


@pytest.mark.parametrize("delimiter", [";", ",", "\t"])
def test_delimiter_is_sniffed(delimiter):
    text = table("Livingroom;sofa;false;true;false;<null>;0;0;false;0.1;0.2;0;false;false;false;false;false")
    rules = parse_furniture_rules(text.replace(";", delimiter))
    assert rules.rules[0].clearance_front == 0.2 and rules.rules[0].is_along_wall


def test_header_case_aliases_and_defaults():
    text = ("Regel;ROOM;name;ISALONGWALL;hasPaar;PaarWith;minPaarDistance;needInTurn\n"
            "1;Bedroom;bed;1;1;;0;true\n"
            "2;Bedroom;nightstand;0;true;BED;0,2;false\n")
    bed, stand = parse_furniture_rules(text).rules
    assert bed.is_along_wall and bed.has_pair and bed.needs_turn
    assert stand.pair_with == "bed" and stand.min_pair_distance == 0.2  # decimal comma
    assert stand.clearance_front == 0.0 and not stand.can_close_window  # missing → default


def test_row_number_column_only_first():
    text = "Room;Name;Regel\nBedroom;bed;7\n"
    assert "unknown column 'Regel'" in str(error_of(text))


def test_scaled_multiplies_distances_only():
    rules = parse_furniture_rules(table(
        "Livingroom;sofa;false;true;true;;0;0;false;0.1;0.2;0.3;false;false;false;false;false",
        "Livingroom;table;false;false;true;sofa;0.2;0.4;false;0;0;0;false;false;false;false;false"))
    scaled = rules.scaled(10)
    sofa, child = scaled.rules
    assert (sofa.clearance_side, sofa.clearance_front, sofa.clearance_back) == pytest.approx((1, 2, 3))
    assert (child.min_pair_distance, child.max_pair_distance) == pytest.approx((2, 4))
    assert sofa.is_along_wall and child.pair_with == "sofa"


def test_children_follow_their_parent_and_details_are_apart():
    rules = parse_furniture_rules(table(
        "Kitchen;stove;false;false;true;counter;0;0;false;0;0;0;false;false;false;false;true",
        "Kitchen;window;false;false;false;;0;0;false;0;0;0;false;false;false;true;false",
        "Kitchen;fridge;false;true;false;;0;0;false;0;0;0;false;false;false;false;false",
        "Kitchen;counter;false;true;true;;0;0;false;0;0;0;false;false;false;false;false",
        "Kitchen;sink;false;false;true;counter;0;0;false;0;0;0;false;false;false;false;true"))
    assert [r.name for r in rules.for_room("kitchen")] == ["fridge", "counter", "stove", "sink"]
    assert [r.name for r in rules.details("KITCHEN")] == ["window"]
    assert rules.for_room("Bedroom") == []


def test_model_candidates_drop_a_numeric_suffix():
    rules = parse_furniture_rules(table(
        "Office;chair12;false;false;false;;0;0;false;0;0;0;false;false;false;false;false"))
    assert rules.rules[0].model_candidates() == ("chair12", "chair")


@pytest.mark.parametrize("row, column, words", [
    ("Livingroom;sofa;maybe;true;false;;0;0;false;0;0;0;false;false;false;false;false",
     "isInCorner", "true/false"),
    ("Livingroom;sofa;false;true;false;;0;0;false;wide;0;0;false;false;false;false;false",
     "clearanceSide", "a number"),
    ("Livingroom;sofa;false;true;false;;0;0;false;-1;0;0;false;false;false;false;false",
     "clearanceSide", "≥ 0"),
    ("Livingroom;;false;true;false;;0;0;false;0;0;0;false;false;false;false;false",
     "Name", "empty"),
    ("Livingroom;sofa;true;true;false;;0;0;false;0;0;0;false;false;false;false;false",
     "isAlongWall", "choose one"),
    ("Livingroom;lamp;false;false;false;;0;0;false;0;0;0;false;true;false;false;false",
     "canBeAround", "PairWith"),
    ("Livingroom;mirror;false;false;false;;0;0;false;0;0;0;false;false;false;true;false",
     "Name", "door or window"),
])
def test_row_errors_name_row_and_column(row, column, words):
    error = error_of(table(row))
    assert error.row == 2 and error.column == column
    assert words in str(error) and "t.csv, row 2" in str(error)


def test_child_without_parent_names_it():
    error = error_of(table(
        "Livingroom;sofa;false;true;true;;0;0;false;0;0;0;false;false;false;false;false",
        "Livingroom;tvboard;false;true;true;Couch;0;0;false;0;0;0;false;false;false;false;false"))
    assert error.row == 3 and error.column == "PairWith"
    assert "'Couch'" in str(error) and "sofa" in str(error)


def test_parent_in_another_room_type_does_not_count():
    error = error_of(table(
        "Bedroom;sofa;false;true;true;;0;0;false;0;0;0;false;false;false;false;false",
        "Livingroom;tvboard;false;true;true;sofa;0;0;false;0;0;0;false;false;false;false;false"))
    assert error.row == 3 and "room type Livingroom" in str(error)


def test_pair_with_needs_has_pair_and_max_not_below_min():
    error = error_of(table(
        "Livingroom;sofa;false;true;true;;0;0;false;0;0;0;false;false;false;false;false",
        "Livingroom;table;false;false;false;sofa;0;0;false;0;0;0;false;false;false;false;false"))
    assert error.column == "hasPair"
    error = error_of(table(
        "Livingroom;sofa;false;true;true;;0;0;false;0;0;0;false;false;false;false;false",
        "Livingroom;table;false;false;true;sofa;0.5;0.2;false;0;0;0;false;false;false;false;false"))
    assert error.column == "maxPairDistance"


def test_duplicates_and_cycles_are_errors():
    error = error_of(table(
        "Livingroom;sofa;false;true;false;;0;0;false;0;0;0;false;false;false;false;false",
        "livingroom;Sofa;false;true;false;;0;0;false;0;0;0;false;false;false;false;false"))
    assert error.row == 3 and "appears twice" in str(error) and "row 2" in str(error)
    error = error_of(table(
        "Livingroom;a;false;false;true;b;0;0;false;0;0;0;false;false;false;false;false",
        "Livingroom;b;false;false;true;a;0;0;false;0;0;0;false;false;false;false;false"))
    assert "cycle" in str(error)


def test_header_errors():
    assert "did you mean 'clearanceFront'" in str(error_of("Room;Name;clearanceFrnt\nA;b;0\n"))
    assert "missing column 'Name'" in str(error_of("Room;isInCorner\nA;true\n"))
    assert "empty" in str(error_of("\n\n"))
    assert "column given twice" in str(error_of("Room;Name;hasPair;hasPaar\nA;b;1;1\n"))
    error = error_of(table("Livingroom;sofa;false;true;false;;0;0;false;0;0;0;false;false;false;false;false;x"))
    assert error.row == 2 and "18 cells" in str(error)
