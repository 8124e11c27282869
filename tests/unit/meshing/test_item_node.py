"""item_node: a placed item's model posed in the world, named and labelled for exporters."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh
from shapely.geometry import box

from cga.model import FloorPlan, FloorSettings, FurnitureItem, Room, front_vector
from cga.meshing.items import item_node, item_transform
from cga.scene import MeshArrays
from cga.operations.furniture.library import ModelLibrary
from cga.resources import shipped_dir

LIBRARY = ModelLibrary([shipped_dir("cga.furniture_models")])
ELEVATION, SLAB = 3.0, 0.2
FLOOR_Y = ELEVATION + SLAB


def plan(room_type: str | None = "Bedroom") -> FloorPlan:
    square = box(0, 0, 10, 10)
    return FloorPlan(index=1, elevation=ELEVATION, height=3.0, footprint=square,
                     settings=FloorSettings(slab_thickness=SLAB),
                     rooms=(Room(id=2, polygon=square, interior=square.buffer(-0.1),
                                 type=room_type),),
                     walls=())


def item(model: str = "chair", rotation: int = 0, size=None, **extra) -> FurnitureItem:
    own = LIBRARY.get(model).size
    return FurnitureItem(name=extra.pop("name", f"{model}1"), model=model, room=2,
                         position=(4.0, 5.0), rotation=rotation,
                         size=own if size is None else size, **extra)


def solid(part: MeshArrays) -> trimesh.Trimesh:
    return trimesh.Trimesh(vertices=part.vertices, faces=part.faces, process=False)


def bounds(part: MeshArrays) -> np.ndarray:
    return np.array([part.vertices.min(axis=0), part.vertices.max(axis=0)])


def test_chair_stands_on_the_floor_at_its_position():
    node = item_node(item(), plan(), LIBRARY)
    lo, hi = node.mesh.bounds
    assert lo[1] == pytest.approx(FLOOR_Y)
    assert (lo[0] + hi[0]) / 2 == pytest.approx(4.0)
    assert (lo[2] + hi[2]) / 2 == pytest.approx(5.0)
    assert hi - lo == pytest.approx(LIBRARY.get("chair").size)


def test_path_kind_and_item_facts():
    node = item_node(item(parent="diningtable"), plan(), LIBRARY)
    model = LIBRARY.get("chair")
    assert node.path == "floor1/room2_Bedroom/furniture/chair1"
    assert node.kind == "furniture"
    assert not node.static
    info = node.item
    assert (info.model, info.room, info.name, info.parent, info.rotation) == (
        "chair", 2, "chair1", "diningtable", 0)
    assert info.model_path == model.path and info.convex_parts
    assert info.density == model.density
    assert info.mass == pytest.approx(model.density * sum(solid(p).volume for p in node.parts))
    assert node.extras == {}
    assert set(node.labels) == {"model", "room", "name", "parent", "rotation", "density",
                                "mass", "convex_parts"}


def test_untyped_room_has_no_type_in_the_path():
    assert item_node(item(), plan(None), LIBRARY).path == "floor1/room2/furniture/chair1"


@pytest.mark.parametrize("rotation", [0, 1, 2, 3, -1, 5])
def test_backrest_is_opposite_the_front(rotation):
    node = item_node(item(rotation=rotation), plan(), LIBRARY)
    above_seat = [p for p in node.parts if bounds(p)[0][1] > FLOOR_Y + 0.46]
    backrest = np.mean([bounds(p).mean(axis=0) for p in above_seat], axis=0)
    offset = backrest[[0, 2]] - np.array([4.0, 5.0])
    front = np.array(front_vector(rotation))
    assert np.dot(offset, front) < -0.1
    assert abs(offset[0] * front[1] - offset[1] * front[0]) < 1e-6, "straight behind"


def test_quarter_turn_faces_minus_x_and_swaps_the_footprint():
    assert front_vector(1) == pytest.approx((-1.0, 0.0))
    w, _, d = LIBRARY.get("sofa").size
    node = item_node(item("sofa", rotation=1), plan(), LIBRARY)
    back = max(node.parts, key=lambda p: bounds(p)[1][1])
    assert bounds(back).mean(axis=0)[0] > 4.0
    extents = node.mesh.extents
    assert (extents[0], extents[2]) == pytest.approx((d, w))


def test_parts_are_posed_like_the_mesh_and_stay_convex():
    node = item_node(item("officechair", rotation=3), plan(), LIBRARY)
    assert len(node.parts) == len(LIBRARY.get("officechair").parts)
    lo = np.min([bounds(p)[0] for p in node.parts], axis=0)
    hi = np.max([bounds(p)[1] for p in node.parts], axis=0)
    assert np.allclose([lo, hi], node.mesh.bounds)
    for part in map(solid, node.parts):
        assert part.is_watertight
        assert part.volume == pytest.approx(part.convex_hull.volume, rel=1e-3)


@pytest.mark.parametrize("model,yaw,size", [("officechair", 0.0, None),
                                            ("sofa", 0.3, (2.3, 0.8, 0.95)),
                                            ("bookshelf", -1.1, None)])
def test_parts_are_arrays_equal_to_each_model_part_moved_alone(model, yaw, size):
    """The parts, sliced from the mesh moved in one pass, carry exactly the bits of
    each model part moved on its own by trimesh (what every check read before)."""
    placed = item(model, rotation=1, yaw=yaw, size=size)
    node = item_node(placed, plan(), LIBRARY)
    source = LIBRARY.get(model)
    matrix = item_transform(placed, source, FLOOR_Y)
    assert len(node.parts) == len(source.parts)
    for part, own in zip(node.parts, source.parts):
        assert isinstance(part, MeshArrays)
        assert np.array_equal(part.vertices, trimesh.transform_points(own.vertices, matrix))
        assert np.array_equal(part.faces, own.faces)
    assert np.array_equal(np.vstack([p.vertices for p in node.parts]), node.mesh.vertices)


def test_door_leaf_is_scaled_to_its_opening():
    model = LIBRARY.get("door")
    size = (1.0, 2.2, model.size[2])
    node = item_node(item("door", rotation=2, size=size, is_detail=True), plan(), LIBRARY)
    assert node.mesh.extents == pytest.approx(size)
    assert node.static
    assert node.item.mass == pytest.approx(model.mass * (1.0 / 0.9) * (2.2 / 2.1), rel=1e-6)


def test_window_sits_at_its_sill():
    node = item_node(item("window", rotation=1, is_detail=True, elevation=0.9), plan(), LIBRARY)
    lo, hi = node.mesh.bounds
    assert lo[1] == pytest.approx(FLOOR_Y + 0.9)
    assert hi[1] == pytest.approx(FLOOR_Y + 0.9 + 1.2)
    assert hi[0] - lo[0] == pytest.approx(0.06)
    assert node.static


def test_rug_is_static():
    assert item_node(item("rug", non_collision=True), plan(), LIBRARY).static


def test_library_model_is_not_modified_by_placing():
    before = LIBRARY.get("chair").mesh.bounds.copy()
    item_node(item(rotation=1, size=(1.0, 1.0, 1.0)), plan(), LIBRARY)
    assert np.array_equal(LIBRARY.get("chair").mesh.bounds, before)


def test_non_positive_size_is_rejected():
    with pytest.raises(ValueError, match="positive"):
        item_node(item(size=(0.5, 0.0, 0.5)), plan(), LIBRARY)
