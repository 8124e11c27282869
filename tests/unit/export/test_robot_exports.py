"""URDF and SDF: pybullet loads them, one body per item plus the building, each where
the scene puts it (checked against the node meshes, converted by hand here); no
reader-specific attributes."""

from __future__ import annotations

import json
import math
import os
import xml.etree.ElementTree as ET

import numpy as np
import pytest
import trimesh

from cga.errors import ExportError
from cga.export.sdf import export_sdf
from cga.export.urdf import export_urdf

from bullet import client  # noqa: F401  (the shared fixture)
from cga.scene import SceneNode
from items import item_info


def _ros_box(mesh):
    """World AABB → ROS AABB: (x, y, z)_ros = (x, −z, y)_world."""
    (x0, y0, z0), (x1, y1, z1) = mesh.bounds
    return np.array([[x0, -z1, y0], [x1, -z0, y1]])


@pytest.fixture(scope="module")
def outputs(small_scene, tmp_path_factory):
    scene, nodes = small_scene
    out = tmp_path_factory.mktemp("robot")
    export_urdf(scene, nodes, out, "house")
    export_sdf(scene, nodes, out, "house")
    return out


def _furniture(nodes):
    return [n for n in nodes if n.kind == "furniture"]


def _load_urdfs(client, out):
    index = json.loads((out / "house.urdf.json").read_text())
    bodies = {}
    for entry in index["bodies"]:
        body = client.loadURDF(str(out / entry["urdf"]), entry["base_position"],
                               entry["base_orientation_xyzw"], useFixedBase=entry["fixed"])
        bodies[entry["node"]] = body
    return bodies


def _check_in_place(client, bodies, nodes):
    for node in _furniture(nodes):
        body = bodies[node.path]
        if node.static:  # visual only: no collision box; the fixture's boxes have their
            # centre of mass at the middle of their bounding box
            position = client.getBasePositionAndOrientation(body)[0]
            assert np.allclose(position, _ros_box(node.mesh).mean(axis=0)), node.path
            assert client.getCollisionShapeData(body, -1) == ()
            continue
        lo, hi = (np.array(v) for v in client.getAABB(body))
        assert np.allclose([lo, hi], _ros_box(node.mesh), atol=0.01), node.path
    lo, hi = _body_box(client, bodies[None])
    structure = np.array([_ros_box(n.mesh) for n in nodes if n.kind != "furniture"])
    assert np.allclose(lo, structure[:, 0].min(axis=0), atol=0.01)
    assert np.allclose(hi, structure[:, 1].max(axis=0), atol=0.01)


def _body_box(client, body):
    """The AABB of all links of a body (the building is one link per structure node)."""
    boxes = [client.getAABB(body, link) for link in range(-1, client.getNumJoints(body))]
    boxes = np.array([b for b in boxes if not np.allclose(b[0], b[1])])
    return boxes[:, 0].min(axis=0), boxes[:, 1].max(axis=0)


def test_urdfs_load_with_one_body_per_item_plus_building(client, outputs, small_scene):
    _, nodes = small_scene
    bodies = _load_urdfs(client, outputs)
    assert client.getNumBodies() == len(_furniture(nodes)) + 1
    _check_in_place(client, bodies, nodes)
    for node in _furniture(nodes):
        mass = client.getDynamicsInfo(bodies[node.path], -1)[0]
        assert mass == pytest.approx(0.0 if node.static else node.item.mass)


def test_sdf_world_loads_with_one_body_per_item_plus_building(client, outputs, small_scene):
    _, nodes = small_scene
    cwd = os.getcwd()
    os.chdir("/")  # mesh URIs resolve against the world file, not the working directory
    try:
        ids = client.loadSDF(str(outputs / "house.world.sdf"))
    finally:
        os.chdir(cwd)
    assert len(ids) == len(_furniture(nodes)) + 1
    names = [client.getBodyInfo(i)[1].decode() for i in ids]
    assert names[0] == "building"
    by_node = {None: ids[0]}
    for node in _furniture(nodes):
        name = node.path.replace("/furniture/", "/").replace("/", "_")
        by_node[node.path] = ids[names.index(name)]
    _check_in_place(client, by_node, nodes)
    root = ET.parse(outputs / "house.world.sdf").getroot()
    assert root.get("version") == "1.7"
    for model in root.iter("model"):
        assert model.find("link/visual") is not None
        if model.findtext("static") == "0":
            assert float(model.findtext("link/inertial/mass")) > 0
            assert model.find("link/collision") is not None
    rug = next(m for m in root.iter("model") if m.get("name").endswith("_rug"))
    assert rug.findtext("static") == "1" and rug.find("link/collision") is None


@pytest.mark.physics
@pytest.mark.parametrize("loader", ["urdf", "sdf"])
def test_items_rest_on_the_building_pieces(client, outputs, small_scene, loader):
    # one convex hull for the building would throw the ground-floor items out of it
    _, nodes = small_scene
    if loader == "urdf":
        bodies = list(_load_urdfs(client, outputs).values())
    else:
        bodies = list(client.loadSDF(str(outputs / "house.world.sdf")))
    before = [client.getBasePositionAndOrientation(b)[0] for b in bodies]
    for _ in range(120):
        client.stepSimulation()
    after = [client.getBasePositionAndOrientation(b)[0] for b in bodies]
    assert np.abs(np.subtract(after, before)).max() < 0.01


