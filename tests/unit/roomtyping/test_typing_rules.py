"""The typing-table parser: the thesis format, and every mistake named by row and column."""

import pytest

from cga.errors import RuleTableError
from cga.operations.roomtyping.rules import (COLUMNS, DEFAULT_TYPE, load_rule_table,
                                             parse_rule_table)

HEADER = "Type;Size;Prob;Neighbours;isOutsideConnected;appearance;additionRoom"

# Figure 5.1 of the thesis, verbatim.
THESIS = """\
Type;Size;Prob;Neighbours;isOutsideConnected;appearance;additionRoom
Kitchen;0.25;0.5;Livingroom;0;1;0
Livingroom;1;1;Bathroom, Livingroom, Bedroom, Kitchen;true;1;0
Bedroom;1;0.1;Bathroom, Livingroom, Bedroom;0;1;0
Bathroom;0.25;0.4;Bedroom, Livingroom, Bathroom;0;1;0
Laundryroom;0.1;0;Bathroom;0;1;1
Storageroom;0.1;0;Kitchen;0;1;1
Commonroom;0;0;Bathroom, Livingroom, Bedroom, Kitchen;0;1;1
"""


def table(*rows, header=HEADER):
    return parse_rule_table("\n".join([header, *rows]) + "\n", file="t.csv")


def error(*rows, header=HEADER) -> RuleTableError:
    with pytest.raises(RuleTableError) as info:
        table(*rows, header=header)
    return info.value


def test_thesis_figure_5_1_parses_like_the_thesis_parser_test():
    rules = parse_rule_table(THESIS, file="TestConfig").rules
    assert len([r for r in rules if r.optional]) == 3  # "Number of Additional Rules: 3"
    assert len([r for r in rules if not r.optional]) == 4  # "Number of needed Rules: 4"
    kitchen = rules[0]
    assert (kitchen.type, kitchen.size, kitchen.prob, kitchen.neighbours, kitchen.outside,
            kitchen.appearance, kitchen.optional, kitchen.row) == (
        "Kitchen", 0.25, 0.5, ("Livingroom",), False, 1, False, 2)
    assert rules[1].neighbours == ("Bathroom", "Livingroom", "Bedroom", "Kitchen")
    assert rules[1].outside is True


def test_shipped_thesis_table_is_figure_5_1():
    shipped = load_rule_table(_shipped("thesis_types.csv"))
    assert shipped.rules == parse_rule_table(THESIS, file=shipped.file).rules


@pytest.mark.parametrize("name", ["house_types.csv", "office_types.csv", "thesis_types.csv"])
def test_shipped_tables_parse_with_one_front_door_rule(name):
    parsed = load_rule_table(_shipped(name))
    assert parsed.outside_rule is not None and not parsed.outside_rule.optional
    assert parsed.mandatory


def _shipped(name):
    from cga.resources import resolve_resource
    return resolve_resource(name, "rules")


def test_header_matched_case_insensitively_in_any_order():
    parsed = table("Livingroom;20;1;Kitchen;TRUE;1;0", "Kitchen;8;0;livingroom;False;1;0",
                   header="type;SIZE;prob;neighbours;IsOutsideConnected;Appearance;ADDITIONROOM")
    assert [r.type for r in parsed.rules] == ["Livingroom", "Kitchen"]
    assert parsed.rules[1].neighbours == ("Livingroom",)  # spelled as its rule spells it
    reordered = parse_rule_table(
        "additionRoom;Type;Neighbours;Size;Prob;appearance;isOutsideConnected\n"
        "0;Hall;Hall;4;1;2;1\n", file="t.csv")
    hall = reordered.rules[0]
    assert (hall.type, hall.size, hall.prob, hall.appearance, hall.outside) == ("Hall", 4, 1, 2, True)


def test_blank_lines_spreadsheet_padding_and_decimal_comma():
    parsed = parse_rule_table(
        f"\n{HEADER};;\n\nLivingroom;12,5;1;Kitchen;1;1;0;;\n;;;;;;\n   \n"
        "Kitchen;6;0,5;Livingroom;0;1;0\n", file="t.csv")
    assert [(r.type, r.size, r.prob, r.row) for r in parsed.rules] == [
        ("Livingroom", 12.5, 1.0, 4), ("Kitchen", 6.0, 0.5, 7)]


