"""Cutting the building's structure into convex pieces for the physics check."""

from __future__ import annotations

import numpy as np
import trimesh
from scipy.spatial import ConvexHull
from shapely.geometry import Polygon

from cga.checks._solids import convex_pieces as _arrays_of_pieces


def _box(lo, hi) -> trimesh.Trimesh:
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)
    return trimesh.creation.box(extents=hi - lo).apply_translation((lo + hi) / 2)


def convex_pieces(mesh: trimesh.Trimesh) -> list[trimesh.Trimesh] | None:
    """The pieces as trimesh solids (the function gives vertex and face arrays)."""
    pieces = _arrays_of_pieces(mesh)
    if pieces is None:
        return None
    return [p if isinstance(p, trimesh.Trimesh)
            else trimesh.Trimesh(vertices=p.vertices, faces=p.faces, process=False)
            for p in pieces]


def _is_box(mesh: trimesh.Trimesh) -> bool:
    return abs(np.prod(mesh.extents) - mesh.volume) <= 1e-6 * mesh.volume


def _tiles(pieces: list[trimesh.Trimesh], solid: trimesh.Trimesh) -> bool:
    """The pieces fill the solid without overlapping: their volumes add up to the
    solid's, and so does the volume of their union."""
    union = trimesh.boolean.union(pieces, engine="manifold") if len(pieces) > 1 else pieces[0]
    total = sum(p.volume for p in pieces)
    return abs(total - solid.volume) < 1e-5 and abs(union.volume - solid.volume) < 1e-5


def _is_convex(mesh: trimesh.Trimesh) -> bool:
    return abs(ConvexHull(mesh.vertices).volume - mesh.volume) <= 1e-6 * mesh.volume


def test_convex_mesh_is_kept_whole():
    box = _box((0, 0, 0), (4, 3, 0.2))
    assert _arrays_of_pieces(box) == [box]


def test_wall_with_door_and_window_becomes_boxes():
    wall = _box((0, 0, 0), (5, 3, 0.2))
    door = _box((1, -0.1, -0.1), (1.9, 2.1, 0.3))
    window = _box((3, 0.9, -0.1), (4.2, 2.1, 0.3))
    solid = trimesh.boolean.difference([wall, door, window], engine="manifold")
    pieces = convex_pieces(solid)
    assert pieces is not None and len(pieces) > 1
    assert all(_is_convex(p) and _is_box(p) for p in pieces)
    assert _tiles(pieces, solid)
    # No piece reaches into an opening.
    for piece in pieces:
        centre = piece.bounds.mean(axis=0)
        assert not (1 < centre[0] < 1.9 and centre[1] < 2.1)
        assert not (3 < centre[0] < 4.2 and 0.9 < centre[1] < 2.1)


def test_l_shaped_slab_becomes_boxes():
    outline = Polygon([(0, 0), (8, 0), (8, 4), (4, 4), (4, 8), (0, 8)])
    slab = trimesh.creation.extrude_polygon(outline, 0.2)
    pieces = convex_pieces(slab)
    assert pieces is not None and len(pieces) >= 2
    assert all(_is_convex(p) for p in pieces)
    assert _tiles(pieces, slab)


def test_open_surface_gives_none():
    sheet = trimesh.Trimesh(vertices=[[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]],
                            faces=[[0, 1, 2], [0, 2, 3]])
    assert convex_pieces(sheet) is None


def test_slanted_wall_is_cut_exactly_or_left_whole():
    wall = _box((0, 0, 0), (5, 3, 0.2))
    door = _box((1, -0.1, -0.1), (1.9, 2.1, 0.3))
    solid = trimesh.boolean.difference([wall, door], engine="manifold")
    solid.apply_transform(trimesh.transformations.rotation_matrix(np.radians(30), (0, 1, 0)))
    pieces = convex_pieces(solid)
    if pieces is not None:
        assert all(_is_convex(p) for p in pieces)
        assert abs(sum(p.volume for p in pieces) - solid.volume) < 1e-5


def test_ring_of_walls_is_cut_into_convex_pieces():
    ring = trimesh.creation.extrude_polygon(
        Polygon([(0, 0), (4, 0), (4, 4), (0, 4)], [[(0.2, 0.2), (3.8, 0.2), (3.8, 3.8), (0.2, 3.8)]]),
        2.5)
    pieces = convex_pieces(ring)
    assert pieces is not None and len(pieces) >= 4
    assert all(_is_convex(p) for p in pieces)
    assert _tiles(pieces, ring)
