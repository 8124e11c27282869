"""The passage rule: items keep a room's doors connected and most of its floor reachable."""

from __future__ import annotations

import numpy as np
import pytest
from shapely.geometry import box
from shapely.ops import unary_union

from furniture_checks import furniture_violations, passage_violations

from cga.errors import DerivationError, UsageError
from cga.authoring import furnish_floor
from cga.operations.furniture.clearance import OpeningStrip
from cga.operations.furniture.layout import ItemSpec, Layout, Pose
from cga.operations.furniture.passage import Blockage, Passage
from cga.operations.furniture.placement import Placer
from cga.operations.furniture.rules import FurnitureRule, parse_furniture_rules
from cga.operations.furniture.solver import furnish_plan

ROOM = box(0, 0, 5, 4)
BOTTOM = OpeningStrip("door 0", (1.0, 0.0), (1.0, 0.0), (0.0, 1.0), 0.9, 0.0)  # x 1.0..1.9
TOP = OpeningStrip("door 1", (3.9, 4.0), (-1.0, 0.0), (0.0, -1.0), 0.9, 0.0)  # x 3.0..3.9


def test_a_row_of_items_across_the_room_needs_a_gap_wider_than_the_robot():
    passage = Passage(ROOM, [BOTTOM, TOP], 0.6)
    row = [(0.0, 1.8, 2.0, 2.4)]
    assert passage.blockage(row, (2.55, 1.8, 5.0, 2.4)) == Blockage("door", "door 1")
    assert passage.blockage(row, (2.65, 1.8, 5.0, 2.4)) is None
    assert Passage(ROOM, [BOTTOM, TOP], 0.5).blockage(row, (2.55, 1.8, 5.0, 2.4)) is None


def test_the_door_named_is_the_one_cut_off_from_the_larger_part():
    passage = Passage(ROOM, [BOTTOM, TOP], 0.6)
    assert passage.blockage([], (0.0, 0.9, 5.0, 1.2)) == Blockage("door", "door 0")
    assert passage.blockage([], (0.0, 3.0, 5.0, 3.2)) == Blockage("door", "door 1")


def test_an_item_in_front_of_a_door_blocks_it():
    passage = Passage(ROOM, [BOTTOM, TOP], 0.6)
    assert passage.blockage([], (1.0, 0.0, 2.0, 0.5)) == Blockage("door", "door 0")


def test_walling_off_a_pocket():
    passage = Passage(ROOM, [BOTTOM], 0.6)  # one door: only pockets matter
    wall = [(2.0, 2.0, 2.6, 4.0)]  # with the candidate it closes off x 2.6..5, z 2..4
    assert passage.blockage(wall, (2.0, 1.4, 5.0, 2.0)) == Blockage("pocket", "26%")
    small = [(3.6, 2.6, 4.2, 4.0)]  # closes off x 4.2..5, z 2.6..4: too small to matter
    assert passage.blockage(small, (3.6, 2.0, 5.0, 2.6)) is None


def test_doors_apart_in_the_empty_room_are_not_held_together():
    necked = unary_union([box(0, 0, 2, 4), box(2, 1.75, 3, 2.25), box(3, 0, 5, 4)])
    left = OpeningStrip("door 0", (0.5, 0.0), (1.0, 0.0), (0.0, 1.0), 0.9, 0.0)
    right = OpeningStrip("door 1", (3.5, 0.0), (1.0, 0.0), (0.0, 1.0), 0.9, 0.0)
    passage = Passage(necked, [left, right], 0.6)
    assert passage.active
    assert passage.blockage([], (1.9, 1.6, 3.1, 2.4)) is None  # the neck is too narrow anyway
    assert Passage(necked, [left, right], 0.4).blockage([], (1.9, 1.6, 3.1, 2.4)) == \
        Blockage("door", "door 1")


def test_a_room_too_narrow_for_the_robot_is_not_tested():
    corridor = box(0, 0, 0.5, 4)
    door = OpeningStrip("door 0", (0.0, 1.0), (0.0, 1.0), (1.0, 0.0), 0.9, 0.0)
    assert not Passage(corridor, [door], 0.6).active


def test_the_verdict_does_not_depend_on_what_was_asked_before():
    rng = np.random.default_rng(3)
    shared = Passage(ROOM, [BOTTOM, TOP], 0.6)
    footprints = []
    for _ in range(60):
        x, z = rng.uniform(0, 4.2), rng.uniform(0, 3.4)
        footprints.append((x, z, x + rng.uniform(0.3, 0.8), z + rng.uniform(0.3, 0.6)))
    for k in range(60):
        obstacles = [footprints[i] for i in rng.choice(60, size=int(rng.integers(0, 6)),
                                                       replace=False)]
        candidate = footprints[k]
        expected = Passage(ROOM, [BOTTOM, TOP], 0.6).blockage(obstacles, candidate)
        assert shared.blockage(obstacles[::-1], candidate) == expected
        assert shared.blockage(obstacles, candidate) == expected