def test_item_urdf_has_box_inertia_and_convex_parts(outputs):
    root = ET.parse(outputs / "urdf" / "house.floor1_room0_Bedroom_bed.urdf").getroot()
    link = root.find("link")
    mass = float(link.find("inertial/mass").get("value"))
    inertia = link.find("inertial/inertia")
    # bed 1.6 (width, link x) × 2.0 (depth, link y) × 0.5 (height, link z)
    assert float(inertia.get("ixx")) == pytest.approx(mass * (2.0**2 + 0.5**2) / 12, rel=1e-5)
    assert float(inertia.get("iyy")) == pytest.approx(mass * (1.6**2 + 0.5**2) / 12, rel=1e-5)
    assert float(inertia.get("izz")) == pytest.approx(mass * (1.6**2 + 2.0**2) / 12, rel=1e-5)
    collisions = link.findall("collision")
    assert len(collisions) == 1
    building = ET.parse(outputs / "urdf" / "house.building.urdf").getroot()
    # the building collides through boxes (walls split around openings): no concave mesh
    shapes = [c.find("geometry")[0].tag for c in building.iter("collision")]
    assert shapes and set(shapes) == {"box"}
    for path in [outputs / "house.urdf", *(outputs / "urdf").iterdir()]:
        for element in ET.parse(path).getroot().iter():
            assert "concave" not in element.attrib, path
    assert building.find("gazebo/static").text == "true"


@pytest.mark.parametrize("loader", ["urdf", "sdf"])
def test_known_position_lands_at_ros_coordinates(client, outputs, loader):
    # the bed stands at world x = 2, z = 3 on floor 1 (walking surface y = 3.2, 0.5 m
    # high, one quarter turn): ROS (2, −3, 3.45), yaw 90°
    if loader == "urdf":
        bed = _load_urdfs(client, outputs)["floor1/room0_Bedroom/furniture/bed"]
    else:
        ids = client.loadSDF(str(outputs / "house.world.sdf"))
        bed = next(i for i in ids if client.getBodyInfo(i)[1] == b"floor1_room0_Bedroom_bed")
    position, orientation = client.getBasePositionAndOrientation(bed)
    assert position == pytest.approx((2.0, -3.0, 3.45), abs=1e-6)
    assert client.getEulerFromQuaternion(orientation)[2] == pytest.approx(math.pi / 2)


def test_movable_item_without_mass_is_an_export_error(small_scene, tmp_path):
    scene, nodes = small_scene
    sofa = next(n for n in nodes if n.path.endswith("/sofa"))
    stripped = [n if n is not sofa else type(n)(n.path, n.kind, n.mesh, {}, False, n.parts)
                for n in nodes]
    with pytest.raises(ExportError, match="sofa.*mass"):
        export_urdf(scene, stripped, tmp_path, "house")


def _pedestal_basin(x, z, floor_y):
    """A 20 × 20 cm pedestal 0.7 m high under a 60 × 50 × 20 cm basin that overhangs to
    the front (−z): its centre of mass is not the middle of its bounding box."""
    pedestal = trimesh.creation.box((0.2, 0.7, 0.2))
    pedestal.apply_translation((x, floor_y + 0.35, z))
    basin = trimesh.creation.box((0.6, 0.2, 0.5))
    basin.apply_translation((x, floor_y + 0.8, z - 0.1))
    mesh = trimesh.util.concatenate([pedestal, basin])
    node = SceneNode("floor0/room2_Bathroom/furniture/washbasin", "furniture", mesh,
                     static=False, parts=(pedestal, basin),
                     item=item_info("washbasin", mass=20.0))
    volumes = np.array([0.2 * 0.7 * 0.2, 0.6 * 0.2 * 0.5])
    centres = np.array([[x, floor_y + 0.35, z], [x, floor_y + 0.8, z - 0.1]])
    return node, (volumes[:, None] * centres).sum(axis=0) / volumes.sum()


@pytest.mark.physics
def test_base_pose_is_the_centre_of_mass_and_overhangs_balance(client, small_scene, tmp_path):
    scene, nodes = small_scene
    washbasin, com = _pedestal_basin(7.0, 4.0, scene.floors[0].floor_y)
    export_urdf(scene, [*nodes, washbasin], tmp_path, "house")
    index = json.loads((tmp_path / "house.urdf.json").read_text())
    entry = next(b for b in index["bodies"] if b["node"] == washbasin.path)
    assert entry["base_position"] == pytest.approx([com[0], -com[2], com[1]], abs=1e-6)
    bodies = _load_urdfs(client, tmp_path)
    start = np.array(client.getBasePositionAndOrientation(bodies[washbasin.path])[0])
    assert start == pytest.approx(entry["base_position"], abs=1e-6)
    for _ in range(240):
        client.stepSimulation()
    end = np.array(client.getBasePositionAndOrientation(bodies[washbasin.path])[0])
    assert np.abs(end - start).max() < 0.005


