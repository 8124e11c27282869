"""The meshing pass's hand-written arithmetic against the numpy calls it replaces, bit for
bit (signed zeros included): the glb, OBJ and JSON files write these floats as they are.

Walls and slabs are axis-aligned, so their corners and edges are full of exact zeros and
repeated values; the strategies mix those with random floats of every scale.
"""

from __future__ import annotations

import math

import numpy as np
import trimesh
from hypothesis import example, given, settings
from hypothesis import strategies as st

from cga.mesh import (_crosses, corner_means, face_normals, homogeneous, mirrors,
                      transform_points)
from cga.meshing.items import _pose, item_transform
from cga.model import FurnitureItem, rotation_matrix

coordinate = st.one_of(
    st.sampled_from([0.0, -0.0, 1.0, -1.0, 0.1, 3.2, -2.45]),
    st.floats(min_value=-1e4, max_value=1e4, allow_nan=False, allow_subnormal=False))


def same_bits(a: np.ndarray, b: np.ndarray) -> bool:
    return a.shape == b.shape and np.array_equal(np.asarray(a, dtype=np.float64).view(np.int64),
                                                 np.asarray(b, dtype=np.float64).view(np.int64))


@st.composite
def triangle_arrays(draw) -> np.ndarray:
    count = draw(st.integers(min_value=0, max_value=12))
    values = draw(st.lists(coordinate, min_size=9 * count, max_size=9 * count))
    return np.array(values, dtype=np.float64).reshape(count, 3, 3)


@settings(max_examples=150, deadline=None)
@given(triangle_arrays())
def test_crosses_are_numpy_s_cross_product_bit_for_bit(triangles):
    edges = triangles[:, 1:, :] - triangles[:, :2, :]
    assert same_bits(_crosses(triangles), np.cross(edges[:, 0], edges[:, 1]))
    assert same_bits(_crosses(triangles), trimesh.triangles.cross(triangles))


@settings(max_examples=150, deadline=None)
@given(triangle_arrays())
def test_corner_means_are_numpy_s_mean_bit_for_bit(triangles):
    assert same_bits(corner_means(triangles), triangles.mean(axis=1))


@settings(max_examples=200, deadline=None)
@given(st.lists(st.tuples(coordinate, coordinate, coordinate), max_size=20),
       st.lists(coordinate, min_size=12, max_size=12), st.booleans())
def test_transform_points_is_trimesh_s_bit_for_bit(points, entries, identity):
    matrix = np.eye(4)
    if not identity:
        matrix[:3] = np.reshape(entries, (3, 4))
    points = np.array(points, dtype=np.float64).reshape(-1, 3)
    assert same_bits(transform_points(points, matrix), trimesh.transform_points(points, matrix))
    kept = homogeneous(points)
    assert same_bits(transform_points(points, matrix, stack=kept),
                     trimesh.transform_points(points, matrix))


yaws = st.one_of(st.just(0.0), st.sampled_from([k * math.pi / 2 for k in range(-4, 5)]),
                 st.floats(min_value=-7.0, max_value=7.0, allow_nan=False))
scales = st.one_of(st.just(1.0), st.floats(min_value=1e-3, max_value=1e3))


class Model:
    def __init__(self, size):
        self.size = size


@settings(max_examples=300, deadline=None)
@given(st.integers(min_value=-5, max_value=8), yaws, st.lists(scales, min_size=3, max_size=3))
@example(1, -math.pi / 2, [2.0, 1.0, 0.5])  # turns and yaw cancel exactly: a -0 sine
def test_the_pose_s_linear_part_is_the_turn_times_a_diagonal_scale_bit_for_bit(turns, yaw,
                                                                               scale):
    rotation = rotation_matrix(turns, yaw)
    own = (1.0, 1.0, 1.0)
    item = FurnitureItem(name="thing", model="thing", room=1, position=(0.5, 0.5),
                         rotation=turns, size=tuple(scale), yaw=yaw)
    linear, matrix = _pose(item, Model(own), 0.0)
    scale = [1.0 if abs(k - 1.0) <= 1e-9 else k for k in scale]  # sizes within 1e-9: unscaled
    assert same_bits(np.reshape(linear, (3, 3)), rotation @ np.diag(scale))
    assert same_bits(np.reshape(linear, (3, 3)), matrix[:3, :3])


def reference_transform(item: FurnitureItem, size: tuple[float, float, float],
                        floor_y: float) -> np.ndarray:
    """item_transform as first written, with numpy throughout."""
    target = np.asarray(item.size, dtype=float)
    own = np.asarray(size, dtype=float)
    scale = np.where(np.abs(target - own) <= 1e-9, 1.0, target / own)
    matrix = np.eye(4)
    matrix[:3, :3] = rotation_matrix(item.rotation, item.yaw) @ np.diag(scale)
    matrix[:3, 3] = (item.position[0], floor_y + item.elevation, item.position[1])
    return matrix


extents = st.floats(min_value=0.01, max_value=5.0)


@settings(max_examples=300, deadline=None)
@given(st.tuples(extents, extents, extents), st.lists(st.sampled_from([0.0, 1e-10, 1e-9, 2e-9,
                                                                       -1e-10, 0.3]),
                                                      min_size=3, max_size=3),
       st.integers(min_value=0, max_value=3), yaws, coordinate, coordinate, coordinate)
def test_item_transform_is_the_numpy_formula_bit_for_bit(own, offsets, turns, yaw, x, z, y):
    size = tuple(o + d if o + d > 0 else o for o, d in zip(own, offsets))
    item = FurnitureItem(name="thing", model="thing", room=1, position=(x, z), rotation=turns,
                         size=size, yaw=yaw, elevation=abs(y) / 100)
    assert same_bits(item_transform(item, Model(own), y), reference_transform(item, own, y))


@settings(max_examples=300, deadline=None)
@given(st.integers(min_value=0, max_value=3), yaws,
       st.lists(st.floats(min_value=0.05, max_value=20.0), min_size=3, max_size=3),
       st.lists(st.sampled_from([1.0, -1.0]), min_size=3, max_size=3),
       st.lists(coordinate, min_size=3, max_size=3))
def test_mirrors_is_the_sign_of_the_determinant(turns, yaw, scale, signs, offset):
    """Frames as the meshing layer builds them: a turn about +y, axis scales that may be
    negative (a door hinged on the model's other side, a stair frame), a move."""
    matrix = np.eye(4)
    matrix[:3, :3] = rotation_matrix(turns, yaw) @ np.diag(np.multiply(scale, signs))
    matrix[:3, 3] = offset
    assert mirrors(matrix) == bool(np.linalg.det(matrix[:3, :3]) < 0)


@settings(max_examples=80, deadline=None)
@given(st.lists(triangle_arrays(), min_size=1, max_size=6))
def test_normals_and_centres_of_meshes_together_are_theirs_one_by_one(meshes):
    """The dressing works out a storey's walls together (BLAS sums each row alone)."""
    together = np.concatenate(meshes)
    assert same_bits(face_normals(together)[0],
                     np.concatenate([face_normals(m)[0] for m in meshes]))
    assert same_bits(corner_means(together), np.concatenate([corner_means(m) for m in meshes]))
