"""The grammar operation: arguments, the plan it needs, units, caching, its one child."""

import math

import numpy as np
import pytest
from shapely.geometry import box

from cga.errors import DerivationError, NoSolutionError, RuleTableError
from cga.model import OUTSIDE
from cga.registry import OperationRegistry
from cga.operation import OperationContext
from cga.operations.floorplan.rectangles import plan_from_rectangles
from cga.operations.type_rooms import TypeRooms
from cga.resources import resolve_resource
from cga.shape import Mass, Shape

HEADER = "Type;Size;Prob;Neighbours;isOutsideConnected;appearance;additionRoom"
THREE = [(0, 0, 6, 10), (6, 0, 14, 5), (6, 5, 14, 10)]


def context(tmp_path, units=1.0, strict=False, seed=0):
    return OperationContext(
        rng=np.random.default_rng(seed), units=units,
        resolve=lambda path, kind="rules": resolve_resource(path, kind, base_dir=tmp_path),
        report=lambda d: None, span=None, successor_count=1, strict=strict)


def floor_shape(plan=None):
    mass = Mass(footprint=box(0, 0, 14, 10), base=0.0, height=3.0)
    return Shape(symbol="Floor", path=("Floor",), scope=mass.scope(), geometry=mass,
                 plan=plan if plan is not None else plan_from_rectangles(THREE))


def args(rules="rules.csv", **kw):
    return {"rules": rules, "strict": False, "door_position": "random", "door_state": "closed",
            **kw}


def write(tmp_path, *rows, name="rules.csv"):
    (tmp_path / name).write_text("\n".join([HEADER, *rows]) + "\n")


def test_registry_entry_and_signature():
    op = OperationRegistry()["type_rooms"]
    assert isinstance(op, TypeRooms)
    assert op.signature() == ("type_rooms(rules, strict=False, door_position='random', "
                              "door_state='closed')")
    assert [p.keyword_only for p in op.params] == [False, True, True, True]
    assert op.params[0].kind == "path"


def test_types_the_plan_and_returns_one_child_with_it(tmp_path):
    write(tmp_path, "Livingroom;20;1;Kitchen;1;1;0", "Kitchen;10;0;Livingroom;0;2;0")
    shape = floor_shape()
    (child,) = TypeRooms().apply(shape, args(), context(tmp_path))
    assert child.successor == 0 and child.geometry is shape.geometry and child.scope is shape.scope
    plan = child.plan
    assert sorted(r.type for r in plan.rooms) == ["Kitchen", "Kitchen", "Livingroom"]
    assert plan.front_door() is not None and plan.room_graph.has_node(OUTSIDE)
    assert shape.plan.rooms[0].type is None and not shape.plan.doors  # input untouched


def test_shipped_table_is_found_by_name(tmp_path):
    corridor = plan_from_rectangles([(0, 0, 6, 4), (6, 0, 14, 4), (0, 4, 14, 6), (0, 6, 2.2, 10),
                                     (2.2, 6, 8, 10), (8, 6, 14, 10)], circulation=[2])
    (child,) = TypeRooms().apply(floor_shape(corridor), args("office_types.csv"), context(tmp_path))
    assert child.plan.room(2).type == "Corridor" and child.plan.room(2).circulation
    assert {r.type for r in child.plan.rooms} >= {"Office", "Meetingroom", "Bathroom"}
    assert child.plan.front_door().swing_room == 2


def test_size_is_in_grammar_units_squared(tmp_path):
    write(tmp_path, "Livingroom;0.5;1;Kitchen;1;1;0", "Kitchen;0.45;0;Livingroom;0;1;0")
    # units 10: Livingroom ≥ 50 m², Kitchen ≥ 45 m²: only the 60 m² room takes either
    with pytest.raises(NoSolutionError, match="45.0 m²"):
        TypeRooms().apply(floor_shape(), args(), context(tmp_path, units=10.0))
    (child,) = TypeRooms().apply(floor_shape(), args(), context(tmp_path, units=1.0))
    assert {"Livingroom", "Kitchen"} <= {r.type for r in child.plan.rooms}


def test_needs_a_floor_plan(tmp_path):
    with pytest.raises(DerivationError, match="type_rooms needs a floor made by make_floor"):
        TypeRooms().apply(floor_shape().derive(plan=None), args(), context(tmp_path))


def test_door_position_is_validated(tmp_path):
    write(tmp_path, "Livingroom;1;1;Kitchen;1;1;0", "Kitchen;1;0;Livingroom;0;1;0")
    with pytest.raises(DerivationError, match="door_position must be one of 'center', 'random'"):
        TypeRooms().apply(floor_shape(), args(door_position="middle"), context(tmp_path))
    (child,) = TypeRooms().apply(floor_shape(), args(door_position="CENTER"), context(tmp_path))
    assert child.plan.doors


