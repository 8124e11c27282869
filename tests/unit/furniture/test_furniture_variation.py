"""Furniture variation (``sizeJitter``) and disorder: table columns, seeded sizes, free
yaw in the model and the meshing, disturbed poses that keep every guarantee."""

from __future__ import annotations

import math

import numpy as np
import pytest

from cga.authoring import furnish_floor
from cga.errors import RuleTableError
from cga.meshing.items import item_node
from cga.model import FurnitureItem, front_vector
from cga.operations.furniture.disorder import MAX_SHIFT, MAX_YAW
from cga.operations.furniture.rules import parse_furniture_rules

from furniture_checks import furniture_violations

HEADER = "Room;Name;isAlongWall;hasPair;PairWith;canBeAround;clearanceFront;clearanceBack"


def parse(*rows: str, header: str = HEADER):
    return parse_furniture_rules("\n".join((header, *rows)) + "\n", file="t.csv")


def error_of(*rows: str, header: str = HEADER) -> RuleTableError:
    with pytest.raises(RuleTableError) as caught:
        parse(*rows, header=header)
    return caught.value


# -- the table -------------------------------------------------------------------------
def test_new_columns_are_optional_and_default_off(rules_dir):
    (sofa,) = parse("Livingroom;sofa;true;false;;false;0.4;0").rules
    assert sofa.size_jitter == (0.0, 0.0, 0.0) and sofa.is_movable is None
    for name in ("house", "office", "thesis", "usar"):
        text = (rules_dir / f"furniture_{name}.csv").read_text(encoding="utf-8")
        parse_furniture_rules(text)  # every shipped table still loads


def test_size_jitter_takes_one_or_three_fractions():
    header = HEADER + ";sizeJitter;isMovable"
    one, three, movable = parse("Office;desk;true;false;;false;0;0;0.1;",
                                "Office;shelf;true;false;;false;0;0;0.1 0 0.05;false",
                                "Office;plant;false;false;;false;0;0;;true",
                                header=header).rules
    assert one.size_jitter == (0.1, 0.1, 0.1) and three.size_jitter == (0.1, 0.0, 0.05)
    assert (one.movable("desk"), one.movable("officechair"), three.movable("armchair"),
            movable.movable("plant")) == (False, True, False, True)


@pytest.mark.parametrize("cell, message", [
    ("wide", "expected a fraction, got 'wide'"),
    ("0.1 0.2", "one fraction or three"),
    ("0.7", "in 0..0.5"),
    ("-0.1", "in 0..0.5"),
])
def test_bad_size_jitter_names_row_and_column(cell, message):
    error = error_of("Office;desk;true;false;;false;0;0;0.1",
                     f"Office;shelf;true;false;;false;0;0;{cell}",
                     header=HEADER + ";sizeJitter")
    assert message in str(error)
    assert "t.csv, row 3, column 'sizeJitter'" in str(error)


def test_bad_movable_cell_names_the_column():
    assert "column 'isMovable'" in str(error_of("Office;desk;true;false;;false;0;0;maybe",
                                                header=HEADER + ";isMovable"))


# -- sizes -----------------------------------------------------------------------------
def jitter_table(tmp_path, jitter: str) -> str:
    path = tmp_path / "jitter.csv"
    path.write_text(HEADER + ";sizeJitter\n"
                    f"Livingroom;sofa;true;false;;false;0.4;0;{jitter}\n"
                    "Livingroom;bookshelf;true;false;;false;0.4;0;\n", encoding="utf-8")
    return str(path)


def sizes(plan) -> dict[str, tuple[float, float, float]]:
    return {i.name: i.size for i in plan.furniture if not i.is_detail}


def test_jitter_stays_in_its_range_and_follows_the_seed(room_plan, library, tmp_path):
    table = jitter_table(tmp_path, "0.1 0 0.2")
    own = library.get("sofa").size
    seen = set()
    for seed in range(30):
        got = sizes(furnish_floor(room_plan(6, 5), table, seed=seed, library=library))
        w, h, d = got["sofa"]
        assert own[0] * 0.9 - 1e-12 <= w <= own[0] * 1.1 + 1e-12
        assert h == own[1]
        assert own[2] * 0.8 - 1e-12 <= d <= own[2] * 1.2 + 1e-12
        assert got["bookshelf"] == library.get("bookshelf").size  # no jitter: model size
        seen.add(got["sofa"])
        again = sizes(furnish_floor(room_plan(6, 5), table, seed=seed, library=library))
        assert again == got
    assert len(seen) == 30


def test_zero_jitter_changes_nothing(room_plan, library, tmp_path):
    for seed in range(5):
        plain = furnish_floor(room_plan(6, 5), jitter_table(tmp_path, ""), seed=seed,
                              library=library)
        zero = furnish_floor(room_plan(6, 5), jitter_table(tmp_path, "0"), seed=seed,
                             library=library)
        assert plain.furniture == zero.furniture


