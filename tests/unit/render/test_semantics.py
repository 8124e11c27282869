"""The class table: stable ids, one class per model, room types."""

from __future__ import annotations

from pathlib import Path

from cga.semantics import (class_id, class_table, furniture_class, instance_ids,
                           room_type_class)

MODELS = Path(__file__).resolve().parents[3] / "models"


def test_ids_are_stable():
    # published ids: changing one breaks every dataset made before
    fixed = {"unlabelled": 0, "wall": 1, "floor": 2, "ceiling": 3, "door": 4, "window": 5,
             "stair": 6, "roof": 7}
    assert {c.name: c.id for c in class_table()
            if c.name in fixed and c.group in ("none", "structure")} == fixed
    assert class_id("sofa", "furniture") == 39
    assert room_type_class("Kitchen") == 104


def test_every_shipped_model_has_its_own_class():
    generic = class_id("furniture", "furniture")
    for obj in MODELS.glob("*.obj"):
        cls = furniture_class(obj.stem)
        if obj.stem in ("door", "window"):
            assert cls == class_id(obj.stem)
        else:
            assert cls != generic, obj.stem


def test_unknown_models_and_room_types_fall_back():
    assert furniture_class("Grand Piano") == class_id("furniture", "furniture")
    assert furniture_class("Double Bed") == class_id("doublebed", "furniture")
    assert room_type_class("Ballroom") == room_type_class(None) == class_id("room", "room_type")


def test_ids_are_unique_and_groups_known():
    table = class_table()
    assert len({c.id for c in table}) == len(table)
    assert len({(c.group, c.name) for c in table}) == len(table)
    assert {c.group for c in table} == {"none", "structure", "furniture", "room_type"}


class _Node:
    def __init__(self, path):
        self.path = path


def test_instance_ids_number_nodes_from_one():
    assert instance_ids([_Node("a"), _Node("b"), _Node("c")]) == {"a": 1, "b": 2, "c": 3}


def test_every_room_type_a_shipped_table_can_make_has_its_own_class():
    """The room-type map tells apart every type the shipped tables, the UvA catalogue and
    the operations themselves (the stair core, the UvA hallways and open areas) write."""
    import csv
    from pathlib import Path

    rules = Path(__file__).resolve().parents[3] / "rules"
    made = {"Stair", "Hallway", "OpenArea"}
    for path in rules.glob("*_types.csv"):
        lines = [l for l in path.read_text(encoding="utf-8").splitlines() if not l.startswith("#")]
        made |= {row["Type"] for row in csv.DictReader(lines, delimiter=";")}
    usar = (rules / "usar_rooms.csv").read_text(encoding="utf-8").splitlines()
    made |= {row["Furniture"] for row in csv.DictReader(usar, delimiter=";")}
    generic = class_id("room", "room_type")
    assert {t for t in made if room_type_class(t) == generic} == set()