def test_a_set_made_from_a_tested_candidate_gets_the_verdicts_of_one_made_afresh(
        monkeypatch):
    """The solver adds most items right after testing them. The set with the item is then
    made from the candidate's own difference, pieces and verdict instead of a second GEOS
    difference, and every verdict on it is the one a fresh rule gives."""
    from shapely.geometry.base import BaseGeometry

    differences = []
    difference = BaseGeometry.difference
    monkeypatch.setattr(BaseGeometry, "difference",
                        lambda self, *args: differences.append(1) or difference(self, *args))
    rng = np.random.default_rng(11)
    shared = Passage(ROOM, [BOTTOM, TOP], 0.6)
    placed: list = []
    tests = 0
    for _ in range(12):  # below the count from which candidates are updated locally
        x, z = rng.uniform(0, 4.5), rng.uniform(0, 3.6)
        candidate = (x, z, x + rng.uniform(0.2, 0.5), z + rng.uniform(0.2, 0.4))
        verdict = shared.blockage(placed, candidate)
        tests += 1
        with monkeypatch.context() as fresh_rule:
            fresh_rule.setattr(BaseGeometry, "difference", difference)
            assert verdict == Passage(ROOM, [BOTTOM, TOP], 0.6).blockage(placed, candidate)
        if verdict is None:
            placed.append(candidate)
            probe = (0.0, 0.0, 0.01, 0.01)  # asks for the set with the candidate
            tests += 1
            with monkeypatch.context() as fresh_rule:
                fresh_rule.setattr(BaseGeometry, "difference", difference)
                expected = Passage(ROOM, [BOTTOM, TOP], 0.6).blockage(placed, probe)
            assert shared.blockage(placed, probe) == expected
    assert len(placed) >= 6
    assert len(differences) <= tests  # one difference per test, none to make the sets


def test_a_candidate_asked_again_is_looked_up_for_its_own_obstacles(monkeypatch):
    passage = Passage(ROOM, [BOTTOM, TOP], 0.6)
    left, right = (0.0, 1.8, 2.6, 2.4), (2.9, 1.8, 5.0, 2.4)  # a row with a 0.3 m gap
    computed = []
    verdict = Passage._candidate_verdict
    monkeypatch.setattr(Passage, "_candidate_verdict",
                        lambda self, *args: computed.append(1) or verdict(self, *args))
    assert passage.blockage([], left) is None
    assert passage.blockage([], left) is None
    assert len(computed) == 1
    assert passage.blockage([right], left) == Blockage("door", "door 1")
    assert passage.blockage([right], left) == Blockage("door", "door 1")
    assert passage.blockage([], left) is None
    assert len(computed) == 2

def test_a_candidate_asked_again_sees_an_item_added_at_the_door():
    room = box(0, 0, 6, 4)
    door = OpeningStrip("door 0", (2.0, 0.0), (1.0, 0.0), (0.0, 1.0), 0.9, 0.0)  # x 2.0..2.9
    padding = [(0.01 * i, 3.9, 0.01 * i + 0.05, 3.95) for i in range(16)]  # in a corner
    across = (3.5, 0.6, 3.6, 4.0)  # walls off the right third, away from the door
    at_door = (2.3, 0.0, 2.6, 0.2)  # covers the door's approach
    passage = Passage(room, [door], 0.6)
    before = passage.blockage(padding, across)
    after = passage.blockage(padding + [at_door], across)
    assert before is not None and before.kind == "pocket" and before.what != "100%"
    assert after == Blockage("pocket", "100%")  # nothing reached any more
    assert after == Passage(room, [door], 0.6).blockage(padding + [at_door], across)


# -- in the layout and the placer ----------------------------------------------------------

def wardrobe(**rule) -> ItemSpec:
    return ItemSpec(FurnitureRule(room="Bedroom", name="wardrobe", is_along_wall=True, **rule),
                    "wardrobe", (1.0, 2.0, 0.625))


def test_the_layout_reports_a_blocked_passage_as_a_conflict():
    layout = Layout(ROOM, passage=Passage(ROOM, [BOTTOM, TOP], 0.6))
    layout.add(ItemSpec(FurnitureRule(room="Bedroom", name="bed"), "bed", (3.9, 1.0, 0.6)),
               Pose(1.95, 2.1, 0))  # x 0..3.9, z 1.8..2.4
    (conflict,) = layout.conflicts(wardrobe(), Pose(4.6875, 2.1, 1))  # 0.475 m from the bed
    assert conflict.describe() == "would block the passage to door 1"
    assert layout.fits(wardrobe(), Pose(2.0, 3.6875, 0))  # against the top wall instead
    rug = ItemSpec(FurnitureRule(room="Bedroom", name="rug", non_collision=True), "rug",
                   (5.0, 0.01, 0.6))
    assert layout.fits(rug, Pose(2.5, 2.1, 0))  # rugs do not block


