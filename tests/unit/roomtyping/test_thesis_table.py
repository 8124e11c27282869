"""The thesis' own example (Fig. 5.1/6.6 table, five rooms as in Fig. 6.8)."""

import numpy as np
import pytest
from typing_checks import validate_typed_plan

from cga.authoring import are_adjacent, doors_between, floor_from_rectangles, type_floor
from cga.operations.floorplan.rectangles import plan_from_rectangles
from cga.operations.roomtyping.rules import load_rule_table
from cga.operations.type_rooms import type_plan
from cga.resources import resolve_resource

TABLE = resolve_resource("thesis_types.csv", "rules")
MANDATORY = {"Kitchen", "Livingroom", "Bedroom", "Bathroom"}


@pytest.mark.parametrize("seed", range(40))
def test_five_rooms_in_metres(seed):
    plan = floor_from_rectangles([(0, 0, 6, 5), (6, 0, 10, 5), (10, 0, 14, 5),
                                  (0, 5, 7, 10), (7, 5, 14, 10)])
    typed = type_floor(plan, TABLE, seed=seed)
    validate_typed_plan(typed, TABLE)
    types = [r.type for r in typed.rooms]
    assert MANDATORY <= set(types)  # four mandatory rules, one optional room
    assert are_adjacent(typed, "Kitchen", "Livingroom")
    assert doors_between(typed, "Kitchen", "Livingroom")
    (front,) = [d for d in typed.doors if d.is_front]
    assert typed.room(front.swing_room).type == "Livingroom"


@pytest.mark.parametrize("seed", range(10))
def test_five_rooms_at_the_thesis_scale(seed):
    # units = 10 (thesis 1:10): Size 1 → 100 m² (Livingroom, Bedroom), 0.25 → 25 m²
    plan = plan_from_rectangles([(0, 0, 12, 10), (12, 0, 24, 10), (0, 10, 8, 20),
                                 (8, 10, 16, 20), (16, 10, 24, 20)])
    typed = type_plan(plan, load_rule_table(TABLE), np.random.default_rng(seed), units=10.0)
    validate_typed_plan(typed, TABLE, units=10.0)
    big = {r.type for r in typed.rooms if r.area >= 100}
    assert {"Livingroom", "Bedroom"} <= big
    assert are_adjacent(typed, "Kitchen", "Livingroom")


def test_four_rooms_use_only_mandatory_rules():
    # Fig. 6.9: with four rooms there is no laundry any more
    plan = floor_from_rectangles([(0, 0, 7, 5), (7, 0, 14, 5), (0, 5, 7, 10), (7, 5, 14, 10)])
    for seed in range(20):
        typed = type_floor(plan, TABLE, seed=seed)
        validate_typed_plan(typed, TABLE)
        assert sorted(r.type for r in typed.rooms) == sorted(MANDATORY)
