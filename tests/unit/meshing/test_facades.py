"""Facade geometry fitted to a storey with an interior (cga.meshing.facades).

The plans are made from rectangles and the openings placed by hand; the expected holes
are computed here from the opening sizes, and points are tested against the meshes'
triangles here, not with the cutting code."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from cga.checks._solids import as_manifold
from cga.meshing import face_mesh
from cga.meshing.facades import FACADE_DEPTH, fit_facade, storey_cutters
from cga.model import FloorSettings, Opening
from cga.operations.floorplan.rectangles import plan_from_rectangles
from cga.scene import SceneNode

DOOR = Opening("door", center=2.0, width=0.9, height=2.1)


@pytest.fixture
def plan():
    """One 4 m × 4 m room, walls 0.2 m thick, a door in the wall along z = 0."""
    plan = plan_from_rectangles([(0, 0, 4, 4)], settings=FloorSettings(windows_per_wall=0))
    front = next(w for w in plan.walls if w.start[1] == 0 and w.end[1] == 0)
    assert front.start == (0.0, 0.0)  # the opening's centre is measured from x = 0
    walls = tuple(w.with_opening(DOOR) if w.id == front.id else w for w in plan.walls)
    return plan.with_changes(walls=walls)


def _on_mesh(mesh: trimesh.Trimesh, point) -> bool:
    """Whether ``point`` lies on one of the mesh's triangles (barycentric test)."""
    triangles = np.asarray(mesh.triangles)
    points = np.repeat([np.asarray(point, dtype=float)], len(triangles), axis=0)
    normals = np.cross(triangles[:, 1] - triangles[:, 0], triangles[:, 2] - triangles[:, 0])
    normals /= np.linalg.norm(normals, axis=1)[:, None]
    in_plane = np.abs(np.einsum("ij,ij->i", points - triangles[:, 0], normals)) < 1e-6
    weights = trimesh.triangles.points_to_barycentric(triangles, points)
    return bool((in_plane & np.all(weights >= -1e-9, axis=1)).any())


def _front_face(plan) -> SceneNode:
    """The storey's front side face: the footprint edge z = 0, seen from −z."""
    y0, y1 = plan.elevation, plan.elevation + plan.height
    vertices = [(4, y0, 0), (0, y0, 0), (0, y1, 0), (4, y1, 0)]
    return SceneNode("Lot/Storey/Facade[0]", "face", face_mesh(vertices, (0, 0, -1)))


def test_a_side_face_loses_exactly_the_door(plan):
    face = _front_face(plan)
    fitted = fit_facade(face, storey_cutters([plan]))
    y = plan.floor_y
    assert fitted is not None and fitted.extras["fitted_to"] == [0]
    assert fitted.mesh.area == pytest.approx(face.mesh.area - DOOR.width * DOOR.height, abs=1e-6)
    assert not _on_mesh(fitted.mesh, (2.0, y + 1.0, 0.0))       # the doorway is open
    assert _on_mesh(fitted.mesh, (2.0, y + DOOR.height + 0.3, 0.0))  # the lintel stays
    assert _on_mesh(fitted.mesh, (0.5, y + 1.0, 0.0))             # beside the door stays


def test_a_mass_before_the_door_and_one_inside_the_room_are_cut_back(plan):
    y = plan.floor_y
    porch = trimesh.creation.box(extents=(3.0, 1.0, 0.5))  # x 0.5–3.5, 0.5 m in front
    porch.apply_translation((2.0, y + 0.5, -0.25))
    cutters = storey_cutters([plan])
    fitted = fit_facade(SceneNode("Lot/Porch", "mass", porch), cutters)
    assert fitted is not None and fitted.mesh.is_watertight
    assert fitted.mesh.volume == pytest.approx(porch.volume - DOOR.width * 1.0 * 0.5, abs=1e-6)
    assert not fitted.mesh.contains([(2.0, y + 0.5, -0.25)])[0]
    assert fitted.mesh.contains([(1.0, y + 0.5, -0.25)])[0]
    column = trimesh.creation.box(extents=(0.3, 2.0, 0.3))  # a pillar in the room
    column.apply_translation((2.0, y + 1.0, 2.0))
    assert fit_facade(SceneNode("Lot/Pillar", "mass", column), cutters) is None


def test_geometry_far_from_the_storey_is_left_alone(plan):
    far = trimesh.creation.box(extents=(1.0, 1.0, 1.0))
    far.apply_translation((2.0, 0.5, -FACADE_DEPTH - 2.0))
    node = SceneNode("Lot/Shed", "mass", far)
    assert fit_facade(node, storey_cutters([plan])) is node


def test_an_open_face_with_a_cut_is_not_a_solid():
    """manifold3d 3.5 crashed (segmentation fault) on this facade bay with a window cut
    out; it is an open surface, so as_manifold must say so without asking manifold3d."""
    vertices = np.array([[14, 0.4, 2.95], [14, 2.7, 2.95], [14, 2.7, 5.0], [14, 0.4, 5.0],
                         [14, 0.4, 4.662074], [14, 0.55, 4.662074], [14, 2.3, 4.662074],
                         [14, 2.3, 4.512074], [14, 2.3, 3.762074], [14, 1.95, 3.762074],
                         [14, 0.4, 3.762074]])
    faces = np.array([[9, 10, 0], [3, 4, 5], [3, 5, 6], [2, 3, 6], [9, 0, 1], [8, 9, 1],
                      [2, 6, 7], [2, 7, 8], [1, 2, 8]])
    assert as_manifold(trimesh.Trimesh(vertices, faces, process=False)) is None
