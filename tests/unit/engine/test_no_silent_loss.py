"""Inputs a user really has (issue 20): nothing is dropped without a word, broken inputs
are refused the same way by ``cga check`` and ``cga build``, and model files are read
as an exporter writes them.

Each test reproduces a failure first seen when building grammars written from the docs
only: windows wider than every wall vanished without a diagnostic; "made 4 rooms instead
of 51" disappeared when the typing then failed; a Latin-1 comment in an OBJ ended in a
traceback and an out-of-range face index in a numpy message without a line; the scene
JSON said ``convex_parts: 1`` for a model the physics check split with V-HACD.
"""

from __future__ import annotations

import contextlib
import io
import json
from pathlib import Path

import pytest
import trimesh

from house_project import house_project

from cga.cli import main
from cga.operations.furniture.library import ModelFileError, load_model
from cga.pipeline import build
from cga.resources import shipped_dir

MODELS = shipped_dir("cga.furniture_models")


def cli(*argv) -> tuple[int, str]:
    err = io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
        status = main([str(a) for a in argv])
    return status, err.getvalue()


@pytest.fixture
def project(tmp_path):
    """The house demo with its own copies of its tables, in a folder of its own."""
    return house_project(tmp_path)


def _edit(path: Path, old: str, new: str) -> None:
    text = path.read_text(encoding="utf-8")
    assert old in text
    path.write_text(text.replace(old, new, 1), encoding="utf-8")


def test_windows_wider_than_every_wall_are_a_warning_in_summary_and_json(tmp_path):
    grammar = tmp_path / "wide.grammar"
    grammar.write_text('Lot: rectangle(8, 6)\nRules:\nLot --> extrude(3) Storey\n'
                       'Storey --> make_floor(2, 0.2, 2>7>1.2, 0.9, 2.1) Floor\n', encoding="utf-8")
    scene = build(grammar, out_dir=tmp_path / "out", formats=("json",), physics=False, quiet=True)
    assert not scene.floors[0].windows
    data = json.loads((tmp_path / "out" / "wide.scene.json").read_text(encoding="utf-8"))
    [warning] = [d for d in data["diagnostics"] if "no window fits" in d["message"]]
    assert warning["level"] == "warning" and warning["floor"] == 0
    assert "7.00 m wide" in warning["message"]


def test_a_warning_given_before_a_failure_is_in_the_error_output(tmp_path):
    grammar = tmp_path / "many.grammar"
    grammar.write_text('Lot: rectangle(8, 6)\nRules:\nLot --> extrude(3) Storey\n'
                       'Storey --> make_floor(50, 0.2, 1>1>1, 0.9, 2.1) Floor\n'
                       'Floor --> type_rooms("huge.csv") Typed\n', encoding="utf-8")
    # a 100 m² room on a 48 m² floor: no re-draw or count of rooms types it
    (tmp_path / "huge.csv").write_text(
        "Type;Size;Prob;Neighbours;isOutsideConnected;appearance;additionRoom\n"
        "Huge;100;1;Huge;true;1;0\n", encoding="utf-8")
    status, err = cli("build", grammar, "--no-physics", "--out", tmp_path / "out")
    assert status == 2 and "Traceback" not in err
    assert "no room typing satisfies" in err
    assert "before this error the build reported:" in err
    assert "instead of 51" in err.split("before this error")[1]
    assert not (tmp_path / "out").exists()


def _first_line(err: str) -> str:
    return err.strip().splitlines()[0]


@pytest.mark.parametrize("table, old, new, message", [
    ("furniture_house.csv", "Livingroom;sofa;false;", "Livingroom;sofa;flase;",
     "expected true/false"),
    ("house_types.csv", "Hall, Kitchen, Diningroom", "Hall, Kitchn, Diningroom",
     "did you mean 'Kitchen'"),
    ("furniture_house.csv", "Livingroom;tvboard;", "Livingroom;grandpiano;", "no model for"),
])
def test_check_refuses_what_build_refuses_with_the_same_message(project, table, old, new,
                                                                message):
    _edit(project / table, old, new)
    checked, check_err = cli("check", project / "house.grammar")
    built, build_err = cli("build", project / "house.grammar", "--no-physics",
                           "--out", project / "out")
    assert checked == built == 2
    assert message in _first_line(check_err)
    assert _first_line(check_err) == _first_line(build_err)
    assert table in _first_line(check_err)


