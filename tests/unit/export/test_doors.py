"""Door leaves on hinges (cga.doors) and door states (type_rooms' door_state).

Expected hinge points, axes and leaf boxes are worked out by hand from the fixture's
plan (conftest.py): an inner wall on x = 5 with a door hinged at its start, an inner wall
on z = 3 with a door hinged at its end, and the front door in the outer wall on z = 6.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest
from shapely.geometry import MultiPoint

from cga.doors import door_leaf
from cga.model import Door
from cga.meshing.solids import wall_footprints
from cga.operations.roomtyping.door_states import AJAR_RANGE, with_door_states

T = 0.04


def _box(leaf, angle):
    corners = leaf.corners(angle)
    return corners.min(axis=0), corners.max(axis=0)


# door id → hinge (x, z), axis y, closed box (x0, x1, z0, z1), open box (x0, x1, z0, z1)
EXPECTED = {
    0: ((5.1, 1.05), 1.0, (5.06, 5.10, 1.055, 1.945), (5.105, 5.995, 1.05, 1.09)),
    1: ((6.95, 3.1), 1.0, (6.055, 6.945, 3.06, 3.10), (6.91, 6.95, 3.105, 3.995)),
    2: ((3.0, 5.8), -1.0, (2.005, 2.995, 5.80, 5.84), (2.96, 3.0, 4.805, 5.795)),
}


@pytest.mark.parametrize("door_id", sorted(EXPECTED))
def test_hinge_axis_and_leaf_box_closed_and_open(small_scene, door_id):
    scene, _ = small_scene
    plan = scene.floors[0]
    door = next(d for d in plan.doors if d.id == door_id)
    leaf = door_leaf(plan, door, T)
    (hx, hz), axis_y, closed, opened = EXPECTED[door_id]
    assert leaf.hinge == pytest.approx((hx, plan.floor_y, hz))
    assert leaf.axis == (0.0, axis_y, 0.0)
    assert (leaf.lower, leaf.upper) == (0.0, pytest.approx(math.pi / 2))
    for angle, (x0, x1, z0, z1) in ((0.0, closed), (math.pi / 2, opened)):
        lo, hi = _box(leaf, angle)
        assert [lo[0], hi[0], lo[2], hi[2]] == pytest.approx([x0, x1, z0, z1], abs=1e-9)
        assert (lo[1], hi[1]) == pytest.approx((plan.floor_y + 0.01,
                                                plan.floor_y + door.height - 0.005))


def test_leaf_clears_every_wall_through_its_range(small_scene):
    scene, _ = small_scene
    for plan in scene.floors:
        for door in plan.doors:
            # the walls seen from above, minus the door's own opening (a doorway-wide band
            # across its wall)
            wall = plan.wall(door.wall)
            along = np.asarray(wall.direction)
            across = np.array([-along[1], along[0]]) * 0.5
            ends = [np.asarray(door.position) + along * s * door.width / 2 for s in (-1, 1)]
            doorway = MultiPoint([ends[0] - across, ends[0] + across, ends[1] - across,
                                  ends[1] + across]).convex_hull
            walls = [w.difference(doorway) if wid == door.wall else w
                     for wid, w in wall_footprints(plan).items()]
            leaf = door_leaf(plan, door, T)
            for angle in np.linspace(0.0, leaf.upper, 31):
                shadow = MultiPoint(leaf.corners(angle)[:, [0, 2]]).convex_hull
                overlap = sum(shadow.intersection(w).area for w in walls)
                assert overlap < 1e-9, (plan.index, door.id, math.degrees(angle))


def test_the_builds_angle_poses_the_leaf(small_scene):
    scene, _ = small_scene
    plan = scene.floors[0]
    door = replace(plan.doors[0], state="ajar", angle=math.radians(30))
    leaf = door_leaf(plan, door, T)
    assert np.allclose(leaf.corners(), leaf.corners(math.radians(30)))
    # 30° about +y from the closed pose: the far edge moved into room 1 (x > 5.1)
    lo, hi = _box(leaf, None)
    assert hi[0] == pytest.approx(5.1 + 0.895 * math.sin(math.radians(30)), abs=1e-9)


def test_door_states_fixed_and_drawn():
    doors = [Door(i, i, (0, 1), (float(i), 0.0), 0.9, 2.1, swing_room=1) for i in range(60)]
    rng = np.random.default_rng(7)
    before = rng.bit_generator.state
    closed = with_door_states(doors, "closed", rng)
    assert {(d.state, d.angle) for d in closed} == {("closed", 0.0)}
    assert rng.bit_generator.state == before  # a fixed state draws nothing
    drawn = with_door_states(doors, "random", np.random.default_rng(7))
    again = with_door_states(doors, "random", np.random.default_rng(7))
    assert drawn == again
    assert {d.state for d in drawn} == {"closed", "open", "ajar"}
    for door in drawn:
        if door.state == "ajar":
            assert AJAR_RANGE[0] <= door.angle <= AJAR_RANGE[1]
        else:
            assert door.angle == (0.0 if door.state == "closed" else pytest.approx(math.pi / 2))
    with pytest.raises(ValueError, match="door_state must be one of"):
        with_door_states(doors, "locked", rng)


@pytest.mark.parametrize("angle", [0.0, 0.3, math.pi / 2, 1.9])
def test_leaf_collision_box_is_trimesh_s_box_and_holds_the_leaf(small_scene, angle):
    """The box part of a door node, made from arrays, is bit for bit the box trimesh
    makes, and its corners are the leaf's."""
    import trimesh

    from cga.meshing.doors import box_arrays

    scene, _ = small_scene
    plan = scene.floors[0]
    for door in plan.doors:
        leaf = door_leaf(plan, replace(door, angle=angle), T)
        centre, extents = leaf.box()
        matrix = leaf.frame() @ trimesh.transformations.translation_matrix(centre)
        box = box_arrays(extents, matrix)
        expected = trimesh.creation.box(extents=extents, transform=matrix)
        assert np.array_equal(box.vertices, expected.vertices)
        assert np.array_equal(box.faces, expected.faces)
        assert trimesh.Trimesh(vertices=box.vertices, faces=box.faces).is_volume
        assert np.allclose(np.sort(box.vertices, axis=0), np.sort(leaf.corners(), axis=0))