def test_collision_parts_take_the_jittered_size(room_plan, library, tmp_path):
    plan = furnish_floor(room_plan(6, 5), jitter_table(tmp_path, "0.2"), seed=4,
                         library=library)
    sofa = next(i for i in plan.furniture if i.name == "sofa")
    assert sofa.size != library.get("sofa").size
    node = item_node(sofa, plan, library)
    parts = np.vstack([p.vertices for p in node.parts])
    bounds = np.array([parts.min(axis=0), parts.max(axis=0)])
    assert bounds == pytest.approx(node.mesh.bounds)
    extent = node.mesh.bounds[1] - node.mesh.bounds[0]
    w, h, d = sofa.size
    assert extent == pytest.approx((d, h, w) if sofa.rotation % 2 else (w, h, d))
    footprint = sofa.footprint().bounds
    assert (footprint[0], footprint[2]) == pytest.approx((bounds[0][0], bounds[1][0]))
    assert (footprint[1], footprint[3]) == pytest.approx((bounds[0][2], bounds[1][2]))


# -- free yaw --------------------------------------------------------------------------
def test_a_quarter_turn_of_yaw_is_a_quarter_turn(library):
    size = library.get("desk").size
    turned = FurnitureItem("desk", "desk", 0, (1.0, 2.0), 0, size, yaw=math.pi / 2)
    quarter = FurnitureItem("desk", "desk", 0, (1.0, 2.0), 1, size)
    assert turned.footprint().symmetric_difference(quarter.footprint()).area < 1e-12
    assert turned.front == pytest.approx(quarter.front)
    assert front_vector(0, 0.3) == pytest.approx((-math.sin(0.3), -math.cos(0.3)))


def test_meshing_turns_the_model_by_its_yaw(room_plan, library):
    plan = room_plan(6, 5)
    size = library.get("desk").size
    item = FurnitureItem("desk", "desk", 0, (3.0, 2.5), 0, size, yaw=0.4)
    node = item_node(item, plan, library)
    corners = np.asarray(item.footprint().exterior.coords)
    lo, hi = node.mesh.bounds
    assert (lo[0], lo[2]) == pytest.approx(corners.min(axis=0), abs=1e-9)
    assert (hi[0], hi[2]) == pytest.approx(corners.max(axis=0), abs=1e-9)


# -- disorder --------------------------------------------------------------------------
def meeting_room(room_plan):
    return room_plan(6, 5, room_type="Meetingroom")


def chair_yaws(plan) -> list[float]:
    return [abs(i.yaw) for i in plan.furniture if i.model.endswith("chair")]


def test_disorder_keeps_every_guarantee(room_plan, library, rules_dir):
    table = rules_dir / "furniture_office.csv"
    for seed in range(8):
        for kind in ("Meetingroom", "Office"):
            plan = furnish_floor(room_plan(6, 5, room_type=kind), table, seed=seed,
                                 disorder=1.0, library=library)
            assert furniture_violations(plan, table, max_yaw=MAX_YAW) == [], (seed, kind)


def test_disorder_moves_only_movable_items_and_within_bounds(room_plan, library, rules_dir):
    table = rules_dir / "furniture_office.csv"
    for seed in range(5):
        tidy = furnish_floor(meeting_room(room_plan), table, seed=seed, library=library)
        messy = furnish_floor(meeting_room(room_plan), table, seed=seed, disorder=1.0,
                              library=library)
        before = {i.name: i for i in tidy.furniture}
        assert [i.name for i in messy.furniture] == list(before)
        for item in messy.furniture:
            old = before[item.name]
            if not item.model.endswith("chair"):
                assert item == old
                continue
            assert abs(item.yaw) <= MAX_YAW and item.rotation == old.rotation
            assert math.dist(item.position, old.position) <= MAX_SHIFT + 1e-9


def test_mean_chair_yaw_rises_with_disorder(room_plan, library, rules_dir):
    table = rules_dir / "furniture_office.csv"
    means = []
    for disorder in (0.0, 0.4, 1.0):
        yaws = [y for seed in range(6) for y in chair_yaws(furnish_floor(
            meeting_room(room_plan), table, seed=seed, disorder=disorder, library=library))]
        means.append(float(np.mean(yaws)))
    assert means[0] == 0.0 < means[1] < means[2]


def test_disorder_outside_the_unit_interval_is_refused(room_plan, library, rules_dir):
    from cga.errors import UsageError

    with pytest.raises(UsageError, match=r"disorder must be in \[0, 1\], got 1.5"):
        furnish_floor(meeting_room(room_plan), rules_dir / "furniture_office.csv",
                      disorder=1.5, library=library)


def test_a_row_sets_its_own_disorder(room_plan, library, rules_dir, tmp_path):
    text = (rules_dir / "furniture_office.csv").read_text(encoding="utf-8").splitlines()
    comments = [line for line in text if line.startswith("#")]  # the `# units: m` line
    text = [line for line in text if not line.startswith("#")]
    header, rows = "\n".join([*comments, text[0] + ";disorder"]), text[1:]
    rows = [r + (";1" if r.split(";")[:2] == ["Meetingroom", "chair2"] else ";")
            for r in rows]
    table = tmp_path / "office.csv"
    table.write_text("\n".join([header, *rows]) + "\n", encoding="utf-8")
    turned = set()
    for seed in range(4):
        plan = furnish_floor(meeting_room(room_plan), table, seed=seed, library=library)
        turned |= {i.name for i in plan.furniture if i.yaw}
        assert furniture_violations(plan, table, max_yaw=MAX_YAW) == []
    assert turned == {"chair2"}


def test_a_row_disorder_above_one_names_row_and_column():
    error = error_of("Office;chair;false;false;;false;0;0;1.5", header=HEADER + ";disorder")
    assert "disorder is a number in 0..1, got '1.5'" in str(error)
    assert "row 2, column 'disorder'" in str(error)
