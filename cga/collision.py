"""Collision shapes: the physics check and every robot export collide through these.

Bullet (pybullet, and simulators that load our URDF/SDF through it) gives every shape a
1 mm collision margin: a shape acts as if inflated by it. An item standing exactly on
the floor, or flush against a wall, would then start 2 mm "deep" in it and the contact
solver would push it about. Shrinking each convex part of an item by
:data:`CONTACT_SHRINK` per face cancels that: with the margins added back the item
touches exactly. Both the check and the exports build item bodies from
:func:`collision_parts` shrunk with :func:`shrink_part`, so what is checked is what is
exported.

The building (walls, slabs, stairs: every static structure node) collides through
convex pieces, :func:`structure_pieces`: MuJoCo and USD/PhysX take only convex shapes
for anything that may touch a moving body, and Bullet handles a few boxes better than one
concave triangle mesh. Each piece is a :class:`ConvexPiece`, a box where it is one (so
MJCF, SDF, URDF and USD can write a primitive) and a convex mesh otherwise.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from cga.mesh import as_trimesh

if TYPE_CHECKING:  # pragma: no cover
    import trimesh

    from cga.scene import MeshArrays, SceneNode

__all__ = ["BULLET_MARGIN", "CONTACT_SHRINK", "ConvexPiece", "collision_parts", "shrink_part",
           "structure_pieces"]

BULLET_MARGIN = 0.001
"""m: Bullet's collision margin around every shape (convex hulls, triangle meshes)."""

CONTACT_SHRINK = 2 * BULLET_MARGIN
"""m: how far each face of an item's convex parts is moved in; other simulators see
items 2 mm smaller than drawn, well below any placement tolerance."""


def shrink_part(vertices: np.ndarray, by: float = CONTACT_SHRINK) -> np.ndarray:
    """A convex part's vertices scaled about its box centre so each axis-aligned face
    moves in by ``by`` (exact for box parts; a part thinner than four times ``by`` keeps
    at least half its size)."""
    vertices = np.asarray(vertices, dtype=float)
    lo, hi = vertices.min(axis=0), vertices.max(axis=0)
    centre, extent = (lo + hi) / 2, hi - lo
    scale = np.maximum(extent - 2 * by, extent / 2) / np.maximum(extent, 1e-12)
    return (vertices - centre) * scale + centre


def collision_parts(node: "SceneNode", cache_dir: Path | None = None) -> list["MeshArrays"]:
    """An item's convex collision parts: its model's parts, or a V-HACD decomposition
    (cached on disk, :mod:`cga.checks.vhacd`) when it has none or its model says they
    are not convex (``ItemInfo.convex_parts`` False, e.g. a user's single-group OBJ)."""
    parts = [p for p in node.parts if len(p.faces)]
    if parts and node.convex_parts:
        return parts
    from cga.checks.vhacd import convex_decomposition  # pybullet only when needed
    from cga.scene import MeshArrays

    return [MeshArrays(np.asarray(p.vertices), np.asarray(p.faces))
            for p in convex_decomposition(as_trimesh(node.mesh), cache=cache_dir)]


_MIN_VOLUME = 1e-9
"""m³: pieces smaller than this are dropped."""

_BOX_TOLERANCE = 1e-6
"""A piece is a box when its volume is within this fraction of its bounding box's."""


@dataclass(frozen=True)
class ConvexPiece:
    """A convex solid of the building, in world coordinates (metres, y up).

    ``vertices`` and ``faces`` are its closed convex mesh. When it is a box standing
    upright (any turn about +y), ``box`` holds its ``(centre, extents, yaw)``: the centre,
    the full extents along its own x, y, z and the turn (rad) about world +y that takes
    its x axis to world ``(cos yaw, 0, −sin yaw)``.
    """

    vertices: np.ndarray
    faces: np.ndarray
    box: tuple[np.ndarray, np.ndarray, float] | None = None


