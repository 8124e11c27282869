"""Dressing's shortcuts against what they replace: the node copy against
``dataclasses.replace``, the used-material set against ``np.bincount``."""

from __future__ import annotations

from dataclasses import fields, replace

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from cga.appearance.dress import _KEPT, _compact, _dressed
from cga.appearance.material import Material
from cga.mesh import TriangleMesh
from cga.scene import SceneNode


def test_the_dressed_copy_names_every_field_of_a_scene_node():
    assert {f.name for f in fields(SceneNode)} == {*_KEPT, "materials", "face_materials"}


def test_the_dressed_copy_is_dataclasses_replace():
    node = SceneNode("floor0/room1/wall2", "wall", TriangleMesh(np.eye(3), [[0, 1, 2]]),
                     extras={"wall_id": 2}, static=False)
    materials = (Material.of("paint", "wall", (0.5, 0.5, 0.5), 0.5, 0.0, 1.0),)
    index = np.zeros(1, dtype=np.int64)
    dressed = _dressed(node, materials, index)
    expected = replace(node, materials=materials, face_materials=index)
    assert all(getattr(dressed, f.name) is getattr(expected, f.name) for f in fields(SceneNode))


def reference_compact(materials, index):
    """_compact as first written: the used candidates found with np.bincount."""
    used = set(np.flatnonzero(np.bincount(index, minlength=len(materials))).tolist())
    unique, order = {}, []
    remap = np.zeros(len(materials), dtype=np.int64)
    for k, m in enumerate(materials):
        if k in used:
            if m.name not in unique:
                unique[m.name] = len(order)
                order.append(m)
            remap[k] = unique[m.name]
    return tuple(order), remap[index]


@settings(max_examples=200, deadline=None)
@given(st.lists(st.sampled_from("abcd"), min_size=1, max_size=8).flatmap(  # names repeat
    lambda names: st.tuples(st.just(names), st.lists(
        st.integers(min_value=0, max_value=len(names) - 1), max_size=40))))
def test_compact_is_the_bincount_formula(case):
    names, faces = case
    materials = [Material.of(n, "wall", (0.5, 0.5, 0.5), 0.5, 0.0, 1.0) for n in names]
    index = np.array(faces, dtype=np.int64)
    order, remapped = _compact(materials, index)
    expected_order, expected_index = reference_compact(materials, index)
    assert order == expected_order
    assert remapped.dtype == expected_index.dtype
    assert np.array_equal(remapped, expected_index)
