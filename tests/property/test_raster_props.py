"""cga.checks._raster: the cells of many polygons at once, checked cell for cell against
Pillow drawing each polygon alone (the occupancy grid's rasteriser before it)."""

from __future__ import annotations

import math

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from PIL import Image, ImageDraw
from shapely.geometry import MultiPolygon, Polygon

from cga.checks._raster import polygon_patches, polygons_of

RES = 0.05


def _pillow(shape, geometry, x_min, z_min, resolution):
    """Reference: each polygon drawn alone with Pillow in an image of its box of cells."""
    rows, cols = shape
    out = []
    for polygon in polygons_of(geometry):
        bx0, bz0, bx1, bz1 = polygon.bounds
        c0 = max(math.floor((bx0 - x_min) / resolution), 0)
        r0 = max(math.floor((bz0 - z_min) / resolution), 0)
        c1 = min(math.floor((bx1 - x_min) / resolution) + 1, cols)
        r1 = min(math.floor((bz1 - z_min) / resolution) + 1, rows)
        if c0 >= c1 or r0 >= r1:
            continue
        image = Image.new("1", (c1 - c0, r1 - r0), 0)
        draw = ImageDraw.Draw(image)

        def pixels(ring):
            xy = np.asarray(ring, dtype=float)[:, :2]
            u = np.floor((xy[:, 0] - x_min) / resolution).astype(int) - c0
            v = np.floor((xy[:, 1] - z_min) / resolution).astype(int) - r0
            return list(zip(u.tolist(), v.tolist()))

        draw.polygon(pixels(polygon.exterior.coords), fill=1, outline=1)
        for interior in polygon.interiors:
            draw.polygon(pixels(interior.coords), fill=0, outline=1)
        out.append((r0, r1, c0, c1, np.asarray(image, dtype=bool)))
    return out


def _same(got, want):
    assert len(got) == len(want)
    for (*box_a, a), (*box_b, b) in zip(got, want):
        assert box_a == box_b
        assert np.array_equal(np.broadcast_to(a, b.shape), b)


# coordinates in quarters of a cell, so vertices fall on cell borders and inside cells
_coord = st.integers(-12, 60).map(lambda n: n * RES / 4)


@st.composite
def _rectilinear_ring(draw):
    """A closed ring of alternating horizontal and vertical steps: it may cross or touch
    itself, run outside the grid, or fold back on itself."""
    n = draw(st.integers(2, 7))
    xs = draw(st.lists(_coord, min_size=n, max_size=n))
    zs = draw(st.lists(_coord, min_size=n, max_size=n))
    ring = []
    for k in range(n):
        ring += [(xs[k], zs[k]), (xs[(k + 1) % n], zs[k])]
    return ring


@st.composite
def _any_ring(draw):
    return draw(st.lists(st.tuples(_coord, _coord), min_size=3, max_size=7))


@settings(max_examples=400, deadline=None)
@given(rings=st.lists(st.one_of(_rectilinear_ring(), _any_ring()), min_size=1, max_size=6),
       holes=st.lists(_rectilinear_ring(), max_size=2),
       shape=st.tuples(st.integers(1, 14), st.integers(1, 14)),
       origin=st.tuples(st.floats(-0.2, 0.2), st.floats(-0.2, 0.2)))
def test_patches_are_pillow_s(rings, holes, shape, origin):
    """Every polygon's patch (rectilinear or not, with holes or not, crossing the grid's
    edges or not) is Pillow's, and each geometry gets its own polygons' patches."""
    polygons = [Polygon(r) for r in rings]
    polygons.append(Polygon(rings[0], holes))
    geometries = [polygons[0], MultiPolygon(polygons[1:3]) if len(polygons) > 2 else Polygon(),
                  *polygons[3:]]
    x_min, z_min = origin
    got = polygon_patches(shape, geometries, x_min, z_min, RES)
    assert len(got) == len(geometries)
    for patches, geometry in zip(got, geometries):
        _same(patches, _pillow(shape, geometry, x_min, z_min, RES))


def test_a_rectangle_is_its_box_of_cells():
    (patch,), = polygon_patches((10, 10), [Polygon([(0.12, 0.07), (0.31, 0.07), (0.31, 0.2),
                                                     (0.12, 0.2)])], 0.0, 0.0, RES)
    r0, r1, c0, c1, cells = patch
    assert (r0, r1, c0, c1) == (1, 5, 2, 7)
    assert cells.all()
