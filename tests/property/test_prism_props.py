"""Prisms against the way they were first assembled: the rings read through
``ring.coords`` and the vertices written coordinate by coordinate, bit for bit (the glb,
OBJ and JSON files write these floats as they are)."""

from __future__ import annotations

import manifold3d
import numpy as np
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st
from shapely.geometry import MultiPolygon, Polygon
from shapely.geometry.polygon import orient

from cga.meshing.prisms import _sides, oriented_rings, prism

coordinate = st.one_of(st.integers(min_value=-6, max_value=6).map(lambda k: k * 0.25),
                       st.floats(min_value=-10.0, max_value=10.0, allow_nan=False,
                                 allow_subnormal=False))


def reference_rings(area):
    rings = []
    for polygon in getattr(area, "geoms", [area]):
        polygon = orient(polygon, sign=1.0)
        rings += [np.asarray(r.coords)[:-1] for r in (polygon.exterior, *polygon.interiors)]
    return rings


def reference_prism(area, y_low, y_high):
    rings = reference_rings(area)
    sizes = tuple(len(ring) for ring in rings)
    n = sum(sizes)
    caps = np.asarray(manifold3d.triangulate(rings), dtype=np.int64)
    plan = np.concatenate(rings)
    vertices = np.empty((2, n, 3))
    vertices[:, :, 0] = plan[:, 0]
    vertices[:, :, 2] = plan[:, 1]
    vertices[0, :, 1], vertices[1, :, 1] = y_low, y_high
    return vertices.reshape(2 * n, 3), np.concatenate([caps, caps[:, ::-1] + n, _sides(sizes)])


@st.composite
def areas(draw):
    """Boxes (some with a hole), either way round, alone or a few apart; or a
    triangle."""
    polygons = []
    for k in range(draw(st.integers(min_value=1, max_value=3))):
        x, z = draw(coordinate), draw(coordinate)
        w = draw(st.floats(min_value=0.5, max_value=4.0))
        d = draw(st.floats(min_value=0.5, max_value=4.0))
        x += 20.0 * k
        shell = [(x, z), (x + w, z), (x + w, z + d), (x, z + d)]
        if draw(st.booleans()):
            shell.reverse()
        holes = []
        if draw(st.booleans()):
            holes = [[(x + w / 4, z + d / 4), (x + w / 4, z + 3 * d / 4),
                      (x + 3 * w / 4, z + 3 * d / 4), (x + 3 * w / 4, z + d / 4)]]
        polygons.append(Polygon(shell, holes))
    if draw(st.booleans()):
        triangle = Polygon([(draw(coordinate), draw(coordinate)) for _ in range(3)])
        if triangle.is_valid and triangle.area > 1e-3:
            return triangle
    return polygons[0] if len(polygons) == 1 else MultiPolygon(polygons)


def same(a: np.ndarray, b: np.ndarray) -> bool:
    return a.shape == b.shape and a.dtype == b.dtype and a.tobytes() == b.tobytes()


@settings(max_examples=200, deadline=None)
@given(areas(), coordinate, st.floats(min_value=0.1, max_value=5.0))
def test_prism_is_its_first_assembly_bit_for_bit(area, y_low, height):
    assert shapely.is_valid(area)
    rings = oriented_rings(area)
    expected_rings = reference_rings(area)
    assert len(rings) == len(expected_rings)
    assert all(same(a, b) for a, b in zip(rings, expected_rings))
    vertices, faces = prism(area, y_low, y_low + height)
    expected_vertices, expected_faces = reference_prism(area, y_low, y_low + height)
    assert same(vertices, expected_vertices)
    assert same(faces, expected_faces)
