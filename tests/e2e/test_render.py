"""Sensor data of a built house (issue 16, DESIGN §15): views, masks and maps read back
the way a training loader reads them, checked against the scene JSON by the independent
checks of tests/support/render_checks.py."""

from __future__ import annotations

import json
import struct
import sys
from pathlib import Path

import numpy as np
import pytest
from PIL import Image
from shapely.geometry import Point, Polygon

from cga.batch import run_batch, seed_folder
from cga.cli import main
from cga.pipeline import build

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "support"))
from render_checks import (floor_pixel_areas, furniture_shadows, load_view,  # noqa: E402
                           pixel_points, wall_surface_distance)
from ros_map_checks import RosMap  # noqa: E402

pytest.importorskip("embreex", reason="needs the render extra: pip install 'cga[render]'")

HOUSE = Path(__file__).resolve().parents[2] / "demos" / "house.grammar"
FORMATS = ["glb", "json", "map", "render"]

pytestmark = pytest.mark.slow


@pytest.fixture(scope="module")
def house(tmp_path_factory):
    out = tmp_path_factory.mktemp("render")
    build(HOUSE, seed=0, out_dir=out, formats=FORMATS, quiet=True, physics=False)
    doc = json.loads((out / "house.scene.json").read_text())
    index = json.loads((out / "house.render" / "index.json").read_text())
    return out, doc, index


def _class_ids(doc, name, group="structure"):
    return next(c["id"] for c in doc["classes"] if c["name"] == name and c["group"] == group)


def _views(index, projection):
    return [v for v in index["views"] if v["projection"] == projection]


def test_every_room_has_a_view_and_every_floor_a_top_down_view(house):
    _, doc, index = house
    rooms = {(r["floor"], r["id"]) for r in doc["rooms"]}
    assert {(v["floor"], v["room"]) for v in _views(index, "perspective")} == rooms
    assert sorted(v["floor"] for v in _views(index, "orthographic")) == [0, 1]


def test_cameras_stand_in_their_room_at_eye_height_clear_of_furniture(house):
    out, doc, index = house
    floors = {f["index"]: f for f in doc["floors"]}
    for view in _views(index, "perspective"):
        camera = json.loads((out / "house.render" / view["files"]["camera"]).read_text())
        x, y, z = np.array(camera["opencv"]["camera_to_world"])[:3, 3]
        assert y == pytest.approx(floors[view["floor"]]["floor_y"] + 1.0)
        room = next(r for r in doc["rooms"]
                    if r["floor"] == view["floor"] and r["id"] == view["room"])
        interior = Polygon(room["interior"]["exterior"], room["interior"]["holes"])
        assert interior.contains(Point(x, z)), view["name"]
        for item in doc["furniture"]:
            solid = not (item["is_detail"] or item["non_collision"])
            lo, hi = item["bbox"]["min"], item["bbox"]["max"]
            if item["floor"] == view["floor"] and solid and lo[1] < y:
                assert not (lo[0] < x < hi[0] and lo[2] < z < hi[2]), (view["name"], item["name"])


def test_every_mask_id_is_in_the_class_table_or_the_scene_json(house):
    out, doc, index = house
    classes = {c["id"] for c in doc["classes"]}
    instances = {n["instance_id"] for n in doc["nodes"]}
    assert len(instances) == len(doc["nodes"])  # unique
    folder = out / "house.render"
    for view in index["views"]:
        images = load_view(folder, view["name"])
        assert set(np.unique(images["semantic"])) <= classes
        assert set(np.unique(images["instance"])) <= instances | {0}
        # a pixel's class is its instance's class, but for the underside of slabs
        by_instance = {n["instance_id"]: n["class_id"] for n in doc["nodes"]}
        hit = images["instance"] > 0
        expected = np.vectorize(by_instance.get)(images["instance"][hit])
        same = expected == images["semantic"][hit]
        ceiling = images["semantic"][hit] == _class_ids(doc, "ceiling")
        assert np.all(same | ceiling)
    for floor in index["floors"]:
        types = np.asarray(Image.open(folder / floor["files"]["room_types"]))
        assert set(np.unique(types)) <= classes