def test_non_convex_user_model_gets_the_same_convex_pieces_as_the_physics_check(tmp_path,
                                                                                  monkeypatch):
    import trimesh

    from cga.collision import collision_parts
    from cga.export.world import robot_world
    from cga.scene import Scene, SceneNode

    monkeypatch.setenv("CGA_CACHE_DIR", str(tmp_path / "cache"))
    slab = trimesh.creation.box(extents=(6.0, 0.2, 6.0))
    slab.apply_translation((0.0, -0.1, 0.0))
    leg = trimesh.creation.box(extents=(0.4, 1.0, 0.4))
    arm = trimesh.creation.box(extents=(1.2, 0.4, 0.4))
    arm.apply_translation((0.4, 0.3, 0.0))
    leg.apply_translation((0.0, 0.5, 0.0))
    el = trimesh.boolean.union([leg, arm], engine="manifold")  # an L: not convex
    item = SceneNode(path="floor0/room0/furniture/sculpture", kind="furniture", mesh=el,
                     item=item_info("sculpture", mass=20.0, convex_parts=False),
                     static=False, parts=(el,))
    scene = Scene(name="t", seed=0, units=1.0, terminals=[])
    world = robot_world(scene, [SceneNode(path="floor0/slab", kind="slab", mesh=slab), item])
    body = world.links[-1]
    pieces = collision_parts(item)
    assert len(pieces) >= 2 and all(
        trimesh.Trimesh(vertices=p.vertices, faces=p.faces).is_convex for p in pieces)
    assert len(body.colliders) == len(pieces)


def test_one_file_urdf_items_fixed_or_floating(small_scene, tmp_path):
    scene, nodes = small_scene
    for items in ("fixed", "floating"):
        export_urdf(scene, nodes, tmp_path / items, "house", items=items)
        root = ET.parse(tmp_path / items / "house.urdf").getroot()
        kinds = {j.find("child").get("link"): j.get("type") for j in root.iter("joint")}
        movable = [n for n in nodes if n.kind == "furniture" and not n.static]
        for node in movable:
            assert kinds[node.path.replace("/furniture/", "/").replace("/", "_")] == items
        assert {k for name, k in kinds.items() if name.endswith("_structure")} == {"fixed"}
        assert {r.get("name") for r in root.iter("robot")} == {"house"}


@pytest.mark.parametrize("up", ["Z", "Y"])
def test_usd_stage_up_axis_puts_the_building_where_the_scene_has_it(small_scene, up):
    pytest.importorskip("pxr")
    from pxr import Usd, UsdGeom

    from cga.export.usd import world_as_stage
    from cga.export.world import robot_world

    scene, nodes = small_scene
    stage = world_as_stage(robot_world(scene, nodes), up=up)
    assert UsdGeom.GetStageUpAxis(stage) == up
    cache = UsdGeom.BBoxCache(Usd.TimeCode.Default(), [UsdGeom.Tokens.default_])
    box = cache.ComputeWorldBound(stage.GetPrimAtPath("/World/building")).ComputeAlignedRange()
    lo, hi = np.array(box.GetMin()), np.array(box.GetMax())
    world = np.array([n.mesh.bounds for n in nodes])
    expected = np.array([world[:, 0].min(axis=0), world[:, 1].max(axis=0)])  # y up
    if up == "Z":
        expected = np.array([_ros_box(trimesh.creation.box(bounds=expected))])[0]
    assert np.allclose([lo, hi], expected, atol=1e-4)


def test_the_robot_formats_share_one_world_and_write_what_each_writes_alone(tmp_path,
                                                                           small_scene):
    """URDF, SDF, MJCF and USD written together make the robot world (collision hulls,
    centres of mass) and the link OBJ texts once, and every file is the same as when
    each format is written alone into a folder of its own."""
    pytest.importorskip("pxr")
    from unittest import mock

    from dataclasses import replace

    from cga.export import mjcf, usd, world

    writers = {"urdf": export_urdf, "sdf": export_sdf, "mjcf": mjcf.export_mjcf,
               "usd": usd.export_usd}
    built, nodes = small_scene
    for fmt, writer in writers.items():  # a copy of the build shares nothing made for it
        writer(replace(built), nodes, tmp_path / "alone" / fmt, "house")
    scene = replace(built)
    with mock.patch.object(world, "_robot_world", wraps=world._robot_world) as made:
        for writer in writers.values():
            writer(scene, nodes, tmp_path / "together", "house")
    assert made.call_count == 1
    together = {p.relative_to(tmp_path / "together"): p.read_bytes()
                for p in (tmp_path / "together").rglob("*") if p.is_file()}
    for fmt in writers:
        folder = tmp_path / "alone" / fmt
        for path in (p for p in folder.rglob("*") if p.is_file()):
            assert together[path.relative_to(folder)] == path.read_bytes(), (fmt, path)
