"""Item bodies from per-model mass properties moved by the pose agree with measuring the
posed parts themselves, and items of one model, size and turn share one shape."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely
import trimesh
from shapely.geometry import box

from cga.checks import check_physics, physics
from cga.checks._bullet import obj_objects
from cga.checks._item_solids import FOOT, item_shape, item_solid
from cga.collision import CONTACT_SHRINK, shrink_part
from cga.meshing.items import item_node
from cga.model import FloorPlan, FloorSettings, FurnitureItem, Room
from cga.operations.furniture.library import ModelLibrary
from cga.resources import shipped_dir
from cga.scene import SceneNode

pytestmark = pytest.mark.physics

LIBRARY = ModelLibrary([shipped_dir("cga.furniture_models")])


def _plan() -> FloorPlan:
    square = box(0, 0, 10, 10)
    return FloorPlan(index=0, elevation=0.0, height=3.0, footprint=square,
                     settings=FloorSettings(slab_thickness=0.2),
                     rooms=(Room(id=1, polygon=square, interior=square, type="Office"),),
                     walls=())


def _node(model: str, position=(4.0, 5.0), rotation: int = 0, yaw: float = 0.0,
          stretch=(1.0, 1.0, 1.0), name: str | None = None, plan: FloorPlan | None = None,
          room: int = 1) -> SceneNode:
    size = tuple(s * k for s, k in zip(LIBRARY.get(model).size, stretch))
    item = FurnitureItem(name=name or model, model=model, room=room, position=position,
                         rotation=rotation, yaw=yaw, size=size)
    return item_node(item, plan or _plan(), LIBRARY)


def _posed_centre_of_mass(node: SceneNode) -> tuple[np.ndarray, float]:
    """Volume-weighted centre of the posed parts, each measured as a trimesh solid."""
    meshes = [trimesh.Trimesh(vertices=p.vertices, faces=p.faces, process=False)
              for p in node.parts if len(p.faces)]
    volumes = np.array([m.volume for m in meshes])
    centres = np.array([m.center_mass for m in meshes])
    return (centres * volumes[:, None]).sum(axis=0) / volumes.sum(), float(volumes.sum())


POSES = [dict(), dict(rotation=1), dict(rotation=3, stretch=(1.3, 0.8, 1.1)),
         dict(rotation=2, yaw=math.radians(17), stretch=(0.7, 1.2, 1.4))]


@pytest.mark.parametrize("model", ["chair", "diningtable", "wardrobe", "sofa"])
@pytest.mark.parametrize("pose", POSES, ids=["plain", "quarter", "stretched", "yawed"])
def test_model_mass_properties_moved_by_the_pose_match_the_posed_parts(model, pose):
    node = _node(model, **pose)
    solid, linear, offset = item_solid(node)
    assert solid.shared
    expected, volume = _posed_centre_of_mass(node)
    assert linear @ solid.centroid + offset == pytest.approx(expected, abs=1e-9)
    assert solid.volume * abs(np.linalg.det(linear)) == pytest.approx(volume, rel=1e-9)


@pytest.mark.parametrize("pose", POSES, ids=["plain", "quarter", "stretched", "yawed"])
def test_shape_is_the_shrunk_posed_parts_about_the_centre_of_mass(pose):
    node = _node("chair", **pose)
    solid, linear, offset = item_solid(node)
    centre = linear @ solid.centroid + offset
    shape = item_shape(solid, linear)
    objects = obj_objects(shape.text)
    parts = [p for p in node.parts if len(p.faces)]
    assert len(objects) == len(parts)
    for points, part in zip(objects, parts):
        expected = shrink_part(np.asarray(part.vertices)) - centre
        assert points == pytest.approx(expected, abs=1e-8)
        # every face of an axis-aligned part moved in by the shrink
        if not pose.get("yaw"):
            extent = np.ptp(part.vertices, axis=0)
            assert np.ptp(points, axis=0) == pytest.approx(
                np.maximum(extent - 2 * CONTACT_SHRINK, extent / 2), abs=1e-8)
    vertices = np.concatenate([p.vertices for p in parts])
    assert centre[1] + shape.lowest == pytest.approx(vertices[:, 1].min(), abs=1e-9)
    feet = vertices[vertices[:, 1] <= vertices[:, 1].min() + FOOT][:, [0, 2]]
    gap = shapely.MultiPoint(feet).convex_hull.distance(shapely.Point(centre[0], centre[2]))
    assert shape.support_gap == pytest.approx(gap, abs=1e-9)


def test_items_of_one_model_size_and_turn_share_a_shape():
    a, b = _node("chair", (2.0, 2.0), name="a"), _node("chair", (7.3, 6.1), name="b")
    turned = _node("chair", (5.0, 8.0), rotation=1, name="c")
    solids = [item_solid(n) for n in (a, b, turned)]
    shapes = [item_shape(s, linear) for s, linear, _ in solids]
    assert shapes[0] is shapes[1]
    assert shapes[2].name != shapes[0].name


def test_node_without_model_facts_is_measured_where_it_is(kit):
    mesh = kit.box_mesh((1.0, 0.5, 2.0), (3.0, 0.45, 4.0))
    node = kit.box_item("crate", (1.0, 0.5, 2.0), (3.0, 4.0))
    solid, linear, offset = item_solid(node)
    assert not solid.shared
    assert np.array_equal(linear, np.eye(3)) and not offset.any()
    assert solid.centroid == pytest.approx(mesh.center_mass)
    assert solid.volume == pytest.approx(1.0)


def test_shared_shapes_give_each_item_its_own_result(kit, two_rooms):
    chairs = [_node("chair", (1.0 + i, 2.0), name=f"chair{i}", plan=two_rooms, room=0)
              for i in range(3)]
    report = check_physics(kit.scene_of(two_rooms), kit.structure(two_rooms) + chairs)
    assert report.passed, report.summary()
    assert [i.name for i in report.items] == ["chair0", "chair1", "chair2"]
    assert [i.mass for i in report.items] == pytest.approx([chairs[0].item.mass] * 3)


def test_world_makes_one_pybullet_shape_per_distinct_shape(kit, two_rooms, monkeypatch):
    made = []
    original = physics._World._shape

    def counting(self, shape, path):
        before = len(self.shapes)
        uid = original(self, shape, path)
        made.append(len(self.shapes) > before)
        return uid

    monkeypatch.setattr(physics._World, "_shape", counting)
    chairs = [_node("chair", (1.0 + i, 2.0), name=f"chair{i}", plan=two_rooms, room=0)
              for i in range(3)]
    chairs.append(_node("chair", (2.0, 3.0), rotation=1, name="turned", plan=two_rooms, room=0))
    check_physics(kit.scene_of(two_rooms), kit.structure(two_rooms) + chairs)
    assert made == [True, False, False, True]
