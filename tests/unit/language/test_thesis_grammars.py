"""The grammars printed in the room-generation thesis parse as written (docs/language.md).

Fixtures in ``tests/data/thesis/`` are copied from the thesis text: Abbildung 6.5 (room
typing test; listing line numbers dropped) and Abbildung 6.12 (furniture test, with the
OCR artefacts ``let -->`` and ``repeated_split("T", ...)`` of the original).
"""

from __future__ import annotations

from pathlib import Path

import pytest

from cga import ast
from cga.parser import parse_file

DATA = Path(__file__).resolve().parents[2] / "data" / "thesis"
TYPING = DATA / "figure_6_5_typing.grammar"
FURNITURE = DATA / "figure_6_12_furniture.grammar"


def rule_map(grammar: ast.Grammar) -> dict[str, ast.Rule]:
    return {rule.predecessor.name: rule for rule in grammar.rules}


def only_step(rule: ast.Rule) -> ast.Step:
    assert isinstance(rule.body, ast.Sequence)
    (step,) = rule.body.steps
    return step


def values(grammar: ast.Grammar) -> dict[str, ast.Expr]:
    return {a.name: a.value for a in grammar.variables}


@pytest.mark.parametrize("path", [TYPING, FURNITURE], ids=["6.5", "6.12"])
def test_fixture_is_the_thesis_listing(path):
    text = path.read_text(encoding="utf-8")
    assert text.startswith("Variables:\n") and "\nRules:\n" in text
    assert "#Body --> component_split" in text


def test_figure_6_5_variables():
    grammar = parse_file(TYPING)
    variables = values(grammar)
    assert list(variables) == [
        "buildingHeight", "floorHeight", "segmentWidth", "doorRoomWidth", "doorRoomDepth",
        "dormerWidth", "dormerOffset", "dormerWidthOffset", "split", "wallWidth",
        "windowHigh", "windowWidth", "numWindows", "doorWidth", "doorHeight"]
    assert variables["split"].value == 4
    assert variables["doorWidth"].value == pytest.approx(0.09)
    door_room_width = variables["doorRoomWidth"]
    assert isinstance(door_room_width, ast.RandomRange)
    assert (door_room_width.low.value, door_room_width.high.value) == (0.25, 0.35)


def test_figure_6_5_rules():
    grammar = parse_file(TYPING)
    rules = rule_map(grammar)
    # the commented-out rules (#Body, #BaseFloorFacade) are not rules
    assert list(rules) == ["Lot", "Body", "FloorFacade", "BaseFloorFacade", "Floor1"]
    lot = only_step(rules["Lot"])
    assert (lot.op.name, [s.name for s in lot.successors]) == ("extrude", ["Body"])
    body = only_step(rules["Body"])
    assert body.op.name == "repeated_split"
    assert body.op.args[0].value.value == "Y"
    assert [s.name for s in body.successors] == ["BaseFloorFacade", "FloorFacade"]
    for name in ("FloorFacade", "BaseFloorFacade"):
        make_floor = only_step(rules[name]).op
        assert make_floor.name == "make_floor"
        assert len(make_floor.args) == 5
        window = make_floor.args[2].value
        assert isinstance(window, ast.TupleExpr)
        assert [item.name for item in window.items] == [
            "numWindows", "windowWidth", "windowHigh"]


def test_figure_6_5_type_rooms_path_and_brace_successor():
    rules = rule_map(parse_file(TYPING))
    step = only_step(rules["Floor1"])
    assert step.op.name == "type_rooms"
    (path,) = step.op.args
    written = r"D:\\RoomsProjekt\\pcgofrooms\\src\\main\\java\\projects\\cgashape" \
        r"\\room_creation\\processor\\TestConfig"
    assert path.value.value == written  # both backslashes of each pair are kept
    assert [s.name for s in step.successors] == ["FloorTyped1"]
    assert rules["Floor1"].span.line == 26


def test_figure_6_12_variables():
    variables = values(parse_file(FURNITURE))
    assert len(variables) == 17
    assert variables["split"].value == 0
    assert (variables["boldIteration"].value, variables["clearanceTries"].value) == (10, 20)


def test_figure_6_12_rules():
    rules = rule_map(parse_file(FURNITURE))
    assert list(rules) == ["let", "Body", "BaseFloorFacade", "Floor1", "FloorTyped1"]
    assert only_step(rules["let"]).op.name == "extrude"
    assert only_step(rules["Body"]).op.args[0].value.value == "T"
    type_rooms = only_step(rules["Floor1"])
    assert type_rooms.op.args[0].value.value == (
        "D:\\RoomsProjekt\\popRoom\\src\\main\\java\\project\\ogashape\\room_creation"
        "\\processor\\TestConfig.csv")
    assert [s.name for s in type_rooms.successors] == ["FloorTyped1"]


def test_figure_6_12_add_furniture_arguments():
    step = only_step(rule_map(parse_file(FURNITURE))["FloorTyped1"])
    assert step.op.name == "add_furniture"
    path, window, door_width, door_height, iterations, tries = step.op.args
    assert path.value.value.endswith("\\placement\\TestConfig.csv")
    assert [item.name for item in window.value.items] == [
        "wallWidth", "windowWidth", "windowHigh"]
    assert [a.value.name for a in (door_width, door_height, iterations, tries)] == [
        "doorWidth", "doorHeight", "boldIteration", "clearanceTries"]
    assert [s.name for s in step.successors] == ["FurnitureFloor"]
