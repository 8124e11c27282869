"""Re-draws of a floor the table cannot type stop when the partition has nothing to cut."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from shapely.geometry import box

from floor_runs import run_make_floor

from cga.errors import NoSolutionError
from cga.operations.roomtyping.rules import parse_rule_table
from cga.operations.type_rooms import type_plan

UNTYPEABLE = parse_rule_table("Type;Size;Prob;Neighbours;isOutsideConnected;appearance;additionRoom\n"
                              "Ballroom;900;1;Hall;true;1;0\nHall;4;0;Ballroom;false;1;0\n")
"""A mandatory room larger than any floor here."""

RECTANGLE = box(0, 0, 14, 10)


def _plan(free_rooms_left: int):
    child, _ = run_make_floor(RECTANGLE, floor=0, seed=3, split=5, wallWidth=0.2,
                              windows=(2, 1.2, 1.2), doorWidth=0.9, doorHeight=2.1)
    recipe = child.plan.layout
    assert recipe is not None
    fixed_rooms = recipe.rooms - recipe.free_rooms
    return child.plan.with_changes(
        layout=dataclasses.replace(recipe, rooms=fixed_rooms + free_rooms_left))


@pytest.mark.parametrize("free_rooms_left", [0, -1])
def test_a_floor_with_no_free_room_is_not_redrawn(free_rooms_left):
    with pytest.raises(NoSolutionError) as failure:
        type_plan(_plan(free_rooms_left), UNTYPEABLE, np.random.default_rng(0), strict=True)
    assert not any("re-drawn" in reason for reason in failure.value.reasons)


def test_an_untypeable_floor_says_how_often_it_was_redrawn():
    with pytest.raises(NoSolutionError) as failure:
        type_plan(_plan(5), UNTYPEABLE, np.random.default_rng(0), strict=True)
    assert any("re-drawn 12 times" in reason for reason in failure.value.reasons)
