"""Faces of masses and the 2D frames they live in.

A :class:`~cga.shape.Face` carries its polygon as 3D vertices; its :class:`~cga.shape.Scope`
follows the CGA convention: the x axis runs along the face (left to right seen from
outside), the z axis is the outward normal and ``y = z × x`` (up, on a wall). Splitting a
face works in the face's own 2D coordinates ``(u, v)`` along the scope's x and y axes;
this module converts between the two and builds the faces ``component_split`` returns.

Orientation: vertices run counter-clockwise seen from outside, so Newell's normal points
outward (:meth:`cga.shape.Face.normal`). Footprints are counter-clockwise in plan
coordinates ``(x, z)``, which seen from above (+y) is clockwise; hence a top face lists
the footprint's corners in reverse.
"""

from __future__ import annotations

import numpy as np
from shapely.geometry import Polygon
from shapely.geometry.polygon import orient

from cga.shape import Face, FaceKind, Mass, Scope

__all__ = ["face_polygon", "face_from_polygon", "side_faces", "top_face", "bottom_face"]

_UP = np.array([0.0, 1.0, 0.0])


def _axes(scope: Scope) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    x, y, z = (np.asarray(a, dtype=float) for a in scope.axes)
    return x, y, z


def face_polygon(face: Face, scope: Scope) -> Polygon:
    """The face as a 2D polygon in its scope's ``(u, v)`` coordinates (counter-clockwise)."""
    x, y, _ = _axes(scope)
    rel = np.asarray(face.vertices, dtype=float) - np.asarray(scope.origin, dtype=float)
    return orient(Polygon(np.column_stack([rel @ x, rel @ y])), sign=1.0)


def face_from_polygon(polygon: Polygon, scope: Scope, kind: FaceKind) -> tuple[Face, Scope]:
    """Lift a ``(u, v)`` polygon in ``scope``'s plane back to a 3D face and its tight scope.

    The new scope keeps the axes and moves the origin to the polygon's lower-left bound.
    """
    x, y, z = _axes(scope)
    ring = np.asarray(orient(polygon, sign=1.0).exterior.coords)[:-1]
    origin = np.asarray(scope.origin, dtype=float)
    vertices = origin + np.outer(ring[:, 0], x) + np.outer(ring[:, 1], y)
    minu, minv, maxu, maxv = polygon.bounds
    new_origin = origin + minu * x + minv * y
    new_scope = Scope(origin=_triple(new_origin), axes=scope.axes,
                      size=(maxu - minu, maxv - minv, 0.0))
    return Face(vertices=tuple(_triple(v) for v in vertices), kind=kind), new_scope


def _triple(v: np.ndarray) -> tuple[float, float, float]:
    """A 3-vector as plain floats (shapes hold tuples, not arrays)."""
    return (float(v[0]), float(v[1]), float(v[2]))


def _scope(origin: np.ndarray, x: np.ndarray, z: np.ndarray, size: tuple[float, float]) -> Scope:
    y = np.cross(z, x)
    return Scope(origin=_triple(origin), axes=tuple(_triple(axis) for axis in (x, y, z)),
                 size=(float(size[0]), float(size[1]), 0.0))


def side_faces(mass: Mass) -> list[tuple[Face, Scope]]:
    """One vertical rectangle per footprint edge (exterior ring, then any holes).

    Face ``i`` stands on edge ``i`` of the footprint's exterior (``a_i → a_{i+1}`` in the
    counter-clockwise ring); its scope's x axis runs from ``a_{i+1}`` to ``a_i`` (left to
    right seen from outside).
    """
    footprint = orient(mass.footprint, sign=1.0)
    bottom, top = mass.base, mass.base + mass.height
    rings = [footprint.exterior, *footprint.interiors]
    faces = []
    for ring in rings:
        coords = np.asarray(ring.coords)[:-1]
        for a, b in zip(coords, np.roll(coords, -1, axis=0)):
            length = float(np.hypot(*(b - a)))
            if length <= 0:
                continue
            a0, b0 = np.array([a[0], bottom, a[1]]), np.array([b[0], bottom, b[1]])
            a1, b1 = a0 + _UP * mass.height, b0 + _UP * mass.height
            along = (a0 - b0) / length
            outward = np.cross(along, _UP)
            vertices = (b0, a0, a1, b1)
            face = Face(vertices=tuple(_triple(v) for v in vertices), kind="side")
            faces.append((face, _scope(b0, along, outward, (length, top - bottom))))
    return faces


def top_face(mass: Mass) -> tuple[Face, Scope]:
    """The roof polygon at ``base + height``, normal +y."""
    footprint = orient(mass.footprint, sign=1.0)
    y = mass.base + mass.height
    ring = np.asarray(footprint.exterior.coords)[:-1][::-1]
    vertices = tuple((float(px), float(y), float(pz)) for px, pz in ring)
    minx, minz, maxx, maxz = footprint.bounds
    scope = _scope(np.array([minx, y, maxz]), np.array([1.0, 0.0, 0.0]), _UP,
                   (maxx - minx, maxz - minz))
    return Face(vertices=vertices, kind="top"), scope


def bottom_face(mass: Mass) -> tuple[Face, Scope]:
    """The ground polygon at ``base``, normal −y."""
    footprint = orient(mass.footprint, sign=1.0)
    ring = np.asarray(footprint.exterior.coords)[:-1]
    vertices = tuple((float(px), float(mass.base), float(pz)) for px, pz in ring)
    minx, minz, maxx, maxz = footprint.bounds
    scope = _scope(np.array([minx, mass.base, minz]), np.array([1.0, 0.0, 0.0]), -_UP,
                   (maxx - minx, maxz - minz))
    return Face(vertices=vertices, kind="bottom"), scope