def structure_pieces(node: "SceneNode") -> list[ConvexPiece]:
    """The convex pieces of a static structure node.

    A rectilinear solid (every wall, slab and stair step of a building with axis-aligned
    walls) is cut into boxes by the planes through its vertices
    (:func:`cga.checks._solids.convex_pieces`, as the physics check does); any other
    solid is decomposed by V-HACD (:func:`cga.checks.vhacd.convex_decomposition`). A
    mesh that encloses no volume (a face of a massing grammar) is thickened into one thin
    prism per triangle, since no simulator collides with a zero-thickness shape.

    Returns
    -------
    list of ConvexPiece
        Empty for a node without faces.
    """
    from cga.checks._solids import convex_pieces

    mesh = as_trimesh(node.mesh)
    if not len(mesh.faces):
        return []
    if not (mesh.is_volume and mesh.volume > 0):
        return [p for p in map(_piece, _sheet_prisms(mesh)) if p is not None]
    pieces = convex_pieces(mesh)
    if pieces is None:
        from cga.checks.vhacd import convex_decomposition

        pieces = list(convex_decomposition(mesh))
    out = [_piece(np.asarray(p.vertices, dtype=float)) for p in pieces if len(p.faces)]
    return [piece for piece in out if piece is not None]


def _sheet_prisms(mesh: "trimesh.Trimesh", half: float = 0.005) -> list[np.ndarray]:
    """Each triangle of an open surface as a prism ``2 × half`` thick."""
    triangles = np.asarray(mesh.triangles, dtype=float)
    normals = np.asarray(mesh.face_normals, dtype=float)[:, None, :] * half
    return [np.vstack([t - n, t + n]) for t, n in zip(triangles, normals)]


def _piece(vertices: np.ndarray) -> ConvexPiece | None:
    """A convex piece from points, recognised as an upright box when it is one; None for
    a sliver without volume (rounding left over from cutting).

    Points that are the eight corners of an axis-aligned box (most pieces of a building:
    :func:`cga.checks._solids.convex_pieces` cuts walls and slabs into such boxes) are
    their own hull, made without Qhull (most of a robot export's cost), and their box is
    read off the corners exactly (the rotated rectangle through them turned such a box
    by rounding noise, up to 1e-12 rad)."""
    import trimesh

    lo, hi = vertices.min(axis=0), vertices.max(axis=0)
    if ((vertices == lo) | (vertices == hi)).all() and len(np.unique(vertices, axis=0)) == 8:
        if not float(np.prod(hi - lo)) > _MIN_VOLUME:
            return None
        corners = trimesh.creation.box(bounds=np.array([lo, hi]))
        return ConvexPiece(np.asarray(corners.vertices, dtype=float), np.asarray(corners.faces),
                           ((lo + hi) / 2, hi - lo, 0.0))
    hull = trimesh.convex.convex_hull(vertices)
    volume = float(hull.volume)
    if not volume > _MIN_VOLUME:
        return None
    points = np.asarray(hull.vertices, dtype=float)
    return ConvexPiece(points, np.asarray(hull.faces), _upright_box(points, volume))


def _upright_box(points: np.ndarray, volume: float) -> tuple[np.ndarray, np.ndarray, float] | None:
    """``(centre, extents, yaw)`` of the convex solid with corners ``points`` and
    ``volume`` when it is an upright box (any turn about +y), else None."""
    from shapely.geometry import MultiPoint

    y0, y1 = float(points[:, 1].min()), float(points[:, 1].max())
    rect = MultiPoint(points[:, [0, 2]]).minimum_rotated_rectangle
    if not (rect.geom_type == "Polygon" and volume >= rect.area * (y1 - y0) * (1 - _BOX_TOLERANCE)):
        return None
    corners = np.asarray(rect.exterior.coords)[:4]
    edge_a, edge_b = corners[1] - corners[0], corners[2] - corners[1]
    yaw = float(np.arctan2(-edge_a[1], edge_a[0]))
    extents = np.array([np.linalg.norm(edge_a), y1 - y0, np.linalg.norm(edge_b)])
    # the same box turned by a quarter turn: keep yaw in [−45°, 45°), so an
    # axis-aligned piece gets yaw 0
    turns = int(np.floor((yaw + np.pi / 4) / (np.pi / 2)))
    yaw -= turns * np.pi / 2
    if turns % 2:
        extents = extents[[2, 1, 0]]
    centre = np.array([*corners.mean(axis=0), (y0 + y1) / 2])[[0, 2, 1]]
    return centre, extents, float(yaw)
