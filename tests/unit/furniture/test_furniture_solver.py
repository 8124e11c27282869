"""The solver on whole rooms and floors: the thesis table, small rooms, details."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from furniture_checks import furniture_violations
from hall_floors import typed_hall_floor

from cga.authoring import furnish_floor
from cga.operations.furniture import placement, solver
from cga.operations.furniture.rules import load_furniture_rules, parse_furniture_rules
from cga.operations.furniture.layout import ItemSpec
from cga.operations.furniture.solver import RoomSite, furnish_plan


def models_for(rules, library):
    return {r.name: (library.get(r.name).name, library.get(r.name).size)
            for r in rules if not r.is_detail}


@pytest.fixture(scope="module")
def thesis(rules_dir, library):
    rules = load_furniture_rules(rules_dir / "furniture_thesis.csv")
    return rules, models_for(rules, library)


def test_thesis_table_places_all_twelve_items_in_a_5_by_4_room(thesis, room_plan, rules_dir):
    rules, models = thesis
    complete = 0
    for seed in range(100):
        plan = room_plan(5.0, 4.0, doors=((seed % 4, 0.25 + 0.5 * (seed % 3) / 2, "start"),),
                         windows=(((seed + 2) % 4, 0.5),))
        furniture, diagnostics = furnish_plan(plan, rules, models, np.random.default_rng(seed))
        furnished = plan.with_changes(furniture=furniture)
        assert furniture_violations(furnished, rules_dir / "furniture_thesis.csv") == []
        names = {item.name for item in furniture}
        expected = {r.name for r in rules if not r.is_detail} | {"door0", "window0"}
        if names == expected and not diagnostics:
            complete += 1
    assert complete >= 95


def test_a_small_room_leaves_items_out_with_reasons(thesis, room_plan, rules_dir):
    rules, models = thesis
    plan = room_plan(3.0, 2.6)
    furniture, diagnostics = furnish_plan(plan, rules, models, np.random.default_rng(1))
    assert diagnostics, "a 3 × 2.6 m room cannot hold the thesis' living room"
    placed = {item.name for item in furniture}
    for diagnostic in diagnostics:
        assert diagnostic.level == "warning" and diagnostic.stage == "add_furniture"
        assert diagnostic.room == 0 and diagnostic.floor == 0
        name, _, reason = diagnostic.message.partition(" left out of room0_Livingroom: ")
        assert name in {r.name for r in rules} and name not in placed and reason
    assert furniture_violations(plan.with_changes(furniture=furniture),
                                rules_dir / "furniture_thesis.csv") == []


def test_orphaned_children_say_their_parent_was_not_placed(room_plan, library):
    rules = parse_furniture_rules(
        "Room;Name;isAlongWall;hasPair;PairWith;canBeAround\n"
        "Livingroom;tableBig;true;true;;false\n"
        "Livingroom;chair;false;true;tableBig;true\n")
    plan = room_plan(1.8, 1.8)
    _, diagnostics = furnish_plan(plan, rules, models_for(rules, library),
                                  np.random.default_rng(0))
    messages = [d.message for d in diagnostics]
    assert messages[0].startswith("tableBig left out of room0_Livingroom: no wall long enough")
    assert messages[1] == "chair left out of room0_Livingroom: parent tableBig not placed"


def test_same_seed_same_layout(thesis, room_plan):
    rules, models = thesis
    plan = room_plan(5.0, 4.0)
    first = furnish_plan(plan, rules, models, np.random.default_rng(42))
    assert furnish_plan(plan, rules, models, np.random.default_rng(42)) == first
    other = furnish_plan(plan, rules, models, np.random.default_rng(43))
    assert other[0] != first[0]


def test_details_for_every_door_and_window_and_only_typed_rooms(room_plan, library):
    rules = parse_furniture_rules(
        "Room;Name;isAlongWall;isDetail\n"
        "Livingroom;doorOak;false;true\n"
        "Livingroom;shelf;true;false\n")
    models = models_for(rules, library)
    plan = room_plan(5.0, 4.0, doors=((0, 0.3, "start"), (1, 0.5, "end")),
                     windows=((2, 0.3), (2, 0.7), (3, 0.5)))
    furniture, _ = furnish_plan(plan, rules, models, np.random.default_rng(0))
    details = {item.name: item for item in furniture if item.is_detail}
    assert set(details) == {"door0", "door1", "window0", "window1", "window2"}
    door, window = details["door0"], details["window2"]
    assert door.model == "doorOak" and window.model == "window"
    assert door.size == pytest.approx((0.9, 2.1, 0.2)) and door.elevation == 0
    assert door.position == pytest.approx((plan.doors[0].position[0], 0.1))  # mid-wall
    assert door.front == pytest.approx((0, 1))  # towards the room it swings into
    assert window.size == pytest.approx((1.2, 1.2, 0.2)) and window.elevation == 0.9
    assert window.position == pytest.approx((0.1, 2.0)) and window.front == pytest.approx((1, 0))
    assert [i.name for i in furniture if not i.is_detail] == ["shelf"]
    untyped = plan.with_changes(rooms=(replace(plan.rooms[0], type=None),))
    furniture, _ = furnish_plan(untyped, rules, models, np.random.default_rng(0))
    assert all(item.is_detail for item in furniture)
    other_type = plan.with_changes(rooms=(replace(plan.rooms[0], type="Hall"),))
    furniture, diagnostics = furnish_plan(other_type, rules, models, np.random.default_rng(0))
    assert all(item.is_detail for item in furniture) and not diagnostics
    assert {i.model for i in furniture if i.name.startswith("door")} == {"door"}


def test_more_attempts_never_place_fewer_items(thesis, room_plan):
    rules, models = thesis
    plan = room_plan(4.2, 3.4)
    for seed in range(10):
        one, _ = furnish_plan(plan, rules, models, np.random.default_rng(seed), attempts=1)
        many, _ = furnish_plan(plan, rules, models, np.random.default_rng(seed), attempts=20)
        assert len(many) >= len(one)


def test_an_overfull_table_leaves_the_surplus_out_before_solving(room_plan, library, rules_dir):
    """Hundreds of rows for one small room: the items past twice the free floor are left
    out unsolved (so a table's cost grows linearly), the rest are solved as usual."""
    rows = "".join(f"Livingroom;plant{i};true\n" for i in range(400))
    rules = parse_furniture_rules("Room;Name;isInCorner\n" + rows)
    models = models_for(rules, library)
    plan = room_plan(3.0, 3.0)
    furniture, diagnostics = furnish_plan(plan, rules, models, np.random.default_rng(0))
    interior = plan.room(0).interior.area
    plant = models["plant0"][1]
    crowded = [d for d in diagnostics if "times the room's free floor" in d.message]
    solved = 400 - len(crowded)
    assert solved * plant[0] * plant[2] <= 2 * interior + plant[0] * plant[2]
    assert len(crowded) >= 400 - 2 * interior / (plant[0] * plant[2]) - 1
    assert len(furniture) + len(diagnostics) == 400 + sum(1 for i in furniture if i.is_detail)


# -- an attempt given up once it cannot beat the best changes nothing ---------------------

def _run_to_the_end(solve_once):
    """``solver._solve_once`` as it was before attempts were given up: every attempt
    places every item it can, whatever the best attempt so far placed."""
    def solve(site, specs, rng, iterations, room, groups, desk_layouts, to_beat=None):
        return solve_once(site, specs, rng, iterations, room, groups, desk_layouts)
    return solve


@pytest.mark.parametrize("kind, disorder, typed_floors",
                         [("house", 0.0, 30), ("house", 0.5, 30), ("office", 0.0, 5)])
def test_attempts_given_up_early_give_the_same_furniture(monkeypatch, library, kind, disorder,
                                                         typed_floors):
    """The solver passes over the rest of an attempt that can no longer place more items
    than its best one, and stops retrying a room whose best attempt left out only items
    the room itself blocks. Its floors must be those of running every attempt to the end
    (the later attempts of a room and its disorder draw from the same stream), and both
    shortcuts must be taken on the tidy house floors, or the comparison proves nothing."""
    passed_over = []
    pass_over = placement.Placer.pass_over
    monkeypatch.setattr(placement.Placer, "pass_over",
                        lambda self, spec: (passed_over.append(spec.name),
                                            pass_over(self, spec))[1])
    stopped = []
    unbeatable = solver._Unbeatable.__call__
    monkeypatch.setattr(solver._Unbeatable, "__call__",
                        lambda self, left_out: stopped.append(unbeatable(self, left_out))
                        or stopped[-1])
    floors = 0
    for seed in range(1, 46):
        floor = typed_hall_floor(kind, seed)
        if floor is None:
            continue
        typed, table = floor
        floors += 1
        furnished = []
        for shortcuts in (True, False):
            with monkeypatch.context() as patch:
                if not shortcuts:
                    patch.setattr(solver, "_solve_once", _run_to_the_end(solver._solve_once))
                    patch.setattr(solver._Unbeatable, "__call__", lambda self, left_out: False)
                furnished.append(furnish_floor(typed, table, seed=seed, disorder=disorder,
                                               library=library))
        shortcut, full = furnished
        assert shortcut.furniture == full.furniture, f"{kind} seed {seed}"
        assert shortcut.diagnostics == full.diagnostics, f"{kind} seed {seed}"
    assert floors >= typed_floors  # office typing fails on most of these floors
    if kind == "house":
        assert len(passed_over) > 20
        # a disordered room draws after its attempts, so it never stops early
        assert sum(stopped) >= 5 if disorder == 0 else not any(stopped)


def test_a_free_item_passed_over_takes_its_draws(monkeypatch, room_plan, library):
    """A free-standing item in an attempt given up takes the draws placing it would have
    taken: the wall table never fits, the chair after it stands freely, so every attempt
    after the first gives up before the chair, and the room's random stream after the
    room (what its disorder then draws from) must be that of running every attempt to
    the end."""
    rules = parse_furniture_rules("Room;Name;isAlongWall\n"
                                  "Livingroom;tableBig;true\n"
                                  "Livingroom;chair;false\n")
    site = RoomSite.from_plan(room_plan(1.8, 1.8), 0)
    specs = [ItemSpec(rule, *models_for(rules, library)[rule.name])
             for rule in rules.for_room("Livingroom")]
    passed_over = []
    pass_over = placement.Placer.pass_over
    monkeypatch.setattr(placement.Placer, "pass_over",
                        lambda self, spec: (passed_over.append(spec.name),
                                            pass_over(self, spec))[1])
    # the table never fits the room, which would stop the retries after the first attempt
    monkeypatch.setattr(solver._Unbeatable, "__call__", lambda self, left_out: False)
    outcomes = []
    for solve_once in (solver._solve_once, _run_to_the_end(solver._solve_once)):
        with monkeypatch.context() as patch:
            patch.setattr(solver, "_solve_once", solve_once)
            rng = np.random.default_rng(3)
            outcomes.append((solver.furnish_room(site, specs, rng), rng.bit_generator.state))
    assert outcomes[0] == outcomes[1]
    assert passed_over == ["chair"] * solver.PATIENCE
