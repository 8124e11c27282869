"""The areas a table asks for, to aim re-drawn cuts at."""

import pytest

from cga.operations.roomtyping.rules import parse_rule_table
from cga.operations.roomtyping.targets import redraw_count, target_areas

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


def house(unit=1.0):
    """Rooms of 16 m² on average (the midpoints of Size..maxSize: 28, 6.5 and 13.5 m²),
    sizes written in ``unit`` m² (0.01 for a table read at units = 10)."""
    def m2(area):
        return f"{area * unit:g}"
    return table("Hall;1;1;Living, Bath, Bed;true;1;0;;;true;false;true",
                 f"Living;{m2(16)};1;Hall;0;1;0;{m2(40)};Hall;true;true;false",
                 f"Bath;{m2(4)};0;Hall;0;2;0;{m2(9)};Hall;false;false;false",
                 f"Bed;{m2(9)};0;Hall;0;3;0;{m2(18)};Hall;false;true;false",
                 f"Guest;{m2(9)};0;Hall;0;10;1;;Hall;false;true;false")


@pytest.mark.parametrize("count, free_area, expected", [
    (6, 30.0, 3),     # holds 1, but the mandatory rules need 3 rooms
    (6, 60.0, 3),     # holds 3
    (6, 90.0, 5),     # holds 5
    (6, 100.0, 6),    # the lot the grammar was written for: 6 rooms of 16 m²
    (6, 192.0, 6),    # holds 12, twice the count: still the grammar's
    (6, 208.0, 13),   # holds 13: as many as it holds
    (6, 400.0, 16),   # holds 25, but the table types 1 + 2 + 3 + 10 rooms
    (12, 300.0, 12),  # never fewer than the grammar asked for
])
def test_redraws_aim_at_other_counts_only_on_a_floor_too_small_or_far_too_big(
        count, free_area, expected):
    assert redraw_count(house(), count, free_area, 1.0, attempt=12, attempts=12) == expected


def test_redraw_count_reads_sizes_in_the_tables_unit():
    # Size 0.16 at units = 10 is 16 m²: the same floor as 16 at units = 1
    assert redraw_count(house(0.01), 6, 210.0, 100.0, attempt=12, attempts=12) == 13
    assert redraw_count(house(0.01), 6, 190.0, 100.0, attempt=12, attempts=12) == 6


def test_the_first_half_of_the_redraws_keep_the_count_the_rest_aim_at_more_rooms():
    counts = [redraw_count(house(), 6, 400.0, 1.0, attempt=a, attempts=12) for a in range(1, 13)]
    assert counts[:6] == [6] * 6 and counts[-1] == 16 and counts == sorted(counts)
    assert [redraw_count(house(), 6, 100.0, 1.0, attempt=a, attempts=12)
            for a in (1, 12)] == [6, 6]


def test_on_a_small_floor_later_redraws_aim_at_fewer_rooms():
    counts = [redraw_count(house(), 8, 60.0, 1.0, attempt=a, attempts=12) for a in range(1, 13)]
    assert counts[:6] == [8] * 6 and counts[-1] == 3
    assert counts == sorted(counts, reverse=True)
