"""The scene document: schema-valid, deterministic, faithful to the model."""

from __future__ import annotations

import dataclasses
import enum
import json
import math
import re
from pathlib import Path

import jsonschema
import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

import cga
from cga.errors import ExportError
from cga.export.scene_json import (_footprint_bounds, export_scene_json, json_text, load_schema,
                                   scene_json_text)
from cga.model import FurnitureItem
from reports import FixedReport


@pytest.fixture(scope="module")
def document(small_scene):
    scene, nodes = small_scene
    return json.loads(scene_json_text(scene, nodes))


def test_schema_is_valid_draft_2020_12():
    schema = load_schema()
    assert schema["$schema"] == "https://json-schema.org/draft/2020-12/schema"
    jsonschema.Draft202012Validator.check_schema(schema)


def _properties(schema, where="#"):
    """Every (where, name, subschema) of a 'properties' block, recursively."""
    for name, sub in schema.get("properties", {}).items():
        yield where, name, sub
        yield from _properties(sub, f"{where}/{name}")
    for key in ("items", "additionalProperties"):
        if isinstance(schema.get(key), dict):
            yield from _properties(schema[key], f"{where}/{key}")
    for name, sub in schema.get("$defs", {}).items():
        yield from _properties(sub, f"{where}/$defs/{name}")


def test_every_property_is_described():
    missing = [f"{where}/{name}" for where, name, sub in _properties(load_schema())
               if not sub.get("description")]
    assert missing == []


def test_document_validates(document):
    jsonschema.Draft202012Validator(load_schema()).validate(document)


def test_schema_rejects_a_broken_document(document):
    broken = json.loads(json.dumps(document))
    broken["furniture"][0]["pose"]["quarter_turns"] = 5
    with pytest.raises(jsonschema.ValidationError):
        jsonschema.validate(broken, load_schema())


def test_same_scene_same_text_except_timings(small_scene, tmp_path):
    scene, nodes = small_scene
    first = export_scene_json(scene, nodes, tmp_path, "house")[0].read_text()
    slower = dataclasses.replace(scene, timings={"derive": 9.5, "export": 1.0})
    second = scene_json_text(slower, nodes)
    assert first != second
    a, b = json.loads(first), json.loads(second)
    a.pop("timings"), b.pop("timings")
    assert a == b
    assert scene_json_text(scene, nodes) == first


def test_keys_sorted_and_floats_rounded(document, small_scene):
    scene, nodes = small_scene
    text = scene_json_text(scene, nodes)
    assert list(document) == sorted(document)
    assert list(document["furniture"][0]) == sorted(document["furniture"][0])

    def floats(value):
        if isinstance(value, float):
            yield value
        elif isinstance(value, dict):
            for v in value.values():
                yield from floats(v)
        elif isinstance(value, list):
            for v in value:
                yield from floats(v)

    assert all(round(f, 6) == f for f in floats(document))
    assert '"position": [5.0, 1.5]' in text  # points stay on one line


def test_header(document):
    assert document["format"] == "cga.scene"
    assert document["generator"] == {"name": "cga", "version": cga.__version__}
    assert document["seed"] == 7
    assert document["frame"]["up"] == "+y"


def test_contents_follow_the_model(document):
    assert [f["index"] for f in document["floors"]] == [0, 1]
    assert len(document["rooms"]) == 6
    kitchen = next(r for r in document["rooms"] if r["type"] == "Kitchen")
    assert kitchen["area"] == 9.0 and kitchen["floor"] == 0
    assert kitchen["polygon"]["exterior"][0] in ([5.0, 0.0], [8.0, 0.0], [8.0, 3.0], [5.0, 3.0])
    assert kitchen["floor_area"] < kitchen["area"]
    fronts = [d for d in document["doors"] if d["front"]]
    assert len(fronts) == 1 and fronts[0]["floor"] == 0 and -1 in fronts[0]["rooms"]
    wall7 = next(w for w in document["walls"] if w["floor"] == 0 and w["id"] == 7)
    assert wall7["outer"] is False
    assert wall7["openings"] == [{"kind": "door", "center": 1.5, "width": 0.9, "height": 2.1,
                                  "sill": 0.0, "position": [5.0, 1.5]}]
    assert len(document["windows"]) == 6
    edges = [(e["floor"], e["rooms"], e["doors"]) for e in document["room_graph"]]
    assert (0, [-1, 0], [2]) in edges and (1, [1, 2], [1]) in edges
    assert len(document["nodes"]) > 10