def test_an_obj_comment_in_latin1_is_read(tmp_path):
    text = (MODELS / "chair.obj").read_bytes()
    path = tmp_path / "chair.obj"
    path.write_bytes("# Stuhl für das Esszimmer\n".encode("latin-1") + text)
    assert load_model(path).size == load_model(MODELS / "chair.obj").size


@pytest.mark.parametrize("content, message", [
    ("v 0 0 0\nv 1 0 0\nv 0 1 0\ng Stühle\nf 1 2 3\n".encode("latin-1"),
     "line 4, column 5: not UTF-8 text (byte 0xfc)"),
    (b"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 2 9\n",
     "line 6: face corner 9 names no vertex (4 defined before this line)"),
    (b"v 0 0 0\nv 1 0 0\nf 1 2 3\nv 0 1 0\n", "line 3: face corner 3 names no vertex"),
    (b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -4\n", "line 4: face corner -4 names no vertex"),
    (b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x\n", "line 4: face corner 'x' is not a vertex number"),
])
def test_a_malformed_obj_names_the_line(tmp_path, content, message):
    path = tmp_path / "sofa.obj"
    path.write_bytes(content)
    with pytest.raises(ModelFileError, match="sofa.obj") as error:
        load_model(path)
    assert message in str(error.value)


def _l_shaped_chair() -> str:
    """A chair-sized L in one group: not convex, so physics splits it with V-HACD."""
    seat = trimesh.creation.box(extents=(0.44, 0.45, 0.46))
    seat.apply_translation((0.0, 0.225, 0.0))
    back = trimesh.creation.box(extents=(0.44, 0.45, 0.08))
    back.apply_translation((0.0, 0.675, 0.19))
    solid = trimesh.boolean.union([seat, back], engine="manifold")
    lines = ["# a user's chair, one group", "g chair"]
    lines += [f"v {x:.6f} {y:.6f} {z:.6f}" for x, y, z in solid.vertices]
    lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in solid.faces]
    return "\n".join(lines) + "\n"


def test_scene_json_counts_the_vhacd_pieces_of_a_user_model(project, monkeypatch, tmp_path):
    monkeypatch.setenv("CGA_CACHE_DIR", str(tmp_path / "cache"))
    (project / "models").mkdir()
    (project / "models" / "chair.obj").write_text(_l_shaped_chair(), encoding="utf-8")
    out = project / "out"
    build(project / "house.grammar", seed=0, out_dir=out, formats=("json",), physics=False,
          quiet=True)
    data = json.loads((out / "house.scene.json").read_text(encoding="utf-8"))
    chairs = [n for n in data["nodes"] if n["kind"] == "furniture"
              and n["path"].rsplit("/", 1)[-1].startswith("chair")]
    assert chairs, "the house has dining chairs at seed 0"
    assert all(n["convex_parts"] >= 2 for n in chairs)


@pytest.mark.parametrize("lot", ["0x5", "bad.geojson", "missing.geojson"])
def test_check_reads_the_lot_as_build_does(project, lot, monkeypatch):
    (project / "bad.geojson").write_text(
        '{"type": "Polygon", "coordinates": [[[0, 0], [1, 1], [0, 1], [1, 0], [0, 0]]]}',
        encoding="utf-8")
    monkeypatch.chdir(project)
    checked, check_err = cli("check", "house.grammar", "--lot", lot)
    built, build_err = cli("build", "house.grammar", "--lot", lot, "--no-physics",
                           "--out", "out")
    assert checked == built == 2
    assert _first_line(check_err) == _first_line(build_err)
    assert cli("check", "house.grammar", "--lot", "14x10") == (0, "")
