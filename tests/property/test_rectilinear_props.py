"""cga.checks._rectilinear: band shadows of rectilinear solids, checked against
manifold3d's trim and projection (the occupancy grid's path before it, still its
fallback): the same region, and so the same cells on a grid."""

from __future__ import annotations

import manifold3d
import numpy as np
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st

from cga.checks._raster import polygon_patches
from cga.checks._rectilinear import rectilinear_shadows
from cga.checks._solids import as_manifold, as_mesh
from cga.checks.occupancy import _solid_footprint
from cga.mesh import TriangleMesh

# a step of 0.1 m is not a float32 value: the solid's faces then lie just off the band's
# planes, as a building's do; a step of 0.25 m is, and puts faces on the planes
_step = st.sampled_from([0.1, 0.25])


@st.composite
def _solid(draw):
    """Boxes united, some boxes cut away (openings): a rectilinear solid, or nothing."""
    step = draw(_step)

    def box():
        lo = draw(st.tuples(*[st.integers(0, 8)] * 3))
        size = draw(st.tuples(*[st.integers(1, 5)] * 3))
        return manifold3d.Manifold.cube([s * step for s in size]).translate(
            [a * step for a in lo])

    solid = manifold3d.Manifold.batch_boolean([box() for _ in range(draw(st.integers(1, 4)))],
                                              manifold3d.OpType.Add)
    for _ in range(draw(st.integers(0, 2))):
        solid = solid - box()
    return solid, step


def _same_cells(got, want, origin):
    """The two shadows are one region, and a grid marks the same cells for both."""
    assert got.is_empty == want.is_empty
    if want.is_empty:
        return
    assert shapely.equals(got, want)
    shape = (70, 70)
    grids = [np.zeros(shape, dtype=bool) for _ in range(2)]
    for grid, shadow in zip(grids, (got, want)):
        for r0, r1, c0, c1, patch in polygon_patches(shape, [shadow], *origin, 0.05)[0]:
            grid[r0:r1, c0:c1] |= patch
    assert np.array_equal(grids[0], grids[1])


_origin = st.tuples(st.floats(-0.3, 0.3), st.floats(-0.3, 0.3))


@settings(max_examples=300, deadline=None)
@given(solid=_solid(), band=st.tuples(st.integers(-1, 14), st.integers(0, 6)),
       nudge=st.sampled_from([0.0, 1e-9, -1e-9, 1e-6, 0.5]), origin=_origin)
def test_shadow_of_a_boolean_is_manifold3d_s(solid, band, nudge, origin):
    """Where it answers for manifold3d's own meshes (whose round-off it may leave to
    manifold3d), the region manifold3d gives and its cells."""
    solid, step = solid
    if solid.is_empty():
        return
    mesh = as_mesh(solid)
    y0 = (band[0] + nudge) * step
    y1 = y0 + (band[1] + 1) * step
    (got,) = rectilinear_shadows([mesh], y0, y1)
    if got is not None:
        _same_cells(got, _solid_footprint(mesh, y0, y1), origin)


@st.composite
def _voxels(draw):
    """A solid of cells on a grid of planes a random number of steps apart, meshed face
    by face (two triangles per face between a filled and an empty cell), with the
    corners shared: watertight unless two cells meet along an edge only."""
    step = draw(_step)
    shape = draw(st.tuples(*[st.integers(1, 4)] * 3))
    filled = np.array(draw(st.lists(st.booleans(), min_size=int(np.prod(shape)),
                                    max_size=int(np.prod(shape))))).reshape(shape)
    planes = [np.cumsum(draw(st.lists(st.integers(1, 4), min_size=n + 1, max_size=n + 1)))
              * step for n in shape]
    padded = np.pad(filled, 1)
    corners = np.stack(np.meshgrid(*planes, indexing="ij"), axis=-1)
    number = np.arange(corners[..., 0].size).reshape(corners.shape[:3])
    faces = []
    for axis in range(3):
        other = [a for a in range(3) if a != axis]
        low = np.moveaxis(padded, axis, 0)[:-1, 1:-1, 1:-1]
        high = np.moveaxis(padded, axis, 0)[1:, 1:-1, 1:-1]
        for at, u, v in np.argwhere(low != high):
            quad = []
            for du, dv in ((0, 0), (1, 0), (1, 1), (0, 1)):
                index = [0, 0, 0]
                index[axis], index[other[0]], index[other[1]] = at, u + du, v + dv
                quad.append(number[tuple(index)])
            points = corners.reshape(-1, 3)[quad]
            looks_up = np.cross(points[1] - points[0], points[2] - points[0])[axis] > 0
            if looks_up != bool(low[at, u, v]):  # a face looks away from its filled cell
                quad = quad[::-1]
            faces += [[quad[0], quad[1], quad[2]], [quad[0], quad[2], quad[3]]]
    return TriangleMesh(corners.reshape(-1, 3), np.array(faces, dtype=np.int64).reshape(-1, 3)), step


@settings(max_examples=300, deadline=None)
@given(solid=_voxels(), band=st.tuples(st.integers(-1, 14), st.integers(0, 6)),
       nudge=st.sampled_from([0.0, 1e-9, 0.5]), origin=_origin)
def test_shadow_of_cells_is_manifold3d_s(solid, band, nudge, origin):
    """On clean rectilinear solids it answers whenever the band's planes lie clear of
    the solid's (a nudge of half a step), with the region manifold3d gives."""
    mesh, step = solid
    y0 = (band[0] + nudge) * step
    y1 = y0 + (band[1] + 1) * step
    (got,) = rectilinear_shadows([mesh], y0, y1)
    if got is None:
        assert nudge != 0.5 or as_manifold(mesh) is None or len(mesh.faces) == 0
        return
    _same_cells(got, _solid_footprint(mesh, y0, y1), origin)


def test_a_slanted_or_open_mesh_is_left_to_manifold3d():
    slanted = manifold3d.Manifold.cube([1.0, 1.0, 1.0]).rotate([0.0, 30.0, 0.0])
    box = as_mesh(manifold3d.Manifold.cube([1.0, 1.0, 1.0]))
    open_box = TriangleMesh(box.vertices, box.faces[:-1])
    flipped = TriangleMesh(box.vertices, np.concatenate([box.faces[:-1], box.faces[-1:, ::-1]]))
    shadows = rectilinear_shadows([as_mesh(slanted), open_box, flipped, box], 0.2, 0.5)
    assert shadows[:3] == [None, None, None]
    assert shapely.equals(shadows[3], shapely.box(0.0, 0.0, 1.0, 1.0))


def test_a_wall_with_a_door_and_a_window():
    """The door's gap stays open; the window above the band does not show (sizes that
    float32 holds exactly, as the solid's coordinates are read)."""
    wall = manifold3d.Manifold.cube([4.0, 2.5, 0.25])
    door = manifold3d.Manifold.cube([1.0, 2.125, 0.5]).translate([0.5, -0.125, -0.125])
    window = manifold3d.Manifold.cube([1.25, 1.0, 0.5]).translate([2.25, 1.25, -0.125])
    (shadow,) = rectilinear_shadows([as_mesh(wall - door - window)], 0.05, 1.2)
    assert shapely.equals(shadow, shapely.union(shapely.box(0.0, 0.0, 0.5, 0.25),
                                                shapely.box(1.5, 0.0, 4.0, 0.25)))
