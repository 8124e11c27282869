"""The typing process on abstract rooms: first rule, phases, caps, small floors, seeds."""

import numpy as np
import pytest

from cga.operations.roomtyping.assign import assign_types, draw_first_rule
from cga.operations.roomtyping.backtrack import RoomSet
from cga.operations.roomtyping.rules import DEFAULT_TYPE, parse_rule_table

HEADER = "Type;Size;Prob;Neighbours;isOutsideConnected;appearance;additionRoom"


def rules(*rows):
    return parse_rule_table("\n".join([HEADER, *rows]), file="t.csv")


def strip(areas, entrances=None):
    """Rooms in a row: room i adjoins rooms i-1 and i+1."""
    n = len(areas)
    adjacency = tuple(frozenset(j for j in (i - 1, i + 1) if 0 <= j < n) for i in range(n))
    return RoomSet(tuple(float(a) for a in areas), adjacency,
                   None if entrances is None else frozenset(entrances))


def star(hub_area, leaf_areas):
    """Room 0 adjoins every other room; the others only room 0."""
    n = len(leaf_areas) + 1
    adjacency = (frozenset(range(1, n)),) + tuple(frozenset({0}) for _ in leaf_areas)
    return RoomSet((float(hub_area), *map(float, leaf_areas)), adjacency)


HOUSE = rules(
    "Livingroom;14;1;Kitchen, Bedroom, Bathroom, Hall;1;1;0",
    "Kitchen;6;0.5;Livingroom;0;1;0",
    "Bedroom;8;0.3;Livingroom, Bathroom;0;3;0",
    "Bathroom;3;0.2;Livingroom, Bedroom;0;1;0",
    "Hall;2;0;Livingroom, Bedroom;0;1;1",
)


def satisfied(rooms, table, types, scale=1.0):
    """Mandatory types whose room is big enough and adjoins a listed type."""
    done = set()
    for rule in table.mandatory:
        for i, t in enumerate(types):
            if t == rule.type and rooms.areas[i] >= rule.size * scale and any(
                    types[j] in rule.neighbours for j in rooms.adjacency[i]):
                done.add(rule.type)
    return done


@pytest.mark.parametrize("seed", range(30))
def test_star_house_types_every_room_and_satisfies_every_mandatory_rule(seed):
    rooms = star(30, [12, 10, 9, 5, 4])
    typing = assign_types(rooms, HOUSE, np.random.default_rng(seed))
    assert typing.types[0] == "Livingroom"  # the only room adjoining all the others
    assert satisfied(rooms, HOUSE, typing.types) == {r.type for r in HOUSE.mandatory}
    assert typing.exempt is None and typing.skipped == ()
    assert DEFAULT_TYPE not in typing.types[:4]
    assert typing.types.count("Bedroom") <= 3 and typing.types.count("Hall") <= 1


def test_same_seed_same_typing_and_seeds_vary_it():
    rooms = strip([20, 20, 20, 20, 20, 20])
    table = rules("Livingroom;1;1;Bedroom;0;1;0", "Bedroom;1;1;Livingroom, Bedroom;0;5;0")
    runs = {seed: assign_types(rooms, table, np.random.default_rng(seed)).types
            for seed in range(12)}
    assert runs[3] == assign_types(rooms, table, np.random.default_rng(3)).types
    assert len({t.index("Livingroom") for t in runs.values()}) > 1


def test_first_rule_is_drawn_by_prob():
    table = rules("A;1;0;B;0;1;0", "B;1;1;A;0;1;0", "C;1;0.5;A;0;1;0").mandatory
    draws = [draw_first_rule(table, np.random.default_rng(s)) for s in range(400)]
    assert set(draws) == {1, 2}  # Prob 0 never qualifies while another rule does
    assert 0.15 < draws.count(2) / len(draws) < 0.35  # C: u ≤ 0.5 (half), then 1 of 2
    zero = rules("A;1;0;B;0;1;0", "B;1;0;A;0;1;0").mandatory
    assert {draw_first_rule(zero, np.random.default_rng(s)) for s in range(50)} == {0, 1}


def test_optional_rules_fill_remaining_rooms_within_appearance_then_default():
    table = rules("Livingroom;1;1;Office;0;1;0", "Office;1;0;Livingroom, Office;0;2;1")
    rooms = strip([10] * 6)
    typing = assign_types(rooms, table, np.random.default_rng(0))
    assert sorted(typing.types) == sorted(["Livingroom", "Office", "Office"] + [DEFAULT_TYPE] * 3)
    assert any("default type Commonroom" in n.message for n in typing.notes)


def test_mandatory_type_repeats_in_the_optional_phase_up_to_appearance():
    table = rules("Livingroom;1;1;Bedroom;0;1;0", "Bedroom;1;0;Livingroom, Bedroom;0;3;0")
    typing = assign_types(strip([10] * 5), table, np.random.default_rng(1))
    assert typing.types.count("Bedroom") == 3
    assert typing.types.count(DEFAULT_TYPE) == 1


def test_optional_rule_needs_size_and_a_listed_neighbour():
    table = rules("Livingroom;1;1;Kitchen;0;1;0", "Kitchen;1;0;Livingroom;0;1;0",
                  "Storageroom;1;0;Kitchen;0;1;1", "Library;50;0;Livingroom;0;1;1")
    rooms = strip([10, 10, 10, 10])
    for seed in range(10):
        types = assign_types(rooms, table, np.random.default_rng(seed)).types
        assert "Library" not in types  # no room of 50 m²
        for i, t in enumerate(types):
            if t == "Storageroom":
                assert any(types[j] == "Kitchen" for j in rooms.adjacency[i])


def test_one_room_floor_with_a_living_room_rule_becomes_a_living_room():
    table = rules("Kitchen;1;1;Livingroom;0;1;0", "Livingroom;1;1;Kitchen;1;1;0",
                  "Bedroom;1;1;Livingroom;0;1;0")
    typing = assign_types(strip([12]), table, np.random.default_rng(0))
    assert typing.types == ("Livingroom",)
    assert typing.skipped == ("Kitchen", "Bedroom")
    warning = next(n for n in typing.notes if n.level == "warning")
    assert "1 room for 3 mandatory rules" in warning.message
    assert "skipped Kitchen, Bedroom" in warning.message


def test_too_few_rooms_keeps_as_many_rules_as_fit_in_rule_order():
    table = rules("Livingroom;10;1;Kitchen, Bedroom;1;1;0", "Kitchen;30;1;Livingroom;0;1;0",
                  "Bedroom;5;1;Livingroom;0;1;0", "Bathroom;2;1;Bedroom;0;1;0")
    typing = assign_types(strip([12, 8, 3]), table, np.random.default_rng(0))
    # Kitchen (30 m²) fits nowhere; Bedroom then Bathroom fit beside the living room
    assert typing.types == ("Livingroom", "Bedroom", "Bathroom")
    assert typing.skipped == ("Kitchen",)


def test_sizes_scale_by_units_squared():
    table = rules("Livingroom;0.2;1;Kitchen;0;1;0", "Kitchen;0.1;1;Livingroom;0;1;0")
    rooms = strip([15, 25])
    typing = assign_types(rooms, table, np.random.default_rng(0), area_scale=100.0)
    assert typing.types == ("Kitchen", "Livingroom")  # 20 m² and 10 m² needed
