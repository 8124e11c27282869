"""The rule-author API, and the pytest example that docs/room_typing.md shows."""

import pytest

from cga.authoring import (are_adjacent, doors_between, floor_from_rectangles, rooms_of_type,
                           type_floor)
from cga.errors import ResourceNotFoundError, UsageError
from cga.model import OUTSIDE


# -- the example of docs/room_typing.md, verbatim -------------------------------------
HALL_FLOOR = [(0, 4, 14, 5.6),  # the hall, wall to wall
              (0, 0, 6, 4), (6, 0, 8.2, 4), (8.2, 0, 11.4, 4), (11.4, 0, 14, 4),
              (0, 5.6, 4, 10), (4, 5.6, 8, 10), (8, 5.6, 11, 10), (11, 5.6, 14, 10)]


def test_house_rules_on_a_floor_with_a_hall():
    plan = floor_from_rectangles(HALL_FLOOR, circulation=[0])
    for seed in range(25):
        typed = type_floor(plan, "house_types.csv", seed=seed)
        (hall,) = rooms_of_type(typed, "Hall")
        assert hall.circulation
        (living,) = rooms_of_type(typed, "Livingroom")
        assert living.area >= 16
        assert doors_between(typed, "Hall", "outside")  # the front door opens into the hall
        for bedroom in rooms_of_type(typed, "Bedroom"):
            assert doors_between(typed, bedroom.id, "Hall")  # bedrooms open onto the hall
            assert len(doors_between(typed, bedroom.id, "Livingroom")) == 0
# -------------------------------------------------------------------------------------


def test_floor_settings_and_index():
    plan = floor_from_rectangles([(0, 0, 5, 4), (5, 0, 10, 4)], door_width=1.0, index=1)
    assert plan.settings.door_width == 1.0 and plan.index == 1
    with pytest.raises(UsageError, match="did you mean 'door_width'"):
        floor_from_rectangles([(0, 0, 5, 4)], doorwidth=1.0)
    with pytest.raises(UsageError, match="overlap"):
        floor_from_rectangles([(0, 0, 5, 4), (4, 0, 8, 4)])


def test_type_floor_is_reproducible_by_seed(tmp_path):
    plan = floor_from_rectangles(HALL_FLOOR, circulation=[0])
    first = type_floor(plan, "house_types.csv", seed=7)
    again = type_floor(plan, "house_types.csv", seed=7)
    assert [r.type for r in first.rooms] == [r.type for r in again.rooms]
    assert first.doors == again.doors
    with pytest.raises(ResourceNotFoundError):
        type_floor(plan, tmp_path / "missing.csv")


def test_helpers_accept_ids_types_and_outside():
    plan = floor_from_rectangles([(0, 0, 6, 10), (6, 0, 14, 5), (6, 5, 14, 10)])
    typed = type_floor(plan, "thesis_types.csv", seed=0, door_position="center")
    assert are_adjacent(typed, 0, 1) and are_adjacent(typed, 1, 2)
    assert are_adjacent(typed, 0, "outside") and are_adjacent(typed, OUTSIDE, 2)
    assert not are_adjacent(typed, "Nosuchroom", 0)
    front = typed.front_door()
    assert doors_between(typed, front.swing_room, OUTSIDE) == [front]
    for door in typed.doors:
        assert door in doors_between(typed, *door.rooms)
    assert rooms_of_type(typed, "Nosuchroom") == []
    with pytest.raises(KeyError):
        are_adjacent(typed, 99, 0)
