"""Meshing of masses and faces, and the glTF document built from scene nodes."""

from __future__ import annotations

import io
import json
import struct

import numpy as np
import pytest
import trimesh
from shapely.geometry import Polygon, box

from cga.errors import ExportError
from cga.export.glb import export_glb, json_safe, scene_as_glb
from cga.meshing import face_mesh, footprint_mesh, mass_mesh, scene_nodes
from cga.scene import Scene, SceneNode
from cga.shape import Face, Mass, Scope, Shape

L_SHAPE = Polygon([(0, 0), (14, 0), (14, 6), (8, 6), (8, 10), (0, 10)])


def terminal(path, geometry):
    scope = geometry.scope() if isinstance(geometry, Mass) else Scope(origin=(0, 0, 0))
    return Shape(symbol=path[-1], path=path, scope=scope, geometry=geometry, attrs={"index": 1})


def gltf_json(data: bytes) -> dict:
    """The JSON chunk of a GLB (spec: 12-byte header, then chunk length + type)."""
    length, kind = struct.unpack_from("<I4s", data, 12)
    assert kind == b"JSON"
    return json.loads(data[20:20 + length])


def test_mass_mesh_is_watertight_prism_in_place():
    mesh = mass_mesh(Mass(L_SHAPE, base=2.0, height=3.0))
    assert mesh.is_watertight and mesh.is_winding_consistent
    assert mesh.volume == pytest.approx(L_SHAPE.area * 3)  # positive: normals point out
    assert np.allclose(mesh.bounds, [[0, 2, 0], [14, 5, 10]])
    # the notch of the L (x > 8, z > 6) is empty: no vertex lies strictly inside it
    v = mesh.vertices
    assert not np.any((v[:, 0] > 8.001) & (v[:, 2] > 6.001))


def test_mass_without_height_is_refused_and_flat_lot_faces_up():
    with pytest.raises(ValueError):
        mass_mesh(Mass(L_SHAPE, 0.0, 0.0))
    courtyard = Polygon(box(0, 0, 10, 10).exterior.coords, [box(4, 4, 6, 6).exterior.coords])
    flat = footprint_mesh(Mass(courtyard, 1.0, 0.0))
    assert flat.area == pytest.approx(96)
    assert np.allclose(flat.face_normals, [0, 1, 0])
    assert np.allclose(flat.vertices[:, 1], 1.0)


def test_face_mesh_faces_outward():
    # counter-clockwise seen from +x: normal +x
    mesh = face_mesh([(0, 0, 5), (0, 0, 0), (0, 3, 0), (0, 3, 5)])
    assert mesh.area == pytest.approx(15)
    assert np.allclose(mesh.face_normals, [1, 0, 0])


def test_scene_nodes_for_masses_and_faces_named_by_path():
    face = Face(vertices=((0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)), kind="side")
    scene = Scene(name="t", seed=0, units=1.0, terminals=[
        terminal(("Lot", "Body[0]"), Mass(L_SHAPE, 0, 3)),
        terminal(("Lot", "Wall[1]"), face),
        terminal(("Lot", "Yard[2]"), Mass(box(20, 0, 25, 5), 0, 0))])
    nodes = scene_nodes(scene)
    assert [(n.path, n.kind) for n in nodes] == [
        ("Lot/Body[0]", "mass"), ("Lot/Wall[1]", "face"), ("Lot/Yard[2]", "face")]
    assert nodes[0].extras == {"symbol": "Body[0]", "shape_path": "Lot/Body[0]", "index": 1}
    assert nodes[1].extras["face"] == "side"


def _nodes():
    return [SceneNode(path="Lot/A[0]", kind="mass", mesh=mass_mesh(Mass(box(0, 0, 2, 1), 0, 3)),
                      extras={"floor": np.int64(2), "tags": ("x", "y")}),
            SceneNode(path="Lot/B[1]", kind="mass", mesh=mass_mesh(Mass(box(5, 5, 6, 6), 1, 1)),
                      extras={})]


def _scene():
    return Scene(name="t", seed=4, units=1.0, terminals=[])


def test_glb_nodes_named_by_path_with_extras_and_world_positions():
    data = scene_as_glb(_scene(), _nodes())
    doc = gltf_json(data)
    names = [n["name"] for n in doc["nodes"]]
    # a tree along the paths: the building, the group "Lot", its two shapes
    assert names == ["t", "Lot", "Lot/A[0]", "Lot/B[1]"]
    assert [doc["nodes"][i]["name"] for i in doc["scenes"][0]["nodes"]] == ["t"]
    assert doc["nodes"][0]["children"] == [1] and doc["nodes"][1]["children"] == [2, 3]
    assert doc["nodes"][2]["extras"] == {"floor": 2, "kind": "mass", "static": True,
                                         "tags": ["x", "y"], "class": "building",
                                         "class_id": 8, "instance_id": 1}
    assert all("matrix" not in n for n in doc["nodes"])
    loaded = trimesh.load(io.BytesIO(data), file_type="glb")
    assert sorted(loaded.graph.nodes_geometry) == ["Lot/A[0]", "Lot/B[1]"]
    assert np.allclose(loaded.bounds, [[0, 0, 0], [6, 3, 6]])
    assert loaded.geometry["Lot/B[1]"].is_watertight


def test_glb_bytes_are_deterministic(tmp_path):
    first = scene_as_glb(_scene(), _nodes())
    assert scene_as_glb(_scene(), _nodes()) == first
    [path] = export_glb(_scene(), _nodes(), tmp_path, "t")
    assert path == tmp_path / "t.glb" and path.read_bytes() == first


def test_glb_rejects_duplicate_paths_and_non_json_extras():
    node = _nodes()[0]
    with pytest.raises(ExportError, match="both named 'Lot/A\\[0\\]'"):
        scene_as_glb(_scene(), [node, node])
    bad = SceneNode(path="x", kind="mass", mesh=node.mesh, extras={"f": object()})
    with pytest.raises(ExportError, match="node 'x': cannot store a object"):
        scene_as_glb(_scene(), [bad])


def test_json_safe():
    assert json_safe({"b": (1, np.float32(2.5)), "a": {3, 1}, "c": np.arange(2)}) == {
        "a": [1, 3], "b": [1, 2.5], "c": [0, 1]}
    assert list(json_safe({"b": 1, "a": 2})) == ["a", "b"]
