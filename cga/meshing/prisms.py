"""Vertical prisms over plan areas: the one solid walls, slabs, rails and stair flights
are made of.

Built directly from the coordinates with ``manifold3d.triangulate`` for the caps (going
through ``manifold3d.CrossSection`` would snap them to single precision, and trimesh's
extrusion merges vertices after the fact), so a prism costs a triangulation and a few
array operations.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np
import shapely
from shapely.geometry import MultiPolygon, Polygon
from shapely.geometry.polygon import orient

from cga.manifold import manifold3d
from cga.mesh import TriangleMesh

__all__ = ["oriented_rings", "prism", "prism_mesh"]


def prism(area: Polygon | MultiPolygon, y_low: float,
          y_high: float) -> tuple[np.ndarray, np.ndarray]:
    """Vertices and triangles of a vertical prism over a plan area.

    Rings are oriented (exteriors counter-clockwise in ``(x, z)``, holes clockwise); a
    triangle counter-clockwise in ``(x, z)`` faces down, so the floor cap keeps the
    triangulation's order and the top cap reverses it. The bottom cap's triangles come
    first, then the top cap's, then the sides'; vertices are the rings' corners at
    ``y_low``, then the same at ``y_high``.
    """
    rings = oriented_rings(area)
    sizes = tuple(len(ring) for ring in rings)
    n = sum(sizes)
    caps = np.asarray(manifold3d.triangulate(rings), dtype=np.int64)
    vertices = np.empty((2, n, 3))
    vertices[:, :, ::2] = np.concatenate(rings) if len(rings) > 1 else rings[0]  # x, z
    vertices[0, :, 1], vertices[1, :, 1] = y_low, y_high
    return vertices.reshape(2 * n, 3), np.concatenate([caps, caps[:, ::-1] + n, _sides(sizes)])


def oriented_rings(area: Polygon | MultiPolygon) -> list[np.ndarray]:
    """The corners of every ring of ``area`` (not repeating the first), exteriors
    counter-clockwise and holes clockwise in ``(x, z)``, polygon by polygon.

    Read with ``shapely.get_coordinates``, the coordinates ``ring.coords`` holds without
    the coordinate sequence made on the way."""
    rings = []
    for polygon in getattr(area, "geoms", [area]):
        polygon = orient(polygon, sign=1.0)
        rings.append(shapely.get_coordinates(polygon.exterior)[:-1])
        rings += [shapely.get_coordinates(r)[:-1] for r in polygon.interiors]
    return rings


@lru_cache(maxsize=256)
def _sides(sizes: tuple[int, ...]) -> np.ndarray:
    """The side triangles of a prism whose bottom corners are rings of ``sizes`` corners
    one after another and whose top corners follow them: for each ring, the triangles
    ``(a, b', b)`` of its edges ``a → b``, then their ``(a, a', b')`` (a prime: the
    corner above).

    They depend on the ring sizes alone, and a storey's walls have a handful of shapes
    (four corners, most of them), so they are made once per shape: written out for
    each wall, these few small arrays cost more than the rest of the prism. Read-only,
    as it is shared."""
    n = sum(sizes)
    sides = []
    offset = 0
    for size in sizes:
        a = offset + np.arange(size)
        b = offset + (np.arange(size) + 1) % size
        sides += [np.column_stack([a, b + n, b]), np.column_stack([a, a + n, b + n])]
        offset += size
    out = np.concatenate(sides)
    out.flags.writeable = False
    return out


def prism_mesh(area: Polygon | MultiPolygon, y_low: float, y_high: float) -> TriangleMesh:
    """:func:`prism` as a mesh: watertight, facing outwards."""
    return TriangleMesh(*prism(area, y_low, y_high))
