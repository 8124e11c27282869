"""The ray caster and cameras on meshes whose answers are known in closed form."""

from __future__ import annotations

import math

import numpy as np
import pytest
import trimesh
from hypothesis import given, settings
from hypothesis import strategies as st

pytest.importorskip("embreex", reason="needs the render extra: pip install 'cga[render]'")

from cga.render.cameras import look_level, orthographic_down, perspective  # noqa: E402
from cga.render.raycast import RayScene, Surface  # noqa: E402
from cga.render.views import ViewRenderer  # noqa: E402
from cga.semantics import class_id  # noqa: E402


def _surface(mesh, kind="wall", cls="wall", instance=1):
    colors = np.tile([0.5, 0.5, 0.5], (len(mesh.faces), 1))
    return Surface(f"node{instance}", kind, mesh, class_id(cls), instance, colors)


def _room(size=(6.0, 3.0, 4.0)):
    """A closed box room (walls as one box seen from inside), its corner at the origin."""
    return trimesh.creation.box(extents=size, transform=trimesh.transformations.translation_matrix(
        np.array(size) / 2))


def test_depth_of_a_wall_straight_ahead_is_exact():
    renderer = ViewRenderer([_surface(_room())])
    # at (3, 1.5, 2) looking along −z: the wall z = 0 is 2 m ahead and fills the view
    camera = perspective("v", 8, 6, 60.0, look_level(np.array([3.0, 1.5, 2.0]), 0.0),
                         floor=0, room=0)
    view = renderer.render(camera)
    assert np.all(view.instance == 1) and np.all(view.semantic == class_id("wall"))
    # depth is along the optical axis: the same for every pixel on a wall facing the camera
    assert np.allclose(view.depth, 2.0, rtol=0, atol=1e-6)  # float32 images


def test_slab_faces_looking_down_are_ceiling_and_up_floor():
    slab = trimesh.creation.box(extents=(4.0, 0.2, 4.0),
                                transform=trimesh.transformations.translation_matrix([0, 2.0, 0]))
    rays = RayScene([_surface(slab, kind="slab", cls="floor")])
    origins = np.array([[0.0, 0.0, 0.0], [0.0, 4.0, 0.0]])
    directions = np.array([[0.0, 1.0, 0.0], [0.0, -1.0, 0.0]])
    hits = rays.cast(origins, directions)
    semantic, instance = rays.labels(hits)
    assert semantic.tolist() == [class_id("ceiling"), class_id("floor")]
    assert np.allclose(hits.t, [1.9, 1.9])


def test_rays_that_leave_the_scene_hit_nothing():
    rays = RayScene([_surface(trimesh.creation.box())])
    hits = rays.cast(np.array([[5.0, 0.0, 0.0]]), np.array([[1.0, 0.0, 0.0]]))
    assert hits.triangle.tolist() == [-1] and np.isinf(hits.t[0])
    assert rays.labels(hits)[0].tolist() == [0]


def test_an_empty_scene_renders_sky():
    view = ViewRenderer([]).render(perspective("v", 4, 3, 60.0, np.eye(4), floor=0, room=None))
    assert np.all(view.instance == 0) and np.all(np.isinf(view.depth))


def test_orthographic_view_from_above_puts_pixel_centres_on_the_cell_centres():
    camera = orthographic_down("top", x_min=1.0, z_min=2.0, cols=4, rows=3, pixel=0.5, y=5.0,
                               floor=0)
    origins, directions = camera.rays()
    assert np.allclose(directions, [0.0, -1.0, 0.0])
    assert np.allclose(origins[0], [1.25, 5.0, 2.25])  # row 0, column 0
    assert np.allclose(origins[-1], [2.75, 5.0, 3.25])  # last row, last column
    assert np.isclose(np.linalg.det(camera.camera_to_world[:3, :3]), 1.0)


@settings(max_examples=40, deadline=None)
@given(x=st.floats(0.5, 5.5), z=st.floats(0.5, 3.5), y=st.floats(0.3, 2.7),
       yaw=st.floats(0.0, 2 * math.pi), pitch=st.floats(-0.6, 0.6), fov=st.floats(30.0, 120.0))
def test_depth_reprojects_onto_the_box_walls(x, z, y, yaw, pitch, fov):
    """Inside a closed 6 × 3 × 4 m box every pixel sees a wall: back-projecting its depth
    with the intrinsics and camera_to_world (as a loader would) lands on a face."""
    size = np.array([6.0, 3.0, 4.0])
    camera = perspective("v", 16, 12, fov, look_level(np.array([x, y, z]), yaw, pitch),
                         floor=0, room=0)
    view = _RENDERER.render(camera)
    v, u = np.indices((12, 16))
    local = np.stack([(u - camera.cx) / camera.fx * view.depth, (v - camera.cy) / camera.fy
                      * view.depth, view.depth], axis=-1).reshape(-1, 3)
    world = local @ camera.camera_to_world[:3, :3].T + camera.camera_to_world[:3, 3]
    to_face = np.minimum(np.abs(world), np.abs(world - size)).min(axis=1)
    assert np.all(np.isfinite(view.depth))
    assert np.max(to_face) < 1e-6
    # and projecting the point with K gives back the pixel
    assert np.allclose(local[:, :2] / local[:, 2:] * [camera.fx, camera.fy]
                       + [camera.cx, camera.cy], np.column_stack([u.ravel(), v.ravel()]))


_RENDERER = ViewRenderer([_surface(_room())])


def test_camera_options_are_checked():
    with pytest.raises(ValueError, match="field of view"):
        perspective("v", 4, 3, 180.0, np.eye(4), floor=0, room=None)
    with pytest.raises(ValueError, match="image size"):
        perspective("v", 0, 3, 60.0, np.eye(4), floor=0, room=None)


def test_cameras_look_along_a_corridor_not_into_its_wall():
    from cga.checks.occupancy import OccupancyGrid
    from cga.render.placement import open_yaw

    # a 10 m × 1 m corridor (0.05 m cells) walled all round, the camera near one wall
    occupied = np.zeros((20, 200), dtype=bool)
    occupied[[0, -1], :] = True
    occupied[:, [0, -1]] = True
    grid = OccupancyGrid(occupied=occupied, free_mask=np.ones_like(occupied),
                         origin=(0.0, -1.0), resolution=0.05, floor=0, band=(0.05, 1.2))
    for seed in range(20):
        yaw = open_yaw(grid, 5.0, 0.3, np.random.default_rng(seed))
        forward = look_level(np.zeros(3), yaw)[:3, 2]
        assert abs(forward[0]) > 0.95  # along the corridor (x), either way