def test_rule_table_errors_reach_the_user(tmp_path):
    write(tmp_path, "Livingroom;1;1;Kitchn;1;1;0", "Kitchen;1;0;Livingroom;0;1;0")
    with pytest.raises(RuleTableError, match="did you mean 'Kitchen'"):
        TypeRooms().apply(floor_shape(), args(), context(tmp_path))


def test_table_is_parsed_once_per_build(tmp_path):
    write(tmp_path, "Livingroom;1;1;Kitchen;1;1;0", "Kitchen;1;0;Livingroom;0;1;0")
    ctx = context(tmp_path)
    TypeRooms().apply(floor_shape(), args(), ctx)
    (tmp_path / "rules.csv").write_text("garbage")
    TypeRooms().apply(floor_shape(), args(), ctx)  # cached: the file is not read again
    with pytest.raises(RuleTableError):
        TypeRooms().apply(floor_shape(), args(), context(tmp_path))


def test_strict_from_the_argument_or_the_build(tmp_path):
    # the Commonroom leftover is listed by nobody: reachable only by an extra door
    write(tmp_path, "Livingroom;1;1;Kitchen;1;1;0", "Kitchen;1;0;Livingroom;0;1;0")
    plan = plan_from_rectangles([(0, 0, 5, 5), (5, 0, 10, 5), (10, 0, 15, 5)])
    relaxed = TypeRooms().apply(floor_shape(plan), args(), context(tmp_path))[0].plan
    assert any(d.reason == "reachability" for d in relaxed.doors)
    with pytest.raises(NoSolutionError, match="strict"):
        TypeRooms().apply(floor_shape(plan), args(strict=True), context(tmp_path))
    with pytest.raises(NoSolutionError, match="strict"):
        TypeRooms().apply(floor_shape(plan), args(), context(tmp_path, strict=True))


def test_diagnostics_are_recorded_on_the_plan(tmp_path):
    write(tmp_path, "Livingroom;1;1;Kitchen;1;1;0", "Kitchen;1;0;Livingroom;0;1;0")
    plan = plan_from_rectangles([(0, 0, 5, 5), (5, 0, 10, 5), (10, 0, 15, 5)], index=0)
    (child,) = TypeRooms().apply(floor_shape(plan), args(), context(tmp_path))
    stages = {d.stage for d in child.plan.diagnostics}
    assert stages == {"type_rooms"}
    assert all(d.floor == 0 for d in child.plan.diagnostics)


def test_door_state_is_validated_and_sets_every_door(tmp_path):
    write(tmp_path, "Livingroom;20;1;Kitchen;1;1;0", "Kitchen;10;0;Livingroom;0;2;0")
    with pytest.raises(DerivationError, match="door_state must be one of 'closed', 'open', "
                                              "'ajar', 'random'"):
        TypeRooms().apply(floor_shape(), args(door_state="shut"), context(tmp_path))
    (child,) = TypeRooms().apply(floor_shape(), args(door_state="OPEN"), context(tmp_path))
    doors = child.plan.doors
    assert doors and {(d.state, round(math.degrees(d.angle), 6)) for d in doors} == {("open", 90.0)}
    graph = child.plan.room_graph
    assert {graph.edges[d.rooms]["state"] for d in doors} == {"open"}


def test_rooms_too_deep_for_a_max_size_name_what_makes_them_smaller(tmp_path):
    """A 20 m deep house with a spine: every room is 9.1 m deep and at least 2.4 m wide,
    so none is as small as the bathroom's 9 m²; no re-draw can help, and the error says
    which make_floor options would."""
    from cga.pipeline import build

    grammar = tmp_path / "deep.grammar"
    grammar.write_text(
        "units = 1;\nLot: rectangle(25, 20)\nRules:\nLot --> extrude(3) Storey\n"
        "Storey --> make_floor(20, 0.2, 2>1.2>1.3, 0.9, 2.1, corridor = \"spine\", "
        "corridor_width = 1.8, min_room_width = 2.4, min_room_area = 5) Floor\n"
        "Floor --> type_rooms(\"house_types.csv\") Typed\n", encoding="utf-8")
    with pytest.raises(NoSolutionError) as info:
        build(grammar, seed=0, formats=(), physics=False, quiet=True)
    (hint,) = [r for r in info.value.reasons if r.startswith("every room the floor was cut into")]
    assert "Bathroom (at most 9.0 m²)" in hint and "min_room_width" in hint
    assert "corridor_position" in hint