def test_duplicate_neighbours_collapse_and_default_type_is_known():
    parsed = table(f"Livingroom;20;1;Kitchen, Kitchen , {DEFAULT_TYPE};1;1;0",
                   "Kitchen;8;0;Livingroom;0;1;0")
    assert parsed.rules[0].neighbours == ("Kitchen", DEFAULT_TYPE)


@pytest.mark.parametrize("rows, row, column, words", [
    (["Livingroom;big;1;Kitchen;1;1;0"], 2, "Size", "bad number 'big'"),
    (["Livingroom;20;1.5;Kitchen;1;1;0"], 2, "Prob", "between 0 and 1"),
    (["Livingroom;-3;1;Kitchen;1;1;0"], 2, "Size", "negative"),
    (["Livingroom;20;1;Kitchen;yes;1;0"], 2, "isOutsideConnected", "unknown boolean 'yes'"),
    (["Livingroom;20;1;Kitchen;1;1;maybe"], 2, "additionRoom", "unknown boolean 'maybe'"),
    (["Livingroom;20;1;Kitchen;1;1.5;0"], 2, "appearance", "whole number"),
    (["Livingroom;20;1;Kitchen;1;0;0"], 2, "appearance", "mandatory"),
    (["Livingroom;20;1;;1;1;0"], 2, "Neighbours", "lists no neighbour"),
    (["Livingroom;20;1;Kitchen;1;1"], 2, "additionRoom", "6 cells"),
    (["Livingroom;20;1;Kitchen;1;1;0;x"], 2, None, "more cells"),
    ([";20;1;Kitchen;1;1;0"], 2, "Type", "empty"),
    (["Livingroom;20;1;Kitchen;1;1;0", "livingroom;20;1;Kitchen;0;1;0"], 3, "Type",
     "already defined in row 2"),
    (["Livingroom;20;1;Kitchn;1;1;0", "Kitchen;8;0;Livingroom;0;1;0"], 2, "Neighbours",
     "did you mean 'Kitchen'?"),
    (["Livingroom;20;1;Kitchen;1;1;0", "Kitchen;8;0;Livingroom;true;1;0"], 3,
     "isOutsideConnected", "only one rule may set isOutsideConnected"),
    (["Livingroom;20;1;Kitchen;1;1;1", "Kitchen;8;0;Livingroom;0;1;0"], 2, "additionRoom",
     "must be mandatory"),
    (["Livingroom;20;1;Kitchen;0;1;1", "Kitchen;8;0;Livingroom;0;1;1"], None, "additionRoom",
     "no mandatory rule"),
])
def test_mistakes_name_file_row_and_column(rows, row, column, words):
    err = error(*rows)
    assert (err.file, err.row, err.column) == ("t.csv", row, column)
    assert words in str(err)
    assert str(err).startswith("t.csv")


def test_missing_and_unknown_columns():
    missing = error("Livingroom;20;1;Kitchen;1;1", header=HEADER.rsplit(";", 1)[0])
    assert (missing.row, missing.column) == (1, "additionRoom")
    assert "missing column 'additionRoom'" in str(missing)
    typo = error("Livingroom;20;1;Kitchen;1;1;0", header=HEADER.replace("Neighbours", "Neighbors"))
    assert typo.column == "Neighbors" and "did you mean 'Neighbours'?" in str(typo)
    twice = error("x", header=HEADER + ";type")
    assert twice.column == "Type" and "twice" in str(twice)


def test_empty_tables():
    with pytest.raises(RuleTableError, match="empty"):
        parse_rule_table("\n \n", file="t.csv")
    with pytest.raises(RuleTableError, match="no rules"):
        parse_rule_table(HEADER + "\n", file="t.csv")


def test_unreadable_file(tmp_path):
    path = tmp_path / "latin1.csv"
    path.write_bytes((HEADER + "\nK\xfcche;8;1;K\xfcche;1;1;0\n").encode("latin-1"))
    with pytest.raises(RuleTableError, match="not UTF-8"):
        load_rule_table(path)
    with pytest.raises(RuleTableError, match="cannot read"):
        load_rule_table(tmp_path)


def test_columns_constant_matches_thesis_header():
    assert ";".join(COLUMNS) == HEADER
