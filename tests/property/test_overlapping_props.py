"""The wall footprints' overlap pairs against the STRtree query with GEOS's ``overlaps``
predicate they replace: the same pairs in the same order (the differences are applied in
that order, so the footprints' coordinates depend on it); and the pieces each wall keeps
against its differences taken one at a time, byte for byte.

Rectangles on a coarse grid touch edge to edge and corner to corner as walls and rooms
do; rotated quadrilaterals and triangles give boxes that meet without the shapes meeting.
"""

from __future__ import annotations

import numpy as np
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st

from cga.meshing.solids import _claimed, _overlapping

grid = st.integers(min_value=0, max_value=8).map(lambda k: k * 0.5)
wild = st.floats(min_value=0.0, max_value=4.0, allow_nan=False, allow_subnormal=False)


@st.composite
def shapes(draw) -> shapely.Geometry:
    kind = draw(st.sampled_from(["rectangle", "rectangle", "triangle", "quadrilateral"]))
    if kind == "rectangle":
        x0, x1 = sorted(draw(st.tuples(grid, grid)))
        z0, z1 = sorted(draw(st.tuples(grid, grid)))
        return shapely.box(x0, z0, x1 + 0.5, z1 + 0.5)
    corners = draw(st.lists(st.tuples(st.one_of(grid, wild), st.one_of(grid, wild)),
                            min_size=3 if kind == "triangle" else 4,
                            max_size=3 if kind == "triangle" else 4))
    polygon = shapely.Polygon(corners)
    return polygon if polygon.is_valid and polygon.area > 0 else shapely.box(0, 0, 1, 1)


@settings(max_examples=300, deadline=None)
@given(st.lists(shapes(), min_size=1, max_size=12), st.lists(shapes(), min_size=1, max_size=12))
def test_the_pairs_are_the_strtree_overlaps_query_in_its_order(geometries, others):
    geometries, others = np.array(geometries), np.array(others)
    expected = shapely.STRtree(others).query(geometries, predicate="overlaps")
    assert np.array_equal(np.array(_overlapping(geometries, others)), expected)


@settings(max_examples=300, deadline=None)
@given(st.lists(shapes(), min_size=1, max_size=16))
def test_the_earlier_pairs_are_those_of_the_query_with_a_lower_tree_index(geometries):
    geometries = np.array(geometries)
    i, j = shapely.STRtree(geometries).query(geometries, predicate="overlaps")
    expected = np.array([i[j < i], j[j < i]])
    assert np.array_equal(np.array(_overlapping(geometries, geometries, earlier=True)), expected)


def reference_claimed(bands, earlier):
    """The joints given up as first written: band by band, one difference at a time."""
    out = []
    for i, band in enumerate(bands):
        piece = band
        for j in earlier[i]:
            piece = piece.difference(bands[j])
        out.append(shapely.simplify(piece, 0.0) if earlier[i] else piece)
    return out


@settings(max_examples=300, deadline=None)
@given(st.lists(shapes(), min_size=1, max_size=16))
def test_the_claimed_pieces_are_the_differences_one_at_a_time(bands):
    bands = np.array(bands)
    earlier = [[] for _ in bands]
    for i, j in zip(*_overlapping(bands, bands, earlier=True)):
        earlier[i].append(j)
    pieces = _claimed(bands, earlier)
    expected = reference_claimed(bands, earlier)
    assert [shapely.to_wkb(p) for p in pieces] == [shapely.to_wkb(p) for p in expected]
