"""Cutting rectilinear solids on their cell grid gives the pieces the manifold3d plane
splits give, in the same order."""

from __future__ import annotations

import numpy as np
import shapely.affinity
import trimesh
from hypothesis import given, settings
from hypothesis import strategies as st
from shapely.geometry import Polygon

from cga.checks._boxes import box_pieces
from cga.checks._solids import convex_pieces


def _box(lo, hi) -> trimesh.Trimesh:
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)
    return trimesh.creation.box(extents=hi - lo).apply_translation((lo + hi) / 2)


def _boxes_of(pieces) -> list[tuple[float, ...]]:
    """Each piece's bounding box, in piece order."""
    return [tuple(np.r_[np.min(p.vertices, axis=0), np.max(p.vertices, axis=0)].round(9))
            for p in pieces]


def _same_as_manifold(solid: trimesh.Trimesh) -> None:
    grid, cut = box_pieces(solid), convex_pieces(solid)
    assert grid is not None
    assert cut is not None
    assert _boxes_of(grid) == _boxes_of(cut)
    assert (grid[0] is solid) == (cut[0] is solid)
    for piece in grid:  # closed boxes, wound outwards
        mesh = trimesh.Trimesh(vertices=piece.vertices, faces=piece.faces, process=False)
        assert mesh.is_watertight and mesh.volume > 0
        assert abs(np.prod(mesh.extents) - mesh.volume) <= 1e-9 * mesh.volume


def test_structure_of_the_demo_house_cuts_like_manifold():
    from pathlib import Path

    from cga.checks.physics import structure_nodes
    from cga.pipeline import build

    grammar = Path(__file__).resolve().parents[3] / "demos" / "house.grammar"
    scene = build(grammar, seed=0, formats=(), physics=False, quiet=True)
    read = 0
    for node in structure_nodes(scene.nodes):
        if len(node.mesh.faces) and box_pieces(node.mesh) is not None:
            _same_as_manifold(node.mesh)
            read += 1
    assert read >= 40  # walls, slabs and stairs of two storeys


def test_box_is_kept_whole():
    box = _box((0, 0, 0), (4, 3, 0.2))
    assert box_pieces(box) == [box]


def test_wall_with_door_and_window():
    wall = _box((0, 0, 0), (5, 3, 0.2))
    door = _box((1, -0.1, -0.1), (1.9, 2.1, 0.3))
    window = _box((3, 0.9, -0.1), (4.2, 2.1, 0.3))
    _same_as_manifold(trimesh.boolean.difference([wall, door, window], engine="manifold"))


def test_l_shaped_slab_needs_the_hull_test():
    outline = Polygon([(0, 0), (8, 0), (8, 4), (4, 4), (4, 8), (0, 8)])
    _same_as_manifold(trimesh.creation.extrude_polygon(outline, 0.2))


def test_ring_of_walls():
    ring = trimesh.creation.extrude_polygon(
        Polygon([(0, 0), (4, 0), (4, 4), (0, 4)],
                [[(0.2, 0.2), (3.8, 0.2), (3.8, 3.8), (0.2, 3.8)]]), 2.5)
    _same_as_manifold(ring)


def test_solids_it_cannot_read_as_cells_are_left_to_manifold():
    wall = _box((0, 0, 0), (5, 3, 0.2))
    door = _box((1, -0.1, -0.1), (1.9, 2.1, 0.3))
    slanted = trimesh.boolean.difference([wall, door], engine="manifold")
    slanted.apply_transform(trimesh.transformations.rotation_matrix(np.radians(30), (0, 1, 0)))
    assert box_pieces(slanted) is None
    sheet = trimesh.Trimesh(vertices=[[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]],
                            faces=[[0, 1, 2], [0, 2, 3]])
    assert box_pieces(sheet) is None
    sliver = trimesh.boolean.union([_box((0, 0, 0), (1, 1, 1)), _box((1, 0, 0), (2, 1.0005, 1))],
                                   engine="manifold")
    assert box_pieces(sliver) is None  # two planes 0.5 mm apart


def test_a_box_with_a_collinear_sliver_triangle_is_read_as_cells():
    """A union of boxes left a T-junction on one face: a triangle whose corners lie on
    one edge. It bounds nothing, so it must not make the solid unreadable."""
    vertices = [[0, 0, 0], [0, 0, 0.5], [0, 0.5, 0], [0, 0.5, 0.5], [0.25, 0, 0],
                [0.25, 0, 0.25], [0.25, 0, 0.5], [0.25, 0.25, 0], [0.25, 0.5, 0],
                [0.25, 0.5, 0.5]]
    faces = [[5, 4, 7], [0, 4, 1], [0, 2, 4], [0, 1, 3], [0, 3, 2], [1, 9, 3], [2, 3, 9],
             [1, 4, 5], [1, 5, 6], [1, 6, 9], [6, 5, 8], [2, 8, 4], [2, 9, 8], [4, 8, 7],
             [8, 5, 7], [6, 8, 9]]
    solid = trimesh.Trimesh(vertices=vertices, faces=faces, process=False)
    assert solid.is_watertight and abs(solid.volume - 0.0625) < 1e-12
    assert box_pieces(solid) == [solid]  # one box: the mesh itself


_cells = st.integers(min_value=0, max_value=6)


