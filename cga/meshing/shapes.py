"""Terminal masses and faces as named world-space meshes (:class:`~cga.scene.SceneNode`).

* A mass becomes a watertight prism: its footprint is extruded with
  :func:`trimesh.creation.extrude_polygon` (which builds along +z from the x–y plane)
  and turned to y-up. A mass of height 0 (an un-extruded lot) becomes a flat face.
* A face becomes a triangulated polygon whose triangles face along its outward normal.

Masses and faces are named by their shape path (``Lot/Body/Upper[2]``).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np
from shapely.geometry import Polygon
from shapely.geometry.base import BaseGeometry

from cga.scene import SceneNode
from cga.shape import Face, Mass, Shape

if TYPE_CHECKING:  # pragma: no cover
    import trimesh

__all__ = ["mass_mesh", "face_mesh", "footprint_mesh", "polygon_mesh", "shape_node"]

# (x, -z) plan polygon extruded along +z, then turned -90° about x: (x, y, z) → (x, z, -y),
# so (x, -z_plan, h) lands at (x, h, z_plan): a rotation, so triangle winding survives.
_TO_Y_UP = np.array([[1.0, 0.0, 0.0, 0.0],
                     [0.0, 0.0, 1.0, 0.0],
                     [0.0, -1.0, 0.0, 0.0],
                     [0.0, 0.0, 0.0, 1.0]])


def _plan_to_xy(footprint: Polygon) -> Polygon:
    """The footprint mirrored to (x, -z), so extrusion along +z and the turn to y-up
    restore the plan exactly."""
    return Polygon([(x, -z) for x, z in footprint.exterior.coords],
                   [[(x, -z) for x, z in ring.coords] for ring in footprint.interiors])


def mass_mesh(mass: Mass) -> "trimesh.Trimesh":
    """The prism of a mass in world coordinates (y up), watertight, outward normals.

    Raises
    ------
    ValueError
        The mass has no height (use :func:`face_mesh` of its footprint instead).
    """
    import trimesh

    if not mass.height > 0:
        raise ValueError("a mass without height has no volume; mesh it as a face")
    mesh = trimesh.creation.extrude_polygon(_plan_to_xy(mass.footprint), mass.height)
    transform = _TO_Y_UP.copy()
    transform[1, 3] = mass.base
    mesh.apply_transform(transform)
    return mesh


def face_mesh(vertices: Any, normal: Any | None = None) -> "trimesh.Trimesh":
    """A planar polygon (N×3 vertices, counter-clockwise seen from outside) triangulated,
    triangles facing along ``normal`` (default: the polygon's Newell normal)."""
    import trimesh

    pts = np.asarray(vertices, dtype=float)
    if normal is None:
        normal = np.cross(pts, np.roll(pts, -1, axis=0)).sum(axis=0)
    n = np.asarray(normal, dtype=float)
    n = n / np.linalg.norm(n)
    u = pts[1] - pts[0]
    u = u - n * (u @ n)
    u = u / np.linalg.norm(u)
    v = np.cross(n, u)
    local = (pts - pts[0]) @ np.column_stack([u, v])
    return polygon_mesh(Polygon(local), pts[0], u, v, n)


def polygon_mesh(polygon: BaseGeometry, origin: Any, u: Any, v: Any,
                 normal: Any) -> "trimesh.Trimesh":
    """A plane (multi)polygon, holes kept, triangulated into 3D: the point ``(a, b)`` of
    the plane lands at ``origin + a·u + b·v``; the triangles face along ``normal``."""
    import trimesh

    origin, u, v = (np.asarray(a, dtype=float) for a in (origin, u, v))
    vertices, faces = [], []
    count = 0
    for piece in getattr(polygon, "geoms", [polygon]):
        if not isinstance(piece, Polygon) or piece.is_empty or not piece.area > 0:
            continue
        flat, triangles = trimesh.creation.triangulate_polygon(piece)
        vertices.append(origin + np.outer(flat[:, 0], u) + np.outer(flat[:, 1], v))
        faces.append(np.asarray(triangles, dtype=np.int64).reshape(-1, 3) + count)
        count += len(flat)
    if not vertices:
        return trimesh.Trimesh(vertices=np.zeros((0, 3)), faces=np.zeros((0, 3), dtype=np.int64),
                               process=False)
    points = np.concatenate(vertices)
    return trimesh.Trimesh(vertices=points, faces=_facing(points, np.concatenate(faces), normal),
                           process=False)


def footprint_mesh(mass: Mass) -> "trimesh.Trimesh":
    """A flat mass (height 0) as its footprint triangulated at ``base``, holes kept,
    facing up."""
    import trimesh

    flat, triangles = trimesh.creation.triangulate_polygon(mass.footprint)
    points = np.column_stack([flat[:, 0], np.full(len(flat), mass.base), flat[:, 1]])
    return trimesh.Trimesh(vertices=points, faces=_facing(points, triangles, (0.0, 1.0, 0.0)),
                           process=False)


def _facing(points: np.ndarray, triangles: np.ndarray, normal: Any) -> np.ndarray:
    """``triangles`` with their winding flipped if they face away from ``normal``."""
    triangles = np.asarray(triangles, dtype=np.int64).reshape(-1, 3)
    if not len(triangles):
        return triangles
    a, b, c = (points[triangles[:, i]] for i in range(3))
    if float(np.cross(b - a, c - a).sum(axis=0) @ np.asarray(normal, dtype=float)) < 0:
        return triangles[:, ::-1].copy()
    return triangles


def shape_node(shape: Shape) -> SceneNode:
    """The scene node of a terminal mass or face, named by its shape path."""
    geometry = shape.geometry
    extras: dict[str, Any] = {"symbol": shape.symbol, "shape_path": shape.path_name}
    for key in ("floor", "index"):
        if key in shape.attrs:
            extras[key] = shape.attrs[key]
    if isinstance(geometry, Mass) and geometry.height > 0:
        return SceneNode(path=shape.path_name, kind="mass", mesh=mass_mesh(geometry),
                         extras=extras)
    if isinstance(geometry, Mass):
        return SceneNode(path=shape.path_name, kind="face", mesh=footprint_mesh(geometry),
                         extras={**extras, "face": "top"})
    face: Face = geometry
    return SceneNode(path=shape.path_name, kind="face", mesh=face_mesh(face.vertices, face.normal()),
                     extras={**extras, "face": face.kind})
