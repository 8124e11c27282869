"""Every demo, built with the glTF, JSON, plan, OBJ, URDF, SDF and map exports, loads in
real clients: jsonschema, an XML parser, Pillow, trimesh, pybullet (URDF and SDF), and a
map reader that checks the ROS maps against the scene JSON. Two builds of one seed give
identical files."""

from __future__ import annotations

import json
import os
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import jsonschema
import numpy as np
import pybullet
import pytest
import trimesh
from PIL import Image
from pybullet_utils.bullet_client import BulletClient

from cga.pipeline import build
from cga.export.scene_json import load_schema

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "support"))
from ros_map_checks import RosMap, check_map_against_scene  # noqa: E402

DEMOS = sorted((Path(__file__).resolve().parents[2] / "demos").glob("*.grammar"))
SEED = 3
FORMATS = ["glb", "json", "plan", "obj", "urdf", "sdf", "map"]

pytestmark = pytest.mark.slow


@pytest.fixture(scope="module", params=DEMOS, ids=lambda p: p.stem)
def built(request, tmp_path_factory):
    grammar = request.param
    out = tmp_path_factory.mktemp(grammar.stem)
    build(grammar, seed=SEED, out_dir=out, formats=FORMATS, quiet=True)
    doc = json.loads((out / f"{grammar.stem}.scene.json").read_text())
    return grammar, out, doc


def _ros_box(bbox):
    """World box → ROS box, (x, y, z)_ros = (x, −z, y)_world, written out independently."""
    (x0, y0, z0), (x1, y1, z1) = bbox["min"], bbox["max"]
    return np.array([[x0, -z1, y0], [x1, -z0, y1]])


def test_scene_json_validates(built):
    _, _, doc = built
    jsonschema.Draft202012Validator(load_schema()).validate(doc)
    assert doc["seed"] == SEED


def test_plans_parse_with_one_label_per_room(built):
    grammar, out, doc = built
    for floor in doc["floors"]:
        svg = ET.parse(out / f"{grammar.stem}.floor{floor['index']}.svg").getroot()
        labels = [e for e in svg.iter() if e.get("class") == "room-label"]
        rooms = [r for r in doc["rooms"] if r["floor"] == floor["index"]]
        assert len(labels) == len(rooms)
        png = Image.open(out / f"{grammar.stem}.floor{floor['index']}.png")
        assert png.size == (int(svg.get("width")), int(svg.get("height")))


def test_obj_loads_with_every_node(built):
    grammar, out, doc = built
    mesh = trimesh.load(out / f"{grammar.stem}.obj", force="mesh", process=False)
    assert len(mesh.faces) > 0
    text = (out / f"{grammar.stem}.obj").read_text()
    groups = [line[2:] for line in text.splitlines() if line.startswith("g ")]
    assert groups == [n["path"].replace(" ", "_") for n in doc["nodes"]]


def _robot_expected(doc):
    """Items with a body of their own, and the number of bodies: door leaves hang in the
    building body on their hinges."""
    leaves = {f["node"] for f in doc["furniture"] if f["door"] is not None}
    items = [n for n in doc["nodes"] if n["kind"] == "furniture" and n["path"] not in leaves]
    return items, len(items) + 1


def test_pybullet_loads_the_urdfs(built):
    grammar, out, doc = built
    items, count = _robot_expected(doc)
    client = BulletClient(connection_mode=pybullet.DIRECT)
    try:
        index = json.loads((out / f"{grammar.stem}.urdf.json").read_text())
        ids = {b["node"]: client.loadURDF(str(out / b["urdf"]), b["base_position"],
                                          b["base_orientation_xyzw"], useFixedBase=b["fixed"])
               for b in index["bodies"]}
        assert client.getNumBodies() == count
        for item in (i for i in items if not i["static"]):  # static items: visual only
            assert np.allclose(client.getAABB(ids[item["path"]]), _ros_box(item["bbox"]),
                               atol=0.01), item["path"]
    finally:
        client.disconnect()


def test_pybullet_loads_the_sdf_world(built):
    grammar, out, doc = built
    _, count = _robot_expected(doc)
    client = BulletClient(connection_mode=pybullet.DIRECT)
    cwd = os.getcwd()
    try:
        os.chdir(out.parent)
        ids = client.loadSDF(str(out / f"{grammar.stem}.world.sdf"))
        assert len(ids) == count
        structure = np.array([_ros_box(n["bbox"]) for n in doc["nodes"]
                              if n["kind"] != "furniture"])
        lo, hi = client.getAABB(ids[0])
        assert np.allclose(lo, structure[:, 0].min(axis=0), atol=0.01)
        assert np.allclose(hi, structure[:, 1].max(axis=0), atol=0.01)
    finally:
        os.chdir(cwd)
        client.disconnect()


def test_ros_maps_match_the_scene(built):
    grammar, out, doc = built
    for floor in doc["floors"]:
        ros_map = RosMap(out / f"{grammar.stem}.floor{floor['index']}.yaml")
        counts = check_map_against_scene(ros_map, doc, floor["index"])
        assert counts["wall"] > 0 and counts["free"] > 0
        if any(floor["index"] in s["floors"] for s in doc["stairs"]):
            assert counts["stair"] > 0  # the stair is an obstacle on both of its floors


def test_same_seed_same_files(tmp_path):
    grammar = next(p for p in DEMOS if p.stem == "house")
    first, second = tmp_path / "first", tmp_path / "second"
    for out in (first, second):  # checks off: their reports carry wall-clock times
        build(grammar, seed=SEED, out_dir=out, formats=FORMATS, quiet=True, physics=False)
    files = sorted(p.relative_to(first) for p in first.rglob("*") if p.is_file())
    assert files == sorted(p.relative_to(second) for p in second.rglob("*") if p.is_file())
    for relative in files:
        a, b = (first / relative).read_bytes(), (second / relative).read_bytes()
        if relative.name.endswith(".scene.json"):
            a, b = (json.loads(x) for x in (a, b))
            a.pop("timings"), b.pop("timings")
        assert a == b, relative
