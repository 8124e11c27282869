"""The areas a table asks for, to aim re-drawn cuts at."""

import pytest

from cga.operations.roomtyping.rules import parse_rule_table
from cga.operations.roomtyping.targets import target_areas

HEADER = ("Type;Size;Prob;Neighbours;isOutsideConnected;appearance;additionRoom;"
          "maxSize;enteredFrom;passThrough;needsWindow;circulation")


def table(*rows):
    return parse_rule_table("\n".join([HEADER, *rows]) + "\n", file="t.csv")


def test_areas_fill_the_floor_and_respect_caps_while_others_can_grow():
    rules = table("Hall;2;1;Living;true;1;0;;;true;false;true",
                  "Living;16;1;Hall;0;1;0;;Hall;true;true;false",
                  "Bath;4;0;Hall;0;1;0;9;Hall;false;false;false")
    areas = target_areas(rules, 2, 100.0, 1.0)
    assert sum(areas) == pytest.approx(100.0)
    assert areas[1] <= 9 and areas[0] == pytest.approx(100 - areas[1])


def test_optional_rules_fill_the_rooms_left_roomiest_first_while_caps_fall_short():
    rules = table("Hall;2;1;Bed;true;1;0;;;true;false;true",
                  "Bed;9;1;Hall;0;3;0;18;Hall;false;true;false",
                  "Store;2;0;Hall;0;1;1;6;Hall;false;false;false",
                  "Family;12;0;Hall;0;1;1;30;Hall;true;true;false")
    areas = target_areas(rules, 4, 80.0, 1.0)
    assert len(areas) == 4 and sum(areas) == pytest.approx(80.0)
    assert max(areas) <= 30 + 1e-9  # Family, Bed, Bed, Bed fill 80 m² without a cap broken


def test_units_scale_sizes():
    rules = table("Hall;0.02;1;A;true;1;0;;;true;false;true",
                  "A;0.2;1;Hall;0;1;0;0.3;Hall;true;false;false",
                  "B;0.1;1;Hall;0;1;0;;Hall;true;false;false")
    areas = target_areas(rules, 2, 40.0, 100.0)
    assert areas[0] <= 30 + 1e-9 and sum(areas) == pytest.approx(40.0)
