"""Vertical prisms over plan areas: the one solid walls, slabs, rails and stair flights
are made of.

Built directly from the coordinates with ``manifold3d.triangulate`` for the caps (going
through ``manifold3d.CrossSection`` would snap them to single precision, and trimesh's
extrusion merges vertices after the fact), so a prism costs a triangulation and a few
array operations.
"""

from __future__ import annotations

import manifold3d
import numpy as np
from shapely.geometry import MultiPolygon, Polygon
from shapely.geometry.polygon import orient

from cga.mesh import TriangleMesh

__all__ = ["prism", "prism_mesh"]


def prism(area: Polygon | MultiPolygon, y_low: float,
          y_high: float) -> tuple[np.ndarray, np.ndarray]:
    """Vertices and triangles of a vertical prism over a plan area.

    Rings are oriented (exteriors counter-clockwise in ``(x, z)``, holes clockwise); a
    triangle counter-clockwise in ``(x, z)`` faces down, so the floor cap keeps the
    triangulation's order and the top cap reverses it. The bottom cap's triangles come
    first, then the top cap's, then the sides'; vertices are the rings' corners at
    ``y_low``, then the same at ``y_high``.
    """
    rings = []
    for polygon in getattr(area, "geoms", [area]):
        polygon = orient(polygon, sign=1.0)
        rings += [np.asarray(r.coords)[:-1] for r in (polygon.exterior, *polygon.interiors)]
    plan = np.concatenate(rings)
    n = len(plan)
    caps = np.asarray(manifold3d.triangulate(rings), dtype=np.int64)
    sides = []
    offset = 0
    for ring in rings:
        a = offset + np.arange(len(ring))
        b = offset + (np.arange(len(ring)) + 1) % len(ring)
        sides += [np.column_stack([a, b + n, b]), np.column_stack([a, a + n, b + n])]
        offset += len(ring)
    vertices = np.empty((2 * n, 3))
    vertices[:n, 0] = vertices[n:, 0] = plan[:, 0]
    vertices[:n, 2] = vertices[n:, 2] = plan[:, 1]
    vertices[:n, 1], vertices[n:, 1] = y_low, y_high
    return vertices, np.vstack([caps, caps[:, ::-1] + n, *sides])


def prism_mesh(area: Polygon | MultiPolygon, y_low: float, y_high: float) -> TriangleMesh:
    """:func:`prism` as a mesh: watertight, facing outwards."""
    return TriangleMesh(*prism(area, y_low, y_high))