def test_top_down_floor_pixels_match_each_rooms_free_area_within_two_percent(house):
    out, doc, index = house
    floor_class = _class_ids(doc, "floor")
    for view in _views(index, "orthographic"):
        images = load_view(out / "house.render", view["name"])
        shadows = furniture_shadows(out / "house.glb", view["floor"])
        for room, (pixels, free) in floor_pixel_areas(images, doc, floor_class, shadows).items():
            assert pixels == pytest.approx(free, rel=0.02), (view["name"], room)


def test_depth_of_wall_pixels_reprojects_onto_the_walls_within_two_centimetres(house):
    out, doc, index = house
    wall = _class_ids(doc, "wall")
    checked = 0
    for view in _views(index, "perspective"):
        images = load_view(out / "house.render", view["name"])
        rows, cols = np.nonzero(images["semantic"] == wall)
        if len(rows) == 0:
            continue
        pick = np.linspace(0, len(rows) - 1, min(len(rows), 4000)).astype(int)
        points = pixel_points(images, rows[pick], cols[pick])
        distance = wall_surface_distance(points, doc)
        assert np.max(distance) <= 0.02, view["name"]
        checked += len(pick)
    assert checked > 10_000


def test_camera_json_conventions(house):
    out, doc, index = house
    view = _views(index, "perspective")[0]
    camera = json.loads((out / "house.render" / f"{view['name']}.camera.json").read_text())
    to_world = np.array(camera["opencv"]["camera_to_world"])
    assert np.allclose(np.array(camera["opencv"]["world_to_camera"]) @ to_world, np.eye(4))
    assert np.allclose(np.array(camera["gltf"]["camera_to_world"]),
                       to_world @ np.diag([1.0, -1.0, -1.0, 1.0]))
    assert np.isclose(np.linalg.det(to_world[:3, :3]), 1.0)
    k = camera["intrinsics"]
    assert camera["width"] == 640 and camera["height"] == 480
    assert np.isclose(2 * np.degrees(np.arctan(320 / k["fx"])), 90.0)
    assert np.isclose(camera["gltf"]["perspective"]["yfov"], 2 * np.arctan(240 / k["fy"]))
    # OpenCV: y down, so the camera's y axis points down in the world (level camera)
    assert np.allclose(to_world[:3, 1], [0.0, -1.0, 0.0])
    floor = next(f for f in doc["floors"] if f["index"] == view["floor"])
    assert to_world[1, 3] == pytest.approx(floor["floor_y"] + 1.0)
    # a pixel's 3D point, projected with world_to_camera and K, lands on that pixel
    images = load_view(out / "house.render", view["name"])
    rows, cols = np.nonzero(images["depth"] > 0)
    points = pixel_points(images, rows[::997], cols[::997])
    local = (np.hstack([points, np.ones((len(points), 1))])
             @ np.array(camera["opencv"]["world_to_camera"]).T)[:, :3]
    uv = (local @ np.array(k["K"]).T)[:, :2] / local[:, 2:]
    assert np.allclose(uv, np.column_stack([cols[::997], rows[::997]]), atol=1e-4)


def test_top_down_maps_lie_on_the_ros_map_grid(house):
    out, doc, index = house
    folder = out / "house.render"
    for floor in index["floors"]:
        n = floor["floor"]
        ros = RosMap(out / f"house.floor{n}.yaml")
        maps = RosMap.__new__(RosMap)
        maps.fields = dict(line.split(": ", 1) for line in
                           (folder / floor["files"]["yaml"]).read_text().splitlines()
                           if not line.startswith("#"))
        maps.resolution = float(maps.fields["resolution"])
        maps.origin = [float(v) for v in maps.fields["origin"].strip("[]").split(",")]
        maps.pixels = np.asarray(Image.open(folder / maps.fields["room_types"]))
        assert maps.resolution == ros.resolution and maps.origin == ros.origin
        assert maps.pixels.shape == ros.pixels.shape
        for room in (r for r in doc["rooms"] if r["floor"] == n):
            interior = Polygon(room["interior"]["exterior"], room["interior"]["holes"])
            x, z = interior.representative_point().coords[0]
            name = (room["type"] or "room").lower()
            expected = next((c["id"] for c in doc["classes"]
                             if c["group"] == "room_type" and c["name"] == name),
                            _class_ids(doc, "room", "room_type"))
            assert maps.at_world(x, z) == expected
            assert ros.at_world(x, z) != 205  # inside the building on the ROS map too


