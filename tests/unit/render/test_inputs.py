"""Reading a build's outputs back for rendering (cga render)."""

from __future__ import annotations

import json

import numpy as np
import pytest
import trimesh

from cga.errors import UsageError
from cga.render.inputs import inputs_from_files


def _document(nodes):
    return {"format": "cga.scene", "name": "t", "seed": 4, "floors": [], "rooms": [],
            "nodes": nodes}


def test_a_node_drawn_as_several_primitives_is_one_surface_with_their_colours(tmp_path):
    # a glb node whose geometry hangs in child frames, as trimesh loads a mesh of
    # several primitives
    scene = trimesh.Scene(base_frame="world")
    scene.graph.update(frame_from="world", frame_to="floor0/slab", matrix=np.eye(4))
    for k, (offset, rgba) in enumerate(((0.0, [255, 0, 0, 255]), (3.0, [0, 0, 255, 255]))):
        box = trimesh.creation.box()
        box.visual.face_colors = rgba
        scene.add_geometry(box, node_name=f"floor0/slab_part{k}", geom_name=f"g{k}",
                           parent_node_name="floor0/slab",
                           transform=trimesh.transformations.translation_matrix([offset, 0, 0]))
    (tmp_path / "t.glb").write_bytes(scene.export(file_type="glb"))
    (tmp_path / "t.scene.json").write_text(json.dumps(_document([
        {"path": "floor0/slab", "kind": "slab", "static": True, "class_id": 2,
         "instance_id": 1}])))
    inputs = inputs_from_files(tmp_path / "t.scene.json")
    [surface] = inputs.surfaces
    assert (surface.path, surface.class_id, surface.instance_id) == ("floor0/slab", 2, 1)
    assert len(surface.mesh.faces) == 24
    assert np.allclose(surface.mesh.bounds, [[-0.5, -0.5, -0.5], [3.5, 0.5, 0.5]])
    assert {tuple(c) for c in np.round(surface.colors, 3)} == {(1.0, 0.0, 0.0), (0.0, 0.0, 1.0)}
    assert inputs.seed == 4 and inputs.floors == ()


def test_a_document_from_an_older_build_is_refused_with_the_reason(tmp_path):
    path = tmp_path / "t.scene.json"
    path.write_text(json.dumps(_document([{"path": "a", "kind": "wall", "static": True}])))
    with pytest.raises(UsageError, match="no semantic labels"):
        inputs_from_files(path)
