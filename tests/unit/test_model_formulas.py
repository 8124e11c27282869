"""The core data model's plain-float formulas give exactly what the numpy and shapely
formulas they replaced gave (issue #21: same bytes, less time).

Each old formula is kept here as the reference, and compared bit for bit (coordinates
through their ``float.hex``, so signed zeros count) on random inputs.
"""

from __future__ import annotations

import math

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from shapely import affinity
from shapely.geometry import box

from cga.doors import DoorLeaf, rotation_about_y
from cga.model import OUTSIDE, FurnitureItem, Wall, front_vector, rotation_matrix

SIZES = st.floats(0.01, 5.0, allow_nan=False)
COORDS = st.floats(-100.0, 100.0, allow_nan=False)
YAWS = st.one_of(st.just(0.0), st.just(-0.0), st.floats(-math.pi, math.pi, allow_nan=False))


def _bits(values) -> list[str]:
    return [float(v).hex() for v in np.asarray(values, dtype=float).ravel()]


def _old_footprint(item: FurnitureItem):
    w, _, d = item.size
    rect = box(-w / 2, -d / 2, w / 2, d / 2)
    rect = affinity.rotate(rect, -90 * (item.rotation % 4), origin=(0, 0))
    if item.yaw:
        rect = affinity.rotate(rect, -item.yaw, origin=(0, 0), use_radians=True)
    return affinity.translate(rect, *item.position)


@settings(max_examples=300, deadline=None)
@given(w=SIZES, d=SIZES, x=COORDS, z=COORDS, rotation=st.integers(-5, 9), yaw=YAWS)
def test_footprint_matches_shapely_affinity(w, d, x, z, rotation, yaw):
    item = FurnitureItem("a", "chair", 1, (x, z), rotation, (w, 1.0, d), yaw=yaw)
    new, old = item.footprint(), _old_footprint(item)
    assert _bits(new.exterior.coords) == _bits(old.exterior.coords)


def _old_front_vector(quarter_turns: int, yaw: float) -> tuple[float, float]:
    v = rotation_matrix(quarter_turns, yaw) @ np.array([0.0, 0.0, -1.0])
    return (float(v[0]), float(v[2]))


QUARTER_YAWS = st.sampled_from([-math.pi, -math.pi / 2, math.pi / 2, math.pi, 2 * math.pi])


@settings(max_examples=300, deadline=None)
@given(rotation=st.integers(-5, 9), yaw=st.one_of(YAWS, QUARTER_YAWS))
def test_front_vector_matches_the_rotation_matrix(rotation, yaw):
    assert _bits(front_vector(rotation, yaw)) == _bits(_old_front_vector(rotation, yaw))


def test_rotation_matrix_has_no_negative_zero_without_yaw():
    for q in range(4):
        assert all(math.copysign(1.0, v) > 0 for v in rotation_matrix(q).ravel() if v == 0)


@st.composite
def walls(draw):
    """A wall along an axis (most of them) or slanted, inner or outer, on either side."""
    sx, sz = draw(COORDS), draw(COORDS)
    kind = draw(st.sampled_from(["x", "z", "slant"]))
    ex = sx if kind == "z" else draw(COORDS.filter(lambda v: v != sx))
    ez = sz if kind == "x" else draw(COORDS.filter(lambda v: v != sz))
    outer = draw(st.booleans())
    rooms = draw(st.sampled_from([(1, OUTSIDE), (OUTSIDE, 1)] if outer else [(1, 2)]))
    return Wall(0, (sx, sz), (ex, ez), outer, rooms, draw(st.floats(0.05, 0.5)))


def _old_band_corners(wall: Wall, before: float, after: float) -> np.ndarray:
    d = np.array(wall.unit())
    n = np.array([-d[1], d[0]])
    a = np.asarray(wall.start) - d * before
    b = np.asarray(wall.end) + d * after
    lo, hi = wall.band()
    return np.array([a + n * lo, b + n * lo, b + n * hi, a + n * hi])


@settings(max_examples=300, deadline=None)
@given(wall=walls(), before=st.floats(0.0, 1.0), after=st.floats(0.0, 1.0))
def test_wall_vectors_match_numpy(wall, before, after):
    d = np.array(wall.unit())
    normal = np.array([-d[1], d[0]])
    assert _bits(wall.direction) == _bits(d)
    assert _bits(wall.normal) == _bits(normal)
    for room in wall.rooms:
        old = normal if room == wall.rooms[0] else -normal
        assert _bits(wall.normal_into(room)) == _bits(old)
    assert _bits(wall.band_corners(before, after)) == _bits(_old_band_corners(wall, before, after))


def _old_frame(leaf: DoorLeaf, angle: float | None) -> np.ndarray:
    turn = leaf.angle if angle is None else angle
    x = np.array([leaf.along[0], 0.0, leaf.along[1]])
    y = np.array([0.0, 1.0, 0.0])
    closed = np.column_stack([x, y, np.cross(x, y)])
    matrix = np.eye(4)
    matrix[:3, :3] = rotation_about_y(turn * leaf.axis[1]) @ closed
    matrix[:3, 3] = leaf.hinge
    return matrix


UNITS = st.one_of(st.sampled_from([(1.0, 0.0), (-1.0, 0.0), (0.0, 1.0), (0.0, -1.0),
                                   (-0.0, 1.0), (1.0, -0.0)]),
                  st.floats(-math.pi, math.pi).map(lambda t: (math.cos(t), math.sin(t))))


@settings(max_examples=300, deadline=None)
@given(along=UNITS, axis=st.sampled_from([1.0, -1.0]), hinge=st.tuples(COORDS, COORDS, COORDS),
       angle=st.one_of(st.none(), st.just(0.0), st.floats(0.0, math.pi)))
def test_door_frame_matches_np_cross(along, axis, hinge, angle):
    leaf = DoorLeaf(0, 1, (1, 2), 1, "ajar", 0.3, hinge, along, (0.0, axis, 0.0),
                    (0.8, 2.0, 0.04))
    assert _bits(leaf.frame(angle)) == _bits(_old_frame(leaf, angle))


@settings(max_examples=100, deadline=None)
@given(along=UNITS, axis=st.sampled_from([1.0, -1.0]), hinge=st.tuples(COORDS, COORDS, COORDS),
       angle=st.one_of(st.none(), st.floats(0.0, math.pi)))
def test_door_corners_match_the_old_formula(along, axis, hinge, angle):
    leaf = DoorLeaf(0, 1, (1, 2), 1, "ajar", 0.3, hinge, along, (0.0, axis, 0.0),
                    (0.8, 2.0, 0.04))
    centre, extents = leaf.box()
    signs = np.array([[i, j, k] for i in (-1, 1) for j in (-1, 1) for k in (-1, 1)])
    matrix = _old_frame(leaf, angle)
    old = (centre + signs * extents / 2) @ matrix[:3, :3].T + matrix[:3, 3]
    assert _bits(leaf.corners(angle)) == _bits(old)
