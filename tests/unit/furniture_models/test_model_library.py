"""ModelLibrary: name matching, search order, caching, user OBJ files and their errors."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import trimesh

from cga.errors import CGAError, ResourceNotFoundError
from cga.operations.furniture.library import (
    DEFAULT_DENSITY,
    FurnitureModel,
    ModelFileError,
    ModelLibrary,
    default_library,
    grammar_model_dirs,
    name_candidates,
    normalize_name,
)
from cga.resources import shipped_dir

SHIPPED = shipped_dir("cga.furniture_models")


def write_obj(path: Path, meshes: list[trimesh.Trimesh], header: str = "",
              groups: bool = True) -> Path:
    """A hand-written OBJ: optional header lines, then each mesh (as ``g part_i``)."""
    lines = [header] if header else []
    first = 1
    for index, mesh in enumerate(meshes):
        if groups:
            lines.append(f"g part_{index}")
        lines += [f"v {x:.9g} {y:.9g} {z:.9g}" for x, y, z in mesh.vertices]
        lines += [f"f {a + first} {b + first} {c + first}" for a, b, c in mesh.faces]
        first += len(mesh.vertices)
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


def cube(lo, hi) -> trimesh.Trimesh:
    return trimesh.creation.box(bounds=np.array([lo, hi], dtype=float))


@pytest.fixture
def shipped() -> ModelLibrary:
    return ModelLibrary([SHIPPED])


@pytest.mark.parametrize("name", ["doublebed", "Double Bed", "double_bed", "doubleBed",
                                  "DOUBLE-BED", "double bed2"])
def test_names_match_ignoring_case_and_separators(shipped, name):
    model = shipped.get(name)
    assert model.name == "doublebed"
    assert model.path.name == "doublebed.obj"


@pytest.mark.parametrize("name, model", [("chair1", "chair"), ("bookshelf2", "bookshelf"),
                                         ("Sofa_Table12", "sofatable")])
def test_numeric_suffix_repeats_a_model(shipped, name, model):
    assert shipped.get(name).name == model


def test_name_normalisation():
    assert normalize_name(" Kitchen_Counter-1 ") == "kitchencounter1"
    assert name_candidates("chair12") == ("chair12", "chair")
    assert name_candidates("Chair") == ("chair",)
    assert name_candidates("42") == ("42",)


def test_full_name_is_tried_in_every_folder_before_the_suffix_is_dropped(tmp_path, shipped):
    write_obj(tmp_path / "Chair1.obj", [cube((-1, 0, -1), (1, 3, 1))])
    library = ModelLibrary([SHIPPED, tmp_path])
    assert library.get("chair1").path == tmp_path / "Chair1.obj"
    assert library.get("chair1").size == pytest.approx((2, 3, 2))
    assert library.get("chair2").path == SHIPPED / "chair.obj"


def test_earlier_folders_shadow_shipped_models(tmp_path):
    write_obj(tmp_path / "sofa.obj", [cube((-0.5, 0, -0.5), (0.5, 1, 0.5))])
    library = default_library([tmp_path])
    assert library.search_dirs == (tmp_path, SHIPPED)
    assert library.get("Sofa").path == tmp_path / "sofa.obj"
    assert library.get("chair").path == SHIPPED / "chair.obj"


def test_each_model_is_loaded_once_per_library(shipped):
    first = shipped.get("chair")
    assert shipped.get("Chair") is first
    assert shipped.get("chair3") is first
    assert ModelLibrary([SHIPPED]).get("chair") is not first


def test_missing_model_names_the_model_and_every_folder(tmp_path):
    missing = tmp_path / "no-such-folder"
    library = ModelLibrary([tmp_path, missing, SHIPPED])
    with pytest.raises(ResourceNotFoundError) as info:
        library.get("spaceship7")
    text = str(info.value)
    assert "spaceship7" in text
    for folder in (tmp_path, missing, SHIPPED):
        assert str(folder) in text
    assert isinstance(info.value, CGAError)


def test_names_lists_every_model_once(tmp_path):
    write_obj(tmp_path / "Lamp Post.obj", [cube((0, 0, 0), (1, 1, 1))])
    names = ModelLibrary([tmp_path, SHIPPED]).names()
    assert "lamppost" in names and "chair" in names
    assert len(names) == len(set(names))


def test_shipped_model_properties(shipped):
    chair = shipped.get("chair")
    assert isinstance(chair, FurnitureModel)
    assert chair.convex_parts
    assert len(chair.parts) >= 6
    assert chair.size == pytest.approx(tuple(chair.mesh.extents))
    assert chair.density == float(_header(chair.path)["density"])
    assert chair.color == tuple(float(c) for c in _header(chair.path)["color"].split())
    assert chair.mass == pytest.approx(
        chair.density * sum(p.volume for p in chair.parts))
    assert len(chair.mesh.faces) == sum(len(p.faces) for p in chair.parts)
    assert chair.mesh.visual.vertex_colors.shape == (len(chair.mesh.vertices), 4)


def _header(path: Path) -> dict[str, str]:
    out = {}
    for line in path.read_text().splitlines():
        if line.startswith("# "):
            key, _, value = line[2:].partition(" ")
            out[key] = value
    return out


def test_user_obj_without_groups_is_one_part_and_flagged_when_concave(tmp_path):
    ell = trimesh.boolean.union([cube((0, 0, 0), (2, 1, 1)), cube((0, 0, 0), (1, 1, 2))],
                                engine="manifold")
    write_obj(tmp_path / "ell.obj", [ell], groups=False)
    model = ModelLibrary([tmp_path]).get("ell")
    assert len(model.parts) == 1
    assert not model.convex_parts
    assert model.parts[0].volume == pytest.approx(3.0)


def test_user_obj_with_convex_groups_is_usable_directly(tmp_path):
    write_obj(tmp_path / "stool.obj",
              [cube((0, 0, 0), (1, 0.5, 1)), cube((0, 0.5, 0), (1, 0.6, 1))],
              header="# density 100")
    model = ModelLibrary([tmp_path]).get("stool")
    assert len(model.parts) == 2
    assert model.convex_parts
    assert model.mass == pytest.approx(60.0)


def test_user_obj_with_an_open_part_is_flagged(tmp_path):
    open_box = cube((0, 0, 0), (1, 1, 1))
    open_box.update_faces(np.arange(len(open_box.faces)) > 1)
    write_obj(tmp_path / "crate.obj", [open_box])
    assert not ModelLibrary([tmp_path]).get("crate").convex_parts


def test_user_model_is_moved_onto_the_floor_and_centred(tmp_path):
    write_obj(tmp_path / "block.obj", [cube((3, 1, -4), (5, 2, -3))])
    model = ModelLibrary([tmp_path]).get("block")
    assert model.size == pytest.approx((2, 1, 1))
    assert model.mesh.bounds[0] == pytest.approx((-1, 0, -0.5))
    assert model.parts[0].bounds[1] == pytest.approx((1, 1, 0.5))


def test_defaults_without_header(tmp_path):
    write_obj(tmp_path / "plain.obj", [cube((0, 0, 0), (1, 1, 1))])
    model = ModelLibrary([tmp_path]).get("plain")
    assert model.density == DEFAULT_DENSITY
    assert model.mass == pytest.approx(DEFAULT_DENSITY)


@pytest.mark.parametrize("header, fragment", [
    ("# density -3", "density"),
    ("# density heavy", "density"),
    ("# color 2 0 0", "color"),
    ("# color 0.5 0.5", "color"),
])
def test_bad_header_values_are_reported_with_the_line(tmp_path, header, fragment):
    path = write_obj(tmp_path / "odd.obj", [cube((0, 0, 0), (1, 1, 1))], header=header)
    with pytest.raises(ModelFileError) as info:
        ModelLibrary([tmp_path]).get("odd")
    assert str(path) in str(info.value)
    assert "line 1" in str(info.value) and fragment in str(info.value)


@pytest.mark.parametrize("text", ["", "v 0 0 0\nv 1 0 0\nv 0 1 0\n",
                                  "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n",
                                  "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"])
def test_unusable_files_raise_a_model_file_error(tmp_path, text):
    (tmp_path / "junk.obj").write_text(text)
    with pytest.raises(ModelFileError):
        ModelLibrary([tmp_path]).get("junk")


def test_grammar_model_dirs(tmp_path):
    grammar = tmp_path / "house.grammar"
    assert grammar_model_dirs(grammar) == [tmp_path.resolve(), tmp_path.resolve() / "models"]
