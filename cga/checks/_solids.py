"""Triangle meshes as manifold3d solids, for exact clipping and projection in the checks.

The occupancy grid projects the slice of each mesh that lies in the robot's height band
(:meth:`manifold3d.Manifold.project`), and the V-HACD cache clips convex hulls back to the
mesh they approximate. Both need a watertight solid; a mesh that is not one (an open
surface, a user model with holes) gives ``None`` and the caller falls back on its hull.
"""

from __future__ import annotations

import manifold3d
import numpy as np
import trimesh

__all__ = ["as_manifold", "as_trimesh"]


def as_manifold(mesh: trimesh.Trimesh) -> manifold3d.Manifold | None:
    """``mesh`` as a manifold3d solid, or ``None`` when it is empty or not watertight."""
    if len(mesh.faces) == 0:
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