def test_furniture_pose_and_box(document):
    bed = next(f for f in document["furniture"] if f["name"] == "bed")
    assert bed["floor"] == 1 and bed["room"] == 0
    assert bed["pose"] == {"position": [2.0, 3.2, 3.0], "yaw_degrees": 90.0, "quarter_turns": 1}
    # a quarter turn swaps width and depth in the world box
    assert bed["bbox"] == {"min": [1.0, 3.2, 2.2], "max": [3.0, 3.7, 3.8]}
    assert bed["node"] == "floor1/room0_Bedroom/furniture/bed"
    assert bed["front"] == [-1.0, 0.0]


def test_nan_in_checks_is_an_export_error(small_scene):
    scene, nodes = small_scene
    bad = dataclasses.replace(scene, checks={"physics": FixedReport(details={"max_penetration": float("nan")})})
    with pytest.raises(ExportError, match=r"checks\.physics\.max_penetration"):
        scene_json_text(bad, nodes)


def _stdlib_text(document):
    """The text the way the standard library writes it: indented, then every list of
    only numbers joined onto one line."""
    text = json.dumps(document, sort_keys=True, indent=2, ensure_ascii=False, allow_nan=False)
    # each number an atomic group: a long number followed by a string would otherwise
    # be split every which way before the match fails
    one_line = re.compile(r"\[\n\s*((?:(?>-?[0-9][0-9.eE+-]*),?\s*)+?)\n\s*\]")
    return one_line.sub(lambda m: "[" + " ".join(m.group(1).split()) + "]", text) + "\n"


_SCALARS = (st.none() | st.booleans() | st.integers(-10**20, 10**20)
            | st.floats(allow_nan=False, allow_infinity=False)
            | st.text(st.characters(codec="utf-8"), max_size=8))
_DOCUMENTS = st.recursive(_SCALARS, lambda inner: (
    st.lists(inner, max_size=5) | st.lists(inner, max_size=3).map(tuple)
    | st.lists(st.integers(-5, 5) | st.floats(-1e9, 1e9), min_size=1, max_size=4)
    | st.dictionaries(st.text(max_size=5), inner, max_size=5)), max_leaves=40)


@settings(max_examples=200, deadline=None)
@given(_DOCUMENTS)
def test_json_text_is_the_standard_librarys_text(document):
    assert json_text(document) == _stdlib_text(document)


def test_json_text_of_a_scene_is_the_standard_librarys_text(small_scene):
    from cga.export.scene_json import scene_as_dict

    document = scene_as_dict(*small_scene)
    assert json_text(document) == _stdlib_text(document)
    # subclasses of the JSON types (numpy floats) are written as their base type
    assert json_text({"p": [np.float64(0.5), 2], "q": [True, 1]}) == _stdlib_text(
        {"p": [np.float64(0.5), 2], "q": [True, 1]})


@pytest.mark.parametrize("bad, error", [(float("nan"), ValueError), (float("inf"), ValueError),
                                        ({1: 2}, TypeError), (object(), TypeError)])
def test_json_text_refuses_what_json_cannot_hold(bad, error):
    with pytest.raises(error):
        json_text({"a": [bad]})
    with pytest.raises(error):  # after numbers: a list that would be written on one line
        json_text({"a": [1.5, 2, bad]})


def test_unfit_value_deep_in_a_list_is_named_by_its_path(small_scene):
    scene, nodes = small_scene
    bad = dataclasses.replace(scene, checks={"physics": FixedReport(
        details={"items": [{"ok": 1.0}, {"ok": float("inf")}], "when": object()})})
    with pytest.raises(ExportError, match=r"checks\.physics\.(items\[1\]\.ok|when) "):
        scene_json_text(bad, nodes)


_COORD = st.floats(-500, 500, allow_nan=False, allow_infinity=False)
_SIZE = st.floats(0.01, 9, allow_nan=False, allow_infinity=False)


@settings(max_examples=400, deadline=None)
@given(x=_COORD, z=_COORD, w=_SIZE, d=_SIZE, rotation=st.integers(-5, 9),
       yaw=st.sampled_from([0.0, 0.3, -1.2]))