def test_scene_json_and_glb_carry_class_and_instance_ids(house):
    out, doc, _ = house
    nodes = {n["path"]: n for n in doc["nodes"]}
    assert sorted(n["instance_id"] for n in doc["nodes"]) == list(range(1, len(nodes) + 1))
    names = {c["id"]: c["name"] for c in doc["classes"]}
    for item in doc["furniture"]:
        node = nodes[item["node"]]
        assert (item["class_id"], item["instance_id"]) == (node["class_id"], node["instance_id"])
        assert names[item["class_id"]] == item["class"]
        if item["door"] is not None:
            assert item["class"] == "door"
    assert {n["class"] for n in doc["nodes"] if n["kind"] == "wall"} == {"wall"}
    # the glb's JSON chunk, read by hand: every mesh node's extras carry the same ids
    data = (out / "house.glb").read_bytes()
    length, kind = struct.unpack_from("<I4s", data, 12)
    gltf = json.loads(data[20:20 + length])
    meshes = [n for n in gltf["nodes"] if "mesh" in n]
    assert len(meshes) == len(nodes)
    for node in meshes:
        extras = node["extras"]
        assert extras["instance_id"] == nodes[node["name"]]["instance_id"]
        assert extras["class_id"] == nodes[node["name"]]["class_id"]


def test_same_seed_writes_identical_render_files(house, tmp_path):
    out, _, _ = house
    build(HOUSE, seed=0, out_dir=tmp_path, formats=FORMATS, quiet=True, physics=False)
    first = sorted(p.relative_to(out) for p in (out / "house.render").iterdir())
    second = sorted(p.relative_to(tmp_path) for p in (tmp_path / "house.render").iterdir())
    assert first == second
    for name in first:
        assert (out / name).read_bytes() == (tmp_path / name).read_bytes(), name


def _positions(folder: Path) -> dict[str, np.ndarray]:
    return {p.name: np.array(json.loads(p.read_text())["opencv"]["camera_to_world"])
            for p in folder.glob("*_room*.camera.json")}


def test_cga_render_reads_the_outputs_and_seeds_change_the_poses(house, tmp_path, capsys):
    out, _, _ = house
    other = tmp_path / "seed1"
    build(HOUSE, seed=1, out_dir=other, formats=["glb", "json"], quiet=True, physics=False)
    args = ["--width", "64", "--height", "48", "--views-per-room", "2", "--quiet"]
    assert main(["render", str(out / "house.scene.json"), "--out", str(tmp_path / "a"), *args]) == 0
    assert main(["render", str(other / "house.scene.json"), "--out", str(tmp_path / "b"), *args]) == 0
    a, b = _positions(tmp_path / "a" / "house.render"), _positions(tmp_path / "b" / "house.render")
    assert len(a) == 2 * len(json.loads((out / "house.scene.json").read_text())["rooms"])
    common = set(a) & set(b)
    assert common and all(not np.allclose(a[k], b[k]) for k in common)
    image = np.asarray(Image.open(tmp_path / "a" / "house.render" / next(iter(a)).replace(
        ".camera.json", ".rgb.png")))
    assert image.shape == (48, 64, 3)


def test_cga_render_refuses_what_is_not_a_build(tmp_path, capsys):
    text = tmp_path / "x.scene.json"
    text.write_text('{"format": "something else"}')
    assert main(["render", str(text)]) == 2
    assert "not a cga scene document" in capsys.readouterr().err
    assert main(["render", str(tmp_path / "missing.scene.json")]) == 2
    assert "no such file" in capsys.readouterr().err


def test_cga_render_without_the_glb_names_it(house, tmp_path, capsys):
    out, _, _ = house
    lone = tmp_path / "house.scene.json"
    lone.write_bytes((out / "house.scene.json").read_bytes())
    assert main(["render", str(lone)]) == 2
    assert "house.glb: no such file" in capsys.readouterr().err


def test_batch_manifest_counts_views(tmp_path):
    report = run_batch(HOUSE, count=1, out_dir=tmp_path, seed_start=2,
                       build_options={"physics": False, "formats": ["glb", "json", "render"]})
    line = json.loads((tmp_path / "manifest.jsonl").read_text().splitlines()[0])
    cameras = list((tmp_path / seed_folder(2) / "house.render").glob("*.camera.json"))
    assert line["views"] == len(cameras) > 0
    assert report.to_dict()["views"] == len(cameras)
