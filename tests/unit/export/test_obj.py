"""OBJ: one group per node in the world frame, materials with colours."""

from __future__ import annotations

import re

import numpy as np
import pytest
import trimesh

from cga.export.obj import export_obj
from cga.export.palette import KIND_COLORS
from cga.scene import SceneNode
from items import item_info


@pytest.fixture(scope="module")
def obj_files(small_scene, tmp_path_factory):
    scene, nodes = small_scene
    out = tmp_path_factory.mktemp("obj")
    return export_obj(scene, nodes, out, "house")


def test_groups_are_the_nodes(obj_files, small_scene):
    _, nodes = small_scene
    obj, mtl = obj_files
    text = obj.read_text()
    assert text.splitlines()[1] == f"mtllib {mtl.name}"
    assert re.findall(r"^g (\S+)$", text, re.MULTILINE) == [n.path for n in nodes]
    assert len(re.findall(r"^v ", text, re.MULTILINE)) == sum(len(n.mesh.vertices) for n in nodes)


def test_trimesh_reads_back_the_world_geometry(obj_files, small_scene):
    _, nodes = small_scene
    obj, _ = obj_files
    loaded = trimesh.load(obj, force="mesh", process=False)
    assert len(loaded.faces) == sum(len(n.mesh.faces) for n in nodes)
    world = np.array([n.mesh.bounds for n in nodes])
    assert np.allclose(loaded.bounds, [world[:, 0].min(axis=0), world[:, 1].max(axis=0)])
    assert loaded.bounds[1][1] == pytest.approx(6.0)  # y up: two 3 m storeys


def test_materials_carry_kind_colours(obj_files):
    _, mtl = obj_files
    blocks = dict(re.findall(r"newmtl (\S+)\n(?:.*\n)*?Kd ([\d. ]+)\n", mtl.read_text()))
    # material names are the row (here the kind of an undressed node) and a digest
    rows = {name.rsplit("_", 1)[0]: name for name in blocks}
    assert set(rows) == {"wall", "slab", "furniture"}
    wall = [float(v) for v in blocks[rows["wall"]].split()]
    assert wall == pytest.approx(KIND_COLORS["wall"], abs=1e-4)


def test_coloured_furniture_keeps_its_colours(small_scene, tmp_path):
    scene, nodes = small_scene
    chair = trimesh.creation.box((0.5, 0.9, 0.5))
    chair.visual.vertex_colors = np.tile([204, 102, 51, 255], (len(chair.vertices), 1))
    node = SceneNode("floor0/room1_Kitchen/furniture/chair", "furniture", chair,
                     static=False, parts=(chair,), item=item_info("chair", mass=5.0))
    obj, mtl = export_obj(scene, [*nodes, node], tmp_path, "house")
    text = obj.read_text()
    block = text.split("g floor0/room1_Kitchen/furniture/chair\n")[1]
    name = block.splitlines()[0].removeprefix("usemtl ")
    assert name.startswith("furniture_chair_")
    assert block.splitlines()[1] == "v -0.250000 -0.450000 -0.250000 0.800000 0.400000 0.200000"
    assert f"newmtl {name}\nKa 0 0 0\nKd 0.8000 0.4000 0.2000" in mtl.read_text()