def test_furniture_bounds_are_the_footprints_bounds(x, z, w, d, rotation, yaw):
    """The bbox written for an item is its shapely footprint's bounds, float for float."""
    item = FurnitureItem(name="t", model="m", room=0, position=(x, z), rotation=rotation,
                         size=(w, 0.8, d), yaw=yaw)
    assert _footprint_bounds(item) == item.footprint().bounds


class _Key(str, enum.Enum):
    """A key whose ``str`` is not its text (``_Key.a`` → ``"_Key.a"``)."""

    a = "a"


@dataclasses.dataclass
class _Point:
    x: float
    y: int


_RAW_SCALARS = (_SCALARS | st.just(-0.0) | st.sampled_from([float("nan"), float("inf")])
                | st.floats(-1e6, 1e6).map(np.float64) | st.integers(-9, 9).map(np.int64)
                | st.floats(-1e3, 1e3).map(lambda x: _Point(x, 1))
                | st.just(Path("a/b")) | st.just(np.arange(3) / 7))
_RAW_DOCUMENTS = st.recursive(_RAW_SCALARS, lambda inner: (
    st.lists(inner, max_size=4) | st.lists(inner, max_size=3).map(tuple)
    | st.lists(st.floats(-1e9, 1e9) | st.integers(-5, 5), min_size=1, max_size=4)
    | st.dictionaries(st.text(max_size=4) | st.integers(0, 3) | st.just(_Key.a), inner,
                      max_size=4)), max_leaves=30)


@settings(max_examples=300, deadline=None)
@given(_RAW_DOCUMENTS)
def test_scene_text_in_one_walk_is_the_cleaned_documents_text(document):
    """The scene document written in one walk, rounding as it goes, is the text of the
    cleaned document, or the same error where it cannot be cleaned (NaN, a type with no
    JSON form): numpy numbers, tuples, dataclasses, non-string keys and NaN included."""
    from cga.export.scene_json import _clean, _document_text

    try:
        expected = json_text(_clean(document))
    except (ExportError, TypeError) as error:  # TypeError: keys that do not sort
        with pytest.raises(type(error), match=re.escape(str(error))):
            _document_text(document)
    else:
        assert _document_text(document) == expected


_FLOATS = (st.floats() | st.sampled_from([-0.0, 0.0, 5e-7, -5e-7, 1e-5, 2.5e-6, 1e16, 1e300,
                                            5e-324, 0.1234565, 1.0000005, 2.675])
           | st.floats(-1e-3, 1e-3) | st.integers(-10**9, 10**9).map(lambda n: n * 5e-7))


@settings(max_examples=1000, deadline=None)
@given(st.lists(_FLOATS | st.integers(-10**20, 10**20), min_size=1, max_size=6))
def test_rounded_floats_are_the_repr_of_the_rounded_floats(values):
    """Floats written once per value and then looked up are ``repr(round(v, 6) + 0.0)``,
    in lists, mixed with ints and alone, for every float: tiny, huge, ties, ``-0.0``
    after ``0.0`` and before it; a NaN or an infinity is the same error."""
    from cga.export.scene_json import _clean, _document_text

    document = {"list": values, "one": values[0], "each": [[v] for v in values],
                "alone": [{"v": v} for v in values], "zero": [0.0, -0.0, 0.0]}
    assert _document_text({"a": -0.0, "b": [0.0, -0.0]}) == '{\n  "a": 0.0,\n  "b": [0.0, 0.0]\n}\n'
    if all(math.isfinite(v) for v in values):
        assert _document_text(document) == json_text(_clean(document))
        assert f"\"one\": {_cleaned_repr(values[0])},\n" in _document_text(document)
    else:
        with pytest.raises(ExportError, match="JSON cannot hold"):
            _document_text(document)


def _cleaned_repr(value):
    return repr(round(value, 6) + 0.0) if type(value) is float else repr(value)


def test_keys_written_again_are_written_alike():
    """A key's text is kept once written; a key equal to a string but not one (an enum of
    strings) is not written as that string, before or after it."""
    from cga.export.scene_json import _clean, _document_text

    for document in ({"a": {"a": 1, "é\n": 2}, "b": [{"a": 3, "é\n": 4}], "c": {_Key.a: 5}},
                     {"a": {_Key.a: 1}, "b": {"a": 2}}):
        assert _document_text(document) == json_text(_clean(document))
    assert json_text({"a": {"a": 1, "é\n": 2}, "b": [{"a": 3}]}) == _stdlib_text(
        {"a": {"a": 1, "é\n": 2}, "b": [{"a": 3}]})