def test_a_wall_item_moves_on_when_its_nearest_spot_cuts_the_doors_apart():
    room = box(0, 0, 5, 1.1)  # a 1.1 m deep strip, two doors in its long side
    doors = [OpeningStrip("door 0", (0.3, 0.0), (1.0, 0.0), (0.0, 1.0), 0.9, 0.0),
             OpeningStrip("door 1", (1.8, 0.0), (1.0, 0.0), (0.0, 1.0), 0.9, 0.0)]
    bands = [box(0.3, 0.0, 1.2, 0.4), box(1.8, 0.0, 2.7, 0.4)]
    for width, cut in ((0.0, True), (0.6, False)):
        layout = Layout(room, passage=Passage(room, doors, width) if width else None)
        placer = Placer(layout, [wardrobe()], np.random.default_rng(0))
        assert placer.place(wardrobe(), (1.5, 0.8)) is None
        pose = layout.pose("wardrobe")
        if cut:  # the spot nearest the start, between the doors
            assert (pose.x, pose.z, pose.rotation) == pytest.approx((1.5, 0.7875, 0))
        b = wardrobe().parts(pose.rotation)[0].box
        footprint = box(pose.x + b[0], pose.z + b[1], pose.x + b[2], pose.z + b[3])
        free = room.difference(footprint).buffer(-0.3)  # where a round robot's centre fits
        joined = any(all(piece.intersects(band) for band in bands)
                     for piece in getattr(free, "geoms", [free]))
        assert joined is not cut


# -- the solver, the operation and the independent validator -------------------------------

CORRIDOR_RULES = ("Room;Name;isAlongWall;clearanceFront\n"
                  "Bedroom;wardrobe;true;0\n")


@pytest.fixture
def corridor(room_plan, library, tmp_path):
    """A 1.1 m wide room with a door at each end: a wardrobe (0.625 m deep) against
    either long wall leaves 0.475 m, too little for a robot between the doors."""
    plan = room_plan(1.5, 5.0, room_type="Bedroom", doors=((0, 0.5, "start"), (2, 0.5, "start")),
                     windows=())
    rules = parse_furniture_rules(CORRIDOR_RULES)
    models = {"wardrobe": (library.get("wardrobe").name, library.get("wardrobe").size)}
    path = tmp_path / "corridor.csv"
    path.write_text(CORRIDOR_RULES)
    return plan, rules, models, path


def test_without_the_rule_the_wardrobe_cuts_the_corridor(corridor):
    plan, rules, models, path = corridor
    for seed in range(10):
        furniture, diagnostics = furnish_plan(plan, rules, models, np.random.default_rng(seed),
                                              passage_width=0)
        assert not diagnostics and any(i.name == "wardrobe" for i in furniture)
        furnished = plan.with_changes(furniture=furniture)
        assert furniture_violations(furnished, path, passage_width=0) == []
        assert passage_violations(furnished, 0.6) == ["room 0: furniture cuts doors [0] from [1] apart"]


def test_with_the_rule_the_wardrobe_is_left_out_and_says_why(corridor):
    plan, rules, models, path = corridor
    for seed in range(10):
        furniture, diagnostics = furnish_plan(plan, rules, models, np.random.default_rng(seed))
        assert not any(i.name == "wardrobe" for i in furniture)
        (diagnostic,) = diagnostics
        assert diagnostic.message.startswith("wardrobe left out of room0_Bedroom: ")
        assert "would block the passage to door" in diagnostic.message
        assert furniture_violations(plan.with_changes(furniture=furniture), path) == []


def test_a_narrower_robot_lets_the_wardrobe_in(corridor):
    plan, rules, models, _ = corridor
    furniture, diagnostics = furnish_plan(plan, rules, models, np.random.default_rng(0),
                                          passage_width=0.45)
    assert not diagnostics and any(i.name == "wardrobe" for i in furniture)


def test_passage_width_must_not_be_negative(room_plan, tmp_path):
    with pytest.raises(UsageError, match="passage_width"):
        furnish_floor(room_plan(), "furniture_thesis.csv", passage_width=-0.1)
    from cga.evaluator import derive
    from cga.parser import parse
    (tmp_path / "types.csv").write_text(
        "Type;Size;Prob;Neighbours;isOutsideConnected;appearance;additionRoom\n"
        "Livingroom;1;1;Livingroom;true;1;0\n")
    text = ("Lot: rectangle(5, 4)\nRules:\nLot --> extrude(3) S\n"
            "S --> make_floor(0, 0.2, 1>1.2>1.2, 0.9, 2.1) F\n"
            'F --> type_rooms("types.csv") T\n'
            'T --> add_furniture("furniture_thesis.csv", passage_width=-1) X\n')
    with pytest.raises(DerivationError, match="passage_width must not be negative"):
        derive(parse(text, str(tmp_path / "g.grammar")), base_dir=tmp_path)
