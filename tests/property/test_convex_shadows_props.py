"""cga.checks.occupancy._convex_shadows: the shadows of furniture's convex parts, checked
coordinate for coordinate against the previous way of making them (a multipoint per
part, its edges offset part by part), which the occupancy grid's cells depend on."""

from __future__ import annotations

import manifold3d
import numpy as np
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st

from cga.checks._raster import polygon_patches
from cga.checks._solids import as_mesh
from cga.checks.occupancy import _SHEET, _band_points, _convex_shadows
from cga.scene import MeshArrays


def _reference(groups, y0, y1):
    """The previous implementation: edges offset part by part, hulls of multipoints."""
    parts = [part for group in groups for part in group]
    group_of = np.repeat(np.arange(len(groups)), [len(g) for g in groups])
    vertices = [np.asarray(part.vertices, dtype=float) for part in parts]
    faces = [np.asarray(part.faces) for part in parts]
    sizes = np.array([len(v) for v in vertices], dtype=np.int64)
    starts = np.concatenate([[0], np.cumsum(sizes)[:-1]])
    points = np.concatenate(vertices) if parts else np.zeros((0, 3))
    vertex_owner = np.repeat(np.arange(len(parts)), sizes)
    edges = (np.concatenate([f[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2) + s
                             for f, s in zip(faces, starts)])
             if parts else np.zeros((0, 2), dtype=np.int64))
    edge_owner = vertex_owner[edges[:, 0]]
    y = points[:, 1]
    inside = (y >= y0) & (y <= y1)
    found, owner = [points[inside][:, [0, 2]]], [vertex_owner[inside]]
    a, b = points[edges[:, 0]], points[edges[:, 1]]
    for h in (y0, y1):
        crossing = (a[:, 1] - h) * (b[:, 1] - h) < 0
        t = (h - a[crossing, 1]) / (b[crossing, 1] - a[crossing, 1])
        found.append((a[crossing] + t[:, None] * (b[crossing] - a[crossing]))[:, [0, 2]])
        owner.append(edge_owner[crossing])
    ids = np.concatenate(owner)
    order = np.argsort(ids, kind="stable")
    points, owner = np.concatenate(found)[order], ids[order]
    kept, owner = np.unique(owner, return_inverse=True)
    hulls = shapely.convex_hull(shapely.multipoints(points, indices=owner))
    flat = shapely.get_type_id(hulls) != shapely.GeometryType.POLYGON
    hulls[flat] = shapely.buffer(hulls[flat], _SHEET)
    rows = group_of[kept]
    column = np.arange(len(kept)) - np.searchsorted(rows, rows)
    table = np.full((len(groups), int(column.max(initial=-1)) + 1), None, dtype=object)
    table[rows, column] = hulls
    return list(shapely.union_all(table, axis=1)) if len(groups) else []


_value = st.integers(-8, 8).map(lambda n: n * 0.125)


@st.composite
def _part(draw):
    """A convex solid: the hull of a few points (some on the band's planes), an
    axis-aligned box, or a flat or a single-point part the band only touches."""
    if draw(st.booleans()):  # a box: its shadow a rectangle, which may hold the others'
        lo, hi = draw(st.tuples(_value, _value, _value)), draw(st.tuples(_value, _value, _value))
        points = [(a, b, c) for a in (lo[0], hi[0]) for b in (lo[1], hi[1]) for c in (lo[2], hi[2])]
    else:
        points = draw(st.lists(st.tuples(_value, _value, _value), min_size=4, max_size=9))
    hull = manifold3d.Manifold.hull_points(np.array(points, dtype=float))
    if hull.is_empty():
        corner = np.array(points[:1], dtype=float)
        return MeshArrays(np.repeat(corner, 3, axis=0), np.array([[0, 1, 2]]))
    mesh = as_mesh(hull)
    return MeshArrays(mesh.vertices, mesh.faces.astype(draw(st.sampled_from([np.int32,
                                                                             np.int64]))))


@settings(max_examples=300, deadline=None)
@given(groups=st.lists(st.lists(_part(), max_size=4), max_size=5),
       band=st.tuples(_value, st.integers(0, 8).map(lambda n: n * 0.125)))
def test_convex_shadows_are_the_previous_ones(groups, band):
    y0, y1 = band[0], band[0] + band[1]
    got = _convex_shadows(groups, y0, y1)
    want = _reference(groups, y0, y1)
    assert len(got) == len(want)
    for a, b in zip(got, want):
        if np.array_equal(shapely.get_coordinates(a), shapely.get_coordinates(b)):
            assert a.geom_type == b.geom_type
            continue
        # a rectangle holding the group's other shadows stands for their union: the same
        # region, and (being rectilinear) the same cells on any grid
        x0, z0, x1, z1 = a.bounds
        assert shapely.equals(a, shapely.box(x0, z0, x1, z1)) and shapely.equals(a, b)
        for origin in ((0.0, 0.0), (0.01, -0.02)):
            assert _cells(a, origin) == _cells(b, origin)


def _cells(shadow, origin):
    grid = np.zeros((80, 80), dtype=bool)
    for r0, r1, c0, c1, patch in polygon_patches(grid.shape, [shadow], *origin, 0.05)[0]:
        grid[r0:r1, c0:c1] |= patch
    return grid.tobytes()


def test_band_points_of_no_parts():
    points, owner = _band_points([], 0.0, 1.0)
    assert points.shape == (0, 2) and owner.shape == (0,)


def test_a_part_touching_the_band_at_one_point():
    """A pyramid whose apex touches the band has one point in it: a buffered point."""
    apex = manifold3d.Manifold.hull_points(np.array(
        [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.25, 0.5, 0.25]]))
    part = MeshArrays(as_mesh(apex).vertices, as_mesh(apex).faces)
    points, _ = _band_points([part], 0.5, 1.0)
    assert len(points) == 1
    (got,), (want,) = _convex_shadows([[part]], 0.5, 1.0), _reference([[part]], 0.5, 1.0)
    assert np.array_equal(shapely.get_coordinates(got), shapely.get_coordinates(want))


def test_a_table_is_its_top():
    """A top over four legs: the top's rectangle, the region the union of all five has."""
    def box(x0, y0, z0, x1, y1, z1):
        mesh = as_mesh(manifold3d.Manifold.cube([x1 - x0, y1 - y0, z1 - z0]).translate(
            [x0, y0, z0]))
        return MeshArrays(mesh.vertices, mesh.faces)

    legs = [box(x, 0.0, z, x + 0.05, 0.7, z + 0.05) for x in (0.0, 0.95) for z in (0.0, 0.55)]
    parts = [box(0.0, 0.7, 0.0, 1.0, 0.75, 0.6), *legs]
    (got,), (want,) = _convex_shadows([parts], 0.05, 1.2), _reference([parts], 0.05, 1.2)
    assert shapely.equals(got, want)
    assert shapely.get_num_coordinates(got) == 5
    assert _cells(got, (0.0, 0.0)) == _cells(want, (0.0, 0.0))
