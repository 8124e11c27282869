"""The add_furniture operation in grammars: arguments, errors, models, units, caching."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from furniture_checks import furniture_violations

from cga.errors import DerivationError, RuleTableError
from cga.evaluator import derive
from cga.authoring import furnish_floor
from cga.operations.add_furniture import LIBRARY_CACHE_KEY, AddFurniture
from cga.operation import OperationContext
from cga.parser import parse
from cga.resources import resolve_resource

TYPES = ("Type;Size;Prob;Neighbours;isOutsideConnected;appearance;additionRoom\n"
         "Livingroom;1;1;Livingroom;true;1;0\n")
HEADER = "Room;Name;isInCorner;isAlongWall;clearanceBack\n"
BOX_OBJ = "".join(f"v {x} {y} {z}\n" for x in (-0.3, 0.3) for y in (0, 0.5) for z in (-0.2, 0.2)) + \
    "f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n"


def grammar(call: str, *, lot: str = "rectangle(5, 4)", units: str = "1") -> str:
    return (f"units = {units};\nLot: {lot}\nRules:\n"
            "Lot --> extrude(3) Storey\n"
            "Storey --> make_floor(0, 0.2, 1>1.2>1.2, 0.9, 2.1) Floor\n"
            'Floor --> type_rooms("types.csv") Typed\n'
            f"Typed --> {call} Furnished\n")


def furnished(tmp_path: Path, text: str, seed: int = 0):
    (tmp_path / "types.csv").write_text(TYPES)
    path = tmp_path / "house.grammar"
    path.write_text(text)
    derivation = derive(parse(text, str(path)), seed=seed, base_dir=tmp_path)
    (shape,) = derivation.terminals
    return shape.plan


def test_thesis_call_furnishes_the_living_room(tmp_path, rules_dir):
    plan = furnished(tmp_path, grammar(
        'add_furniture("furniture_thesis.csv", 0.2>1.2>1.2, 0.9, 2.1, 10, 20)'))
    names = {item.name for item in plan.furniture}
    assert {"tableBig", "chair", "sofa", "tvboard", "SofaTable", "FloorLamp"} <= names
    assert sum(item.name.startswith("window") for item in plan.furniture) == len(plan.windows)
    assert sum(item.name.startswith("door") for item in plan.furniture) == len(plan.doors) == 1
    assert furniture_violations(plan, rules_dir / "furniture_thesis.csv") == []


def test_keywords_and_defaults(tmp_path):
    plan = furnished(tmp_path, grammar(
        'add_furniture("furniture_house.csv", steeringIterations=3, clearanceTries=2)'))
    assert any(item.name == "sofa" for item in plan.furniture)


def test_same_seed_same_furniture(tmp_path):
    text = grammar('add_furniture("furniture_thesis.csv")')
    assert furnished(tmp_path, text, seed=4).furniture == furnished(tmp_path, text, seed=4).furniture


def test_without_a_floor_plan_is_an_error(tmp_path):
    text = 'Lot: rectangle(5, 4)\nRules:\nLot --> add_furniture("furniture_house.csv") X\n'
    with pytest.raises(DerivationError) as caught:
        derive(parse(text, "g.grammar"), base_dir=tmp_path)
    assert "no floor plan" in str(caught.value) and "type_rooms" in str(caught.value)
    assert caught.value.span.line == 3


def test_untyped_rooms_are_an_error(tmp_path):
    text = ("Lot: rectangle(5, 4)\nRules:\nLot --> extrude(3) S\n"
            "S --> make_floor(0, 0.2, 1>1.2>1.2, 0.9, 2.1) F\n"
            'F --> add_furniture("furniture_house.csv") X\n')
    with pytest.raises(DerivationError) as caught:
        derive(parse(text, "g.grammar"), base_dir=tmp_path)
    assert "no room of this floor has a type" in str(caught.value)


def test_a_missing_model_names_row_and_column(tmp_path):
    (tmp_path / "mine.csv").write_text(HEADER + "Livingroom;shelf;false;true;0\n"
                                       "Livingroom;unicorn;false;true;0\n")
    with pytest.raises(RuleTableError) as caught:
        furnished(tmp_path, grammar('add_furniture("mine.csv")'))
    assert caught.value.row == 3 and caught.value.column == "Name"
    assert "'unicorn'" in str(caught.value) and str(tmp_path) in str(caught.value)


def test_models_next_to_the_grammar_are_found(tmp_path):
    (tmp_path / "models").mkdir()
    (tmp_path / "models" / "unicorn.obj").write_text(BOX_OBJ)
    (tmp_path / "mine.csv").write_text(HEADER + "Livingroom;unicorn;true;false;0\n")
    plan = furnished(tmp_path, grammar('add_furniture("mine.csv")'))
    (unicorn,) = [item for item in plan.furniture if item.name == "unicorn"]
    assert unicorn.size == pytest.approx((0.6, 0.5, 0.4))


def test_table_distances_are_in_grammar_units(tmp_path):
    (tmp_path / "mine.csv").write_text(HEADER + "Livingroom;shelf;false;true;0.15\n")
    plan = furnished(tmp_path, grammar('add_furniture("mine.csv")', lot="rectangle(2.5, 2)",
                                       units="2"))
    (shelf,) = [item for item in plan.furniture if item.name == "shelf"]
    interior = plan.rooms[0].interior.bounds
    bounds = shelf.footprint().bounds
    gaps = [bounds[0] - interior[0], bounds[1] - interior[1], interior[2] - bounds[2],
            interior[3] - bounds[3]]
    assert min(gaps) == pytest.approx(0.3)  # 0.15 units × 2 m per unit


def test_the_model_library_is_shared_through_the_build_cache(tmp_path, room_plan):
    from cga.shape import Mass, Shape
    from shapely.geometry import box

    mass = Mass(box(0, 0, 5, 4), 0.0, 3.0)
    shape = Shape("Typed", ("Typed",), mass.scope(), mass, plan=room_plan(5, 4))
    cache: dict = {}
    ctx = OperationContext(rng=np.random.default_rng(0), units=1.0,
                           resolve=lambda p, k="rules": resolve_resource(p, k, base_dir=tmp_path),
                           report=lambda d: None, span=None, successor_count=1, cache=cache,
                           base_dir=tmp_path)
    args = {"rules": "furniture_thesis.csv", "openings": None, "doorWidth": None,
            "doorHeight": None, "steeringIterations": 10, "clearanceTries": 20,
            "passage_width": 0.6, "disorder": 0.0}
    (first,) = AddFurniture().apply(shape, args, ctx)
    library = cache[LIBRARY_CACHE_KEY]
    assert library.search_dirs[:2] == (tmp_path, tmp_path / "models")
    (second,) = AddFurniture().apply(shape, args, ctx)
    assert cache[LIBRARY_CACHE_KEY] is library
    assert first.plan.furniture and second.plan.furniture


def test_furnish_floor_for_rule_authors():
    from cga.authoring import floor_from_rectangles, type_floor

    plan = type_floor(floor_from_rectangles([(0, 0, 6, 10), (6, 0, 14, 5), (6, 5, 14, 10)]),
                      "house_types.csv", seed=2)
    result = furnish_floor(plan, "furniture_house.csv", seed=2)
    assert result.furniture and result == furnish_floor(plan, "furniture_house.csv", seed=2)
    typed = {room.id for room in plan.rooms if room.type}
    assert {item.room for item in result.furniture if not item.is_detail} <= typed


def test_absurd_steering_iterations_are_refused(tmp_path):
    text = grammar('add_furniture("furniture_thesis.csv", 0.2>1.2>1.2, 0.9, 2.1, 1000000000)')
    with pytest.raises(DerivationError, match="steeringIterations must be at most 10,000"):
        furnished(tmp_path, text)


@pytest.mark.parametrize("value", ["1.5", "-0.1"])
def test_disorder_outside_zero_to_one_is_refused(tmp_path, value):
    text = grammar(f'add_furniture("furniture_house.csv", disorder={value})')
    with pytest.raises(DerivationError, match=r"disorder must be in \[0, 1\]") as caught:
        furnished(tmp_path, text)
    assert caught.value.span is not None and caught.value.span.line == 7  # the call


def test_disorder_from_a_grammar_variable_turns_the_chairs(tmp_path):
    text = grammar('add_furniture("furniture_thesis.csv", 0.2>1.2>1.2, 0.9, 2.1, 10, 20, '
                   'disorder = mess)').replace("Rules:\n", "Variables:\n  mess = 1;\nRules:\n")
    chairs = [i for i in furnished(tmp_path, text).furniture if i.model == "chair"]
    tidy = [i for i in furnished(tmp_path, text.replace("mess = 1", "mess = 0")).furniture
            if i.model == "chair"]
    assert chairs and any(c.yaw for c in chairs) and not any(c.yaw for c in tidy)
