"""prism: a vertical prism over any plan area (holes, several pieces) is a closed solid
facing outwards, its side triangles shared among prisms of the same ring sizes."""

from __future__ import annotations

import numpy as np
import pytest
import shapely
import trimesh
from hypothesis import given, settings
from hypothesis import strategies as st
from shapely.geometry import box

from cga.meshing.prisms import prism

rectangles = st.tuples(st.integers(0, 8), st.integers(0, 8), st.integers(1, 4), st.integers(1, 4))


def area_of(adds, cuts):
    """Boxes united, then boxes a quarter off their grid cut out (holes, notches,
    separate pieces)."""
    area = shapely.union_all([box(x, z, x + w, z + d) for x, z, w, d in adds])
    for x, z, w, d in cuts:
        area = area.difference(box(x + 0.25, z + 0.25, x + w + 0.25, z + d + 0.25))
    return area


@settings(max_examples=80, deadline=None)
@given(st.lists(rectangles, min_size=1, max_size=4), st.lists(rectangles, max_size=2),
       st.floats(min_value=-5.0, max_value=5.0), st.floats(min_value=0.1, max_value=4.0))
def test_a_prism_is_a_closed_outward_solid_of_area_times_height(adds, cuts, y_low, height):
    area = area_of(adds, cuts)
    if area.is_empty or area.area < 1e-6:
        return
    vertices, faces = prism(area, y_low, y_low + height)
    solid = trimesh.Trimesh(vertices, faces, process=False)
    assert solid.is_watertight and solid.is_winding_consistent
    assert solid.volume == pytest.approx(area.area * height, rel=1e-9)
    n = len(vertices) // 2
    assert np.all(vertices[:n, 1] == y_low) and np.all(vertices[n:, 1] == y_low + height)
    assert np.array_equal(vertices[:n, [0, 2]], vertices[n:, [0, 2]])


def test_prisms_of_the_same_ring_sizes_share_their_side_triangles_read_only():
    _, first = prism(box(0, 0, 1, 1), 0.0, 1.0)
    _, second = prism(box(5, 5, 9, 6), 2.0, 3.0)
    assert np.array_equal(first[4:], second[4:])  # after the two caps' two triangles each
    first[-1, 0] = 99  # the faces returned are the caller's own
    assert prism(box(0, 0, 1, 1), 0.0, 1.0)[1][-1, 0] != 99
