"""Triangle meshes as manifold3d solids, for exact clipping, projection and cutting.

The occupancy grid projects the slice of each mesh that lies in the robot's height band
(:meth:`manifold3d.Manifold.project`), the V-HACD cache clips convex hulls back to the
mesh they approximate, and the physics check cuts the building's structure into convex
pieces (:func:`convex_pieces`). All need a watertight solid; a mesh that is not one (an
open surface, a user model with holes) gives ``None`` and the caller falls back.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Sequence
from typing import TypeVar

import numpy as np

from cga import scene
from cga.manifold import manifold3d
from cga.mesh import MeshLike, TriangleMesh, is_watertight


__all__ = ["as_manifold", "as_mesh", "convex_pieces", "cut_pieces"]

P = TypeVar("P")
V = TypeVar("V")

_CONVEX_TOLERANCE = 1e-6
"""A piece is convex when its volume is within this fraction of its hull's."""

_MIN_VOLUME = 1e-9
"""m³: pieces smaller than this are slivers of rounding (manifold3d stores float32)."""

_MAX_PIECES = 256
"""Cutting stops (and :func:`convex_pieces` gives up) beyond this many pieces."""


def as_manifold(mesh: MeshLike) -> manifold3d.Manifold | None:
    """``mesh`` as a manifold3d solid, or ``None`` when it is empty or not watertight.

    Watertightness is tested first (every edge shared by exactly two triangles):
    manifold3d 3.5 can crash on some open surfaces, such as a facade face with a door
    cut out, instead of reporting them as not manifold."""
    if len(mesh.faces) == 0 or not is_watertight(np.asarray(mesh.faces)):
        return None
    solid = manifold3d.Manifold(manifold3d.Mesh(
        vert_properties=np.asarray(mesh.vertices, dtype=np.float32),
        tri_verts=np.asarray(mesh.faces, dtype=np.uint32)))
    if solid.status() != manifold3d.Error.NoError or solid.is_empty():
        return None
    return solid


def as_mesh(solid: manifold3d.Manifold) -> TriangleMesh:
    """A manifold3d solid as a mesh (vertex positions only)."""
    out = solid.to_mesh()
    return TriangleMesh(np.asarray(out.vert_properties[:, :3], dtype=float),
                        np.asarray(out.tri_verts, dtype=np.int64))


def convex_pieces(mesh: MeshLike) -> Sequence[MeshLike] | None:
    """Cut a solid into convex pieces with axis-aligned planes through its vertices.

    A building's structure is rectilinear: a wall is a box with rectangular openings, a
    slab a prism over a rectilinear footprint. Cutting such a solid with the planes
    ``x``, ``z`` and ``y`` = constant through its vertices leaves boxes. Returns the
    pieces as arrays (one piece, the mesh itself, when it is already convex), or
    ``None`` when the mesh is not a watertight solid or some piece is not convex (a
    slanted wall with an opening), so the caller can use the mesh as it is.

    Notes
    -----
    At most a few dozen cuts per wall; each is a manifold3d plane split. A piece that
    fills its bounding box is a box, so convex, without computing its hull; each piece's
    convexity is settled once, not once per plane it straddles.
    """
    solid = as_manifold(mesh)
    if solid is None:
        return None
    if _is_convex(solid):
        return [mesh]
    vertices = np.asarray(solid.to_mesh().vert_properties[:, :3], dtype=float)
    planes = ((axis, float(value)) for axis in (0, 2, 1) for value in np.unique(vertices[:, axis]))
    pieces = cut_pieces([_Cut(solid)], planes, _split)
    if pieces is None or not all(piece.convex for piece in pieces):
        return None
    return [_arrays(piece.solid) for piece in pieces]


def cut_pieces(pieces: list[P], planes: Iterable[tuple[int, V]],
               split: Callable[[P, int, V], list[P] | None]) -> list[P] | None:
    """Cut ``pieces`` by each plane ``(axis, position)`` in turn: ``split`` gives the
    parts of a piece the plane cuts (None: the piece stays whole). A cut piece's parts
    take its place, so the order of the pieces is the order of the cuts. None once
    there are more than :data:`_MAX_PIECES` pieces.

    The one cutting order :func:`convex_pieces` (manifold3d solids) and
    :func:`cga.checks._boxes.box_pieces` (cells on a grid) share, so both make the
    same pieces in the same order."""
    for axis, position in planes:
        cut: list[P] = []
        for piece in pieces:
            parts = split(piece, axis, position)
            if parts is None:
                cut.append(piece)
            else:
                cut.extend(parts)
        pieces = cut
        if len(pieces) > _MAX_PIECES:
            return None
    return pieces


def _split(piece: "_Cut", axis: int, value: float) -> "list[_Cut] | None":
    """The parts of ``piece`` on either side of the plane ``axis`` = ``value`` (slivers
    of rounding dropped), when the plane passes through it and it is not convex."""
    box = piece.box
    if not (box[axis] + 1e-9 < value < box[axis + 3] - 1e-9) or piece.convex:
        return None
    normal = tuple(1.0 if k == axis else 0.0 for k in range(3))
    return [_Cut(p) for p in piece.solid.split_by_plane(normal, value) if p.volume() > _MIN_VOLUME]


class _Cut:
    """A piece being cut: its solid, bounding box and (once asked) convexity."""

    __slots__ = ("solid", "box", "_convex")

    def __init__(self, solid: manifold3d.Manifold):
        self.solid = solid
        self.box = solid.bounding_box()
        self._convex: bool | None = None

    @property
    def convex(self) -> bool:
        if self._convex is None:
            self._convex = _is_convex(self.solid, self.box)
        return self._convex


def _arrays(solid: manifold3d.Manifold) -> scene.MeshArrays:
    out = solid.to_mesh()
    return scene.MeshArrays(np.asarray(out.vert_properties[:, :3], dtype=float),
                 np.asarray(out.tri_verts, dtype=np.int64))


def _is_convex(solid: manifold3d.Manifold,
               box: tuple[float, float, float, float, float, float] | None = None) -> bool:
    """Whether ``solid``'s volume is within :data:`_CONVEX_TOLERANCE` of its hull's. A
    solid that fills as much of its bounding box is (the hull lies in the box)."""
    volume = solid.volume()
    lo_x, lo_y, lo_z, hi_x, hi_y, hi_z = box if box is not None else solid.bounding_box()
    if volume > 0 and volume >= (hi_x - lo_x) * (hi_y - lo_y) * (hi_z - lo_z) * (1.0 - _CONVEX_TOLERANCE):
        return True
    hull = solid.hull().volume()
    return hull > 0 and volume >= hull * (1.0 - _CONVEX_TOLERANCE)
