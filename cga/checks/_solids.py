"""Triangle meshes as manifold3d solids, for exact clipping, projection and cutting.

The occupancy grid projects the slice of each mesh that lies in the robot's height band
(:meth:`manifold3d.Manifold.project`), the V-HACD cache clips convex hulls back to the
mesh they approximate, and the physics check cuts the building's structure into convex
pieces (:func:`convex_pieces`). All need a watertight solid; a mesh that is not one (an
open surface, a user model with holes) gives ``None`` and the caller falls back.
"""

from __future__ import annotations

import manifold3d
import numpy as np
import trimesh

__all__ = ["as_manifold", "as_trimesh", "convex_pieces"]

_CONVEX_TOLERANCE = 1e-6
"""A piece is convex when its volume is within this fraction of its hull's."""

_MIN_VOLUME = 1e-9
"""m³: pieces smaller than this are slivers of rounding (manifold3d stores float32)."""

_MAX_PIECES = 256
"""Cutting stops (and :func:`convex_pieces` gives up) beyond this many pieces."""


def as_manifold(mesh: trimesh.Trimesh) -> manifold3d.Manifold | None:
    """``mesh`` as a manifold3d solid, or ``None`` when it is empty or not watertight.

    Watertightness is tested first (every edge shared by exactly two triangles):
    manifold3d 3.5 can crash on some open surfaces, such as a facade face with a door
    cut out, instead of reporting them as not manifold."""
    if len(mesh.faces) == 0 or not mesh.is_watertight:
        return None
    solid = manifold3d.Manifold(manifold3d.Mesh(
        vert_properties=np.asarray(mesh.vertices, dtype=np.float32),
        tri_verts=np.asarray(mesh.faces, dtype=np.uint32)))
    if solid.status() != manifold3d.Error.NoError or solid.is_empty():
        return None
    return solid


def as_trimesh(solid: manifold3d.Manifold) -> trimesh.Trimesh:
    """A manifold3d solid as a trimesh (vertex positions only)."""
    out = solid.to_mesh()
    return trimesh.Trimesh(vertices=np.asarray(out.vert_properties[:, :3], dtype=float),
                           faces=np.asarray(out.tri_verts, dtype=np.int64), process=False)


def convex_pieces(mesh: trimesh.Trimesh) -> list[trimesh.Trimesh] | None:
    """Cut a solid into convex pieces with axis-aligned planes through its vertices.

    A building's structure is rectilinear: a wall is a box with rectangular openings, a
    slab a prism over a rectilinear footprint. Cutting such a solid with the planes
    ``x``, ``z`` and ``y`` = constant through its vertices leaves boxes. Returns the
    pieces (one piece, the mesh itself, when it is already convex), or ``None`` when the
    mesh is not a watertight solid or some piece is not convex (a slanted wall with an
    opening), so the caller can use the mesh as it is.

    Notes
    -----
    At most a few dozen cuts per wall; each is a manifold3d plane split.
    """
    solid = as_manifold(mesh)
    if solid is None:
        return None
    if _is_convex(solid):
        return [mesh]
    vertices = np.asarray(solid.to_mesh().vert_properties[:, :3], dtype=float)
    pieces = [solid]
    for axis in (0, 2, 1):
        normal = tuple(1.0 if k == axis else 0.0 for k in range(3))
        for value in np.unique(vertices[:, axis]):
            cut: list[manifold3d.Manifold] = []
            for piece in pieces:
                box = piece.bounding_box()
                if box[axis] + 1e-9 < value < box[axis + 3] - 1e-9 and not _is_convex(piece):
                    cut.extend(p for p in piece.split_by_plane(normal, float(value))
                               if p.volume() > _MIN_VOLUME)
                else:
                    cut.append(piece)
            pieces = cut
            if len(pieces) > _MAX_PIECES:
                return None
    if not all(_is_convex(piece) for piece in pieces):
        return None
    return [as_trimesh(piece) for piece in pieces]


def _is_convex(solid: manifold3d.Manifold) -> bool:
    hull = solid.hull().volume()
    return hull > 0 and solid.volume() >= hull * (1.0 - _CONVEX_TOLERANCE)