@st.composite
def _rectilinear_solids(draw) -> trimesh.Trimesh:
    """A union of boxes on a 0.25 m lattice, with up to two boxes cut out."""
    def box():
        lo = [draw(_cells) for _ in range(3)]
        hi = [v + draw(st.integers(min_value=1, max_value=4)) for v in lo]
        return _box(np.multiply(lo, 0.25), np.multiply(hi, 0.25))
    solid = trimesh.boolean.union([box() for _ in range(draw(st.integers(1, 3)))],
                                  engine="manifold")
    holes = [box() for _ in range(draw(st.integers(0, 2)))]
    if holes:
        solid = trimesh.boolean.difference([solid, *holes], engine="manifold")
    return solid


@settings(max_examples=60, deadline=None)
@given(_rectilinear_solids())
def test_random_rectilinear_solids_are_tiled_by_boxes(solid):
    """Exact on any rectilinear solid: boxes that fill it without overlapping. (Where a
    manifold3d split leaves a zero-thickness flap on a piece, ``convex_pieces`` cuts that
    piece once more, so the two may differ in how finely they cut, not in what they
    cover.)"""
    if len(solid.faces) == 0 or not solid.is_watertight:
        return
    pieces = box_pieces(solid)
    assert pieces is not None
    meshes = [p if isinstance(p, trimesh.Trimesh)
              else trimesh.Trimesh(vertices=p.vertices, faces=p.faces, process=False)
              for p in pieces]
    for mesh in meshes:
        assert mesh.is_watertight and mesh.volume > 0
        assert abs(np.prod(mesh.extents) - mesh.volume) <= 1e-9 * mesh.volume
    union = trimesh.boolean.union(meshes, engine="manifold") if len(meshes) > 1 else meshes[0]
    assert abs(sum(m.volume for m in meshes) - solid.volume) < 1e-6
    assert abs(union.volume - solid.volume) < 1e-6


def _extruded(outline, thickness: float, axes: tuple[int, int, int]) -> trimesh.Trimesh:
    """``outline`` extruded by ``thickness``, with the outline's x, y and the extrusion
    placed on the world axes ``axes``: an exact permutation of coordinates (no rotation
    to round them off the axes), with the triangles turned when it mirrors."""
    solid = trimesh.creation.extrude_polygon(outline, thickness)
    vertices = np.empty_like(solid.vertices)
    vertices[:, list(axes)] = solid.vertices
    faces = solid.faces if axes in ((0, 1, 2), (1, 2, 0), (2, 0, 1)) else solid.faces[:, ::-1]
    return trimesh.Trimesh(vertices=vertices, faces=faces, process=False)


@st.composite
def _walls(draw) -> trimesh.Trimesh:
    """A wall on a 0.1 m lattice, along x or z, with up to three doors (from the floor)
    and windows through it, wall left between each two."""
    length, height = draw(st.integers(10, 60)), draw(st.integers(12, 30))
    count = draw(st.integers(0, 3))
    sides = sorted(draw(st.lists(st.integers(1, length - 1), min_size=2 * count,
                                 max_size=2 * count, unique=True)))
    outline = Polygon([(0, 0), (length, 0), (length, height), (0, height)])
    for x0, x1 in zip(sides[::2], sides[1::2]):
        y0 = draw(st.one_of(st.just(0), st.integers(1, height - 3)))
        y1 = draw(st.integers(y0 + 1, height - 1))
        outline = outline.difference(Polygon([(x0, y0), (x1, y0), (x1, y1), (x0, y1)]))
    outline = shapely.affinity.scale(outline, 0.1, 0.1, origin=(0, 0))
    thickness = 0.1 * draw(st.integers(1, 3))
    return _extruded(outline, thickness, draw(st.sampled_from([(0, 1, 2), (2, 1, 0)])))


@st.composite
def _slabs(draw) -> trimesh.Trimesh:
    """A slab on a 0.25 m lattice, 0.2 m thick (y up): an L, a U, or a rectangle with a
    stair opening."""
    width, depth = draw(st.integers(3, 12)), draw(st.integers(3, 12))
    kind = draw(st.sampled_from(["L", "U", "opening"]))
    x0 = draw(st.integers(1, width - (1 if kind == "L" else 2)))
    x1 = width if kind == "L" else draw(st.integers(x0 + 1, width - 1))
    z0 = draw(st.integers(1, depth - (2 if kind == "opening" else 1)))
    z1 = draw(st.integers(z0 + 1, depth - 1)) if kind == "opening" else depth
    cut = Polygon([(x0, z0), (x1, z0), (x1, z1), (x0, z1)])
    outline = Polygon([(0, 0), (width, 0), (width, depth), (0, depth)]).difference(cut)
    return _extruded(shapely.affinity.scale(outline, 0.25, 0.25, origin=(0, 0)), 0.2, (0, 2, 1))


@settings(max_examples=80, deadline=None)
@given(st.one_of(_walls(), _slabs()))
def test_random_walls_and_slabs_cut_like_manifold(solid):
    """On walls with openings and slabs with notches the grid gives the pieces, in
    their order, that manifold3d's plane splits give."""
    assert solid.is_watertight and solid.volume > 0
    grid, cut = box_pieces(solid), convex_pieces(solid)
    assert grid is not None
    assert cut is not None
    assert len(grid) == len(cut)
    for mine, theirs in zip(grid, cut):
        bounds = [np.r_[np.min(p.vertices, axis=0), np.max(p.vertices, axis=0)]
                  for p in (mine, theirs)]
        assert np.allclose(bounds[0], bounds[1], rtol=0, atol=1e-6)
